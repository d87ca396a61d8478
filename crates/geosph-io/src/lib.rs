//! Output of geosph runs: particle frames for ParaView, diagnostics as CSV, plots as PNG.
//!
//! Every file is written atomically (temporary file in the same folder, `sync_all`, `rename`),
//! so a run killed at any moment leaves each output file either in its previous complete state
//! or in its new complete state, never half-written.
//!
//! Modules:
//! - [`atomic`]: [`write_atomically`] and [`replace_atomically`], the write-to-temporary-then-rename
//!   primitive every other module uses.
//! - [`vtu`]: one particle frame (positions and per-particle fields, one or several particle
//!   sets) as a compressed binary VTK XML UnstructuredGrid (`.vtu`) of vertex cells.
//! - [`pvd`]: [`PvdCollection`], the VTK Collection (`.pvd`) that lists the `.vtu` frames of a
//!   run with their times, rewritten after every frame and reopened on restart.
//! - [`csv`]: [`CsvSeries`], a time-series CSV writer flushed row by row, and
//!   [`write_csv_atomically`] for whole tables.
//! - [`plot`]: [`line_plot_png`], line plots (simulation) with point markers (reference data),
//!   linear or log–log axes, as PNG.
//!
//! Errors of all modules are one [`Error`] type; every file-system error names its path.
//!
//! # Example
//!
//! Write a 2D frame of three particles with a pressure field and list it in a `.pvd`:
//!
//! ```
//! use geosph_core::{Real, Vector};
//! use geosph_io::{write_vtu, Field, FieldData, Frame, PvdCollection};
//!
//! let dir = std::env::temp_dir().join(format!("geosph-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//!
//! let position = [Vector::<2>::new(0.0, 0.0), Vector::new(0.1, 0.0), Vector::new(0.0, 0.1)];
//! let pressure: [Real; 3] = [1.0e3, 2.0e3, 3.0e3];
//! let frame = Frame {
//!     position: &position,
//!     fields: vec![Field { name: "pressure", data: FieldData::Scalar(&pressure) }],
//! };
//! write_vtu(dir.join("frame_000000.vtu"), &frame)?;
//!
//! let mut series = PvdCollection::open_or_create(dir.join("particles.pvd"))?;
//! series.add(0.0, "frame_000000.vtu")?;
//! assert_eq!(series.entries().len(), 1);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod atomic;
pub mod csv;
pub mod plot;
pub mod pvd;
pub mod vtu;

mod error;

pub use atomic::{replace_atomically, write_atomically};
pub use csv::{CsvSeries, write_csv_atomically};
pub use error::Error;
pub use plot::{Axes, PlotSpec, Series, line_plot_png};
pub use pvd::{PvdCollection, PvdEntry};
pub use vtu::{Field, FieldData, Frame, write_vtu, write_vtu_sets};
