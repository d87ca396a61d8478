//! The pair lists of one rank of a distributed run ([`crate::distributed`]): the rank's
//! particles are its own followed by its halo; the lists span both, and the solvers' passes
//! compute both, but only the owned particles' results count.

use geosph_core::{Particles, PerParticle, Real};
use geosph_partition::{PartitionError, Transport};

use super::PairLists;
use crate::distributed::{Distribution, ExchangeCounts};
use crate::solver::SolverError;
use crate::state::PartitionState;

impl<const D: usize> PairLists<D> {
    /// Makes these the lists of one rank of `transport`: from the next
    /// [`PairLists::reorder_if_due`] on, the particles are this rank's own followed by its
    /// halo. Needs a Verlet skin (the halo's margin between set-ups); exact lists take
    /// [`PairLists::distribute_with_margin`]. A cut restored with a checkpoint
    /// ([`PairLists::restore_partition`]) is used on as many ranks.
    ///
    /// # Panics
    /// If the lists are already distributed.
    pub fn distribute(&mut self, transport: Box<dyn Transport>) -> Result<(), PartitionError> {
        self.distribute_with_margin(transport, self.skin)
    }

    /// [`PairLists::distribute`] with the halo's `margin` (positive) in place of the skin: the
    /// cells are the support plus `margin` wide, and a set-up is due once a particle has moved
    /// a quarter of it. For exact lists (no skin), which are rebuilt at every update: a
    /// [`PairLists::reorder_if_due`] right before each update keeps every particle within
    /// a quarter of the margin of where it was at the last set-up whenever lists are built,
    /// however far a step moves it.
    ///
    /// # Panics
    /// If the lists are already distributed.
    pub fn distribute_with_margin(
        &mut self,
        transport: Box<dyn Transport>,
        margin: Real,
    ) -> Result<(), PartitionError> {
        assert!(
            self.distribution.is_none(),
            "the lists are already distributed"
        );
        let radius = self.support_radius + margin;
        self.distribution = Some(Distribution::new(
            transport,
            self.domain.clone(),
            radius,
            margin,
            self.restored_partition.take(),
        )?);
        self.valid = false;
        Ok(())
    }

    /// An error naming `what` in a distributed run, which does not support it yet (a second
    /// distribution, a restart into a distributed solver); nothing on one process.
    pub fn single_process(&self, what: &str) -> Result<(), SolverError> {
        match self.distribution {
            Some(_) => Err(SolverError::NotDistributed(format!(
                "{what} does not run on several ranks yet"
            ))),
            None => Ok(()),
        }
    }

    /// The check every solver's `distribute` makes first: an error if these lists are
    /// already distributed.
    pub fn can_distribute(&self) -> Result<(), SolverError> {
        self.single_process("distributing a run again")
    }

    /// Removes the particles without `keep[i]` (those that left the domain) from `particles`
    /// and `carried`, keeping the others' order, and forgets the lists. In a distributed
    /// run `keep` covers the owned particles and the halo; every rank calls this when any
    /// rank removes a particle (the halos hold copies of it), and all set up anew at once,
    /// keeping the cut ([`Distribution::remove`]; collective). The lists are rebuilt at the
    /// next update.
    pub fn remove_particles(
        &mut self,
        particles: &mut Particles<D>,
        carried: &mut dyn PerParticle,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        self.valid = false;
        let Some(distribution) = &mut self.distribution else {
            particles.retain(keep);
            carried.retain(keep);
            return Ok(());
        };
        distribution.remove(particles, carried, keep);
        self.reorder_if_due(0, particles, carried)?;
        Ok(())
    }

    /// Keeps the cut of a distributed run's checkpoint (`None`: one process's) for
    /// [`PairLists::distribute`].
    pub fn restore_partition(&mut self, partition: Option<PartitionState>) {
        self.restored_partition = partition;
    }

    /// The cut to save with the run ([`Distribution::partition_state`]; `None` on one
    /// process).
    pub fn partition_state(&self) -> Option<PartitionState> {
        self.distribution
            .as_ref()
            .and_then(Distribution::partition_state)
    }

    /// This rank's share of a distributed run, if it is one, to change.
    pub fn distribution_mut(&mut self) -> Option<&mut Distribution<D>> {
        self.distribution.as_mut()
    }

    /// This rank's share of a distributed run, if it is one.
    pub fn distribution(&self) -> Option<&Distribution<D>> {
        self.distribution.as_ref()
    }

    /// The particles of a set of `n` that this rank owns: the first `owned` (all of them in a
    /// run on one process).
    pub fn owned(&self, n: usize) -> usize {
        self.distribution.as_ref().map_or(n, Distribution::owned)
    }

    /// The largest of each of `values` over the ranks, in place (nothing on one process).
    pub fn max_over_ranks(&self, values: &mut [Real]) {
        if let Some(distribution) = &self.distribution {
            distribution.max_each(values);
        }
    }

    /// Every rank's `values` (the same number on every rank) concatenated in rank order
    /// (`values` on one process).
    pub fn gather_over_ranks(&self, values: &[Real]) -> Vec<Real> {
        match &self.distribution {
            Some(distribution) => distribution.gather_each(values),
            None => values.to_vec(),
        }
    }

    /// A step's figures over every rank from this rank's: the mean and the largest of a
    /// per-particle measure over its `owned` particles (e.g. the density error) and a count
    /// (e.g. wall contacts). Unchanged on one process; in a distributed run the mean weighted
    /// by the ranks' particles and the count summed, both in rank order.
    pub fn figures_over_ranks(
        &self,
        mean: Real,
        max: Real,
        owned: usize,
        count: usize,
    ) -> (Real, Real, usize) {
        if self.distribution.is_none() {
            return (mean, max, count);
        }
        let local = [mean * owned as Real, owned as Real, max, count as Real];
        let gathered = self.gather_over_ranks(&local);
        let (mut sum, mut particles, mut largest, mut counted) = (0.0, 0.0, 0.0, 0.0);
        for rank in gathered.chunks_exact(4) {
            sum += rank[0];
            particles += rank[1];
            largest = Real::max(largest, rank[2]);
            counted += rank[3];
        }
        (sum / particles.max(1.0), largest, counted as usize)
    }

    /// What the exchanges of a distributed run did (`None` on one process).
    pub fn exchange_counts(&self) -> Option<ExchangeCounts> {
        self.distribution.as_ref().map(Distribution::counts)
    }

    /// Brings the halo of `particles` up to date with the particles the other ranks own
    /// (nothing on one process). Called before every pass that reads the neighbours' fields
    /// after they changed; the next [`PairLists::update`] checks that the halo still holds
    /// every neighbour.
    pub fn exchange_halo(&mut self, particles: &mut Particles<D>) {
        if let Some(distribution) = &mut self.distribution {
            distribution.refresh(particles);
        }
    }

    /// Overwrites the halo's entries of `values` (one per particle of the set, owned and
    /// halo) with the owners' ([`Distribution::refresh_values`]; nothing on one process).
    pub fn exchange_halo_values(&self, values: &mut [Real]) {
        self.exchange_halo_records(values, 1);
    }

    /// [`PairLists::exchange_halo_values`] for `width` values per particle, one particle's
    /// after another ([`Distribution::refresh_records`]).
    pub fn exchange_halo_records(&self, values: &mut [Real], width: usize) {
        if let Some(distribution) = &self.distribution {
            distribution.refresh_records(values, width);
        }
    }

    /// Between steps: on one process, the Z-order sort when `step` is due
    /// ([`PairLists::sort_if_due`]); in a distributed run, a set-up when it is due
    /// ([`Distribution::due`]: migration, sort and a new halo), balanced by each particle's
    /// listed neighbours. `carried` (the solver's own state of each particle) is reordered,
    /// and in a distributed run moved, with the particles. Returns whether the particles
    /// changed order; the lists are then rebuilt at the next update.
    pub fn reorder_if_due(
        &mut self,
        step: usize,
        particles: &mut Particles<D>,
        carried: &mut dyn PerParticle,
    ) -> Result<bool, SolverError> {
        if self.distribution.is_none() {
            let permutation = self.sort_if_due(step, particles)?;
            if let Some(permutation) = &permutation {
                carried.permute(permutation);
            }
            return Ok(permutation.is_some());
        }
        self.wrap(&mut particles.position);
        let distribution = self.distribution.as_mut().expect("distributed");
        if !distribution.due(&particles.position) {
            return Ok(false);
        }
        let owned = distribution.owned();
        let (inner, contact) = (&self.inner, &self.contact);
        let listed = self.valid && inner.len() == particles.len();
        let work: Option<Vec<Real>> = listed.then(|| {
            (0..owned)
                .map(|i| (inner.neighbours(i).len() + contact.neighbours(i).len()) as Real)
                .collect()
        });
        distribution.set_up(particles, carried, work.as_deref())?;
        self.valid = false;
        Ok(true)
    }
}
