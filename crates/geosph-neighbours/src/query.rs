//! Fixed-radius queries on a built [`CellGrid`]: CSR neighbour lists and closure access.

use geosph_core::{NeighbourList, Real, Vector};
use rayon::prelude::*;

use crate::grid::{CELL_MARGIN, CellGrid};
use crate::scratch::ChunkBuffer;

/// Queries per rayon task in [`CellGrid::neighbour_list`].
const QUERY_CHUNK: usize = 1024;

/// Chunks per thread in one wave of [`CellGrid::neighbour_list`] (balances the load before
/// the wave's buffers are appended to the list).
const CHUNKS_PER_THREAD: usize = 4;

/// Most rows (cell runs along axes 1..D) a query scans: 3^(D−1) for D ≤ 3.
const MAX_ROWS: usize = 9;

/// Whether the queries in `D` dimensions leave out the cells around a query that lie beyond
/// the radius. In 3D these are about a quarter of the 27 cells and of the candidates: the
/// lists of 10⁶ particles build in 0.39 s instead of 0.52–0.53 s (`docs/performance.md`). In
/// 2D only a tenth of the candidates go and the test costs more than it saves (0.089–0.099 s
/// instead of 0.077–0.087 s for 10⁶).
const fn culls_cells(dimension: usize) -> bool {
    dimension >= 3
}

impl<const D: usize> CellGrid<D> {
    /// Calls `f(run, image)` with each run of built-particle indices (one run per contiguous
    /// range of cells) in the cells that can hold neighbours of `x`: in 3D, of the 27 cells
    /// around `x`, those whose nearest point is farther than the radius (less `CELL_MARGIN`
    /// cells for rounding) are left out ([`culls_cells`]; rows of cells along axes 1 and 2
    /// whole, along axis 0 the end cells of a run). Runs are ascending and
    /// come in ascending cell order except across a periodic wrap. `image` is false when the
    /// plain difference `x − x_j` is bitwise the minimum image [`Domain::displacement`] for
    /// every candidate (no periodic axis within two cells of a face or with fewer than five
    /// cells), so callers may skip the rounding. A non-finite `x` has no candidates.
    ///
    /// [`Domain::displacement`]: geosph_core::Domain::displacement
    #[inline]
    fn for_each_candidate_run(&self, x: &Vector<D>, mut f: impl FnMut(&[u32], bool)) {
        let map = &self.map;
        let radius2 = self.radius * self.radius;
        // Axis 0 (contiguous in memory): at most two ranges [a, b] of cells.
        let mut x_ranges = [(0usize, 0usize); 2];
        let mut x_range_count = 0;
        // Axes 1..D: at most three cells each, combined into ascending row offsets.
        let mut rows = [0usize; MAX_ROWS];
        let mut row_count = 1;
        // The squared distance from `x` to each row, and along axis 0 to each cell of a
        // single range (a wrap makes two: those are not trimmed).
        let mut row_gap2 = [0.0; MAX_ROWS];
        let mut x_gap2 = [0.0; 3];
        let mut image = false;
        for k in 0..D {
            let u = (x[k] - map.min[k]) * map.inv_size[k];
            if !u.is_finite() {
                return;
            }
            let n = map.counts[k];
            let mut cells = [0usize; 3];
            let mut gap2 = [0.0; 3];
            let mut cell_count = 0;
            // The distance from x to a cell `offset` cells away along the axis, in metres
            // squared, less the margin.
            let size = 1.0 / map.inv_size[k];
            let fraction = u - u.floor();
            let gap = |offset: isize| {
                let cells = match offset {
                    ..0 => fraction - (offset + 1) as Real,
                    0 => 0.0,
                    _ => (offset - 1) as Real + 1.0 - fraction,
                };
                let metres = (cells - CELL_MARGIN).max(0.0) * size;
                metres * metres
            };
            if map.periodic[k] {
                let floor = u.floor();
                // Away from the faces (and with n ≥ 5) every candidate is within 2 cells,
                // under L/2, where the minimum image is the plain difference.
                image |= n < 5 || floor < 1.0 || floor > (n - 2) as Real;
                if n < 3 {
                    for c in 0..n {
                        cells[c] = c;
                    }
                    cell_count = n;
                } else {
                    let c = (floor.rem_euclid(n as Real) as usize).min(n - 1);
                    cells = [(c + n - 1) % n, c, (c + 1) % n];
                    if culls_cells(D) {
                        gap2 = [gap(-1), 0.0, gap(1)];
                    }
                    cell_count = 3;
                }
            } else {
                // Clamp before converting: far-away queries only need to miss the grid,
                // unless particles outside it are in its edge cells.
                let (first, last) = match map.edge_cells {
                    true => (0.0, (n - 1) as Real),
                    false => (-2.0, n as Real + 1.0),
                };
                let c = u.floor().clamp(first, last) as isize;
                let lo = (c - 1).max(0);
                let hi = (c + 1).min(n as isize - 1);
                if lo > hi {
                    return;
                }
                // A query outside the grid (clamped) keeps every cell: it is rare.
                let inside = culls_cells(D) && (0.0..n as Real).contains(&u);
                for cell in lo..=hi {
                    cells[cell_count] = cell as usize;
                    gap2[cell_count] = if inside { gap(cell - c) } else { 0.0 };
                    cell_count += 1;
                }
            }
            if k == 0 {
                // Merge into contiguous ranges: cells are ascending except across a wrap.
                let cells = &cells[..cell_count];
                let mut start = cells[0];
                let mut prev = cells[0];
                for &c in &cells[1..] {
                    if c != prev + 1 {
                        x_ranges[x_range_count] = (start, prev);
                        x_range_count += 1;
                        start = c;
                    }
                    prev = c;
                }
                x_ranges[x_range_count] = (start, prev);
                x_range_count += 1;
                if x_range_count == 2 && x_ranges[1].0 < x_ranges[0].0 {
                    x_ranges.swap(0, 1);
                }
                if culls_cells(D) && x_range_count == 1 {
                    x_gap2 = gap2;
                }
            } else {
                // The new axis varies slowest, so rows stay in ascending memory order.
                let stride = map.strides[k];
                let mut new = [0usize; MAX_ROWS];
                let mut new_gap2 = [0.0; MAX_ROWS];
                let mut m = 0;
                for (&c, &g2) in cells[..cell_count].iter().zip(&gap2) {
                    for (&row, &row_g2) in rows[..row_count].iter().zip(&row_gap2) {
                        new[m] = row + c * stride;
                        new_gap2[m] = row_g2 + g2;
                        m += usize::from(!culls_cells(D) || row_g2 + g2 <= radius2);
                    }
                }
                (rows, row_gap2) = (new, new_gap2);
                row_count = m;
            }
        }
        for (&row, &row_g2) in rows[..row_count].iter().zip(&row_gap2) {
            for &(mut a, mut b) in &x_ranges[..x_range_count] {
                if culls_cells(D) && x_range_count == 1 {
                    // Trim the end cells out of reach (the cell of x, at gap 0, stays).
                    let last = b - a;
                    a += usize::from(row_g2 + x_gap2[0] > radius2);
                    b -= usize::from(last > 0 && row_g2 + x_gap2[last] > radius2);
                }
                let (start, end) = self.cells_range(row + a, row + b);
                if start < end {
                    f(&self.particle_index[start..end], image);
                }
            }
        }
    }

    /// Calls `g(j, d)` for each built particle `j` with `d = x − x_j` (minimum image) and
    /// `d·d ≤ radius²`, in the order of [`CellGrid::for_each_candidate_run`].
    #[inline(always)]
    fn visit_neighbours(
        &self,
        position: &[Vector<D>],
        x: &Vector<D>,
        mut g: impl FnMut(u32, Vector<D>, Real),
    ) {
        let r2 = self.radius * self.radius;
        self.for_each_candidate_run(x, |run, image| {
            if image {
                for &j in run {
                    let d = self.domain.displacement(x, &position[j as usize]);
                    let d2 = d.norm_squared();
                    if d2 <= r2 {
                        g(j, d, d2);
                    }
                }
            } else {
                for &j in run {
                    let d = x - position[j as usize];
                    let d2 = d.norm_squared();
                    if d2 <= r2 {
                        g(j, d, d2);
                    }
                }
            }
        });
    }

    /// Appends to `buffer` the built particles within the search radius of `x`, in the order
    /// of [`CellGrid::for_each_candidate_run`]. Same test as [`CellGrid::visit_neighbours`],
    /// written without a branch per candidate: each candidate is stored, and the end advances
    /// only past those inside (about a third in 2D, a sixth in 3D, so a branch would often be
    /// mispredicted).
    #[inline(always)]
    fn push_neighbours(&self, position: &[Vector<D>], x: &Vector<D>, buffer: &mut ChunkBuffer) {
        let r2 = self.radius * self.radius;
        self.for_each_candidate_run(x, |run, image| {
            let base = buffer.len;
            let end = base + run.len();
            if buffer.slots.len() < end {
                let grown = end.max(2 * buffer.slots.len());
                buffer.slots.resize(grown, 0);
            }
            let out = &mut buffer.slots[base..end];
            let mut m = 0;
            if image {
                for &j in run {
                    let d = self.domain.displacement(x, &position[j as usize]);
                    out[m] = j;
                    m += (d.norm_squared() <= r2) as usize;
                }
            } else {
                for &j in run {
                    let d = x - position[j as usize];
                    out[m] = j;
                    m += (d.norm_squared() <= r2) as usize;
                }
            }
            buffer.len = base + m;
        });
    }

    /// Calls `f(j, x − x_j, r)` for every built particle `j` within the search radius of the
    /// point `x`: `d = domain.displacement(x, x_j)` (minimum image on periodic axes) with
    /// `d·d ≤ radius²` (inclusive), `r = |d|`.
    ///
    /// `position` must be the slice given to the last [`CellGrid::build`]. Neighbours come
    /// cell by cell, in the order of [`CellGrid::neighbour_list`]. A non-finite `x` has no
    /// neighbours.
    ///
    /// # Panics
    /// If `position.len()` differs from the number of built particles.
    #[inline]
    pub fn for_each_neighbour(
        &self,
        position: &[Vector<D>],
        x: &Vector<D>,
        mut f: impl FnMut(u32, Vector<D>, Real),
    ) {
        self.check_built_set(position);
        self.visit_neighbours(position, x, |j, d, d2| f(j, d, d2.sqrt()));
    }

    /// Fills `list` with, for each point of `queries`, the built particles `j` within the
    /// search radius: `d = domain.displacement(x_q, x_j)` (minimum image on periodic axes)
    /// with `d·d ≤ radius²` (inclusive), in cell order: the cells around `x_q` by ascending
    /// linear index (rows along axis 0), each cell's particles by ascending index.
    ///
    /// `position` must be the slice given to the last [`CellGrid::build`]. Querying the built
    /// set itself (`queries = position`) lists every particle as its own neighbour; any other
    /// point set (e.g. fluid particles against a grid of wall particles) works the same way,
    /// including points outside the domain (a non-finite point has no neighbours). `list`'s
    /// buffers are reused, so repeated calls of similar size do not allocate.
    ///
    /// Queries run in parallel in fixed chunks, a wave of chunks at a time; each chunk writes
    /// its queries' runs to its own scratch buffer, and the buffers are appended to the list
    /// in query order. Every run depends only on its query and the built positions, so the
    /// list is bitwise identical for any number of threads. The runs are not sorted by index:
    /// the order is as fixed, and sorting them cost a third of the query time (a 2D dam break
    /// of 9 000 particles, `docs/performance.md`). Queries run in index order: sort the
    /// particles along a space-filling curve ([`CellGrid::z_order`]) now and then to keep
    /// memory access local.
    ///
    /// # Panics
    /// If `position.len()` differs from the number of built particles, or if the list would
    /// hold more than `u32::MAX` pairs.
    pub fn neighbour_list(
        &self,
        position: &[Vector<D>],
        queries: &[Vector<D>],
        list: &mut NeighbourList,
    ) {
        self.check_built_set(position);
        let n = queries.len();
        list.offsets.resize(n + 1, 0);
        list.offsets[0] = 0;
        list.indices.clear();
        let mut buffers = self.scratch.take();
        let wave_chunks = rayon::current_num_threads().max(1) * CHUNKS_PER_THREAD;
        if buffers.len() < wave_chunks {
            buffers.resize_with(wave_chunks, ChunkBuffer::default);
        }
        // Equal chunks of at most QUERY_CHUNK queries, a whole number of them per wave: a last
        // wave of one short chunk would run on one thread while the others wait.
        let waves = n.div_ceil(wave_chunks * QUERY_CHUNK).max(1);
        let chunk = n.div_ceil(waves * wave_chunks).max(1);
        let mut total = 0u64;
        for wave_start in (0..n).step_by(wave_chunks * chunk) {
            let wave_end = n.min(wave_start + wave_chunks * chunk);
            let wave_queries = &queries[wave_start..wave_end];
            let counts = &mut list.offsets[wave_start + 1..wave_end + 1];
            counts
                .par_chunks_mut(chunk)
                .zip(wave_queries.par_chunks(chunk))
                .zip(buffers.par_iter_mut())
                .for_each(|((counts, queries), buffer)| {
                    buffer.len = 0;
                    for (count, x) in counts.iter_mut().zip(queries) {
                        let start = buffer.len;
                        self.push_neighbours(position, x, buffer);
                        *count = (buffer.len - start) as u32;
                    }
                });
            let used = wave_queries.len().div_ceil(chunk);
            let wave_pairs: usize = buffers[..used].iter().map(|b| b.len).sum();
            reserve_extrapolated(&mut list.indices, wave_pairs, wave_end, n);
            for buffer in &buffers[..used] {
                list.indices.extend_from_slice(buffer.filled());
            }
            for offset in counts.iter_mut() {
                total += *offset as u64;
                *offset = u32::try_from(total).unwrap_or_else(|_| {
                    panic!("neighbour list of {n} queries exceeds u32::MAX pairs")
                });
            }
        }
        self.scratch.put_back(buffers);
    }

    /// Panics unless `position` has one entry per built particle.
    #[inline]
    fn check_built_set(&self, position: &[Vector<D>]) {
        assert_eq!(
            position.len(),
            self.particle_count(),
            "positions of {} particles given to a cell grid built for {}",
            position.len(),
            self.particle_count()
        );
    }
}

/// Makes room in `indices` for `more` pairs, having listed `done` of `total` queries once they
/// are appended. If it must grow, it grows to the pairs per query so far times `total`, plus
/// an eighth: a list's capacity ends close to its length instead of up to twice it (a `Vec`
/// doubling), and later builds of similar size reuse it without allocating.
fn reserve_extrapolated(indices: &mut Vec<u32>, more: usize, done: usize, total: usize) {
    let needed = indices.len() + more;
    if needed <= indices.capacity() {
        return;
    }
    let per_query = needed as f64 / done.max(1) as f64;
    let estimate = (per_query * total as f64 * 1.125).ceil() as usize;
    indices.reserve_exact(estimate.max(needed) - indices.len());
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Domain;

    /// A lattice of 40 000 points (about 26 neighbours each, the 2D dam break's count with its
    /// skin) is listed in several waves: the list's capacity ends within the eighth of
    /// headroom that `reserve_extrapolated` adds (plus the boundary rows' shortfall), not up to
    /// twice its length (1.51× with a `Vec`'s doubling here), and a second build of the same
    /// points does not grow it.
    #[test]
    fn list_capacity_stays_near_its_length() {
        let dx = 0.01;
        let side = 200;
        let domain = Domain::new(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(2.0, 2.0)).unwrap();
        let mut grid = CellGrid::new(domain, 2.86 * dx).unwrap();
        let position: Vec<Vector<2>> = (0..side * side)
            .map(|k| Vector::<2>::new((k % side) as f64 + 0.5, (k / side) as f64 + 0.5) * dx)
            .collect();
        grid.build(&position).unwrap();
        let mut list = NeighbourList::new();
        grid.neighbour_list(&position, &position, &mut list);
        let (pairs, capacity) = (list.pair_count(), list.indices.capacity());
        assert!(pairs > 20 * position.len(), "{pairs} pairs");
        assert!(
            capacity as f64 <= 1.25 * pairs as f64,
            "{capacity} for {pairs} pairs"
        );
        grid.neighbour_list(&position, &position, &mut list);
        assert_eq!(list.indices.capacity(), capacity);
    }
}
