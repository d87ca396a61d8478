//! The solver interface the runner steps, whatever the material: one step, its report, its
//! failure, and what a checkpoint saves.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real};
use geosph_neighbours::SearchError;
use geosph_partition::Transport;
use serde::{Deserialize, Serialize};

use crate::distributed::Distribution;
use crate::state::{SolverState, StateError};
use crate::wall_motion::{MotionError, WallMotion};

/// What one step did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// The time step taken.
    pub dt: Real,
    /// Pressure iterations (1 for explicit solvers; the constant-density solve for DFSPH).
    pub iterations: usize,
    /// Iterations of DFSPH's divergence-free solve (0 for the other solvers).
    pub divergence_iterations: usize,
    /// Mean relative density error over the particles, as the solver measures it
    /// ([`Solver::density_error`]).
    pub density_error_mean: Real,
    /// Largest relative density error.
    pub density_error_max: Real,
    /// Particles that ended the step behind a wall's surface and were put back on it
    /// ([`keep_out_of_walls`](crate::keep_out_of_walls)); 0 where the walls held by pressure.
    pub wall_contacts: usize,
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
    /// The stage run before t = 0 ([`Solver::initial_stage`]) failed.
    #[error("{0}")]
    Stage(String),
    /// Moving walls ([`WallMotion`]) failed or are not supported by this solver.
    #[error("{0}")]
    WallMotion(String),
    /// The domain could not be shared between the ranks of a distributed run.
    #[error(transparent)]
    Partition(#[from] geosph_partition::PartitionError),
    /// The solver (or what the scene asks of it) does not run distributed.
    #[error("{0}")]
    NotDistributed(String),
}

/// What a stage run before t = 0 reached (the soil's geostatic stage): a line for the run's
/// summary and named figures for programs that check it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StageReport {
    /// The stage's name, e.g. "geostatic".
    pub name: String,
    /// Steps the stage took.
    pub steps: usize,
    /// What it reached, in one line.
    pub text: String,
    /// Its figures by name, e.g. `("lateral_ratio_mean", 0.43)`.
    pub figures: Vec<(String, Real)>,
}

impl StageReport {
    /// The figure called `name`, if the stage reports one.
    pub fn figure(&self, name: &str) -> Option<Real> {
        self.figures
            .iter()
            .find(|(figure, _)| figure == name)
            .map(|&(_, value)| value)
    }
}

impl std::fmt::Display for StageReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl From<MotionError> for SolverError {
    fn from(error: MotionError) -> Self {
        match error {
            MotionError::Search(error) => Self::Search(error),
            MotionError::Failed(message) => Self::WallMotion(message),
        }
    }
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

/// An SPH solver of one material (a fluid method, or soil), stepped by the runner. Dispatch
/// happens once per step; the hot loops inside are monomorphised over kernel and physics
/// terms.
pub trait Solver<const D: usize>: Send {
    /// The method's name, e.g. "wcsph".
    fn name(&self) -> &'static str;

    /// What the particles are, for reports: "fluid" unless the solver says otherwise.
    fn material(&self) -> &'static str {
        "fluid"
    }

    /// Whether a step iterates a pressure solve, so that its iteration counts are worth
    /// reporting.
    fn iterates(&self) -> bool {
        false
    }

    /// Runs the stage the solver takes before t = 0 of a new run (the soil's geostatic stage)
    /// and reports it; `None` when it has none. The runner calls it once, before the first
    /// sample of a new run, and never on a restart: [`Solver::restore_state`] brings the
    /// solver to where the stage and the saved steps left it.
    fn initial_stage(
        &mut self,
        _particles: &mut Particles<D>,
    ) -> Result<Option<StageReport>, SolverError> {
        Ok(None)
    }

    /// Advances the particles from `time` by one step of at most `max_dt`.
    fn step(
        &mut self,
        particles: &mut Particles<D>,
        time: Real,
        max_dt: Real,
    ) -> Result<StepReport, SolverError>;

    /// The wall particles, with their current pressure.
    fn walls(&self) -> &WallParticles<D>;

    /// Moves walls with `motion` at the end of every step from now on (rigid bodies); an
    /// error for a solver whose walls cannot move (the default).
    fn set_wall_motion(&mut self, _motion: Box<dyn WallMotion<D>>) -> Result<(), SolverError> {
        Err(SolverError::WallMotion(format!(
            "the {} solver does not move walls: rigid bodies need a fluid solver",
            self.name()
        )))
    }

    /// The walls' motion, if set.
    fn wall_motion(&self) -> Option<&dyn WallMotion<D>> {
        None
    }

    /// Makes this the solver of one rank of a distributed run over `transport`
    /// ([`crate::distributed`]); `particles` are then, from the first step on, this rank's
    /// own followed by its halo ([`Solver::distribution`]). Every rank must hold every
    /// particle when this is called (each built the same scene). An error for a solver that
    /// does not run distributed (the default).
    fn distribute(
        &mut self,
        _particles: &mut Particles<D>,
        _transport: Box<dyn Transport>,
    ) -> Result<(), SolverError> {
        Err(SolverError::NotDistributed(format!(
            "the {} solver does not run on several ranks yet",
            self.name()
        )))
    }

    /// This rank's share of a distributed run, to change (`None` on one process).
    fn distribution_mut(&mut self) -> Option<&mut Distribution<D>> {
        None
    }

    /// This rank's share of a distributed run (`None` on one process).
    fn distribution(&self) -> Option<&Distribution<D>> {
        None
    }

    /// Per-particle quantities derived from `particles` for output (the soil's stress
    /// components and invariants), by name; the runner writes them into every frame after
    /// the particles' own fields. None by default.
    fn output_scalars(&self, _particles: &Particles<D>) -> Vec<(&'static str, Vec<Real>)> {
        Vec::new()
    }

    /// The reference sound speed c₀ (0 for incompressible solvers).
    fn sound_speed(&self) -> Real;

    /// The stress magnitude ‖σ‖, Pa, that a stable run of this material can reach in a domain
    /// `height` deep along gravity of magnitude `gravity`; the runner's health check stops a
    /// run whose stress passes a multiple of it. `None` for materials that carry no stress
    /// (the default).
    fn stress_scale(&self, _gravity: Real, _height: Real) -> Option<Real> {
        None
    }

    /// Energy that the interfaces of `fluid` store and the flow can draw on, J (per metre in
    /// 2D): σ L of surface tension; 0 without one (the default). The runner's health check
    /// counts it in the energy budget.
    fn surface_energy(&self, _fluid: &Particles<D>) -> Real {
        0.0
    }

    /// The density error this solver controls, per particle, as a fraction of ρ₀: |ρ/ρ₀ − 1|
    /// for WCSPH; the compression max(ρ/ρ₀ − 1, 0) for the incompressible solvers, whose
    /// free-surface particles sit below ρ₀ by construction.
    fn density_error(&self, density: Real) -> Real;

    /// What a user can change when the density error runs away.
    fn blow_up_advice(&self) -> &'static str;

    /// Removes the particles `k` without `keep[k]` (particles that left the domain) from
    /// `particles` and the same entries from the solver's own per-particle state, keeping the order
    /// of the others; neighbour lists and cached rates are then those of the particles that
    /// remain. Called between steps, only when some particle is removed; in a distributed run
    /// `keep` covers this rank's particles, owned then halo, and every rank calls it when
    /// any rank removes one (collective; `PairLists::remove_particles`).
    fn remove_particles(
        &mut self,
        particles: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError>;

    /// Everything the next step depends on besides the particles (step count, cached rates,
    /// neighbour-list positions, warm-start data), for a checkpoint. In a distributed run
    /// every rank calls it at the same step, and it may combine values over the ranks (WCSPH's
    /// largest eddy viscosity): a caller makes no rank skip it.
    fn save_state(&self) -> SolverState;

    /// Continues from `state`, saved by [`Solver::save_state`] of a solver built from the
    /// same scene, with `particles` already set to the particles saved with it; the next step is
    /// then bitwise the step the saving run took next.
    fn restore_state(
        &mut self,
        state: SolverState,
        particles: &mut Particles<D>,
    ) -> Result<(), SolverError>;
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

/// Restores a solver's `motion` from the `saved` state of a checkpoint (moving `walls` to
/// where it has them): an error when one of the two has moving walls and the other not.
pub fn restore_wall_motion<const D: usize>(
    motion: &mut Option<Box<dyn WallMotion<D>>>,
    saved: &Option<Vec<u8>>,
    walls: &mut WallParticles<D>,
) -> Result<(), SolverError> {
    match (motion, saved) {
        (None, None) => Ok(()),
        (Some(motion), Some(state)) => motion
            .restore_state(state, walls)
            .map_err(|error| SolverError::WallMotion(format!("restart: {error}"))),
        (Some(_), None) => Err(SolverError::WallMotion(
            "restart: the checkpoint holds no rigid bodies, the scene has some".into(),
        )),
        (None, Some(_)) => Err(SolverError::WallMotion(
            "restart: the checkpoint holds rigid bodies, the scene has none".into(),
        )),
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
