//! geosph scenes: what to simulate, as data.
//!
//! A scene is a RON file (see `data/scenes/`) read into [`Scene`]; unknown or misspelt fields
//! are errors with their line and column, everything optional has a default. [`Scene::validate`]
//! checks every value against its allowed range before any work is done, and
//! [`setup::build`] turns a valid scene into particles, walls and solver inputs.
//!
//! Modules:
//! - [`format`](mod@format): the serde types of the scene file.
//! - [`validate`]: range checks with errors naming the field ([`SceneError`]).
//! - [`setup`]: particles, walls, domain, smoothing length and sound speed of a scene; the
//!   fluid's blocks (boxes, polygons, closed meshes) are filled as one union, each lattice
//!   site once ([`BlockReport`]).
//! - [`body_spec`]: the scene's rigid bodies ([`BodySpec`]) and their checks; [`bodies`]: each
//!   body's dummy particles, interior, surface and contact hull, and the walls as the bodies
//!   collide with them.
//!
//! # Example
//!
//! Read a scene, have a careless value reported with its field and allowed range, then build
//! the particles of the corrected scene:
//!
//! ```
//! use geosph_scene::{Scene, build};
//!
//! let text = r#"Scene(
//!     name: "column", dimension: 2, dx: 0.05, end_time: 0.5, smoothing_ratio: 3.0,
//!     fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.5, 1.0])]),
//!     walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0])],
//!     solver: Wcsph(()),
//! )"#;
//! let mut scene = Scene::from_ron(text)?;
//! let error = scene.validate().unwrap_err();
//! assert_eq!(error.to_string(), "scene field `smoothing_ratio`: must lie in [1, 2.5], got 3");
//!
//! scene.smoothing_ratio = 1.3;
//! let setup = build::<2>(&scene)?;
//! assert_eq!(setup.fluid.len(), 10 * 20);
//! assert!(setup.walls.len() > 0 && setup.sound_speed > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod bodies;
pub mod body_spec;
mod checks;
mod error;
pub mod format;
mod gas;
mod initial;
mod mesh_walls;
mod parse;
mod periodic;
mod phases;
mod proximity;
mod regions;
pub mod setup;
pub mod validate;

pub use body_spec::{BodyShape, BodySpec};
pub use format::{
    BlockState, FluidSpec, HealthSpec, HeightSpec, InitialVelocity, LoadSpec, OutputSpec,
    ProbeSpec, Region, Scene, SolverSpec, SurfaceSpec, WallSpec,
};
pub use regions::BlockReport;
pub use setup::{LoadSurface, Setup, build};
pub use validate::SceneError;
