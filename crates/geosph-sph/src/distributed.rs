//! A run distributed over ranks (issue 26): each rank owns the particles of a run of cells
//! along the Z-order curve ([`geosph_partition::Partition`]) and holds, after them, a *halo*
//! of copies of the other ranks' particles around its own.
//!
//! The halo is two cells deep (cells at least one interaction radius wide): every neighbour
//! of an owned particle, and every neighbour of those, is local. So a pass that reads a value
//! its neighbours summed over theirs (the wall pressure of Adami et al. 2012, the renormalised
//! density gradient of δ-SPH) is right for every owned particle without an exchange between
//! the passes that only read fields: the halo's fields are refreshed before each rate
//! evaluation, and again after a pass that writes a field a later pass reads two cells away
//! (a Shepard density, the soil's stress update). What a rank computes for its halo particles
//! is not used; their fields are overwritten at the next refresh.
//!
//! Ownership and the halo's composition change only at a *set-up*, between steps: when some
//! particle has moved a quarter of the Verlet skin (for exact lists, of the halo's margin)
//! since the last one. Then particles that
//! left a rank's cells move to their owner with the state their solver keeps of them
//! ([`PerParticle`]), the owned particles are sorted along the curve, and the halo is made
//! anew. Between set-ups the halo covers every pair as long as no particle moves more than half
//! the skin, which [`Distribution::agree`] verifies at every list update.

use std::sync::Mutex;
use std::time::Instant;

use geosph_core::{Domain, Particles, PerParticle, Permutation, Real, Vector};
use geosph_neighbours::SearchError;
use geosph_partition::{
    Cells, ExchangePlan, Partition, PartitionError, Transport, halo_plan, imbalance, migration_plan,
};

use crate::state::PartitionState;

/// Depth of the halo in cells: neighbours of neighbours are local.
pub const HALO_DEPTH: u32 = 2;

/// The imbalance (largest rank's work over the mean) above which a set-up cuts the cells
/// anew.
pub const REBALANCE_ABOVE: Real = 1.1;

/// What the exchanges of a run did, for its summary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExchangeCounts {
    /// Set-ups (migration and new halo).
    pub setups: usize,
    /// Set-ups that cut the cells anew.
    pub partitions: usize,
    /// Particles this rank received from others at set-ups.
    pub migrated: usize,
    /// Halo refreshes.
    pub refreshes: usize,
    /// Particles in this rank's halo now.
    pub halo: usize,
    /// Wall-clock seconds in exchanges and reductions.
    pub seconds: f64,
}

/// One rank's share of a distributed run: its transport, the partition, which of its
/// particles it owns (the first [`Distribution::owned`]) and the plan of its halo.
pub struct Distribution<const D: usize> {
    /// The transport and the seconds spent in it, behind a lock so that the lists stay
    /// shareable between rayon's threads (MPI is called by the thread running the step only).
    link: Mutex<Link>,
    rank: usize,
    size: usize,
    cells: Cells<D>,
    partition: Option<Partition<D>>,
    owned: usize,
    halo: ExchangePlan,
    setup_position: Vec<Vector<D>>,
    skin: Real,
    /// The imbalance the last cut reached (cells are indivisible, so it may exceed
    /// [`REBALANCE_ABOVE`]).
    cut_imbalance: Real,
    /// Every rank holds every particle (each built the same scene, or read the same
    /// checkpoint): until the first set-up, which keeps each rank's own without sending.
    holds_all: bool,
    /// The next step starts with a set-up that keeps the cut (after a checkpoint, so that a
    /// restart from it, which starts with one, continues alike; and after a restored cut).
    set_up_keeping_cut: bool,
    counts: ExchangeCounts,
}

/// A transport, the wall time spent in it and the halo refreshes made through it.
struct Link {
    transport: Box<dyn Transport>,
    seconds: f64,
    refreshes: usize,
}

impl<const D: usize> Distribution<D> {
    /// The share of this rank of `transport` in a run on `domain` whose lists reach `radius`
    /// (the support plus the skin `skin`, which must be positive, the halo's margin, and
    /// smaller than `radius`). With `saved`, the cut of a checkpoint of a run on as many
    /// ranks, the first set-up cuts the cells as it did (on another rank count, by the
    /// particles' count).
    pub fn new(
        transport: Box<dyn Transport>,
        domain: Domain<D>,
        radius: Real,
        skin: Real,
        saved: Option<PartitionState>,
    ) -> Result<Self, PartitionError> {
        if !(skin > 0.0 && skin < radius) {
            return Err(PartitionError::Skin { skin, radius });
        }
        let cells = Cells::new(domain, radius)?;
        let size = transport.size();
        let saved = saved.filter(|saved| saved.cuts.len() + 1 == size);
        let (partition, cut_imbalance) = match saved {
            Some(saved) => (
                Some(Partition::from_cuts(cells.clone(), saved.cuts)?),
                saved.imbalance,
            ),
            None => (None, 1.0),
        };
        Ok(Self {
            set_up_keeping_cut: partition.is_some(),
            partition,
            cut_imbalance,
            holds_all: true,
            rank: transport.rank(),
            size: transport.size(),
            link: Mutex::new(Link {
                transport,
                seconds: 0.0,
                refreshes: 0,
            }),
            cells,
            owned: 0,
            halo: ExchangePlan::default(),
            setup_position: Vec::new(),
            skin,
            counts: ExchangeCounts::default(),
        })
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Ranks in all.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The particles this rank owns: the first `owned` of its set, the halo after them.
    pub fn owned(&self) -> usize {
        self.owned
    }

    /// The rank that owns the cell of `x` (`None` before the cells are first cut).
    pub fn owner(&self, x: &Vector<D>) -> Option<usize> {
        self.partition.as_ref().map(|partition| partition.owner(x))
    }

    /// The cut of the cells, to save with the run (`None` before the first set-up).
    pub fn partition_state(&self) -> Option<PartitionState> {
        self.partition.as_ref().map(|partition| PartitionState {
            cuts: partition.cuts().to_vec(),
            imbalance: self.cut_imbalance,
        })
    }

    /// Makes the next step start with a set-up that keeps the cut: what a restart from a
    /// checkpoint written now does, so that the run and its restart continue alike (every
    /// rank must call it).
    pub fn set_up_next_step(&mut self) {
        self.set_up_keeping_cut = self.partition.is_some();
    }

    /// Removes the particles this rank owns without `keep[i]` (those that left the domain;
    /// `keep` covers the owned particles, then the halo) with their entries of `carried`,
    /// keeping the others' order, and drops the halo: the other ranks' halos hold copies of
    /// the removed particles, so every rank calls this when any rank removes one, and the
    /// next set-up, due at once ([`Distribution::set_up_pending`]), keeps the cut.
    ///
    /// # Panics
    /// Before the first set-up, when every rank still holds every particle.
    pub fn remove(
        &mut self,
        particles: &mut Particles<D>,
        carried: &mut dyn PerParticle,
        keep: &[bool],
    ) {
        assert!(
            !self.holds_all,
            "particles are removed after the first set-up"
        );
        let owned = self.owned;
        particles.resize(owned);
        carried.resize(owned);
        let keep = &keep[..owned];
        particles.retain(keep);
        carried.retain(keep);
        geosph_core::retain(&mut self.setup_position, keep);
        self.owned = particles.len();
        self.set_up_next_step();
    }

    /// What the exchanges did so far.
    pub fn counts(&self) -> ExchangeCounts {
        let link = self.link();
        ExchangeCounts {
            seconds: link.seconds,
            refreshes: link.refreshes,
            ..self.counts
        }
    }

    /// The largest `value` over the ranks.
    pub fn max(&self, value: Real) -> Real {
        self.timed(|transport| transport.max(value))
    }

    /// The largest of each of `values` over the ranks, in place.
    pub fn max_each(&self, values: &mut [Real]) {
        self.timed(|transport| transport.max_each(values));
    }

    /// Each of `values` summed over the ranks in rank order, in place
    /// ([`Transport::sum_each`]).
    pub fn sum_each(&self, values: &mut [Real]) {
        self.timed(|transport| transport.sum_each(values));
    }

    /// Every rank's `values` (the same number on every rank), concatenated in rank order.
    pub fn gather_each(&self, values: &[Real]) -> Vec<Real> {
        self.timed(|transport| transport.gather_each(values))
    }

    fn link(&self) -> std::sync::MutexGuard<'_, Link> {
        self.link
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Runs `f` on the transport, adding its wall time to the exchanges'.
    fn timed<T>(&self, f: impl FnOnce(&dyn Transport) -> T) -> T {
        let mut link = self.link();
        let start = Instant::now();
        let result = f(link.transport.as_ref());
        link.seconds += start.elapsed().as_secs_f64();
        result
    }

    /// The halo's records of the last set-up's plan, `halo` of `width` values each, that
    /// `pack(i, record)` appends for owned particle i on the rank that owns it (collective);
    /// record k is that of halo particle `owned + k`.
    ///
    /// # Panics
    /// If the other ranks' halo plans changed without a set-up here (another number of
    /// records arrived).
    fn receive_halo(
        &self,
        halo: usize,
        width: usize,
        pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Vec<Real> {
        let received = self.timed(|transport| transport.exchange(&self.halo, width, pack));
        assert_eq!(
            received.values.len(),
            halo * width,
            "a halo refresh must bring the particles of the last set-up"
        );
        self.link().refreshes += 1;
        received.values
    }

    /// The largest |x − x_set-up|² of a particle this rank owns.
    fn moved2(&self, position: &[Vector<D>]) -> Real {
        let domain = self.cells.domain();
        position[..self.owned]
            .iter()
            .zip(&self.setup_position)
            .map(|(x, x0)| domain.displacement(x, x0).norm_squared())
            .fold(0.0, Real::max)
    }

    /// Whether a set-up is due whatever the particles did: before the first, or after
    /// [`Distribution::set_up_next_step`] (the same on every rank, no collective).
    pub fn set_up_pending(&self) -> bool {
        self.holds_all || self.set_up_keeping_cut
    }

    /// Whether the next step should start with a set-up: before the first, after
    /// [`Distribution::set_up_next_step`], or once some particle has moved a quarter of the
    /// skin since the last (collective).
    pub fn due(&self, position: &[Vector<D>]) -> bool {
        self.set_up_pending() || 16.0 * self.max(self.moved2(position)) > self.skin * self.skin
    }

    /// The outcome of a list update that every rank agrees on (collective): this rank's
    /// `result` if every rank succeeded and every particle is within half the skin of where it
    /// was at the last set-up (so that the halo still holds every neighbour); otherwise an
    /// error on every rank, this rank's own, [`SearchError::HaloOutdated`], or
    /// [`SearchError::OnAnotherRank`]. So one rank's failure never leaves the others waiting
    /// in the next exchange.
    pub fn agree(
        &self,
        result: Result<bool, SearchError>,
        position: &[Vector<D>],
    ) -> Result<bool, SearchError> {
        let mut shared = [self.moved2(position), Real::from(u8::from(result.is_err()))];
        self.max_each(&mut shared);
        let [moved2, failed] = shared;
        if failed > 0.0 {
            return Err(result.err().unwrap_or(SearchError::OnAnotherRank));
        }
        let (moved, limit) = (moved2.sqrt(), 0.5 * self.skin);
        if moved > limit {
            return Err(SearchError::HaloOutdated { moved, limit });
        }
        result
    }

    /// Migrates, sorts and makes the halo anew (collective): drops the halo of `particles`,
    /// cuts the cells anew (unless the set-up keeps the cut: [`Distribution::set_up_next_step`],
    /// a restored cut) if this is the first set-up or the work (`work[i]` of owned
    /// particle i, one each without) is out of balance, sends the owned particles that left
    /// this rank's cells to their owners with their entries of `carried`, sorts the owned
    /// particles along the curve (by cell, then id), and receives the halo (its entries of
    /// `carried` are zero). At the first set-up every rank holds every particle (each built
    /// the same scene) and keeps those it owns.
    pub fn set_up(
        &mut self,
        particles: &mut Particles<D>,
        carried: &mut dyn PerParticle,
        work: Option<&[Real]>,
    ) -> Result<(), PartitionError> {
        let rank = self.rank();
        let first = self.holds_all;
        let owned = if first { particles.len() } else { self.owned };
        particles.resize(owned);
        carried.resize(owned);
        if !self.set_up_keeping_cut {
            self.balance(particles, work)?;
        }
        let partition = self.partition.as_ref().expect("balanced");

        let (mut plan, keep) = migration_plan(partition, rank, &particles.position);
        if first {
            plan = ExchangePlan {
                send: vec![Vec::new(); self.size],
            };
        }
        let (width, extra) = (particles.record_width(), carried.record_width());
        let received = self.timed(|transport| {
            transport.exchange(&plan, width + extra, &mut |i, record| {
                particles.pack(i, record);
                carried.pack(i, record);
            })
        });
        particles.retain(&keep);
        carried.retain(&keep);
        let kept = particles.len();
        let arrived = received.values.len() / (width + extra);
        particles.resize(kept + arrived);
        carried.resize(kept + arrived);
        for (k, record) in received.values.chunks_exact(width + extra).enumerate() {
            particles.unpack(kept + k, &record[..width]);
            carried.unpack(kept + k, &record[width..]);
        }

        let cells = &self.cells;
        let mut order: Vec<u32> = (0..particles.len() as u32).collect();
        order.sort_unstable_by_key(|&i| {
            let i = i as usize;
            (cells.key(&particles.position[i]), particles.id[i])
        });
        let permutation = Permutation::from_order(order).expect("a sort yields a permutation");
        particles.permute(&permutation);
        carried.permute(&permutation);
        self.owned = particles.len();
        self.setup_position.clear();
        self.setup_position.extend_from_slice(&particles.position);

        self.halo = halo_plan(partition, rank, &particles.position, HALO_DEPTH);
        let received = self.timed(|transport| {
            transport.exchange(&self.halo, width, &mut |i, record| {
                particles.pack(i, record)
            })
        });
        let halo = received.values.len() / width;
        particles.resize(self.owned + halo);
        carried.resize(self.owned + halo);
        for (k, record) in received.values.chunks_exact(width).enumerate() {
            particles.unpack(self.owned + k, record);
        }
        self.holds_all = false;
        self.set_up_keeping_cut = false;
        self.counts.setups += 1;
        self.counts.migrated += arrived;
        self.counts.halo = halo;
        Ok(())
    }

    /// Cuts the cells by the owned particles' work if there is no partition yet or the work
    /// is out of balance (above [`REBALANCE_ABOVE`], and 5 % above what the last cut reached:
    /// cells too coarse to balance better are not cut again at every set-up); every rank
    /// gathers every cell's work, so all cut alike.
    fn balance(
        &mut self,
        particles: &Particles<D>,
        work: Option<&[Real]>,
    ) -> Result<(), PartitionError> {
        let work_of = |i: usize| work.map_or(1.0, |work| work[i]);
        let n = particles.len();
        if self.partition.is_some() {
            let total: Real = (0..n).map(work_of).sum();
            let per_rank = self.timed(|transport| transport.all_gather(&[total]).values);
            if imbalance(&per_rank) <= REBALANCE_ABOVE.max(1.05 * self.cut_imbalance) {
                return Ok(());
            }
        }
        let mut keyed: Vec<(u64, Real)> = (0..n)
            .map(|i| (self.cells.key(&particles.position[i]), work_of(i)))
            .collect();
        keyed.sort_unstable_by_key(|&(key, _)| key);
        // (high 32 bits of the key, low 32 bits, work) per cell: a key is exact in two f64.
        let mut local = Vec::new();
        for run in keyed.chunk_by(|a, b| a.0 == b.0) {
            let key = run[0].0;
            let work: Real = run.iter().map(|&(_, w)| w).sum();
            local.extend_from_slice(&[(key >> 32) as Real, (key & 0xffff_ffff) as Real, work]);
        }
        // At the first set-up every rank holds every particle: its own list is everyone's.
        let gathered = if self.holds_all {
            local
        } else {
            self.timed(|transport| transport.all_gather(&local).values)
        };
        let cell_work: Vec<(u64, Real)> = gathered
            .chunks_exact(3)
            .map(|c| (((c[0] as u64) << 32) | c[1] as u64, c[2]))
            .collect();
        let partition = Partition::balanced(self.cells.clone(), self.size(), cell_work.clone())?;
        self.cut_imbalance = imbalance(&partition.work_per_rank(&cell_work));
        self.partition = Some(partition);
        self.counts.partitions += 1;
        Ok(())
    }

    /// Overwrites the halo of `particles` with the current fields of the particles the other
    /// ranks own (collective).
    ///
    /// # Panics
    /// If the other ranks' halo plans changed without a set-up here.
    pub fn refresh(&mut self, particles: &mut Particles<D>) {
        let (halo, width) = (particles.len() - self.owned, particles.record_width());
        let records = self.receive_halo(halo, width, &mut |i, record| particles.pack(i, record));
        for (k, record) in records.chunks_exact(width).enumerate() {
            particles.unpack(self.owned + k, record);
        }
    }

    /// Overwrites the halo's entries of `values`, one per particle of this rank's set (its
    /// own, then its halo), with the values of the particles the other ranks own
    /// (collective): for a field that a pass computed for every particle, right on the owned
    /// ones only, and that the next pass reads from neighbours (a pressure solve's p/ρ²).
    ///
    /// # Panics
    /// If `values` holds fewer than the owned particles, or the other ranks' halo plans
    /// changed without a set-up here.
    pub fn refresh_values(&self, values: &mut [Real]) {
        self.refresh_records(values, 1);
    }

    /// [`Distribution::refresh_values`] for records of `width` values per particle (`values`
    /// holds the particles' records one after another): for a tensor per particle.
    ///
    /// # Panics
    /// As [`Distribution::refresh_values`].
    pub fn refresh_records(&self, values: &mut [Real], width: usize) {
        let (own, halo) = values.split_at_mut(self.owned * width);
        let received = self.receive_halo(halo.len() / width, width, &mut |i, record| {
            record.extend_from_slice(&own[i * width..(i + 1) * width]);
        });
        halo.copy_from_slice(&received);
    }
}
