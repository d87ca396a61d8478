//! Elastic–perfectly plastic Drucker–Prager soil matched to Mohr–Coulomb in plane strain, with
//! two ways to integrate a plastic step.

use geosph_core::{Real, Tensor3};
use serde::{Deserialize, Serialize};

use crate::constitutive::{Constitutive, Response, StressUpdate};
use crate::invariants::{deviator, first_invariant};
use crate::kinematics::jaumann_rate;
use crate::material::{
    ConeMatch, DruckerPragerConstants, ElasticConstants, MaterialError, SoilMaterial,
};

/// A stress is treated as on the yield surface when f ≥ −`YIELD_TOLERANCE` × (k_c + α_φ|I₁| +
/// √J₂). After either return f is zero to round-off (≈ 1e-16 of that scale).
pub const YIELD_TOLERANCE: Real = 1e-9;

/// How a plastic step is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ReturnAlgorithm {
    /// Bui et al. (2008): forward Euler on the continuum elastoplastic rate
    /// ([`DruckerPragerBui2008::stress_rate`]), then the tension-cracking treatment and the
    /// stress scaling back to the yield surface ([`DruckerPragerBui2008::bui2008_correction`]).
    Bui2008,
    /// Closest-point return in the energy norm (backward Euler; Simo & Hughes 1998,
    /// Computational Inelasticity, Ch. 3; de Souza Neto, Perić & Owen 2008, Computational
    /// Methods for Plasticity, Sect. 8.3 for the Drucker–Prager cone and apex): elastic
    /// predictor, then [`DruckerPragerBui2008::consistent_return`].
    ConsistentReturn,
}

/// Drucker–Prager elastic–perfectly plastic soil after Bui, Fukagawa, Sako & Ohno (2008),
/// "Lagrangian meshfree particles method (SPH) for large deformation and failure flows of
/// geomaterial using elastic–plastic soil constitutive model", Int. J. Numer. Anal. Meth.
/// Geomech. 32:1537–1570.
///
/// Yield function f = √J₂ + α_φ I₁ − k_c, plastic potential g = √J₂ + α_ψ I₁ (tension
/// positive; constants in [`DruckerPragerConstants`]). The elastoplastic stress rate is
///
/// dσ/dt = ω·σ − σ·ω + 2G ė + K ε̇_kk 1 − λ̇ (3K α_ψ 1 + (G/√J₂) s),
///
/// λ̇ = (3 α_φ K ε̇_kk + (G/√J₂) s:ε̇) / (9 K α_φ α_ψ + G)  when f = 0 and λ̇ > 0, else λ̇ = 0
///
/// (Bui et al. 2008, Sect. 3.2, with α_ψ in place of the paper's 3 sin ψ; ψ = φ is their
/// associated form with 9Kα_φ² + G in the denominator). Both [`ReturnAlgorithm`]s share the
/// elastic law, the Jaumann term and the yield surface; they differ only in how a step that
/// leaves the elastic domain is brought back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerPragerBui2008 {
    material: SoilMaterial,
    elastic: ElasticConstants,
    surface: DruckerPragerConstants,
    matching: ConeMatch,
    algorithm: ReturnAlgorithm,
}

impl DruckerPragerBui2008 {
    /// The model of a validated `material`, integrated with `algorithm`, with the cone of
    /// Bui et al. (2008) ([`ConeMatch::Associated`]; see [`Self::with_matching`]).
    pub fn new(material: SoilMaterial, algorithm: ReturnAlgorithm) -> Result<Self, MaterialError> {
        material.validate()?;
        Ok(Self {
            material,
            elastic: material.elastic(),
            surface: material.drucker_prager(),
            matching: ConeMatch::Associated,
            algorithm,
        })
    }

    /// The same material with the cone matched to Mohr–Coulomb by `matching`.
    pub fn with_matching(mut self, matching: ConeMatch) -> Self {
        self.surface = self.material.drucker_prager_matched(matching);
        self.matching = matching;
        self
    }

    /// How the cone is matched to Mohr–Coulomb.
    pub fn matching(&self) -> ConeMatch {
        self.matching
    }

    /// The parameters.
    pub fn material(&self) -> &SoilMaterial {
        &self.material
    }

    /// α_φ, k_c, α_ψ.
    pub fn constants(&self) -> &DruckerPragerConstants {
        &self.surface
    }

    /// The return algorithm.
    pub fn algorithm(&self) -> ReturnAlgorithm {
        self.algorithm
    }

    /// The same material with another return algorithm.
    pub fn with_algorithm(mut self, algorithm: ReturnAlgorithm) -> Self {
        self.algorithm = algorithm;
        self
    }

    /// The constitutive (objective) part of the Bui et al. (2008) rate and its plastic
    /// multiplier: Dᵉ:ε̇ − λ̇ Dᵉ:∂g/∂σ with Dᵉ:∂g/∂σ = 3Kα_ψ 1 + (G/√J₂) s and
    /// λ̇ = (∂f/∂σ : Dᵉ : ε̇) / (∂f/∂σ : Dᵉ : ∂g/∂σ) = (3α_φ K ε̇_kk + (G/√J₂) s:ε̇) /
    /// (9Kα_φα_ψ + G), applied only when σ is on the yield surface (f within
    /// [`YIELD_TOLERANCE`]) and λ̇ > 0. At the apex (√J₂ = 0) the gradient of f is undefined:
    /// the rate is elastic there and the corrections of
    /// [`DruckerPragerBui2008::bui2008_correction`] take over.
    ///
    /// Returns (rate, λ̇). Linear in ε̇: pass Δε to get the increment and Δλ.
    pub fn elastoplastic_rate(&self, stress: &Tensor3, strain_rate: &Tensor3) -> (Tensor3, Real) {
        let elastic_rate = self.elastic.stress_increment(strain_rate);
        // The invariants once for √J₂, the scale and f.
        let s = deviator(stress);
        let sqrt_j2 = (0.5 * s.norm_squared()).sqrt();
        let i1 = first_invariant(stress);
        let scale = self.surface.stress_scale(i1, sqrt_j2);
        let f = self.surface.yield_function_of(i1, sqrt_j2);
        if f < -YIELD_TOLERANCE * scale || sqrt_j2 <= 1e-14 * scale || sqrt_j2 == 0.0 {
            return (elastic_rate, 0.0);
        }
        let (k, g) = (self.elastic.bulk_modulus, self.elastic.shear_modulus);
        let (alpha_phi, alpha_psi) = (self.surface.alpha_phi, self.surface.alpha_psi);
        let lambda_dot = (3.0 * alpha_phi * k * strain_rate.trace()
            + g / sqrt_j2 * s.dot(strain_rate))
            / (9.0 * k * alpha_phi * alpha_psi + g);
        if lambda_dot <= 0.0 {
            return (elastic_rate, 0.0);
        }
        let flow = Tensor3::identity() * (3.0 * k * alpha_psi) + s * (g / sqrt_j2);
        (elastic_rate - flow * lambda_dot, lambda_dot)
    }

    /// The full material stress rate of Bui et al. (2008): the Jaumann term ω·σ − σ·ω plus
    /// [`DruckerPragerBui2008::elastoplastic_rate`]. For integrators that integrate dσ/dt
    /// themselves; apply [`DruckerPragerBui2008::bui2008_correction`] after each update.
    pub fn stress_rate(&self, stress: &Tensor3, strain_rate: &Tensor3, spin: &Tensor3) -> Tensor3 {
        jaumann_rate(stress, spin) + self.elastoplastic_rate(stress, strain_rate).0
    }

    /// The two corrections Bui et al. (2008) apply after each stress update:
    ///
    /// 1. *Tension cracking*: if −α_φ I₁ + k_c < 0 (beyond the apex), the normal stresses are
    ///    shifted by the same amount, σ_ii ← σ_ii − (I₁ − k_c/α_φ)/3, which puts I₁ on the apex
    ///    value k_c/α_φ and leaves the deviator unchanged (φ > 0 only; a φ = 0 cylinder has no
    ///    apex).
    /// 2. *Stress scaling*: if −α_φ I₁ + k_c < √J₂, the deviator is scaled back to the surface,
    ///    s ← r s with r = (−α_φ I₁ + k_c)/√J₂, at constant I₁.
    ///
    /// After (1) the scaling ratio is 0, so a state beyond the apex ends exactly at the apex
    /// (σ = 0 when c = 0). Returns the corrected stress and [`Response::Apex`] if (1) acted,
    /// [`Response::Cone`] if only (2) acted, else [`Response::Elastic`].
    pub fn bui2008_correction(&self, stress: &Tensor3) -> (Tensor3, Response) {
        let mut corrected = *stress;
        let mut response = Response::Elastic;
        if let Some(apex) = self.surface.apex_first_invariant() {
            let i1 = first_invariant(&corrected);
            if i1 > apex {
                corrected -= Tensor3::identity() * ((i1 - apex) / 3.0);
                response = Response::Apex;
            }
        }
        let i1 = first_invariant(&corrected);
        let s = deviator(&corrected);
        let sqrt_j2 = (0.5 * s.norm_squared()).sqrt();
        let limit = (self.surface.k_c - self.surface.alpha_phi * i1).max(0.0);
        if sqrt_j2 > limit {
            corrected = s * (limit / sqrt_j2) + Tensor3::identity() * (i1 / 3.0);
            if response == Response::Elastic {
                response = Response::Cone;
            }
        }
        (corrected, response)
    }

    /// The closest-point return of a trial stress σ^tr (elastic predictor) for perfect
    /// plasticity, in closed form (de Souza Neto, Perić & Owen 2008, Sect. 8.3.3, without
    /// hardening):
    ///
    /// - f(σ^tr) ≤ 0: elastic, σ = σ^tr.
    /// - cone: Δλ = f(σ^tr) / (G + 9Kα_φα_ψ), s = (1 − GΔλ/√J₂^tr) s^tr,
    ///   I₁ = I₁^tr − 9Kα_ψ Δλ, valid while √J₂^tr − GΔλ ≥ 0;
    /// - apex otherwise: σ = k_c/(3α_φ) 1 (σ = 0 when c = 0).
    ///
    /// The return direction is Dᵉ:∂g/∂σ = 3Kα_ψ 1 + (G/√J₂) s, so with ψ = 0 the cone return
    /// is radial in the deviatoric plane at constant I₁ — the same as Bui's stress scaling.
    pub fn consistent_return(&self, trial: &Tensor3) -> (Tensor3, Response) {
        let f = self.surface.yield_function(trial);
        if f <= 0.0 {
            return (*trial, Response::Elastic);
        }
        let (k, g) = (self.elastic.bulk_modulus, self.elastic.shear_modulus);
        let (alpha_phi, alpha_psi) = (self.surface.alpha_phi, self.surface.alpha_psi);
        let delta_lambda = f / (g + 9.0 * k * alpha_phi * alpha_psi);
        let i1 = first_invariant(trial);
        let s = deviator(trial);
        let sqrt_j2 = (0.5 * s.norm_squared()).sqrt();
        let returned_sqrt_j2 = sqrt_j2 - g * delta_lambda;
        if alpha_phi > 0.0 && returned_sqrt_j2 < 0.0 {
            let apex = self.surface.k_c / (3.0 * alpha_phi);
            return (Tensor3::identity() * apex, Response::Apex);
        }
        let ratio = if sqrt_j2 > 0.0 {
            returned_sqrt_j2.max(0.0) / sqrt_j2
        } else {
            0.0
        };
        let returned =
            s * ratio + Tensor3::identity() * ((i1 - 9.0 * k * alpha_psi * delta_lambda) / 3.0);
        (returned, Response::Cone)
    }
}

impl Constitutive for DruckerPragerBui2008 {
    fn name(&self) -> &'static str {
        "drucker-prager-bui2008"
    }

    #[inline]
    fn update(
        &self,
        stress: &Tensor3,
        strain_increment: &Tensor3,
        spin_increment: &Tensor3,
    ) -> StressUpdate {
        let rotated = stress + jaumann_rate(stress, spin_increment);
        let (updated, response) = match self.algorithm {
            ReturnAlgorithm::Bui2008 => {
                let (increment, delta_lambda) = self.elastoplastic_rate(stress, strain_increment);
                let (corrected, response) = self.bui2008_correction(&(rotated + increment));
                let response = if response == Response::Elastic && delta_lambda > 0.0 {
                    Response::Cone
                } else {
                    response
                };
                (corrected, response)
            }
            ReturnAlgorithm::ConsistentReturn => {
                self.consistent_return(&(rotated + self.elastic.stress_increment(strain_increment)))
            }
        };
        StressUpdate::with_plastic_strain(
            &self.elastic,
            &rotated,
            updated,
            strain_increment,
            response,
        )
    }

    fn yield_function(&self, stress: &Tensor3) -> Option<Real> {
        Some(self.surface.yield_function(stress))
    }

    fn elastic(&self) -> &ElasticConstants {
        &self.elastic
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const P0: Real = 100e3;

    fn model(
        cohesion: Real,
        dilatancy_deg: Real,
        algorithm: ReturnAlgorithm,
    ) -> DruckerPragerBui2008 {
        let material = SoilMaterial::new(20e6, 0.3, 30.0, cohesion, dilatancy_deg).unwrap();
        DruckerPragerBui2008::new(material, algorithm).unwrap()
    }

    /// Isotropic p₀ plus a pure shear τ on xy.
    fn confined_shear(tau: Real) -> Tensor3 {
        let mut stress = Tensor3::identity() * -P0;
        stress[(0, 1)] = tau;
        stress[(1, 0)] = tau;
        stress
    }

    fn shear_strength(model: &DruckerPragerBui2008) -> Real {
        model.constants().k_c + 3.0 * model.constants().alpha_phi * P0
    }

    #[test]
    fn elastic_step_is_hookes_law() {
        for algorithm in [ReturnAlgorithm::Bui2008, ReturnAlgorithm::ConsistentReturn] {
            let m = model(5e3, 0.0, algorithm);
            let strain = Tensor3::new(-1e-5, 2e-6, 0.0, 2e-6, 3e-6, 0.0, 0.0, 0.0, 0.0);
            let update = m.update(&confined_shear(1e3), &strain, &Tensor3::zeros());
            assert_eq!(update.response, Response::Elastic);
            assert_eq!(update.equivalent_plastic_strain_increment, 0.0);
            let expected = confined_shear(1e3) + m.elastic().stress_increment(&strain);
            assert_relative_eq!(update.stress, expected, epsilon = 1e-9);
        }
    }

    #[test]
    fn continuum_rate_is_tangent_to_the_yield_surface() {
        // On the surface the plastic rate satisfies the consistency condition ∂f/∂σ : σ̇ = 0.
        for dilatancy in [0.0, 10.0, 30.0] {
            let m = model(5e3, dilatancy, ReturnAlgorithm::Bui2008);
            let stress = confined_shear(shear_strength(&m));
            let strain_rate = Tensor3::new(1e-3, 4e-3, 0.0, 4e-3, -2e-3, 0.0, 0.0, 0.0, 0.0);
            let (rate, lambda_dot) = m.elastoplastic_rate(&stress, &strain_rate);
            assert!(lambda_dot > 0.0);
            let s = deviator(&stress);
            let sqrt_j2 = (0.5 * s.norm_squared()).sqrt();
            let normal = Tensor3::identity() * m.constants().alpha_phi + s / (2.0 * sqrt_j2);
            assert_relative_eq!(normal.dot(&rate), 0.0, epsilon = 1e-9 * rate.norm());
        }
    }

    #[test]
    fn unloading_from_the_surface_is_elastic() {
        let m = model(5e3, 0.0, ReturnAlgorithm::Bui2008);
        let stress = confined_shear(shear_strength(&m));
        let mut strain = Tensor3::zeros();
        strain[(0, 1)] = -1e-5;
        strain[(1, 0)] = -1e-5;
        let (_, lambda) = m.elastoplastic_rate(&stress, &strain);
        assert_eq!(lambda, 0.0);
    }

    #[test]
    fn cone_return_lands_on_the_surface_with_the_flow_rule() {
        for dilatancy in [0.0, 15.0, 30.0] {
            let m = model(5e3, dilatancy, ReturnAlgorithm::ConsistentReturn);
            let from = confined_shear(0.5 * shear_strength(&m));
            let strain = Tensor3::new(-2e-4, 3e-3, 0.0, 3e-3, 1e-4, 0.0, 0.0, 0.0, 0.0);
            let update = m.update(&from, &strain, &Tensor3::zeros());
            assert_eq!(update.response, Response::Cone);
            let f = m.yield_function(&update.stress).unwrap();
            assert!(f.abs() < 1e-9 * P0, "f = {f}");
            // Δεᵖ = Δλ (α_ψ 1 + s/(2√J₂)): volumetric part 3α_ψΔλ, deviatoric norm Δλ/√2.
            let plastic = update.plastic_strain_increment;
            let deviatoric = deviator(&plastic);
            let delta_lambda = deviatoric.norm() * 2.0_f64.sqrt();
            assert_relative_eq!(
                plastic.trace(),
                3.0 * m.constants().alpha_psi * delta_lambda,
                epsilon = 1e-12
            );
            let s = deviator(&update.stress);
            assert_relative_eq!(deviatoric / deviatoric.norm(), s / s.norm(), epsilon = 1e-9);
        }
    }

    #[test]
    fn tension_without_cohesion_returns_to_zero_stress() {
        for algorithm in [ReturnAlgorithm::Bui2008, ReturnAlgorithm::ConsistentReturn] {
            let m = model(0.0, 0.0, algorithm);
            let strain = Tensor3::new(1e-2, 2e-3, 0.0, 2e-3, 5e-3, 0.0, 0.0, 0.0, 0.0);
            for from in [
                Tensor3::zeros(),
                Tensor3::identity() * -10.0,
                confined_shear(0.0),
            ] {
                let update = m.update(&from, &strain, &Tensor3::zeros());
                assert_eq!(update.response, Response::Apex, "{algorithm:?}");
                assert!(update.stress.norm() <= 1e-12 * P0, "{:?}", update.stress);
            }
        }
    }

    #[test]
    fn tension_with_cohesion_returns_to_the_apex() {
        for algorithm in [ReturnAlgorithm::Bui2008, ReturnAlgorithm::ConsistentReturn] {
            let m = model(5e3, 0.0, algorithm);
            let apex = m.constants().k_c / (3.0 * m.constants().alpha_phi);
            assert_relative_eq!(
                apex,
                5e3 / 30.0_f64.to_radians().tan(),
                max_relative = 1e-12
            );
            let strain = Tensor3::identity() * 1e-3;
            let update = m.update(&Tensor3::zeros(), &strain, &Tensor3::zeros());
            assert_eq!(update.response, Response::Apex);
            assert_relative_eq!(update.stress, Tensor3::identity() * apex, epsilon = 1e-9);
        }
    }

    #[test]
    fn algorithms_agree_from_an_elastic_state_without_dilatancy() {
        // From inside the cone Bui's step is an elastic predictor plus stress scaling at
        // constant I₁; with ψ = 0 the closest-point return is the same radial return.
        let bui = model(5e3, 0.0, ReturnAlgorithm::Bui2008);
        let consistent = bui.with_algorithm(ReturnAlgorithm::ConsistentReturn);
        let from = confined_shear(0.3 * shear_strength(&bui));
        let strain = Tensor3::new(-4e-4, 5e-3, 1e-4, 5e-3, 7e-4, -3e-4, 1e-4, -3e-4, 0.0);
        let a = bui.update(&from, &strain, &Tensor3::zeros());
        let b = consistent.update(&from, &strain, &Tensor3::zeros());
        assert_eq!(a.response, Response::Cone);
        assert_eq!(b.response, Response::Cone);
        assert_relative_eq!(a.stress, b.stress, epsilon = 1e-12 * P0);
    }

    #[test]
    fn algorithms_differ_at_second_order_from_the_surface() {
        // From a point on the cone with a non-coaxial increment, Bui's tangent step + scaling
        // and the closest-point return differ by O(|Δε|²).
        let bui = model(5e3, 10.0, ReturnAlgorithm::Bui2008);
        let consistent = bui.with_algorithm(ReturnAlgorithm::ConsistentReturn);
        let from = confined_shear(shear_strength(&bui));
        let direction = Tensor3::new(1.0, 0.5, 0.0, 0.5, -1.5, 0.0, 0.0, 0.0, 0.0);
        let difference = |h: Real| {
            let a = bui.update(&from, &(direction * h), &Tensor3::zeros());
            let b = consistent.update(&from, &(direction * h), &Tensor3::zeros());
            (a.stress - b.stress).norm()
        };
        let (d1, d2) = (difference(1e-4), difference(2e-4));
        let order = (d2 / d1).log2();
        assert!(
            (order - 2.0).abs() < 0.1,
            "order {order}, d = {d1:e}, {d2:e}"
        );
    }
}
