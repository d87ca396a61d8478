//! `geosph-distributed-check`: the 2D dam break of `data/scenes/dam-break-2d.ron` (with WCSPH
//! as shipped and with PCISPH, IISPH and DFSPH) and the soil collapse of
//! `data/scenes/granular-collapse.ron` (all coarser, and shorter) distributed over the ranks of
//! `mpiexec`, against the same runs in one process, particle by particle.
//!
//! Every rank builds each scene and runs it twice: alone (the reference), and as one rank of
//! the distributed run (the soil's geostatic stage runs in full on every rank first, then the
//! run is shared). At the end the ranks gather their owned particles; every particle must be
//! owned by exactly one rank and agree with the reference within round-off: |Δx| ≤ 10⁻⁹ dx,
//! |Δv| ≤ 10⁻⁹ c (the sound or P-wave speed; for the incompressible solvers, which have
//! none, the free-fall speed √(2 g H) of the column's height), |Δρ| ≤ 10⁻⁹ ρ₀ and, for soil,
//! |Δσ| ≤ 10⁻⁹ of the solver's stress scale; and the runs must take as many steps and, for
//! the incompressible solvers (but BiCGSTAB: `CASES`), as many pressure iterations. The two runs differ only in the order in which each particle
//! sums its neighbours (which the lists' order sets); a neighbour missing from a halo changes
//! the results by orders of magnitude more (a halo one cell deep: 7 × 10⁻⁵ dx in the dam
//! break).
//!
//! `mpiexec -n 4 geosph-distributed-check [--dx-scale 1] [--end-scale 1] [--only <scene name>]`;
//! exit status 1 if a check fails, 2 on bad input.

use std::process::ExitCode;
use std::sync::Arc;

use geosph_core::{Particles, Real};
use geosph_mpi::Ranks;
use geosph_runner::build_solver;
use geosph_scene::{Scene, setup};
use geosph_sph::Solver;

/// A case of the check.
struct Case {
    /// The scene's text.
    scene: &'static str,
    /// The (from, to) changes made to it.
    changes: &'static [(&'static str, &'static str)],
    /// The solver that replaces the scene's: the case's name after the scene's, and the
    /// solver as the scene's RON writes it.
    solver: Option<(&'static str, &'static str)>,
    /// The coarse dx and the end time.
    dx: Real,
    end: Real,
    /// Whether the distributed run must take as many pressure iterations as one process.
    same_iterations: bool,
}

const DAM_BREAK: &str = include_str!("../../../../data/scenes/dam-break-2d.ron");

/// A case of the dam break with `solver` to `end`.
const fn dam_break(solver: Option<(&'static str, &'static str)>, end: Real) -> Case {
    Case {
        scene: DAM_BREAK,
        changes: &[],
        solver,
        dx: 0.04,
        end,
        same_iterations: true,
    }
}

/// The cases. The dam break runs as shipped, and with the options whose passes read values
/// summed two cells away or reduce over the ranks inside a step: Antuono's δ-SPH
/// (renormalised density gradients), a Shepard density every 20 steps, particle shifting (the
/// largest speed), XSPH and symplectic Euler, to 0.05 s: this flow amplifies round-off sooner
/// (one process perturbed by one ulp of x departs from itself by 5 × 10⁻¹⁴ dx at 0.03 s and
/// 6.5 dx at 0.15 s: the shifting's free-surface switch). The Runge–Kutta and
/// predictor–corrector integrators, whose later stages read the halo moved by the stage
/// before (refreshed by `ExplicitSystem::begin_stage`), run to 0.1 s, and so does SPS
/// turbulence (C_s = 0.5, so that its stress is large) beside a laminar viscosity, whose
/// no-slip walls show the fluid a velocity extrapolated from each rank's own particles:
/// the halo's stresses come from their owners (docs/turbulence.md).
/// The soil runs to 0.04 s, the onset of its flow: from 0.05 s on, the yield and the wall
/// friction switching particle by particle amplify round-off, and one process perturbed by
/// one ulp of x departs from itself by 10⁻⁶ dx at 0.1 s and 10⁻³ dx at 0.2 s
/// (docs/parallel.md).
/// The incompressible solvers' pressure solves refresh the halo's p/ρ² at every iteration
/// and stop on errors reduced over the ranks, so an iteration more or less on one rank shows.
/// PCISPH and IISPH (relaxed Jacobi) run with their defaults to 0.3 s, DFSPH to 0.1 s: its
/// warm start switches on where a particle's residual before any pressure is positive, which
/// round-off decides near rest (one process whose x coordinates are changed by one part in
/// 10¹⁵ departs from itself by 0.12 dx at 0.03 s), and the distributed run's round-off,
/// 10⁻¹³ dx at 0.1 s, reaches 10⁻² dx by 0.3 s. IISPH's BiCGSTAB stops at a residual of a
/// fraction `tolerance` of its source, and two solves that both reach it differ by about that
/// fraction (its iterates are no smooth function of the round-off of the dot products, whose
/// order the ranks change): at its default 10⁻² one step differs from one process by 4 × 10⁻³
/// of √(2 g H), at 10⁻⁸ by 2 × 10⁻⁸, at 10⁻¹⁰ by 6 × 10⁻¹²; so it runs at 10⁻¹⁰ for one
/// step (5 ms), and its iteration counts, which at that tolerance depend on the round-off, are not
/// compared.
const CASES: [Case; 10] = [
    dam_break(None, 0.3),
    dam_break(Some(("pcisph", "Pcisph(())")), 0.3),
    dam_break(Some(("iisph", "Iisph(())")), 0.3),
    Case {
        same_iterations: false,
        ..dam_break(
            Some((
                "iisph-bicgstab",
                "Iisph((iteration: Bicgstab((tolerance: 1e-10)), max_iterations: 1000))",
            )),
            0.005,
        )
    },
    dam_break(Some(("dfsph", "Dfsph(())")), 0.1),
    Case {
        changes: &[
            ("dam-break-2d", "dam-break-2d-options"),
            ("Fourtakas(delta: 0.1)", "Antuono(delta: 0.1)"),
            (
                "integrator: LeapFrog,",
                "integrator: SymplecticEuler, shepard_every: 20, shifting: Some(()), xsph: 0.25,",
            ),
        ],
        ..dam_break(None, 0.05)
    },
    Case {
        changes: &[
            ("dam-break-2d", "dam-break-2d-runge-kutta"),
            ("integrator: LeapFrog,", "integrator: RungeKutta4,"),
        ],
        ..dam_break(None, 0.1)
    },
    Case {
        changes: &[
            ("dam-break-2d", "dam-break-2d-predictor-corrector"),
            ("integrator: LeapFrog,", "integrator: PredictorCorrector,"),
        ],
        ..dam_break(None, 0.1)
    },
    Case {
        changes: &[
            ("dam-break-2d", "dam-break-2d-sps"),
            (
                "viscosity: Artificial(alpha: 0.02, beta: 0.0),",
                "viscosity: Laminar(kinematic_viscosity: 1e-3),",
            ),
            (
                "integrator: LeapFrog,",
                "integrator: LeapFrog, sps: Some((smagorinsky: 0.5)),",
            ),
        ],
        ..dam_break(None, 0.1)
    },
    Case {
        scene: include_str!("../../../../data/scenes/granular-collapse.ron"),
        changes: &[],
        solver: None,
        dx: 0.005,
        end: 0.04,
        same_iterations: true,
    },
];

/// Relative agreement with the single-process run (in units of dx, c, ρ₀ and the stress
/// scale).
const ROUND_OFF: Real = 1e-9;

fn main() -> ExitCode {
    let ranks = match Ranks::init() {
        Ok(ranks) => Arc::new(ranks),
        Err(error) => {
            eprintln!("geosph-distributed-check: {error}");
            return ExitCode::from(2);
        }
    };
    ranks.abort_on_panic();
    let result = arguments().and_then(|arguments| {
        let mut passed = true;
        for case in &CASES {
            let mut text = case.scene.to_owned();
            for (from, to) in case.changes {
                text = text.replacen(from, to, 1);
            }
            let mut label = Scene::from_ron(&text)
                .map_err(|error| error.to_string())?
                .name;
            if let Some((name, spec)) = case.solver {
                // The scene's solver is its last field.
                let start = text.find("    solver: ").expect("a scene's solver");
                text = format!("{}    solver: {spec},\n)\n", &text[..start]);
                label = format!("{label}/{name}");
            }
            let mut scene = Scene::from_ron(&text).map_err(|error| error.to_string())?;
            if arguments.only.as_ref().is_some_and(|only| *only != label) {
                continue;
            }
            scene.dx = case.dx * arguments.dx_scale;
            let end = case.end * arguments.end_scale;
            passed &= check(&ranks, &label, &scene, end, case.same_iterations)?;
        }
        Ok(passed)
    });
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(message) => {
            eprintln!(
                "geosph-distributed-check (rank {}): {message}",
                ranks.rank()
            );
            ExitCode::from(2)
        }
    }
}

/// The command line: factors on each case's dx and end time, and the one case to run.
struct Arguments {
    dx_scale: Real,
    end_scale: Real,
    only: Option<String>,
}

/// `--dx-scale`, `--end-scale` and `--only <case>` (a scene's name, with `/<solver>` where
/// the case replaces its solver: `dam-break-2d/iisph-bicgstab`) from the command line.
fn arguments() -> Result<Arguments, String> {
    let mut parsed = Arguments {
        dx_scale: 1.0,
        end_scale: 1.0,
        only: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().ok_or(format!("{flag} needs a value"))?;
        if flag == "--only" {
            parsed.only = Some(value);
            continue;
        }
        let number: Real = value
            .parse()
            .map_err(|_| format!("{flag}: not a number: {value}"))?;
        match flag.as_str() {
            "--dx-scale" if number > 0.0 => parsed.dx_scale = number,
            "--end-scale" if number > 0.0 => parsed.end_scale = number,
            _ => {
                return Err(format!(
                    "unknown flag or value out of range (> 0): {flag} {value}"
                ));
            }
        }
    }
    Ok(parsed)
}

/// The particles and solver of the scene, built as every rank builds them, after the
/// solver's initial stage (the soil's geostatic stage).
fn build(scene: &Scene) -> Result<(Particles<2>, Box<dyn Solver<2>>), String> {
    let (mut particles, inputs) = setup::build::<2>(scene)
        .map_err(|error| error.to_string())?
        .split();
    let mut solver =
        build_solver(scene, inputs, &mut particles).map_err(|error| error.to_string())?;
    solver
        .initial_stage(&mut particles)
        .map_err(|error| error.to_string())?;
    Ok((particles, solver))
}

/// Steps `solver` to `end`; returns the steps taken and the pressure iterations of all (the
/// constant-density and divergence solves').
fn run(
    solver: &mut dyn Solver<2>,
    particles: &mut Particles<2>,
    end: Real,
) -> Result<(usize, usize), String> {
    let (mut time, mut steps, mut iterations) = (0.0, 0, 0);
    while time < end * (1.0 - 1e-12) {
        let report = solver
            .step(particles, time, end - time)
            .map_err(|error| format!("step {steps}: {error}"))?;
        time += report.dt;
        steps += 1;
        iterations += report.iterations + report.divergence_iterations;
    }
    Ok((steps, iterations))
}

/// Values per particle gathered: id, x (2), v (2), ρ, σ (xx, yy, zz, xy).
const WIDTH: usize = 10;

/// Appends the record of particle `i`.
fn record(particles: &Particles<2>, i: usize, out: &mut Vec<Real>) {
    let (x, v) = (particles.position[i], particles.velocity[i]);
    out.extend_from_slice(&[Real::from(particles.id[i]), x[0], x[1], v[0], v[1]]);
    out.push(particles.density[i]);
    let stress = particles.soil.as_ref().map(|soil| soil.stress[i]);
    let s = stress.unwrap_or_default();
    out.extend_from_slice(&[s[(0, 0)], s[(1, 1)], s[(2, 2)], s[(0, 1)]]);
}

/// Runs `scene` (the case `label`) to `end` alone and distributed; true if they agree (with
/// `same_iterations`, in the pressure iterations too).
fn check(
    ranks: &Arc<Ranks>,
    label: &str,
    scene: &Scene,
    end: Real,
    same_iterations: bool,
) -> Result<bool, String> {
    let dx = scene.dx;
    let (rank, size) = (ranks.rank(), ranks.size());

    let (mut reference, mut solver) = build(scene)?;
    let rest_density = reference.mass[0] / dx.powi(2);
    let height = setup::build::<2>(scene)
        .map_err(|error| error.to_string())?
        .fluid_height;
    let gravity = 9.81;
    let wave_speed = match solver.sound_speed() {
        0.0 => (2.0 * gravity * height).sqrt(),
        c => c,
    };
    let stress_scale = solver.stress_scale(gravity, height).unwrap_or(1.0);
    let start = std::time::Instant::now();
    let (reference_steps, reference_iterations) = run(solver.as_mut(), &mut reference, end)?;
    let reference_seconds = start.elapsed().as_secs_f64();

    let (mut particles, mut solver) = build(scene)?;
    let total = particles.len();
    solver
        .distribute(&mut particles, Box::new(Arc::clone(ranks)))
        .map_err(|error| error.to_string())?;
    let start = std::time::Instant::now();
    let (steps, iterations) = run(solver.as_mut(), &mut particles, end)?;
    let seconds = start.elapsed().as_secs_f64();
    let distribution = solver.distribution().expect("distributed");
    let (owned, counts) = (distribution.owned(), distribution.counts());

    let mut mine = Vec::with_capacity(WIDTH * owned);
    for i in 0..owned {
        record(&particles, i, &mut mine);
    }
    let gathered = ranks.all_gather(&mine);
    let loads = ranks.all_gather(&[
        owned as Real,
        counts.halo as Real,
        counts.seconds,
        seconds,
        counts.setups as Real,
        counts.migrated as Real,
    ]);

    let mut slot = vec![usize::MAX; total];
    for i in 0..reference.len() {
        slot[reference.id[i] as usize] = i;
    }
    let mut seen = vec![0usize; total];
    let mut largest = [0.0; 4];
    let (mut front, mut reference_front) = (Real::MIN, Real::MIN);
    let mut expected = Vec::with_capacity(WIDTH);
    for got in gathered.values.chunks_exact(WIDTH) {
        let id = got[0] as usize;
        seen[id] += 1;
        expected.clear();
        record(&reference, slot[id], &mut expected);
        let difference = |k: usize, n: usize| {
            (0..n)
                .map(|c| (got[k + c] - expected[k + c]).powi(2))
                .sum::<Real>()
                .sqrt()
        };
        let scaled = [
            difference(1, 2) / dx,
            difference(3, 2) / wave_speed,
            difference(5, 1) / rest_density,
            difference(6, 4) / stress_scale,
        ];
        for (large, value) in largest.iter_mut().zip(scaled) {
            *large = Real::max(*large, value);
        }
        front = front.max(got[1]);
        reference_front = reference_front.max(expected[1]);
    }
    let once = seen.iter().all(|&count| count == 1);
    let agree = largest.iter().all(|&value| value <= ROUND_OFF);
    let same_steps =
        steps == reference_steps && (!same_iterations || iterations == reference_iterations);
    if rank == 0 {
        println!(
            "{} dx = {dx} m to t = {end} s on {size} ranks: {total} particles, {steps} steps, {iterations} iterations (one process: {reference_steps} steps, {reference_iterations} iterations, {reference_seconds:.2} s)",
            label
        );
        for (r, load) in loads.values.chunks_exact(6).enumerate() {
            println!(
                "  rank {r}: {} owned, {} halo, {} set-ups, {} migrated in; {:.2} s, of which {:.2} s in exchanges",
                load[0], load[1], load[4], load[5], load[3], load[2]
            );
        }
        let [x, v, rho, sigma] = largest;
        println!(
            "  largest differences from one process: |dx| {x:.2e} dx, |dv| {v:.2e} c, |drho| {rho:.2e} rho0, |dsigma| {sigma:.2e} of {stress_scale:.3e} Pa (bound {ROUND_OFF:e})"
        );
        println!("  front x: {front:.6} m (one process: {reference_front:.6} m)");
        if !once {
            let missing = seen.iter().filter(|&&count| count == 0).count();
            let doubled = seen.iter().filter(|&&count| count > 1).count();
            println!("FAILED: {missing} particles owned by no rank, {doubled} by several");
        }
        if !agree {
            println!("FAILED: the distributed run departs from one process beyond round-off");
        }
        if !same_steps {
            println!("FAILED: the distributed run took another number of steps or iterations");
        }
    }
    Ok(once && agree && same_steps)
}
