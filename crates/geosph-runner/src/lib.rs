//! Runs a geosph scene.
//!
//! [`run`] validates the scene, builds particles and the solver it declares (and nothing it
//! does not declare), steps the solver to the end time with events at the output and sample
//! times, writes a VTU frame per output interval plus a `.pvd` series that ParaView opens, a
//! `diagnostics.csv` time series, shows a progress bar with ETA, and returns a [`Summary`].
//! A step whose state is not finite or whose density error exceeds the blow-up bound stops the
//! run with [`RunError::BlowUp`], the last good frame already on disk.
//!
//! Modules:
//! - [`observer`]: the [`Observer`] hook through which applications sample their own
//!   quantities (e.g. a dam-break front) at every sample time.
//! - [`output`]: the run's output folder: frames, `.pvd`, CSV.
//! - [`health`]: the blow-up checks.
//! - [`run`](mod@run): the loop, [`RunOptions`], [`Summary`], [`RunError`].
#![warn(missing_docs)]

pub mod health;
pub mod observer;
pub mod output;
pub mod run;

pub use observer::{NoObserver, Observer};
pub use run::{RunError, RunOptions, Summary, run};
