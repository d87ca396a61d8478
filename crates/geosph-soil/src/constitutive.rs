//! The constitutive interface of the soil models (the scene-level choice of a model is
//! [`crate::model`]).
//!
//! One explicit step of every model takes σ_n, the strain increment Δε = ε̇ Δt (symmetric 3×3)
//! and the spin increment Δω = ω Δt (skew 3×3), and returns σ_{n+1} with the plastic strain
//! increment. The SPH integrator computes ε̇ and ω from the particle's velocity gradient
//! ([`crate::kinematics`]) and calls [`Constitutive::update`] once per stress update.

use geosph_core::{Real, Tensor3};

use crate::material::ElasticConstants;

/// Which part of the model the step ended in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Response {
    /// No plastic flow: σ_{n+1} = σ_n + Jaumann term + Dᵉ:Δε.
    Elastic,
    /// Plastic flow on the smooth part of the yield surface (the cone).
    Cone,
    /// The stress was returned to the apex of the cone (hydrostatic tension limit).
    Apex,
}

/// The result of one constitutive step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StressUpdate {
    /// σ_{n+1}.
    pub stress: Tensor3,
    /// Δεᵖ = Δε − Cᵉ:(σ_{n+1} − σ̃_n), with σ̃_n = σ_n + ω·σ_n − σ_n·ω (Δω) the rotated stress:
    /// the part of the strain increment the elastic law does not carry. Exactly zero for
    /// [`Response::Elastic`].
    pub plastic_strain_increment: Tensor3,
    /// The equivalent plastic strain increment Δε̄ᵖ = √(2/3 Δεᵖ:Δεᵖ) (von Mises measure,
    /// Hill 1950), which the caller accumulates (e.g. `SoilFields::plastic_strain`).
    pub equivalent_plastic_strain_increment: Real,
    /// Where the step ended.
    pub response: Response,
}

impl StressUpdate {
    /// An elastic step to `stress`.
    pub fn elastic(stress: Tensor3) -> Self {
        Self {
            stress,
            plastic_strain_increment: Tensor3::zeros(),
            equivalent_plastic_strain_increment: 0.0,
            response: Response::Elastic,
        }
    }

    /// A step from the rotated stress σ̃_n to `stress` under the strain increment Δε, with
    /// the plastic strain computed as Δε − Cᵉ:(σ_{n+1} − σ̃_n).
    #[inline]
    pub fn with_plastic_strain(
        elastic: &ElasticConstants,
        rotated_stress: &Tensor3,
        stress: Tensor3,
        strain_increment: &Tensor3,
        response: Response,
    ) -> Self {
        if response == Response::Elastic {
            return Self::elastic(stress);
        }
        let plastic = strain_increment - elastic.strain_increment(&(stress - rotated_stress));
        Self {
            stress,
            plastic_strain_increment: plastic,
            equivalent_plastic_strain_increment: (2.0 / 3.0 * plastic.norm_squared()).sqrt(),
            response,
        }
    }
}

/// A pointwise constitutive model for an explicit stress update.
///
/// Implementations are stateless apart from their parameters (perfect plasticity needs no
/// internal variables); the stress and the accumulated plastic strain live with the caller.
pub trait Constitutive: Send + Sync {
    /// The model's name, e.g. `drucker-prager-bui2008`.
    fn name(&self) -> &'static str;

    /// One explicit step: σ_n, Δε = ε̇ Δt (symmetric), Δω = ω Δt (skew) → σ_{n+1}.
    ///
    /// The Jaumann term Δω·σ_n − σ_n·Δω is added to σ_n before the constitutive part
    /// (forward Euler in the rotation, as Bui et al. 2008 integrate it).
    fn update(
        &self,
        stress: &Tensor3,
        strain_increment: &Tensor3,
        spin_increment: &Tensor3,
    ) -> StressUpdate;

    /// The yield function f(σ) (negative inside the elastic domain), `None` for a model
    /// without one.
    fn yield_function(&self, stress: &Tensor3) -> Option<Real>;

    /// The elastic constants (for the time-step bound and for tests).
    fn elastic(&self) -> &ElasticConstants;
}
