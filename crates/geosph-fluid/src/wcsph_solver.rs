//! The WCSPH solver: [`WcsphSystem`] under an explicit integrator.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use geosph_sph::{
    Distribution, FlowShare, Solver, SolverError, SolverState, StepReport, Transport, WallMotion,
    density_errors, event_step, keep_out_of_walls, max_speed, restore_wall_motion,
};
use geosph_time::{Integrator, Rates, StepLimits, time_step};

use crate::wcsph::WcsphSystem;

/// Weakly compressible SPH: [`WcsphSystem`] advanced by an explicit [`Integrator`] with the
/// adaptive step of [`time_step`], Z-order sorting on the schedule of the system's
/// [`PairLists`](geosph_sph::PairLists) and Shepard density re-initialisation every
/// `shepard_every` steps (0: never).
pub struct Wcsph<const D: usize, K: Kernel<D>> {
    /// The physics.
    pub system: WcsphSystem<D, K>,
    /// The time integrator.
    pub integrator: Integrator<D>,
    /// Courant number of the acoustic limit.
    pub cfl: Real,
    /// Steps between Shepard density re-initialisations (0: never).
    pub shepard_every: usize,
    steps: usize,
    /// Walls moved at the end of each step (rigid bodies), if any.
    motion: Option<Box<dyn WallMotion<D>>>,
}

impl<const D: usize, K: Kernel<D>> Wcsph<D, K> {
    /// A solver for `fluid`; creates its pressure field from the current density (and, for
    /// a gas, internal energy, whose rate the integrator then carries).
    pub fn new(
        system: WcsphSystem<D, K>,
        mut integrator: Integrator<D>,
        fluid: &mut Particles<D>,
    ) -> Self {
        if system.gas.is_some() {
            integrator.enable_energy();
        }
        if system.corrects_position() {
            integrator.enable_position_correction();
        }
        fluid.enable_pressure();
        system.update_pressure(fluid);
        Self {
            system,
            integrator,
            cfl: 0.25,
            shepard_every: 0,
            steps: 0,
            motion: None,
        }
    }
}

impl<const D: usize, K: Kernel<D>> Solver<D> for Wcsph<D, K> {
    fn name(&self) -> &'static str {
        "wcsph"
    }

    fn step(
        &mut self,
        fluid: &mut Particles<D>,
        time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError> {
        let lists = &mut self.system.lists;
        lists.reorder_if_due(self.steps, fluid, &mut self.integrator)?;
        // In a distributed run the particles from `owned` on are the halo: copies whose
        // rates are not computed in full. Limits and errors are over the owned ones, then
        // over the ranks.
        let owned = lists.owned(fluid.len());
        self.system.shepard_due =
            self.shepard_every > 0 && self.steps > 0 && self.steps % self.shepard_every == 0;
        let gravity = self.system.gravity.norm();
        // A gas's sound speed is its state's: the largest c_i of the owned particles.
        let sound_speed = match &self.system.gas {
            None => self.system.eos.sound_speed,
            Some(gas) => {
                let pressure = fluid.pressure.as_deref().unwrap_or_default();
                let speeds = fluid.density[..owned].iter().zip(pressure);
                speeds.fold(0.0, |c: Real, (&rho, &p)| {
                    c.max(gas.law.sound_speed(rho, p))
                })
            }
        };
        let mut largest = [
            match self.motion {
                Some(_) => {
                    max_speed(&fluid.velocity[..owned]).max(max_speed(&self.system.walls.velocity))
                }
                None => max_speed(&fluid.velocity[..owned]),
            },
            max_speed(&self.integrator.rates().acceleration[..owned]),
            // ν_t of the last rates (those of the end of the previous step).
            self.system
                .sps
                .as_ref()
                .map_or(0.0, |sps| sps.max_eddy_viscosity()),
            sound_speed,
        ];
        lists.max_over_ranks(&mut largest);
        let limits = StepLimits {
            cfl: self.cfl,
            smoothing_length: self.system.kernel.smoothing_length(),
            sound_speed: largest[3],
            // Moving walls (bodies) count as the flow does: a body must not outrun the step.
            max_speed: largest[0],
            max_acceleration: largest[1].max(gravity),
            kinematic_viscosity: self.system.viscosity.kinematic_viscosity() + largest[2],
        };
        // Capillary waves of the particle scale (Brackbill et al. 1992, eq. 61).
        let capillary = self
            .system
            .surface_tension
            .as_ref()
            .map_or(Real::INFINITY, |tension| {
                tension.time_step_limit(self.system.eos.rest_density, limits.smoothing_length)
            });
        let dt = event_step(time_step(&limits).min(capillary), max_dt);
        self.system.time_step = dt;
        self.integrator.step(&mut self.system, fluid, time, dt)?;
        let wall_contacts = keep_out_of_walls(
            &self.system.lists,
            &self.system.kernel,
            &self.system.walls,
            &mut fluid.position[..owned],
            &mut fluid.velocity[..owned],
        );
        if let Some(motion) = &mut self.motion {
            motion.advance(
                dt,
                FlowShare::of(fluid, &self.system.lists),
                &mut self.system.walls,
            )?;
        }
        self.steps += 1;
        let (mean, max) = match &self.system.gas {
            None => density_errors(&fluid.density[..owned], self.system.eos.rest_density),
            // A gas has no rest density to keep: its state must stay physical.
            Some(_) => {
                let energy = fluid.energy.as_deref().unwrap_or_default();
                let unphysical = fluid.density[..owned]
                    .iter()
                    .any(|&rho| self.density_error(rho) > 0.0)
                    || energy[..owned]
                        .iter()
                        .any(|e| !(e.is_finite() && *e >= 0.0));
                let error = if unphysical { Real::INFINITY } else { 0.0 };
                (error, error)
            }
        };
        let (mean, max, wall_contacts) =
            self.system
                .lists
                .figures_over_ranks(mean, max, owned, wall_contacts);
        Ok(StepReport {
            dt,
            iterations: 1,
            divergence_iterations: 0,
            density_error_mean: mean,
            density_error_max: max,
            wall_contacts,
        })
    }

    fn walls(&self) -> &WallParticles<D> {
        &self.system.walls
    }

    fn set_wall_motion(&mut self, motion: Box<dyn WallMotion<D>>) -> Result<(), SolverError> {
        self.system.lists.walls_move();
        self.motion = Some(motion);
        Ok(())
    }

    fn wall_motion(&self) -> Option<&dyn WallMotion<D>> {
        self.motion.as_deref()
    }

    fn distribute(
        &mut self,
        _fluid: &mut Particles<D>,
        transport: Box<dyn Transport>,
    ) -> Result<(), SolverError> {
        if self.system.gas.is_some() {
            return Err(SolverError::NotDistributed(
                "a gas (an equation of state with internal energy) runs in one process only".into(),
            ));
        }
        if self.system.surface_tension.is_some() {
            return Err(SolverError::NotDistributed(
                "surface tension runs in one process only (its normals are not sent between \
                 ranks)"
                    .into(),
            ));
        }
        self.system.lists.can_distribute()?;
        self.system.lists.distribute(transport)?;
        Ok(())
    }

    fn distribution(&self) -> Option<&Distribution<D>> {
        self.system.lists.distribution()
    }

    fn distribution_mut(&mut self) -> Option<&mut Distribution<D>> {
        self.system.lists.distribution_mut()
    }

    fn sound_speed(&self) -> Real {
        self.system.eos.sound_speed
    }

    /// |ρ/ρ₀ − 1|; for a gas, whose density may take any positive value, 0 for a finite
    /// positive density and infinite otherwise.
    fn density_error(&self, density: Real) -> Real {
        match self.system.gas {
            None => (density / self.system.eos.rest_density - 1.0).abs(),
            Some(_) if density.is_finite() && density > 0.0 => 0.0,
            Some(_) => Real::INFINITY,
        }
    }

    fn surface_energy(&self, fluid: &Particles<D>) -> Real {
        self.system.surface_tension.as_ref().map_or(0.0, |tension| {
            let (kernel, domain) = (&self.system.kernel, self.system.lists.domain());
            let correction = self.system.gradient_correction;
            tension.coefficient * tension.interface_measure(kernel, domain, fluid, correction)
        })
    }

    fn blow_up_advice(&self) -> &'static str {
        match self.system.gas {
            None => "the sound speed is too low or the time step too large (lower `cfl`)",
            Some(_) => {
                "the time step is too large for the shocks (lower `cfl`) or their artificial \
                 viscosity too weak (raise `viscosity.alpha` and `viscosity.beta`)"
            }
        }
    }

    fn remove_particles(
        &mut self,
        fluid: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        self.system
            .lists
            .remove_particles(fluid, &mut self.integrator, keep)?;
        // The cached rates hold the removed particles' forces.
        self.integrator.invalidate();
        Ok(())
    }

    /// The step count, the integrator's cached rates and the positions of the neighbour
    /// lists; in a distributed run, the rates of the particles this rank owns and the cut of
    /// the cells, without the lists (the next step starts with a set-up, which rebuilds them).
    fn save_state(&self) -> SolverState {
        let mut state = SolverState::new(self.name(), self.steps);
        let rates = self.integrator.rates();
        let lists = &self.system.lists;
        let owned = lists.owned(rates.density_rate.len());
        state.arrays.push(
            "rates_current",
            &[Real::from(self.integrator.rates_current())],
        );
        let per_particle = &mut state.per_particle;
        per_particle.push_matrices("acceleration", &rates.acceleration[..owned]);
        per_particle.push("density_rate", &rates.density_rate[..owned]);
        if rates.has_position_correction() {
            per_particle.push_matrices("position_correction", &rates.position_correction[..owned]);
        }
        if rates.has_energy() {
            per_particle.push("energy_rate", &rates.energy_rate[..owned]);
        }
        // The largest ν_t of the last rates over the ranks: the next step's viscous limit.
        if let Some(sps) = &self.system.sps {
            let mut largest = [sps.max_eddy_viscosity()];
            lists.max_over_ranks(&mut largest);
            state.arrays.push("max_eddy_viscosity", &largest);
        }
        state.partition = lists.partition_state();
        if state.partition.is_none() {
            if let Some(listed) = lists.listed_positions() {
                per_particle.push_matrices("listed_position", listed);
            }
            if let Some(listed) = lists.listed_wall_positions() {
                state.arrays.push_matrices("listed_wall_position", listed);
            }
        }
        state.wall_motion = self.motion.as_ref().map(|motion| motion.save_state());
        state
    }

    fn restore_state(
        &mut self,
        mut state: SolverState,
        fluid: &mut Particles<D>,
    ) -> Result<(), SolverError> {
        self.system.lists.single_process("a restart")?;
        let steps = state.steps_of(self.name())?;
        let n = fluid.len();
        let current = state.arrays.take_value("rates_current")? != 0.0;
        let per_particle = &mut state.per_particle;
        let rates = Rates {
            acceleration: per_particle.take_matrices("acceleration", n)?,
            density_rate: per_particle.take_values("density_rate", n)?,
            position_correction: match self.system.corrects_position() {
                true => per_particle.take_matrices("position_correction", n)?,
                false => Vec::new(),
            },
            energy_rate: match self.system.gas {
                Some(_) => per_particle.take_values("energy_rate", n)?,
                None => Vec::new(),
            },
        };
        if let Some(sps) = &mut self.system.sps {
            sps.restore_max_eddy_viscosity(state.arrays.take_value("max_eddy_viscosity")?);
        }
        self.integrator.restore_rates(rates, current);
        restore_wall_motion(&mut self.motion, &state.wall_motion, &mut self.system.walls)?;
        if state.per_particle.contains("listed_position") {
            let listed = state.per_particle.take_matrices("listed_position", n)?;
            let walls = if state.arrays.contains("listed_wall_position") {
                let count = self.system.walls.len();
                state.arrays.take_matrices("listed_wall_position", count)?
            } else {
                self.system.walls.position.clone()
            };
            self.system.lists.rebuild_at(listed, &walls)?;
        }
        self.system.lists.restore_partition(state.partition);
        self.steps = steps;
        Ok(())
    }
}
