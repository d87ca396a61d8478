//! Implicit incompressible SPH (Ihmsen et al. 2014) and the relaxed Jacobi iteration it shares
//! with PCISPH.

use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use rayon::prelude::*;

use super::system::MIN_LEN;
use super::{
    PressureIteration, PressureMethod, PressureSolveSettings, PressureSource, PressureSystem,
    Scratch, SolveReport,
};

/// IISPH: the pressure Poisson equation from the continuity equation,
///
/// Δt² Σ_j m_j (a^p_i − a^p_j)·∇_i W_ij + Δt² Σ_b m_b a^p_i·∇_i W_ib = ρ₀ − ρ*_i,
///
/// where a^p is the pressure acceleration of [`PressureSystem::pressure_acceleration`] and
/// ρ*_i = ρ_i + Δt Σ_j m_j (v*_i − v*_j)·∇_i W_ij + walls is the density predicted from the
/// velocities v* after the known forces (Ihmsen, Cornelis, Solenthaler, Horvath & Teschner
/// 2014, IEEE TVCG 20:426, eqs. 3–11), solved matrix-free by relaxed Jacobi,
///
/// p_i ← max(0, p_i + ω (ρ̃_i − ρ₀) ρ_i² / (Δt² d_i)),
///
/// with ρ̃_i the density the current pressures predict, the diagonal −Δt² d_i/ρ_i² of
/// [`PressureSystem::diagonal`], ω = 0.5 and the warm start p = ½ p of the previous step
/// (ibid., §3.3 and §4). ω is capped at [`PressureSystem::relaxation_limit`], below which the
/// iteration converges on the kernel's lattice (0.5 is within it for Wendland C2 and the cubic
/// spline in 2D, not for the quintic spline or in 3D).
///
/// With `iteration: Bicgstab` the system is solved by BiCGSTAB instead, on its own source
/// ([`Bicgstab`](super::Bicgstab)); the rest of this description is the relaxed Jacobi's.
///
/// With the velocity-divergence [`PressureSource`] the right-hand side is −Δt Σ_j m_j
/// (v*_i − v*_j)·∇_i W_ij instead (Cornelis et al. 2019): the same iteration projects v* onto
/// a divergence-free field without correcting the density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iisph {
    /// Relaxation ω of the Jacobi update (Ihmsen et al.: 0.5).
    pub relaxation: Real,
    /// Factor on the previous step's pressure as the initial guess (0.5).
    pub warm_start: Real,
    /// The iteration (default relaxed Jacobi).
    pub iteration: PressureIteration,
}

impl Default for Iisph {
    fn default() -> Self {
        Self {
            relaxation: 0.5,
            warm_start: 0.5,
            iteration: PressureIteration::RelaxedJacobi,
        }
    }
}

impl<const D: usize> PressureMethod<D> for Iisph {
    const NAME: &'static str = "iisph";

    fn correct_density<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport {
        if let PressureIteration::Bicgstab(bicgstab) = self.iteration {
            return bicgstab.solve(system, fluid, dt, settings, scratch);
        }
        let warm_start = self.warm_start;
        let diagonal = system.diagonal();
        let pressure = fluid.pressure.as_mut().expect("pressure is enabled");
        // No warm start where the particle takes no pressure (a zero diagonal).
        pressure
            .par_iter_mut()
            .zip(diagonal.par_iter())
            .for_each(|(p, d)| *p = if *d > 0.0 { *p * warm_start } else { 0.0 });
        let relaxation = self.relaxation.min(system.relaxation_limit());
        relaxed_jacobi(
            system,
            fluid,
            dt,
            settings,
            scratch,
            StopOn::Complementarity,
            |i, rho_i| {
                if diagonal[i] > 0.0 {
                    relaxation * rho_i * rho_i / (dt * dt * diagonal[i])
                } else {
                    0.0
                }
            },
        )
    }
}

/// The error a [`relaxed_jacobi`] solve stops on.
#[derive(Clone, Copy)]
pub(crate) enum StopOn {
    /// The mean compression, mean of max(ρ̃_i/ρ₀ − 1, 0) (PCISPH).
    Compression,
    /// The [complementarity error](super::errors::complementarity_error) over ρ₀: |ρ̃_i/ρ₀ − 1| where
    /// p_i > 0, max(ρ̃_i/ρ₀ − 1, 0) elsewhere (IISPH).
    Complementarity,
}

/// Solves for pressures p ≥ 0 that bring the density predicted from the velocities v* in
/// `fluid.velocity` to ρ₀ (with the velocity-divergence [`PressureSource`]: that make its
/// predicted rate of change zero), by the fixed-point update
/// p_i ← max(0, p_i + s_i (ρ̃_i − ρ₀)) with the per-particle step `step(i, ρ_i)`; then
/// applies v ← v* + Δt a^p.
///
/// Each iteration is two gather passes over the pairs: a^p from p, then the density change
/// Δt² Σ_j m_j (a^p_i − a^p_j)·∇_i W_ij (+ walls) that a^p causes. The error over ρ₀ is that
/// of `stop`; iterations stop when it is at most the target after the minimum count and no
/// particle that takes pressure is predicted beyond `max_compression`.
pub(crate) fn relaxed_jacobi<const D: usize, K: Kernel<D>>(
    system: &PressureSystem<D, K>,
    fluid: &mut Particles<D>,
    dt: Real,
    settings: &PressureSolveSettings,
    scratch: &mut Scratch<D>,
    stop: StopOn,
    step: impl Fn(usize, Real) -> Real + Sync,
) -> SolveReport {
    let rho0 = system.rest_density;
    let Particles {
        velocity,
        mass,
        density,
        pressure,
        ..
    } = fluid;
    let pressure = pressure.as_mut().expect("pressure is enabled");
    let Scratch {
        acceleration,
        pressure_term,
        divergence,
        residual,
        ..
    } = scratch;

    let walls = &system.walls;
    let (mass, density) = (&*mass, &*density);
    let floor = if settings.negative_pressure {
        Real::NEG_INFINITY
    } else {
        0.0
    };
    // The density predicted from v* alone, minus ρ₀: residual_i = ρ*_i − ρ₀ (or, with the
    // velocity-divergence source, its part Δt Σ_j m_j (v*_i − v*_j)·∇_i W_ij); and p/ρ² of
    // the starting pressure.
    let source = settings.source;
    {
        let velocity = &*velocity;
        residual
            .par_iter_mut()
            .zip(pressure_term.par_iter_mut())
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, (r, term))| {
                let rho_i = density[i];
                let rate = dt * system.divergence_at(i, mass, velocity, &walls.velocity);
                *r = match source {
                    PressureSource::DensityInvariance => rho_i + rate - rho0,
                    PressureSource::VelocityDivergence => rate,
                };
                *term = pressure[i] / (rho_i * rho_i);
            });
    }
    // In a distributed run p/ρ² is refreshed on the halo after every update, as the next
    // pass (the pressure acceleration of the owned particles' neighbours) reads it there.
    system.lists.exchange_halo_values(pressure_term);
    let owned = system.owned();

    let mut report = SolveReport::default();
    while report.iterations < settings.max_iterations {
        system.pressure_acceleration(mass, pressure_term, acceleration);
        // The density the pressures predict, the Jacobi update and its p/ρ², in one pass.
        let acceleration = &*acceleration;
        pressure
            .par_iter_mut()
            .zip(divergence.par_iter_mut())
            .zip(pressure_term.par_iter_mut())
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, ((p, predicted), term))| {
                let rho_i = density[i];
                // ρ̃_i − ρ₀ with the current pressures; kept for the error sum.
                *predicted = residual[i]
                    + dt * dt * system.divergence_at(i, mass, acceleration, &walls.acceleration);
                *p = (*p + step(i, rho_i) * *predicted).max(floor);
                *term = *p / (rho_i * rho_i);
            });
        report.iterations += 1;
        system.lists.exchange_halo_values(pressure_term);
        let (predicted, diagonal) = (&divergence[..owned], &system.diagonal()[..owned]);
        let (mean, max) = system.error_over_ranks(match stop {
            _ if settings.negative_pressure => {
                super::errors::mean_and_max_absolute(predicted, diagonal)
            }
            StopOn::Compression => super::errors::mean_and_max_positive(predicted, diagonal),
            StopOn::Complementarity => {
                super::errors::complementarity_error(predicted, &pressure[..owned], diagonal)
            }
        });
        report.error = mean / rho0;
        if report.iterations >= settings.min_iterations
            && report.error <= settings.target_density_error
            && max <= settings.max_compression * rho0
        {
            break;
        }
    }
    let pressure_term = &*pressure_term;
    velocity
        .par_iter_mut()
        .enumerate()
        .with_min_len(MIN_LEN)
        .for_each(|(i, v)| *v += system.pressure_acceleration_at(i, mass, pressure_term) * dt);
    report
}
