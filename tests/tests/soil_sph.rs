//! Soil SPH against closed forms and the granular column collapse of Bui et al. (2008)
//! (the closed forms and set-up of `docs/soil.md`, "SPH coupling"; data/scenes/granular-collapse.ron).

use geosph_core::Real;
use geosph_runner::RunOptions;
use geosph_scene::{Scene, SolverSpec};
use geosph_soil::build_soil;
use geosph_soil::sph::InitialStress;
use geosph_sph::StageReport;
use nalgebra::Matrix2;
use slope_failure::{DEFAULT_SCENE, Report};

/// A level elastic layer 0.1 m deep, periodic in x, on a floor, loaded by gravity.
fn k0_scene() -> Scene {
    Scene::from_ron(
        "Scene(
            name: \"k0-column\",
            dimension: 2,
            dx: 0.005,
            smoothing_ratio: 1.3,
            end_time: 0.01,
            domain: (min: [0.0, -0.05], max: [0.1, 0.3], periodic: [true, false]),
            soil: (density: 2650.0, blocks: [Box(min: [0.0, 0.0], max: [0.1, 0.1])]),
            walls: [Polyline(points: [(0.0, 0.0), (0.1, 0.0)], layers: 4)],
            solver: Soil((
                constitutive: LinearElastic(youngs_modulus: 0.84e6, poisson_ratio: 0.3),
                geostatic: (),
            )),
        )",
    )
    .unwrap()
}

/// What `scene`'s initial stage returns (2D soil scenes).
fn initial_stage(scene: &Scene) -> Result<Option<StageReport>, geosph_sph::SolverError> {
    let SolverSpec::Soil(config) = &scene.solver else {
        unreachable!("a soil scene")
    };
    let (mut soil, inputs) = geosph_scene::build::<2>(scene).unwrap().split();
    let mut solver = build_soil(config, inputs, &mut soil).unwrap();
    solver.initial_stage(&mut soil)
}

/// The report of `scene`'s geostatic stage (2D soil scenes with a stage).
fn geostatic_stage(scene: &Scene) -> StageReport {
    initial_stage(scene)
        .unwrap()
        .expect("the scene has a geostatic stage")
}

/// K₀ column: after the geostatic stage σ_v is within 2 % of ρ g (H − y) and σ_h/σ_v within
/// 5 % of ν/(1 − ν) (plane strain, no lateral strain) below the top three layers, at the
/// scenes' h = 1.3 dx.
///
/// Without the lattice gradient correction (`SoilSystem::gradient_correction`) the discrete
/// gradient of a linear field on the lattice, Σ_j V_j (x_j − x_i) ⊗ ∇W_ij, is 0.974 I for
/// Wendland C2 at h = 1.3 dx, which makes the stress gradient that balances gravity 2.7 %
/// too steep.
#[test]
fn k0_column_after_the_geostatic_stage() {
    let report = geostatic_stage(&k0_scene());
    eprintln!("{report}");
    let figure = |name| report.figure(name).expect(name);
    assert_eq!(figure("converged"), 1.0, "{report}");
    assert!(figure("checked_particles") >= (20 * 17) as Real, "{report}");
    assert!(figure("vertical_stress_error_max") < 0.02, "{report}");
    let k0 = 0.3 / 0.7;
    let (low, high) = (figure("lateral_ratio_min"), figure("lateral_ratio_max"));
    assert!(
        (low / k0 - 1.0).abs() < 0.05 && (high / k0 - 1.0).abs() < 0.05,
        "{report}"
    );
    assert!(figure("residual_max") < 0.01, "{report}");
}

/// The geostatic stage of every shipped column scene at dx = 2.5 mm and the scenes'
/// h = 1.3 dx, each particle below the top three layers against the state that applies where it
/// is (`geosph_soil::sph::stress_check`). The scenes start from the 1D state of a level layer
/// (`initial_stress: Oedometric`, the K₀ procedure), which the relaxation must keep: SPH
/// equilibrium of the discrete stress gradient against gravity, with the friction walls
/// holding the soil without carrying its weight.
/// - Every particle: σ_v within 2 % of ρ g (H − y) and σ_h/σ_v within 5 % of the material's
///   oedometric ratio at that σ_v (the bounds for the 1D state), the residual below
///   1 % of g.
/// - No particle is free field (farther than the soil height H from a rough side wall): the
///   columns are at most 2H long.
/// - Every layer between the two friction walls: its mean σ_v between Janssen's (1895) value
///   with the walls' friction fully mobilised (the least the walls allow) and ρ g z (walls
///   cannot push the soil down), within 1 % of ρ g z.
#[test]
fn geostatic_stage_of_the_shipped_scenes() {
    for (name, text) in slope_failure::SCENES {
        let mut scene = Scene::from_ron(text).unwrap();
        scene.dx = 0.0025;
        let report = geostatic_stage(&scene);
        eprintln!("{name}: {report}");
        let figure = |name| report.figure(name).expect(name);
        assert_eq!(figure("converged"), 1.0, "{name}: {report}");
        assert_eq!(figure("checked_particles"), 0.0, "{name}: {report}");
        assert!(figure("wall_zone_particles") > 0.0, "{name}: {report}");
        assert!(
            figure("wall_zone_vertical_stress_error_max") <= 0.02,
            "{name}: {report}"
        );
        assert!(
            figure("wall_zone_lateral_ratio_error_max") <= 0.05,
            "{name}: {report}"
        );
        assert!(figure("residual_max") < 0.01, "{name}: {report}");
        assert!(figure("janssen_layers") >= 30.0, "{name}: {report}");
        assert_eq!(figure("janssen_outside_bounds"), 0.0, "{name}: {report}");
    }
}

/// The K₀ start bins the soil into lattice columns along gravity: with gravity off the axes
/// the stage refuses it with a message that names the field and the way out.
#[test]
fn k0_start_needs_gravity_along_an_axis() {
    let mut scene = Scene::from_ron(DEFAULT_SCENE).unwrap();
    scene.dx = 0.01;
    scene.gravity = Some(vec![-0.5, -9.8]);
    let error = initial_stage(&scene).unwrap_err().to_string();
    assert!(
        error.contains("geostatic.initial_stress") && error.contains("initial_stress: Zero"),
        "{error}"
    );
}

/// Gravity switched on at once (`initial_stress: Zero`) on the default column, 0.2 m × 0.1 m
/// between friction walls at dx = 2.5 mm: the column settles and the walls carry part of its
/// weight by friction, every layer between them within Janssen's (1895) bounds (the least
/// σ̄_v the fully mobilised friction allows, and ρ g z) to 1 % of ρ g z.
#[test]
fn gravity_loading_arches_within_janssen_bounds() {
    let mut scene = Scene::from_ron(DEFAULT_SCENE).unwrap();
    scene.dx = 0.0025;
    let SolverSpec::Soil(config) = &mut scene.solver else {
        unreachable!("a soil scene")
    };
    config
        .geostatic
        .as_mut()
        .expect("the default scene has a geostatic stage")
        .initial_stress = InitialStress::Zero;
    let report = geostatic_stage(&scene);
    eprintln!("{report}");
    let figure = |name| report.figure(name).expect(name);
    assert_eq!(figure("converged"), 1.0, "{report}");
    assert!(figure("janssen_layers") >= 30.0, "{report}");
    assert_eq!(figure("janssen_outside_bounds"), 0.0, "{report}");
}

pub(crate) fn collapse(dx: Real, end_time: Real) -> Report {
    let mut scene = Scene::from_ron(DEFAULT_SCENE).unwrap();
    scene.dx = dx;
    scene.end_time = end_time;
    slope_failure::run(&scene, &RunOptions::default()).unwrap()
}

/// Bui et al. (2008) collapse at a coarse dx: the soil at the wall keeps its height (within
/// 2 dx), a wedge slides off the free side (the front moves by more than 5 dx), and the deposit
/// is at rest from t = 0.7 s (the experiment stops by about 0.6 s): its front moves by less
/// than dx/100 over the last 0.3 s, and the kinetic energy left is below 10⁻³ of its peak.
/// Its runout changes by at most 3 % from dx/2 to dx/4 (run to t = 0.6 s), and the deposit
/// matches the experiment ([`against_the_experiment`]).
///
/// The residual kinetic energy is elastic ringing of the deposit (it fluctuates between 10⁻⁵
/// and 4·10⁻⁴ J without trend at dx = 5 mm), so it bounds but does not define rest.
#[test]
fn granular_collapse_keeps_an_inner_block_and_comes_to_rest() {
    let dx = 0.005;
    let report = collapse(dx, 1.0);
    eprintln!("{report}");
    let column = report.column;
    assert!(
        (report.last.height_at_wall - column.height).abs() <= 2.0 * dx,
        "{report}"
    );
    assert!(report.last.front > column.length + 5.0 * dx, "{report}");
    let creep = creep_after(&report, 0.7);
    against_the_experiment(&report);
    assert!(
        creep < 0.01 * dx,
        "front moved {creep:.2e} m after t = 0.7 s\n{report}"
    );
    assert!(
        report.last.kinetic_energy < 1e-3 * report.peak_kinetic_energy,
        "{report}"
    );

    // The required convergence (issue 22): the runout (the deposit toe, 0.1 H thick) changes
    // by at most 3 % from dx = 2.5 to 1.25 mm, both at rest (the toe is final by t = 0.6 s).
    let (medium, fine) = (collapse(0.5 * dx, 0.6), collapse(0.25 * dx, 0.6));
    eprintln!("{medium}\n{fine}");
    let change = fine.last.runout / medium.last.runout - 1.0;
    assert!(
        change.abs() <= 0.03,
        "runout {:.4} m at dx = {} m, {:.4} m at {} m: {:+.1} %",
        medium.last.runout,
        0.5 * dx,
        fine.last.runout,
        0.25 * dx,
        100.0 * change
    );
}

/// The deposit at dx = 5 mm against the experiment of Bui et al. (2008) (the surface and toe
/// of `data/validation/bui-2008-final-surface.csv`, compared by
/// `slope_failure::bui2008::ExperimentComparison`).
///
/// Tolerances from the convergence study of docs/soil.md ("Stress noise during the collapse",
/// the default scene: the mean-stress diffusion and the K₀ start) as it stood when the test was
/// written: at dx = 1.25 mm the surface error P_d was 6.2 % and the toe 6.1 % beyond the
/// measured one. A surface drawn by particles is known to ±dx/2 at each of the 27 points,
/// which bounds P_d's change by (dx/2)√27 / ‖f_exp‖ = 4.7 % at dx = 5 mm: P_d ≤ 6.2 + 4.7 ≈
/// 10.9 %. The toe moved by at most 0.15 % per halving of dx from 5 to 1.25 mm, and a toe drawn
/// by particles is known to ±dx/2 (0.7 % of the measured toe at dx = 5 mm): within
/// 6.1 + 2 × 0.15 + 0.7 ≈ 7.1 % of the measured toe. The one-division artificial viscosity
/// (a change of rounding) later gave 6.5 % and +6.5 % at 1.25 mm and moved the 5 mm toe by
/// 2.5 % (docs/soil.md, "Round-off"); the bounds were not widened for it (measured at 5 mm:
/// P_d 5.1 %, toe +3.5 %). The height at the wall is the measured 0.1 m within dx/2.
pub(crate) fn against_the_experiment(report: &Report) {
    let experiment = report
        .experiment
        .as_ref()
        .expect("the default scene is the experiment's set-up");
    let (toe, measured_toe) = experiment.toe;
    assert!(experiment.surface_error <= 0.109, "{report}");
    assert!((toe / measured_toe - 1.0).abs() <= 0.071, "{report}");
    let (height, measured_height) = experiment.height_at_wall;
    assert!(
        (height - measured_height).abs() <= 0.5 * report.column.spacing,
        "{report}"
    );
}

/// How far the front moved from the first sample at or after `time` to the end of the run.
fn creep_after(report: &Report, time: Real) -> Real {
    let settled = report
        .samples
        .iter()
        .find(|s| s.time >= time)
        .expect("samples after the given time");
    (report.last.front - settled.front).abs()
}

/// The mean of the stress noise η over the flow, 0.05 s ≤ t ≤ 0.5 s.
fn flow_noise(report: &Report) -> Real {
    let flow: Vec<Real> = report
        .samples
        .iter()
        .filter(|s| (0.05..=0.5).contains(&s.time))
        .map(|s| s.stress_noise)
        .collect();
    flow.iter().sum::<Real>() / flow.len() as Real
}

/// The diffusion of the mean stress (`stress_diffusion`, `geosph_soil::sph::MeanStressDiffusion`,
/// on by default) on the Bui et al. (2008) collapse at dx = 5 mm removes the checkerboard
/// without spoiling the deposit:
/// - the particle-scale noise η of the stress (`geosph_soil::sph::stress_noise`, the distance
///   of σ from its neighbourhood's linear fit) of the deposit at rest is at most 5 % of |σ|
///   (without the diffusion 12–22 % at dx = 5 to 0.625 mm, docs/soil.md; a smooth state such
///   as the geostatic one gives about 1 %), and over the flow it is at most half of what it
///   is with `stress_diffusion: None`;
/// - the deposit is at rest, as in [`granular_collapse_keeps_an_inner_block_and_comes_to_rest`]
///   (its front moves by less than dx/100 after t = 0.7 s, E_k below 10⁻³ of its peak; the
///   deviator diffused as well makes the pile creep, and this catches it), and matches the
///   experiment within the tolerances of [`against_the_experiment`].
#[test]
fn mean_stress_diffusion_removes_the_checkerboard() {
    let dx = 0.005;
    let viscosity = "artificial_viscosity: (alpha: 0.1, beta: 0.0),";
    assert!(DEFAULT_SCENE.contains(viscosity));
    let without_diffusion = format!("{viscosity} stress_diffusion: None,");
    let mut scene = Scene::from_ron(&DEFAULT_SCENE.replace(viscosity, &without_diffusion)).unwrap();
    scene.dx = dx;
    let undiffused = slope_failure::run(&scene, &RunOptions::default()).unwrap();
    let diffused = collapse(dx, 1.0);
    eprintln!("{diffused}\n{undiffused}");
    assert!(diffused.last.stress_noise <= 0.05, "{diffused}");
    assert!(
        flow_noise(&diffused) <= 0.5 * flow_noise(&undiffused),
        "η over the flow {:.3} with the diffusion, {:.3} without",
        flow_noise(&diffused),
        flow_noise(&undiffused)
    );
    assert!(
        diffused.last.kinetic_energy < 1e-3 * diffused.peak_kinetic_energy,
        "{diffused}"
    );
    let creep = creep_after(&diffused, 0.7);
    assert!(
        creep < 0.01 * dx,
        "front moved {creep:.2e} m after t = 0.7 s"
    );
    against_the_experiment(&diffused);
}

fn cohesive_slope(cohesion: Real) -> Report {
    let mut scene = Scene::from_ron(slope_failure::SCENES[2].1).unwrap();
    scene.dx = 0.005;
    if let SolverSpec::Soil(config) = &mut scene.solver
        && let geosph_soil::ConstitutiveConfig::DruckerPrager { material, .. } =
            &mut config.constitutive
    {
        material.cohesion = cohesion;
    }
    slope_failure::run(&scene, &RunOptions::default()).unwrap()
}

/// A vertical cut 0.1 m high with c = 2 kPa (a quarter of the critical height
/// 4c tan(45° + φ/2)/(ρg) = 0.44 m) stands for 1 s after release: its face moves by less than
/// one dx. The same cut with c = 0 fails: its front runs out by more than 5 dx.
#[test]
fn cohesive_slope_stands_and_fails_without_cohesion() {
    let dx = 0.005;
    let standing = cohesive_slope(2000.0);
    eprintln!("c = 2 kPa: {standing}");
    let length = standing.column.length;
    assert!(
        standing
            .samples
            .iter()
            .all(|s| (s.front - length).abs() < dx),
        "{standing}"
    );
    assert!((standing.last.height_at_wall - standing.column.height).abs() < dx);
    let failing = cohesive_slope(0.0);
    eprintln!("c = 0: {failing}");
    assert!(failing.last.front > length + 5.0 * dx, "{failing}");
}

/// The velocity gradient of a linear velocity field v = A x, seen through the strain
/// increment of one step (ε = sym(A) Δt), on a free soil block: with the CSPM correction it is
/// exact at every particle, corners included; without it the particles near the free surface
/// miss up to half their support.
#[test]
fn cspm_velocity_gradient_is_exact_for_a_linear_field_at_free_surfaces() {
    let gradient = Matrix2::new(2.0e-3, 1.0e-3, -0.5e-3, -1.0e-3);
    let worst_error = |correct: bool| {
        let mut scene = Scene::from_ron(
            "Scene(
                name: \"linear-velocity\",
                dimension: 2,
                dx: 0.005,
                gravity: [0.0, 0.0],
                end_time: 1.0,
                domain: (min: [0.0, 0.0], max: [0.2, 0.2]),
                soil: (density: 2650.0, blocks: [Box(min: [0.05, 0.05], max: [0.1, 0.1])]),
                solver: Soil((
                    constitutive: LinearElastic(youngs_modulus: 0.84e6, poisson_ratio: 0.3),
                )),
            )",
        )
        .unwrap();
        let SolverSpec::Soil(config) = &mut scene.solver else {
            unreachable!("a soil scene")
        };
        config.velocity_gradient_correction = correct;
        let config = config.clone();
        let (mut soil, inputs) = geosph_scene::build::<2>(&scene).unwrap().split();
        let mut solver = build_soil(&config, inputs, &mut soil).unwrap();
        for (v, x) in soil.velocity.iter_mut().zip(&soil.position) {
            *v = gradient * x;
        }
        let report = solver.step(&mut soil, 0.0, 1e-6).unwrap();
        let exact = 0.5 * (gradient + gradient.transpose()) * report.dt;
        let strain = &soil.soil.as_ref().unwrap().strain;
        strain
            .iter()
            .map(|e| (e.fixed_view::<2, 2>(0, 0) - exact).norm() / exact.norm())
            .fold(0.0, Real::max)
    };
    let (corrected, plain) = (worst_error(true), worst_error(false));
    eprintln!("largest relative strain error: corrected {corrected:.1e}, plain {plain:.2}");
    assert!(corrected < 1e-9, "corrected {corrected:.1e}");
    assert!(plain > 0.2, "plain {plain:.2}");
}

/// Columns of the bars at aspect ratios 1, 2 and 4 (`slope_failure::aspect_ratios`) at
/// dx = 2.5 mm against the laws fitted to the experiments of Nguyen, Bui & Fukagawa (2015):
/// final height h∞/h₀ = 1/(1.42 a^(2/3)) and run-out d∞/d₀ = 4.30 a^0.72 (the grain toe).
///
/// Tolerances from the convergence study of docs/soil.md ("Other aspect ratios", the
/// defaults: the mean-stress diffusion and the K₀ start): at dx = 1.25 mm h∞ is within 6.7 %
/// of the law (a = 1, 2, 4: −6.7, −3.1, +0.6 %) and moves by up to 1.6 % from 2.5 to 1.25 mm:
/// |h∞/h∞,law − 1| ≤ 6.7 + 1.6 ≈ 8.3 %. The grain toe is at most 10.0 % short of the law at
/// 1.25 mm (−10.0, +0.2, −1.9 %) and moves by up to 5.1 % from 2.5 to 1.25 mm:
/// |d∞/d∞,law − 1| ≤ 10.0 + 5.1 ≈ 15.1 %. At 5 mm the thin end of the deposit is not
/// resolved (the grain toe 16–25 % short), so the test runs at 2.5 mm. The law's two
/// published forms differ by up to 6 %.
#[test]
fn aspect_ratios_against_the_experiments() {
    for a in [1.0, 2.0, 4.0] {
        let mut scene = slope_failure::aspect_ratios::column_scene(a);
        scene.dx = 0.0025;
        let report = slope_failure::run(&scene, &RunOptions::default()).unwrap();
        eprintln!("{report}");
        let comparison = report.aspect_ratio.expect("a column of the bars");
        let (height, measured_height) = comparison.final_height;
        assert!((height / measured_height - 1.0).abs() <= 0.083, "{report}");
        let (runout, Some(measured_runout), _) = comparison.runout else {
            panic!("a = {a} has a run-out law");
        };
        assert!((runout / measured_runout - 1.0).abs() <= 0.151, "{report}");
    }
}
