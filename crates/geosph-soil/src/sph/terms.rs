//! Switchable pair terms of the soil momentum equation: artificial viscosity and artificial
//! stress. Each is a type parameter of [`crate::sph::SoilSystem`]; the "off" types are zero
//! sized and their terms vanish at compile time.

use geosph_core::{Matrix, Real, Tensor3, Vector};
use geosph_kernels::Kernel;

/// The artificial-viscosity term Π_ij of a soil–soil pair.
pub trait PairViscosity<const D: usize>: Copy + Send + Sync + 'static {
    /// Whether the term exists (false: the pair loop skips it at compile time).
    const ON: bool;

    /// Π_ij for r_ij = x_i − x_j, v_ij = v_i − v_j, r² = |r_ij|² and ρ̄_ij = (ρ_i + ρ_j)/2.
    fn pi(&self, r_ij: &Vector<D>, v_ij: &Vector<D>, r2: Real, rho_mean: Real) -> Real;
}

/// No artificial viscosity.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoViscosity;

impl<const D: usize> PairViscosity<D> for NoViscosity {
    const ON: bool = false;

    #[inline(always)]
    fn pi(&self, _: &Vector<D>, _: &Vector<D>, _: Real, _: Real) -> Real {
        0.0
    }
}

/// Monaghan's (1992, Annu. Rev. Astron. Astrophys. 30, eq. 4.1) artificial viscosity with the
/// elastic wave speed c as signal speed (Bui et al. 2008, eq. 33):
///
/// Π_ij = (−α c μ_ij + β μ_ij²)/ρ̄_ij if v_ij·r_ij < 0, else 0,
/// μ_ij = h v_ij·r_ij / (r_ij² + 0.01 h²).
///
/// It enters the momentum equation as −Σ_j m_j Π_ij ∇_i W_ij (soil–soil pairs only, as Bui
/// et al. 2008 apply it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtificialViscosityMonaghan {
    /// α_Π.
    pub alpha: Real,
    /// β_Π.
    pub beta: Real,
    /// h.
    pub smoothing_length: Real,
    /// c = √((K + 4G/3)/ρ₀).
    pub wave_speed: Real,
}

impl<const D: usize> PairViscosity<D> for ArtificialViscosityMonaghan {
    const ON: bool = true;

    #[inline(always)]
    fn pi(&self, r_ij: &Vector<D>, v_ij: &Vector<D>, r2: Real, rho_mean: Real) -> Real {
        let approach = v_ij.dot(r_ij);
        if approach >= 0.0 {
            return 0.0;
        }
        let h = self.smoothing_length;
        let mu = h * approach / (r2 + 0.01 * h * h);
        (-self.alpha * self.wave_speed * mu + self.beta * mu * mu) / rho_mean
    }
}

/// The artificial stress of Gray, Monaghan & Swift (2001) against the tensile instability.
pub trait TensileCorrection<const D: usize>: Copy + Send + Sync + 'static {
    /// Whether the term exists.
    const ON: bool;

    /// The D×D block of the particle's artificial stress R_i from its stress and density.
    fn particle_term(&self, stress: &Tensor3, density: Real) -> Matrix<D>;

    /// f_ij^n, with f_ij = W(r_ij)/W(dx).
    fn pair_factor(&self, kernel_value: Real) -> Real;
}

/// No artificial stress.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoArtificialStress;

impl<const D: usize> TensileCorrection<D> for NoArtificialStress {
    const ON: bool = false;

    #[inline(always)]
    fn particle_term(&self, _: &Tensor3, _: Real) -> Matrix<D> {
        Matrix::zeros()
    }

    #[inline(always)]
    fn pair_factor(&self, _: Real) -> Real {
        0.0
    }
}

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
}

impl<const D: usize> TensileCorrection<D> for ArtificialStressGray2001 {
    const ON: bool = true;

    fn particle_term(&self, stress: &Tensor3, density: Real) -> Matrix<D> {
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

    #[inline(always)]
    fn pair_factor(&self, kernel_value: Real) -> Real {
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
            TensileCorrection::<2>::particle_term(&term, &compressive, 2.0),
            Matrix::<2>::zeros()
        );
        assert_relative_eq!(
            TensileCorrection::<2>::pair_factor(&term, kernel.value(1.0)),
            1.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn viscosity_acts_only_on_approaching_pairs() {
        let av = ArtificialViscosityMonaghan {
            alpha: 0.1,
            beta: 0.0,
            smoothing_length: 1.0,
            wave_speed: 10.0,
        };
        let r = Vector::<2>::new(1.0, 0.0);
        let approaching = Vector::<2>::new(-1.0, 0.0);
        let pi = PairViscosity::<2>::pi(&av, &r, &approaching, 1.0, 2.0);
        // μ = −1/1.01, Π = 0.1 · 10 / 1.01 / 2.
        assert_relative_eq!(pi, 0.5 / 1.01, epsilon = 1e-12);
        assert_eq!(
            PairViscosity::<2>::pi(&av, &r, &-approaching, 1.0, 2.0),
            0.0
        );
    }
}
