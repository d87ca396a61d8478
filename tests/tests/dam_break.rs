//! Dam break against Martin & Moyce (1952).
//!
//! A water column a = 1 m wide and 2a high collapses in a 4 m × 4 m tank. Martin & Moyce
//! measured the surge front Z = x/a against T = t √(2g/a) and the residual height H = h/(2a)
//! against τ = t √(g/a) for n² = 2 (`data/validation/`).
//!
//! Tolerances. The measured times include the opening of the gate, which delays the collapse,
//! and the experiment has a wet-bed-free, rough tank floor; inviscid SPH therefore runs ahead
//! of the measured front. Published weakly compressible SPH results lead it by 0.2–0.3 in Z
//! at T = 2–3 (Colagrossi & Landrini 2003, J. Comput. Phys. 191:448, fig. 6), and so does
//! geosph at dx = 0.02 m (RMS ΔZ = 0.23, `docs/validation.md`). This coarse test case
//! (dx = 0.04 m, ≈ 1250 particles) must keep the RMS front error below 0.35 and every point
//! within 0.5, the height within RMS 0.08 (one part in twelve of the column), and never pass
//! Ritter's (1892) frictionless bound Z = 1 + 2T.

use std::path::PathBuf;

use geosph_runner::RunOptions;
use geosph_scene::Scene;

#[test]
fn dam_break_front_and_height_follow_martin_moyce() {
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.04;
    // τ = 5.25 (the 16th height point), front data end at T = 3.33 (t = 0.75 s).
    scene.end_time = 1.7;
    scene.output.interval = 0.25;
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-coarse");
    let _ = std::fs::remove_dir_all(&out);
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    let report = dam_break::run(&scene, &options).unwrap();
    let validation = report.validation.expect("the column has n² = 2");
    println!("{}\n{validation}", report.summary);
    assert_eq!(validation.front_points, 15);
    assert!(
        validation.front_rms < 0.35,
        "front RMS {}",
        validation.front_rms
    );
    assert!(
        validation.front_max < 0.5,
        "front max {}",
        validation.front_max
    );
    assert!(validation.height_points >= 15);
    assert!(
        validation.height_rms < 0.08,
        "height RMS {}",
        validation.height_rms
    );
    assert_eq!(validation.ahead_of_ritter, None);
    // The output a user opens: frames listed in the .pvd, the plots and the CSVs.
    let pvd = std::fs::read_to_string(out.join("dam-break-2d.pvd")).unwrap();
    // Frames at t = 0, 0.25, …, 1.5 s.
    assert_eq!(pvd.matches("<DataSet").count(), 7, "{pvd}");
    for file in [
        "front.png",
        "height.png",
        "front.csv",
        "diagnostics.csv",
        "frames/dam-break-2d_000006.vtu",
    ] {
        let size = std::fs::metadata(out.join(file))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(size > 100, "{file} missing or empty");
    }
}

/// The shipped 3D dam break, a slab periodic across y, meets the 2D case's Martin & Moyce bounds
/// through all 15 front points (t = 0.8 s) with fewer wall than fluid particles: the flow
/// wraps across y, so no side wall slows it, and the tank has walls only on its floor and ends.
#[test]
fn dam_break_3d_periodic_slab_follows_martin_moyce_with_fewer_walls_than_fluid() {
    let mut scene = Scene::from_ron(include_str!("../../data/scenes/dam-break-3d.ron")).unwrap();
    scene.end_time = 0.8;
    // Frames and free surfaces every 0.2 s, read by VTK in `.ci/run`.
    scene.output.interval = 0.2;
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-3d-slab");
    let _ = std::fs::remove_dir_all(&out);
    let options = RunOptions {
        out_dir: Some(out),
        ..Default::default()
    };
    let report = dam_break::run(&scene, &options).unwrap();
    let validation = report.validation.expect("the column has n² = 2");
    println!("{}\n{validation}", report.summary);
    let summary = &report.summary;
    assert!(
        summary.wall_particles < summary.fluid_particles,
        "{} wall for {} fluid particles",
        summary.wall_particles,
        summary.fluid_particles
    );
    assert_eq!(validation.front_points, 15);
    assert!(
        validation.front_rms < 0.35 && validation.front_max < 0.5,
        "front RMS {}, max {}",
        validation.front_rms,
        validation.front_max
    );
    assert!(
        validation.height_rms < 0.08,
        "height RMS {}",
        validation.height_rms
    );
    assert_eq!(validation.ahead_of_ritter, None);
}

/// With particle shifting the coarse dam break meets the same bounds, and through the wall
/// impact (t = 1 s) no particle leaves the tank through a wall: a shift is limited to
/// 0.1 dx per step (without the limit two particles left at t ≈ 0.92 s, `docs/fluid.md`).
#[test]
fn dam_break_with_particle_shifting_keeps_its_particles_in_the_tank() {
    let text = dam_break::DEFAULT_SCENE.replacen("cfl: 0.25,", "cfl: 0.25, shifting: Some(()),", 1);
    assert!(
        text.contains("shifting"),
        "the scene's solver block changed"
    );
    let mut scene = Scene::from_ron(&text).unwrap();
    scene.dx = 0.04;
    scene.end_time = 1.0;
    let report = dam_break::run(&scene, &RunOptions::default()).unwrap();
    let validation = report.validation.expect("the column has n² = 2");
    println!("{}\n{validation}", report.summary);
    assert_eq!(report.summary.escaped, 0);
    assert!(validation.front_rms < 0.35 && validation.front_max < 0.5);
    assert!(validation.height_rms < 0.08);
    assert_eq!(validation.ahead_of_ritter, None);
}

/// The front's shape and its convergence (issue 21's bar), at dx = 0.03 and 0.015 m through
/// all 15 measured front points (T ≤ 3.33, t = 0.75 s): delayed by the stated gate delay
/// ΔT = `GATE_DELAY` (fitted once to the default run, `docs/validation.md`), the finer run's
/// front is within 3 % RMS of Martin & Moyce's; and the two resolutions' fronts differ by at
/// most 1 % RMS at the measured times, so the remaining raw lead (ΔZ ≈ 0.2) is not a
/// resolution effect.
#[test]
fn dam_break_front_shape_after_gate_delay_and_resolution_convergence() {
    let front = |dx: f64| {
        let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
        scene.dx = dx;
        scene.end_time = 0.8;
        scene.output.vtk = false;
        let report = dam_break::run(&scene, &RunOptions::default()).unwrap();
        let validation = report.validation.expect("the column has n² = 2");
        println!("dx = {dx}:\n{validation}");
        (report.samples, validation)
    };
    let (coarse, _) = front(0.03);
    let (fine, validation) = front(0.015);
    assert_eq!(validation.front_points, 15);
    assert!(
        validation.delayed_front_rms <= 0.03,
        "front after ΔT = {}: RMS {:.2} %",
        dam_break::GATE_DELAY,
        100.0 * validation.delayed_front_rms
    );
    let at = |samples: &[dam_break::Sample], t: f64| {
        let k = samples
            .partition_point(|s| s.time < t)
            .clamp(1, samples.len() - 1);
        let (a, b) = (samples[k - 1], samples[k]);
        a.front + (b.front - a.front) * (t - a.time) / (b.time - a.time)
    };
    let scale = (2.0 * 9.81_f64).sqrt();
    let differences: Vec<f64> = dam_break::martin_moyce_front()
        .x
        .iter()
        .map(|&t_scaled| {
            let t = t_scaled / scale;
            (at(&coarse, t) - at(&fine, t)) / at(&fine, t)
        })
        .collect();
    let rms = (differences.iter().map(|d| d * d).sum::<f64>() / differences.len() as f64).sqrt();
    println!("dx = 0.03 against 0.015 m: RMS {:.2} %", 100.0 * rms);
    assert!(
        rms <= 0.01,
        "fronts at dx and dx/2 differ by {:.2} % RMS",
        100.0 * rms
    );
}
