//! The lattice sites `origin + (k + ½) dx` of a bounding box, in a fixed order.

use geosph_core::Real;

/// The sites `origin + (k + ½) dx` (k integer per axis) of the cells that cover the box
/// [`lo` − `margin`, `hi` + `margin`], the first axis outermost and the last innermost.
pub(crate) fn sites<const N: usize>(
    lo: [Real; N],
    hi: [Real; N],
    origin: [Real; N],
    dx: Real,
    margin: Real,
) -> impl Iterator<Item = [Real; N]> {
    let first: [i64; N] =
        std::array::from_fn(|k| ((lo[k] - margin - origin[k]) / dx - 0.5).floor() as i64);
    let last: [i64; N] =
        std::array::from_fn(|k| ((hi[k] + margin - origin[k]) / dx - 0.5).ceil() as i64);
    let empty = (0..N).any(|k| last[k] < first[k]);
    let mut index = (!empty).then_some(first);
    std::iter::from_fn(move || {
        let current = index?;
        // The next index, the last axis fastest.
        let mut next = current;
        index = None;
        for k in (0..N).rev() {
            if next[k] < last[k] {
                next[k] += 1;
                index = Some(next);
                break;
            }
            next[k] = first[k];
        }
        Some(std::array::from_fn(|k| {
            origin[k] + (current[k] as Real + 0.5) * dx
        }))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sites_cover_the_box_in_order() {
        let all: Vec<[Real; 2]> = sites([0.0, 0.0], [0.2, 0.1], [0.0, 0.0], 0.1, 0.0).collect();
        // Cells from floor(−0.5) = −1 to ceil(1.5) = 2 along x, −1 to 1 along y.
        assert_eq!(all.len(), 4 * 3);
        assert_eq!(all[0], [-0.05, -0.05]);
        assert_eq!(all[1], [-0.05, 0.05]);
        assert!((all[11][0] - 0.25).abs() < 1e-12 && (all[11][1] - 0.15).abs() < 1e-12);
    }
}
