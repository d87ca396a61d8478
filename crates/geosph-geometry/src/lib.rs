//! Geometry for SPH set-ups: surface meshes read from STL and OBJ files and checked
//! ([`SurfaceMesh`]), the solids they bound ([`Solid`]) filled with particles on the
//! lattice, in 3D or in a vertical [`Section`] for 2D scenes, and closed meshes of simple
//! solids ([`primitives`]); the surfaces walls are laid behind ([`WallSurface`]), open or
//! closed, with the normal and depth of each wall site.
//!
//! The inside test and distances come from dimforge's `parry` (its angle-weighted
//! pseudo-normals); the files are read by `stl_io` and `tobj`. Positions are geosph's
//! `nalgebra` vectors; parry's own types stay inside this crate.
//!
//! # Example
//!
//! Fill a sphere of radius 0.1 m at dx = 5 mm and compare the particles' volume with the
//! mesh's:
//!
//! ```
//! use geosph_core::Vector;
//! use geosph_geometry::{Solid, primitives};
//!
//! let sphere = Solid::new(primitives::sphere(&Vector::<3>::zeros(), 0.1, 48))?;
//! let dx = 0.005;
//! let particles = sphere.fill(&Vector::<3>::zeros(), dx);
//! let filled = particles.len() as f64 * dx.powi(3);
//! assert!((filled / sphere.volume() - 1.0).abs() < 0.01);
//! # Ok::<(), geosph_geometry::MeshError>(())
//! ```
#![warn(missing_docs)]

mod height_grid;
mod lattice;
mod mesh;
pub mod primitives;
mod solid;
mod surface;

pub use mesh::{MeshError, SurfaceMesh};
pub use solid::{Section, Solid};
pub use surface::{SurfacePoint, WallSite, WallSurface};
