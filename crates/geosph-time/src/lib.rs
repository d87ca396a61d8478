//! Explicit time integration for geosph's explicit (weakly compressible and soil) solvers.
//!
//! Modules:
//! - [`rates`]: [`Rates`], the time derivatives a solver computes (acceleration, density rate,
//!   position correction such as XSPH, stress rate), and the [`ExplicitSystem`] trait a solver
//!   implements.
//! - [`integrator`]: the schemes ([`Integrator`]): symplectic Euler, kick-drift-kick leap-frog,
//!   predictor–corrector and classical RK4, each advancing [`geosph_core::Particles`] by Δt.
//! - [`step_size`]: the adaptive Δt from the acoustic CFL, body-force and viscous limits.
#![warn(missing_docs)]

pub mod integrator;
pub mod rates;
pub mod step_size;

pub use integrator::{Integrator, Scheme};
pub use rates::{ExplicitSystem, Rates};
pub use step_size::{StepLimits, time_step};
