//! Weakly compressible SPH against analytic solutions.
//!
//! - Hydrostatic tank (2D, 3D): still water of depth H in a tank with Adami dummy walls. After
//!   settling, the pressure at height y is p = ρ₀ g (H − y) (Adami, Hu & Adams 2012, §5.1); we
//!   require the layer-averaged pressure, averaged over the second half of the run (the weakly
//!   damped acoustic breathing of the column, period 4H/c₀ ≈ 0.07 s, is still ±3 % after
//!   1 s), within 2 % of it for every single layer below the top three, the one touching the
//!   bed included (issue 21's bar; measured with the default Fourtakas diffusion and the
//!   lattice gradient correction: at most 1.8 % in 2D, 0.8 % in 3D), no particle through a
//!   wall, and the mass exactly conserved.
//! - The same 2D tank with its walls laid behind a mesh of the channel (issue 23): the same
//!   2 % bar for every layer and no particle through a wall.
//! - Closed periodic box without walls or gravity: the symmetric pressure and viscous forces
//!   are antisymmetric pair by pair, so total linear momentum is conserved to round-off.
//! - Bitwise identical results with 1 and 2 threads.

use geosph_core::{Particles, Real, Vector};
use geosph_fluid::build_wcsph;
use geosph_runner::{RunOptions, run};
use geosph_scene::Scene;
use geosph_tests::FinalState;

use rand::{Rng, SeedableRng, rngs::StdRng};

pub(crate) fn hydrostatic_scene(dimension: usize, dx: Real, depth: Real, end_time: Real) -> Scene {
    hydrostatic_scene_with(dimension, dx, depth, end_time, "Wcsph(())")
}

/// The still tank of `hydrostatic_scene` with the solver `solver` (RON).
fn hydrostatic_scene_with(
    dimension: usize,
    dx: Real,
    depth: Real,
    end_time: Real,
    solver: &str,
) -> Scene {
    let (min, max, tank) = if dimension == 2 {
        (
            "[0.0, 0.0]".to_owned(),
            format!("[1.0, {depth}]"),
            "[1.0, 1.0]".to_owned(),
        )
    } else {
        (
            "[0.0, 0.0, 0.0]".to_owned(),
            format!("[0.4, 0.4, {depth}]"),
            "[0.4, 0.4, 0.8]".to_owned(),
        )
    };
    let zero = if dimension == 2 {
        "[0.0, 0.0]"
    } else {
        "[0.0, 0.0, 0.0]"
    };
    Scene::from_ron(&format!(
        "Scene(name: \"hydrostatic\", dimension: {dimension}, dx: {dx}, end_time: {end_time},
            output: (interval: {end_time}, sample_interval: {end_time}, vtk: false),
            fluid: (blocks: [Box(min: {min}, max: {max})]),
            walls: [Tank(min: {zero}, max: {tank})],
            solver: {solver})"
    ))
    .unwrap()
}

/// Mean pressure of each horizontal particle layer (bins of height dx), with the layer's mean
/// height; layers within `skip_top` layers of the surface `depth` are left out.
fn layer_pressures<const D: usize>(
    fluid: &Particles<D>,
    dx: Real,
    depth: Real,
    skip_top: usize,
) -> Vec<(Real, Real)> {
    let pressure = fluid.pressure.as_ref().unwrap();
    let layers = (depth / dx).round() as usize;
    let mut sums = vec![(0.0, 0.0, 0usize); layers + 2];
    for (x, p) in fluid.position.iter().zip(pressure) {
        let layer = ((x[D - 1] / dx).floor().max(0.0) as usize).min(layers + 1);
        sums[layer].0 += x[D - 1];
        sums[layer].1 += p;
        sums[layer].2 += 1;
    }
    sums.iter()
        .take(layers.saturating_sub(skip_top))
        .filter(|s| s.2 > 0)
        .map(|&(y, p, n)| (y / n as Real, p / n as Real))
        .collect()
}

/// Accumulates layer-averaged pressures over the samples after `from`.
#[derive(Default)]
pub(crate) struct LayerAverage {
    pub from: Real,
    pub dx: Real,
    pub depth: Real,
    pub samples: usize,
    pub layers: Vec<(Real, Real)>,
    pub last: FinalState,
}

impl LayerAverage {
    fn add<const D: usize>(&mut self, time: Real, fluid: &Particles<D>) {
        if time < self.from - 1e-9 {
            return;
        }
        let layers = layer_pressures(fluid, self.dx, self.depth, 3);
        if self.layers.is_empty() {
            self.layers = vec![(0.0, 0.0); layers.len()];
        }
        for (sum, (y, p)) in self.layers.iter_mut().zip(layers) {
            sum.0 += y;
            sum.1 += p;
        }
        self.samples += 1;
    }

    pub fn mean(&self) -> Vec<(Real, Real)> {
        let n = self.samples as Real;
        self.layers.iter().map(|&(y, p)| (y / n, p / n)).collect()
    }
}

impl geosph_runner::Observer<2> for LayerAverage {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, time: Real, fluid: &Particles<2>, row: &mut Vec<Real>) {
        self.add(time, fluid);
        geosph_runner::Observer::<2>::sample(&mut self.last, time, fluid, row);
    }
}

impl geosph_runner::Observer<3> for LayerAverage {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, time: Real, fluid: &Particles<3>, row: &mut Vec<Real>) {
        self.add(time, fluid);
        geosph_runner::Observer::<3>::sample(&mut self.last, time, fluid, row);
    }
}

pub(crate) fn check_hydrostatic<const D: usize>(
    fluid: &Particles<D>,
    layers: &[(Real, Real)],
    initial: usize,
    dx: Real,
    depth: Real,
    wall: Real,
) {
    assert_eq!(fluid.len(), initial, "particles were lost");
    // Mass is carried by particles of equal, constant mass: conserved exactly when none is
    // lost and none changes. It is ρ₀ dx^D, except for the incompressible solvers, which use
    // ρ₀ / Σ_k W(|k dx|), 1 % less for Wendland C2 (`docs/incompressible.md`).
    let particle_mass = fluid.mass[0];
    let lattice_mass = 1000.0 * dx.powi(D as i32);
    assert!(
        (particle_mass / lattice_mass - 1.0).abs() < 0.02,
        "particle mass {particle_mass} against ρ₀ dx^D = {lattice_mass}"
    );
    assert!(
        fluid.mass.iter().all(|&m| m == particle_mass),
        "a particle mass changed"
    );
    for x in &fluid.position {
        for k in 0..D {
            let upper = if k == D - 1 { Real::INFINITY } else { wall };
            assert!(x[k] > 0.0 && x[k] < upper, "particle crossed a wall: {x:?}");
        }
    }
    let (rho, g) = (1000.0, 9.81);
    assert!(layers.len() >= 4, "too few layers: {}", layers.len());
    for &(y, p) in layers {
        let exact = rho * g * (depth - y);
        let error = (p - exact).abs() / exact;
        println!(
            "layer at y = {y:.3}: error {:+.2} %",
            100.0 * (p - exact) / exact
        );
        // Every single layer, the one touching the bed included, within 2 % of ρ g (H − y)
        // (issue 21's bar).
        assert!(
            error < 0.02,
            "layer at y = {y:.3}: p = {p:.1} Pa, ρg(H − y) = {exact:.1} Pa, error {:.2} %",
            100.0 * error
        );
    }
}

fn run_hydrostatic(
    dimension: usize,
    dx: Real,
    depth: Real,
    end_time: Real,
) -> (LayerAverage, usize) {
    run_hydrostatic_scene(hydrostatic_scene(dimension, dx, depth, end_time), dx, depth)
}

/// Runs a still-tank `scene`, averaging the layer pressures over its second half.
pub(crate) fn run_hydrostatic_scene(
    mut scene: Scene,
    dx: Real,
    depth: Real,
) -> (LayerAverage, usize) {
    let end_time = scene.end_time;
    scene.output.sample_interval = 0.01;
    let mut average = LayerAverage {
        from: 0.5 * end_time,
        dx,
        depth,
        ..Default::default()
    };
    let summary = run(&scene, &RunOptions::default(), &mut average).unwrap();
    (average, summary.fluid_particles)
}

#[test]
fn hydrostatic_tank_2d_matches_rho_g_depth() {
    let (dx, depth) = (0.02, 0.6);
    let (average, particles) = run_hydrostatic(2, dx, depth, 2.0);
    let (_, fluid) = average.last.plane.as_ref().unwrap();
    check_hydrostatic(fluid, &average.mean(), particles, dx, depth, 1.0);
}

#[test]
fn hydrostatic_tank_3d_matches_rho_g_depth() {
    let (dx, depth) = (0.04, 0.4);
    let (average, particles) = run_hydrostatic(3, dx, depth, 1.2);
    let (_, fluid) = average.last.space.as_ref().unwrap();
    check_hydrostatic(fluid, &average.mean(), particles, dx, depth, 0.4);
}

#[test]
fn periodic_box_conserves_linear_momentum() {
    let scene = Scene::from_ron(
        "Scene(name: \"periodic\", dimension: 2, dx: 0.05, end_time: 1.0, gravity: [0.0, 0.0],
            domain: (min: [0.0, 0.0], max: [1.0, 1.0], periodic: [true, true]),
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])], hydrostatic: false),
            solver: Wcsph((sound_speed: 10.0, viscosity: Artificial(alpha: 0.1, beta: 0.0),
                           diffusion: Molteni(delta: 0.1))))",
    )
    .unwrap();
    let (mut fluid, solver_inputs) = geosph_scene::build::<2>(&scene).unwrap().split();
    let mut rng = StdRng::seed_from_u64(7);
    for v in &mut fluid.velocity {
        *v = Vector::<2>::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
    }
    let momentum = |p: &Particles<2>| -> Vector<2> {
        p.velocity.iter().zip(&p.mass).map(|(v, m)| v * *m).sum()
    };
    let scale: Real = fluid
        .velocity
        .iter()
        .zip(&fluid.mass)
        .map(|(v, m)| v.norm() * m)
        .sum();
    let initial = momentum(&fluid);
    let geosph_scene::SolverSpec::Wcsph(config) = &scene.solver else {
        unreachable!("the scene names WCSPH")
    };
    let mut solver = build_wcsph(config, solver_inputs, &mut fluid).unwrap();
    let mut time = 0.0;
    for _ in 0..1000 {
        time += solver.step(&mut fluid, time, 1.0).unwrap().dt;
    }
    let drift = (momentum(&fluid) - initial).norm() / scale;
    // Round-off of ~10³ pair sums per particle over 1000 steps.
    assert!(
        drift < 1e-12,
        "momentum drift {drift:e} (relative to Σ m|v|)"
    );
}

#[test]
fn results_are_identical_for_one_and_two_threads() {
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.05;
    scene.end_time = 0.1;
    scene.output.vtk = false;
    let mut results = Vec::new();
    for threads in [1, 2] {
        let mut state = FinalState::default();
        let options = RunOptions {
            threads: Some(threads),
            ..Default::default()
        };
        run(&scene, &options, &mut state).unwrap();
        results.push(state.plane.unwrap().1);
    }
    let (one, two) = (&results[0], &results[1]);
    assert_eq!(one.id, two.id);
    for i in 0..one.len() {
        assert_eq!(one.position[i], two.position[i], "position of particle {i}");
        assert_eq!(one.velocity[i], two.velocity[i], "velocity of particle {i}");
        assert_eq!(
            one.density[i].to_bits(),
            two.density[i].to_bits(),
            "density of particle {i}"
        );
    }
}

/// The scene's pressure probes become `p_<name>` columns of `diagnostics.csv`: at t = 0 the
/// hydrostatic start holds ρ₀ g (H − y) on every particle (Tait, `hydrostatic: true`), so a
/// probe at a lattice point inside the water reads it (Shepard interpolation is exact for a
/// linear field over a symmetric support), and a probe above the water reads NaN.
#[test]
fn pressure_probes_read_the_hydrostatic_start() {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("probes");
    let _ = std::fs::remove_dir_all(&out);
    let scene = Scene::from_ron(
        "Scene(name: \"probes\", dimension: 2, dx: 0.02, end_time: 0.01,
            output: (interval: 0.01, sample_interval: 0.005, vtk: false,
                     probes: [(name: \"mid\", position: [0.15, 0.21]),
                              (name: \"dry\", position: [0.15, 0.8])]),
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.3, 0.4])], hydrostatic: true),
            walls: [Tank(min: [0.0, 0.0], max: [0.3, 1.0])],
            solver: Wcsph(()))",
    )
    .unwrap();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    run(&scene, &options, &mut geosph_runner::NoObserver).unwrap();
    let (column, rows) = diagnostics(&out);
    let (mid, dry) = (column("p_mid"), column("p_dry"));
    assert_eq!(rows.len(), 3, "samples at t = 0, 0.005 and 0.01 s");
    let expected = 1000.0 * 9.81 * (0.4 - 0.21);
    assert!(
        (rows[0][mid] / expected - 1.0).abs() < 1e-3,
        "p_mid = {} Pa at t = 0, expected {expected} Pa",
        rows[0][mid]
    );
    assert!(rows.iter().all(|row| row[dry].is_nan()));
}

/// The changes of the still tank's bed pressure (1 m wide, 0.6 m deep, dx = 0.02 m) between
/// consecutive readings of a probe at the middle of the bed every 1 ms over the second
/// second, as fractions of ρ₀ g H, with the solver `solver` (RON).
fn bed_pressure_changes(solver: &str, name: &str) -> Vec<Real> {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&out);
    let (dx, depth) = (0.02, 0.6);
    let mut scene = hydrostatic_scene_with(2, dx, depth, 2.0, solver);
    scene.output.sample_interval = 0.001;
    scene.output.probes = vec![geosph_scene::ProbeSpec {
        name: "bed".into(),
        position: vec![0.5, 0.0],
    }];
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    run(&scene, &options, &mut geosph_runner::NoObserver).unwrap();
    let (column, rows) = diagnostics(&out);
    let (time, bed) = (column("time"), column("p_bed"));
    let pressure: Vec<Real> = rows
        .into_iter()
        .filter(|row| row[time] >= 1.0)
        .map(|row| row[bed])
        .collect();
    assert!(pressure.len() > 900, "{} samples", pressure.len());
    let scale = 1000.0 * 9.81 * depth;
    pressure
        .windows(2)
        .map(|w| (w[1] - w[0]).abs() / scale)
        .collect()
}

/// WCSPH: the bed pressure changes by less than 1 % of ρ₀ g H from one sample (about every
/// 6 steps) to the next (issue 21's bar for a gauge's raw signal; 0.10 % measured,
/// `docs/validation.md`, "Hydrostatic tank").
#[test]
fn still_tank_bed_pressure_is_steady_from_sample_to_sample() {
    let largest = bed_pressure_changes("Wcsph(())", "bed-probe")
        .into_iter()
        .fold(0.0, Real::max);
    println!(
        "largest sample-to-sample change {:.3} % of ρ₀gH",
        100.0 * largest
    );
    assert!(largest < 0.01, "{:.2} % of ρ₀gH", 100.0 * largest);
}

/// IISPH with the BiCGSTAB solve: the bed pressure changes by less than 1 % of ρ₀ g H from
/// one step (1 ms) to the next on average (issue 21's bar; 0.18 % measured against 2.5 % with
/// the default relaxed Jacobi, whose few iterations stop at a different stage of the long
/// modes' convergence each step; the largest change, 1.55 %, is not within it:
/// `docs/validation.md`, "Hydrostatic tank").
#[test]
fn still_tank_bed_pressure_is_steady_with_the_bicgstab_solve() {
    let changes = bed_pressure_changes("Iisph((iteration: Bicgstab(())))", "bed-probe-bicgstab");
    let mean = changes.iter().sum::<Real>() / changes.len() as Real;
    let largest = changes.iter().copied().fold(0.0, Real::max);
    println!(
        "step-to-step change of ρ₀gH: mean {:.3} %, largest {:.3} %",
        100.0 * mean,
        100.0 * largest
    );
    assert!(mean < 0.01, "mean change {:.2} % of ρ₀gH", 100.0 * mean);
}

/// `diagnostics.csv` of the run in `out`: a column lookup by name and the rows as numbers.
fn diagnostics(out: &std::path::Path) -> (impl Fn(&str) -> usize, Vec<Vec<Real>>) {
    let csv = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let column = move |name: &str| {
        header
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    (column, rows)
}
