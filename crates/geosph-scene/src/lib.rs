//! geosph scenes: what to simulate, as data.
//!
//! A scene is a RON file (see `data/scenes/`) read into [`Scene`]; unknown or misspelt fields
//! are errors with their line and column, everything optional has a default. [`Scene::validate`]
//! checks every value against its allowed range before any work is done, and
//! [`setup::build`] turns a valid scene into particles, walls and solver inputs.
//!
//! Modules:
//! - [`format`]: the serde types of the scene file.
//! - [`validate`]: range checks with errors naming the field ([`SceneError`]).
//! - [`setup`]: particles, walls, domain, smoothing length and sound speed of a scene.
#![warn(missing_docs)]

pub mod format;
mod parse;
pub mod setup;
pub mod validate;

pub use format::{FluidSpec, OutputSpec, Region, Scene, SolverSpec, WallSpec};
pub use setup::{Setup, build};
pub use validate::SceneError;
