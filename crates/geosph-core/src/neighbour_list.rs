//! Flat (compressed sparse row) neighbour lists.

/// Neighbours of each query particle in compressed-sparse-row form.
///
/// The neighbours of query particle `i` are `indices[offsets[i]..offsets[i + 1]]`, in an order
/// fixed by the positions alone (the cell order of `geosph-neighbours`, not ascending index),
/// so any sum over them is evaluated in the same order whatever the number of threads. When
/// the query set is the searched set itself, every particle lists itself.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NeighbourList {
    /// `offsets[i]..offsets[i + 1]` is the range of particle `i` in `indices`; `len() + 1` entries.
    pub offsets: Vec<u32>,
    /// Neighbour indices of all particles, one run per query particle.
    pub indices: Vec<u32>,
}

impl NeighbourList {
    /// An empty list for zero query particles.
    pub fn new() -> Self {
        Self {
            offsets: vec![0],
            indices: Vec::new(),
        }
    }

    /// Number of query particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no query particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The neighbours of query particle `i`.
    #[inline]
    pub fn neighbours(&self, i: usize) -> &[u32] {
        &self.indices[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Total number of (query, neighbour) pairs.
    #[inline]
    pub fn pair_count(&self) -> usize {
        self.indices.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csr_ranges() {
        let list = NeighbourList {
            offsets: vec![0, 2, 2, 5],
            indices: vec![0, 1, 0, 1, 2],
        };
        assert_eq!(list.len(), 3);
        assert_eq!(list.neighbours(0), &[0, 1]);
        assert!(list.neighbours(1).is_empty());
        assert_eq!(list.neighbours(2), &[0, 1, 2]);
        assert_eq!(list.pair_count(), 5);
        assert!(NeighbourList::new().is_empty());
    }
}
