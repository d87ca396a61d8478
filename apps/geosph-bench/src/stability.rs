//! Stability under stress, with criteria that can fail:
//! - the largest stable time-step factor of each solver × kernel, by bisection on a dam break
//!   through its wall impact (the soil: on the column collapse);
//! - a long run: a still tank for 10⁵ WCSPH steps, whose free surface must not drift by more
//!   than one dx and whose pressure error must not grow;
//! - a start from a lattice jittered by ±0.3 dx, which must settle;
//! - a 20 m/s impact of a water block on a wall, which no particle may cross;
//! - a cohesive soil block pulled apart, whose particles must not clump (tensile instability).
//!
//! A run "blows up" when the runner stops it (`geosph_runner::health`: a non-finite state, a
//! particle outside the domain, density error beyond 20 %, soil stress or kinetic energy
//! beyond their bounds).

use std::fmt::Write as _;
use std::time::Instant;

use geosph_core::Real;
use geosph_runner::RunOptions;

use crate::matrix::{FLUID_SOLVERS, KERNELS};
use crate::{Case, Config};

mod stress;
pub use stress::{
    IISPH_BICGSTAB, ImpactOutcome, impact, impact_outcome, jittered_start, long_run, tension,
};

/// One stability result.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityResult {
    /// The test, e.g. "largest time-step factor".
    pub test: &'static str,
    /// What was tested, e.g. "dfsph/wendland-c2".
    pub subject: String,
    /// What was measured, in words and figures.
    pub measured: String,
    /// The criterion.
    pub criterion: &'static str,
    /// Whether the criterion holds.
    pub passed: bool,
    /// Wall time of the test, s.
    pub wall_time: Real,
}

/// The Courant number bound the scene format accepts over the solver's default: the largest
/// time-step factor a scene can ask for.
fn factor_bound(solver: &str) -> Real {
    match solver {
        "wcsph" => 1.0 / 0.25,
        "soil" => 1.0 / 0.2,
        _ => 1.0 / 0.4,
    }
}

/// Largest stable time-step factor of `solver` with `kernel`, by bisection between the default
/// (1) and the scene format's bound, on the dam break through its wall impact (the collapse for
/// soil). Stable: the run ends without the runner stopping it and with a finite error.
pub fn largest_time_step_factor(
    solver: &'static str,
    kernel: &'static str,
    quick: bool,
) -> StabilityResult {
    let started = Instant::now();
    let (case, dx) = match (solver, quick) {
        ("soil", true) => (Case::Collapse, 0.02),
        ("soil", false) => (Case::Collapse, 0.01),
        (_, true) => (Case::DamBreak, 0.1),
        (_, false) => (Case::DamBreak, 0.04),
    };
    let stable = |dt_factor: Real| -> Result<(), String> {
        let config = Config {
            case,
            solver,
            kernel,
            variant: "default",
            dx,
            dt_factor,
        };
        let mut scene = case.scene(&config, false)?;
        // Through the impact on the far wall (at t ≈ 0.6 s) for the dam break.
        scene.end_time = if case == Case::DamBreak {
            0.9
        } else {
            scene.end_time
        };
        if case == Case::Collapse {
            slope_failure::run(&scene, &RunOptions::default())
                .map(|_| ())
                .map_err(|e| e.to_string())
        } else {
            dam_break::run(&scene, &RunOptions::default())
                .map(|_| ())
                .map_err(|e| e.to_string())
        }
    };
    let bound = factor_bound(solver);
    let (measured, passed) = match stable(1.0) {
        Err(reason) => (
            format!("unstable at the default time step: {reason}"),
            false,
        ),
        Ok(()) => match stable(bound) {
            Ok(()) => (
                format!("stable up to the scene format's bound, {bound}× the default"),
                true,
            ),
            Err(reason) => {
                let (mut low, mut high, mut last_reason) = (1.0, bound, reason);
                for _ in 0..if quick { 2 } else { 4 } {
                    let middle = 0.5 * (low + high);
                    match stable(middle) {
                        Ok(()) => low = middle,
                        Err(reason) => {
                            high = middle;
                            last_reason = reason;
                        }
                    }
                }
                (
                    format!("stable at {low:.3}×, unstable at {high:.3}× ({last_reason})"),
                    true,
                )
            }
        },
    };
    StabilityResult {
        test: "largest time-step factor",
        subject: format!("{solver}/{kernel} ({} dx = {dx})", case.name()),
        measured,
        criterion: "the default time step is stable",
        passed,
        wall_time: started.elapsed().as_secs_f64(),
    }
}

/// Every stability test, printing a line per test to standard error. `quick`: coarse and short
/// versions, WCSPH and DFSPH with Wendland C2 only for the time-step bisection.
pub fn run_all(quick: bool) -> Vec<StabilityResult> {
    let mut tests: Vec<Box<dyn Fn() -> StabilityResult>> = Vec::new();
    let solvers: &[&'static str] = if quick {
        &["wcsph", "dfsph"]
    } else {
        &FLUID_SOLVERS
    };
    let kernels: &[&'static str] = if quick { &["wendland-c2"] } else { &KERNELS };
    for &solver in solvers {
        for &kernel in kernels {
            tests.push(Box::new(move || {
                largest_time_step_factor(solver, kernel, quick)
            }));
        }
    }
    tests.push(Box::new(move || {
        largest_time_step_factor("soil", "wendland-c2", quick)
    }));
    for &solver in solvers {
        tests.push(Box::new(move || long_run(solver, false, quick)));
        if solver == "wcsph" {
            tests.push(Box::new(move || long_run(solver, true, quick)));
        }
        tests.push(Box::new(move || jittered_start(solver, quick)));
        tests.push(Box::new(move || impact(solver, quick)));
    }
    // The opt-in converged IISPH solve, on the stress cases.
    if !quick {
        tests.push(Box::new(|| long_run(IISPH_BICGSTAB, false, false)));
        tests.push(Box::new(|| jittered_start(IISPH_BICGSTAB, false)));
        tests.push(Box::new(|| impact(IISPH_BICGSTAB, false)));
    }
    for artificial_stress in [false, true] {
        tests.push(Box::new(move || tension(artificial_stress, quick)));
    }
    let count = tests.len();
    tests
        .iter()
        .enumerate()
        .map(|(index, test)| {
            let result = test();
            eprintln!(
                "[{:>2}/{count}] {} — {}: {} ({}, {:.1} s)",
                index + 1,
                result.test,
                result.subject,
                result.measured,
                if result.passed { "pass" } else { "FAIL" },
                result.wall_time
            );
            result
        })
        .collect()
}

/// The stability map as Markdown.
pub fn markdown(results: &[StabilityResult], header: &str) -> String {
    let mut text = String::from(header);
    text.push_str(
        "\nA run is stopped as blown up by the runner's health check (`geosph_runner::health`): \
         a non-finite state or time step, a particle outside the domain, a density error \
         beyond 20 %, a soil stress beyond 10 × its geostatic-plus-impact scale, or a kinetic \
         energy beyond twice what gravity and the initial state can supply.\n",
    );
    let mut test = "";
    for result in results {
        if result.test != test {
            test = result.test;
            let _ = write!(
                text,
                "\n## {test}\n\nCriterion: {}.\n\n| subject | measured | result | wall time (s) |\n\
                 | --- | --- | --- | --- |\n",
                result.criterion
            );
        }
        let _ = writeln!(
            text,
            "| {} | {} | {} | {:.1} |",
            result.subject,
            result.measured.replace('|', "/"),
            if result.passed { "pass" } else { "**FAIL**" },
            result.wall_time
        );
    }
    text
}
