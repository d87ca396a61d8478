//! The material-neutral SPH layer of geosph, between the building blocks (core, kernels,
//! neighbours, time, boundary) and the materials (`geosph-fluid`, `geosph-soil`).
//!
//! Modules:
//! - [`solver`]: the [`Solver`] interface the runner steps, its [`StepReport`] and
//!   [`SolverError`], and the event-aligned step ([`event_step`]).
//! - [`state`]: [`SolverState`], what a solver saves in a checkpoint to continue bitwise.
//! - [`setup`]: [`SphSetup`], the scene-level inputs of every solver, and [`ParticleStart`],
//!   how a solver's configuration wants its particles to start.
//! - [`eos`]: equations of state (Tait, linear) and their inverses, for WCSPH and for the
//!   initial density of any liquid.
//! - [`config_error`]: [`ConfigError`] and the range checks every solver configuration
//!   validates itself with.
//! - [`lists`]: [`PairLists`], the one owner of the grids, the inner and wall contact lists,
//!   the Verlet skin and the Z-order schedule, with the pair visitors that hand each term
//!   j, r_ij, r² and ∇_i W_ij.
//! - [`pair_arrays`]: one parallel pass writing per-pair and per-particle arrays together.
//! - [`viscosity`]: the viscous pair terms (artificial, laminar) both materials use.
//! - [`density_error`]: the density-error reductions, in a fixed order.
//! - [`lattice`]: kernel sums and gradient calibration on the initial lattice.
//! - [`shifting`]: δ⁺-SPH particle shifting with free-surface detection.
//! - [`sps`]: sub-particle-scale turbulence, the Smagorinsky stress of Dalrymple & Rogers
//!   (2006).
//! - [`wall_contact`]: [`keep_out_of_walls`], no particle ends a step behind a wall's surface.
//! - [`wall_motion`]: [`WallMotion`], walls a solver moves once per step (rigid bodies).
//! - [`surface_load`]: the force and moment of the fluid's pressure on a surface.
#![warn(missing_docs)]

pub mod config_error;
pub mod density_error;
pub mod distributed;
pub mod eos;
pub mod lattice;
pub mod lists;
pub mod pair_arrays;
pub mod setup;
pub mod shifting;
pub mod solver;
pub mod sps;
pub mod state;
pub mod surface_load;
pub mod viscosity;
pub mod wall_contact;
pub mod wall_motion;

pub use config_error::ConfigError;
pub use density_error::{compression, density_errors};
pub use distributed::{Distribution, ExchangeCounts};
pub use eos::{EosKind, EquationOfState, GasLaw};
/// How the pair lists' grids index their cells (dense or hashed), as [`SphSetup`] names it.
pub use geosph_neighbours::CellIndex;
/// The transport of a distributed run (MPI in `geosph-mpi`), as [`Solver::distribute`] takes it.
pub use geosph_partition::Transport;
pub use lists::{Neighbour, PairLists};
pub use setup::{ParticleStart, SphSetup};
pub use shifting::{NoShift, ParticleShifting, ShiftStep, ShiftSums, ShiftTerm, ShiftingInput};
pub use solver::{
    Solver, SolverError, StageReport, StepReport, event_step, max_speed, restore_wall_motion,
};
pub use sps::{NoSps, SpsConfig, SpsTerm, SubParticleStress, TurbulenceTerm};
pub use state::{PartitionState, SolverState, StateArrays, StateError};
pub use viscosity::{
    ArtificialMonaghan1992, Inviscid, LaminarMorris1997, Pair, Viscosity, ViscousTerm,
    ViscousVisitor,
};
pub use wall_contact::keep_out_of_walls;
pub use wall_motion::{FlowShare, MotionError, WallMotion};
