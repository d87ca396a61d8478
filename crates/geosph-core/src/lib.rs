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
#![warn(missing_docs)]

pub mod domain;
pub mod neighbour_list;
pub mod particles;
pub mod permutation;
pub mod types;

pub use domain::Domain;
pub use neighbour_list::NeighbourList;
pub use particles::{Particles, SoilFields};
pub use permutation::Permutation;
pub use types::{Matrix, Real, Tensor3, Vector};
