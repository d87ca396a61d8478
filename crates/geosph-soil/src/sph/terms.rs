//! The artificial stress of the soil momentum equation (the artificial viscosity is
//! [`geosph_sph::ArtificialMonaghan1992`], shared with the fluids).

use geosph_core::{Matrix, Real, Tensor3};
use geosph_kernels::Kernel;

/// Gray, Monaghan & Swift (2001, Comput. Methods Appl. Mech. Engrg. 190:6641, eqs. 3.13–3.18):
/// in the principal frame of σ_i, R'_a = −ε σ'_a/ρ_i² for each tensile principal stress
/// σ'_a > 0 and 0 otherwise; R_i = Q diag(R') Qᵀ rotates it back. The momentum equation gains
/// Σ_j m_j f_ij^n (R_i + R_j)·∇_i W_ij with f_ij = W(r_ij)/W(dx).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtificialStressGray2001 {
    /// ε.
    pub epsilon: Real,
    /// n.
    pub exponent: Real,
    /// 1/W(dx).
    pub inverse_reference_value: Real,
}

impl ArtificialStressGray2001 {
    /// The term for kernel `kernel` at initial spacing `spacing`.
    pub fn new<const D: usize, K: Kernel<D>>(
        kernel: &K,
        epsilon: Real,
        exponent: Real,
        spacing: Real,
    ) -> Self {
        Self {
            epsilon,
            exponent,
            inverse_reference_value: 1.0 / kernel.value(spacing),
        }
    }

    /// The D×D block of the particle's artificial stress R_i from its stress and density.
    pub fn particle_term<const D: usize>(&self, stress: &Tensor3, density: Real) -> Matrix<D> {
        // In plane strain σ_xz = σ_yz = 0, so e_z is a principal direction and the in-plane
        // block of R is that of the in-plane principal stresses.
        let eigen = stress.symmetric_eigen();
        if eigen.eigenvalues.iter().all(|&s| s <= 0.0) {
            return Matrix::zeros();
        }
        let scale = -self.epsilon / (density * density);
        let principal = eigen
            .eigenvalues
            .map(|s| if s > 0.0 { scale * s } else { 0.0 });
        block(
            &(eigen.eigenvectors
                * Tensor3::from_diagonal(&principal)
                * eigen.eigenvectors.transpose()),
        )
    }

    /// f_ij^n, with f_ij = W(r_ij)/W(dx).
    #[inline(always)]
    pub fn pair_factor(&self, kernel_value: Real) -> Real {
        (kernel_value * self.inverse_reference_value).powf(self.exponent)
    }
}

/// The upper-left D×D block of a 3×3 tensor (what the D-dimensional momentum equation sees).
#[inline]
pub fn block<const D: usize>(tensor: &Tensor3) -> Matrix<D> {
    Matrix::<D>::from_fn(|i, j| tensor[(i, j)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use geosph_kernels::WendlandC2;

    #[test]
    fn artificial_stress_acts_on_tensile_principal_stresses_only() {
        let kernel = WendlandC2::<2>::new(1.3);
        let term = ArtificialStressGray2001::new(&kernel, 0.3, 4.0, 1.0);
        // Principal stresses +2 (tension) along (1, 1)/√2 and −5 along (1, −1)/√2.
        let (a, b) = (2.0, -5.0);
        let stress = Tensor3::new(
            0.5 * (a + b),
            0.5 * (a - b),
            0.0,
            0.5 * (a - b),
            0.5 * (a + b),
            0.0,
            0.0,
            0.0,
            -1.0,
        );
        let r: Matrix<2> = term.particle_term(&stress, 2.0);
        let expected = -0.3 * a / 4.0;
        // R = expected · n nᵀ with n = (1, 1)/√2.
        assert_relative_eq!(r[(0, 0)], 0.5 * expected, epsilon = 1e-12);
        assert_relative_eq!(r[(0, 1)], 0.5 * expected, epsilon = 1e-12);
        assert_relative_eq!(r[(1, 1)], 0.5 * expected, epsilon = 1e-12);
        let compressive = Tensor3::new(-1.0, 0.2, 0.0, 0.2, -3.0, 0.0, 0.0, 0.0, -1.0);
        assert_eq!(
            term.particle_term::<2>(&compressive, 2.0),
            Matrix::<2>::zeros()
        );
        assert_relative_eq!(term.pair_factor(kernel.value(1.0)), 1.0, epsilon = 1e-12);
    }
}
