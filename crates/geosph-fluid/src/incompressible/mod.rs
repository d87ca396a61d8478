//! Incompressible SPH: PCISPH, IISPH and DFSPH on one set of discrete operators.
//!
//! All three advance a step with the same skeleton (symplectic Euler, as in the papers):
//!
//! 1. known accelerations a* (gravity, viscosity, wall head) and the step Δt from the velocity
//!    CFL, so the step does not depend on a sound speed;
//! 2. v* = v + Δt a*;
//! 3. a pressure solve that makes the density predicted from v*, ρ_i + Δt Σ_j m_j
//!    (v*_i − v*_j)·∇_i W_ij, equal to ρ₀ within the target average error, and corrects v;
//! 4. x ← x + Δt v, then the neighbour lists, summation densities and diagonals for the new
//!    positions (and, for DFSPH, the divergence-free solve).
//!
//! They differ in step 3 only: how the pressure is updated from the density residual
//! ([`Pcisph`], [`Iisph`], [`Dfsph`]). Pressures are clamped at zero, so free surfaces need no
//! detection, unless [`PressureSolveSettings::negative_pressure`] lets a flow without a free
//! surface (periodic, confined) carry suction. With [`ParticleShifting`](geosph_sph::ParticleShifting) the drift of step 4 is
//! x ← x + Δt (v + δv_shift), the shift computed from the lists of the step's start. The
//! derivation of the shared system is in `docs/fluid.md`.

mod dfsph;
mod errors;
mod iisph;
mod krylov;
mod pcisph;
mod settings;
mod system;

pub use dfsph::Dfsph;
pub use iisph::Iisph;
pub use krylov::{Bicgstab, KrylovScratch, PressureIteration};
pub use pcisph::Pcisph;
pub use settings::{PressureSolveSettings, PressureSource};
pub use system::{DIAGONAL_FLOOR, PressureSystem, WallPressure};

use geosph_boundary::WallParticles;
use geosph_core::{Particles, PerParticle, Permutation, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_sph::lattice::{
    lattice_gradient_factor, lattice_gradient_squares, lattice_jacobi_bound, lattice_kernel_sum,
};
use geosph_sph::{
    Distribution, FlowShare, ShiftingInput, Solver, SolverError, SolverState, StateArrays,
    StateError, StepReport, Transport, WallMotion, compression, event_step, keep_out_of_walls,
    max_speed, restore_wall_motion,
};
use rayon::prelude::*;

/// What a pressure solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveReport {
    /// Iterations of the solve.
    pub iterations: usize,
    /// Its last average error (relative compression, or for DFSPH's divergence solve Δt
    /// times the relative density rate; for IISPH's [`Bicgstab`] the mean |residual|/ρ₀ of
    /// its equation).
    pub error: Real,
}

/// Per-particle work arrays of the pressure solves, owned by the solver and reused every step.
#[derive(Clone, Debug, Default)]
pub struct Scratch<const D: usize> {
    /// Accelerations (known, or from pressure).
    pub acceleration: Vec<Vector<D>>,
    /// p/ρ² of a pressure (or pressure increment) field.
    pub pressure_term: Vec<Real>,
    /// A divergence Σ_j m_j (u_i − u_j)·∇_i W_ij.
    pub divergence: Vec<Real>,
    /// Per-particle residual or source.
    pub residual: Vec<Real>,
    /// Shifting velocity δv of the step.
    pub shift: Vec<Vector<D>>,
    /// Particle volumes m/ρ (for shifting).
    pub volume: Vec<Real>,
    /// Work vectors of the Krylov solve.
    pub krylov: KrylovScratch,
}

impl<const D: usize> Scratch<D> {
    fn resize(&mut self, n: usize) {
        self.acceleration.resize(n, Vector::zeros());
        self.pressure_term.resize(n, 0.0);
        self.divergence.resize(n, 0.0);
        self.residual.resize(n, 0.0);
    }

    /// The shifting velocity δv of every particle into [`Scratch::shift`] (zero without
    /// shifting), from the lists of the current positions.
    fn shifting_velocity<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &Particles<D>,
        spacing: Real,
        dt: Real,
    ) {
        let n = fluid.len();
        let mut speed = [max_speed(&fluid.velocity[..system.lists.owned(n)])];
        system.lists.max_over_ranks(&mut speed);
        self.shift.resize(n, Vector::zeros());
        let Some(shifting) = &system.shifting else {
            return;
        };
        self.volume.resize(n, 0.0);
        (
            self.volume.par_iter_mut(),
            fluid.mass.par_iter(),
            fluid.density.par_iter(),
        )
            .into_par_iter()
            .for_each(|(v, m, rho)| *v = m / rho);
        let input = ShiftingInput {
            position: &fluid.position,
            volume: &self.volume,
            wall_position: &system.walls.position,
            wall_volume: &system.walls.volume,
            max_speed: speed[0],
            time_step: dt,
        };
        shifting.velocity(
            &system.kernel,
            spacing,
            &system.lists,
            input,
            &mut self.shift,
        );
    }
}

/// The pressure solve that distinguishes PCISPH, IISPH and DFSPH.
pub trait PressureMethod<const D: usize>: Send {
    /// The method's name, e.g. "iisph".
    const NAME: &'static str;

    /// Corrects the predicted velocities in `fluid.velocity` (and sets `fluid.pressure`) so the
    /// density predicted for the end of the step is ρ₀ within the target error.
    fn correct_density<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport;

    /// Called after positions, lists and densities were updated (DFSPH's divergence solve).
    fn after_update<K: Kernel<D>>(
        &mut self,
        _system: &PressureSystem<D, K>,
        _fluid: &mut Particles<D>,
        _dt: Real,
        _settings: &PressureSolveSettings,
        _scratch: &mut Scratch<D>,
    ) -> SolveReport {
        SolveReport::default()
    }

    /// The method's own state of each particle (a warm start), which is reordered and
    /// thinned with the particles and, in a distributed run, moves between ranks with them
    /// (`None`: it keeps none).
    fn carried(&mut self) -> Option<&mut dyn PerParticle> {
        None
    }

    /// Readies the method to step `fluid` as one rank of a distributed run (every rank
    /// still holds every particle), or names what of it does not run on several ranks.
    fn distribute(&mut self, _fluid: &Particles<D>) -> Result<(), SolverError> {
        Ok(())
    }

    /// Adds the method's own per-particle warm-start arrays of the first `owned` particles
    /// (all of them on one process) to a checkpoint's `arrays`.
    fn save_state(&self, _arrays: &mut StateArrays, _owned: usize) {}

    /// Takes the method's warm-start arrays of the `n` particles restored back from `arrays`
    /// (a restart); an error naming the array that holds another number.
    fn restore_state(&mut self, _arrays: &mut StateArrays, _n: usize) -> Result<(), StateError> {
        Ok(())
    }
}

/// The per-particle state of a method that keeps none.
struct NoParticleState;

impl PerParticle for NoParticleState {
    fn record_width(&self) -> usize {
        0
    }

    fn pack(&self, _i: usize, _record: &mut Vec<Real>) {}

    fn unpack(&mut self, _i: usize, _record: &[Real]) {}

    fn resize(&mut self, _n: usize) {}

    fn retain(&mut self, _keep: &[bool]) {}

    fn permute(&mut self, _permutation: &Permutation) {}
}

/// Runs `f` on the method's [carried](PressureMethod::carried) state (on an empty one if it
/// keeps none).
fn with_carried<const D: usize, M: PressureMethod<D>, T>(
    method: &mut M,
    f: impl FnOnce(&mut dyn PerParticle) -> T,
) -> T {
    match method.carried() {
        Some(carried) => f(carried),
        None => f(&mut NoParticleState),
    }
}

/// An incompressible solver: the shared [`PressureSystem`] stepped with the pressure solve `M`.
pub struct Incompressible<const D: usize, K: Kernel<D>, M: PressureMethod<D>> {
    /// The discrete operators.
    pub system: PressureSystem<D, K>,
    /// The pressure solve.
    pub method: M,
    /// Iteration controls and time-step rule.
    pub settings: PressureSolveSettings,
    /// Particle spacing dx (for the CFL rule).
    pub spacing: Real,
    scratch: Scratch<D>,
    previous_velocity: Vec<Vector<D>>,
    max_acceleration: Real,
    steps: usize,
    /// Walls moved at the end of each step (rigid bodies), if any.
    motion: Option<Box<dyn WallMotion<D>>>,
}

impl<const D: usize, K: Kernel<D>, M: PressureMethod<D>> Incompressible<D, K, M> {
    /// A solver for `fluid`: sorts it, builds the lists and densities, creates its pressure.
    pub fn new(
        mut system: PressureSystem<D, K>,
        method: M,
        settings: PressureSolveSettings,
        spacing: Real,
        fluid: &mut Particles<D>,
    ) -> Result<Self, SearchError> {
        fluid.enable_pressure();
        // Masses and wall volumes for which the initial lattice is at ρ₀ exactly.
        let cell = 1.0 / lattice_kernel_sum(&system.kernel, spacing);
        let scale = cell / spacing.powi(D as i32);
        fluid.mass.iter_mut().for_each(|m| *m *= scale);
        system.walls.volume.iter_mut().for_each(|v| *v *= scale);
        system.gradient_correction = 1.0 / lattice_gradient_factor(&system.kernel, spacing, cell);
        system.jacobi_bound = lattice_jacobi_bound(&system.kernel, spacing);
        system.lattice_gradient_squares = lattice_gradient_squares(&system.kernel, spacing);
        let mut method = method;
        let permutation = system.lists.sort(fluid)?;
        with_carried(&mut method, |carried| carried.permute(&permutation));
        system.update(fluid)?;
        let mut scratch = Scratch::default();
        scratch.resize(fluid.len());
        Ok(Self {
            max_acceleration: system.gravity.norm(),
            system,
            method,
            settings,
            spacing,
            scratch,
            previous_velocity: vec![Vector::zeros(); fluid.len()],
            steps: 0,
            motion: None,
        })
    }

    /// The largest Δt for which no particle moves more than λ dx:
    /// |v|max Δt + ½ |a|max Δt² = λ dx, bounded by the viscous limit ⅛ h²/ν and
    /// `max_time_step`; |v|max over the `owned` particles of every rank.
    fn stable_step(&self, fluid: &Particles<D>, owned: usize) -> Real {
        let reach = self.settings.cfl * self.spacing;
        // Moving walls (bodies) count as the flow does: a body must not outrun the step.
        let mut speed = [match self.motion {
            Some(_) => max_speed(&fluid.velocity).max(max_speed(&self.system.walls.velocity)),
            None => max_speed(&fluid.velocity[..owned]),
        }];
        self.system.lists.max_over_ranks(&mut speed);
        let [speed] = speed;
        let acceleration = self.max_acceleration;
        let mut dt = if acceleration > 0.0 {
            (-speed + (speed * speed + 2.0 * acceleration * reach).sqrt()) / acceleration
        } else if speed > 0.0 {
            reach / speed
        } else {
            Real::INFINITY
        };
        let nu = self.system.viscosity.kinematic_viscosity();
        if nu > 0.0 {
            let h = self.system.kernel.smoothing_length();
            dt = dt.min(0.125 * h * h / nu);
        }
        if let Some(max) = self.settings.max_time_step {
            dt = dt.min(max);
        }
        dt
    }
}

impl<const D: usize, K: Kernel<D>, M: PressureMethod<D>> Solver<D> for Incompressible<D, K, M> {
    fn name(&self) -> &'static str {
        M::NAME
    }

    fn iterates(&self) -> bool {
        true
    }

    fn step(
        &mut self,
        fluid: &mut Particles<D>,
        _time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError> {
        // In a distributed run the particles from `owned` on are the halo: copies whose
        // solves are right near the owned particles only. Before the first step (and after a
        // checkpoint) the ranks set up; at every step's start the halo takes the owners'
        // velocities and densities, which the last update and solve left right on the owned
        // particles only. Limits and errors are over the owned particles, then over the ranks.
        if let Some(distribution) = self.system.lists.distribution() {
            if distribution.set_up_pending() {
                let (lists, method) = (&mut self.system.lists, &mut self.method);
                with_carried(method, |carried| {
                    lists.reorder_if_due(self.steps, fluid, carried)
                })?;
                self.system.update(fluid)?;
            }
            self.system.lists.exchange_halo(fluid);
        }
        let n = fluid.len();
        let owned = self.system.lists.owned(n);
        self.scratch.resize(n);
        let dt = event_step(self.stable_step(fluid, owned), max_dt);

        // v* into the spare buffer, which then swaps with v: the old velocity stays behind
        // for the acceleration bound below.
        self.previous_velocity.resize(n, Vector::zeros());
        self.system.wall_viscous_velocity(fluid);
        self.system
            .predict_velocity(fluid, dt, &mut self.previous_velocity);
        std::mem::swap(&mut fluid.velocity, &mut self.previous_velocity);
        let density_solve =
            self.method
                .correct_density(&self.system, fluid, dt, &self.settings, &mut self.scratch);
        if self.system.shifting.is_some() {
            self.scratch
                .shifting_velocity(&self.system, fluid, self.spacing, dt);
            (
                fluid.position.par_iter_mut(),
                fluid.velocity.par_iter(),
                self.scratch.shift.par_iter(),
            )
                .into_par_iter()
                .for_each(|(x, v, shift)| *x += (v + shift) * dt);
        } else {
            fluid
                .position
                .par_iter_mut()
                .zip(fluid.velocity.par_iter())
                .for_each(|(x, v)| *x += v * dt);
        }
        let wall_contacts = keep_out_of_walls(
            &self.system.lists,
            &self.system.kernel,
            &self.system.walls,
            &mut fluid.position[..owned],
            &mut fluid.velocity[..owned],
        );
        // Largest |Δv|/Δt of this step, for the next step's limit (ordered, thread-independent).
        let mut largest = [fluid.velocity[..owned]
            .iter()
            .zip(&self.previous_velocity)
            .fold(self.system.gravity.norm(), |max: Real, (v, v0)| {
                max.max((v - v0).norm() / dt)
            })];
        self.system.lists.max_over_ranks(&mut largest);
        self.max_acceleration = largest[0];

        // Bodies move with the pressure of this step, before the lists and wall gradients
        // of the next are built.
        if let Some(motion) = &mut self.motion {
            motion.advance(
                dt,
                FlowShare::of(fluid, &self.system.lists),
                &mut self.system.walls,
            )?;
        }
        self.steps += 1;
        // The Z-order sort when due; in a distributed run a set-up once a particle has moved
        // a quarter of the halo's margin, else the halo's new positions from their owners:
        // so the lists built next hold every pair near the owned particles.
        let (lists, method) = (&mut self.system.lists, &mut self.method);
        if !with_carried(method, |carried| {
            lists.reorder_if_due(self.steps, fluid, carried)
        })? {
            lists.exchange_halo(fluid);
        }
        self.system.update(fluid)?;
        self.scratch.resize(fluid.len());
        let divergence_solve =
            self.method
                .after_update(&self.system, fluid, dt, &self.settings, &mut self.scratch);
        let owned = self.system.lists.owned(fluid.len());
        let (mean, max) = compression(&fluid.density[..owned], self.system.rest_density);
        let (mean, max, wall_contacts) =
            self.system
                .lists
                .figures_over_ranks(mean, max, owned, wall_contacts);
        Ok(StepReport {
            dt,
            iterations: density_solve.iterations,
            divergence_iterations: divergence_solve.iterations,
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

    /// The lists of one rank, with a halo margin of one support (so the halo is two cells
    /// of two supports deep); the method's warm start moves with the particles.
    fn distribute(
        &mut self,
        fluid: &mut Particles<D>,
        transport: Box<dyn Transport>,
    ) -> Result<(), SolverError> {
        self.system.lists.can_distribute()?;
        self.method.distribute(fluid)?;
        let margin = self.system.kernel.support_radius();
        self.system
            .lists
            .distribute_with_margin(transport, margin)?;
        Ok(())
    }

    fn distribution(&self) -> Option<&Distribution<D>> {
        self.system.lists.distribution()
    }

    fn distribution_mut(&mut self) -> Option<&mut Distribution<D>> {
        self.system.lists.distribution_mut()
    }

    fn sound_speed(&self) -> Real {
        0.0
    }

    fn density_error(&self, density: Real) -> Real {
        (density / self.system.rest_density - 1.0).max(0.0)
    }

    fn blow_up_advice(&self) -> &'static str {
        "the pressure solve did not hold the density: lower `cfl`, set `max_time_step`, or raise `max_iterations`"
    }

    /// The pressure warm start travels with the particles, the method's own with
    /// [`PressureMethod::carried`]; lists, densities and diagonals are rebuilt for the
    /// particles that remain.
    fn remove_particles(
        &mut self,
        fluid: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        let (lists, method) = (&mut self.system.lists, &mut self.method);
        with_carried(method, |carried| {
            lists.remove_particles(fluid, carried, keep)
        })?;
        self.system.update(fluid)?;
        Ok(())
    }

    /// The step count, the acceleration bound of the next step's Δt and the method's warm
    /// start (in a distributed run, of the particles this rank owns, with the cut of the
    /// cells); the pressure warm start travels with the particles. Lists, densities and
    /// diagonals are rebuilt exactly from the positions.
    fn save_state(&self) -> SolverState {
        let mut state = SolverState::new(self.name(), self.steps);
        state
            .arrays
            .push("max_acceleration", &[self.max_acceleration]);
        let owned = self.system.lists.owned(self.system.diagonal().len());
        self.method.save_state(&mut state.per_particle, owned);
        state.partition = self.system.lists.partition_state();
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
        let max_acceleration = state.arrays.take_value("max_acceleration")?;
        self.method
            .restore_state(&mut state.per_particle, fluid.len())?;
        restore_wall_motion(&mut self.motion, &state.wall_motion, &mut self.system.walls)?;
        self.system.lists.restore_partition(state.partition);
        self.system.update(fluid)?;
        self.max_acceleration = max_acceleration;
        self.steps = steps;
        Ok(())
    }
}
