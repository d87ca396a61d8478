//! `blowup.txt`: the human-readable report of a blow-up.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use geosph_core::{Particles, Real};
use geosph_sph::Solver;

use super::{Diagnosis, Limits, OUTSIDE_ADVICE, Quantity};
use crate::output::RunOutput;

/// The last good state of a blown-up run, in its output folder.
pub const LAST_GOOD_FILE: &str = "blowup.vtu";

/// The failed state of a blown-up run, for inspection.
pub const FAILED_FILE: &str = "blowup-failed.vtu";

/// The report of a blown-up run.
pub const REPORT_FILE: &str = "blowup.txt";

/// Where a blown-up run saved its states and report.
#[derive(Clone, Debug, PartialEq)]
pub enum BlowUpFiles {
    /// In the output folder.
    Written {
        /// [`LAST_GOOD_FILE`]: the state before the failed step.
        last_good: PathBuf,
        /// [`FAILED_FILE`]: the state the failed step left.
        failed: PathBuf,
        /// [`REPORT_FILE`].
        report: PathBuf,
    },
    /// The run had no output folder.
    NoOutput,
    /// Writing them failed, for this reason.
    Failed(String),
}

impl std::fmt::Display for BlowUpFiles {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Written {
                last_good, report, ..
            } => write!(
                f,
                "last good frame `{}`, report `{}`",
                last_good.display(),
                report.display()
            ),
            Self::NoOutput => f.write_str("no output folder: nothing saved"),
            Self::Failed(reason) => write!(f, "saving the blow-up files failed: {reason}"),
        }
    }
}

/// Particles the report describes, worst first.
pub const SUSPECTS: usize = 5;

/// Neighbours listed by id and distance for each suspect, closest first.
pub const CLOSEST: usize = 6;

/// Everything the report is written from.
pub struct BlowUpReport<'a, const D: usize> {
    /// Scene name.
    pub scene: &'a str,
    /// The solver (its name and advice, the density error it controls, its walls).
    pub solver: &'a dyn Solver<D>,
    /// What went wrong.
    pub diagnosis: &'a Diagnosis,
    /// The failed step (1 is the first step of the run).
    pub step: usize,
    /// Simulated time at the end of the failed step (its start when the solver failed
    /// inside the step), s.
    pub time: Real,
    /// The state the failed step produced (or left, when the solver failed inside it).
    pub failed: &'a Particles<D>,
    /// The state before the failed step, and its time.
    pub last_good: (&'a Particles<D>, Real),
    /// The run's bounds.
    pub limits: &'a Limits<D>,
    /// The files written beside the report, named in it: (last good, failed) state.
    pub frames: (&'a str, &'a str),
}

impl<const D: usize> BlowUpReport<'_, D> {
    /// Writes the last good state, the failed state (both with the walls) and the report into
    /// the folder of `output`, each atomically, in that order.
    pub fn save(&self, output: &RunOutput) -> BlowUpFiles {
        let solver = self.solver;
        let written = (|| {
            let last_good = output.write_snapshot(self.frames.0, self.last_good.0, solver)?;
            let failed = output.write_snapshot(self.frames.1, self.failed, solver)?;
            let report = output.dir().join(REPORT_FILE);
            self.write(&report)?;
            Ok::<_, geosph_io::Error>(BlowUpFiles::Written {
                last_good,
                failed,
                report,
            })
        })();
        written.unwrap_or_else(|error| BlowUpFiles::Failed(error.to_string()))
    }

    /// Writes the report to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), geosph_io::Error> {
        let text = self.text();
        geosph_io::write_atomically(path, |w| w.write_all(text.as_bytes()))
    }

    /// The report's text.
    pub fn text(&self) -> String {
        let d = self.diagnosis;
        let mut text = String::new();
        let t = &mut text;
        let _ = writeln!(t, "geosph blow-up report");
        let _ = writeln!(t);
        let _ = writeln!(
            t,
            "scene        {} ({}D, {}, {} particles)",
            self.scene,
            D,
            self.solver.name(),
            self.failed.len()
        );
        let _ = writeln!(
            t,
            "step         {} failed, reaching t = {:.6} s; the last good state is step {} at t = {:.6} s",
            self.step,
            self.time,
            self.step.saturating_sub(1),
            self.last_good.1
        );
        let _ = writeln!(t, "quantity     {}", d.quantity);
        let bound = match d.bound {
            Some(bound) => format!("bound {}", num(bound)),
            None => "must be finite".to_owned(),
        };
        let _ = writeln!(
            t,
            "value        {} {} ({bound})",
            num(d.value),
            d.quantity.unit()
        );
        if let Some((i, id)) = d.particle {
            let _ = writeln!(t, "particle     {i} (id {id})");
        }
        let _ = writeln!(t, "explanation  {}", d.explanation);
        let _ = writeln!(t, "advice       {}", advice(d.quantity, self.solver));
        let _ = writeln!(
            t,
            "files        {}: the last good state (step {}); {}: the failed state (step {})",
            self.frames.0,
            self.step.saturating_sub(1),
            self.frames.1,
            self.step
        );
        let _ = writeln!(
            t,
            "bounds       density error {}; stress {}; kinetic energy {}",
            super::MAX_DENSITY_ERROR,
            self.limits
                .max_stress
                .map_or("unchecked".to_owned(), |s| format!("{} Pa", num(s))),
            match &self.limits.energy {
                Some(budget) => format!(
                    "{} × (initial {} J + work of gravity) + {} J",
                    super::ENERGY_FACTOR,
                    num(budget.initial),
                    num(budget.floor)
                ),
                None => "unchecked (gravity along a periodic axis)".to_owned(),
            }
        );
        let _ = writeln!(t);
        let _ = writeln!(
            t,
            "worst particles (index in the failed state; the id is the `id` field of both VTU files)"
        );
        for (rank, &i) in self.suspects().iter().enumerate() {
            let _ = writeln!(t);
            self.describe(t, rank + 1, i);
        }
        text
    }

    /// The particles to describe, worst first: the one the diagnosis names, then the others
    /// ranked by the failed quantity.
    pub fn suspects(&self) -> Vec<usize> {
        let fluid = self.failed;
        let speed = |i: usize| fluid.velocity[i].norm();
        let stress = |i: usize| fluid.soil.as_ref().map_or(0.0, |s| s.stress[i].norm());
        let outside = |i: usize| {
            let (x, domain) = (&fluid.position[i], &self.limits.domain);
            (0..D)
                .filter(|&k| !domain.periodic[k])
                .map(|k| (domain.min[k] - x[k]).max(x[k] - domain.max[k]))
                .fold(Real::NEG_INFINITY, Real::max)
        };
        let non_finite = |i: usize| {
            let finite = fluid.position[i].iter().all(|c| c.is_finite())
                && fluid.velocity[i].iter().all(|c| c.is_finite())
                && fluid.density[i].is_finite()
                && stress(i).is_finite();
            if finite { speed(i) } else { Real::INFINITY }
        };
        let score = |i: usize| -> Real {
            let score = match self.diagnosis.quantity {
                Quantity::TimeStep | Quantity::Velocity | Quantity::Density => non_finite(i),
                Quantity::Position => outside(i).max(non_finite(i)),
                Quantity::DensityError => self.solver.density_error(fluid.density[i]),
                Quantity::Stress => stress(i),
                Quantity::KineticEnergy => 0.5 * fluid.mass[i] * speed(i).powi(2),
            };
            if score.is_nan() {
                Real::INFINITY
            } else {
                score
            }
        };
        let named = self.diagnosis.particle.map(|(i, _)| i);
        let mut order: Vec<usize> = (0..fluid.len()).filter(|&i| Some(i) != named).collect();
        order.sort_by(|&a, &b| score(b).total_cmp(&score(a)).then(a.cmp(&b)));
        named
            .into_iter()
            .filter(|&i| i < fluid.len())
            .chain(order)
            .take(SUSPECTS)
            .collect()
    }

    /// Writes the description of particle `i` of the failed state.
    fn describe(&self, t: &mut String, rank: usize, i: usize) {
        let fluid = self.failed;
        let id = fluid.id[i];
        let _ = writeln!(t, "#{rank} particle {i} (id {id})");
        let _ = writeln!(t, "   failed     {}", self.state(fluid, i));
        match self.last_good.0.id.iter().position(|&other| other == id) {
            Some(j) => {
                let _ = writeln!(t, "   last good  {}", self.state(self.last_good.0, j));
            }
            None => {
                let _ = writeln!(t, "   last good  (not found)");
            }
        }
        let _ = writeln!(t, "   neighbours {}", self.neighbours(i));
    }

    /// Position, velocity, density (and stress) of particle `i` of `particles`.
    fn state(&self, particles: &Particles<D>, i: usize) -> String {
        let v = &particles.velocity[i];
        let mut text = format!(
            "x = {}, v = {} (|v| = {} m/s), ρ = {} kg/m³ (density error {:.2} %)",
            point(particles.position[i].as_slice()),
            point(v.as_slice()),
            num(v.norm()),
            num(particles.density[i]),
            100.0 * self.solver.density_error(particles.density[i])
        );
        if let Some(soil) = &particles.soil {
            let _ = write!(text, ", ‖σ‖ = {} Pa", num(soil.stress[i].norm()));
        }
        text
    }

    /// The fluid and wall particles of the failed state within the support radius of particle
    /// `i`, found by brute force: their count and the closest ones by id and distance.
    fn neighbours(&self, i: usize) -> String {
        let fluid = self.failed;
        let x = &fluid.position[i];
        if !x.iter().all(|c| c.is_finite()) {
            return "none: the position is not finite".to_owned();
        }
        let (domain, radius, dx) = (
            &self.limits.domain,
            self.limits.support_radius,
            self.limits.spacing,
        );
        let mut near: Vec<(Real, u32)> = fluid
            .position
            .iter()
            .zip(&fluid.id)
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, (y, &id))| (domain.displacement(x, y).norm(), id))
            .filter(|(r, _)| *r < radius)
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let walls: Vec<Real> = self
            .solver
            .walls()
            .position
            .iter()
            .map(|y| domain.displacement(x, y).norm())
            .filter(|r| *r < radius)
            .collect();
        let closest_wall = walls.iter().copied().fold(Real::INFINITY, Real::min);
        let mut text = format!(
            "{} fluid and {} wall particles within the support radius {} m ({:.2} dx)",
            near.len(),
            walls.len(),
            num(radius),
            radius / dx
        );
        if !near.is_empty() {
            let closest: Vec<String> = near
                .iter()
                .take(CLOSEST)
                .map(|(r, id)| format!("id {id} at {} m ({:.2} dx)", num(*r), r / dx))
                .collect();
            let _ = write!(text, "; closest: {}", closest.join(", "));
        }
        if closest_wall.is_finite() {
            let _ = write!(
                text,
                "; closest wall particle at {} m ({:.2} dx)",
                num(closest_wall),
                closest_wall / dx
            );
        }
        text
    }
}

/// What a user can change, per quantity.
fn advice<const D: usize>(quantity: Quantity, solver: &dyn Solver<D>) -> String {
    match quantity {
        Quantity::Position => OUTSIDE_ADVICE.to_owned(),
        Quantity::Stress => "the stress integration is unstable: lower `cfl`, raise the artificial viscosity, or check the elastic constants".to_owned(),
        Quantity::KineticEnergy => format!(
            "the scheme creates energy, which precedes most blow-ups: {}",
            solver.blow_up_advice()
        ),
        Quantity::TimeStep | Quantity::Velocity | Quantity::Density | Quantity::DensityError => {
            solver.blow_up_advice().to_owned()
        }
    }
}

/// A number for the report: fixed-point in [10⁻³, 10⁴), else scientific.
pub fn num(x: Real) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{x:.5}")
    } else {
        format!("{x:.4e}")
    }
}

/// `(x, y, z)` with [`num`] for each coordinate.
pub fn point(coordinates: &[Real]) -> String {
    let parts: Vec<String> = coordinates.iter().map(|&x| num(x)).collect();
    format!("({})", parts.join(", "))
}
