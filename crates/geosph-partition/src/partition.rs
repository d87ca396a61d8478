//! The cells of the domain, their Morton keys, and the cuts of the key range between ranks.

use geosph_core::{Domain, Real, Vector};
use geosph_neighbours::grid::CELL_MARGIN;
use geosph_neighbours::morton_encode;

/// Why a partition could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PartitionError {
    /// The interaction radius is not a positive finite number.
    #[error("partition: the interaction radius must be finite and > 0, got {0}")]
    Radius(Real),
    /// No rank to partition over.
    #[error("partition: the number of ranks must be at least 1, got 0")]
    NoRank,
    /// More ranks than cells: a cell is the smallest unit a rank can own.
    #[error(
        "partition: {ranks} ranks for a domain of {cells} cells ({counts:?} cells per axis, each at least the interaction radius wide): at most {cells} ranks; run on fewer ranks or enlarge the domain"
    )]
    TooManyRanks {
        /// Ranks asked for.
        ranks: usize,
        /// Cells of the domain.
        cells: usize,
        /// Cells per axis.
        counts: Vec<usize>,
    },
    /// An axis has more cells than a Morton key can index.
    #[error(
        "partition: axis {axis} has {count} cells of the interaction radius; a Morton key in this dimension holds fewer than {limit}"
    )]
    TooManyCells {
        /// The axis.
        axis: usize,
        /// Its cells.
        count: usize,
        /// The most a key can index.
        limit: u64,
    },
    /// A cell's work is negative or not finite.
    #[error("partition: the work of a cell must be finite and >= 0, got {0}")]
    Work(Real),
    /// A distributed run needs a Verlet skin: the margin its halo keeps between set-ups.
    #[error(
        "partition: a distributed run needs a Verlet skin between 0 and the interaction radius {radius}, got {skin} (the solver's `skin`)"
    )]
    Skin {
        /// The skin.
        skin: Real,
        /// The interaction radius.
        radius: Real,
    },
    /// Saved cuts that decrease: not a partition's.
    #[error("partition: saved cuts must not decrease")]
    Cuts,
}

/// The domain cut into cells at least one interaction radius wide, with the Morton key of
/// each: a particle's neighbours all lie in the 3^D cells around its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Cells<const D: usize> {
    domain: Domain<D>,
    counts: [usize; D],
    inv_size: [Real; D],
}

impl<const D: usize> Cells<D> {
    /// The cells of `domain` for interactions within `radius` (the support radius plus any
    /// Verlet skin): ⌊L_k / (radius (1 + ε))⌋ cells along axis k (at least one), ε the
    /// neighbour grid's [`CELL_MARGIN`], so each is wider than `radius` by enough that
    /// rounding in a particle's cell coordinate cannot put two particles one radius apart two
    /// cells apart.
    pub fn new(domain: Domain<D>, radius: Real) -> Result<Self, PartitionError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(PartitionError::Radius(radius));
        }
        let extent = domain.extent();
        let edge = radius * (1.0 + CELL_MARGIN);
        let limit = 1u64 << (64 / D).min(32);
        let mut counts = [1; D];
        let mut inv_size = [0.0; D];
        for axis in 0..D {
            let cells = (extent[axis] / edge).floor();
            let count = if cells >= 1.0 { cells as usize } else { 1 };
            if count as u64 >= limit {
                return Err(PartitionError::TooManyCells { axis, count, limit });
            }
            counts[axis] = count;
            inv_size[axis] = count as Real / extent[axis];
        }
        Ok(Self {
            domain,
            counts,
            inv_size,
        })
    }

    /// Cells per axis.
    pub fn counts(&self) -> [usize; D] {
        self.counts
    }

    /// Cells in all.
    pub fn len(&self) -> usize {
        self.counts.iter().product()
    }

    /// Whether there are no cells (never: every axis has at least one).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The domain.
    pub fn domain(&self) -> &Domain<D> {
        &self.domain
    }

    /// The integer coordinates of the cell of `x`: wrapped on periodic axes, clamped to the
    /// first or last cell on the others (a particle that has left the domain stays with the
    /// rank of the nearest cell until the run removes it; NaN goes to cell 0).
    pub fn coords(&self, x: &Vector<D>) -> [u32; D] {
        let mut coords = [0; D];
        for (axis, c) in coords.iter_mut().enumerate() {
            let n = self.counts[axis];
            let u = ((x[axis] - self.domain.min[axis]) * self.inv_size[axis]).floor();
            let cell = if self.domain.periodic[axis] {
                u.rem_euclid(n as Real)
            } else {
                u
            };
            // `as` saturates (and maps NaN to 0); the clamp covers rounding at the top face.
            *c = (cell.max(0.0) as usize).min(n - 1) as u32;
        }
        coords
    }

    /// The Morton key of the cell of `x`.
    pub fn key(&self, x: &Vector<D>) -> u64 {
        morton_encode(self.coords(x))
    }

    /// Calls `f` with the key of every cell of the (2 `depth` + 1)^D block around `coords`
    /// (itself included) that exists: wrapped across periodic faces, cut at the others. A
    /// periodic axis of fewer than 2 `depth` + 1 cells yields some cells more than once.
    pub fn for_each_cell_around(&self, coords: [u32; D], depth: u32, mut f: impl FnMut(u64)) {
        let depth = i64::from(depth);
        let mut offset = [-depth; D];
        'odometer: loop {
            let mut cell = [0u32; D];
            let mut inside = true;
            for axis in 0..D {
                let n = self.counts[axis] as i64;
                let c = coords[axis] as i64 + offset[axis];
                if self.domain.periodic[axis] {
                    cell[axis] = c.rem_euclid(n) as u32;
                } else if (0..n).contains(&c) {
                    cell[axis] = c as u32;
                } else {
                    inside = false;
                }
            }
            if inside {
                f(morton_encode(cell));
            }
            for o in offset.iter_mut() {
                if *o < depth {
                    *o += 1;
                    continue 'odometer;
                }
                *o = -depth;
            }
            break;
        }
    }
}

/// Ranks owning contiguous runs of the Morton key range of [`Cells`]: rank r owns the cells
/// with keys in [cuts_r, cuts_{r+1}), so space-filling-curve order keeps each rank's cells
/// mostly together and its halo short.
#[derive(Clone, Debug, PartialEq)]
pub struct Partition<const D: usize> {
    cells: Cells<D>,
    /// The first key of each rank after the first (`ranks − 1` cuts, non-decreasing; a rank
    /// whose cut equals the next one's owns no cell, and the cuts of ranks that no work
    /// reached are `u64::MAX`).
    cuts: Vec<u64>,
}

impl<const D: usize> Partition<D> {
    /// Cuts `cells` between `ranks` so that each rank's share of the total work is as even as
    /// whole cells allow: a cell goes to the rank whose equal share holds the middle of the
    /// cell's work along the curve, so no rank is off its share by more than one cell's work.
    /// `cell_work` lists (key, work) per cell in any order, a key any number of times (the
    /// works add); cells not listed have none. Work is what a rank's step costs per cell, e.g.
    /// its particles' neighbour counts; a distributed caller gathers each rank's list first.
    /// Without work, rank 0 owns every cell.
    pub fn balanced(
        cells: Cells<D>,
        ranks: usize,
        mut cell_work: Vec<(u64, Real)>,
    ) -> Result<Self, PartitionError> {
        if ranks == 0 {
            return Err(PartitionError::NoRank);
        }
        if ranks > cells.len() {
            return Err(PartitionError::TooManyRanks {
                ranks,
                cells: cells.len(),
                counts: cells.counts.to_vec(),
            });
        }
        if let Some(&(_, work)) = cell_work
            .iter()
            .find(|(_, w)| !(w.is_finite() && *w >= 0.0))
        {
            return Err(PartitionError::Work(work));
        }
        cell_work.sort_unstable_by_key(|&(key, _)| key);
        let total: Real = cell_work.iter().map(|&(_, work)| work).sum();
        let mut cuts = vec![u64::MAX; ranks - 1];
        let mut next = 0;
        let mut before = 0.0;
        let mut k = 0;
        while k < cell_work.len() {
            let key = cell_work[k].0;
            let mut work = 0.0;
            while k < cell_work.len() && cell_work[k].0 == key {
                work += cell_work[k].1;
                k += 1;
            }
            let middle = before + 0.5 * work;
            while next < cuts.len()
                && work > 0.0
                && middle * ranks as Real >= total * (next + 1) as Real
            {
                cuts[next] = key;
                next += 1;
            }
            before += work;
        }
        Ok(Self { cells, cuts })
    }

    /// The partition of particles at `position` with the work `work[i]` each (one each when
    /// `None`), for a run that starts with every particle on every rank.
    ///
    /// # Panics
    /// If `work` has fewer entries than `position`.
    pub fn from_particles(
        cells: Cells<D>,
        ranks: usize,
        position: &[Vector<D>],
        work: Option<&[Real]>,
    ) -> Result<Self, PartitionError> {
        let cell_work = position
            .iter()
            .enumerate()
            .map(|(i, x)| (cells.key(x), work.map_or(1.0, |work| work[i])))
            .collect();
        Self::balanced(cells, ranks, cell_work)
    }

    /// The partition of `cells` whose rank r > 0 owns the keys from `cuts[r − 1]` on, as
    /// [`Partition::cuts`] gave them (a partition saved with a run and restored).
    ///
    /// # Errors
    /// [`PartitionError::TooManyRanks`] for more ranks than cells; [`PartitionError::Cuts`]
    /// when `cuts` decrease.
    pub fn from_cuts(cells: Cells<D>, cuts: Vec<u64>) -> Result<Self, PartitionError> {
        let ranks = cuts.len() + 1;
        if ranks > cells.len() {
            return Err(PartitionError::TooManyRanks {
                ranks,
                cells: cells.len(),
                counts: cells.counts.to_vec(),
            });
        }
        if cuts.windows(2).any(|pair| pair[1] < pair[0]) {
            return Err(PartitionError::Cuts);
        }
        Ok(Self { cells, cuts })
    }

    /// The first key of each rank after the first.
    pub fn cuts(&self) -> &[u64] {
        &self.cuts
    }

    /// The cells.
    pub fn cells(&self) -> &Cells<D> {
        &self.cells
    }

    /// Ranks.
    pub fn ranks(&self) -> usize {
        self.cuts.len() + 1
    }

    /// The rank that owns the cell of key `key`.
    pub fn owner_of_key(&self, key: u64) -> usize {
        self.cuts.partition_point(|&cut| cut <= key)
    }

    /// The rank that owns a particle at `x`.
    pub fn owner(&self, x: &Vector<D>) -> usize {
        self.owner_of_key(self.cells.key(x))
    }

    /// The ranks other than `rank` that own a cell of the (2 `depth` + 1)^D block around the
    /// cell of `x`, ascending, written to `ranks` (cleared first): where a particle of `rank`
    /// at `x` is in the halo `depth` cells deep.
    pub fn halo_ranks(&self, x: &Vector<D>, rank: usize, depth: u32, ranks: &mut Vec<usize>) {
        ranks.clear();
        self.cells
            .for_each_cell_around(self.cells.coords(x), depth, |key| {
                let owner = self.owner_of_key(key);
                if owner != rank && !ranks.contains(&owner) {
                    ranks.push(owner);
                }
            });
        ranks.sort_unstable();
    }

    /// The work of each rank for `cell_work` as [`Partition::balanced`] takes it.
    pub fn work_per_rank(&self, cell_work: &[(u64, Real)]) -> Vec<Real> {
        let mut work = vec![0.0; self.ranks()];
        for &(key, w) in cell_work {
            work[self.owner_of_key(key)] += w;
        }
        work
    }
}

/// The imbalance of a work distribution: the largest rank's work over the mean (1: even).
pub fn imbalance(work_per_rank: &[Real]) -> Real {
    let total: Real = work_per_rank.iter().sum();
    if total <= 0.0 {
        return 1.0;
    }
    let max = work_per_rank.iter().copied().fold(0.0, Real::max);
    max * work_per_rank.len() as Real / total
}
