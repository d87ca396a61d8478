//! The SPH coupling of the soil model: elastoplastic soil particles, soil walls, the geostatic
//! stage and the solver the runner steps.
//!
//! - [`config`]: the scene block [`SoilConfig`] (constitutive model, stabilisation switches,
//!   walls, geostatic stage) and its validation.
//! - [`build`]: [`build_soil`], the solver a [`SoilConfig`] describes.
//! - [`system`]: [`SoilSystem`], one explicit step (velocity gradient, continuity, stress
//!   update, momentum in symmetric form), monomorphised over kernel and switchable terms.
//! - [`terms`]: artificial viscosity (Monaghan 1992) and artificial stress (Gray et al. 2001).
//! - [`diffusion`]: diffusion of the mean stress against the checkerboard (after Feng et al.
//!   2021), with the density following it.
//! - [`walls`]: Bui's β rule for dummy velocities and the wall-stress extrapolation.
//! - [`regularise`]: Shepard and MLS stress regularisation (Nguyen et al. 2017).
//! - [`geostatic`]: the geostatic stage ([`SoilSolver::run_geostatic_stage`]) with its
//!   [`GeostaticReport`] and the release.
//! - [`stress_check`]: the geostatic state against the 1D state and Janssen's arching.
//! - [`mod@stress_noise`]: [`stress_noise()`], the checkerboard noise of a stress field.
//! - [`solver`]: [`SoilSolver`], the time step and the per-step bookkeeping.
//! - [`search_config`]: [`StrengthReductionConfig`], the settings of that search.
//! - [`strength_reduction`]: the factor of safety by strength reduction
//!   ([`SoilSolver::factor_of_safety`]).

pub mod build;
pub mod config;
pub mod diffusion;
pub mod geostatic;
pub mod regularise;
pub(crate) mod relaxation;
pub mod search_config;
pub mod solver;
pub mod strength_reduction;
pub mod stress_check;
pub mod stress_noise;
pub mod system;
pub mod terms;
pub mod walls;

pub use build::{build_soil, factor_of_safety};
pub use config::{
    ArtificialStressConfig, ArtificialViscosityConfig, ConfigError, GeostaticConfig, InitialStress,
    RegularisationConfig, ReleaseBox, SoilConfig, SoilError, SoilWallConfig,
    StrengthReductionConfig, StressDiffusionConfig, WallSlip, WallStress,
};
pub use diffusion::MeanStressDiffusion;
pub use geostatic::GeostaticReport;
pub use solver::SoilSolver;
pub use strength_reduction::{FactorOfSafety, Trial, TrialOutcome};
pub use stress_check::{JanssenCheck, StressCheck, ZoneCheck};
pub use stress_noise::stress_noise;
pub use system::SoilSystem;
