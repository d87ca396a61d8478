//! Soil walls: the velocity and the stress that dummy particles show to soil particles, and
//! the Coulomb friction of a wall on the soil sliding along it.

use geosph_core::{Real, Tensor3, Vector};

/// The velocity dummy particle B shows to soil particle A by Bui's rule (Bui et al. 2008,
/// Int. J. Numer. Anal. Meth. Geomech. 32:1537, eqs. 39–40, after Morris et al. 1997):
///
/// v_B = v_A − β (v_A − u_w),  β = min(β_max, 1 + d_B/d_A)  (no slip),
/// v_B = v_A − β ((v_A − u_w)·n) n  (free slip: the rule on the normal component only),
///
/// with d_A = (x_A − x_B)·n − d_B and d_B the distances of A and B from the wall surface and n
/// the unit wall normal at B pointing into the soil. β = 1 + d_B/d_A makes the relative
/// velocity vary linearly through the wall and vanish on its surface; a particle on or behind
/// the surface (d_A ≤ 0) gets β_max. With `free_slip = false` this is
/// [`geosph_boundary::bui::dummy_velocity`].
#[inline]
pub fn dummy_velocity<const D: usize>(
    x_a: &Vector<D>,
    v_a: &Vector<D>,
    x_b: &Vector<D>,
    normal_b: &Vector<D>,
    depth_b: Real,
    wall_velocity: &Vector<D>,
    beta_max: Real,
    free_slip: bool,
) -> Vector<D> {
    let d_a = (x_a - x_b).dot(normal_b) - depth_b;
    let beta = if d_a > 0.0 {
        beta_max.min(1.0 + depth_b / d_a)
    } else {
        beta_max
    };
    let relative = v_a - wall_velocity;
    if free_slip {
        v_a - normal_b * (beta * relative.dot(normal_b))
    } else {
        v_a - relative * beta
    }
}

/// The stress increment from soil particle i to dummy particle w along gravity,
/// ρ_i (g·(x_i − x_w)) ĝĝᵀ embedded in 3×3: the hydrostatic-like extrapolation of σ_v that
/// makes a level layer at rest (σ_v = −ρ g (H − y)) exact at the wall (the stress analogue of
/// Adami et al. 2012, J. Comput. Phys. 231:7057, eq. 27).
#[inline]
pub fn gravity_extrapolation<const D: usize>(
    density_i: Real,
    gravity: &Vector<D>,
    x_i_minus_x_w: &Vector<D>,
) -> Tensor3 {
    let g2 = gravity.norm_squared();
    if g2 == 0.0 {
        return Tensor3::zeros();
    }
    let magnitude = density_i * gravity.dot(x_i_minus_x_w) / g2;
    let mut increment = Tensor3::zeros();
    for a in 0..D {
        for b in 0..D {
            increment[(a, b)] = magnitude * gravity[a] * gravity[b];
        }
    }
    increment
}

/// The stress a slipping wall's dummy particle shows: σ mirrored in the wall plane,
/// R σ R with R = I − 2 n nᵀ, which keeps the normal stresses and reverses the shear σ_nt, so
/// that the pair sums carry no shear traction across the wall (the stress analogue of the
/// mirrored tangential velocity of free slip); the shear a friction wall carries is then its
/// Coulomb friction alone.
#[inline]
pub fn mirror_shear<const D: usize>(stress: &Tensor3, normal: &Vector<D>) -> Tensor3 {
    let mut reflection = Tensor3::identity();
    for a in 0..D {
        for b in 0..D {
            reflection[(a, b)] -= 2.0 * normal[a] * normal[b];
        }
    }
    reflection * stress * reflection
}

/// The Coulomb friction acceleration of a soil particle next to a fixed wall with friction
/// coefficient μ = tan δ: with n the (kernel-averaged) wall normal, the wall's normal push
/// a_n = a_wall·n, and the tangential velocity the step would reach without friction,
/// v_t* = (v + Δt a) − ((v + Δt a)·n) n, the friction is
///
/// a_f = −min(μ a_n, |v_t*|/Δt) v_t*/|v_t*|  (a_n > 0; else 0),
///
/// i.e. kinetic friction μ a_n opposing the sliding, or sticking (v_t = 0) when μ a_n could
/// stop the particle within the step (static friction).
#[inline]
pub(crate) fn coulomb_friction<const D: usize>(
    wall_normal: &Vector<D>,
    a_wall: &Vector<D>,
    velocity: &Vector<D>,
    acceleration: &Vector<D>,
    tan_delta: Real,
    dt: Real,
) -> Vector<D> {
    let length = wall_normal.norm();
    if length == 0.0 {
        return Vector::zeros();
    }
    let n = wall_normal / length;
    let push = a_wall.dot(&n);
    if push <= 0.0 {
        return Vector::zeros();
    }
    let v_star = velocity + acceleration * dt;
    let tangential = v_star - n * v_star.dot(&n);
    let speed = tangential.norm();
    if speed == 0.0 {
        return Vector::zeros();
    }
    let magnitude = (tan_delta * push).min(speed / dt);
    -tangential * (magnitude / speed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A wall with normal n = (cos 30°, sin 30°): the mirrored stress has the same normal
    /// traction component n·σ·n and tangential normal stress t·σ·t, and the opposite shear
    /// t·σ·n; the out-of-plane σ_zz is untouched.
    #[test]
    fn mirror_shear_reverses_only_the_shear_across_the_wall() {
        let n = Vector::<2>::new(30f64.to_radians().cos(), 30f64.to_radians().sin());
        let t = Vector::<2>::new(-n[1], n[0]);
        let sigma = Tensor3::new(-3.0, 1.5, 0.0, 1.5, -7.0, 0.0, 0.0, 0.0, -4.0);
        let mirrored = mirror_shear(&sigma, &n);
        let component = |s: &Tensor3, a: &Vector<2>, b: &Vector<2>| {
            let mut sum = 0.0;
            for i in 0..2 {
                for j in 0..2 {
                    sum += a[i] * s[(i, j)] * b[j];
                }
            }
            sum
        };
        assert_relative_eq!(
            component(&mirrored, &n, &n),
            component(&sigma, &n, &n),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            component(&mirrored, &t, &t),
            component(&sigma, &t, &t),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            component(&mirrored, &t, &n),
            -component(&sigma, &t, &n),
            max_relative = 1e-12
        );
        assert_relative_eq!(mirrored[(2, 2)], -4.0);
    }

    #[test]
    fn no_slip_rule_matches_the_boundary_crate_and_free_slip_keeps_the_tangent() {
        let normal = Vector::<2>::new(0.0, 1.0);
        let x_a = Vector::<2>::new(0.0, 0.2);
        let x_b = Vector::<2>::new(0.05, -0.1);
        let v_a = Vector::<2>::new(1.0, -0.4);
        let zero = Vector::<2>::zeros();
        let ours = dummy_velocity(&x_a, &v_a, &x_b, &normal, 0.1, &zero, 1.5, false);
        let theirs =
            geosph_boundary::bui::dummy_velocity(&x_a, &v_a, &x_b, &normal, 0.1, &zero, 1.5);
        assert_relative_eq!(ours, theirs, epsilon = 1e-15);
        let slip = dummy_velocity(&x_a, &v_a, &x_b, &normal, 0.1, &zero, 1.5, true);
        assert_eq!(slip[0], 1.0);
        // β = 1.5: the normal velocity is mirrored through the surface, −0.5 × (−0.4).
        assert_relative_eq!(slip[1], 0.2, epsilon = 1e-15);
    }

    #[test]
    fn extrapolation_reproduces_the_lithostatic_gradient() {
        // σ_yy = −ρ g (H − y): a dummy 0.3 below a soil particle is 0.3 ρ g more compressed.
        let gravity = Vector::<2>::new(0.0, -10.0);
        let increment = gravity_extrapolation(2000.0, &gravity, &Vector::<2>::new(0.1, 0.3));
        assert_relative_eq!(increment[(1, 1)], -0.3 * 2000.0 * 10.0, epsilon = 1e-9);
        assert_eq!(increment[(0, 0)], 0.0);
        assert_eq!(increment[(0, 1)], 0.0);
    }

    #[test]
    fn friction_slows_sliding_and_sticks_slow_particles() {
        let n = Vector::<2>::new(0.0, 2.0);
        let push = Vector::<2>::new(0.0, 10.0);
        let fast = Vector::<2>::new(1.0, 0.0);
        let a = Vector::<2>::zeros();
        let f = coulomb_friction(&n, &push, &fast, &a, 0.5, 1e-3);
        assert_relative_eq!(f[0], -5.0, epsilon = 1e-12);
        assert_eq!(f[1], 0.0);
        let slow = Vector::<2>::new(1e-3, 0.0);
        let f = coulomb_friction(&n, &push, &slow, &a, 0.5, 1e-3);
        assert_relative_eq!(slow[0] + f[0] * 1e-3, 0.0, epsilon = 1e-15);
        let pull = -push;
        assert_eq!(
            coulomb_friction(&n, &pull, &fast, &a, 0.5, 1e-3),
            Vector::<2>::zeros()
        );
    }
}
