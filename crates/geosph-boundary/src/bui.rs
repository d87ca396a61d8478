//! Bui's velocity rule for dummy particles.

use geosph_core::{Real, Vector};

/// The velocity a dummy particle B shows to particle A (Bui et al. 2008, Int. J. Numer. Anal.
/// Meth. Geomech. 32:1537–1570, after Morris et al. 1997):
///
/// v_B = (1 − β) v_A + β v_wall,  β = min(β_max, 1 + d_B / d_A),
///
/// where d_A and d_B are the distances of A and B to the wall surface. β = 1 + d_B/d_A makes
/// the velocity vary linearly through the wall and vanish (relative to the wall) on its
/// surface; β_max (1.5 in Bui et al.) bounds it when A comes very close to the wall.
///
/// `normal_b` is the unit wall normal at B pointing into the flow and `depth_b` = d_B; the
/// distance of A is d_A = (x_A − x_B)·n_B − d_B. A particle on or behind the surface
/// (d_A ≤ 0) gets β = β_max.
#[inline]
pub fn dummy_velocity<const D: usize>(
    x_a: &Vector<D>,
    v_a: &Vector<D>,
    x_b: &Vector<D>,
    normal_b: &Vector<D>,
    depth_b: Real,
    wall_velocity: &Vector<D>,
    beta_max: Real,
) -> Vector<D> {
    let d_a = (x_a - x_b).dot(normal_b) - depth_b;
    let beta = if d_a > 0.0 {
        beta_max.min(1.0 + depth_b / d_a)
    } else {
        beta_max
    };
    v_a * (1.0 - beta) + wall_velocity * beta
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn velocity_vanishes_on_the_wall_surface() {
        // Wall surface y = 0, flow above; A at height 0.2, B at depth 0.1 below.
        let normal = Vector::<2>::new(0.0, 1.0);
        let x_a = Vector::<2>::new(0.0, 0.2);
        let x_b = Vector::<2>::new(0.05, -0.1);
        let v_a = Vector::<2>::new(1.0, 0.0);
        let v_b = dummy_velocity(&x_a, &v_a, &x_b, &normal, 0.1, &Vector::zeros(), 1.5);
        // β = 1.5: linear profile through the surface, v_B = −d_B/d_A v_A.
        assert_relative_eq!(v_b[0], -0.5, epsilon = 1e-14);
        // Close to the wall β is capped at β_max.
        let near = Vector::<2>::new(0.0, 0.01);
        let v_b = dummy_velocity(&near, &v_a, &x_b, &normal, 0.1, &Vector::zeros(), 1.5);
        assert_relative_eq!(v_b[0], -0.5, epsilon = 1e-14);
        let far = Vector::<2>::new(0.0, 0.4);
        let v_b = dummy_velocity(&far, &v_a, &x_b, &normal, 0.1, &Vector::zeros(), 1.5);
        assert_relative_eq!(v_b[0], -0.25, epsilon = 1e-14);
    }
}
