//! Explicit time integration for geosph's weakly compressible solver, and the time-step
//! limits every explicit solver uses. The soil advances its stress with the return map inside
//! its own symplectic Euler step (`docs/soil.md`, "One step"), so no stress rate passes
//! through these schemes.
//!
//! Modules:
//! - [`rates`]: [`Rates`], the time derivatives a solver computes (acceleration, density rate,
//!   position correction such as XSPH), and the [`ExplicitSystem`] trait a solver
//!   implements.
//! - [`integrator`]: the schemes ([`Integrator`]): symplectic Euler, kick-drift-kick leap-frog,
//!   predictor–corrector and classical RK4, each advancing [`geosph_core::Particles`] by Δt.
//! - [`step_size`]: the adaptive Δt from the acoustic CFL, body-force and viscous limits.
//!
//! # Example
//!
//! A system of its own (one particle falling under gravity) advanced by the leap-frog
//! integrator; any [`ExplicitSystem`] can be stepped the same way:
//!
//! ```
//! use geosph_core::{Particles, Real, Vector};
//! use geosph_time::{ExplicitSystem, Integrator, Rates, Scheme};
//!
//! struct Falling;
//!
//! impl ExplicitSystem<2> for Falling {
//!     type Error = std::convert::Infallible;
//!     fn prepare(&mut self, _: &mut Particles<2>) -> Result<(), Self::Error> {
//!         Ok(())
//!     }
//!     fn rates(&mut self, _: &Particles<2>, _time: Real, rates: &mut Rates<2>) {
//!         rates.acceleration.fill(Vector::<2>::new(0.0, -9.81));
//!     }
//! }
//!
//! let mut particle = Particles::at_rest(vec![Vector::<2>::zeros()], 1.0, 1000.0);
//! let mut integrator = Integrator::new(Scheme::LeapFrog, 1);
//! let dt = 0.01;
//! for step in 0..100 {
//!     integrator.step(&mut Falling, &mut particle, step as Real * dt, dt).unwrap();
//! }
//! // Leap-frog is exact for constant acceleration: y = −g t²/2 at t = 1 s.
//! assert!((particle.position[0][1] + 0.5 * 9.81).abs() < 1e-9);
//! assert!((particle.velocity[0][1] + 9.81).abs() < 1e-9);
//! ```
#![warn(missing_docs)]

pub mod integrator;
pub mod rates;
pub mod step_size;

pub use integrator::{Integrator, Scheme};
pub use rates::{ExplicitSystem, Rates};
pub use step_size::{StepLimits, time_step};
