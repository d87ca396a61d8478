//! Particles that leave the domain leave the simulation: a lone particle thrown up above a
//! tank leaves through the top of the domain while the water stays in the tank. The run
//! goes on without it, counts it in the summary and in `diagnostics.csv`, and is the same
//! for any number of threads; when more than `health.max_escaped_fraction` of the particles
//! leave, the run stops with the outside-domain diagnosis.

use std::path::{Path, PathBuf};

use geosph_core::Real;
use geosph_runner::health::{self, Quantity};
use geosph_runner::{NoObserver, RunError, RunOptions, run};
use geosph_scene::{Scene, SolverSpec};

/// The lone particle of `data/scenes/tests/lone-particle.ron`: 100 particles of water in an
/// open tank and one thrown up through the top of the domain, which it crosses at
/// t = 0.099 s. With the default `health.max_escaped_fraction` of 1 %, one of 101 particles
/// (0.99 %) may leave.
pub(crate) fn lone_particle_scene(solver: &str) -> Scene {
    let mut scene =
        Scene::from_ron(include_str!("../../data/scenes/tests/lone-particle.ron")).unwrap();
    scene.solver = match solver {
        "soil" => SolverSpec::Soil(Default::default()),
        name => SolverSpec::from_name(name).unwrap(),
    };
    scene
}

/// The moment the lone particle crosses the top of the domain.
const ESCAPE_TIME: Real = 0.099;

fn scratch(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    folder
}

fn options(out: &Path, threads: usize) -> RunOptions {
    RunOptions {
        out_dir: Some(out.to_path_buf()),
        threads: Some(threads),
        ..Default::default()
    }
}

/// The `escaped` column of `diagnostics.csv` in `out`.
fn escaped_column(out: &Path) -> Vec<Real> {
    let text = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|name| *name == "escaped")
        .unwrap_or_else(|| panic!("no `escaped` column in {header:?}"));
    lines
        .map(|line| line.split(',').nth(column).unwrap().parse().unwrap())
        .collect()
}

/// Runs `scene` (one of [`lone_particle_scene`]) and checks what the run reports.
fn assert_the_lone_particle_escapes(label: &str, scene: &Scene) {
    let out = scratch(&format!("escape-{label}"));
    let summary = run(scene, &options(&out, 1), &mut NoObserver)
        .unwrap_or_else(|error| panic!("{label}: {error}"));
    assert!(summary.simulated_time >= scene.end_time - 1e-9, "{summary}");
    assert_eq!(summary.escaped, 1, "{label}: {summary}");
    assert_eq!(summary.fluid_particles, 100, "{label}: {summary}");
    let first = summary.first_escape.expect("a first escape time");
    // Removed after the step in which it leaves.
    assert!(
        (first - ESCAPE_TIME).abs() < 0.01,
        "{label}: first escape at {first} s"
    );
    // Its mass is one 101st of the fluid's (the incompressible solvers rescale all masses alike).
    assert!(
        (summary.escaped_mass_fraction - 1.0 / 101.0).abs() < 1e-3,
        "{label}: {summary}"
    );
    let text = summary.to_string();
    assert!(
        text.contains("escaped            1 particles (0.99")
            && text.contains(&format!("first at t = {first:.3} s")),
        "{text}"
    );
    let column = escaped_column(&out);
    assert_eq!(column.first(), Some(&0.0));
    assert_eq!(column.last(), Some(&1.0));
    assert!(column.windows(2).all(|pair| pair[0] <= pair[1]));
}

#[test]
fn a_wcsph_particle_that_leaves_the_domain_leaves_the_run() {
    assert_the_lone_particle_escapes("wcsph", &lone_particle_scene("wcsph"));
}

#[test]
fn a_pcisph_particle_that_leaves_the_domain_leaves_the_run() {
    assert_the_lone_particle_escapes("pcisph", &lone_particle_scene("pcisph"));
}

#[test]
fn a_dfsph_particle_that_leaves_the_domain_leaves_the_run() {
    assert_the_lone_particle_escapes("dfsph", &lone_particle_scene("dfsph"));
}

#[test]
fn a_soil_particle_that_leaves_the_domain_leaves_the_run() {
    assert_the_lone_particle_escapes("soil", &lone_particle_scene("soil"));
}

/// Without a Verlet skin, leap-frog WCSPH searches neighbours after the drift of every step,
/// so its search meets the particle outside inside the step: the lists bin it in their edge
/// cells, and it is removed after the step as with a skin.
#[test]
fn a_wcsph_particle_met_outside_inside_a_step_leaves_the_run() {
    let mut scene = lone_particle_scene("wcsph");
    let SolverSpec::Wcsph(config) = &mut scene.solver else {
        panic!("a WCSPH scene");
    };
    config.neighbour_skin = 0.0;
    assert_the_lone_particle_escapes("wcsph-no-skin", &scene);
}

/// The removal keeps the order of the other particles, so the run is the same with 1 and 2
/// threads, to the bit.
#[test]
fn a_run_with_an_escape_is_the_same_for_any_thread_count() {
    let mut outputs = Vec::new();
    for threads in [1, 2] {
        let out = scratch(&format!("escape-threads-{threads}"));
        run(
            &lone_particle_scene("wcsph"),
            &options(&out, threads),
            &mut NoObserver,
        )
        .unwrap();
        outputs.push((
            std::fs::read(out.join("diagnostics.csv")).unwrap(),
            std::fs::read(out.join("frames/escape_000006.vtu")).unwrap(),
        ));
    }
    assert!(outputs[0] == outputs[1], "1 and 2 threads differ");
}

/// With `health.max_escaped_fraction` below one particle in 101, the lone particle leaving is
/// a blow-up, diagnosed as before particles could leave.
#[test]
fn more_escapes_than_allowed_stop_the_run_with_the_outside_domain_diagnosis() {
    for solver in ["wcsph", "dfsph"] {
        let out = scratch(&format!("escape-too-many-{solver}"));
        let mut scene = lone_particle_scene(solver);
        scene.health.max_escaped_fraction = 0.005;
        let error = run(&scene, &options(&out, 1), &mut NoObserver).unwrap_err();
        let message = error.to_string();
        assert_eq!(error.exit_code(), health::EXIT_BLOW_UP, "{message}");
        let RunError::BlowUp {
            time, diagnosis, ..
        } = error
        else {
            panic!("{solver}: not a blow-up: {message}");
        };
        assert_eq!(diagnosis.quantity, Quantity::Position, "{message}");
        assert_eq!(diagnosis.particle.map(|(_, id)| id), Some(100), "{message}");
        assert!((time - ESCAPE_TIME).abs() < 0.01, "{message}");
        assert!(
            message.contains("1 of 101 particles (0.99 %) would have left the domain")
                && message.contains("`health.max_escaped_fraction` = 0.005"),
            "{message}"
        );
        assert!(out.join(health::report::REPORT_FILE).is_file());
    }
}
