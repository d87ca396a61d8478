//! The app compares with Martin & Moyce (1952) only on their set-up, tracks a front only where
//! something collapses, and plots a scene's pressure probes.

use std::path::PathBuf;

use dam_break::{Column, DEFAULT_SCENE, is_martin_moyce};
use geosph_runner::RunOptions;
use geosph_scene::Scene;

fn edited(from: &str, to: &str) -> Scene {
    assert!(DEFAULT_SCENE.contains(from), "{from}");
    Scene::from_ron(&DEFAULT_SCENE.replacen(from, to, 1)).unwrap()
}

fn martin_moyce(scene: &Scene) -> bool {
    is_martin_moyce(scene, &Column::of(scene).unwrap())
}

#[test]
fn only_martin_and_moyces_set_up_is_compared_with_their_data() {
    assert!(martin_moyce(&Scene::from_ron(DEFAULT_SCENE).unwrap()));
    // The 3D column, with the default gravity.
    let three_d = include_str!("../../../data/scenes/dam-break-3d.ron");
    assert!(martin_moyce(&Scene::from_ron(three_d).unwrap()));
    // Aspect ratio 1: another experiment.
    assert!(!martin_moyce(&edited("max: [1.0, 2.0]", "max: [1.0, 1.0]")));
    // The column away from the back wall.
    assert!(!martin_moyce(&edited(
        "Box(min: [0.0, 0.0], max: [1.0, 2.0])",
        "Box(min: [1.0, 0.0], max: [2.0, 2.0])"
    )));
    // Gravity not straight down.
    assert!(!martin_moyce(&edited(
        "gravity: [0.0, -9.81]",
        "gravity: [1.0, -9.81]"
    )));
}

#[test]
fn a_wall_pressure_scene_gets_its_probe_plot_and_no_foreign_reference() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-probes");
    let _ = std::fs::remove_dir_all(&out);
    // Lobovsky et al.'s (2014) proportions, coarse: a 0.6 m × 0.3 m column in a 1.61 m tank,
    // gauges on the downstream wall.
    let scene = Scene::from_ron(
        "Scene(name: \"wall-pressure\", dimension: 2, dx: 0.03, gravity: [0.0, -9.81],
           end_time: 0.6, output: (interval: 0.3, sample_interval: 0.01, vtk: false,
               probes: [(name: \"low\", position: [1.61, 0.03]),
                        (name: \"high\", position: [1.61, 0.08])]),
           fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.6, 0.3])]),
           walls: [Tank(min: [0.0, 0.0], max: [1.61, 0.9])],
           solver: Wcsph(()))",
    )
    .unwrap();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        threads: Some(1),
        ..Default::default()
    };
    let report = dam_break::run(&scene, &options).unwrap();
    assert!(report.validation.is_none());
    assert!(!report.samples.is_empty());
    for plot in ["probes.png", "front.png", "height.png"] {
        let bytes = std::fs::read(out.join(plot)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{plot}");
    }
}

#[test]
fn without_gravity_nothing_is_tracked() {
    let scene = Scene::from_ron(
        "Scene(name: \"vortex\", dimension: 2, dx: 0.1, gravity: [0.0, 0.0], end_time: 0.02,
           domain: (min: [0.0, 0.0], max: [1.0, 1.0], periodic: [true, true]),
           fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])],
                   velocity: TaylorGreen(speed: 1.0, wavelength: 1.0)),
           solver: Wcsph(()))",
    )
    .unwrap();
    let options = RunOptions {
        threads: Some(1),
        ..Default::default()
    };
    let report = dam_break::run(&scene, &options).unwrap();
    assert!(report.samples.is_empty() && report.validation.is_none());
}
