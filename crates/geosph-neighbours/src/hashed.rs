//! The hashed cell index of a [`CellGrid`]: storage for the occupied cells only, for
//! unbounded or very sparse domains.
//!
//! A dense grid keeps one offset per cell of the domain, so a spray of 10⁴ drops in a valley
//! 10 km wide costs the memory and the build time of every empty cell. The hashed index
//! keeps what the compact hashing of Ihmsen et al. (2011, Comput. Graph. Forum 30:99) keeps:
//! the particles sorted by cell, one entry per occupied cell (its linear index and where its
//! particles start) and a hash table from a cell's linear index to its entry (the spatial
//! hashing of Teschner et al. 2003, here with the integer cell index as the key, so two cells
//! never share a slot). Memory and build time grow with the particles, not the domain.
//!
//! The sort is by (cell, particle index), as the dense grid's counting sort orders them, and
//! a query visits the same cells in the same order, so both indexes give the same neighbour
//! lists, bitwise, for any number of threads.

use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// The occupied cells of a built particle set and the hash table that finds them.
#[derive(Clone, Debug, Default)]
pub(crate) struct HashedCells {
    /// (linear cell index, particle index) of each built particle, sorted (scratch).
    keyed: Vec<(u64, u32)>,
    /// Linear index of each occupied cell, ascending.
    cells: Vec<u64>,
    /// `start[k]..start[k + 1]` is occupied cell k's range in the particle order; one more
    /// entry than `cells`.
    start: Vec<u32>,
    /// Linear cell index → its rank in `cells`.
    table: FxHashMap<u64, u32>,
}

impl HashedCells {
    /// Sorts the particles of linear cells `cell_of` (one per particle) and fills
    /// `particle_index` with them in (cell, index) order; `rank_of` gets each particle's
    /// occupied-cell rank. Buffers are kept between builds.
    pub(crate) fn build(
        &mut self,
        cell_of: &[u64],
        particle_index: &mut Vec<u32>,
        rank_of: &mut Vec<u32>,
    ) {
        self.keyed.clear();
        self.keyed
            .par_extend(cell_of.par_iter().enumerate().map(|(i, &c)| (c, i as u32)));
        self.keyed.par_sort_unstable();
        particle_index.clear();
        particle_index.par_extend(self.keyed.par_iter().map(|&(_, i)| i));
        self.cells.clear();
        self.start.clear();
        self.table.clear();
        rank_of.resize(cell_of.len(), 0);
        for (slot, &(cell, i)) in self.keyed.iter().enumerate() {
            if self.cells.last() != Some(&cell) {
                self.table.insert(cell, self.cells.len() as u32);
                self.cells.push(cell);
                self.start.push(slot as u32);
            }
            rank_of[i as usize] = self.cells.len() as u32 - 1;
        }
        self.start.push(self.keyed.len() as u32);
    }

    /// The range in the particle order of the particles in the linear cells `lo..=hi`
    /// (consecutive cells, so their particles are consecutive too); empty when none is
    /// occupied.
    #[inline]
    pub(crate) fn range(&self, lo: usize, hi: usize) -> (usize, usize) {
        let first = (lo..=hi).find_map(|c| self.table.get(&(c as u64)));
        let Some(&first) = first else {
            return (0, 0);
        };
        let last = (lo..=hi)
            .rev()
            .find_map(|c| self.table.get(&(c as u64)))
            .copied()
            .unwrap_or(first);
        (
            self.start[first as usize] as usize,
            self.start[last as usize + 1] as usize,
        )
    }

    /// How many cells hold particles.
    pub(crate) fn occupied(&self) -> usize {
        self.cells.len()
    }

    /// Empties the index, buffers kept.
    pub(crate) fn clear(&mut self) {
        self.keyed.clear();
        self.cells.clear();
        self.start.clear();
        self.table.clear();
    }
}
