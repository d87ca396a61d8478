//! The uniform cell grid and its counting sort of particles into cells.

use std::ops::Range;

use geosph_core::{Domain, Real, Vector};
use rayon::prelude::*;

use crate::error::SearchError;
use crate::hashed::HashedCells;
use crate::scratch::QueryScratch;

/// Relative amount by which a cell edge exceeds the search radius.
///
/// With an edge of exactly the radius, rounding in `(x − min)/edge` could put two particles
/// exactly one radius apart two cells apart. An edge of at least `radius·(1 + CELL_MARGIN)`
/// leaves room for rounding errors of up to `CELL_MARGIN` cell widths, i.e. coordinates up to
/// about 10⁹ cells from the origin.
pub const CELL_MARGIN: Real = 1e-6;

/// Largest number of cells in a dense grid ([`CellGrid::new`]): cell indices are stored as
/// `u32`. A hashed grid ([`CellGrid::hashed`]) has no such limit.
pub const MAX_CELLS: usize = u32::MAX as usize;

/// Largest number of particles in a built set: particle indices are stored as `u32`.
pub const MAX_PARTICLES: usize = u32::MAX as usize - 1;

/// Below this many particles the counting sort runs on one thread.
const PARALLEL_SORT_THRESHOLD: usize = 1 << 15;

/// At most this many cell ranges are sorted in parallel; each of them reads all `cell_of`.
const MAX_SORT_PARTS: usize = 8;

/// Particles per rayon task when computing cells.
const CELL_CHUNK: usize = 4096;

/// Marks a particle outside the domain in `cell_of` during a build.
const INVALID_CELL: u32 = u32::MAX;

/// How a [`CellGrid`] indexes its cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CellIndex {
    /// One offset per cell of the domain ([`CellGrid::new`]): the fastest for particles that
    /// fill their domain.
    #[default]
    Dense,
    /// The occupied cells only, in a hash table ([`CellGrid::hashed`]): for unbounded or very
    /// sparse domains.
    Hashed,
}

/// The geometry of the grid: how a position maps to a cell. Small and `Copy`, so parallel
/// closures can use it while the grid's buffers are borrowed mutably.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellMap<const D: usize> {
    /// Lower corner of the domain.
    pub(crate) min: Vector<D>,
    /// Upper corner of the domain.
    pub(crate) max: Vector<D>,
    /// Periodic axes.
    pub(crate) periodic: [bool; D],
    /// Cells per axis.
    pub(crate) counts: [usize; D],
    /// `1 / cell edge` per axis.
    pub(crate) inv_size: Vector<D>,
    /// Linear-index stride of each axis (x fastest).
    pub(crate) strides: [usize; D],
    /// Whether a finite position outside the domain on a closed axis goes to the edge cell
    /// along it ([`CellGrid::bin_outside_in_edge_cells`]) instead of failing the build.
    pub(crate) edge_cells: bool,
}

impl<const D: usize> CellMap<D> {
    /// Integer cell coordinates of a particle of the built set, or `None` if it lies outside
    /// `[min, max)` on some axis (or a coordinate is NaN); with `edge_cells`, a finite
    /// coordinate outside a closed axis is in the edge cell along it.
    #[inline]
    pub(crate) fn cell_coords(&self, x: &Vector<D>) -> Option<[usize; D]> {
        let mut c = [0usize; D];
        for k in 0..D {
            if !(x[k] >= self.min[k] && x[k] < self.max[k]) {
                if !(self.edge_cells && !self.periodic[k] && x[k].is_finite()) {
                    return None;
                }
                c[k] = if x[k] < self.min[k] {
                    0
                } else {
                    self.counts[k] - 1
                };
                continue;
            }
            // u ≥ 0, so truncation is floor; clamp in case rounding reaches the upper face.
            let u = (x[k] - self.min[k]) * self.inv_size[k];
            c[k] = (u as usize).min(self.counts[k] - 1);
        }
        Some(c)
    }

    /// Linear index of the cell with coordinates `c` (x fastest).
    #[inline]
    pub(crate) fn linear(&self, c: &[usize; D]) -> usize {
        (0..D).map(|k| c[k] * self.strides[k]).sum()
    }
}

/// A uniform grid of cells, each at least one search radius wide, for fixed-radius
/// neighbour search.
///
/// [`CellGrid::build`] sorts a particle set into the cells with a counting sort: afterwards
/// the particles of cell `c` are `particle_index()[cell_start()[c]..cell_start()[c + 1]]`, in
/// ascending index order. A query then scans the 3^D cells around a point
/// ([`CellGrid::neighbour_list`], [`CellGrid::for_each_neighbour`]).
///
/// Axes: on a periodic axis of length `L` the grid has `n = ⌊L / (radius·(1 + 10⁻⁶))⌋` cells
/// that tile the period exactly, and the displacement is the minimum image; periods shorter
/// than `2·radius` are refused ([`SearchError::PeriodTooShort`]). On other axes the cells
/// cover `[min, max)` (a single cell one radius wide when the axis is shorter than that).
/// The margin of 10⁻⁶ keeps rounding from losing pairs exactly one radius apart.
///
/// All buffers are kept between builds, so rebuilding for a moved particle set of the same
/// size does not allocate.
///
/// The cells' index is dense ([`CellGrid::new`]: one offset per cell of the domain) or
/// hashed ([`CellGrid::hashed`]: the occupied cells only, for unbounded or sparse domains;
/// `hashed.rs`). Both give the same lists, bitwise.
#[derive(Clone, Debug)]
pub struct CellGrid<const D: usize> {
    pub(crate) domain: Domain<D>,
    pub(crate) radius: Real,
    pub(crate) map: CellMap<D>,
    /// `cell_start[c]..cell_start[c + 1]` is the range of cell `c` in `particle_index`.
    pub(crate) cell_start: Vec<u32>,
    /// Particle indices sorted by cell, ascending within a cell.
    pub(crate) particle_index: Vec<u32>,
    /// Linear cell index of each particle of the built set (hashed: its occupied cell's
    /// rank).
    pub(crate) cell_of: Vec<u32>,
    /// The hashed index of the occupied cells (`None`: dense, `cell_start`), with the
    /// particles' linear cells of a build.
    hashed: Option<(HashedCells, Vec<u64>)>,
    /// Scratch: next free slot of each cell during the scatter of the counting sort.
    cursor: Vec<u32>,
    /// Scratch of the queries.
    pub(crate) scratch: QueryScratch,
}

impl<const D: usize> CellGrid<D> {
    /// An empty grid over `domain` for the search radius `radius` (call [`CellGrid::build`]
    /// before querying; until then it holds no particles).
    pub fn new(domain: Domain<D>, radius: Real) -> Result<Self, SearchError> {
        Self::with_index(domain, radius, CellIndex::Dense)
    }

    /// An empty grid like [`CellGrid::new`] whose index holds the occupied cells only, in a
    /// hash table (Ihmsen et al. 2011's compact hashing; `hashed.rs`): for unbounded or very
    /// sparse domains, where a dense index of every cell would cost more than the particles.
    /// The cells may number up to 2⁶⁴ (2²¹ per axis in 3D, the Morton codes' limit); the
    /// neighbour lists are those of the dense grid, bitwise.
    pub fn hashed(domain: Domain<D>, radius: Real) -> Result<Self, SearchError> {
        Self::with_index(domain, radius, CellIndex::Hashed)
    }

    /// An empty grid with a dense index ([`CellGrid::new`]), or a hashed one
    /// ([`CellGrid::hashed`]) when the domain has more cells than a dense index holds.
    pub fn fitting(domain: Domain<D>, radius: Real) -> Result<Self, SearchError> {
        match Self::new(domain.clone(), radius) {
            Err(SearchError::TooManyCells { .. }) => Self::hashed(domain, radius),
            grid => grid,
        }
    }

    /// An empty grid with the cell index `index`: [`CellGrid::new`] or [`CellGrid::hashed`].
    pub fn with_index(
        domain: Domain<D>,
        radius: Real,
        index: CellIndex,
    ) -> Result<Self, SearchError> {
        let hashed = index == CellIndex::Hashed;
        const { assert!(D >= 1 && D <= 3, "CellGrid supports 1, 2 and 3 dimensions") };
        if !(radius.is_finite() && radius > 0.0) {
            return Err(SearchError::InvalidRadius { radius });
        }
        let min_edge = radius * (1.0 + CELL_MARGIN);
        let mut counts = [1usize; D];
        let mut inv_size = Vector::<D>::zeros();
        for k in 0..D {
            let length = domain.max[k] - domain.min[k];
            if domain.periodic[k] && length < 2.0 * radius {
                return Err(SearchError::PeriodTooShort {
                    axis: k,
                    length,
                    radius,
                });
            }
            // `as usize` saturates, so a huge ratio is caught by the limits below.
            let n = (length / min_edge).floor() as usize;
            if n >= 1 {
                counts[k] = n;
                inv_size[k] = n as Real / length;
            } else {
                // Non-periodic axis shorter than one edge: one cell, still one radius wide.
                counts[k] = 1;
                inv_size[k] = 1.0 / min_edge;
            }
        }
        // Morton codes take u32 coordinates of 64/D bits, and no cell may have the code
        // u64::MAX that marks a particle outside (in 2D the last cell of 2^32 per axis would).
        let morton_limit: usize = match D {
            1 => 1 << 32,
            2 => (1 << 32) - 1,
            _ => 1 << 21,
        };
        let limit = if hashed { usize::MAX } else { MAX_CELLS };
        let total = counts
            .iter()
            .try_fold(1usize, |acc, &n| acc.checked_mul(n))
            .filter(|&t| t <= limit);
        let Some(total) = total.filter(|_| counts.iter().all(|&n| n <= morton_limit)) else {
            return Err(SearchError::TooManyCells {
                cells_per_axis: counts.to_vec(),
                limit,
            });
        };
        let mut strides = [1usize; D];
        for k in 1..D {
            strides[k] = strides[k - 1] * counts[k - 1];
        }
        let map = CellMap {
            min: domain.min,
            max: domain.max,
            periodic: domain.periodic,
            counts,
            inv_size,
            strides,
            edge_cells: false,
        };
        Ok(Self {
            domain,
            radius,
            map,
            cell_start: vec![0; if hashed { 1 } else { total + 1 }],
            particle_index: Vec::new(),
            cell_of: Vec::new(),
            hashed: hashed.then(Default::default),
            cursor: Vec::new(),
            scratch: QueryScratch::default(),
        })
    }

    /// From now on a particle outside the domain on a closed axis (with finite coordinates)
    /// is binned in the edge cell along that axis instead of failing [`CellGrid::build`], and
    /// a query from outside scans the edge cells. Every pair within the radius is still
    /// found: along an axis the cell coordinate clamped to [0, n − 1] moves two coordinates
    /// no farther apart, so two points less than a cell width apart stay in the same or
    /// adjacent cells. For the pair lists of a run that removes a particle that left the domain
    /// after the step in which it left (`geosph-sph`'s `PairLists`).
    pub fn bin_outside_in_edge_cells(&mut self) {
        self.map.edge_cells = true;
    }

    /// Sorts the particles at `position` into the cells (counting sort), replacing any set
    /// built before.
    ///
    /// Runs in parallel for large sets; the result does not depend on the number of threads.
    /// Every particle must lie in the half-open domain `[min, max)` on every axis (wrap periodic
    /// axes with [`Domain::wrap`] first; after [`CellGrid::bin_outside_in_edge_cells`] a finite
    /// position outside a closed axis is binned too); otherwise the grid is left empty and the
    /// error names the first such particle.
    pub fn build(&mut self, position: &[Vector<D>]) -> Result<(), SearchError> {
        let n = position.len();
        if n > MAX_PARTICLES {
            return Err(SearchError::TooManyParticles {
                count: n,
                limit: MAX_PARTICLES,
            });
        }
        let map = self.map;
        if let Some((cells, cell_key)) = &mut self.hashed {
            cell_key.resize(n, 0);
            let outside = cell_key
                .par_iter_mut()
                .zip(position.par_iter())
                .enumerate()
                .filter_map(|(i, (key, x))| match map.cell_coords(x) {
                    Some(c) => {
                        *key = map.linear(&c) as u64;
                        None
                    }
                    None => Some(i),
                })
                .min();
            if let Some(index) = outside {
                self.clear();
                return Err(self.outside(index, position));
            }
            cells.build(cell_key, &mut self.particle_index, &mut self.cell_of);
            return Ok(());
        }
        self.cell_of.resize(n, 0);
        let any_outside = self
            .cell_of
            .par_chunks_mut(CELL_CHUNK)
            .zip(position.par_chunks(CELL_CHUNK))
            .map(|(cells, xs)| {
                let mut outside = false;
                for (cell, x) in cells.iter_mut().zip(xs) {
                    *cell = match map.cell_coords(x) {
                        Some(c) => map.linear(&c) as u32,
                        None => {
                            outside = true;
                            INVALID_CELL
                        }
                    };
                }
                outside
            })
            .reduce(|| false, |a, b| a || b);
        if any_outside {
            let index = self
                .cell_of
                .iter()
                .position(|&c| c == INVALID_CELL)
                .expect("a particle was flagged outside");
            self.clear();
            return Err(self.outside(index, position));
        }

        let cells = self.cell_start.len() - 1;
        let parts = if n < PARALLEL_SORT_THRESHOLD || cells < 2 {
            1
        } else {
            rayon::current_num_threads().clamp(1, MAX_SORT_PARTS)
        };

        // Count the particles of each cell into cell_start[c + 1].
        self.cell_start[0] = 0;
        count_cells(&self.cell_of, 0..cells, &mut self.cell_start[1..], parts);
        // Exclusive prefix sum: cell_start[c] = particles in cells before c.
        let mut sum = 0u32;
        for s in self.cell_start.iter_mut() {
            sum += *s;
            *s = sum;
        }

        // Scatter particle indices into their cells, ascending within a cell.
        self.particle_index.resize(n, 0);
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.cell_start[..cells]);
        scatter_cells(
            &self.cell_of,
            &self.cell_start,
            0..cells,
            &mut self.particle_index,
            &mut self.cursor,
            parts,
        );
        Ok(())
    }

    /// The error of particle `index`, outside the domain.
    fn outside(&self, index: usize, position: &[Vector<D>]) -> SearchError {
        SearchError::OutsideDomain {
            index,
            position: position[index].iter().copied().collect(),
            min: self.domain.min.iter().copied().collect(),
            max: self.domain.max.iter().copied().collect(),
        }
    }

    /// Empties the grid: no particles, buffers kept.
    fn clear(&mut self) {
        self.cell_of.clear();
        self.particle_index.clear();
        self.cell_start.fill(0);
        if let Some((cells, _)) = &mut self.hashed {
            cells.clear();
        }
    }

    /// The range in [`CellGrid::particle_index`] of the particles in the consecutive linear
    /// cells `lo..=hi`.
    #[inline]
    pub(crate) fn cells_range(&self, lo: usize, hi: usize) -> (usize, usize) {
        match &self.hashed {
            None => (
                self.cell_start[lo] as usize,
                self.cell_start[hi + 1] as usize,
            ),
            Some((cells, _)) => cells.range(lo, hi),
        }
    }

    /// How the grid indexes its cells.
    pub fn index(&self) -> CellIndex {
        match self.hashed {
            Some(_) => CellIndex::Hashed,
            None => CellIndex::Dense,
        }
    }

    /// Cells that hold particles in a hashed grid (`None` for a dense one).
    pub fn occupied_cells(&self) -> Option<usize> {
        self.hashed.as_ref().map(|(cells, _)| cells.occupied())
    }

    /// The search radius.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The domain the grid covers.
    pub fn domain(&self) -> &Domain<D> {
        &self.domain
    }

    /// Total number of cells (occupied or not).
    pub fn cell_count(&self) -> usize {
        self.map.counts.iter().product()
    }

    /// Number of cells along each axis.
    pub fn cells_per_axis(&self) -> [usize; D] {
        self.map.counts
    }

    /// Edge length of a cell along each axis (at least the search radius).
    pub fn cell_size(&self) -> Vector<D> {
        self.map.inv_size.map(|inv| 1.0 / inv)
    }

    /// Number of particles in the built set.
    pub fn particle_count(&self) -> usize {
        self.cell_of.len()
    }

    /// Offsets into [`CellGrid::particle_index`]: cell `c` holds
    /// `particle_index()[cell_start()[c]..cell_start()[c + 1]]`; `cell_count() + 1` entries
    /// in a dense grid, one (0) in a hashed grid ([`CellGrid::cell_particles`] serves both).
    pub fn cell_start(&self) -> &[u32] {
        &self.cell_start
    }

    /// Indices of the built particles sorted by cell, ascending within each cell.
    pub fn particle_index(&self) -> &[u32] {
        &self.particle_index
    }

    /// Linear cell index (x fastest) of each built particle; in a hashed grid the rank of its
    /// cell among the occupied ones, in ascending linear order.
    pub fn cell_of(&self) -> &[u32] {
        &self.cell_of
    }

    /// The built particles in cell `cell` (linear index), in ascending order.
    pub fn cell_particles(&self, cell: usize) -> &[u32] {
        let (start, end) = self.cells_range(cell, cell);
        &self.particle_index[start..end]
    }
}

/// Counts into `counts[c − cells.start]` the particles whose cell lies in `cells`, splitting
/// the cell range into `parts` pieces counted in parallel (each reads all of `cell_of`).
fn count_cells(cell_of: &[u32], cells: Range<usize>, counts: &mut [u32], parts: usize) {
    if parts <= 1 || cells.len() < 2 {
        counts.fill(0);
        let (lo, hi) = (cells.start as u32, cells.end as u32);
        for &c in cell_of {
            if (lo..hi).contains(&c) {
                counts[(c - lo) as usize] += 1;
            }
        }
        return;
    }
    let left_parts = parts / 2;
    let mid = cells.start + cells.len() * left_parts / parts;
    let (left, right) = counts.split_at_mut(mid - cells.start);
    rayon::join(
        || count_cells(cell_of, cells.start..mid, left, left_parts),
        || count_cells(cell_of, mid..cells.end, right, parts - left_parts),
    );
}

/// Writes each particle whose cell lies in `cells` to `out[cursor[c] − cell_start[cells.start]]`
/// and advances the cursor, visiting particles in ascending order. The cell range is split
/// into `parts` pieces holding about equal numbers of particles, scattered in parallel into
/// disjoint parts of `out`.
fn scatter_cells(
    cell_of: &[u32],
    cell_start: &[u32],
    cells: Range<usize>,
    out: &mut [u32],
    cursor: &mut [u32],
    parts: usize,
) {
    let base = cell_start[cells.start];
    if parts <= 1 || cells.len() < 2 {
        let (lo, hi) = (cells.start as u32, cells.end as u32);
        if lo == 0 && hi as usize == cell_start.len() - 1 {
            // Whole grid: no range test needed.
            for (i, &c) in cell_of.iter().enumerate() {
                let slot = &mut cursor[c as usize];
                out[(*slot - base) as usize] = i as u32;
                *slot += 1;
            }
        } else {
            for (i, &c) in cell_of.iter().enumerate() {
                if (lo..hi).contains(&c) {
                    let slot = &mut cursor[(c - lo) as usize];
                    out[(*slot - base) as usize] = i as u32;
                    *slot += 1;
                }
            }
        }
        return;
    }
    let left_parts = parts / 2;
    let end = cell_start[cells.end];
    let target = base + ((end - base) as u64 * left_parts as u64 / parts as u64) as u32;
    // First cell whose start reaches the target, kept strictly inside the range.
    let mid = cells.start + cell_start[cells.clone()].partition_point(|&s| s < target);
    let mid = mid.clamp(cells.start + 1, cells.end - 1);
    let split = (cell_start[mid] - base) as usize;
    let (out_left, out_right) = out.split_at_mut(split);
    let (cursor_left, cursor_right) = cursor.split_at_mut(mid - cells.start);
    rayon::join(
        || {
            scatter_cells(
                cell_of,
                cell_start,
                cells.start..mid,
                out_left,
                cursor_left,
                left_parts,
            )
        },
        || {
            scatter_cells(
                cell_of,
                cell_start,
                mid..cells.end,
                out_right,
                cursor_right,
                parts - left_parts,
            )
        },
    );
}
