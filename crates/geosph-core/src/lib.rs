//! Shared types of geosph, and nothing more.
//!
//! Every other geosph crate depends on this one; it depends on no other geosph crate.
//!
//! Modules:
//! - [`types`]: the scalar [`Real`] (`f64`) and small vector/tensor aliases generic over the
//!   dimension `D` (2 or 3) on nalgebra's `SVector`/`SMatrix`.
//! - [`domain`]: the axis-aligned simulation [`Domain`] with optional periodic axes and the
//!   minimum-image displacement `x_i − x_j`.
//! - [`neighbour_list`]: the flat (CSR) [`NeighbourList`] that neighbour searches produce and
//!   every SPH sum consumes.
//! - [`permutation`]: a reordering of particles ([`Permutation`]) applied in place to any field.
//! - [`particles`]: structure-of-arrays [`Particles`] storage; optional field groups (pressure,
//!   soil state, gradient-correction matrices) exist only when a solver or model asks for them.
//!
//! # Example
//!
//! Particles at rest in a box periodic along x, and the minimum-image distance across the
//! period:
//!
//! ```
//! use geosph_core::{Domain, Particles, Vector};
//!
//! let domain = Domain::with_periodic(Vector::<2>::zeros(), Vector::<2>::new(1.0, 1.0), [true, false])?;
//! let x = vec![Vector::<2>::new(0.05, 0.5), Vector::<2>::new(0.95, 0.5)];
//! let particles = Particles::at_rest(x, 0.01, 1000.0);
//! assert_eq!(particles.len(), 2);
//! assert!(particles.pressure.is_none()); // optional fields exist only when asked for
//! let r = domain.displacement(&particles.position[0], &particles.position[1]);
//! assert!((r[0] - 0.1).abs() < 1e-12); // through the periodic boundary, not 0.9 across
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod domain;
pub mod neighbour_list;
pub mod particles;
pub mod permutation;
mod record;
pub mod types;

pub use domain::Domain;
pub use neighbour_list::NeighbourList;
pub use particles::{Particles, SoilFields, retain};
pub use permutation::Permutation;
pub use record::PerParticle;
pub use types::{Matrix, Real, Tensor3, Vector};
