//! Parallel writes into per-pair arrays aligned with a CSR neighbour list.

use geosph_core::NeighbourList;

/// Particles handled sequentially by one task.
const BLOCK: usize = 512;

/// Calls `visit(i, neighbours_of_i, pair_values_of_i)` for every query particle `i`, where
/// `pair_values_of_i` is the slice of `values` aligned with `list.neighbours(i)`.
///
/// The particle range is halved recursively with `rayon::join`, splitting `values` at the CSR
/// offset of the middle particle, so each task owns a disjoint slice: no allocation, no
/// atomics, and the same result for any number of threads.
pub(crate) fn for_each_particle_pairs<T: Send>(
    list: &NeighbourList,
    values: &mut [T],
    visit: impl Fn(usize, &[u32], &mut [T]) + Sync,
) {
    debug_assert_eq!(values.len(), list.pair_count());
    split(list, 0, list.len(), values, &visit);
}

fn split<T: Send>(
    list: &NeighbourList,
    first: usize,
    end: usize,
    values: &mut [T],
    visit: &(impl Fn(usize, &[u32], &mut [T]) + Sync),
) {
    if end - first <= BLOCK {
        let base = list.offsets[first] as usize;
        for i in first..end {
            let (start, stop) = (list.offsets[i] as usize, list.offsets[i + 1] as usize);
            visit(
                i,
                &list.indices[start..stop],
                &mut values[start - base..stop - base],
            );
        }
        return;
    }
    let middle = first + (end - first) / 2;
    let cut = (list.offsets[middle] - list.offsets[first]) as usize;
    let (left, right) = values.split_at_mut(cut);
    rayon::join(
        || split(list, first, middle, left, visit),
        || split(list, middle, end, right, visit),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pair_slot_is_written_once_with_its_owner() {
        let n = 3000;
        let mut offsets = vec![0u32];
        let mut indices = Vec::new();
        for i in 0..n {
            for k in 0..(i % 7) {
                indices.push(((i + k) % n) as u32);
            }
            offsets.push(indices.len() as u32);
        }
        let list = NeighbourList { offsets, indices };
        let mut owner = vec![usize::MAX; list.pair_count()];
        for_each_particle_pairs(&list, &mut owner, |i, neighbours, slots| {
            assert_eq!(neighbours.len(), slots.len());
            slots.iter_mut().for_each(|slot| *slot = i);
        });
        for i in 0..n {
            let range = list.offsets[i] as usize..list.offsets[i + 1] as usize;
            assert!(owner[range].iter().all(|&o| o == i));
        }
    }
}
