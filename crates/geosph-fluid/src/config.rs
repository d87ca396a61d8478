//! Scene-level configuration of the fluid solvers (what a scene writes, its defaults and its
//! validation); [`crate::build`] turns it into a solver.

use geosph_boundary::Slip;
use geosph_core::{Real, Vector};
use geosph_sph::config_error::{ConfigError, in_range, positive};
use geosph_sph::eos::EosKind;
use geosph_sph::{
    ArtificialMonaghan1992, LaminarMorris1997, ParticleShifting, ParticleStart, SpsConfig,
    ViscousTerm,
};
use geosph_time::Scheme;
use serde::{Deserialize, Serialize};

pub use crate::surface_tension::SurfaceTensionConfig;

use crate::diffusion::{DeltaAntuono2010, DeltaFourtakas2019, DeltaMolteni2009, DiffusionTerm};
use crate::incompressible::{
    PressureIteration, PressureSolveSettings, PressureSource, WallPressure,
};

/// The viscous term of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ViscosityConfig {
    /// No viscosity.
    None,
    /// Monaghan (1992) artificial viscosity.
    Artificial {
        /// α, typically 0.01–0.1.
        alpha: Real,
        /// β, usually 0 for liquids.
        #[serde(default)]
        beta: Real,
    },
    /// Morris et al. (1997) laminar viscosity.
    Laminar {
        /// ν in m²/s (water: 1e-6).
        kinematic_viscosity: Real,
    },
}

/// The density-diffusion term of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum DiffusionConfig {
    /// No diffusion.
    None,
    /// Molteni & Colagrossi (2009).
    Molteni {
        /// δ, typically 0.1.
        delta: Real,
    },
    /// Antuono et al. (2010), with renormalised density gradients.
    Antuono {
        /// δ, typically 0.1.
        delta: Real,
    },
    /// Fourtakas et al. (2019), Molteni's term about hydrostatics.
    Fourtakas {
        /// δ, typically 0.1.
        delta: Real,
    },
}

impl ViscosityConfig {
    /// Checks the coefficients: α in [0, 1], β in [0, 2], ν > 0.
    pub fn validate(&self) -> Result<(), ConfigError> {
        match *self {
            Self::None => Ok(()),
            Self::Artificial { alpha, beta } => {
                in_range("viscosity.alpha", alpha, 0.0, 1.0)?;
                in_range("viscosity.beta", beta, 0.0, 2.0)
            }
            Self::Laminar {
                kinematic_viscosity,
            } => positive("viscosity.kinematic_viscosity", kinematic_viscosity),
        }
    }

    /// Whether the term models physical (laminar) viscosity, for the velocity walls show it
    /// ([`Slip::viscous_velocity`]).
    pub fn is_physical(&self) -> bool {
        matches!(self, Self::Laminar { .. })
    }

    /// The term for smoothing length `h` and sound speed `sound_speed` (the artificial
    /// viscosity's c̄).
    pub fn term(&self, h: Real, sound_speed: Real) -> ViscousTerm {
        match *self {
            Self::None => ViscousTerm::Inviscid,
            Self::Artificial { alpha, beta } => ViscousTerm::Artificial(ArtificialMonaghan1992 {
                alpha,
                beta,
                smoothing_length: h,
                sound_speed,
            }),
            Self::Laminar {
                kinematic_viscosity,
            } => ViscousTerm::Laminar(LaminarMorris1997 {
                kinematic_viscosity,
                lattice_correction: 1.0,
            }),
        }
    }
}

impl DiffusionConfig {
    /// The term for smoothing length `h`, sound speed `sound_speed` (c₀ of δ h c₀), and,
    /// for Fourtakas et al.'s, rest density and gravity.
    pub fn term<const D: usize>(
        &self,
        h: Real,
        sound_speed: Real,
        rest_density: Real,
        gravity: Vector<D>,
    ) -> DiffusionTerm<D> {
        match *self {
            Self::None => DiffusionTerm::None,
            Self::Molteni { delta } => DiffusionTerm::Molteni(DeltaMolteni2009 {
                delta,
                smoothing_length: h,
                sound_speed,
            }),
            Self::Antuono { delta } => {
                DiffusionTerm::Antuono(DeltaAntuono2010::new(delta, h, sound_speed))
            }
            Self::Fourtakas { delta } => DiffusionTerm::Fourtakas(DeltaFourtakas2019 {
                base: DeltaMolteni2009 {
                    delta,
                    smoothing_length: h,
                    sound_speed,
                },
                hydrostatic_gradient: gravity * (rest_density / (sound_speed * sound_speed)),
            }),
        }
    }
}

/// Density by continuity or by summation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DensityConfig {
    /// Continuity equation (default).
    #[default]
    Continuity,
    /// Kernel summation over fluid and walls.
    Summation,
}

/// Parameters of weakly compressible SPH.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WcsphConfig {
    /// Equation of state (default Tait, γ = 7); a gas (`IdealGas`, `StiffenedGas`) carries
    /// its internal energy ([`crate::gas`]).
    pub equation_of_state: EosKind,
    /// Reference sound speed c₀ in m/s; `None`: 10 × the expected largest speed, max(√(2 g H),
    /// largest initial speed, largest wall speed).
    pub sound_speed: Option<Real>,
    /// Continuity or summation.
    pub density: DensityConfig,
    /// δ-SPH density diffusion (default Fourtakas et al. 2019, δ = 0.1).
    pub diffusion: DiffusionConfig,
    /// Viscous term (default artificial, α = 0.02).
    pub viscosity: ViscosityConfig,
    /// XSPH factor ε (default 0: off).
    pub xsph: Real,
    /// δ⁺-SPH particle shifting (default `None`: off; `Some(())` for Sun et al.'s settings).
    pub shifting: Option<ParticleShifting>,
    /// Sub-particle-scale turbulence (default `None`: off; `Some(())` for Dalrymple & Rogers'
    /// coefficients), beside the viscous term.
    pub sps: Option<SpsConfig>,
    /// Surface tension between the phase of the named blocks and the rest of the fluid
    /// (default `None`: off; [`SurfaceTensionConfig`]).
    pub surface_tension: Option<SurfaceTensionConfig>,
    /// Steps between Shepard density re-initialisations (default 0: never).
    pub shepard_every: usize,
    /// Clamp negative pressure to zero (default false).
    pub clamp_negative_pressure: bool,
    /// Background pressure p_b in Pa, added to the equation of state (default 0; for confined
    /// flows with suction such as a vortex, about ρ₀U²: see [`EquationOfState`](geosph_sph::eos::EquationOfState)).
    pub background_pressure: Real,
    /// Time integrator (default leap-frog).
    pub integrator: Scheme,
    /// Courant number of the acoustic time-step limit (default 0.25).
    pub cfl: Real,
    /// Steps between Z-order sorts (default 100).
    pub reorder_every: usize,
    /// Wall slip condition (default no-slip).
    pub wall_slip: Slip,
    /// Clamp negative wall pressure to zero, so walls never pull fluid (default true).
    pub clamp_wall_pressure: bool,
    /// Verlet skin of the neighbour lists as a fraction of the support radius (default 0.1;
    /// 0 rebuilds the lists every step).
    pub neighbour_skin: Real,
}

impl Default for WcsphConfig {
    fn default() -> Self {
        Self {
            equation_of_state: EosKind::Tait { gamma: 7.0 },
            sound_speed: None,
            density: DensityConfig::Continuity,
            diffusion: DiffusionConfig::Fourtakas { delta: 0.1 },
            viscosity: ViscosityConfig::Artificial {
                alpha: 0.02,
                beta: 0.0,
            },
            xsph: 0.0,
            shifting: None,
            sps: None,
            surface_tension: None,
            shepard_every: 0,
            clamp_negative_pressure: false,
            background_pressure: 0.0,
            integrator: Scheme::LeapFrog,
            cfl: 0.25,
            reorder_every: 100,
            wall_slip: Slip::NoSlip,
            clamp_wall_pressure: true,
            neighbour_skin: 0.1,
        }
    }
}

impl WcsphConfig {
    /// Checks every value against its allowed range (fields relative to the solver block).
    pub fn validate(&self) -> Result<(), ConfigError> {
        if let EosKind::Tait { gamma } = self.equation_of_state {
            in_range("equation_of_state.gamma", gamma, 1.0, 10.0)?;
        }
        crate::gas::validate(self)?;
        if let Some(c0) = self.sound_speed {
            positive("sound_speed", c0)?;
        }
        match self.diffusion {
            DiffusionConfig::None => {}
            DiffusionConfig::Molteni { delta }
            | DiffusionConfig::Antuono { delta }
            | DiffusionConfig::Fourtakas { delta } => in_range("diffusion.delta", delta, 0.0, 1.0)?,
        }
        self.viscosity.validate()?;
        in_range("xsph", self.xsph, 0.0, 1.0)?;
        if let Some(sps) = &self.sps {
            sps.validate("sps")?;
        }
        if let Some(shifting) = &self.shifting {
            shifting.validate("shifting")?;
        }
        if let Some(tension) = &self.surface_tension {
            tension.validate("surface_tension")?;
        }
        if !(self.background_pressure.is_finite() && self.background_pressure >= 0.0) {
            return Err(ConfigError::new(
                "background_pressure",
                format!(
                    "must be a finite number ≥ 0 Pa, got {}",
                    self.background_pressure
                ),
            ));
        }
        in_range("neighbour_skin", self.neighbour_skin, 0.0, 1.0)?;
        // Beyond C = 1 a sound wave crosses more than a smoothing length per step. Explicit
        // schemes are usually run at C ≤ 0.4 (Monaghan 1992); the measured limits of each
        // solver and kernel are in docs/stability.md, and a run that goes unstable is stopped
        // with a diagnosis.
        if !(self.cfl.is_finite() && self.cfl > 0.0 && self.cfl <= 1.0) {
            return Err(ConfigError::new(
                "cfl",
                format!(
                    "must lie in (0, 1] for the explicit {:?} integrator, got {}",
                    self.integrator, self.cfl
                ),
            ));
        }
        Ok(())
    }

    /// The particles start with this configuration's equation of state and sound speed (the
    /// scene's rule when none is given), hydrostatic when the scene asks.
    pub fn particle_start(&self) -> ParticleStart {
        ParticleStart {
            equation_of_state: self.equation_of_state,
            background_pressure: self.background_pressure,
            sound_speed: self.sound_speed,
            hydrostatic: true,
        }
    }
}

/// Parameters of the incompressible solvers (PCISPH, IISPH, DFSPH).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IncompressibleConfig {
    /// Target average relative compression (default 0.001 = 0.1 %); with the
    /// velocity-divergence `source`, the target of Δt |Dρ/Dt| / ρ₀.
    pub target_density_error: Real,
    /// Bound on any one particle's predicted compression (default 0.1 = 10 %): the solve
    /// iterates past the mean target while a particle that takes pressure exceeds it.
    pub max_compression: Real,
    /// Least pressure iterations per step (default 2; PCISPH always does at least 3).
    pub min_iterations: usize,
    /// Most pressure iterations per step (default 100).
    pub max_iterations: usize,
    /// Courant number λ of the velocity CFL: no particle moves more than λ dx per step
    /// (default 0.4).
    pub cfl: Real,
    /// Upper bound on the time step in s (default 0.005 s; `None` for no bound).
    pub max_time_step: Option<Real>,
    /// Viscous term (default artificial, α = 0.02, with the velocity scale 10 √(2 g H) that
    /// WCSPH uses as its sound speed, so both dissipate alike).
    pub viscosity: ViscosityConfig,
    /// Wall pressure model (default hydrostatic).
    pub wall_pressure: WallPressure,
    /// Wall slip condition (default no-slip).
    pub wall_slip: Slip,
    /// IISPH: relaxation ω of the Jacobi update (default 0.5).
    pub relaxation: Real,
    /// IISPH: how the pressure system is iterated (default `RelaxedJacobi`; `Bicgstab(())`
    /// converges it, for pressures that a gauge can read in still and slow water; it reads
    /// `max_iterations` per active-set pass, `target_density_error` and `max_compression`
    /// as its [`Bicgstab`](crate::incompressible::Bicgstab) documents).
    pub iteration: PressureIteration,
    /// DFSPH: run the divergence-free solve (default true).
    pub divergence_solve: bool,
    /// DFSPH: target of the divergence solve, average Δt Dρ/Dt / ρ₀ (default 0.001).
    pub target_divergence_error: Real,
    /// Steps between Z-order sorts (default 100).
    pub reorder_every: usize,
    /// δ⁺-SPH particle shifting of the drift (default `None`: off).
    pub shifting: Option<ParticleShifting>,
    /// Let pressures go negative (default false): for flows without a free surface only
    /// (periodic or confined, e.g. a vortex), where suction is physical.
    pub negative_pressure: bool,
    /// Renormalise every pair gradient per particle (default false), so that divergences and
    /// gradients of linear fields are exact on disordered particles
    /// ([`PressureSystem::renormalise_gradients`](crate::incompressible::PressureSystem::renormalise_gradients)); only with `negative_pressure`, for flows
    /// without a free surface.
    pub renormalise_gradients: bool,
    /// PCISPH and IISPH: the source of the pressure equation (default
    /// `DensityInvariance`; `VelocityDivergence` only with `negative_pressure`, and not for
    /// DFSPH, whose divergence solve is that source).
    pub source: PressureSource,
}

impl Default for IncompressibleConfig {
    fn default() -> Self {
        let settings = PressureSolveSettings::default();
        Self {
            target_density_error: settings.target_density_error,
            max_compression: settings.max_compression,
            min_iterations: settings.min_iterations,
            max_iterations: settings.max_iterations,
            cfl: settings.cfl,
            max_time_step: settings.max_time_step,
            viscosity: ViscosityConfig::Artificial {
                alpha: 0.02,
                beta: 0.0,
            },
            wall_pressure: WallPressure::Hydrostatic,
            wall_slip: Slip::NoSlip,
            relaxation: 0.5,
            iteration: PressureIteration::RelaxedJacobi,
            divergence_solve: true,
            target_divergence_error: 1e-3,
            reorder_every: 100,
            shifting: None,
            negative_pressure: settings.negative_pressure,
            renormalise_gradients: false,
            source: settings.source,
        }
    }
}

impl IncompressibleConfig {
    /// Checks every value against its allowed range (fields relative to the solver block), the
    /// ones every method takes; [`IncompressibleConfig::validate_for`] adds the method's own.
    fn validate(&self) -> Result<(), ConfigError> {
        in_range("target_density_error", self.target_density_error, 1e-6, 0.1)?;
        in_range(
            "max_compression",
            self.max_compression,
            self.target_density_error,
            1.0,
        )?;
        in_range(
            "target_divergence_error",
            self.target_divergence_error,
            1e-6,
            0.1,
        )?;
        if self.max_iterations == 0 || self.max_iterations < self.min_iterations {
            return Err(ConfigError::new(
                "max_iterations",
                format!(
                    "must be at least 1 and at least min_iterations = {}, got {}",
                    self.min_iterations, self.max_iterations
                ),
            ));
        }
        // A particle must not cross more than one spacing per step, or pairs enter the support
        // unseen by the pressure solve.
        in_range("cfl", self.cfl, 1e-3, 1.0)?;
        if let Some(dt) = self.max_time_step {
            positive("max_time_step", dt)?;
        }
        in_range("relaxation", self.relaxation, 0.05, 1.0)?;
        if self.renormalise_gradients && !self.negative_pressure {
            return Err(ConfigError::new(
                "renormalise_gradients",
                "needs `negative_pressure: true`: it is for flows without a free surface, where \
                 the renormalisation matrix of a surface particle is singular"
                    .to_owned(),
            ));
        }
        if self.source == PressureSource::VelocityDivergence && !self.negative_pressure {
            return Err(ConfigError::new(
                "source",
                "`VelocityDivergence` needs `negative_pressure: true`: it does not correct the \
                 density, so a free surface would lose volume step by step; it is for flows \
                 without one, whose volume the domain fixes"
                    .to_owned(),
            ));
        }
        if let Some(shifting) = &self.shifting {
            shifting.validate("shifting")?;
        }
        self.viscosity.validate()
    }

    /// Checks every value against its allowed range for `method` (fields relative to the
    /// solver block): the ones every method takes, and those only some take.
    pub fn validate_for(&self, method: IncompressibleMethod) -> Result<(), ConfigError> {
        if let PressureIteration::Bicgstab(bicgstab) = self.iteration {
            if method != IncompressibleMethod::Iisph {
                return Err(ConfigError::new(
                    "iteration",
                    "`Bicgstab` is for IISPH only; PCISPH and DFSPH take `RelaxedJacobi` (the \
                     default)"
                        .to_owned(),
                ));
            }
            if self.source != PressureSource::default() {
                return Err(ConfigError::new(
                    "source",
                    "`Bicgstab` has its own source, the velocity divergence with a share \
                     `density_relaxation` of the density error; leave `source` at \
                     `DensityInvariance` (the default) and set `density_relaxation: 0.0` for \
                     no relaxed density term"
                        .to_owned(),
                ));
            }
            in_range("iteration.tolerance", bicgstab.tolerance, 1e-10, 0.5)?;
            in_range(
                "iteration.density_relaxation",
                bicgstab.density_relaxation,
                0.0,
                1.0,
            )?;
            if !(1..=100).contains(&bicgstab.active_set_passes) {
                return Err(ConfigError::new(
                    "iteration.active_set_passes",
                    format!("must lie in [1, 100], got {}", bicgstab.active_set_passes),
                ));
            }
        }
        if method == IncompressibleMethod::Dfsph && self.source != PressureSource::default() {
            return Err(ConfigError::new(
                "source",
                "is for PCISPH and IISPH; DFSPH takes only `DensityInvariance` (the default): \
                 it solves for both sources, the velocity divergence in its divergence solve \
                 (`divergence_solve`) and the density in its density solve"
                    .to_owned(),
            ));
        }
        self.validate()
    }

    /// The particles start at ρ₀, or hydrostatic with Tait's inverse (γ = 7) when the scene
    /// asks: these solvers recompute the density by summation and use c₀ only as the velocity
    /// scale of their artificial viscosity, which the scene's rule sets.
    pub fn particle_start(&self) -> ParticleStart {
        ParticleStart {
            equation_of_state: EosKind::Tait { gamma: 7.0 },
            background_pressure: 0.0,
            sound_speed: None,
            hydrostatic: true,
        }
    }
}

/// The incompressible methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IncompressibleMethod {
    /// Solenthaler & Pajarola (2009).
    Pcisph,
    /// Ihmsen et al. (2014).
    Iisph,
    /// Bender & Koschier (2015, 2017).
    Dfsph,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renormalised_gradients_need_a_flow_without_a_free_surface() {
        let free_surface = IncompressibleConfig {
            renormalise_gradients: true,
            ..Default::default()
        };
        let message = free_surface.validate().unwrap_err().to_string();
        assert!(
            message.contains("renormalise_gradients") && message.contains("negative_pressure"),
            "{message}"
        );
        let confined = IncompressibleConfig {
            renormalise_gradients: true,
            negative_pressure: true,
            ..Default::default()
        };
        assert!(confined.validate().is_ok());
    }

    /// The message with which `method` refuses `config`.
    fn refusal(config: &IncompressibleConfig, method: IncompressibleMethod) -> String {
        config.validate_for(method).unwrap_err().to_string()
    }

    #[test]
    fn the_divergence_source_is_for_confined_flows_and_not_for_dfsph() {
        let free_surface = IncompressibleConfig {
            source: PressureSource::VelocityDivergence,
            ..Default::default()
        };
        let message = refusal(&free_surface, IncompressibleMethod::Iisph);
        assert!(
            message.contains("source") && message.contains("negative_pressure"),
            "{message}"
        );
        let confined = IncompressibleConfig {
            negative_pressure: true,
            ..free_surface
        };
        assert!(confined.validate_for(IncompressibleMethod::Iisph).is_ok());
        assert!(confined.validate_for(IncompressibleMethod::Pcisph).is_ok());
        let message = refusal(&confined, IncompressibleMethod::Dfsph);
        assert!(
            message.contains("source") && message.contains("divergence_solve"),
            "{message}"
        );
    }

    #[test]
    fn the_bicgstab_solve_is_for_iisph_with_its_own_source() {
        let bicgstab = IncompressibleConfig {
            iteration: PressureIteration::Bicgstab(Default::default()),
            ..Default::default()
        };
        assert!(bicgstab.validate_for(IncompressibleMethod::Iisph).is_ok());
        for method in [IncompressibleMethod::Pcisph, IncompressibleMethod::Dfsph] {
            let message = refusal(&bicgstab, method);
            assert!(
                message.contains("iteration") && message.contains("IISPH"),
                "{message}"
            );
        }
        let divergence = IncompressibleConfig {
            source: PressureSource::VelocityDivergence,
            negative_pressure: true,
            ..bicgstab.clone()
        };
        let message = refusal(&divergence, IncompressibleMethod::Iisph);
        assert!(message.contains("density_relaxation"), "{message}");
    }
}
