//! Stress invariants and the (p, q) measures of soil mechanics.
//!
//! σ is tension positive; p and q follow the soil-mechanics convention (compression positive):
//! p = −I₁/3, q = √(3 J₂). For a triaxial state (σ_a, σ_r, σ_r): q = |σ_a − σ_r|.

use geosph_core::{Real, Tensor3};

/// The first invariant I₁ = tr σ = σ_xx + σ_yy + σ_zz.
#[inline]
pub fn first_invariant(stress: &Tensor3) -> Real {
    stress.trace()
}

/// The deviator s = σ − (I₁/3) 1.
#[inline]
pub fn deviator(stress: &Tensor3) -> Tensor3 {
    stress - Tensor3::identity() * (stress.trace() / 3.0)
}

/// The second invariant of the deviator, J₂ = ½ s:s (s symmetric).
#[inline]
pub fn second_deviatoric_invariant(stress: &Tensor3) -> Real {
    0.5 * deviator(stress).norm_squared()
}

/// The mean effective pressure p = −I₁/3 (compression positive).
#[inline]
pub fn mean_pressure(stress: &Tensor3) -> Real {
    -first_invariant(stress) / 3.0
}

/// The deviatoric (von Mises) stress q = √(3 J₂).
#[inline]
pub fn deviatoric_stress(stress: &Tensor3) -> Real {
    (3.0 * second_deviatoric_invariant(stress)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn pure_shear_has_j2_equal_to_tau_squared_and_no_pressure() {
        let tau = 7.0;
        let mut stress = Tensor3::zeros();
        stress[(0, 1)] = tau;
        stress[(1, 0)] = tau;
        assert_relative_eq!(
            second_deviatoric_invariant(&stress),
            tau * tau,
            epsilon = 1e-12
        );
        assert_eq!(mean_pressure(&stress), 0.0);
        assert_relative_eq!(
            deviatoric_stress(&stress),
            3.0_f64.sqrt() * tau,
            epsilon = 1e-12
        );
    }

    #[test]
    fn triaxial_state_has_q_equal_to_the_principal_difference() {
        // σ_a = −300 (axial, compression), σ_r = −100.
        let stress = Tensor3::from_diagonal(&nalgebra::Vector3::new(-100.0, -300.0, -100.0));
        assert_relative_eq!(mean_pressure(&stress), 500.0 / 3.0, epsilon = 1e-12);
        assert_relative_eq!(deviatoric_stress(&stress), 200.0, epsilon = 1e-12);
        assert_relative_eq!(deviator(&stress).trace(), 0.0, epsilon = 1e-12);
    }
}
