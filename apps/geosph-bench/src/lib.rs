//! The accuracy-against-cost harness of geosph.
//!
//! Runs a matrix of configurations — case × solver × kernel × variant × resolution × time-step
//! factor — on cases with a reference, and records for each run its wall time, particle-steps
//! per second, time steps and error against the reference ([`matrix`]); writes them as CSV, a
//! Markdown report with the observed orders of convergence and the Pareto front of error
//! against wall time, and log–log plots ([`report`]). [`stability`] finds, per solver and
//! kernel, the largest stable time-step factor by bisection and runs the stress cases (long
//! runs, disordered starts, impact, tension).
//!
//! The cases and their references ([`case`]):
//! - Taylor–Green vortex, 2D periodic, Re = 100 (Taylor & Green 1937): velocity field;
//! - hydrostatic tank: p = ρ₀ g (H − y);
//! - dam break: Martin & Moyce (1952) front and column height;
//! - granular column collapse (Bui et al. 2008): the deposit's surface against the experiment;
//! - K₀ column: σ_v = ρ g (H − y), σ_h/σ_v = ν/(1 − ν);
//! - square drop under surface tension: the Laplace jump σ/R ([`fluid_models`]);
//! - Sod's shock tube of an ideal gas: the exact Riemann solution ([`fluid_models`]).
#![warn(missing_docs)]

pub mod case;
pub mod fluid_models;
pub mod laminar;
pub mod matrix;
pub mod measures;
pub mod report;
pub mod stability;

use geosph_core::Real;

pub use case::Case;

/// One run of the matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// The case.
    pub case: Case,
    /// Solver name: `wcsph`, `pcisph`, `iisph`, `dfsph` or `soil`.
    pub solver: &'static str,
    /// Kernel name, as in a scene.
    pub kernel: &'static str,
    /// A solver option set: for WCSPH the density diffusion (`molteni`, `antuono`, `none`),
    /// the default diffusion with SPS turbulence (`sps`) or with the hashed cell index of
    /// the neighbour search (`hashed`), for the square drop no surface tension (`off`),
    /// otherwise `default`.
    pub variant: &'static str,
    /// Particle spacing in m.
    pub dx: Real,
    /// Multiplier of the solver's default Courant number.
    pub dt_factor: Real,
}

impl Config {
    /// A short label, e.g. `dfsph/wendland-c2 dx=0.02 dt×1`.
    pub fn label(&self) -> String {
        let variant = if self.variant == "default" {
            String::new()
        } else {
            format!("+{}", self.variant)
        };
        format!(
            "{}{variant}/{} dx={} dt×{}",
            self.solver, self.kernel, self.dx, self.dt_factor
        )
    }
}

/// What one run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// What was run.
    pub config: Config,
    /// Moving particles.
    pub particles: usize,
    /// Time steps, the soil's geostatic stage included.
    pub steps: usize,
    /// Wall-clock time of the run, set-up included, s.
    pub wall_time: Real,
    /// Particle-steps per wall-clock second.
    pub particle_steps_per_second: Real,
    /// The case's measured quantity (e.g. the runout), for cases compared across runs.
    pub value: Real,
    /// Error against the reference (dimensionless, see [`Case::error_definition`]).
    pub error: Real,
    /// `ok`, or the one-line reason the run failed.
    pub status: String,
}

impl Outcome {
    /// Whether the run finished with a finite error and time.
    pub fn is_ok(&self) -> bool {
        self.completed() && self.error.is_finite()
    }

    /// Whether the run finished, with or without a finite error.
    pub fn completed(&self) -> bool {
        self.status == "ok" && self.wall_time.is_finite()
    }
}
