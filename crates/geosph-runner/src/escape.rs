//! Particles that leave the domain: removed from the run, counted and reported.
//!
//! A particle with a finite position outside the domain on a non-periodic axis (a droplet
//! thrown over a wall, a grain falling past the end of a slope) has left the simulation, as in
//! DualSPHysics. [`Escapes`] removes it from the particles and, through
//! [`Solver::remove_particles`], from the solver's per-particle state, keeping the order
//! of the others (so a run stays the same for any number of threads), and counts it in the
//! loop's [`Progress`]. It finds them after every step, before the health check
//! ([`Escapes::after_step`]): until then the pair lists bin a particle outside the domain in
//! the edge cells of their grid, which keeps its pairs
//! (`CellGrid::bin_outside_in_edge_cells`), so it takes part in the step in which it leaves.
//!
//! On several ranks (`Escapes::after_step_on_rank`) each rank finds its own, the ranks sum
//! what they found in one collective a step, and all remove together (the halos hold copies)
//! and set up anew: the same particles as one process removes, after the same step.
//!
//! A non-finite position is never an escape: the health check diagnoses it as a blow-up. Once
//! more than `health.max_escaped_fraction` of the particles would have left, the run stops
//! with the outside-domain diagnosis instead, so that a blow-up is not hidden by removing
//! what it throws out. A step in which nothing left costs one pass over the positions.

use geosph_core::{Domain, Particles, Real, Vector};
use geosph_sph::{Solver, SolverError, Transport};

use crate::checkpoint::Progress;
use crate::health::{self, Diagnosis, Limits, Scan};

/// What [`Escapes`] did after a step.
#[derive(Clone, Debug, PartialEq)]
pub enum Removal {
    /// No particle left the domain (or some position is not finite: a blow-up, not an
    /// escape).
    Nothing,
    /// Particles left the domain and were removed.
    Removed,
    /// Removing them would exceed the allowed fraction: the run stops with this diagnosis of
    /// the failed state.
    TooMany(Diagnosis),
}

/// Removes the particles that leave the domain; holds the allowed fraction and the mask of
/// the particles kept (allocated at the first escape, then reused).
#[derive(Clone, Debug)]
pub struct Escapes {
    max_fraction: Real,
    keep: Vec<bool>,
}

impl Escapes {
    /// At most `max_fraction` of the particles of the run may leave (the scene's
    /// `health.max_escaped_fraction`).
    pub fn new(max_fraction: Real) -> Self {
        Self {
            max_fraction,
            keep: Vec::new(),
        }
    }

    /// Removes the particles of `fluid` outside the domain of `limits` after a step that
    /// ended at `time`, from `fluid` and `solver`, counts them in `progress` and takes their
    /// energy out of the budget of `limits`.
    pub fn after_step<const D: usize>(
        &mut self,
        fluid: &mut Particles<D>,
        solver: &mut dyn Solver<D>,
        limits: &mut Limits<D>,
        progress: &mut Progress,
        time: Real,
    ) -> Result<Removal, SolverError> {
        let Some(count) = self.mark(fluid, &limits.domain) else {
            return Ok(Removal::Nothing);
        };
        if let Some(diagnosis) = self.too_many(count, fluid, limits, progress) {
            return Ok(Removal::TooMany(diagnosis));
        }
        self.remove(count, fluid, solver, limits, progress, time)?;
        Ok(Removal::Removed)
    }

    /// Sets the mask to keep the particles inside the domain and returns how many are
    /// outside; `None` when none is, or when a position is not finite.
    fn mark<const D: usize>(&mut self, fluid: &Particles<D>, domain: &Domain<D>) -> Option<usize> {
        let mut count = 0;
        let mut finite = true;
        for x in &fluid.position {
            finite &= x.iter().all(|c| c.is_finite());
            count += usize::from(domain.has_left(x));
        }
        if !finite || count == 0 {
            return None;
        }
        self.keep.clear();
        self.keep
            .extend(fluid.position.iter().map(|x| !domain.has_left(x)));
        Some(count)
    }

    /// The diagnosis when `count` more particles of `fluid` leaving would exceed the allowed
    /// fraction of the run's particles.
    fn too_many<const D: usize>(
        &self,
        count: usize,
        fluid: &Particles<D>,
        limits: &Limits<D>,
        progress: &Progress,
    ) -> Option<Diagnosis> {
        if !self.exceeds(count, fluid.len() as u64, progress) {
            return None;
        }
        let total = fluid.len() as u64 + progress.escaped;
        let escaped = progress.escaped + count as u64;
        let fraction = escaped as Real / total as Real;
        let (i, distance) = Scan::first_outside(fluid, limits)?;
        let mut diagnosis =
            health::outside_domain(i, fluid.id[i], distance, &fluid.position[i], &limits.domain);
        diagnosis.explanation = format!(
            "{escaped} of {total} particles ({:.2} %) would have left the domain, more than `health.max_escaped_fraction` = {} allows; the first {}",
            100.0 * fraction,
            self.max_fraction,
            diagnosis.explanation
        );
        Some(diagnosis)
    }

    /// Removes the `count` particles the mask drops, from `fluid` and `solver`.
    fn remove<const D: usize>(
        &self,
        count: usize,
        fluid: &mut Particles<D>,
        solver: &mut dyn Solver<D>,
        limits: &mut Limits<D>,
        progress: &mut Progress,
        time: Real,
    ) -> Result<(), SolverError> {
        let figures = self.removed(fluid, fluid.len(), limits);
        account(count, figures, limits, progress, time);
        solver.remove_particles(fluid, &self.keep)
    }

    /// The kinetic energy, the moment m g·x and the mass of the particles among the first
    /// `owned` of `fluid` that the mask drops.
    fn removed<const D: usize>(
        &self,
        fluid: &Particles<D>,
        owned: usize,
        limits: &Limits<D>,
    ) -> [Real; 3] {
        let mut figures = [0.0; 3];
        for (i, _) in self.keep[..owned].iter().enumerate().filter(|(_, k)| !**k) {
            let m = fluid.mass[i];
            figures[0] += 0.5 * m * fluid.velocity[i].norm_squared();
            figures[1] += m * limits.gravity.dot(&fluid.position[i]);
            figures[2] += m;
        }
        figures
    }

    /// [`Escapes::after_step`] on one rank of a distributed run, whose first `owned`
    /// particles of `fluid` are its own (collective: every rank calls it after every step).
    /// Each rank marks its own particles outside the domain; their count, energies and mass,
    /// with the particles' count and whether a position is not finite, are summed over the
    /// ranks in one collective, so that every rank removes together, counts alike and keeps
    /// the same energy budget. When too many have left, the diagnosis needs every particle:
    /// `whole` gathers them (collective) and the diagnosis is that of one process.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn after_step_on_rank<const D: usize>(
        &mut self,
        fluid: &mut Particles<D>,
        owned: usize,
        solver: &mut dyn Solver<D>,
        limits: &mut Limits<D>,
        progress: &mut Progress,
        time: Real,
        transport: &dyn Transport,
        whole: &mut dyn FnMut(&Particles<D>) -> Particles<D>,
    ) -> Result<Removal, SolverError> {
        let domain = &limits.domain;
        let outside = |x: &Vector<D>| domain.has_left(x);
        let finite = fluid.position[..owned]
            .iter()
            .all(|x| x.iter().all(|c| c.is_finite()));
        self.keep.clear();
        self.keep.extend(fluid.position.iter().map(|x| !outside(x)));
        let count = self.keep[..owned].iter().filter(|k| !**k).count();
        let [kinetic, moment, mass] = self.removed(fluid, owned, limits);
        let mut sums = [
            count as Real,
            Real::from(u8::from(!finite)),
            kinetic,
            moment,
            mass,
            owned as Real,
        ];
        transport.sum_each(&mut sums);
        let count = sums[0] as usize;
        if sums[1] > 0.0 || count == 0 {
            return Ok(Removal::Nothing);
        }
        if self.exceeds(count, sums[5] as u64, progress) {
            let everyone = whole(fluid);
            let diagnosis = self
                .too_many(count, &everyone, limits, progress)
                .expect("too many particles left, and some is outside");
            *fluid = everyone;
            return Ok(Removal::TooMany(diagnosis));
        }
        account(count, [sums[2], sums[3], sums[4]], limits, progress, time);
        solver.remove_particles(fluid, &self.keep)?;
        Ok(Removal::Removed)
    }

    /// Whether `count` more of the run's `particles` leaving would exceed the allowed
    /// fraction.
    fn exceeds(&self, count: usize, particles: u64, progress: &Progress) -> bool {
        let total = particles + progress.escaped;
        (progress.escaped + count as u64) as Real / total as Real > self.max_fraction
    }
}

/// Counts `count` particles that left at `time`, with their kinetic energy, moment m g·x and
/// mass (`figures`), in `progress` and takes their energy out of the budget of `limits`.
fn account<const D: usize>(
    count: usize,
    [kinetic_energy, gravity_moment, mass]: [Real; 3],
    limits: &mut Limits<D>,
    progress: &mut Progress,
    time: Real,
) {
    if let Some(budget) = &mut limits.energy {
        budget.carry_away(kinetic_energy, gravity_moment);
    }
    progress.escaped += count as u64;
    progress.escaped_mass += mass;
    progress.first_escape.get_or_insert(time);
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Vector;

    #[test]
    fn only_finite_positions_outside_are_marked() {
        let domain = Domain::with_periodic(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [true, false],
        )
        .unwrap();
        let position = vec![
            Vector::<2>::new(0.5, 0.5),
            Vector::<2>::new(0.5, 1.0),
            Vector::<2>::new(1.5, 0.5),
            Vector::<2>::new(0.5, -0.1),
        ];
        let mut fluid = Particles::at_rest(position, 1.0, 1000.0);
        let mut escapes = Escapes::new(0.5);
        // The upper face is outside (the domain is half-open); x is periodic.
        assert_eq!(escapes.mark(&fluid, &domain), Some(2));
        assert_eq!(escapes.keep, [true, false, true, false]);
        fluid.position[0][0] = Real::NAN;
        assert_eq!(escapes.mark(&fluid, &domain), None);
    }
}
