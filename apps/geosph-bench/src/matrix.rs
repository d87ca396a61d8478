//! The configurations to run, and running them with a progress line per run.

use std::collections::BTreeMap;
use std::time::Instant;

use geosph_core::Real;

use crate::{Case, Config, Outcome};

/// The fluid solvers.
pub const FLUID_SOLVERS: [&str; 4] = ["wcsph", "pcisph", "iisph", "dfsph"];

/// The kernels compared (the other three are covered by the kernel tests).
pub const KERNELS: [&str; 3] = ["cubic-spline", "wendland-c2", "quintic-spline"];

/// Resolutions of each case, coarse to fine (`quick`: the CI matrix).
pub fn resolutions(case: Case, quick: bool) -> Vec<Real> {
    match (case, quick) {
        (Case::TaylorGreen, false) => vec![1.0 / 25.0, 1.0 / 50.0, 1.0 / 100.0],
        (Case::TaylorGreen, true) => vec![1.0 / 16.0, 1.0 / 24.0, 1.0 / 32.0],
        (Case::Poiseuille | Case::Couette, false) => vec![1e-4, 5e-5, 2.5e-5],
        (Case::Poiseuille | Case::Couette, true) => vec![1e-4, 6.25e-5, 5e-5],
        (Case::Hydrostatic, false) => vec![0.05, 0.025, 0.0125],
        (Case::Hydrostatic, true) => vec![0.1, 0.0625, 0.05],
        (Case::DamBreak, false) => vec![0.05, 0.025, 0.0125],
        (Case::DamBreak, true) => vec![0.1, 0.0625, 0.05],
        (Case::WallPressure, false) => vec![0.015, 0.01, 0.005],
        (Case::WallPressure, true) => vec![0.03, 0.02, 0.015],
        (Case::Collapse, false) => vec![0.01, 0.005, 0.0025],
        (Case::Collapse, true) => vec![0.02, 0.0125, 0.01],
        (Case::K0Column, false) => vec![0.01, 0.005, 0.0025],
        (Case::K0Column, true) => vec![0.02, 0.0125, 0.01],
        (Case::SquareDrop, false) => vec![0.04, 0.02, 0.01],
        (Case::SquareDrop, true) => vec![0.04],
        (Case::ShockTube, false) => vec![0.02, 0.01, 0.005],
        (Case::ShockTube, true) => vec![0.02],
    }
}

/// The matrix: every case at every resolution with each solver and kernel at the default time
/// step (WCSPH with its default, Fourtakas et al.'s diffusion); WCSPH also with Molteni's and
/// Antuono's diffusion and none, with SPS turbulence and with the hashed cells (scenes with a
/// domain box), the square drop also without surface tension (the WCSPH models, square
/// drop and shock tube, with their scenes' kernel only), and every solver also at twice the
/// default time step on the middle resolution. `quick`: WCSPH and DFSPH (WCSPH only for the
/// vortex) with Wendland C2 only.
pub fn configurations(cases: &[Case], quick: bool) -> Vec<Config> {
    let mut configs = Vec::new();
    for &case in cases {
        let dxs = resolutions(case, quick);
        let solvers: &[&'static str] = match (case, quick) {
            _ if case.is_soil() => &["soil"],
            _ if case.is_wcsph_model() => &["wcsph"],
            // The pressure solvers are far less accurate on the vortex (docs/benchmarks.md).
            (Case::TaylorGreen, true) => &["wcsph"],
            (_, true) => &["wcsph", "dfsph"],
            (_, false) => &FLUID_SOLVERS,
        };
        let kernels: &[&'static str] = match (case.is_soil() || case.is_wcsph_model(), quick) {
            (false, false) => &KERNELS,
            _ => &["wendland-c2"],
        };
        let config = |solver, kernel, variant, dx, dt_factor| Config {
            case,
            solver,
            kernel,
            variant,
            dx,
            dt_factor,
        };
        for &solver in solvers {
            let variant = if solver == "wcsph" && !case.is_wcsph_model() {
                "fourtakas"
            } else {
                "default"
            };
            for &kernel in kernels {
                for &dx in &dxs {
                    configs.push(config(solver, kernel, variant, dx, 1.0));
                }
            }
            if quick {
                continue;
            }
            let middle = dxs[dxs.len() / 2];
            configs.push(config(solver, "wendland-c2", variant, middle, 2.0));
            // IISPH's converged BiCGSTAB solve, on the cases with still or free-surface water.
            if solver == "iisph"
                && matches!(
                    case,
                    Case::Hydrostatic | Case::DamBreak | Case::WallPressure
                )
            {
                for &dx in &dxs {
                    configs.push(config(solver, "wendland-c2", "bicgstab", dx, 1.0));
                }
            }
            // Each option on and off: diffusion, SPS, surface tension, the hashed cells (on
            // the scenes with a domain box).
            let others: &[&'static str] = match case {
                Case::SquareDrop => &["off", "hashed"],
                Case::ShockTube => &["hashed"],
                Case::TaylorGreen | Case::Poiseuille | Case::Couette => {
                    &["molteni", "antuono", "none", "sps", "hashed"]
                }
                _ if case.is_soil() => &[],
                _ => &["molteni", "antuono", "none", "sps"],
            };
            if solver == "wcsph" {
                for &other in others {
                    for &dx in &dxs {
                        configs.push(config(solver, "wendland-c2", other, dx, 1.0));
                    }
                }
            }
        }
    }
    configs
}

/// Runs every configuration in order, printing a progress line per run (with an estimate of
/// the time left, from the particle-steps per second so far) to standard error.
pub fn run_all(configs: &[Config], quick: bool) -> Vec<Outcome> {
    let started = Instant::now();
    let mut outcomes = Vec::with_capacity(configs.len());
    // Expected cost of a run: particles × steps ∝ dx^−(D+1); fit per case as runs finish.
    let mut seconds_per_unit: BTreeMap<Case, Real> = BTreeMap::new();
    let cost_units = |config: &Config| config.dx.powi(-3) / config.dt_factor;
    for (index, config) in configs.iter().enumerate() {
        let result = config.case.run(config, quick);
        let outcome = match result {
            Ok(measured) => Outcome {
                config: config.clone(),
                particles: measured.particles,
                steps: measured.steps,
                wall_time: measured.wall_time,
                particle_steps_per_second: (measured.particles * measured.steps) as Real
                    / measured.wall_time,
                value: measured.value,
                error: measured.error,
                status: "ok".into(),
            },
            Err(reason) => Outcome {
                config: config.clone(),
                particles: 0,
                steps: 0,
                wall_time: Real::NAN,
                particle_steps_per_second: Real::NAN,
                value: Real::NAN,
                error: Real::NAN,
                status: reason,
            },
        };
        if outcome.wall_time.is_finite() {
            let rate = outcome.wall_time / cost_units(config);
            let entry = seconds_per_unit.entry(config.case).or_insert(rate);
            *entry = entry.max(rate);
        }
        let left = configs[index + 1..]
            .iter()
            .map(|c| seconds_per_unit.get(&c.case).copied().unwrap_or(0.0) * cost_units(c))
            .sum::<Real>()
            .max(0.0);
        let result = if outcome.status == "ok" && config.case == Case::Collapse {
            format!(
                "{:.1} s, {} steps, {:.2} M particle-steps/s, runout {:.4} m, error {:.3e}",
                outcome.wall_time,
                outcome.steps,
                outcome.particle_steps_per_second * 1e-6,
                outcome.value,
                outcome.error
            )
        } else if outcome.status == "ok" {
            format!(
                "{:.1} s, {} steps, {:.2} M particle-steps/s, error {:.3e}",
                outcome.wall_time,
                outcome.steps,
                outcome.particle_steps_per_second * 1e-6,
                outcome.error
            )
        } else {
            format!("FAILED: {}", outcome.status)
        };
        eprintln!(
            "[{:>3}/{}] {:<12} {:<40} {result} (elapsed {:.0} s, about {:.0} s left)",
            index + 1,
            configs.len(),
            config.case.name(),
            config.label(),
            started.elapsed().as_secs_f64(),
            left
        );
        outcomes.push(outcome);
    }
    outcomes
}

/// Configurations that differ only in resolution: (case, solver, kernel, variant, dt factor).
pub type Series = (Case, &'static str, &'static str, &'static str, u64);

/// The series a configuration belongs to.
pub fn series_of(config: &Config) -> Series {
    (
        config.case,
        config.solver,
        config.kernel,
        config.variant,
        config.dt_factor.to_bits(),
    )
}

/// Indices of `outcomes` grouped by series, each sorted from coarse to fine.
pub fn by_series(outcomes: &[Outcome]) -> BTreeMap<Series, Vec<usize>> {
    let mut groups: BTreeMap<Series, Vec<usize>> = BTreeMap::new();
    for (index, outcome) in outcomes.iter().enumerate() {
        groups
            .entry(series_of(&outcome.config))
            .or_default()
            .push(index);
    }
    for members in groups.values_mut() {
        members.sort_by(|&a, &b| outcomes[b].config.dx.total_cmp(&outcomes[a].config.dx));
    }
    groups
}

/// Observed orders of convergence of a series between successive resolutions:
/// p = ln(e_coarse/e_fine) / ln(dx_coarse/dx_fine).
pub fn orders(outcomes: &[Outcome], members: &[usize]) -> Vec<Real> {
    members
        .windows(2)
        .map(|pair| {
            let (coarse, fine) = (&outcomes[pair[0]], &outcomes[pair[1]]);
            (coarse.error / fine.error).ln() / (coarse.config.dx / fine.config.dx).ln()
        })
        .collect()
}
