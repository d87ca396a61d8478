//! Morton (Z-order) codes of cells and the reordering of particles along the Z curve.
//!
//! The Morton code of a cell interleaves the bits of its integer coordinates (bit `b` of
//! axis `k` becomes bit `D·b + k` of the code), so cells close in space mostly get close
//! codes. Sorting particles by the code of their cell and applying the result with
//! [`geosph_core::Particles::permute`] makes memory order follow space, which keeps the
//! neighbour loops cache-friendly.

use geosph_core::{Permutation, Vector};
use rayon::prelude::*;

use crate::error::SearchError;
use crate::grid::CellGrid;

/// Spreads the low 32 bits of `x` to the even bits of a `u64`.
#[inline]
fn spread_by_one(x: u32) -> u64 {
    let mut x = x as u64;
    x = (x | (x << 16)) & 0x0000_FFFF_0000_FFFF;
    x = (x | (x << 8)) & 0x00FF_00FF_00FF_00FF;
    x = (x | (x << 4)) & 0x0F0F_0F0F_0F0F_0F0F;
    x = (x | (x << 2)) & 0x3333_3333_3333_3333;
    x = (x | (x << 1)) & 0x5555_5555_5555_5555;
    x
}

/// Spreads the low 21 bits of `x` to every third bit of a `u64`.
#[inline]
fn spread_by_two(x: u32) -> u64 {
    let mut x = (x & 0x1F_FFFF) as u64;
    x = (x | (x << 32)) & 0x001F_0000_0000_FFFF;
    x = (x | (x << 16)) & 0x001F_0000_FF00_00FF;
    x = (x | (x << 8)) & 0x100F_00F0_0F00_F00F;
    x = (x | (x << 4)) & 0x10C3_0C30_C30C_30C3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// The 2D Morton code of `(x, y)`: bit `b` of `x` goes to bit `2b`, of `y` to bit `2b + 1`.
#[inline]
pub fn morton_encode_2d(x: u32, y: u32) -> u64 {
    spread_by_one(x) | (spread_by_one(y) << 1)
}

/// The 3D Morton code of `(x, y, z)`, using the low 21 bits of each: bit `b` of `x`, `y`, `z`
/// goes to bit `3b`, `3b + 1`, `3b + 2`.
#[inline]
pub fn morton_encode_3d(x: u32, y: u32, z: u32) -> u64 {
    spread_by_two(x) | (spread_by_two(y) << 1) | (spread_by_two(z) << 2)
}

/// The Morton code of integer cell coordinates in `D` dimensions (bit `b` of axis `k` goes to
/// bit `D·b + k`); only the low `64 / D` bits of each coordinate are used.
#[inline]
pub fn morton_encode<const D: usize>(coords: [u32; D]) -> u64 {
    match D {
        1 => coords[0] as u64,
        2 => morton_encode_2d(coords[0], coords[1]),
        3 => morton_encode_3d(coords[0], coords[1], coords[2]),
        _ => {
            let bits = 64 / D;
            let mut code = 0u64;
            for b in 0..bits.min(32) {
                for (k, &c) in coords.iter().enumerate() {
                    code |= (((c >> b) & 1) as u64) << (D * b + k);
                }
            }
            code
        }
    }
}

impl<const D: usize> CellGrid<D> {
    /// The permutation that sorts the particles at `position` by the Morton code of their cell
    /// (stable: particles of one cell keep their relative order).
    ///
    /// Apply it with [`geosph_core::Particles::permute`] (which reorders every field and keeps
    /// `id`), then [`CellGrid::build`] again. Neighbourhoods are unchanged: if `j` is a
    /// neighbour of `i` before, then `p⁻¹(j)` is a neighbour of `p⁻¹(i)` after, where
    /// `order()[k]` is the old slot of new slot `k`. Does not change the grid; `position` need
    /// not be the built set. Errors as [`CellGrid::build`] for a particle outside the domain.
    pub fn z_order(&self, position: &[Vector<D>]) -> Result<Permutation, SearchError> {
        let n = position.len();
        if n > crate::grid::MAX_PARTICLES {
            return Err(SearchError::TooManyParticles {
                count: n,
                limit: crate::grid::MAX_PARTICLES,
            });
        }
        let map = self.map;
        // No cell has the code u64::MAX: per axis at most 2^32 cells in 1D, 2^32 − 1 in 2D
        // and 2^21 in 3D (`CellGrid::with_index`).
        let mut codes: Vec<u64> = position
            .par_iter()
            .with_min_len(4096)
            .map(|x| {
                map.cell_coords(x)
                    .map_or(OUTSIDE, |c| morton_encode::<D>(c.map(|ck| ck as u32)))
            })
            .collect();
        if let Some(index) = codes.iter().position(|&code| code == OUTSIDE) {
            return Err(SearchError::OutsideDomain {
                index,
                position: position[index].iter().copied().collect(),
                min: self.domain.min.iter().copied().collect(),
                max: self.domain.max.iter().copied().collect(),
            });
        }
        // The index goes into the low bits of its code when both fit in 64 (8 B per particle
        // and as much scratch, against 16 + 16 B for (code, index) pairs); the whole key then
        // orders by code and, within a cell, by index, which is the stable order.
        let code_bits = u64::BITS - codes.iter().fold(0, |o, &c| o | c).leading_zeros();
        let index_bits = u64::BITS - (n.max(1) as u64 - 1).leading_zeros();
        let order = if code_bits + index_bits <= u64::BITS {
            for (i, code) in codes.iter_mut().enumerate() {
                *code = (*code << index_bits) | i as u64;
            }
            let mask = (1u64 << index_bits) - 1;
            radix_sort(codes, |key| key)
                .into_iter()
                .map(|key| (key & mask) as u32)
                .collect()
        } else {
            let keyed = codes.into_iter().zip(0..n as u32).collect();
            radix_sort(keyed, |(code, _)| code)
                .into_iter()
                .map(|(_, i)| i)
                .collect()
        };
        Ok(Permutation::from_order(order).expect("a sort yields a permutation"))
    }
}

/// Marks a particle outside the domain among the Morton codes.
const OUTSIDE: u64 = u64::MAX;

/// `items` sorted by `key`, stable, by a least-significant-digit radix sort with 8-bit digits
/// that skips digits on which all keys agree.
pub(crate) fn radix_sort<T: Copy + Default>(mut items: Vec<T>, key: impl Fn(T) -> u64) -> Vec<T> {
    let (all_or, all_and) = items.iter().fold((0u64, u64::MAX), |(o, a), &item| {
        let k = key(item);
        (o | k, a & k)
    });
    let varying = all_or & !all_and;
    let mut scratch = vec![T::default(); items.len()];
    let mut counts = [0usize; 256];
    for shift in (0..64).step_by(8) {
        if (varying >> shift) & 0xFF == 0 {
            continue;
        }
        counts.fill(0);
        for &item in &items {
            counts[((key(item) >> shift) & 0xFF) as usize] += 1;
        }
        let mut sum = 0;
        for c in counts.iter_mut() {
            let count = *c;
            *c = sum;
            sum += count;
        }
        for &item in &items {
            let digit = ((key(item) >> shift) & 0xFF) as usize;
            scratch[counts[digit]] = item;
            counts[digit] += 1;
        }
        std::mem::swap(&mut items, &mut scratch);
    }
    items
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bit-by-bit interleaving, the definition.
    fn reference(coords: &[u32], bits: usize) -> u64 {
        let d = coords.len();
        let mut code = 0u64;
        for b in 0..bits {
            for (k, &c) in coords.iter().enumerate() {
                code |= (((c >> b) & 1) as u64) << (d * b + k);
            }
        }
        code
    }

    #[test]
    fn small_codes_2d_and_3d() {
        assert_eq!(morton_encode_2d(0, 0), 0);
        assert_eq!(morton_encode_2d(1, 0), 1);
        assert_eq!(morton_encode_2d(0, 1), 2);
        assert_eq!(morton_encode_2d(3, 3), 15);
        assert_eq!(morton_encode_2d(2, 1), 0b0110);
        assert_eq!(morton_encode_3d(1, 0, 0), 1);
        assert_eq!(morton_encode_3d(0, 1, 0), 2);
        assert_eq!(morton_encode_3d(0, 0, 1), 4);
        assert_eq!(morton_encode_3d(7, 7, 7), 511);
        assert_eq!(morton_encode_3d(2, 0, 1), 0b001_100);
        assert_eq!(morton_encode_2d(u32::MAX, u32::MAX), u64::MAX);
        assert_eq!(
            morton_encode_3d(0x1F_FFFF, 0x1F_FFFF, 0x1F_FFFF),
            u64::MAX >> 1
        );
    }

    #[test]
    fn matches_bitwise_interleaving() {
        // A simple xorshift so the test needs no rand dependency.
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..10_000 {
            let (a, b, c) = (next() as u32, next() as u32, next() as u32);
            assert_eq!(morton_encode_2d(a, b), reference(&[a, b], 32));
            let (a21, b21, c21) = (a & 0x1F_FFFF, b & 0x1F_FFFF, c & 0x1F_FFFF);
            assert_eq!(
                morton_encode_3d(a21, b21, c21),
                reference(&[a21, b21, c21], 21)
            );
            assert_eq!(morton_encode::<2>([a, b]), morton_encode_2d(a, b));
            assert_eq!(
                morton_encode::<3>([a21, b21, c21]),
                morton_encode_3d(a21, b21, c21)
            );
            assert_eq!(morton_encode::<1>([a]), a as u64);
            assert_eq!(
                morton_encode::<4>([a, b, c, a]),
                reference(&[a, b, c, a], 16)
            );
        }
    }

    #[test]
    fn z_curve_visits_quadrants_in_order() {
        // On a 4×4 grid the codes walk each 2×2 quadrant before the next one.
        let mut cells: Vec<(u32, u32)> = (0..4).flat_map(|y| (0..4).map(move |x| (x, y))).collect();
        cells.sort_by_key(|&(x, y)| morton_encode_2d(x, y));
        let quadrant = |&(x, y): &(u32, u32)| (x / 2) + 2 * (y / 2);
        let quadrants: Vec<u32> = cells.iter().map(quadrant).collect();
        assert_eq!(quadrants, [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3]);
        assert_eq!(&cells[..4], &[(0, 0), (1, 0), (0, 1), (1, 1)]);
    }

    #[test]
    fn radix_sort_is_stable() {
        let sort = |keys: &[u64]| -> Vec<u32> {
            let items = keys
                .iter()
                .enumerate()
                .map(|(i, &k)| (k, i as u32))
                .collect();
            radix_sort(items, |(k, _)| k)
                .into_iter()
                .map(|(_, i)| i)
                .collect()
        };
        assert_eq!(
            sort(&[5, 1 << 40, 3, 5, 0, 1 << 40, 3, 256]),
            [4, 2, 6, 0, 3, 7, 1, 5]
        );
        assert!(sort(&[]).is_empty());
        assert_eq!(sort(&[7, 7, 7]), [0, 1, 2]);
        assert_eq!(sort(&[u64::MAX - 1, 1, u64::MAX - 1, 0]), [3, 1, 0, 2]);
    }

    /// The packed keys give the order of a stable sort by cell code: particles given two per
    /// 0.1 square in reverse order of the squares (the grid's cells are about that size), and
    /// one outside.
    #[test]
    fn z_order_sorts_by_cell_then_index() {
        use geosph_core::{Domain, Vector};
        let domain = Domain::new(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(1.0, 1.0)).unwrap();
        let grid = CellGrid::new(domain, 0.1).unwrap();
        let position: Vec<Vector<2>> = (0..200)
            .map(|k| {
                let cell = 99 - k / 2;
                let offset = if k % 2 == 0 { 0.07 } else { 0.03 };
                Vector::<2>::new(
                    (cell % 10) as f64 * 0.1 + offset,
                    (cell / 10) as f64 * 0.1 + 0.05,
                )
            })
            .collect();
        let code = |x: &Vector<2>| {
            let [cx, cy] = grid.map.cell_coords(x).unwrap();
            morton_encode_2d(cx as u32, cy as u32)
        };
        let mut expected: Vec<u32> = (0..200).collect();
        expected.sort_by_key(|&i| code(&position[i as usize]));
        let order = grid.z_order(&position).unwrap();
        assert_eq!(order.order(), expected.as_slice());
        let mut outside = position.clone();
        outside[17] = Vector::<2>::new(1.5, 0.5);
        assert!(matches!(
            grid.z_order(&outside),
            Err(SearchError::OutsideDomain { index: 17, .. })
        ));
    }
}
