//! Runs a geosph scene.
//!
//! [`run`](fn@run) validates the scene, builds particles and the solver it declares (and nothing it
//! does not declare), steps the solver to the end time with events at the output and sample
//! times, writes a VTU frame per output interval plus a `.pvd` series that ParaView opens, a
//! `diagnostics.csv` time series, shows a progress bar with ETA, and returns a [`Summary`].
//! Particles that leave the domain are removed from the run and counted ([`escape`]). After
//! every step [`health::check`] looks for a blow-up (a non-finite value, a particle outside the
//! domain once more than the allowed fraction has left, a density error, soil stress or
//! kinetic energy beyond its bound); the first one stops the run with [`RunError::BlowUp`],
//! after writing the state before the failed step (`blowup.vtu`), the failed state and a report
//! (`blowup.txt`) into the output folder.
//!
//! Modules:
//! - [`observer`]: the [`Observer`] hook through which applications sample their own
//!   quantities (e.g. a dam-break front) at every sample time.
//! - [`share`]: [`Share`], what a sample sees of the particles: every particle in one
//!   process, a rank's own with the reductions over the ranks in a distributed run.
//! - [`output`]: the run's output folder: frames, `.pvd`, CSV.
//! - [`loads`]: force and moment of the fluid's pressure on mesh walls (the scene's
//!   `output.loads`), extra columns of `diagnostics.csv` and `loads.png`.
//! - [`probes`]: pressure probes at fixed points (the scene's `output.probes`), extra columns
//!   `p_<name>` of `diagnostics.csv`.
//! - [`heights`]: water-level gauges along vertical lines (the scene's `output.heights`),
//!   extra columns `h_<name>` of `diagnostics.csv` and `heights.png`.
//! - [`health`]: the blow-up checks, their bounds and the blow-up report.
//! - [`escape`]: particles that leave the domain, removed from the run, counted and reported.
//! - [`interrupt`]: the Ctrl-C flag the loop checks once per step.
//! - [`checkpoint`]: the complete state of a run in `checkpoint.bin`, for a bitwise restart.
//! - [`run`](mod@run): [`run`](fn@run), [`RunOptions`], [`Summary`], [`RunError`]; the loop
//!   itself is a private run-loop type (start or restart, step, sample, output, checkpoint,
//!   blow-up, finish).
//!
//! # Example
//!
//! Run a tiny scene for a few milliseconds without writing files (set
//! [`RunOptions::out_dir`] to get frames, the `.pvd` and `diagnostics.csv`):
//!
//! ```
//! use geosph_runner::{NoObserver, RunOptions, run};
//! use geosph_scene::Scene;
//!
//! let scene = Scene::from_ron(r#"Scene(
//!     name: "tiny", dimension: 2, dx: 0.1, end_time: 0.005,
//!     fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.4, 0.4])]),
//!     walls: [Tank(min: [0.0, 0.0], max: [1.0, 1.0])],
//!     solver: Wcsph(()),
//! )"#)?;
//! let summary = run(&scene, &RunOptions { threads: Some(1), ..Default::default() }, &mut NoObserver)?;
//! assert_eq!(summary.fluid_particles, 16);
//! assert!(summary.simulated_time >= 0.005 - 1e-12 && summary.frames == 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod checkpoint;
#[cfg(feature = "cli")]
pub mod cli;
mod error;
pub mod escape;
pub mod health;
pub mod heights;
pub mod interrupt;
pub mod loads;
pub mod observer;
mod options;
pub mod output;
pub mod probes;
pub mod run;
mod run_loop;
pub mod share;
mod summary;

pub use checkpoint::CheckpointEvery;
pub use heights::HeightGauges;
pub use loads::WallLoads;
pub use observer::{NoObserver, Observer, push_records, take_records};
pub use options::Ranks;
pub use output::scene_outputs;
pub use probes::PressureProbes;
pub use run::{RunError, RunOptions, Summary, run};
pub use run_loop::build_solver;
pub use share::Share;
pub use summary::RankLoad;
