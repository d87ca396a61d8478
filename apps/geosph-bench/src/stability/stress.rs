//! The stability map's stress cases: a long still-tank run, a jittered start, a 20 m/s impact
//! on a wall, and a cohesive soil block pulled apart (the time-step bisection is in the parent
//! module).

use std::time::Instant;

use geosph_core::{Particles, Real};
use geosph_fluid::config::DiffusionConfig;
use geosph_fluid::incompressible::PressureIteration;
use geosph_runner::{Observer, RunOptions};
use geosph_scene::{InitialVelocity, Scene, SolverSpec};

use super::StabilityResult;
use crate::case::run;
use crate::measures::{DEPTH, hydrostatic_error};

/// Free-surface height, pressure error and RMS speed of a still tank, sampled over a run.
#[derive(Clone, Debug, Default)]
struct TankWatch {
    dx: Real,
    /// (t, surface height, pressure error, RMS speed) per sample.
    samples: Vec<[Real; 4]>,
}

impl TankWatch {
    fn measure<const D: usize>(&mut self, time: Real, fluid: &Particles<D>) {
        let up = D - 1;
        // Highest particle per column of width dx, averaged.
        let mut tops: Vec<(i64, Real)> = fluid
            .position
            .iter()
            .map(|x| ((x[0] / self.dx).floor() as i64, x[up]))
            .collect();
        tops.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
        tops.dedup_by_key(|top| top.0);
        let surface =
            tops.iter().map(|top| top.1).sum::<Real>() / tops.len().max(1) as Real + 0.5 * self.dx;
        let pressure_error = fluid.pressure.as_ref().map_or(Real::NAN, |pressure| {
            let deep: Vec<Real> = fluid
                .position
                .iter()
                .zip(pressure)
                .filter(|(x, _)| x[up] < DEPTH - 3.0 * self.dx)
                .map(|(x, p)| hydrostatic_error(*p, x[up]).powi(2))
                .collect();
            (deep.iter().sum::<Real>() / deep.len().max(1) as Real).sqrt()
        });
        let speed = (fluid
            .velocity
            .iter()
            .map(|v| v.norm_squared())
            .sum::<Real>()
            / fluid.len().max(1) as Real)
            .sqrt();
        self.samples.push([time, surface, pressure_error, speed]);
    }
}

impl<const D: usize> Observer<D> for TankWatch {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, time: Real, fluid: &Particles<D>, _row: &mut Vec<Real>) {
        self.measure(time, fluid);
    }
}

/// The default solver of `name`, or for [`IISPH_BICGSTAB`] IISPH with its BiCGSTAB solve.
fn solver_spec(name: &str) -> Result<SolverSpec, String> {
    if name == IISPH_BICGSTAB {
        let mut spec = SolverSpec::from_name("iisph").expect("a solver");
        if let SolverSpec::Iisph(config) = &mut spec {
            config.iteration = PressureIteration::Bicgstab(Default::default());
        }
        return Ok(spec);
    }
    SolverSpec::from_name(name).ok_or_else(|| format!("unknown solver `{name}`"))
}

/// The subject name of IISPH with `iteration: Bicgstab(())` in the stress cases.
pub const IISPH_BICGSTAB: &str = "iisph+bicgstab";

fn tank_scene(solver: &str, dx: Real, end_time: Real, jitter: Real) -> Result<Scene, String> {
    let mut scene = Scene::from_ron(&format!(
        "Scene(name: \"tank\", dimension: 2, dx: {dx}, end_time: {end_time},
           output: (interval: {end_time}, sample_interval: {sample}, vtk: false),
           fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, {DEPTH}])], jitter: {jitter}),
           walls: [Tank(min: [0.0, 0.0], max: [1.0, 1.0])],
           solver: Wcsph(()))",
        sample = end_time / 100.0
    ))
    .map_err(|error| error.to_string())?;
    scene.solver = solver_spec(solver)?;
    Ok(scene)
}

/// The long run: a still tank, 0.5 m deep, dx = 0.05 m, for 10⁵ WCSPH steps (10⁴ `quick`);
/// the incompressible solvers for the same simulated time.
pub fn long_run(solver: &'static str, antuono: bool, quick: bool) -> StabilityResult {
    let started = Instant::now();
    let dx = 0.05;
    // WCSPH: dt = 0.25 · 1.3 dx / c₀, c₀ = 10 √(2 g H) = 31.3 m/s → 5.19 × 10⁻⁴ s.
    let end_time = if quick { 5.2 } else { 52.0 };
    let mut watch = TankWatch {
        dx,
        samples: Vec::new(),
    };
    let outcome = tank_scene(solver, dx, end_time, 0.0).and_then(|mut scene| {
        if let (SolverSpec::Wcsph(wcsph), true) = (&mut scene.solver, antuono) {
            wcsph.diffusion = DiffusionConfig::Antuono { delta: 0.1 };
        }
        run(&scene, &RunOptions::default(), &mut watch)
    });
    let (measured, passed) = match outcome {
        Err(reason) => (format!("blew up: {reason}"), false),
        Ok(summary) => {
            let samples = &watch.samples;
            let first = samples[0][1];
            let drift = samples
                .iter()
                .map(|s| (s[1] - first).abs())
                .fold(0.0, Real::max);
            let tenth = (samples.len() / 10).max(1);
            let mean =
                |part: &[[Real; 4]]| part.iter().map(|s| s[2]).sum::<Real>() / part.len() as Real;
            // Skip the first sample (the start, before any acoustic settling).
            let early = mean(&samples[1..=tenth]);
            let late = mean(&samples[samples.len() - tenth..]);
            (
                format!(
                    "{} steps to t = {end_time} s: surface drift {:.2} dx; pressure error {:.2} % early, {:.2} % late",
                    summary.steps,
                    drift / dx,
                    100.0 * early,
                    100.0 * late
                ),
                drift <= dx && late <= (1.5 * early).max(0.02),
            )
        }
    };
    StabilityResult {
        test: "long still tank",
        subject: if antuono {
            format!("{solver}+antuono")
        } else {
            solver.to_owned()
        },
        measured,
        criterion: "surface within one dx, late pressure error ≤ 1.5 × early or ≤ 2 % (the still-tank bar)",
        passed,
        wall_time: started.elapsed().as_secs_f64(),
    }
}

/// A still tank started from a lattice jittered by ±0.3 dx (dx = 0.025 m): it must settle to
/// an RMS speed below 5 % of √(g H) and a pressure error below 5 % of ρ₀ g H by t = 2 s.
pub fn jittered_start(solver: &'static str, quick: bool) -> StabilityResult {
    let started = Instant::now();
    let (dx, end_time) = if quick { (0.05, 1.0) } else { (0.025, 2.0) };
    let mut watch = TankWatch {
        dx,
        samples: Vec::new(),
    };
    let outcome = tank_scene(solver, dx, end_time, 0.3)
        .and_then(|scene| run(&scene, &RunOptions::default(), &mut watch));
    let scale = (9.81 * DEPTH).sqrt();
    let (measured, passed) = match outcome {
        Err(reason) => (format!("blew up: {reason}"), false),
        Ok(_) => {
            let &[_, _, pressure_error, speed] = watch.samples.last().expect("sampled");
            let peak = watch.samples.iter().map(|s| s[3]).fold(0.0, Real::max);
            (
                format!(
                    "peak RMS speed {:.3} √(gH), final {:.4} √(gH); final pressure error {:.2} %",
                    peak / scale,
                    speed / scale,
                    100.0 * pressure_error
                ),
                speed < 0.05 * scale && pressure_error < 0.05,
            )
        }
    };
    StabilityResult {
        test: "jittered start (±0.3 dx)",
        subject: format!("{solver} (dx = {dx})"),
        measured,
        criterion: "settles: RMS speed < 0.05 √(gH), pressure error < 5 %",
        passed,
        wall_time: started.elapsed().as_secs_f64(),
    }
}

/// The extent of the particles at the last sample, and how close two came.
#[derive(Clone, Debug)]
struct Extent {
    min: Real,
    max: Real,
    top: Real,
    /// Smallest distance between two particles over the nominal spacing, over all samples.
    closest: Real,
    dx: Real,
    watch_pairs: bool,
}

impl Extent {
    fn new(dx: Real, watch_pairs: bool) -> Self {
        Self {
            min: Real::NAN,
            max: Real::NAN,
            top: Real::NAN,
            closest: Real::INFINITY,
            dx,
            watch_pairs,
        }
    }
}

impl<const D: usize> Observer<D> for Extent {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }
    fn sample(&mut self, _time: Real, fluid: &Particles<D>, _row: &mut Vec<Real>) {
        self.min = fluid
            .position
            .iter()
            .map(|x| x[0])
            .fold(Real::INFINITY, Real::min);
        self.max = fluid
            .position
            .iter()
            .map(|x| x[0])
            .fold(Real::NEG_INFINITY, Real::max);
        self.top = fluid
            .position
            .iter()
            .map(|x| x[D - 1])
            .fold(Real::NEG_INFINITY, Real::max);
        if self.watch_pairs {
            let mut closest = Real::INFINITY;
            for (i, a) in fluid.position.iter().enumerate() {
                for b in &fluid.position[i + 1..] {
                    closest = closest.min((a - b).norm_squared());
                }
            }
            self.closest = self.closest.min(closest.sqrt() / self.dx);
        }
    }
}

/// Where the fluid of [`impact`] ended: its smallest and largest x and its largest y (m), the
/// tank's inner faces being x = 0, x = 1 m and y = 1 m, and the run's summary.
pub struct ImpactOutcome {
    /// Smallest x of a fluid particle at the end (the left wall's face is x = 0).
    pub min: Real,
    /// Largest x at the end (the right wall's face is x = 1 m).
    pub max: Real,
    /// Largest y at the end (the lid's face is y = 1 m).
    pub top: Real,
    /// The run's summary.
    pub summary: geosph_runner::Summary,
}

/// Runs the 0.2 m water block thrown at 20 m/s against the left wall of a closed 1 m tank
/// with `solver` at spacing `dx`, or says why it stopped.
pub fn impact_outcome(solver: &str, dx: Real) -> Result<ImpactOutcome, String> {
    let mut extent = Extent::new(dx, false);
    let scene = Scene::from_ron(&format!(
        "Scene(name: \"impact\", dimension: 2, dx: {dx}, end_time: 0.1,
           output: (interval: 0.1, sample_interval: 0.005, vtk: false),
           fluid: (blocks: [Box(min: [0.4, 0.0], max: [0.6, 0.2])], hydrostatic: false,
                   velocity: Uniform([-20.0, 0.0])),
           walls: [Tank(min: [0.0, 0.0], max: [1.0, 1.0], open_top: false)],
           solver: Wcsph(()))"
    ))
    .map_err(|error| error.to_string());
    let summary = scene.and_then(|mut scene| {
        scene.solver = solver_spec(solver)?;
        run(&scene, &RunOptions::default(), &mut extent)
    })?;
    Ok(ImpactOutcome {
        min: extent.min,
        max: extent.max,
        top: extent.top,
        summary,
    })
}

/// A 0.2 m water block thrown at 20 m/s against the left wall of a closed 1 m tank
/// (dx = 0.01 m): no particle may cross a wall.
pub fn impact(solver: &'static str, quick: bool) -> StabilityResult {
    let started = Instant::now();
    let dx = if quick { 0.02 } else { 0.01 };
    let (measured, passed) = match impact_outcome(solver, dx) {
        Err(reason) => (format!("blew up: {reason}"), false),
        Ok(end) => (
            format!(
                "{} steps; particles in x = {:.3}…{:.3} m, below y = {:.3} m at the end; max density error {:.1} %; {} particle-steps put back on a wall's surface",
                end.summary.steps,
                end.min,
                end.max,
                end.top,
                100.0 * end.summary.max_density_error,
                end.summary.wall_contacts
            ),
            end.min >= 0.0 && end.max <= 1.0 && end.top <= 1.0,
        ),
    };
    StabilityResult {
        test: "20 m/s impact",
        subject: format!("{solver} (dx = {dx})"),
        measured,
        criterion: "completes, no particle behind a wall's surface",
        passed,
        wall_time: started.elapsed().as_secs_f64(),
    }
}

/// A cohesive Drucker–Prager block (c = 10 kPa, φ = 30°, E = 10 MPa), 0.1 m square, without
/// gravity or walls, pulled apart at 2 s⁻¹ for 0.05 s: the closest two particles must stay
/// more than half a spacing apart (the tensile instability pairs them up, Swegle et al. 1995),
/// with and without Gray et al.'s (2001) artificial stress.
pub fn tension(artificial_stress: bool, quick: bool) -> StabilityResult {
    let started = Instant::now();
    let dx = if quick { 0.005 } else { 0.0025 };
    let stress = if artificial_stress {
        "artificial_stress: Some((epsilon: 0.3, exponent: 4.0)),"
    } else {
        ""
    };
    let mut extent = Extent::new(dx, true);
    let outcome = Scene::from_ron(&format!(
        "Scene(name: \"tension\", dimension: 2, dx: {dx}, end_time: 0.05, gravity: [0.0, 0.0],
           output: (interval: 0.05, sample_interval: 0.005, vtk: false),
           soil: (density: 2000.0, blocks: [Box(min: [0.0, 0.0], max: [0.1, 0.1])]),
           solver: Soil((
               constitutive: DruckerPrager(
                   material: (youngs_modulus: 1.0e7, poisson_ratio: 0.3, friction_angle_deg: 30.0,
                              cohesion: 1.0e4, dilatancy_angle_deg: 0.0),
                   algorithm: Bui2008,
               ),
               {stress}
           )))"
    ))
    .map_err(|error| error.to_string())
    .and_then(|mut scene| {
        if let Some(fluid) = &mut scene.fluid {
            fluid.velocity = InitialVelocity::Stretch {
                centre: vec![0.05, 0.05],
                rate: 2.0,
            };
        }
        run(&scene, &RunOptions::default(), &mut extent)
    });
    let (measured, passed) = match outcome {
        Err(reason) => (format!("blew up: {reason}"), false),
        Ok(summary) => (
            format!(
                "{} steps; closest pair {:.2} dx",
                summary.steps, extent.closest
            ),
            extent.closest > 0.5,
        ),
    };
    StabilityResult {
        test: "cohesive block in tension",
        subject: format!(
            "soil, {} (dx = {dx})",
            if artificial_stress {
                "artificial stress ε = 0.3"
            } else {
                "no artificial stress"
            }
        ),
        measured,
        criterion: "no clumping: closest pair > 0.5 dx",
        passed,
        wall_time: started.elapsed().as_secs_f64(),
    }
}
