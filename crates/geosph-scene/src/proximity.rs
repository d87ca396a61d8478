//! Which particles of one set come too close to another's, or lie inside a wall's layers.

use geosph_boundary::generate::{FlowSide, Segment, segments};
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

/// The first fluid particle that lies behind the polyline `points` (on the side away from
/// the flow, beyond round-off) by less than `thickness`, i.e. inside the wall's particle
/// layers, with how far behind it is. Only the first two coordinates count.
pub(crate) fn behind_polyline<const D: usize>(
    fluid: &[Vector<D>],
    points: &[Vector<2>],
    flow: FlowSide,
    thickness: Real,
) -> Option<(usize, Real)> {
    for Segment {
        start,
        length,
        tangent,
        into_flow,
    } in segments(points, flow)
    {
        let round_off = 1e-9 * length;
        for (i, x) in fluid.iter().enumerate() {
            let relative = Vector::<2>::new(x[0], x[1]) - start;
            let along = relative.dot(&tangent);
            let behind = -relative.dot(&into_flow);
            if along >= 0.0 && along <= length && behind > round_off && behind < thickness {
                return Some((i, behind));
            }
        }
    }
    None
}
