//! Walls that move with the flow: rigid bodies, advanced by the solver once per step.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real};
use geosph_neighbours::SearchError;

use crate::distributed::Distribution;
use crate::lists::PairLists;

/// Why moving walls could not advance.
#[derive(Debug, thiserror::Error)]
pub enum MotionError {
    /// The fluid's neighbour search failed (a particle left the domain): the runner's
    /// escape handling takes it from here, as for any step.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// A body failed (left the domain, non-finite), with what to do about it.
    #[error("{0}")]
    Failed(String),
}

/// Walls a solver moves once per step, after the flow has advanced and before its neighbour
/// lists are next built (`geosph-bodies`' rigid bodies, two-way coupled: the flow's pressure
/// moves them, their wall particles hold the flow).
///
/// A solver that supports it takes one through [`Solver::set_wall_motion`](crate::Solver) and
/// calls [`WallMotion::advance`] at the end of each step with the step's Δt and the flow at
/// its end; the implementation rewrites the position, normal, velocity and acceleration of
/// the wall particles it owns and leaves the others alone.
pub trait WallMotion<const D: usize>: Send {
    /// Advances the walls over the step `dt` that brought the flow to `flow` (with the
    /// pressure of the step's end). In a distributed run every rank holds every wall and
    /// advances it alike, from loads summed over the ranks ([`FlowShare::sum_over_ranks`]).
    fn advance(
        &mut self,
        dt: Real,
        flow: FlowShare<'_, D>,
        walls: &mut WallParticles<D>,
    ) -> Result<(), MotionError>;

    /// The names of the figures [`WallMotion::sample`] appends to a diagnostics row.
    fn columns(&self) -> Vec<String>;

    /// Appends the current figures (positions, velocities, loads) to `row`.
    fn sample(&self, row: &mut Vec<Real>);

    /// The columns of [`WallMotion::columns`] worth a plot against time, in m (each body's
    /// height).
    fn plotted(&self) -> Vec<String> {
        Vec::new()
    }

    /// Everything the next [`WallMotion::advance`] depends on, for a checkpoint.
    fn save_state(&self) -> Vec<u8>;

    /// Continues from `state`, saved by [`WallMotion::save_state`] of a motion built from the
    /// same scene, and puts the walls it moves where that state has them.
    fn restore_state(&mut self, state: &[u8], walls: &mut WallParticles<D>) -> Result<(), String>;
}

/// The flow at the end of a step as [`WallMotion::advance`] reads it: this rank's particles,
/// of which it owns the first `owned` (every particle on one process; in a distributed run
/// the rest are its halo, copies of other ranks' particles, which a load must not count a
/// second time), and the ranks to sum a load's partial sums over.
#[derive(Clone, Copy)]
pub struct FlowShare<'a, const D: usize> {
    /// This rank's particles, its own first.
    pub particles: &'a Particles<D>,
    /// How many of `particles` this rank owns.
    pub owned: usize,
    /// The ranks of a distributed run (`None` on one process).
    pub distribution: Option<&'a Distribution<D>>,
}

impl<'a, const D: usize> FlowShare<'a, D> {
    /// The flow of `particles`, shared out as `lists` share them.
    pub fn of(particles: &'a Particles<D>, lists: &'a PairLists<D>) -> Self {
        Self {
            particles,
            owned: lists.owned(particles.len()),
            distribution: lists.distribution(),
        }
    }

    /// Sums over this rank's owned particles, in place, made sums over every particle: added
    /// over the ranks in rank order ([`Distribution::sum_each`]; nothing on one process), so
    /// every rank gets the same.
    pub fn sum_over_ranks(&self, values: &mut [Real]) {
        if let Some(distribution) = self.distribution {
            distribution.sum_each(values);
        }
    }
}
