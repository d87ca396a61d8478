//! Rigid bodies for geosph: bodies made of dummy wall particles that the flow's pressure
//! moves and that hold the flow, integrated with contacts and Coulomb friction by rapier
//! (dimforge's rigid-body engine, `rapier2d-f64`/`rapier3d-f64`).
//!
//! Modules:
//! - [`world`]: [`World`], rapier's 2D or 3D engine behind one interface on `Vector<D>`, with
//!   [`FixedShape`] obstacles, [`MassProperties`] and [`Motion`].
//! - [`bodies`]: [`RigidBodies`], the coupling with the flow, which a fluid solver runs once
//!   per step as its [`WallMotion`](geosph_sph::WallMotion).
#![warn(missing_docs)]

pub mod bodies;
pub mod world;

pub use bodies::{BodyDescription, BodyError, Coupling, RigidBodies, mass_properties};
pub use world::{FixedShape, MassProperties, Motion, World};
