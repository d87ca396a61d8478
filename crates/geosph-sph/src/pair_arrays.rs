//! Parallel writes into per-pair arrays aligned with CSR neighbour lists, and into
//! per-particle arrays, in one pass.

use geosph_core::NeighbourList;

/// Particles handled sequentially by one task.
const BLOCK: usize = 512;

/// One particle's view in [`for_each_particle`]: its fluid and wall neighbours with the slices
/// of the per-pair arrays aligned with them, and its entries of three per-particle arrays.
pub struct ParticleView<'a, T, U, A, B, C> {
    /// Fluid neighbours of the particle.
    pub fluid: &'a [u32],
    /// Per-pair values aligned with `fluid`.
    pub fluid_values: &'a mut [T],
    /// Wall neighbours of the particle.
    pub wall: &'a [u32],
    /// Per-pair values aligned with `wall`.
    pub wall_values: &'a mut [U],
    /// The particle's entries of the three per-particle arrays.
    pub own: (&'a mut A, &'a mut B, &'a mut C),
}

/// Mutable per-pair arrays of two CSR lists and three per-particle arrays, cut together.
struct Parts<'a, T, U, A, B, C> {
    fluid_values: &'a mut [T],
    wall_values: &'a mut [U],
    own: (&'a mut [A], &'a mut [B], &'a mut [C]),
}

/// Calls `visit(i, view)` for every particle `i` of the two neighbour lists `fluid` and `wall`
/// (same particles), with `view` its neighbours, its slices of the per-pair arrays
/// `fluid_values` and `wall_values` (aligned with the lists' indices) and its entries of the
/// per-particle arrays `own`.
///
/// The particle range is halved recursively with `rayon::join`, cutting every array at the
/// middle particle (the per-pair ones at its CSR offsets), so each task owns disjoint slices:
/// no allocation, no atomics, and the same result for any number of threads.
pub fn for_each_particle<T: Send, U: Send, A: Send, B: Send, C: Send>(
    (fluid, wall): (&NeighbourList, &NeighbourList),
    fluid_values: &mut [T],
    wall_values: &mut [U],
    own: (&mut [A], &mut [B], &mut [C]),
    visit: impl Fn(usize, ParticleView<'_, T, U, A, B, C>) + Sync,
) {
    debug_assert_eq!(fluid_values.len(), fluid.pair_count());
    debug_assert_eq!(wall_values.len(), wall.pair_count());
    debug_assert!(own.0.len() == fluid.len() && own.1.len() == fluid.len());
    debug_assert!(own.2.len() == fluid.len() && wall.len() == fluid.len());
    let parts = Parts {
        fluid_values,
        wall_values,
        own,
    };
    split((fluid, wall), 0, fluid.len(), parts, &visit);
}

fn split<T: Send, U: Send, A: Send, B: Send, C: Send>(
    lists: (&NeighbourList, &NeighbourList),
    first: usize,
    end: usize,
    parts: Parts<'_, T, U, A, B, C>,
    visit: &(impl Fn(usize, ParticleView<'_, T, U, A, B, C>) + Sync),
) {
    let (fluid, wall) = lists;
    if end - first <= BLOCK {
        let (fluid_base, wall_base) = (fluid.offsets[first] as usize, wall.offsets[first] as usize);
        let Parts {
            fluid_values,
            wall_values,
            own: (a, b, c),
        } = parts;
        for i in first..end {
            let (fs, fe) = (fluid.offsets[i] as usize, fluid.offsets[i + 1] as usize);
            let (ws, we) = (wall.offsets[i] as usize, wall.offsets[i + 1] as usize);
            let k = i - first;
            visit(
                i,
                ParticleView {
                    fluid: &fluid.indices[fs..fe],
                    fluid_values: &mut fluid_values[fs - fluid_base..fe - fluid_base],
                    wall: &wall.indices[ws..we],
                    wall_values: &mut wall_values[ws - wall_base..we - wall_base],
                    own: (&mut a[k], &mut b[k], &mut c[k]),
                },
            );
        }
        return;
    }
    let middle = first + (end - first) / 2;
    let fluid_cut = (fluid.offsets[middle] - fluid.offsets[first]) as usize;
    let wall_cut = (wall.offsets[middle] - wall.offsets[first]) as usize;
    let own_cut = middle - first;
    let Parts {
        fluid_values,
        wall_values,
        own: (a, b, c),
    } = parts;
    let (fluid_left, fluid_right) = fluid_values.split_at_mut(fluid_cut);
    let (wall_left, wall_right) = wall_values.split_at_mut(wall_cut);
    let (a_left, a_right) = a.split_at_mut(own_cut);
    let (b_left, b_right) = b.split_at_mut(own_cut);
    let (c_left, c_right) = c.split_at_mut(own_cut);
    let left = Parts {
        fluid_values: fluid_left,
        wall_values: wall_left,
        own: (a_left, b_left, c_left),
    };
    let right = Parts {
        fluid_values: fluid_right,
        wall_values: wall_right,
        own: (a_right, b_right, c_right),
    };
    rayon::join(
        || split(lists, first, middle, left, visit),
        || split(lists, middle, end, right, visit),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pair_slot_and_particle_entry_is_written_once_with_its_owner() {
        let n = 3000;
        let list = |width: usize| {
            let mut offsets = vec![0u32];
            let mut indices = Vec::new();
            for i in 0..n {
                for k in 0..(i % width) {
                    indices.push(((i + k) % n) as u32);
                }
                offsets.push(indices.len() as u32);
            }
            NeighbourList { offsets, indices }
        };
        let (fluid, wall) = (list(7), list(3));
        let mut fluid_owner = vec![usize::MAX; fluid.pair_count()];
        let mut wall_owner = vec![usize::MAX; wall.pair_count()];
        let (mut a, mut b, mut c) = (vec![0usize; n], vec![0usize; n], vec![0usize; n]);
        for_each_particle(
            (&fluid, &wall),
            &mut fluid_owner,
            &mut wall_owner,
            (&mut a, &mut b, &mut c),
            |i, view| {
                assert_eq!(view.fluid.len(), view.fluid_values.len());
                assert_eq!(view.wall.len(), view.wall_values.len());
                view.fluid_values.iter_mut().for_each(|slot| *slot = i);
                view.wall_values.iter_mut().for_each(|slot| *slot = i);
                (*view.own.0, *view.own.1, *view.own.2) = (i, i + 1, i + 2);
            },
        );
        for i in 0..n {
            let range = fluid.offsets[i] as usize..fluid.offsets[i + 1] as usize;
            assert!(fluid_owner[range].iter().all(|&o| o == i));
            let range = wall.offsets[i] as usize..wall.offsets[i + 1] as usize;
            assert!(wall_owner[range].iter().all(|&o| o == i));
            assert_eq!((a[i], b[i], c[i]), (i, i + 1, i + 2));
        }
    }
}
