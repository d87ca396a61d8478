//! Blow-up diagnosis: a run whose time step is absurd for its fluid stops with a diagnosis
//! naming the quantity and a particle, a one-line error, the last good state readable in
//! `blowup.vtu` and a report in `blowup.txt`; the criteria the provoked run does not reach
//! (kinetic energy, soil stress, domain) are checked on states made to break them.

use std::path::{Path, PathBuf};

use geosph_core::{Particles, Real, Vector};
use geosph_runner::health::report::{FAILED_FILE, LAST_GOOD_FILE, REPORT_FILE};
use geosph_runner::health::{self, LimitInputs, Limits, Quantity};
use geosph_runner::{NoObserver, RunError, RunOptions, run};
use geosph_scene::{Scene, SolverSpec};
use geosph_sph::Solver;
use vtkio::model::{Attribute, DataSet, Piece, Vtk};

fn scratch(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    folder
}

/// The 2D dam break at dx = 5 cm (800 particles) with WCSPH's sound speed set to `sound_speed`
/// and the column starting at ρ₀ (not hydrostatic), so that it is healthy at t = 0.
fn dam_break(sound_speed: Real) -> Scene {
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.05;
    scene.end_time = 0.5;
    scene.fluid.as_mut().unwrap().hydrostatic = false;
    let SolverSpec::Wcsph(config) = &mut scene.solver else {
        panic!("the dam break is a WCSPH scene");
    };
    config.sound_speed = Some(sound_speed);
    scene
}

/// The fluid set of a VTU file (the points whose `kind` is 0): positions (x, y, z), densities
/// and ids.
fn read_fluid(path: &Path) -> (Vec<[Real; 3]>, Vec<Real>, Vec<u32>) {
    let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("{} is not an unstructured grid", path.display());
    };
    let Some(Piece::Inline(piece)) = pieces.into_iter().next() else {
        panic!("{} has no inline piece", path.display());
    };
    let field = |name: &str| -> Vec<Real> {
        piece
            .data
            .point
            .iter()
            .find_map(|attribute| match attribute {
                Attribute::DataArray(array) if array.name == name => array.data.cast_into(),
                _ => None,
            })
            .unwrap_or_else(|| panic!("{}: no field `{name}`", path.display()))
    };
    let (kind, density, id) = (field("kind"), field("density"), field("id"));
    let coordinates: Vec<Real> = piece.points.cast_into().unwrap();
    let fluid = |k: &usize| kind[*k] == 0.0;
    let indices: Vec<usize> = (0..kind.len()).filter(fluid).collect();
    (
        indices
            .iter()
            .map(|&k| {
                [
                    coordinates[3 * k],
                    coordinates[3 * k + 1],
                    coordinates[3 * k + 2],
                ]
            })
            .collect(),
        indices.iter().map(|&k| density[k]).collect(),
        indices.iter().map(|&k| id[k] as u32).collect(),
    )
}

/// The sound speed of 1 m/s, against the 6.3 m/s at which a 2 m column collapses, makes WCSPH's
/// acoustic time step C h / c far too long for the compression the flow demands: the
/// density error passes its 20 % bound within a few steps.
#[test]
fn an_absurd_time_step_is_diagnosed_and_the_last_good_frame_is_readable() {
    let out = scratch("blow-up-dam-break");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        threads: Some(1),
        ..Default::default()
    };
    let error = run(&dam_break(1.0), &options, &mut NoObserver).unwrap_err();
    let message = error.to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    assert_eq!(error.exit_code(), health::EXIT_BLOW_UP);
    let RunError::BlowUp {
        step,
        diagnosis,
        files,
        ..
    } = error
    else {
        panic!("not a blow-up: {message}");
    };
    assert_eq!(diagnosis.quantity, Quantity::DensityError, "{message}");
    assert!(diagnosis.value > health::MAX_DENSITY_ERROR);
    assert!(step > 1, "the initial state is healthy: {message}");
    let (i, id) = diagnosis.particle.expect("a particle is named");
    for path in [LAST_GOOD_FILE, REPORT_FILE] {
        let path = out.join(path);
        assert!(
            message.contains(&path.display().to_string()),
            "{message} names {}",
            path.display()
        );
    }
    assert!(matches!(
        *files,
        health::report::BlowUpFiles::Written { .. }
    ));

    let report = std::fs::read_to_string(out.join(REPORT_FILE)).unwrap();
    assert!(report.contains("quantity     density error"), "{report}");
    assert!(
        report.contains(&format!("#1 particle {i} (id {id})")),
        "{report}"
    );
    assert!(
        report.contains("fluid and"),
        "neighbours are listed: {report}"
    );

    // The last good state is a complete, finite frame within the density bound; the failed
    // state is there for inspection.
    let (points, density, ids) = read_fluid(&out.join(LAST_GOOD_FILE));
    assert_eq!(points.len(), 800);
    assert!(ids.contains(&id));
    assert!(points.iter().flatten().all(|c| c.is_finite()));
    let worst = density
        .iter()
        .map(|rho| (rho / 1000.0 - 1.0).abs())
        .fold(0.0, Real::max);
    assert!(
        worst <= health::MAX_DENSITY_ERROR,
        "last good error {worst}"
    );
    let (failed, density, _) = read_fluid(&out.join(FAILED_FILE));
    assert_eq!(failed.len(), 800);
    assert!(
        density
            .iter()
            .any(|rho| (rho / 1000.0 - 1.0).abs() > health::MAX_DENSITY_ERROR)
    );
}

/// Without an output folder the error says that nothing was saved.
#[test]
fn a_blow_up_without_output_folder_says_nothing_was_saved() {
    let error = run(&dam_break(1.0), &RunOptions::default(), &mut NoObserver).unwrap_err();
    let message = error.to_string();
    assert!(matches!(error, RunError::BlowUp { .. }), "{message}");
    assert!(
        message.ends_with("no output folder: nothing saved"),
        "{message}"
    );
}

/// A scene's particles, its solver and the run's limits, as the runner builds them.
fn built<const D: usize>(scene: &Scene) -> (Particles<D>, Box<dyn Solver<D>>, Limits<D>) {
    let (mut fluid, inputs) = geosph_scene::build::<D>(scene).unwrap().split();
    let limit_inputs = LimitInputs::of(&inputs);
    let mut solver = match &scene.solver {
        SolverSpec::Wcsph(config) => geosph_fluid::build_wcsph(config, inputs, &mut fluid).unwrap(),
        SolverSpec::Soil(config) => geosph_soil::build_soil(config, inputs, &mut fluid).unwrap(),
        _ => unreachable!("WCSPH and soil scenes only"),
    };
    solver.initial_stage(&mut fluid).unwrap();
    let limits = Limits::new(limit_inputs, &fluid, solver.as_ref());
    (fluid, solver, limits)
}

/// A step report of a healthy step.
fn healthy_step() -> geosph_sph::StepReport {
    geosph_sph::StepReport {
        dt: 1e-4,
        iterations: 1,
        ..Default::default()
    }
}

/// Gravity is the only input of a dam break: kinetic energy up to what the fall of the centre
/// of mass supplies is healthy, the same energy without a fall is a blow-up.
#[test]
fn kinetic_energy_beyond_the_work_of_gravity_is_a_blow_up() {
    let scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    let (mut fluid, solver, limits) = built::<2>(&scene);
    let step = healthy_step();
    assert_eq!(health::check(&step, &fluid, solver.as_ref(), &limits), None);

    // Every particle 5 cm lower, moving at 0.99 × the free-fall speed of that drop.
    let (drop, g) = (0.05, 9.81);
    let speed = 0.99 * (2.0 * g * drop as Real).sqrt();
    for (x, v) in fluid.position.iter_mut().zip(&mut fluid.velocity) {
        x[1] -= drop;
        *v = Vector::<2>::new(speed, 0.0);
    }
    assert_eq!(health::check(&step, &fluid, solver.as_ref(), &limits), None);

    // The same speeds back at the start height: energy from nowhere.
    for x in &mut fluid.position {
        x[1] += drop;
    }
    let diagnosis = health::check(&step, &fluid, solver.as_ref(), &limits).unwrap();
    assert_eq!(diagnosis.quantity, Quantity::KineticEnergy, "{diagnosis:?}");
    assert!(diagnosis.value > diagnosis.bound.unwrap());
}

/// A particle outside the domain is named with its position.
#[test]
fn a_particle_outside_the_domain_is_a_blow_up() {
    let scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    let (mut fluid, solver, limits) = built::<2>(&scene);
    fluid.position[17][0] = limits.domain.max[0] + 0.5;
    let diagnosis = health::check(&healthy_step(), &fluid, solver.as_ref(), &limits).unwrap();
    assert_eq!(diagnosis.quantity, Quantity::Position);
    assert_eq!(diagnosis.particle, Some((17, fluid.id[17])));
    assert!((diagnosis.value - 0.5).abs() < 1e-12, "{diagnosis:?}");
}

/// The granular column after its geostatic stage is healthy; a stress a thousand times the
/// bound, or a non-finite one, is a blow-up naming the particle.
#[test]
fn soil_stress_beyond_its_bound_is_a_blow_up() {
    let mut scene = Scene::from_ron(slope_failure::DEFAULT_SCENE).unwrap();
    scene.dx = 0.01;
    let (mut fluid, solver, limits) = built::<2>(&scene);
    let step = healthy_step();
    assert_eq!(health::check(&step, &fluid, solver.as_ref(), &limits), None);
    let bound = limits.max_stress.expect("soil scenes bound the stress");
    let geostatic = fluid
        .soil
        .as_ref()
        .unwrap()
        .stress
        .iter()
        .map(|s| s.norm())
        .fold(0.0, Real::max);
    assert!(geostatic > 0.0 && bound > 10.0 * geostatic);

    let stress = &mut fluid.soil.as_mut().unwrap().stress;
    let scale = 1e3 * bound / stress[42].norm();
    stress[42] *= scale;
    let diagnosis = health::check(&step, &fluid, solver.as_ref(), &limits).unwrap();
    assert_eq!(diagnosis.quantity, Quantity::Stress);
    assert_eq!(diagnosis.particle, Some((42, fluid.id[42])));

    fluid.soil.as_mut().unwrap().stress[7][(0, 1)] = Real::NAN;
    let diagnosis = health::check(&step, &fluid, solver.as_ref(), &limits).unwrap();
    assert_eq!(diagnosis.quantity, Quantity::Stress);
    assert_eq!(diagnosis.particle, Some((7, fluid.id[7])));
    assert_eq!(diagnosis.bound, None);
}
