//! Dam break against a wall: the pressure gauges of Lobovsky, Botia-Vera, Castellana,
//! Mas-Soler & Souto-Iglesias (2014, J. Fluids Struct. 48:407–434), with the shipped scene
//! `data/scenes/lobovsky-wall-pressure.ron` (H = 0.3 m) at its resolution H/dx = 60.
//!
//! The bar (issue 21): arrival within 0.1 t√(g/H), the plateau (t√(g/H) = 3–5.5) within
//! 0.05 ρgH on average. Asserted here where geosph meets it today, for WCSPH and DFSPH: the
//! arrival at sensors 1 and 3 (3 and 30 mm above the bed, where the surge strikes) and the
//! plateau at sensor 1. Reported but not asserted, because geosph does not meet the bar yet
//! (`docs/validation.md`, "Wall pressure"): the plateau at sensors 3 and 4 (0.06–0.13 ρgH
//! low), the raw signal's scatter about its running mean (0.1–0.3 ρgH against ≤ 0.05) and
//! WCSPH's negative dips after the impact.

use geosph_runner::RunOptions;
use geosph_scene::{Scene, SolverSpec};

const SCENE: &str = include_str!("../../data/scenes/lobovsky-wall-pressure.ron");

fn wall_pressure(solver: Option<&str>) {
    let mut scene = Scene::from_ron(SCENE).unwrap();
    if let Some(name) = solver {
        scene.solver = SolverSpec::from_name(name).unwrap();
    }
    // t√(g/H) = 5.72, past the plateau's end 5.5.
    scene.end_time = 1.0;
    scene.output.vtk = false;
    let report = dam_break::run(&scene, &RunOptions::default()).unwrap();
    assert!(report.validation.is_none(), "not Martin & Moyce's column");
    let comparison = report
        .wall_pressure
        .expect("Lobovsky's set-up with 3 gauges");
    println!("{}\n{comparison}", report.summary);
    let names: Vec<&str> = comparison.gauges.iter().map(|g| g.sensor).collect();
    assert_eq!(names, ["sensor 1", "sensor 3", "sensor 4"]);
    for gauge in &comparison.gauges[..2] {
        let (Some(arrival), Some(measured)) = gauge.arrival else {
            panic!("{}: no arrival", gauge.sensor)
        };
        assert!(
            (arrival - measured).abs() <= 0.1,
            "{}: arrival {arrival:.3} against {measured:.3}",
            gauge.sensor
        );
    }
    let sensor1 = &comparison.gauges[0];
    let (Some(plateau), Some(measured)) = sensor1.plateau else {
        panic!("sensor 1: the run does not cover the plateau")
    };
    assert!(
        (plateau - measured).abs() <= 0.05,
        "sensor 1: plateau {plateau:.3} against {measured:.3}"
    );
}

#[test]
fn wall_pressure_follows_lobovsky_wcsph() {
    wall_pressure(None);
}

#[test]
fn wall_pressure_follows_lobovsky_dfsph() {
    wall_pressure(Some("dfsph"));
}
