//! The fluid-solver interface the runner steps, and the WCSPH solver behind it.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_time::{Integrator, Rates, StepLimits, time_step};

use crate::diffusion::DensityDiffusion;
use crate::state::{SolverState, StateError};
use crate::viscosity::Viscosity;
use crate::wcsph::WcsphSystem;

/// What one step did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// The time step taken.
    pub dt: Real,
    /// Pressure iterations (1 for explicit solvers; the constant-density solve for DFSPH).
    pub iterations: usize,
    /// Iterations of DFSPH's divergence-free solve (0 for the other solvers).
    pub divergence_iterations: usize,
    /// Mean relative density error |ρ − ρ₀|/ρ₀ over the fluid.
    pub density_error_mean: Real,
    /// Largest relative density error.
    pub density_error_max: Real,
}

/// Why a step failed.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// The neighbour search failed, e.g. a particle left the domain.
    #[error("{0}{hint}", hint = search_hint(.0))]
    Search(#[from] SearchError),
    /// A saved state does not fit this solver (a restart from another scene's checkpoint).
    #[error(transparent)]
    State(#[from] StateError),
}

/// What a user can do about a failed search.
fn search_hint(error: &SearchError) -> &'static str {
    match error {
        SearchError::OutsideDomain { .. } => {
            "; a particle left the domain: if the flow may go there (a splash, an outflow), enlarge the scene's `domain`, otherwise check the walls and the time step"
        }
        _ => "",
    }
}

/// A fluid solver: one method, stepped by the runner. Dispatch happens once per step; the hot
/// loops inside are monomorphised over kernel and physics terms.
pub trait FluidSolver<const D: usize>: Send {
    /// The method's name, e.g. "wcsph".
    fn name(&self) -> &'static str;

    /// Advances the fluid from `time` by one step of at most `max_dt`.
    fn step(
        &mut self,
        fluid: &mut Particles<D>,
        time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError>;

    /// The wall particles, with their current pressure.
    fn walls(&self) -> &WallParticles<D>;

    /// The reference sound speed c₀ (0 for incompressible solvers).
    fn sound_speed(&self) -> Real;

    /// The density error this solver controls, per particle, as a fraction of ρ₀: |ρ/ρ₀ − 1|
    /// for WCSPH; the compression max(ρ/ρ₀ − 1, 0) for the incompressible solvers, whose
    /// free-surface particles sit below ρ₀ by construction.
    fn density_error(&self, density: Real) -> Real;

    /// What a user can change when the density error runs away.
    fn blow_up_advice(&self) -> &'static str;

    /// Removes the particles `k` without `keep[k]` (particles that left the domain) from
    /// `fluid` and the same entries from the solver's own per-particle state, keeping the order
    /// of the others; neighbour lists and cached rates are then those of the particles that
    /// remain. Called between steps, only when some particle is removed.
    fn remove_particles(
        &mut self,
        fluid: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError>;

    /// Everything the next step depends on besides the particles (step count, cached rates,
    /// neighbour-list positions, warm-start data), for a checkpoint.
    fn save_state(&self) -> SolverState;

    /// Continues from `state`, saved by [`FluidSolver::save_state`] of a solver built from the
    /// same scene, with `fluid` already set to the particles saved with it; the next step is
    /// then bitwise the step the saving run took next.
    fn restore_state(
        &mut self,
        state: SolverState,
        fluid: &mut Particles<D>,
    ) -> Result<(), SolverError>;
}

/// Mean and maximum of |ρ/ρ₀ − 1|, summed in index order so they do not depend on the number
/// of threads.
pub fn density_errors(density: &[Real], rest_density: Real) -> (Real, Real) {
    // Sequential: one pass of a few µs per 10⁴ particles, cheaper than waking threads.
    let (sum, max) = density
        .iter()
        .fold((0.0, 0.0), |(sum, max): (Real, Real), rho| {
            let error = (rho / rest_density - 1.0).abs();
            (sum + error, max.max(error))
        });
    (sum / density.len().max(1) as Real, max)
}

/// The step to take when the stability limit is `stable` and the next event (output, sample,
/// end) is `max_dt` away: the interval divided into the fewest equal steps no longer than
/// `stable`, so the steps up to an event are all alike and none is a sliver.
///
/// `stable` is exceeded by at most a relative 10⁻⁶, so that an event a whole number of steps
/// away up to the round-off of the accumulated time is not reached by an extra half step.
/// Equal steps matter for the incompressible solvers: their pressure corrects the density
/// error left by the previous step within one step, so it scales with 1/Δt², and a step
/// shortened to land on an event would put a pressure unlike the run's into every output and
/// sample (`docs/incompressible.md`, "Equal steps up to each event").
pub fn event_step(stable: Real, max_dt: Real) -> Real {
    let steps = (max_dt / stable * (1.0 - 1e-6)).ceil().max(1.0);
    max_dt / steps
}

/// Largest |v| of `velocity`.
pub fn max_speed<const D: usize>(velocity: &[geosph_core::Vector<D>]) -> Real {
    velocity
        .iter()
        .fold(0.0, |max: Real, v| max.max(v.norm_squared()))
        .sqrt()
}

/// Weakly compressible SPH: [`WcsphSystem`] advanced by an explicit [`Integrator`] with the
/// adaptive step of [`time_step`], Z-order sorting every `reorder_every` steps and Shepard
/// density re-initialisation every `shepard_every` steps (0: never).
pub struct Wcsph<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>> {
    /// The physics.
    pub system: WcsphSystem<D, K, V, F>,
    /// The time integrator.
    pub integrator: Integrator<D>,
    /// Courant number of the acoustic limit.
    pub cfl: Real,
    /// Steps between Z-order sorts of the particles (0: never).
    pub reorder_every: usize,
    /// Steps between Shepard density re-initialisations (0: never).
    pub shepard_every: usize,
    steps: usize,
}

impl<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>> Wcsph<D, K, V, F> {
    /// A solver for `fluid`; creates its pressure field from the current density.
    pub fn new(
        system: WcsphSystem<D, K, V, F>,
        integrator: Integrator<D>,
        fluid: &mut Particles<D>,
    ) -> Self {
        fluid.enable_pressure();
        system.update_pressure(fluid);
        Self {
            system,
            integrator,
            cfl: 0.25,
            reorder_every: 100,
            shepard_every: 0,
            steps: 0,
        }
    }
}

impl<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>> FluidSolver<D>
    for Wcsph<D, K, V, F>
{
    fn name(&self) -> &'static str {
        "wcsph"
    }

    fn step(
        &mut self,
        fluid: &mut Particles<D>,
        time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError> {
        if self.reorder_every > 0 && self.steps % self.reorder_every == 0 {
            if self.system.domain.is_periodic() {
                let domain = &self.system.domain;
                fluid.position.iter_mut().for_each(|x| domain.wrap(x));
            }
            let grid = self.system.fluid_grid_for_sorting();
            grid.build(&fluid.position)?;
            let permutation = grid.z_order(&fluid.position)?;
            fluid.permute(&permutation);
            self.integrator.permute(&permutation);
        }
        self.system.shepard_due =
            self.shepard_every > 0 && self.steps > 0 && self.steps % self.shepard_every == 0;
        let gravity = self.system.gravity.norm();
        let limits = StepLimits {
            cfl: self.cfl,
            smoothing_length: self.system.kernel.smoothing_length(),
            sound_speed: self.system.eos.sound_speed,
            max_speed: max_speed(&fluid.velocity),
            max_acceleration: self.integrator.rates().max_acceleration().max(gravity),
            kinematic_viscosity: self.system.viscosity.kinematic_viscosity(),
        };
        let dt = event_step(time_step(&limits), max_dt);
        self.integrator.step(&mut self.system, fluid, time, dt)?;
        self.steps += 1;
        let (mean, max) = density_errors(&fluid.density, self.system.eos.rest_density);
        Ok(StepReport {
            dt,
            iterations: 1,
            divergence_iterations: 0,
            density_error_mean: mean,
            density_error_max: max,
        })
    }

    fn walls(&self) -> &WallParticles<D> {
        &self.system.walls
    }

    fn sound_speed(&self) -> Real {
        self.system.eos.sound_speed
    }

    fn density_error(&self, density: Real) -> Real {
        (density / self.system.eos.rest_density - 1.0).abs()
    }

    fn blow_up_advice(&self) -> &'static str {
        "the sound speed is too low or the time step too large (lower `cfl`)"
    }

    fn remove_particles(
        &mut self,
        fluid: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        fluid.retain(keep);
        self.integrator.retain(keep);
        self.system.invalidate_lists();
        Ok(())
    }

    fn save_state(&self) -> SolverState {
        let mut state = SolverState::new(self.name(), self.steps);
        let (arrays, rates) = (&mut state.arrays, self.integrator.rates());
        arrays.push(
            "rates_current",
            &[Real::from(self.integrator.rates_current())],
        );
        arrays.push_matrices("acceleration", &rates.acceleration);
        arrays.push("density_rate", &rates.density_rate);
        arrays.push_matrices("position_correction", &rates.position_correction);
        if let Some(stress_rate) = &rates.stress_rate {
            arrays.push_matrices("stress_rate", stress_rate);
        }
        if let Some(listed) = self.system.listed_positions() {
            arrays.push_matrices("listed_position", listed);
        }
        state
    }

    fn restore_state(
        &mut self,
        mut state: SolverState,
        fluid: &mut Particles<D>,
    ) -> Result<(), SolverError> {
        let steps = state.steps_of(self.name())?;
        let arrays = &mut state.arrays;
        let n = fluid.len();
        let current = arrays.take_value("rates_current")? != 0.0;
        let rates = Rates {
            acceleration: arrays.take_matrices("acceleration", n)?,
            density_rate: arrays
                .take_matrices::<1, 1>("density_rate", n)?
                .iter()
                .map(|m| m[(0, 0)])
                .collect(),
            position_correction: arrays.take_matrices("position_correction", n)?,
            stress_rate: match arrays.contains("stress_rate") {
                true => Some(arrays.take_matrices("stress_rate", n)?),
                false => None,
            },
        };
        self.integrator.restore_rates(rates, current);
        if arrays.contains("listed_position") {
            let listed = arrays.take_matrices("listed_position", n)?;
            self.system.rebuild_lists_at(listed)?;
        }
        self.steps = steps;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_particle_outside_the_domain_gets_a_hint() {
        let error = SolverError::from(SearchError::OutsideDomain {
            index: 7,
            position: vec![0.5, 9.0],
            min: vec![0.0, 0.0],
            max: vec![1.0, 6.0],
        });
        let message = error.to_string();
        assert!(message.contains("particle 7"), "{message}");
        assert!(
            message.contains("enlarge the scene's `domain`"),
            "{message}"
        );
    }

    #[test]
    fn events_are_reached_without_slivers() {
        assert_eq!(event_step(1e-4, 5e-5), 5e-5);
        assert_eq!(event_step(1e-4, 1.5e-4), 0.75e-4);
        approx::assert_relative_eq!(event_step(1e-4, 1e-3), 1e-4, max_relative = 1e-15);
        // Three equal steps rather than two full ones and a remainder of 5 %.
        approx::assert_relative_eq!(event_step(1e-4, 2.1e-4), 0.7e-4, max_relative = 1e-15);
        // An event one step away up to round-off is reached in one step, not two halves.
        let rounded = 1e-4 * (1.0 + 1e-12);
        assert_eq!(event_step(1e-4, rounded), rounded);
        assert_eq!(event_step(Real::INFINITY, 0.1), 0.1);
    }
}
