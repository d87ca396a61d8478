//! Fluid solvers of geosph, on the shared SPH layer of `geosph-sph` (solver interface, pair
//! lists, viscous terms).
//!
//! Modules:
//! - [`diffusion`]: δ-SPH density diffusion (Molteni & Colagrossi 2009, Antuono et al. 2010,
//!   Fourtakas et al. 2019, the default).
//! - [`wcsph`]: the weakly compressible SPH system ([`WcsphSystem`]): symmetric momentum,
//!   continuity or summation density, XSPH, Shepard re-initialisation, Adami walls.
//! - [`gas`]: a gas in WCSPH, its energy equation and artificial viscosity with local sound
//!   speeds ([`gas::GasDynamics`]).
//! - [`riemann`]: the exact solution of a gas's Riemann problem, the shock tube's reference.
//! - [`surface_tension`]: the continuum surface force between two phases
//!   ([`surface_tension::SurfaceTension`]).
//! - [`incompressible`]: PCISPH, IISPH and DFSPH on shared operators ([`incompressible::PressureSystem`]).
//! - [`wcsph_solver`]: [`Wcsph`], the WCSPH system under an explicit integrator.
//! - [`config`]: scene-level configuration ([`WcsphConfig`], [`IncompressibleConfig`]).
//! - [`build`]: [`build_wcsph`] and [`build_incompressible`], which resolve every option to a
//!   type once, so the hot loops carry no option flags.
//!
//! # Example
//!
//! A small water block at rest in a tank, stepped with the default WCSPH configuration,
//! without the scene or runner crates:
//!
//! ```
//! use geosph_boundary::generate;
//! use geosph_core::{Domain, Particles, Vector};
//! use geosph_fluid::{EosKind, EquationOfState, WcsphConfig, build_wcsph};
//! use geosph_sph::{Solver, SphSetup};
//! use geosph_kernels::KernelKind;
//!
//! // Tait: p = ρ₀c₀²/γ ((ρ/ρ₀)^γ − 1), 4.12 kPa for 1 % compression at c₀ = 20 m/s.
//! let eos = EquationOfState { kind: EosKind::Tait { gamma: 7.0 }, rest_density: 1000.0, sound_speed: 20.0, background_pressure: 0.0 };
//! assert!((eos.pressure(1010.0) - 4122.0).abs() < 1.0);
//!
//! let dx = 0.05;
//! let (min, max) = (Vector::<2>::zeros(), Vector::<2>::new(0.5, 0.5));
//! let mut water = Particles::at_rest(generate::fill_box(&min, &Vector::<2>::new(0.5, 0.25), dx), 1000.0 * dx * dx, 1000.0);
//! let setup = SphSetup {
//!     kernel: KernelKind::WendlandC2,
//!     smoothing_length: 1.3 * dx,
//!     domain: Domain::new(Vector::<2>::repeat(-0.5), Vector::<2>::repeat(1.5))?,
//!     rest_density: 1000.0,
//!     sound_speed: 20.0,
//!     gravity: Vector::<2>::new(0.0, -9.81),
//!     walls: generate::tank(&min, &max, dx, 3, true, 1000.0),
//!     spacing: dx,
//!     cell_index: Default::default(),
//!     block_ids: vec![0..water.len() as u32],
//! };
//! let mut solver = build_wcsph(&WcsphConfig::default(), setup, &mut water)?;
//! let mut time = 0.0;
//! while time < 0.01 {
//!     time += solver.step(&mut water, time, 0.01 - time)?.dt;
//! }
//! assert!(water.position.iter().all(|x| x[1] > 0.0)); // held up by the tank floor
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod build;
pub mod config;
pub mod diffusion;
pub mod gas;
pub mod incompressible;
pub mod riemann;
pub mod surface_tension;
pub mod wcsph;
pub mod wcsph_solver;

pub use build::{build_incompressible, build_wcsph};
pub use config::{IncompressibleConfig, IncompressibleMethod, WcsphConfig};
/// The equations of state, from the shared layer (`geosph_sph::eos`).
pub use geosph_sph::eos;
pub use geosph_sph::eos::{EosKind, EquationOfState, GasLaw};
pub use wcsph::WcsphSystem;
pub use wcsph_solver::Wcsph;
