//! Hypoelastic (linear elastic, Jaumann rate) soil.

use geosph_core::{Real, Tensor3};

use crate::constitutive::{Constitutive, StressUpdate};
use crate::kinematics::jaumann_rate;
use crate::material::{ElasticConstants, MaterialError};

/// Linear elasticity with the Jaumann stress rate (Bui et al. 2008, elastic part of the
/// stress-rate equation):
///
/// dσ/dt = ω·σ − σ·ω + 2G ė + K ε̇_kk 1,  ė = ε̇ − (ε̇_kk/3) 1,
///
/// i.e. dσ/dt = ω·σ − σ·ω + Dᵉ:ε̇ with Dᵉ:ε̇ = λ ε̇_kk 1 + 2G ε̇.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearElastic {
    elastic: ElasticConstants,
}

impl LinearElastic {
    /// The model of E > 0 and ν ∈ [0, 0.5).
    pub fn new(youngs_modulus: Real, poisson_ratio: Real) -> Result<Self, MaterialError> {
        Ok(Self {
            elastic: ElasticConstants::new(youngs_modulus, poisson_ratio)?,
        })
    }

    /// The material stress rate dσ/dt = ω·σ − σ·ω + Dᵉ:ε̇, for integrators that integrate the
    /// stress rate themselves (it is linear in ε̇ and ω).
    #[inline]
    pub fn stress_rate(&self, stress: &Tensor3, strain_rate: &Tensor3, spin: &Tensor3) -> Tensor3 {
        jaumann_rate(stress, spin) + self.elastic.stress_increment(strain_rate)
    }
}

impl Constitutive for LinearElastic {
    fn name(&self) -> &'static str {
        "linear-elastic"
    }

    #[inline]
    fn update(
        &self,
        stress: &Tensor3,
        strain_increment: &Tensor3,
        spin_increment: &Tensor3,
    ) -> StressUpdate {
        StressUpdate::elastic(stress + self.stress_rate(stress, strain_increment, spin_increment))
    }

    fn yield_function(&self, _stress: &Tensor3) -> Option<Real> {
        None
    }

    fn elastic(&self) -> &ElasticConstants {
        &self.elastic
    }
}
