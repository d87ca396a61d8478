//! Damped relaxation to rest, shared by the geostatic stage and the strength-reduction
//! trials: the scales of the damping and of rest, and the stepping loop.

use std::fmt;

use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use geosph_sph::Solver;

use crate::sph::solver::SoilSolver;

/// The kinetic energy of `soil`, J (per metre in 2D).
pub(crate) fn kinetic_energy<const D: usize>(soil: &Particles<D>) -> Real {
    soil.velocity
        .iter()
        .zip(&soil.mass)
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum()
}

/// The scales of a damped relaxation of soil H high along gravity (the geostatic stage and the
/// strength-reduction trials): the damping μ = 2ζω₁ with ω₁ = πc/(2H), the shortest
/// relaxation 4H/c (one period of that mode) and the energy ½ M (gH/c)² that rest is measured
/// against (c the P-wave speed, M the soil's mass).
pub(crate) struct RelaxationScale {
    /// H, m.
    pub height: Real,
    /// μ, 1/s.
    pub damping: Real,
    /// 4H/c, s.
    pub min_time: Real,
    /// ½ M (gH/c)², J.
    pub reference_energy: Real,
}

impl RelaxationScale {
    /// The scales of `soil` in `solver` with damping ratio ζ = `damping_ratio`.
    pub fn of<const D: usize, K: Kernel<D>>(
        solver: &SoilSolver<D, K>,
        soil: &Particles<D>,
        damping_ratio: Real,
    ) -> Self {
        let system = &solver.system;
        let g = system.gravity.norm();
        let down = system.gravity / g;
        let (low, high) = soil
            .position
            .iter()
            .map(|x| -x.dot(&down))
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), h| {
                (lo.min(h), hi.max(h))
            });
        let height = high - low + system.spacing;
        let c = system.wave_speed;
        let omega = std::f64::consts::PI * c / (2.0 * height);
        let total_mass: Real = soil.mass.iter().sum();
        let speed = g * height / c;
        Self {
            height,
            damping: 2.0 * damping_ratio * omega,
            min_time: 4.0 * height / c,
            reference_energy: 0.5 * total_mass * speed * speed,
        }
    }
}

/// How a relaxation ([`relax`]) ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Relaxation {
    /// Steps taken.
    pub steps: usize,
    /// Simulated time, s.
    pub time: Real,
    /// The last E_k / ½ M (gH/c)².
    pub kinetic_energy_ratio: Real,
    /// Whether the soil came to rest (rather than `stop` or the time limit ending it).
    pub at_rest: bool,
}

/// A relaxation that could not go on: a step failed or the state is not finite.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RelaxationFailure {
    /// Steps taken before.
    pub steps: usize,
    /// Simulated time reached, s.
    pub time: Real,
    /// What went wrong.
    pub reason: String,
}

impl fmt::Display for RelaxationFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "after {} steps (t = {:.4} s): {}",
            self.steps, self.time, self.reason
        )
    }
}

/// Damped steps of `solver` on `soil` from a fresh start ([`SoilSolver::restart`]) with the
/// damping μ of `scale`, checked every 10 steps: the soil is at rest when
/// E_k < `tolerance` · ½M(gH/c)² after at least one period 4H/c; `stop(soil)` ends the
/// relaxation early; `max_time` bounds it. The solver's own damping is restored on every path.
pub(crate) fn relax<const D: usize, K: Kernel<D>>(
    solver: &mut SoilSolver<D, K>,
    soil: &mut Particles<D>,
    scale: &RelaxationScale,
    max_time: Real,
    tolerance: Real,
    mut stop: impl FnMut(&Particles<D>) -> bool,
) -> Result<Relaxation, RelaxationFailure> {
    let own_damping = solver.system.damping_rate();
    solver.system.set_damping_rate(scale.damping);
    solver.restart();
    let mut relaxation = Relaxation {
        steps: 0,
        time: 0.0,
        kinetic_energy_ratio: Real::INFINITY,
        at_rest: false,
    };
    let mut run = || -> Result<(), RelaxationFailure> {
        let failure = |r: &Relaxation, reason: String| RelaxationFailure {
            steps: r.steps,
            time: r.time,
            reason,
        };
        while relaxation.time < max_time {
            let report = solver
                .step(soil, relaxation.time, max_time - relaxation.time)
                .map_err(|error| failure(&relaxation, error.to_string()))?;
            relaxation.time += report.dt;
            relaxation.steps += 1;
            if relaxation.steps % 10 == 0 || relaxation.time >= max_time {
                relaxation.kinetic_energy_ratio = kinetic_energy(soil) / scale.reference_energy;
                if !relaxation.kinetic_energy_ratio.is_finite() {
                    return Err(failure(&relaxation, "the state is not finite".into()));
                }
                if stop(soil) {
                    break;
                }
                if relaxation.time >= scale.min_time && relaxation.kinetic_energy_ratio < tolerance
                {
                    relaxation.at_rest = true;
                    break;
                }
            }
        }
        Ok(())
    };
    let result = run();
    solver.system.set_damping_rate(own_damping);
    result.map(|()| relaxation)
}
