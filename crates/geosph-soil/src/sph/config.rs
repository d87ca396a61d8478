//! Scene-level configuration of the soil solver, its validation, and the factory that builds a
//! solver from it (monomorphised over the kernel).

use geosph_core::Real;
use geosph_neighbours::SearchError;
pub use geosph_sph::ConfigError;
use geosph_sph::ParticleStart;
use geosph_sph::config_error::in_range;
use serde::{Deserialize, Serialize};

use crate::drucker_prager::ReturnAlgorithm;
use crate::material::{ConeMatch, MaterialError, SoilMaterial};
use crate::model::ConstitutiveConfig;
pub use crate::sph::search_config::StrengthReductionConfig;

/// Monaghan (1992) artificial viscosity between soil particles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArtificialViscosityConfig {
    /// α_Π (linear term), in [0, 1].
    pub alpha: Real,
    /// β_Π (quadratic term), in [0, 2].
    #[serde(default)]
    pub beta: Real,
}

/// Gray, Monaghan & Swift (2001) artificial stress against the tensile instability.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArtificialStressConfig {
    /// ε in (0, 1] (Gray et al. 2001: 0.3).
    pub epsilon: Real,
    /// The exponent n of f_ij = W(r_ij)/W(dx) in [1, 10] (Gray et al. 2001: 4).
    #[serde(default = "default_exponent")]
    pub exponent: Real,
}

fn default_exponent() -> Real {
    4.0
}

/// Diffusion of the mean stress against the checkerboard of the stress field, after Feng et al.
/// (2021), with the density following it
/// ([`MeanStressDiffusion`](crate::sph::diffusion::MeanStressDiffusion)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StressDiffusionConfig {
    /// δ of the diffusivity δ h c, in [10⁻⁶, 1] (default 0.1, as Feng et al. 2021).
    pub delta: Real,
    /// K₀ = σ_h/σ_v of the lithostatic state taken out of the stress differences, in [0, 2]
    /// (default: the model's, Jaky's 1 − sin φ or the elastic ν/(1 − ν)).
    pub lateral_ratio: Option<Real>,
}

impl Default for StressDiffusionConfig {
    fn default() -> Self {
        Self {
            delta: 0.1,
            lateral_ratio: None,
        }
    }
}

/// Stress regularisation every `every` steps (Nguyen et al. 2017).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum RegularisationConfig {
    /// σ_i ← Σ_j V_j σ_j W_ij / Σ_j V_j W_ij (zeroth order, cheap).
    Shepard {
        /// Steps between regularisations (≥ 1).
        every: usize,
    },
    /// σ_i ← Σ_j V_j σ_j W^MLS_ij with the linear MLS kernel (Nguyen et al. 2017 use every = 5).
    Mls {
        /// Steps between regularisations (≥ 1).
        every: usize,
    },
}

/// How soil slides along a wall.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum WallSlip {
    /// Bui's β rule on the whole relative velocity (no-slip wall, Bui et al. 2008).
    #[default]
    NoSlip,
    /// Bui's β rule on the normal component only; the tangential velocity is mirrored
    /// unchanged (free slip).
    FreeSlip,
    /// Free slip plus a Coulomb friction force limited by tan δ times the wall's normal push.
    Friction {
        /// Interface friction angle δ in degrees, [0, 90).
        angle_deg: Real,
    },
}

impl WallSlip {
    /// Whether soil may slide along the wall (free slip or friction): the wall then mirrors
    /// only the normal velocity and shows the soil its stress mirrored in the wall plane.
    pub fn slips(&self) -> bool {
        *self != Self::NoSlip
    }

    /// The Coulomb friction coefficient μ = tan δ of a `Friction` wall, `None` otherwise.
    pub fn friction_coefficient(&self) -> Option<Real> {
        match *self {
            Self::Friction { angle_deg } => Some(angle_deg.to_radians().tan()),
            Self::NoSlip | Self::FreeSlip => None,
        }
    }
}

/// Which stress the dummy particles carry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum WallStress {
    /// The kernel-weighted (Shepard) average of the nearest soil particles' stress
    /// (Bui et al. 2008 take the stress of the soil next to the wall).
    Shepard,
    /// The same average with each soil stress extrapolated to the dummy particle along gravity,
    /// σ_w = Σ_i [σ_i + ρ_i g·(x_i − x_w) ĝĝᵀ] W_wi / Σ_i W_wi (the stress analogue of Adami et
    /// al. 2012, eq. 27). Default: exact for a level layer at rest.
    #[default]
    Extrapolated,
}

/// The wall condition of soil scenes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SoilWallConfig {
    /// Tangential condition (default no-slip).
    pub slip: WallSlip,
    /// Stress of the dummy particles (default extrapolated along gravity).
    pub stress: WallStress,
    /// β_max of Bui's rule, in [1, 2] (default 1.5 as Bui et al. 2008).
    pub beta_max: Real,
    /// Add the soft repulsive force of Liu et al. (2012) from wall particles (default false).
    pub repulsive: bool,
    /// Apply the artificial viscosity also in soil–wall pairs, with the velocity of Bui's
    /// rule for the dummy particle (default true). Bui et al. (2008) apply it between soil
    /// particles only; then a soil particle that is alone on a wall keeps bouncing on the
    /// stress it carried when it separated (at dx = 2.5 mm 1.9 % of the collapse's particles
    /// still move faster than 1 mm/s at t = 1 s, 0.25 % with the wall term: `docs/soil.md`).
    pub viscous: bool,
}

impl Default for SoilWallConfig {
    fn default() -> Self {
        Self {
            slip: WallSlip::NoSlip,
            stress: WallStress::Extrapolated,
            beta_max: 1.5,
            repulsive: false,
            viscous: true,
        }
    }
}

/// Parameters of the soil SPH solver (the `Soil(...)` solver of a scene).
///
/// Every stabilisation term is optional and costs nothing when absent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SoilConfig {
    /// The constitutive model (default: the aluminium bars of Bui et al. 2008, E = 0.84 MPa,
    /// ν = 0.3, φ = 19.8°, c = 0, ψ = 0, Bui's return).
    pub constitutive: ConstitutiveConfig,
    /// Artificial viscosity (default α = 0.1, β = 0).
    pub artificial_viscosity: Option<ArtificialViscosityConfig>,
    /// Artificial stress (default off).
    pub artificial_stress: Option<ArtificialStressConfig>,
    /// ξ of the velocity damping F = −ξ √(E/(ρ h²)) m v of Nguyen et al. (2017) during the run
    /// (default off; they use 5 × 10⁻⁵ for column collapses).
    pub damping: Option<Real>,
    /// Stress regularisation (default off).
    pub regularisation: Option<RegularisationConfig>,
    /// Diffusion of the mean stress against the stress checkerboard (default on, δ = 0.1;
    /// `None` switches it off).
    pub stress_diffusion: Option<StressDiffusionConfig>,
    /// CSPM correction of the velocity gradient, exact for linear velocity fields also at free
    /// surfaces (default off).
    pub velocity_gradient_correction: bool,
    /// Walls.
    pub walls: SoilWallConfig,
    /// Geostatic stage before the run (default none: start from σ = 0).
    pub geostatic: Option<GeostaticConfig>,
    /// Settings of the factor-of-safety search by strength reduction, which `slope-failure
    /// --factor-of-safety` runs instead of the scene's run (default none: the search's own
    /// defaults).
    pub factor_of_safety: Option<StrengthReductionConfig>,
    /// Courant number of the elastic-wave limit, (0, 1] (default 0.2).
    pub cfl: Real,
    /// Steps between Z-order sorts (default 100; 0 never).
    pub reorder_every: usize,
    /// Verlet skin of the neighbour lists as a fraction of the support radius (default 0.1).
    pub neighbour_skin: Real,
}

impl Default for SoilConfig {
    fn default() -> Self {
        Self {
            constitutive: ConstitutiveConfig::DruckerPrager {
                material: SoilMaterial {
                    youngs_modulus: 0.84e6,
                    poisson_ratio: 0.3,
                    friction_angle_deg: 19.8,
                    cohesion: 0.0,
                    dilatancy_angle_deg: 0.0,
                },
                algorithm: ReturnAlgorithm::Bui2008,
                cone: ConeMatch::Associated,
            },
            artificial_viscosity: Some(ArtificialViscosityConfig {
                alpha: 0.1,
                beta: 0.0,
            }),
            artificial_stress: None,
            damping: None,
            regularisation: None,
            stress_diffusion: Some(StressDiffusionConfig::default()),
            velocity_gradient_correction: false,
            walls: SoilWallConfig::default(),
            geostatic: None,
            factor_of_safety: None,
            cfl: 0.2,
            reorder_every: 100,
            neighbour_skin: 0.1,
        }
    }
}

/// A box (lower and upper corner, `dimension` numbers each) of wall particles to remove at
/// release, e.g. a retaining wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReleaseBox {
    /// Lower corner.
    pub min: Vec<Real>,
    /// Upper corner.
    pub max: Vec<Real>,
}

/// Parameters of the geostatic stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GeostaticConfig {
    /// Damping ratio ζ of the fundamental mode of the soil height H: the stage damps with
    /// μ = 2ζω₁, ω₁ = πc/(2H) (shear-free column, c the P-wave speed); default 1 (critical).
    pub damping_ratio: Real,
    /// The stage ends when E_k < tolerance × ½ M (gH/c)² (the kinetic energy of the whole
    /// mass M at the particle speed gH/c of the loading wave) after at least one period
    /// 4H/c of the fundamental mode; default 10⁻⁶.
    pub kinetic_energy_tolerance: Real,
    /// Longest stage in simulated seconds (default 1); a stage that reaches it reports
    /// `converged = false`.
    pub max_time: Real,
    /// Wall particles removed at release.
    pub release: Vec<ReleaseBox>,
    /// Make every wall free-slip during the stage, as roller boundaries in a gravity-loading
    /// step (default false): walls that hold the soil by shear carry part of its weight (the
    /// silo effect of Janssen 1895), so σ_v falls short of ρ g (H − y) next to them. A
    /// cohesionless column between free-slip walls may creep instead of coming to rest.
    pub free_slip_walls: bool,
    /// The stress the stage starts from (default [`InitialStress::Zero`], gravity switched on
    /// at once).
    pub initial_stress: InitialStress,
}

/// The stress a geostatic stage starts from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum InitialStress {
    /// No stress: gravity is switched on at once and the soil settles into its state (the
    /// "gravity loading" of geotechnical finite-element practice).
    #[default]
    Zero,
    /// The 1D state of a level layer, set before the relaxation (the "K₀ procedure" of
    /// geotechnical finite-element practice, e.g. Potts & Zdravković 1999, §5): σ_v = −ρ₀ g d
    /// with d the depth below the top of the particle's dx-wide column, and every horizontal
    /// normal stress K σ_v with K the material's own oedometric ratio at that σ_v
    /// (`stress_check::OedometricRatio`). The relaxation then only settles what that state
    /// does not balance: rough walls, an inclined surface. A layer is no longer loaded all at
    /// once between walls that hold its sides, as a column filled layer by layer is not.
    Oedometric,
}

impl Default for GeostaticConfig {
    fn default() -> Self {
        Self {
            damping_ratio: 1.0,
            kinetic_energy_tolerance: 1e-6,
            max_time: 1.0,
            release: Vec::new(),
            free_slip_walls: false,
            initial_stress: InitialStress::Zero,
        }
    }
}

impl GeostaticConfig {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let check = |field: &str, value: Real, ok: bool, allowed: &str| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(ConfigError {
                    field: format!("geostatic.{field}"),
                    message: format!("must lie in {allowed}, got {value}"),
                })
            }
        };
        let zeta = self.damping_ratio;
        check("damping_ratio", zeta, zeta > 0.0 && zeta <= 10.0, "(0, 10]")?;
        let tol = self.kinetic_energy_tolerance;
        check(
            "kinetic_energy_tolerance",
            tol,
            tol > 0.0 && tol < 1.0,
            "(0, 1)",
        )?;
        check("max_time", self.max_time, self.max_time > 0.0, "(0, inf)")?;
        for (k, release) in self.release.iter().enumerate() {
            if release.min.len() != release.max.len()
                || release
                    .min
                    .iter()
                    .zip(&release.max)
                    .any(|(a, b)| a.partial_cmp(b) != Some(std::cmp::Ordering::Less))
            {
                return Err(ConfigError {
                    field: format!("geostatic.release[{k}]"),
                    message: "needs min < max on every axis".into(),
                });
            }
        }
        Ok(())
    }
}

impl From<MaterialError> for ConfigError {
    fn from(error: MaterialError) -> Self {
        Self {
            field: format!("constitutive.{}", error.parameter),
            message: format!("must lie in {}, got {}", error.allowed, error.value),
        }
    }
}

impl SoilConfig {
    /// Soil particles start at ρ₀, never hydrostatic (their stress comes from the geostatic
    /// stage); c₀ = 0 leaves the wave speed to the solver, which takes it from the elastic
    /// constants. Soil has no equation of state: the one given only fills the field (the
    /// scene's initial pressure fields, hydrostatic or Taylor–Green, are for liquids).
    pub fn particle_start(&self) -> ParticleStart {
        ParticleStart {
            equation_of_state: geosph_sph::EosKind::Tait { gamma: 7.0 },
            background_pressure: 0.0,
            sound_speed: Some(0.0),
            hydrostatic: false,
        }
    }

    /// Checks every value against its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.constitutive.build()?;
        if let Some(av) = self.artificial_viscosity {
            in_range("artificial_viscosity.alpha", av.alpha, 0.0, 1.0)?;
            in_range("artificial_viscosity.beta", av.beta, 0.0, 2.0)?;
        }
        if let Some(stress) = self.artificial_stress {
            in_range("artificial_stress.epsilon", stress.epsilon, 1e-6, 1.0)?;
            in_range("artificial_stress.exponent", stress.exponent, 1.0, 10.0)?;
        }
        if let Some(xi) = self.damping {
            in_range("damping", xi, 0.0, 1.0)?;
        }
        if let Some(diffusion) = self.stress_diffusion {
            in_range("stress_diffusion.delta", diffusion.delta, 1e-6, 1.0)?;
            if let Some(ratio) = diffusion.lateral_ratio {
                in_range("stress_diffusion.lateral_ratio", ratio, 0.0, 2.0)?;
            }
        }
        if let Some(RegularisationConfig::Shepard { every } | RegularisationConfig::Mls { every }) =
            self.regularisation
            && every == 0
        {
            return Err(ConfigError {
                field: "regularisation.every".into(),
                message: "must be at least 1, got 0".into(),
            });
        }
        if let WallSlip::Friction { angle_deg } = self.walls.slip
            && !(angle_deg.is_finite() && (0.0..90.0).contains(&angle_deg))
        {
            return Err(ConfigError {
                field: "walls.slip.angle_deg".into(),
                message: format!("must lie in [0, 90) degrees, got {angle_deg}"),
            });
        }
        in_range("walls.beta_max", self.walls.beta_max, 1.0, 2.0)?;
        if let Some(geostatic) = &self.geostatic {
            geostatic.validate()?;
        }
        if let Some(search) = &self.factor_of_safety {
            search.validate()?;
        }
        if !(self.cfl.is_finite() && self.cfl > 0.0 && self.cfl <= 1.0) {
            return Err(ConfigError {
                field: "cfl".into(),
                message: format!("must lie in (0, 1], got {}", self.cfl),
            });
        }
        in_range("neighbour_skin", self.neighbour_skin, 0.0, 1.0)
    }
}

/// Why a soil solver could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SoilError {
    /// A configuration value is out of range.
    #[error("soil solver {0}")]
    Config(#[from] ConfigError),
    /// The neighbour search failed (e.g. a particle left the domain).
    #[error(transparent)]
    Search(#[from] SearchError),
    /// A step of the geostatic stage failed.
    #[error("geostatic stage: {0}")]
    Step(#[from] geosph_sph::SolverError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_reads_from_ron_with_defaults_and_names_bad_fields() {
        let config: SoilConfig = ron::from_str("(cfl: 0.1)").unwrap();
        assert_eq!(config.cfl, 0.1);
        assert!(config.validate().is_ok());
        let bad = SoilConfig {
            artificial_viscosity: Some(ArtificialViscosityConfig {
                alpha: 3.0,
                beta: 0.0,
            }),
            ..SoilConfig::default()
        };
        assert_eq!(
            bad.validate().unwrap_err().field,
            "artificial_viscosity.alpha"
        );
        let friction = SoilConfig {
            walls: SoilWallConfig {
                slip: WallSlip::Friction { angle_deg: 95.0 },
                ..SoilWallConfig::default()
            },
            ..SoilConfig::default()
        };
        assert_eq!(
            friction.validate().unwrap_err().field,
            "walls.slip.angle_deg"
        );
        let material = SoilConfig {
            constitutive: ConstitutiveConfig::LinearElastic {
                youngs_modulus: -1.0,
                poisson_ratio: 0.3,
            },
            ..SoilConfig::default()
        };
        let error = material.validate().unwrap_err();
        assert_eq!(error.field, "constitutive.youngs_modulus");
        for (text, field) in [
            (
                "(stress_diffusion: Some((delta: 0.0)))",
                "stress_diffusion.delta",
            ),
            (
                "(stress_diffusion: Some((lateral_ratio: Some(-0.5))))",
                "stress_diffusion.lateral_ratio",
            ),
        ] {
            let config: SoilConfig = ron::from_str(text).unwrap();
            assert_eq!(config.validate().unwrap_err().field, field, "{text}");
        }
        let diffusion: SoilConfig = ron::from_str("(stress_diffusion: Some(()))").unwrap();
        assert_eq!(diffusion.stress_diffusion.unwrap().delta, 0.1);
        let unknown = ron::from_str::<SoilConfig>("(cfl: 0.1, damping_ratio: 0.2)");
        assert!(unknown.unwrap_err().to_string().contains("damping_ratio"));
    }
}
