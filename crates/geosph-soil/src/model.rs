//! The scene-level choice of a soil model: [`ConstitutiveConfig`], as written in RON, and
//! [`SoilModel`], the model it builds.

use geosph_core::{Real, Tensor3};
use serde::{Deserialize, Serialize};

use crate::constitutive::{Constitutive, StressUpdate};
use crate::drucker_prager::{DruckerPragerBui2008, ReturnAlgorithm};
use crate::elastic::LinearElastic;
use crate::material::{ConeMatch, ElasticConstants, MaterialError, SoilMaterial};

/// The constitutive model of a soil scene, as it is written in RON.
///
/// ```ron
/// DruckerPrager(
///     material: (youngs_modulus: 0.84e6, poisson_ratio: 0.3, friction_angle_deg: 19.8,
///                cohesion: 0.0, dilatancy_angle_deg: 0.0),
///     algorithm: Bui2008,
/// )
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ConstitutiveConfig {
    /// [`LinearElastic`].
    LinearElastic {
        /// E.
        youngs_modulus: Real,
        /// ν.
        poisson_ratio: Real,
    },
    /// [`DruckerPragerBui2008`].
    DruckerPrager {
        /// E, ν, φ, c, ψ.
        material: SoilMaterial,
        /// How plastic steps are integrated.
        algorithm: ReturnAlgorithm,
        /// How the cone is matched to Mohr–Coulomb in plane strain (default `Associated`, as
        /// Bui et al. 2008; `FlowRule` makes non-associated plane-strain flow Mohr–Coulomb's).
        #[serde(default)]
        cone: ConeMatch,
    },
}

impl ConstitutiveConfig {
    /// Validates the parameters and builds the model.
    pub fn build(&self) -> Result<SoilModel, MaterialError> {
        Ok(match *self {
            Self::LinearElastic {
                youngs_modulus,
                poisson_ratio,
            } => SoilModel::LinearElastic(LinearElastic::new(youngs_modulus, poisson_ratio)?),
            Self::DruckerPrager {
                material,
                algorithm,
                cone,
            } => SoilModel::DruckerPrager(
                DruckerPragerBui2008::new(material, algorithm)?.with_matching(cone),
            ),
        })
    }
}

/// A built constitutive model; dispatches with one `match` per call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SoilModel {
    /// [`LinearElastic`].
    LinearElastic(LinearElastic),
    /// [`DruckerPragerBui2008`].
    DruckerPrager(DruckerPragerBui2008),
}

impl Constitutive for SoilModel {
    fn name(&self) -> &'static str {
        match self {
            Self::LinearElastic(model) => model.name(),
            Self::DruckerPrager(model) => model.name(),
        }
    }

    #[inline]
    fn update(
        &self,
        stress: &Tensor3,
        strain_increment: &Tensor3,
        spin_increment: &Tensor3,
    ) -> StressUpdate {
        match self {
            Self::LinearElastic(model) => model.update(stress, strain_increment, spin_increment),
            Self::DruckerPrager(model) => model.update(stress, strain_increment, spin_increment),
        }
    }

    fn yield_function(&self, stress: &Tensor3) -> Option<Real> {
        match self {
            Self::LinearElastic(model) => model.yield_function(stress),
            Self::DruckerPrager(model) => model.yield_function(stress),
        }
    }

    fn elastic(&self) -> &ElasticConstants {
        match self {
            Self::LinearElastic(model) => model.elastic(),
            Self::DruckerPrager(model) => model.elastic(),
        }
    }
}

impl SoilModel {
    /// The ratio K₀ = σ_h/σ_v of soil at rest: Jaky's (1944) 1 − sin φ for Drucker–Prager,
    /// ν/(1 − ν) (no lateral strain) for the elastic model.
    pub fn lateral_ratio_at_rest(&self) -> Real {
        match self {
            Self::LinearElastic(model) => {
                let nu = model.elastic().poisson_ratio;
                nu / (1.0 - nu)
            }
            Self::DruckerPrager(model) => {
                1.0 - model.material().friction_angle_deg.to_radians().sin()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_reads_from_ron_and_builds() {
        let text = "DruckerPrager(material: (youngs_modulus: 0.84e6, poisson_ratio: 0.3, \
                    friction_angle_deg: 19.8, cohesion: 0.0, dilatancy_angle_deg: 0.0), \
                    algorithm: ConsistentReturn)";
        let config: ConstitutiveConfig = ron::from_str(text).unwrap();
        let model = config.build().unwrap();
        assert_eq!(model.name(), "drucker-prager-bui2008");
        assert!(model.yield_function(&Tensor3::zeros()).is_some());

        let elastic: ConstitutiveConfig =
            ron::from_str("LinearElastic(youngs_modulus: 1e6, poisson_ratio: 0.25)").unwrap();
        assert_eq!(elastic.build().unwrap().name(), "linear-elastic");

        let unknown = ron::from_str::<ConstitutiveConfig>(
            "LinearElastic(youngs_modulus: 1e6, poisson_ratio: 0.25, density: 2.0)",
        );
        assert!(unknown.unwrap_err().to_string().contains("density"));
    }

    #[test]
    fn build_rejects_out_of_range_parameters() {
        let config = ConstitutiveConfig::LinearElastic {
            youngs_modulus: 1e6,
            poisson_ratio: 0.5,
        };
        assert_eq!(config.build().unwrap_err().parameter, "poisson_ratio");
    }
}
