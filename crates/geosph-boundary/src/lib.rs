//! Wall boundaries for SPH.
//!
//! Walls are sets of dummy (ghost) particles, several layers thick, stored apart from the fluid
//! or soil particles in [`WallParticles`]. Each step the wall particles receive a pressure,
//! density and velocity from the particles near them, so that the ordinary SPH sums of the
//! fluid see a wall as a continuation of the flow that enforces no penetration (and no-slip or
//! free-slip).
//!
//! Modules:
//! - [`walls`]: [`WallParticles`] storage and the slip condition [`Slip`].
//! - [`adami`]: the generalised wall condition of Adami, Hu & Adams (2012)
//!   ([`DummyAdami2012`]): extrapolated pressure with the gravity/wall-acceleration term.
//! - [`bui`]: Bui's dummy-velocity rule v_B = (1 − β) v_A + β v_wall (Bui et al. 2008).
//! - [`repulsive`]: the soft repulsive wall force of Liu et al. (2012) ([`RepulsiveLiu2012`]).
//! - [`generate`]: particle generators: lattice-filled boxes, tanks and polyline walls.
//!
//! # Example
//!
//! The dummy particles of an open 2D tank, three layers thick, around a 1 m × 0.5 m interior:
//!
//! ```
//! use geosph_boundary::generate;
//! use geosph_core::Vector;
//!
//! let dx = 0.1;
//! let (min, max) = (Vector::<2>::zeros(), Vector::<2>::new(1.0, 0.5));
//! let walls = generate::tank(&min, &max, dx, 3, true, 1000.0);
//! // Floor (10 + 2·3 columns) × 3 layers, plus two side walls of 5 × 3.
//! assert_eq!(walls.len(), 16 * 3 + 2 * 5 * 3);
//! // Every dummy particle lies outside the interior and knows its way back into the flow.
//! for (x, n) in walls.position.iter().zip(&walls.normal) {
//!     assert!(x[0] < min[0] || x[0] > max[0] || x[1] < min[1]);
//!     assert!((n.norm() - 1.0).abs() < 1e-12);
//! }
//! ```
#![warn(missing_docs)]

pub mod adami;
pub mod bui;
pub mod generate;
pub mod repulsive;
pub mod walls;

pub use adami::DummyAdami2012;
pub use repulsive::RepulsiveLiu2012;
pub use walls::{Slip, WallParticles};
