//! Soil parameters, elastic constants and the Drucker–Prager constants matched to Mohr–Coulomb
//! in plane strain.

use geosph_core::{Real, Tensor3};
use serde::{Deserialize, Serialize};

use crate::invariants::{first_invariant, second_deviatoric_invariant};

/// A material parameter outside its allowed range (or not finite).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("soil material: {parameter} = {value} is outside the allowed range {allowed}")]
pub struct MaterialError {
    /// The parameter's name as scene files spell it (e.g. `poisson_ratio`).
    pub parameter: &'static str,
    /// The rejected value.
    pub value: Real,
    /// The allowed range, e.g. `[0, 0.5)`.
    pub allowed: &'static str,
}

fn check(
    parameter: &'static str,
    value: Real,
    allowed: &'static str,
    ok: bool,
) -> Result<(), MaterialError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(MaterialError {
            parameter,
            value,
            allowed,
        })
    }
}

/// The parameters of an elastic–perfectly plastic Mohr–Coulomb soil, as a scene carries them.
///
/// Angles are in degrees. Ranges ([`SoilMaterial::validate`]): E > 0, ν ∈ [0, 0.5),
/// φ ∈ [0°, 90°), c ≥ 0, 0 ≤ ψ ≤ φ. Units are the caller's (SI: Pa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SoilMaterial {
    /// Young's modulus E.
    pub youngs_modulus: Real,
    /// Poisson's ratio ν.
    pub poisson_ratio: Real,
    /// Internal friction angle φ in degrees.
    pub friction_angle_deg: Real,
    /// Cohesion c.
    pub cohesion: Real,
    /// Dilatancy angle ψ in degrees (0: no plastic volume change; φ: associated flow).
    pub dilatancy_angle_deg: Real,
}

impl SoilMaterial {
    /// A validated material (see [`SoilMaterial::validate`] for the ranges).
    pub fn new(
        youngs_modulus: Real,
        poisson_ratio: Real,
        friction_angle_deg: Real,
        cohesion: Real,
        dilatancy_angle_deg: Real,
    ) -> Result<Self, MaterialError> {
        let material = Self {
            youngs_modulus,
            poisson_ratio,
            friction_angle_deg,
            cohesion,
            dilatancy_angle_deg,
        };
        material.validate()?;
        Ok(material)
    }

    /// Checks E > 0, ν ∈ [0, 0.5), φ ∈ [0°, 90°), c ≥ 0 and 0 ≤ ψ ≤ φ (all finite); the error
    /// names the first parameter out of range.
    pub fn validate(&self) -> Result<(), MaterialError> {
        ElasticConstants::new(self.youngs_modulus, self.poisson_ratio)?;
        let phi = self.friction_angle_deg;
        check(
            "friction_angle_deg",
            phi,
            "[0, 90) degrees",
            (0.0..90.0).contains(&phi),
        )?;
        check("cohesion", self.cohesion, "[0, inf)", self.cohesion >= 0.0)?;
        let psi = self.dilatancy_angle_deg;
        check(
            "dilatancy_angle_deg",
            psi,
            "[0, friction_angle_deg] degrees",
            psi >= 0.0 && psi <= phi,
        )
    }

    /// The elastic constants of E and ν (call on a validated material).
    pub fn elastic(&self) -> ElasticConstants {
        ElasticConstants::from_unchecked(self.youngs_modulus, self.poisson_ratio)
    }

    /// The Drucker–Prager constants α_φ, k_c, α_ψ matched to Mohr–Coulomb in plane strain as
    /// Bui et al. (2008) match them ([`ConeMatch::Associated`]).
    pub fn drucker_prager(&self) -> DruckerPragerConstants {
        self.drucker_prager_matched(ConeMatch::Associated)
    }

    /// The Drucker–Prager constants α_φ, k_c, α_ψ with the plane-strain match `matching`.
    pub fn drucker_prager_matched(&self, matching: ConeMatch) -> DruckerPragerConstants {
        let (phi, psi) = (
            self.friction_angle_deg.to_radians(),
            self.dilatancy_angle_deg.to_radians(),
        );
        match matching {
            ConeMatch::Associated => {
                DruckerPragerConstants::plane_strain_match(phi, self.cohesion, psi)
            }
            ConeMatch::FlowRule => {
                DruckerPragerConstants::plane_strain_flow_match(phi, self.cohesion, psi)
            }
        }
    }
}

/// Isotropic linear elasticity: E, ν and the derived G, K, λ.
///
/// G = E / (2(1 + ν)), K = E / (3(1 − 2ν)), λ = E ν / ((1 + ν)(1 − 2ν)). In plane strain the
/// (xx, yy, zz) block of the stiffness is E/((1 + ν)(1 − 2ν)) [[1−ν, ν, ν], [ν, 1−ν, ν],
/// [ν, ν, 1−ν]] (the design note `002` has the factor E/((1 + ν)(1 − ν)), which is wrong).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticConstants {
    /// E.
    pub youngs_modulus: Real,
    /// ν.
    pub poisson_ratio: Real,
    /// Shear modulus G = E / (2(1 + ν)).
    pub shear_modulus: Real,
    /// Bulk modulus K = E / (3(1 − 2ν)).
    pub bulk_modulus: Real,
    /// Lamé's first parameter λ = K − 2G/3.
    pub lame_lambda: Real,
}

impl ElasticConstants {
    /// Validated constants: E > 0 and ν ∈ [0, 0.5).
    pub fn new(youngs_modulus: Real, poisson_ratio: Real) -> Result<Self, MaterialError> {
        check(
            "youngs_modulus",
            youngs_modulus,
            "(0, inf)",
            youngs_modulus > 0.0,
        )?;
        check(
            "poisson_ratio",
            poisson_ratio,
            "[0, 0.5)",
            (0.0..0.5).contains(&poisson_ratio),
        )?;
        Ok(Self::from_unchecked(youngs_modulus, poisson_ratio))
    }

    fn from_unchecked(youngs_modulus: Real, poisson_ratio: Real) -> Self {
        let (e, nu) = (youngs_modulus, poisson_ratio);
        Self {
            youngs_modulus: e,
            poisson_ratio: nu,
            shear_modulus: e / (2.0 * (1.0 + nu)),
            bulk_modulus: e / (3.0 * (1.0 - 2.0 * nu)),
            lame_lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        }
    }

    /// Hooke's law Δσ = Dᵉ:Δε = λ tr(Δε) 1 + 2G Δε (Δε symmetric; rates work the same).
    #[inline]
    pub fn stress_increment(&self, strain_increment: &Tensor3) -> Tensor3 {
        Tensor3::identity() * (self.lame_lambda * strain_increment.trace())
            + strain_increment * (2.0 * self.shear_modulus)
    }

    /// The compliance Δε = Cᵉ:Δσ = Δs/(2G) + tr(Δσ)/(9K) 1, the inverse of
    /// [`ElasticConstants::stress_increment`].
    #[inline]
    pub fn strain_increment(&self, stress_increment: &Tensor3) -> Tensor3 {
        let trace = stress_increment.trace();
        let deviator = stress_increment - Tensor3::identity() * (trace / 3.0);
        deviator / (2.0 * self.shear_modulus)
            + Tensor3::identity() * (trace / (9.0 * self.bulk_modulus))
    }

    /// The P-wave modulus K + 4G/3; √((K + 4G/3)/ρ) is the elastic wave speed that bounds the
    /// explicit time step.
    pub fn p_wave_modulus(&self) -> Real {
        self.bulk_modulus + 4.0 * self.shear_modulus / 3.0
    }
}

/// The Drucker–Prager yield surface f = √J₂ + α_φ I₁ − k_c (tension positive) and plastic
/// potential g = √J₂ + α_ψ I₁, matched to Mohr–Coulomb in plane strain (Bui et al. 2008,
/// Int. J. Numer. Anal. Meth. Geomech. 32:1537, Sect. 3.2):
///
/// α_φ = tan φ / √(9 + 12 tan²φ),  k_c = 3c / √(9 + 12 tan²φ),  α_ψ = tan ψ / √(9 + 12 tan²ψ).
///
/// The dilatancy coefficient α_ψ is the same match applied to ψ, so ψ = φ gives associated
/// flow. (Bui et al. 2008 and the design note `002` write the non-associated potential as
/// g = √J₂ + 3 I₁ sin ψ, which does not reduce to the associated rule at ψ = φ; geosph uses
/// α_ψ — see `docs/soil.md`.) The apex of the cone is at I₁ = k_c/α_φ (σ = k_c/(3α_φ) 1);
/// with c = 0 it is σ = 0, i.e. no tensile strength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerPragerConstants {
    /// α_φ.
    pub alpha_phi: Real,
    /// k_c.
    pub k_c: Real,
    /// α_ψ.
    pub alpha_psi: Real,
}

/// tan θ / √(9 + 12 tan²θ), the plane-strain match of a Mohr–Coulomb angle θ.
fn plane_strain_coefficient(angle: Real) -> Real {
    let t = angle.tan();
    t / (9.0 + 12.0 * t * t).sqrt()
}

/// Which plane-strain match of Mohr–Coulomb the Drucker–Prager cone uses.
///
/// In plane-strain plastic flow ε̇_zz = 0, and with the potential g = √J₂ + α_ψ I₁ the flow
/// settles where ∂g/∂σ_zz = 0, i.e. s_zz = −2α_ψ √J₂. There √J₂ = R/√(1 − 3α_ψ²) (R the radius
/// of the in-plane Mohr circle) and I₁ = 3p − 3α_ψ√J₂ (p the in-plane mean stress, tension
/// positive), so f = 0 reads R (1 − 3α_φα_ψ)/√(1 − 3α_ψ²) + 3α_φ p = k_c. It is Mohr–Coulomb's
/// R = c cos φ − p sin φ when 3α_φ/A = sin φ and k_c/A = c cos φ, A = (1 − 3α_φα_ψ)/√(1 − 3α_ψ²).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ConeMatch {
    /// Bui et al. (2008): α_φ = tan φ/√(9 + 12 tan²φ), k_c = 3c/√(9 + 12 tan²φ), the solution
    /// of the conditions above for associated flow (α_ψ = α_φ). With ψ < φ the cone is weaker
    /// than Mohr–Coulomb in plane-strain flow: at ψ = 0 its friction is 3α_φ instead of sin φ
    /// (0.336 against 0.342 at φ = 20°).
    #[default]
    Associated,
    /// The solution for the model's own flow rule: with D = √(1 − 3α_ψ²) + α_ψ sin φ,
    /// α_φ = sin φ/(3D) and k_c = c cos φ/D (ψ = 0: α_φ = sin φ/3, k_c = c cos φ; ψ = φ: the
    /// associated match), so that plane-strain flow is Mohr–Coulomb's for every ψ.
    FlowRule,
}

impl DruckerPragerConstants {
    /// The plane-strain match of φ, c and ψ of Bui et al. (2008) ([`ConeMatch::Associated`];
    /// angles in radians; no validation).
    pub fn plane_strain_match(friction_angle: Real, cohesion: Real, dilatancy_angle: Real) -> Self {
        let t = friction_angle.tan();
        Self {
            alpha_phi: plane_strain_coefficient(friction_angle),
            k_c: 3.0 * cohesion / (9.0 + 12.0 * t * t).sqrt(),
            alpha_psi: plane_strain_coefficient(dilatancy_angle),
        }
    }

    /// The plane-strain match of φ, c and ψ for the flow rule ([`ConeMatch::FlowRule`];
    /// angles in radians; no validation).
    pub fn plane_strain_flow_match(
        friction_angle: Real,
        cohesion: Real,
        dilatancy_angle: Real,
    ) -> Self {
        let alpha_psi = plane_strain_coefficient(dilatancy_angle);
        let (sin, cos) = friction_angle.sin_cos();
        let d = (1.0 - 3.0 * alpha_psi * alpha_psi).sqrt() + alpha_psi * sin;
        Self {
            alpha_phi: sin / (3.0 * d),
            k_c: cohesion * cos / d,
            alpha_psi,
        }
    }

    /// f(σ) = √J₂ + α_φ I₁ − k_c: negative inside (elastic), zero on the surface.
    #[inline]
    pub fn yield_function(&self, stress: &Tensor3) -> Real {
        self.yield_function_of(
            first_invariant(stress),
            second_deviatoric_invariant(stress).sqrt(),
        )
    }

    /// [`DruckerPragerConstants::yield_function`] of a stress with invariants I₁ and √J₂.
    #[inline]
    pub fn yield_function_of(&self, first_invariant: Real, sqrt_j2: Real) -> Real {
        sqrt_j2 + self.alpha_phi * first_invariant - self.k_c
    }

    /// I₁ at the apex of the cone, k_c/α_φ; `None` for φ = 0 (a cylinder, no apex).
    pub fn apex_first_invariant(&self) -> Option<Real> {
        (self.alpha_phi > 0.0).then(|| self.k_c / self.alpha_phi)
    }

    /// The stress scale k_c + α_φ|I₁| + √J₂ against which the yield function is compared, of
    /// a stress with invariants I₁ and √J₂.
    #[inline]
    pub(crate) fn stress_scale(&self, first_invariant: Real, sqrt_j2: Real) -> Real {
        self.k_c + self.alpha_phi * first_invariant.abs() + sqrt_j2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn sand() -> SoilMaterial {
        SoilMaterial::new(10e6, 0.3, 30.0, 5e3, 0.0).unwrap()
    }

    #[test]
    fn plane_strain_match_reproduces_the_validation_constants() {
        let m = SoilMaterial::new(1e6, 0.3, 30.0, 1.0, 0.0)
            .unwrap()
            .drucker_prager();
        assert_relative_eq!(m.alpha_phi, 0.16013, epsilon = 1e-5);
        assert_relative_eq!(m.k_c, 0.83205, epsilon = 1e-5);
        assert_eq!(m.alpha_psi, 0.0);
        let bars = SoilMaterial::new(0.84e6, 0.3, 19.8, 0.0, 0.0)
            .unwrap()
            .drucker_prager();
        assert_relative_eq!(bars.alpha_phi, 0.11081, epsilon = 1e-5);
        assert_eq!(bars.k_c, 0.0);
        assert_eq!(bars.apex_first_invariant(), Some(0.0));
        let associated = SoilMaterial::new(1e6, 0.3, 30.0, 1.0, 30.0)
            .unwrap()
            .drucker_prager();
        assert_eq!(associated.alpha_psi, associated.alpha_phi);
    }

    /// On the plane-strain flow state of [`ConeMatch`] (s_zz = −2α_ψ√J₂) the
    /// `FlowRule` cone is Mohr–Coulomb's R = c cos φ − p sin φ for every ψ ≤ φ, and the
    /// `Associated` one only for ψ = φ.
    #[test]
    fn flow_rule_match_is_mohr_coulomb_in_plane_strain_flow() {
        let on_mohr_coulomb = |dp: &DruckerPragerConstants, phi: Real, c: Real, p: Real| {
            let radius = c * phi.cos() - p * phi.sin();
            let a = dp.alpha_psi;
            let s_zz = -2.0 * a * radius / (1.0 - 3.0 * a * a).sqrt();
            let stress = Tensor3::from_diagonal(&nalgebra::Vector3::new(
                p + radius,
                p - radius,
                p + 1.5 * s_zz,
            ));
            dp.yield_function(&stress) / radius
        };
        for (phi_deg, psi_deg) in [(20.0, 0.0), (30.0, 10.0), (35.0, 35.0), (19.8, 0.0)] {
            let (phi, psi): (Real, Real) = (Real::to_radians(phi_deg), Real::to_radians(psi_deg));
            let (c, p) = (5e3, -40e3);
            let flow = DruckerPragerConstants::plane_strain_flow_match(phi, c, psi);
            assert!(
                on_mohr_coulomb(&flow, phi, c, p).abs() < 1e-12,
                "φ = {phi_deg}, ψ = {psi_deg}"
            );
            let bui = DruckerPragerConstants::plane_strain_match(phi, c, psi);
            let bui_error = on_mohr_coulomb(&bui, phi, c, p);
            if psi_deg == phi_deg {
                assert!(bui_error.abs() < 1e-12);
                assert_relative_eq!(flow.alpha_phi, bui.alpha_phi, epsilon = 1e-15);
                assert_relative_eq!(flow.k_c, bui.k_c, epsilon = 1e-9);
            } else {
                // The associated match lies inside Mohr–Coulomb in non-associated flow: the
                // Mohr–Coulomb limit state is beyond its cone.
                assert!(
                    bui_error > 1e-3,
                    "φ = {phi_deg}, ψ = {psi_deg}: {bui_error}"
                );
            }
        }
        let zero = DruckerPragerConstants::plane_strain_flow_match(0.0, 7.0, 0.0);
        assert_eq!((zero.alpha_phi, zero.k_c), (0.0, 7.0));
    }

    #[test]
    fn elastic_constants_are_consistent() {
        let e = sand().elastic();
        assert_relative_eq!(e.shear_modulus, 10e6 / 2.6, max_relative = 1e-14);
        assert_relative_eq!(e.bulk_modulus, 10e6 / 1.2, max_relative = 1e-14);
        assert_relative_eq!(
            e.lame_lambda,
            e.bulk_modulus - 2.0 * e.shear_modulus / 3.0,
            max_relative = 1e-14
        );
        let strain = Tensor3::new(1e-3, 2e-4, 0.0, 2e-4, -3e-3, 1e-4, 0.0, 1e-4, 5e-4);
        let back = e.strain_increment(&e.stress_increment(&strain));
        assert_relative_eq!(back, strain, epsilon = 1e-18);
    }

    #[test]
    fn plane_strain_stiffness_has_the_factor_with_one_minus_two_nu() {
        let (e, nu) = (10e6, 0.3);
        let elastic = ElasticConstants::new(e, nu).unwrap();
        let mut strain = Tensor3::zeros();
        strain[(0, 0)] = 1e-4;
        let stress = elastic.stress_increment(&strain);
        let factor = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        assert_relative_eq!(
            stress[(0, 0)],
            factor * (1.0 - nu) * 1e-4,
            max_relative = 1e-14
        );
        assert_relative_eq!(stress[(1, 1)], factor * nu * 1e-4, max_relative = 1e-14);
        assert_relative_eq!(stress[(2, 2)], factor * nu * 1e-4, max_relative = 1e-14);
        let wrong = e / ((1.0 + nu) * (1.0 - nu)) * (1.0 - nu) * 1e-4;
        assert!((stress[(0, 0)] - wrong).abs() > 0.1 * wrong);
    }

    #[test]
    fn out_of_range_parameters_are_named() {
        let cases: [(SoilMaterial, &str); 9] = [
            (
                SoilMaterial {
                    youngs_modulus: 0.0,
                    ..sand()
                },
                "youngs_modulus",
            ),
            (
                SoilMaterial {
                    youngs_modulus: Real::NAN,
                    ..sand()
                },
                "youngs_modulus",
            ),
            (
                SoilMaterial {
                    poisson_ratio: 0.5,
                    ..sand()
                },
                "poisson_ratio",
            ),
            (
                SoilMaterial {
                    poisson_ratio: -0.1,
                    ..sand()
                },
                "poisson_ratio",
            ),
            (
                SoilMaterial {
                    friction_angle_deg: 90.0,
                    ..sand()
                },
                "friction_angle_deg",
            ),
            (
                SoilMaterial {
                    friction_angle_deg: -1.0,
                    ..sand()
                },
                "friction_angle_deg",
            ),
            (
                SoilMaterial {
                    cohesion: -1.0,
                    ..sand()
                },
                "cohesion",
            ),
            (
                SoilMaterial {
                    dilatancy_angle_deg: 31.0,
                    ..sand()
                },
                "dilatancy_angle_deg",
            ),
            (
                SoilMaterial {
                    dilatancy_angle_deg: -1.0,
                    ..sand()
                },
                "dilatancy_angle_deg",
            ),
        ];
        for (material, parameter) in cases {
            let error = material.validate().unwrap_err();
            assert_eq!(error.parameter, parameter);
            let message = error.to_string();
            assert!(message.contains(parameter), "{message}");
            assert!(message.contains("allowed range"), "{message}");
        }
        assert!(sand().validate().is_ok());
        assert!(SoilMaterial::new(1.0, 0.0, 0.0, 0.0, 0.0).is_ok());
    }

    #[test]
    fn yield_function_is_zero_on_the_surface() {
        let dp = sand().drucker_prager();
        let p0 = 100e3;
        let tau = dp.k_c + 3.0 * dp.alpha_phi * p0;
        let mut stress = Tensor3::identity() * -p0;
        stress[(0, 1)] = tau;
        stress[(1, 0)] = tau;
        assert_relative_eq!(dp.yield_function(&stress), 0.0, epsilon = 1e-9);
    }

    #[test]
    fn material_reads_from_ron_and_rejects_unknown_fields() {
        let text = "(youngs_modulus: 0.84e6, poisson_ratio: 0.3, friction_angle_deg: 19.8, \
                    cohesion: 0.0, dilatancy_angle_deg: 0.0)";
        let material: SoilMaterial = ron::from_str(text).unwrap();
        assert_eq!(material.friction_angle_deg, 19.8);
        let back: SoilMaterial = ron::from_str(&ron::to_string(&material).unwrap()).unwrap();
        assert_eq!(back, material);
        let misspelt = text.replace("cohesion", "cohesoin");
        let error = ron::from_str::<SoilMaterial>(&misspelt)
            .unwrap_err()
            .to_string();
        assert!(error.contains("cohesoin"), "{error}");
    }
}
