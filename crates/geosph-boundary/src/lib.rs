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
#![warn(missing_docs)]

pub mod adami;
pub mod bui;
pub mod generate;
pub mod repulsive;
pub mod walls;

pub use adami::DummyAdami2012;
pub use repulsive::RepulsiveLiu2012;
pub use walls::{Slip, WallParticles};
