//! The soil solver the runner steps: time step, Z-order sorting, stress regularisation.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use geosph_sph::{
    Distribution, Solver, SolverError, SolverState, StageReport, StepReport, Transport,
    compression, event_step, max_speed,
};
use geosph_time::{StepLimits, time_step};

use crate::invariants::{deviatoric_stress, mean_pressure};
use crate::sph::config::{GeostaticConfig, RegularisationConfig};
use crate::sph::regularise::{RegularisationScratch, regularise_stress};
use crate::sph::system::SoilSystem;

/// Elastoplastic soil SPH: [`SoilSystem`] with the step
///
/// Δt = min(C h / (c + |v|max), ¼ √(h/|a|max)),  c = √((K + 4G/3)/ρ₀),
///
/// the CFL condition on the fastest elastic wave. In plane strain and 3D the P wave is the
/// fastest, with modulus M = K + 4G/3 = E(1 − ν)/((1 + ν)(1 − 2ν)) (Bui et al. 2008 bound the
/// step with √(E/ρ), which is slower by √((1 − ν)/((1 + ν)(1 − 2ν))) = 1/1.16 at ν = 0.3).
pub struct SoilSolver<const D: usize, K: Kernel<D>> {
    /// The physics.
    pub system: SoilSystem<D, K>,
    /// Courant number C.
    pub cfl: Real,
    /// Stress regularisation, if any.
    pub regularisation: Option<RegularisationConfig>,
    /// The geostatic stage still to run before t = 0 ([`Solver::initial_stage`]), if any.
    pub geostatic: Option<GeostaticConfig>,
    scratch: RegularisationScratch<D>,
    steps: usize,
}

impl<const D: usize, K: Kernel<D>> SoilSolver<D, K> {
    /// A solver around `system`.
    pub fn new(system: SoilSystem<D, K>, cfl: Real) -> Self {
        Self {
            system,
            cfl,
            regularisation: None,
            geostatic: None,
            scratch: RegularisationScratch::default(),
            steps: 0,
        }
    }

    /// The stable step of the current state.
    ///
    /// In a distributed run, over every rank's owned particles (collective).
    pub fn stable_step(&self, soil: &Particles<D>) -> Real {
        let lists = &self.system.lists;
        let owned = lists.owned(soil.len());
        let acceleration = self.system.acceleration();
        let mut largest = [
            max_speed(&soil.velocity[..owned]),
            max_speed(&acceleration[..owned.min(acceleration.len())]),
        ];
        lists.max_over_ranks(&mut largest);
        time_step(&StepLimits {
            cfl: self.cfl,
            smoothing_length: self.system.kernel.smoothing_length(),
            sound_speed: self.system.wave_speed,
            max_speed: largest[0],
            max_acceleration: largest[1].max(self.system.gravity.norm()),
            kinematic_viscosity: 0.0,
        })
    }

    /// Steps taken so far.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Makes the next step the first of a run: the step count (which schedules the Z-order
    /// sort and the regularisation) back to zero, and the last step's accelerations and lists
    /// forgotten ([`SoilSystem::forget_last_step`]), so that relaxations started from the same
    /// state step alike whatever ran before them.
    pub fn restart(&mut self) {
        self.steps = 0;
        self.system.forget_last_step();
    }

    /// Runs `work` with the mean-stress diffusion off and switches it back as it was: the
    /// geostatic stage and the strength-reduction trials seek static states, validated without
    /// it, and the diffusion's lithostatic K₀ need not be their state's.
    pub(crate) fn without_mean_stress_diffusion<T>(
        &mut self,
        work: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let diffusion = self.system.mean_stress_diffusion();
        self.system.set_mean_stress_diffusion(None);
        let result = work(self);
        self.system.set_mean_stress_diffusion(diffusion);
        result
    }
}

/// The stress scale ρ₀ (|g| H + c √(2 |g| H)) of soil in a domain H deep along gravity: the
/// geostatic stress at depth H plus the stress ρ₀ c v of an elastic impact at the free-fall
/// speed v = √(2 |g| H) (c the P-wave speed), the deepest column and the longest fall the
/// domain allows.
pub fn geostatic_and_impact_stress(
    rest_density: Real,
    gravity: Real,
    height: Real,
    wave_speed: Real,
) -> Real {
    rest_density * (gravity * height + wave_speed * (2.0 * gravity * height).sqrt())
}

impl<const D: usize, K: Kernel<D>> Solver<D> for SoilSolver<D, K> {
    fn name(&self) -> &'static str {
        "soil-sph"
    }

    fn material(&self) -> &'static str {
        "soil"
    }

    /// The stress components (tension positive; xz and yz in 3D only), p = −I₁/3 and
    /// q = √(3J₂) (compression positive).
    fn output_scalars(&self, soil: &Particles<D>) -> Vec<(&'static str, Vec<Real>)> {
        let Some(fields) = &soil.soil else {
            return Vec::new();
        };
        let stress = &fields.stress;
        let component = |a: usize, b: usize| stress.iter().map(|s| s[(a, b)]).collect();
        let mut scalars = vec![
            ("stress_xx", component(0, 0)),
            ("stress_yy", component(1, 1)),
            ("stress_zz", component(2, 2)),
            ("stress_xy", component(0, 1)),
        ];
        if D == 3 {
            scalars.push(("stress_xz", component(0, 2)));
            scalars.push(("stress_yz", component(1, 2)));
        }
        scalars.push(("p", stress.iter().map(mean_pressure).collect()));
        scalars.push(("q", stress.iter().map(deviatoric_stress).collect()));
        scalars
    }

    fn initial_stage(
        &mut self,
        soil: &mut Particles<D>,
    ) -> Result<Option<StageReport>, SolverError> {
        let Some(stage) = self.geostatic.take() else {
            return Ok(None);
        };
        let report = self
            .run_geostatic_stage(soil, &stage)
            .map_err(|error| SolverError::Stage(error.to_string()))?;
        Ok(Some(report.stage_report()))
    }

    fn step(
        &mut self,
        soil: &mut Particles<D>,
        _time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError> {
        self.system.reorder_if_due(self.steps, soil)?;
        let dt = event_step(self.stable_step(soil), max_dt);
        self.system.step(soil, dt)?;
        self.steps += 1;
        if let Some(regularisation) = self.regularisation {
            let (every, mls) = match regularisation {
                RegularisationConfig::Shepard { every } => (every, false),
                RegularisationConfig::Mls { every } => (every, true),
            };
            if self.steps % every == 0 {
                // The halo moved with accelerations summed over part of its neighbours.
                self.system.lists.exchange_halo(soil);
                regularise_stress(&self.system, soil, mls, &mut self.scratch);
            }
        }
        // Only compression counts: elastic soil compresses by σ/M ≈ 0.1 %, so a large compression
        // is an instability, while a spreading front lowers its density legitimately.
        let owned = self.system.lists.owned(soil.len());
        let (mean, max) = compression(&soil.density[..owned], self.system.rest_density);
        let (mean, max, _) = self.system.lists.figures_over_ranks(mean, max, owned, 0);
        Ok(StepReport {
            dt,
            iterations: 1,
            divergence_iterations: 0,
            density_error_mean: mean,
            density_error_max: max,
            // Soil walls hold by Coulomb contact and Bui's boundary stress (docs/soil.md).
            wall_contacts: 0,
        })
    }

    fn walls(&self) -> &WallParticles<D> {
        &self.system.walls
    }

    /// Shares the run once the geostatic stage, if any, has run: the stage runs on every rank
    /// in full, before ([`Solver::initial_stage`]).
    fn distribute(
        &mut self,
        _soil: &mut Particles<D>,
        transport: Box<dyn Transport>,
    ) -> Result<(), SolverError> {
        self.system.lists.can_distribute()?;
        if self.geostatic.is_some() {
            return Err(SolverError::NotDistributed(
                "the soil's geostatic stage runs on every rank before the run is shared: run `initial_stage` first".into(),
            ));
        }
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
        self.system.wave_speed
    }

    fn stress_scale(&self, gravity: Real, height: Real) -> Option<Real> {
        let system = &self.system;
        Some(geostatic_and_impact_stress(
            system.rest_density,
            gravity,
            height,
            system.wave_speed,
        ))
    }

    fn density_error(&self, density: Real) -> Real {
        (density / self.system.rest_density - 1.0).max(0.0)
    }

    fn blow_up_advice(&self) -> &'static str {
        "the soil is compressed far beyond its elastic range: lower `cfl`, or raise the artificial viscosity"
    }

    /// Stress, strain and displacement travel with the particles; the last accelerations (they
    /// bound the next Δt) lose the same entries.
    fn remove_particles(
        &mut self,
        soil: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        self.system.remove_particles(soil, keep)
    }

    /// The step count, the last accelerations (they bound the next Δt) and the positions of the
    /// neighbour lists; stress, strain and displacement travel with the particles. In a
    /// distributed run, the accelerations of the particles this rank owns and the cut of the
    /// cells, without the lists (the next step starts with a set-up, which rebuilds them).
    fn save_state(&self) -> SolverState {
        let mut state = SolverState::new(self.name(), self.steps);
        let acceleration = self.system.acceleration();
        let lists = &self.system.lists;
        let owned = lists.owned(acceleration.len());
        state
            .per_particle
            .push_matrices("acceleration", &acceleration[..owned]);
        state.partition = lists.partition_state();
        if let Some(listed) = lists
            .listed_positions()
            .filter(|_| state.partition.is_none())
        {
            state.per_particle.push_matrices("listed_position", listed);
        }
        state
    }

    fn restore_state(
        &mut self,
        mut state: SolverState,
        soil: &mut Particles<D>,
    ) -> Result<(), SolverError> {
        self.system.lists.single_process("a restart")?;
        let steps = state.steps_of(self.name())?;
        // The checkpoint was written after the geostatic stage: its particles are restored,
        // and its release is applied to the walls of the scene.
        if let Some(stage) = self.geostatic.take() {
            self.system.release_walls(&stage)?;
        }
        let n = soil.len();
        let per_particle = &mut state.per_particle;
        let acceleration = per_particle.take_matrices("acceleration", n)?;
        let listed = match per_particle.contains("listed_position") {
            true => Some(per_particle.take_matrices("listed_position", n)?),
            false => None,
        };
        self.system.lists.restore_partition(state.partition);
        self.system.restore(acceleration, listed)?;
        self.steps = steps;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stress_scale_adds_geostatic_and_impact_stress() {
        // Bui's bars: ρ₀ = 2650 kg/m³, a 0.5 m high domain, c = 20 m/s.
        let scale = geostatic_and_impact_stress(2650.0, 9.81, 0.5, 20.0);
        let geostatic = 2650.0 * 9.81 * 0.5;
        let impact = 2650.0 * 20.0 * (2.0 * 9.81 * 0.5 as Real).sqrt();
        assert!((scale - geostatic - impact).abs() < 1e-9 * scale);
    }
}
