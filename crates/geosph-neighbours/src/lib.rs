//! Fixed-radius neighbour search for SPH on a uniform cell grid.
//!
//! A [`CellGrid`] sorts a particle set into cells at least one search radius wide (counting
//! sort, in parallel with rayon) and answers queries by scanning the 3^D cells around a point:
//! CSR [`NeighbourList`](geosph_core::NeighbourList)s in cell order, bitwise identical for any
//! number of threads, or closure-style access. Periodic axes use the minimum image.
//!
//! Modules:
//! - [`grid`]: [`CellGrid`], its construction over a [`Domain`](geosph_core::Domain) and the
//!   counting sort of particles into cells ([`CellGrid::build`]); with
//!   [`CellGrid::hashed`], an index of the occupied cells only (`hashed.rs`), for unbounded
//!   or very sparse domains.
//! - [`query`]: [`CellGrid::neighbour_list`] (CSR lists for self and cross queries) and
//!   [`CellGrid::for_each_neighbour`].
//! - [`morton`]: Morton (Z-order) codes and [`CellGrid::z_order`], the permutation that makes
//!   memory order follow space.
//! - [`error`]: [`SearchError`], why a grid could not be made or built.
//!
//! ```
//! use geosph_core::{Domain, NeighbourList, Vector};
//! use geosph_neighbours::CellGrid;
//!
//! let domain = Domain::new(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(1.0, 1.0)).unwrap();
//! let x = vec![Vector::<2>::new(0.1, 0.1), Vector::<2>::new(0.2, 0.1), Vector::<2>::new(0.9, 0.9)];
//! let mut grid = CellGrid::new(domain, 0.1).unwrap();
//! grid.build(&x).unwrap();
//! let mut list = NeighbourList::new();
//! grid.neighbour_list(&x, &x, &mut list);
//! assert_eq!(list.neighbours(0), &[0, 1]); // exactly at the radius counts
//! assert_eq!(list.neighbours(2), &[2]);
//! ```
#![warn(missing_docs)]

pub mod error;
pub mod grid;
mod hashed;
pub mod morton;
pub mod query;
mod scratch;

pub use error::SearchError;
pub use grid::{CellGrid, CellIndex};
pub use morton::{morton_encode, morton_encode_2d, morton_encode_3d};

/// The rayon this crate runs on, re-exported so that callers can pick the number of threads
/// for a search (`rayon::ThreadPoolBuilder::new().num_threads(n).build()?.install(..)`)
/// without a dependency of their own.
pub use rayon;
