//! Pointwise kinematics: strain rate and spin from a velocity gradient, and the Jaumann term.
//!
//! The velocity gradient is L_αβ = ∂v_α/∂x_β (row = velocity component, column = derivative
//! direction). In 2D it is embedded in the upper-left 2×2 block of a 3×3 tensor, so that
//! ε̇_zz = ε̇_xz = ε̇_yz = 0 (plane strain) while σ_zz keeps evolving through the constitutive law.

use geosph_core::{Matrix, Real, Tensor3};

/// Embeds a D×D tensor (D = 2 or 3) in the upper-left block of a zero 3×3 tensor.
#[inline]
pub fn embed<const D: usize>(tensor: &Matrix<D>) -> Tensor3 {
    const { assert!(D == 2 || D == 3, "geosph-soil kinematics are for 2D and 3D") };
    let mut embedded = Tensor3::zeros();
    for i in 0..D {
        for j in 0..D {
            embedded[(i, j)] = tensor[(i, j)];
        }
    }
    embedded
}

/// The strain rate ε̇ = ½(L + Lᵀ) of the velocity gradient L_αβ = ∂v_α/∂x_β, embedded in 3×3.
#[inline]
pub fn strain_rate<const D: usize>(velocity_gradient: &Matrix<D>) -> Tensor3 {
    let l = embed(velocity_gradient);
    (l + l.transpose()) * 0.5
}

/// The spin (vorticity) tensor ω = ½(L − Lᵀ), ω_αβ = ½(∂v_α/∂x_β − ∂v_β/∂x_α), embedded in 3×3
/// (Bui et al. 2008, the spin ω̇^{αβ} of the Jaumann rate).
#[inline]
pub fn spin<const D: usize>(velocity_gradient: &Matrix<D>) -> Tensor3 {
    let l = embed(velocity_gradient);
    (l - l.transpose()) * 0.5
}

/// The co-rotational part of the Jaumann stress rate (Bui et al. 2008, Int. J. Numer. Anal.
/// Meth. Geomech. 32:1537, stress-rate equation of Sect. 3: σ̇^{αβ} = σ^{αγ} ω̇^{βγ} +
/// σ^{γβ} ω̇^{αγ} + constitutive part),
///
/// σ·ωᵀ + ω·σ = ω·σ − σ·ω,
///
/// with ω = ½(L − Lᵀ) from [`spin`]. The material rate is dσ/dt = σ^∇ + ω·σ − σ·ω, where
/// σ^∇ (the objective Jaumann rate) is what the constitutive law gives. A rigid rotation
/// v = Ω e_z × x has L = [[0, −Ω], [Ω, 0]] and σ(t) = R(Ωt) σ₀ Rᵀ(Ωt) with R the
/// counter-clockwise rotation, which this sign reproduces. In plane strain the (xx, yy, xy)
/// components are (2σ_xy ω_xy, 2σ_xy ω_yx, σ_xx ω_yx + σ_yy ω_xy) and the zz component is 0,
/// as in the design note `002` (which has this term right).
///
/// Linear in ω: pass the spin increment Δω = ω Δt to get the stress increment. For a
/// symmetric σ and a skew ω, σ·ω = −(ω·σ)ᵀ, so the term is ω·σ + (ω·σ)ᵀ: one matrix product
/// (bitwise the same as the two, each entry's products being negated exactly).
#[inline]
pub fn jaumann_rate(stress: &Tensor3, spin: &Tensor3) -> Tensor3 {
    let spun = spin * stress;
    spun + spun.transpose()
}

/// The rotation tensor R(θ) about e_z (counter-clockwise), used by tests and element paths.
pub fn rotation_about_z(angle: Real) -> Tensor3 {
    let (s, c) = angle.sin_cos();
    Tensor3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use geosph_core::Matrix;

    #[test]
    fn simple_shear_splits_into_equal_strain_rate_and_spin() {
        // v_x = γ̇ y: L_xy = ∂v_x/∂y = γ̇.
        let gamma_dot = 2.0;
        let l = Matrix::<2>::new(0.0, gamma_dot, 0.0, 0.0);
        let d = strain_rate(&l);
        let w = spin(&l);
        assert_eq!(d[(0, 1)], 1.0);
        assert_eq!(d[(1, 0)], 1.0);
        assert_eq!(w[(0, 1)], 1.0);
        assert_eq!(w[(1, 0)], -1.0);
        assert_eq!(d + w, embed(&l));
        for k in 0..3 {
            assert_eq!(d[(2, k)], 0.0, "plane strain: no zz/xz/yz strain rate");
        }
    }

    #[test]
    fn three_dimensional_gradient_is_taken_whole() {
        let l = Matrix::<3>::from_fn(|i, j| (3 * i + j) as Real);
        let d = strain_rate(&l);
        let w = spin(&l);
        assert_eq!(d + w, l);
        assert_eq!(d, d.transpose());
        assert_eq!(w, -w.transpose());
    }

    #[test]
    fn jaumann_term_matches_the_plane_strain_component_form() {
        let stress = Tensor3::new(-3.0, 1.5, 0.0, 1.5, -7.0, 0.0, 0.0, 0.0, -4.0);
        let l = Matrix::<2>::new(0.3, 1.1, -0.4, 0.2);
        let w = spin(&l);
        let rate = jaumann_rate(&stress, &w);
        let (sxx, syy, sxy) = (stress[(0, 0)], stress[(1, 1)], stress[(0, 1)]);
        let (wxy, wyx) = (w[(0, 1)], w[(1, 0)]);
        assert_relative_eq!(rate[(0, 0)], 2.0 * sxy * wxy, epsilon = 1e-14);
        assert_relative_eq!(rate[(1, 1)], 2.0 * sxy * wyx, epsilon = 1e-14);
        assert_relative_eq!(rate[(0, 1)], sxx * wyx + syy * wxy, epsilon = 1e-14);
        assert_eq!(rate[(2, 2)], 0.0);
        assert_eq!(rate, stress * w.transpose() + w * stress);
        assert_relative_eq!(rate.trace(), 0.0, epsilon = 1e-14);
    }

    #[test]
    fn jaumann_term_is_the_derivative_of_a_rigid_rotation() {
        // d/dt (R σ₀ Rᵀ) at t = 0 for R = R(Ω t) is W σ₀ − σ₀ W with W = [[0, −Ω], [Ω, 0]].
        let omega = 0.7;
        let stress = Tensor3::new(-3.0, 1.5, 0.0, 1.5, -7.0, 0.0, 0.0, 0.0, -4.0);
        let w = spin(&Matrix::<2>::new(0.0, -omega, omega, 0.0));
        let dt = 1e-6;
        let rotated = |t: Real| {
            let r = rotation_about_z(omega * t);
            r * stress * r.transpose()
        };
        let finite_difference = (rotated(dt) - rotated(-dt)) / (2.0 * dt);
        assert_relative_eq!(finite_difference, jaumann_rate(&stress, &w), epsilon = 1e-8);
    }
}
