//! Which particles of one set come too close to another's.

use geosph_core::{Real, Vector};

/// The first fluid particle `i` closer than `gap` (minus round-off) to a wall particle `j`, with
/// the distance; by hashing the wall particles into cells of size `gap`.
pub(crate) fn overlap<const D: usize>(
    fluid: &[Vector<D>],
    walls: &[Vector<D>],
    gap: Real,
) -> Option<(usize, usize, Real)> {
    use std::collections::HashMap;
    let cell = |x: &Vector<D>| -> [i64; D] { std::array::from_fn(|k| (x[k] / gap).floor() as i64) };
    let mut cells: HashMap<[i64; D], Vec<usize>> = HashMap::new();
    for (j, x) in walls.iter().enumerate() {
        cells.entry(cell(x)).or_default().push(j);
    }
    let limit = gap * (1.0 - 1e-9);
    let offsets = 3_usize.pow(D as u32);
    for (i, x) in fluid.iter().enumerate() {
        let home = cell(x);
        for offset in 0..offsets {
            let mut key = home;
            let mut rest = offset;
            for k in 0..D {
                key[k] += (rest % 3) as i64 - 1;
                rest /= 3;
            }
            for &j in cells.get(&key).into_iter().flatten() {
                let distance = (x - walls[j]).norm();
                if distance < limit {
                    return Some((i, j, distance));
                }
            }
        }
    }
    None
}
