//! PCISPH, IISPH and DFSPH against analytic and experimental references.
//!
//! - Hydrostatic tank (2D): still water of depth H = 0.4 m in a 0.3 m wide tank, dx = 0.02 m,
//!   run for 20 s of simulated time, the stability horizon geosph requires of every solver, with the pressure
//!   solved to a target average compression of 0.1 %: the measured average compression over
//!   the run at the target (5 % allowance, see the assertion), no particle through a wall,
//!   the mass exact, and the pressure (averaged over the second 10 s, sampled every step)
//!   against ρ₀ g (H − y), H the depth of the water's mass at ρ₀: the bed layer and the mean
//!   over the layers below the top three within 5 % (see the test); for each solver, and for
//!   IISPH converged to 0.01 %, the profile read by pressure probes on the centre line and the
//!   one averaged over pairs of adjacent layers within 2 % of the bed pressure ρ₀ g H.
//! - Dam break (coarse, dx = 0.04 m) at the default velocity CFL of 0.4, against Martin &
//!   Moyce (1952) with the same bounds as the WCSPH case (`dam_break.rs`: front RMS < 0.35,
//!   every point within 0.5, height RMS < 0.08, never ahead of Ritter's bound), and an
//!   average compression below 0.2 % at the default 0.1 % target.

use geosph_core::{Particles, Real};
use geosph_kernels::KernelKind;
use geosph_runner::{NoObserver, Observer, PressureProbes, RunOptions, Share, Summary, run};
use geosph_scene::ProbeSpec;
use geosph_scene::Scene;

use crate::wcsph::LayerAverage;

/// Tank width in m (narrower than the WCSPH case: the pressure solves iterate 20–80 times per
/// step in still water).
const WIDTH: f64 = 0.3;

/// Rest density ρ₀ (kg/m³) and gravity g (m/s²) of the scenes.
const RHO0: Real = 1000.0;
const G: Real = 9.81;

/// No particle lost or through a wall (x in (0, width), y > 0) and all masses equal.
fn check_contained(fluid: &Particles<2>, initial: usize, width: Real) {
    assert_eq!(fluid.len(), initial, "particles were lost");
    assert!(
        fluid.mass.iter().all(|&m| m == fluid.mass[0]),
        "a particle mass changed"
    );
    for x in &fluid.position {
        assert!(
            x[0] > 0.0 && x[0] < width && x[1] > 0.0,
            "particle crossed a wall: {x:?}"
        );
    }
}

/// Heights (m) of the probes on the tank's centre line: every dx/2 from y = 0.06 m to
/// 0.32 m, where the probe's support (2.6 dx) lies inside the water, clear of the bed and of
/// the surface.
fn probe_heights() -> Vec<Real> {
    (12..=64).map(|k| 0.005 * k as Real).collect()
}

/// The still tank's layer pressures ([`LayerAverage`]) and a column of pressure probes
/// ([`PressureProbes`], the scene's gauges), both averaged from `layers.from` on.
struct TankObserver {
    layers: LayerAverage,
    probes: PressureProbes<2>,
    sums: Vec<Real>,
    samples: usize,
    row: Vec<Real>,
}

impl Observer<2> for TankObserver {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, time: Real, fluid: &Particles<2>, row: &mut Vec<Real>) {
        Observer::<2>::sample(&mut self.layers, time, fluid, row);
        if time < self.layers.from - 1e-9 {
            return;
        }
        self.row.clear();
        self.probes.sample(&Share::whole_run(fluid), &mut self.row);
        for (sum, p) in self.sums.iter_mut().zip(&self.row) {
            *sum += p;
        }
        self.samples += 1;
    }
}

impl Observer<3> for TankObserver {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, _time: Real, _fluid: &Particles<3>, _row: &mut Vec<Real>) {
        unreachable!("the tank is 2D")
    }
}

/// The still tank with `solver`.
struct Tank {
    summary: Summary,
    /// Layer pressures averaged over the second half, below the top three layers, as (y, p).
    layers: Vec<(Real, Real)>,
    /// Probe pressures on the centre line averaged over the second half, as (y, p).
    probes: Vec<(Real, Real)>,
    /// The depth H = Σm / (ρ₀ W) of the water at rest density.
    water_depth: Real,
    /// The final fluid.
    fluid: Particles<2>,
}

/// Runs the still tank with `solver`, sampling every step (Δt is the 5 ms `max_time_step`
/// in still water): samples a fixed number of steps apart would alias a pressure that
/// alternates from step to step, which PCISPH's and DFSPH's do at some step sizes
/// (`docs/incompressible.md`, "Equal steps up to each event").
///
/// The reference depth comes from the mass, not from the filled box: the incompressible
/// solvers give each particle the mass ρ₀ / Σ_k W of the lattice (1 % below ρ₀ dx² for
/// Wendland C2, `docs/incompressible.md`), so at ρ₀ the water stands 1 % lower than the box,
/// and its weight, which the bed carries, is ρ₀ g H W.
fn tank_profile(solver: &str) -> Tank {
    let (dx, depth, end_time) = (0.02, 0.4, 20.0);
    let scene = Scene::from_ron(&format!(
        "Scene(name: \"hydrostatic\", dimension: 2, dx: {dx}, end_time: {end_time},
            output: (interval: {end_time}, sample_interval: 0.005, vtk: false),
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [{WIDTH}, {depth}])]),
            walls: [Tank(min: [0.0, 0.0], max: [{WIDTH}, 1.0])],
            solver: {solver})"
    ))
    .unwrap();
    let heights = probe_heights();
    let probes: Vec<ProbeSpec> = heights
        .iter()
        .enumerate()
        .map(|(k, &y)| ProbeSpec {
            name: format!("p{k}"),
            position: vec![0.5 * WIDTH, y],
        })
        .collect();
    let kernel: KernelKind = scene.kernel.parse().unwrap();
    let mut observer = TankObserver {
        layers: LayerAverage {
            from: 0.5 * end_time,
            dx,
            depth,
            ..Default::default()
        },
        probes: PressureProbes::new(&probes, kernel, scene.smoothing_ratio * dx),
        sums: vec![0.0; heights.len()],
        samples: 0,
        row: Vec::new(),
    };
    let summary = run(&scene, &RunOptions::default(), &mut observer)
        .unwrap_or_else(|error| panic!("{solver}: {error}"));
    println!("{summary}");
    let (_, fluid) = observer.layers.last.plane.take().unwrap();
    let water_depth = fluid.mass.iter().sum::<Real>() / (RHO0 * WIDTH);
    let layers = observer.layers.mean();
    for &(y, p) in &layers {
        println!(
            "{solver} y = {y:.3}: p/ρ₀g(H − y) − 1 = {:+.2} %, (p − ρ₀g(H − y))/ρ₀gH = {:+.2} %",
            100.0 * (p / (RHO0 * G * (water_depth - y)) - 1.0),
            100.0 * (p / (RHO0 * G * water_depth) - (1.0 - y / water_depth))
        );
    }
    let samples = observer.samples as Real;
    let probes: Vec<(Real, Real)> = heights
        .iter()
        .zip(&observer.sums)
        .map(|(&y, sum)| (y, sum / samples))
        .collect();
    for &(y, p) in &probes {
        println!(
            "{solver} probe y = {y:.3}: (p − ρ₀g(H − y))/ρ₀gH = {:+.2} %",
            100.0 * (p / (RHO0 * G * water_depth) - (1.0 - y / water_depth))
        );
    }
    Tank {
        summary,
        layers,
        probes,
        water_depth,
        fluid,
    }
}

/// Largest layer deviation from ρ₀ g (H − y), as a fraction of the bed pressure ρ₀ g H.
fn profile_error(layers: &[(Real, Real)], water_depth: Real) -> Real {
    layers
        .iter()
        .map(|&(y, p)| (p - RHO0 * G * (water_depth - y)).abs() / (RHO0 * G * water_depth))
        .fold(0.0, Real::max)
}

/// Largest deviation of the profile averaged over pairs of adjacent layers (2 dx), as a
/// fraction of ρ₀ g H. The pair average removes the layer-to-layer alternation of the
/// pressure, the Nyquist mode p ∝ (−1)^row that exerts no force on a lattice particle and so
/// is not fixed by the density constraint (`docs/incompressible.md`, "Still water").
fn pair_profile_error(layers: &[(Real, Real)], water_depth: Real) -> Real {
    let pairs: Vec<(Real, Real)> = layers
        .windows(2)
        .map(|w| (0.5 * (w[0].0 + w[1].0), 0.5 * (w[0].1 + w[1].1)))
        .collect();
    profile_error(&pairs, water_depth)
}

/// Largest deviation of the probes' pressure from ρ₀ g (H − y), as a fraction of ρ₀ g H.
fn probe_error(tank: &Tank) -> Real {
    profile_error(&tank.probes, tank.water_depth)
}

/// The still tank at the default 0.1 % target with `solver`: the required 2 % of ρ₀ g H on
/// the probes' profile and on the layers averaged in pairs ([`pair_profile_error`]); returns
/// the largest single-layer error as a fraction of ρ₀ g H.
fn hydrostatic_tank(solver: &str) -> Real {
    let tank = tank_profile(solver);
    let (summary, layers, water_depth) = (&tank.summary, &tank.layers, tank.water_depth);
    // The WCSPH tank's 5 % on the bed layer and on the mean relative error of the layers
    // below the top three (which weights the shallow layers most).
    let errors: Vec<Real> = layers
        .iter()
        .map(|&(y, p)| p / (RHO0 * G * (water_depth - y)) - 1.0)
        .collect();
    let mean_error = errors.iter().sum::<Real>() / errors.len() as Real;
    assert!(
        errors[0].abs() < 0.05 && mean_error.abs() < 0.05,
        "{solver}: bed layer {:+.2} %, mean over the layers {:+.2} %",
        100.0 * errors[0],
        100.0 * mean_error
    );
    let (smoothed, probed) = (pair_profile_error(layers, water_depth), probe_error(&tank));
    println!(
        "{solver}: largest error of ρ₀ g H: single layer {:.2} %, pair of layers {:.2} %, probes {:.2} %",
        100.0 * profile_error(layers, water_depth),
        100.0 * smoothed,
        100.0 * probed
    );
    assert!(
        smoothed < 0.02 && probed < 0.02,
        "{solver}: largest error of ρ₀ g H over pairs of layers {:.2} %, at the probes {:.2} %",
        100.0 * smoothed,
        100.0 * probed
    );
    check_contained(&tank.fluid, summary.fluid_particles, WIDTH);
    // The Jacobi solves stop once the *predicted* mean compression is at most the 0.1 %
    // target; the compression measured after the move differs from that linear prediction
    // at second order in Δt, for which we allow 5 %. BiCGSTAB, which does not stop on it,
    // is held to the same bound. The maximum is a stability guard.
    assert!(
        summary.max_density_error < 0.03 && summary.mean_density_error < 1.05e-3,
        "{solver}: compression mean {:.3} %, max {:.3} %",
        100.0 * summary.mean_density_error,
        100.0 * summary.max_density_error
    );
    profile_error(layers, water_depth)
}

/// The required 2 % profile, with the pressure converged further: IISPH at a 0.01 % target.
///
/// The layer pressures (layers dx thick) alternate about ρ₀ g (H − y) by up to ±3 % of the
/// bed pressure ρ₀ g H, a mode at the particle scale whose pattern changes with rounding
/// (`docs/incompressible.md`, "Still water"). Asserted are the probes and the layers averaged
/// in pairs (2 dx) within the required 2 % of ρ₀ g H, and every single layer within the WCSPH
/// tank's 5 %.
#[test]
fn hydrostatic_tank_converged_iisph_is_within_2_percent() {
    let solver = "Iisph((target_density_error: 0.0001, max_iterations: 500))";
    let tank = tank_profile(solver);
    let error = profile_error(&tank.layers, tank.water_depth);
    let smoothed = pair_profile_error(&tank.layers, tank.water_depth);
    let probed = probe_error(&tank);
    println!(
        "largest error of ρ₀ g H: single layer {:.2} %, pair of layers {:.2} %, probes {:.2} %",
        100.0 * error,
        100.0 * smoothed,
        100.0 * probed
    );
    assert!(
        smoothed < 0.02 && probed < 0.02 && error < 0.05,
        "{solver}: largest error of ρ₀ g H over pairs of layers {:.2} %, at the probes {:.2} %, \
         for one layer {:.2} %",
        100.0 * smoothed,
        100.0 * probed,
        100.0 * error
    );
    check_contained(&tank.fluid, tank.summary.fluid_particles, WIDTH);
    assert!(tank.summary.mean_density_error < 1.05e-4);
}

/// The required 2 % at the probes and over pairs of layers (1.30 % and 1.57 % measured).
#[test]
fn hydrostatic_tank_holds_rho_g_depth_for_20_s_pcisph() {
    hydrostatic_tank("Pcisph(())");
}

/// The required 2 % at the probes and over pairs of layers (1.78 % and 0.62 % measured).
#[test]
fn hydrostatic_tank_holds_rho_g_depth_for_20_s_iisph() {
    hydrostatic_tank("Iisph(())");
}

/// The required 2 % at the probes and over pairs of layers (0.63 % and 0.79 % measured).
#[test]
fn hydrostatic_tank_holds_rho_g_depth_for_20_s_dfsph() {
    hydrostatic_tank("Dfsph(())");
}

/// IISPH with the BiCGSTAB solve meets the required 2 % on every single layer too (1.73 %
/// measured; pairs of layers 0.69 %, probes 0.99 %).
#[test]
fn hydrostatic_tank_single_layers_within_2_percent_iisph_bicgstab() {
    let single = hydrostatic_tank("Iisph((iteration: Bicgstab(())))");
    assert!(
        single < 0.02,
        "largest single-layer error {:.2} % of ρ₀ g H",
        100.0 * single
    );
}

fn dam_break(solver: &str) {
    dam_break_with_scene(solver, dam_break::DEFAULT_SCENE);
}

fn dam_break_with_scene(solver: &str, scene: &str) {
    {
        let mut scene = Scene::from_ron(scene).unwrap();
        scene.dx = 0.04;
        scene.end_time = 1.7;
        scene.output.vtk = false;
        scene.solver = Scene::from_ron(&format!(
            "Scene(name: \"s\", dimension: 2, dx: 1.0, end_time: 1.0,
                solver: {solver})"
        ))
        .unwrap()
        .solver;
        let report = dam_break::run(&scene, &RunOptions::default())
            .unwrap_or_else(|error| panic!("{solver}: {error}"));
        let validation = report.validation.expect("the column has n² = 2");
        println!("{solver}\n{}\n{validation}", report.summary);
        assert!(
            validation.front_rms < 0.35,
            "{solver}: front RMS {}",
            validation.front_rms
        );
        assert!(
            validation.front_max < 0.5,
            "{solver}: front max {}",
            validation.front_max
        );
        assert!(
            validation.height_rms < 0.08,
            "{solver}: height RMS {}",
            validation.height_rms
        );
        assert_eq!(validation.ahead_of_ritter, None, "{solver}");
        assert!(
            report.summary.mean_density_error < 0.002,
            "{solver}: mean compression {}",
            report.summary.mean_density_error
        );
    }
}

#[test]
fn dam_break_follows_martin_moyce_pcisph() {
    dam_break("Pcisph(())");
}

#[test]
fn dam_break_follows_martin_moyce_iisph() {
    dam_break("Iisph(())");
}

#[test]
fn dam_break_follows_martin_moyce_dfsph() {
    dam_break("Dfsph(())");
}

/// The quintic spline (support 3h = 3.9 dx, 44 lattice neighbours) has λ_max = 4.11 for the
/// Jacobi iteration of the pressure system, so IISPH's published ω = 0.5 makes the stiffest
/// mode grow: this run blew up at step 17 (t = 0.06 s, 75 % compression) before the
/// relaxation was capped at 1.5/λ_max (`PressureSystem::relaxation_limit`).
#[test]
fn dam_break_follows_martin_moyce_iisph_quintic() {
    let scene = dam_break::DEFAULT_SCENE
        .replace("\"wendland-c2\"", "\"quintic-spline\"")
        .replace("layers: 3", "layers: 4");
    assert!(scene.contains("quintic-spline") && scene.contains("layers: 4"));
    dam_break_with_scene("Iisph(())", &scene);
}

/// A still 3D tank (0.2 × 0.2 m, 0.3 m deep, dx = 0.02 m, 1 500 particles) with IISPH at a
/// 0.01 % target, for 1 s. The lattice pressure system of Wendland C2 in 3D has λ_max = 4.20,
/// so the published ω = 0.5 makes its stiffest mode grow by 10 % per iteration: at the ~50
/// iterations per step this target needs, the run blew up at step 3 (39 % compression) before
/// the relaxation was capped at 1.5/λ_max (`PressureSystem::relaxation_limit`).
#[test]
fn still_tank_3d_iisph_converges_with_the_relaxation_limit() {
    let scene = Scene::from_ron(
        "Scene(name: \"tank3d\", dimension: 3, dx: 0.02, end_time: 1.0,
            output: (interval: 1.0, sample_interval: 0.01, vtk: false),
            fluid: (blocks: [Box(min: [0.0, 0.0, 0.0], max: [0.2, 0.2, 0.3])]),
            walls: [Tank(min: [0.0, 0.0, 0.0], max: [0.2, 0.2, 0.6])],
            solver: Iisph((target_density_error: 0.0001, max_iterations: 300)))",
    )
    .unwrap();
    let summary = run(&scene, &RunOptions::default(), &mut NoObserver)
        .unwrap_or_else(|error| panic!("3D IISPH tank: {error}"));
    println!("{summary}");
    assert_eq!(summary.escaped, 0);
    // The measured mean compression exceeds the predicted one the solve stops on at second
    // order in Δt (1.8 × 10⁻⁴ measured); a diverging solve gives percents.
    assert!(
        summary.mean_density_error < 5e-4 && summary.max_density_error < 0.05,
        "compression mean {:.4} %, max {:.2} %",
        100.0 * summary.mean_density_error,
        100.0 * summary.max_density_error
    );
    assert!(summary.mean_iterations < 300.0);
}

/// The first step of the dam break with the cubic spline at h = dx (SPlisHSPlasH's kernel and
/// support, 2 wall layers), dx = 0.015 m, DFSPH at a 1 % target: Δt is the 0.005 s bound and,
/// with the masked warm start and the mean target alone, the run stopped at step 1 on 21.3 %
/// compression (pairs of particles in the column closed to 0.76 dx; the health bound is
/// 20 %). The bound on any one particle's predicted compression (`max_compression`, 10 %)
/// mended that first; the release solve (the first solve may lower the initial pressure and
/// stops on the complementarity error, `docs/incompressible.md`) now holds it with the bound
/// off as well (measured: 2.8 % with either).
#[test]
fn dfsph_first_step_holds_local_compression() {
    let scene = dam_break::DEFAULT_SCENE
        .replace("\"wendland-c2\"", "\"cubic-spline\"")
        .replace("smoothing_ratio: 1.3", "smoothing_ratio: 1.0")
        .replace("layers: 3", "layers: 2");
    let mut scene = Scene::from_ron(&scene).unwrap();
    (scene.dx, scene.end_time, scene.output.vtk) = (0.015, 0.03, false);
    for max_compression in [1.0, 0.1] {
        let mut scene = scene.clone();
        scene.solver = Scene::from_ron(&format!(
            "Scene(name: \"s\", dimension: 2, dx: 1.0, end_time: 1.0,
                solver: Dfsph((target_density_error: 0.01, max_compression: {max_compression})))"
        ))
        .unwrap()
        .solver;
        let report = dam_break::run(&scene, &RunOptions::default())
            .unwrap_or_else(|error| panic!("max_compression {max_compression}: {error}"));
        println!("max_compression {max_compression}:\n{}", report.summary);
        assert!(
            report.summary.max_density_error < 0.15,
            "max_compression {max_compression}: max compression {:.2} %",
            100.0 * report.summary.max_density_error
        );
    }
}
