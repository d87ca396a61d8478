//! Divergence-free SPH (Bender & Koschier 2015, 2017).

use geosph_core::{Particles, PerParticle, Permutation, Real};
use geosph_kernels::Kernel;
use rayon::prelude::*;

use super::system::MIN_LEN;
use super::{PressureMethod, PressureSolveSettings, PressureSystem, Scratch, SolveReport};
use geosph_sph::{SolverError, StateArrays, StateError};

/// DFSPH: two velocity-space solvers that share the per-particle factor α_i = ρ_i / d_i
/// (Bender & Koschier 2017, IEEE TVCG 23:1193, eq. 9, with d_i of
/// [`PressureSystem::diagonal`]), computed once per step with the neighbour lists.
///
/// - **Constant density** (ibid., Algorithm 3): while the average of the predicted
///   compression max(ρ*_i − ρ₀, 0), ρ*_i = ρ_i + Δt Σ_j m_j (v_i − v_j)·∇_i W_ij, exceeds the
///   target (or a particle that takes pressure is predicted beyond `max_compression`, our
///   addition: `docs/incompressible.md`), each particle takes the pressure increment
///   δp_i = (ρ*_i − ρ₀) ρ_i² / (Δt² d_i) (the stiffness κ_i = δp_i/ρ_i of the paper) and the
///   velocities change by Δt a^p(δp).
/// - **Divergence-free** (ibid., Algorithm 2), after the positions and lists are updated: the
///   same with the density rate max(Σ_j m_j (v_i − v_j)·∇_i W_ij, 0) and
///   δp_i = (Dρ_i/Dt) ρ_i² / (Δt d_i), until Δt times its average is below the target.
///
/// Both start from half the previous step's summed pressures (warm start, ibid., §4.4, with the
/// factor ½ of [`Iisph`](super::Iisph)), but only on particles whose residual before any
/// pressure acts is positive. Increments are never negative (the residual is clamped at zero),
/// so a warm start where no pressure is needed could never be relaxed: the initial
/// hydrostatic pressure on the free face of a dam break, where the exact pressure drops to
/// zero at release, kicked those particles to 3 m/s in the first step.
///
/// The first constant-density solve (the *release*, our addition: `docs/incompressible.md`)
/// starts from half the initial pressure on every particle that can take pressure and may
/// lower it: a projected, relaxed Jacobi iteration, p_i ← max(p_i + ω δp_i, 0) with the
/// unclamped residual and ω of [`PressureSystem::relaxation_limit`], stopping on the
/// complementarity error as [`Iisph`](super::Iisph) does. The masked warm start would leave a
/// jump of ½ ρ₀ g (H − z) two rows inside a free face, which the clamped increments cannot
/// lower and which kicked the face outward at a speed ∝ 1/dx.
#[derive(Clone, Debug, PartialEq)]
pub struct Dfsph {
    /// Run the divergence-free solve (default true).
    pub divergence_solve: bool,
    /// Target of the divergence solve: average of Δt Dρ/Dt / ρ₀ (default 0.001).
    pub target_divergence_error: Real,
    /// Summed pressure increments of the last constant-density solve (its warm start).
    density_pressure: Vec<Real>,
    /// Summed pressure increments of the last divergence solve (its warm start).
    divergence_pressure: Vec<Real>,
    /// Increments of the current iteration.
    increment: Vec<Real>,
    /// Whether the first constant-density solve (the release) has been made.
    released: bool,
}

impl Dfsph {
    /// DFSPH with or without the divergence-free solve and its target.
    pub fn new(divergence_solve: bool, target_divergence_error: Real) -> Self {
        Self {
            divergence_solve,
            target_divergence_error,
            density_pressure: Vec::new(),
            divergence_pressure: Vec::new(),
            increment: Vec::new(),
            released: false,
        }
    }
}

impl Default for Dfsph {
    fn default() -> Self {
        Self::new(true, 1e-3)
    }
}

/// Factor on the previous step's summed pressure as the initial guess. The solve stops on the
/// compression alone, so a pressure no longer needed (an expanding particle's) is relaxed only
/// as far as the iterations run: half of it, as IISPH's warm start, decays it geometrically
/// from step to step and costs a few iterations where the pressure is steady.
const WARM_START: Real = 0.5;

/// Which residual a DFSPH solve drives to zero.
#[derive(Clone, Copy)]
enum Residual {
    /// ρ + Δt Dρ/Dt − ρ₀ (the increment is divided by Δt²).
    Density,
    /// Dρ/Dt (the increment is divided by Δt).
    Divergence,
}

impl Dfsph {
    /// One DFSPH solve: warm start with `summed`, then iterate; `summed` ends holding the sum
    /// of all increments.
    #[allow(clippy::too_many_arguments)]
    fn solve<const D: usize, K: Kernel<D>>(
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        kind: Residual,
        target: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
        summed: &mut [Real],
        increment: &mut [Real],
        release: bool,
    ) -> SolveReport {
        let rho0 = system.rest_density;
        // The residual, clamped unless pressures may be negative: predicted compression, or
        // compression rate.
        // The release (the first solve, from the initial pressure) may lower pressures: a
        // projected iteration, p ≥ 0 kept by the increments, unless they may be negative.
        let projected = release && !settings.negative_pressure;
        let floor = if settings.negative_pressure || projected {
            Real::NEG_INFINITY
        } else {
            0.0
        };
        let residual_of = |rho_i: Real, div: Real| match kind {
            Residual::Density => (rho_i + dt * div - rho0).max(floor),
            Residual::Divergence => div.max(floor),
        };
        let diagonal = system.diagonal();
        let walls_velocity = &system.walls.velocity;
        let Particles {
            velocity,
            mass,
            density,
            ..
        } = fluid;
        let (mass, density) = (&*mass, &*density);
        let Scratch {
            pressure_term,
            residual,
            ..
        } = scratch;
        // v ← v + Δt a^p(p) from `pressure_term` = p/ρ², and each particle's `summed` pressure
        // raised by its `increment`, in one pass (a^p_i reads no velocity).
        let apply = |pressure_term: &[Real],
                     increment: Option<&[Real]>,
                     velocity: &mut [_],
                     summed: &mut [Real]| {
            velocity
                .par_iter_mut()
                .zip(summed.par_iter_mut())
                .enumerate()
                .with_min_len(MIN_LEN)
                .for_each(|(i, (v, p))| {
                    *v += system.pressure_acceleration_at(i, mass, pressure_term) * dt;
                    if let Some(increment) = increment {
                        *p += increment[i];
                    }
                });
        };
        // Warm start where the particle can take pressure (a non-zero diagonal) and, but at the
        // release, is compressed (its rate) before any pressure acts.
        {
            let velocity = &*velocity;
            summed
                .par_iter_mut()
                .zip(pressure_term.par_iter_mut())
                .enumerate()
                .with_min_len(MIN_LEN)
                .for_each(|(i, (p, term))| {
                    let div = system.divergence_at(i, mass, velocity, walls_velocity);
                    let rho_i = density[i];
                    let warm = release || residual_of(rho_i, div) != 0.0;
                    *p = if diagonal[i] > 0.0 && warm {
                        *p * WARM_START
                    } else {
                        0.0
                    };
                    *term = *p / (rho_i * rho_i);
                });
        }
        // In a distributed run p/ρ² is refreshed on the halo before each velocity update:
        // the owned particles' neighbours' pressure accelerations read it there. The
        // velocities then stay right within a support of the owned particles, which is as
        // far as the next residual reads them.
        system.lists.exchange_halo_values(pressure_term);
        apply(pressure_term, None, velocity, summed);
        let owned = system.owned();
        // The increment's scale, the error's, and the bound on any one residual (only the
        // density solve bounds a particle's compression).
        let (scale, error_scale, max_residual) = match kind {
            Residual::Density => (1.0 / (dt * dt), 1.0 / rho0, settings.max_compression * rho0),
            Residual::Divergence => (1.0 / dt, dt / rho0, Real::INFINITY),
        };
        // A clamped solve only raises pressures and cannot overshoot into oscillation; a
        // two-sided one is a Jacobi iteration whose stiffest (checkerboard) mode grows unless
        // relaxed to the system's limit.
        let scale = if settings.negative_pressure || projected {
            scale * system.relaxation_limit().min(1.0)
        } else {
            scale
        };
        let mut report = SolveReport::default();
        while report.iterations < settings.max_iterations {
            // The residual, the increment it asks for and the increment's p/ρ², in one pass.
            {
                let velocity = &*velocity;
                let summed_now = &*summed;
                residual
                    .par_iter_mut()
                    .zip(increment.par_iter_mut())
                    .zip(pressure_term.par_iter_mut())
                    .enumerate()
                    .with_min_len(MIN_LEN)
                    .for_each(|(i, ((r, dp), term))| {
                        let div = system.divergence_at(i, mass, velocity, walls_velocity);
                        let rho_i = density[i];
                        *r = residual_of(rho_i, div);
                        *dp = if diagonal[i] > 0.0 {
                            *r * scale * rho_i * rho_i / diagonal[i]
                        } else {
                            0.0
                        };
                        if projected {
                            // The pressure may fall, to zero at the least.
                            *dp = dp.max(-summed_now[i]);
                        }
                        *term = *dp / (rho_i * rho_i);
                    });
            }
            let error = match projected {
                true => super::errors::complementarity_error(
                    &residual[..owned],
                    &summed[..owned],
                    &diagonal[..owned],
                ),
                false => super::errors::residual_error(
                    &residual[..owned],
                    &diagonal[..owned],
                    settings.negative_pressure,
                ),
            };
            let (mean, max) = system.error_over_ranks(error);
            report.error = mean * error_scale;
            if report.iterations >= settings.min_iterations
                && report.error <= target
                && max <= max_residual
            {
                break;
            }
            report.iterations += 1;
            system.lists.exchange_halo_values(pressure_term);
            apply(pressure_term, Some(increment), velocity, summed);
        }
        report
    }
}

impl Dfsph {
    /// Writes the pressure of the step, the sum of both solves' pressures (each acts on the
    /// velocity as Δt a^p), into `fluid` for output and for the wall head's limit.
    fn report_pressure<const D: usize>(&self, fluid: &mut Particles<D>) {
        let pressure = fluid.pressure.as_mut().expect("pressure is enabled");
        let divergence = &self.divergence_pressure;
        pressure
            .par_iter_mut()
            .zip(self.density_pressure.par_iter())
            .enumerate()
            .for_each(|(i, (p, density))| *p = density + divergence.get(i).copied().unwrap_or(0.0));
    }
}

impl<const D: usize> PressureMethod<D> for Dfsph {
    const NAME: &'static str = "dfsph";

    fn correct_density<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport {
        self.increment.resize(fluid.len(), 0.0);
        let pressure = fluid.pressure.as_ref().expect("pressure is enabled");
        if self.density_pressure.len() != pressure.len() {
            // The first step starts from the initial (hydrostatic) pressure.
            self.density_pressure.clone_from(pressure);
        }
        let release = !self.released;
        self.released = true;
        Self::solve(
            system,
            fluid,
            dt,
            Residual::Density,
            settings.target_density_error,
            settings,
            scratch,
            &mut self.density_pressure,
            &mut self.increment,
            release,
        )
    }

    fn after_update<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport {
        if !self.divergence_solve {
            self.report_pressure(fluid);
            return SolveReport::default();
        }
        self.increment.resize(fluid.len(), 0.0);
        self.divergence_pressure.resize(fluid.len(), 0.0);
        let settings = PressureSolveSettings {
            min_iterations: 1,
            ..*settings
        };
        let report = Self::solve(
            system,
            fluid,
            dt,
            Residual::Divergence,
            self.target_divergence_error,
            &settings,
            scratch,
            &mut self.divergence_pressure,
            &mut self.increment,
            false,
        );
        self.report_pressure(fluid);
        report
    }

    fn carried(&mut self) -> Option<&mut dyn PerParticle> {
        Some(self)
    }

    /// Both warm starts as the first steps on one process make them: the constant-density
    /// solve's from the initial pressure, the divergence solve's from zero (unless a restart
    /// restored them), so that they can move with the particles from the first set-up on.
    fn distribute(&mut self, fluid: &Particles<D>) -> Result<(), SolverError> {
        let pressure = fluid.pressure.as_ref().expect("pressure is enabled");
        if self.density_pressure.len() != pressure.len() {
            self.density_pressure.clone_from(pressure);
        }
        self.divergence_pressure.resize(pressure.len(), 0.0);
        Ok(())
    }

    fn save_state(&self, arrays: &mut StateArrays, owned: usize) {
        let upto = |summed: &[Real]| summed.len().min(owned);
        let (density, divergence) = (&self.density_pressure, &self.divergence_pressure);
        arrays.push("density_pressure", &density[..upto(density)]);
        arrays.push("divergence_pressure", &divergence[..upto(divergence)]);
    }

    /// A warm start is saved empty before it is first made (a checkpoint before the first
    /// step), else with one value per particle.
    fn restore_state(&mut self, arrays: &mut StateArrays, n: usize) -> Result<(), StateError> {
        let mut warm_start = |name: &str| -> Result<Vec<Real>, StateError> {
            let values = arrays.take(name)?;
            match values.len() {
                len if len == 0 || len == n => Ok(values),
                len => Err(StateError(format!(
                    "`{name}` holds {len} values, not one for each of the {n} particles (or none)"
                ))),
            }
        };
        self.density_pressure = warm_start("density_pressure")?;
        self.divergence_pressure = warm_start("divergence_pressure")?;
        self.released = true;
        Ok(())
    }
}

/// The two warm starts of each particle, which travel with it (the increments are the
/// current iteration's only). Before the first step on one process a warm start may be
/// empty (not yet made): reordering and thinning leave it so.
impl PerParticle for Dfsph {
    fn record_width(&self) -> usize {
        2
    }

    fn pack(&self, i: usize, record: &mut Vec<Real>) {
        record.extend_from_slice(&[self.density_pressure[i], self.divergence_pressure[i]]);
    }

    fn unpack(&mut self, i: usize, record: &[Real]) {
        self.density_pressure[i] = record[0];
        self.divergence_pressure[i] = record[1];
    }

    fn resize(&mut self, n: usize) {
        self.density_pressure.resize(n, 0.0);
        self.divergence_pressure.resize(n, 0.0);
    }

    fn retain(&mut self, keep: &[bool]) {
        for summed in [&mut self.density_pressure, &mut self.divergence_pressure] {
            if summed.len() == keep.len() {
                geosph_core::retain(summed, keep);
            }
        }
    }

    fn permute(&mut self, permutation: &Permutation) {
        for summed in [&mut self.density_pressure, &mut self.divergence_pressure] {
            if summed.len() == permutation.len() {
                permutation.apply(summed);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A checkpoint's warm starts are taken back with one value per particle, or none (saved
    /// before they were first made); another count is an error naming the array.
    #[test]
    fn warm_starts_of_another_particle_count_are_refused() {
        let arrays = |density: &[Real], divergence: &[Real]| {
            let mut arrays = StateArrays::default();
            arrays.push("density_pressure", density);
            arrays.push("divergence_pressure", divergence);
            arrays
        };
        let restore = |mut arrays: StateArrays| {
            PressureMethod::<2>::restore_state(&mut Dfsph::default(), &mut arrays, 3)
        };
        assert!(restore(arrays(&[1.0, 2.0, 3.0], &[0.0; 3])).is_ok());
        assert!(restore(arrays(&[], &[])).is_ok());
        let error = restore(arrays(&[1.0, 2.0, 3.0], &[0.0; 2])).unwrap_err();
        assert_eq!(
            error.0,
            "`divergence_pressure` holds 2 values, not one for each of the 3 particles (or none)"
        );
    }
}
