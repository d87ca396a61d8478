//! Fluid solvers of geosph.
//!
//! Modules:
//! - [`eos`]: equations of state (Tait, linear) and their inverses.
//! - [`viscosity`]: viscous terms as pair-loop type parameters: [`viscosity::Inviscid`],
//!   Monaghan's artificial viscosity, Morris' laminar viscosity.
//! - [`diffusion`]: δ-SPH density diffusion (Molteni & Colagrossi 2009, Antuono et al. 2010).
//! - [`wcsph`]: the weakly compressible SPH system ([`WcsphSystem`]): symmetric momentum,
//!   continuity or summation density, XSPH, Shepard re-initialisation, Adami walls.
//! - [`incompressible`]: PCISPH, IISPH and DFSPH on shared operators ([`incompressible::PressureSystem`]).
//! - [`solver`]: the [`FluidSolver`] trait the runner steps, and [`Wcsph`].
//! - [`config`]: scene-level configuration ([`WcsphConfig`]) and [`build_wcsph`], which
//!   resolves every option to a type once, so the hot loops carry no option flags.
#![warn(missing_docs)]

pub mod config;
pub mod diffusion;
pub mod eos;
pub mod incompressible;
pub mod solver;
pub mod viscosity;
pub mod wcsph;

pub use config::{
    FluidSetup, IncompressibleConfig, IncompressibleMethod, WcsphConfig, build_incompressible,
    build_wcsph,
};
pub use eos::{EosKind, EquationOfState};
pub use solver::{FluidSolver, SolverError, StepReport, Wcsph};
pub use wcsph::WcsphSystem;
