//! The geostatic stage: gravity loading with damping until the soil is at rest, a check of the
//! reached stress against the lithostatic σ_v, and the release.

use std::collections::HashMap;

use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_sph::{Solver, StageReport};

use crate::sph::config::{ConfigError, GeostaticConfig, SoilError, WallSlip};
use crate::sph::solver::SoilSolver;
use crate::sph::system::SoilSystem;

/// What the geostatic stage reached.
#[derive(Clone, Debug, PartialEq)]
pub struct GeostaticReport {
    /// Steps of the stage.
    pub steps: usize,
    /// Simulated time of the stage, s.
    pub time: Real,
    /// Whether E_k fell below the tolerance before `max_time`.
    pub converged: bool,
    /// Final E_k / (½ M (gH/c)²).
    pub kinetic_energy_ratio: Real,
    /// Root mean square of the undamped acceleration |a_i + μ v_i| over |g|: the equilibrium
    /// residual of the SPH momentum equation.
    pub residual_rms: Real,
    /// Largest |a_i + μ v_i| / |g|.
    pub residual_max: Real,
    /// Particles deeper than two layers below the top of their column, where the stress is
    /// compared.
    pub checked_particles: usize,
    /// Largest |σ_v − σ_v,ref| / |σ_v,ref| with σ_v,ref = −ρ₀ |g| (H − y), H the top of the
    /// particle's column (tension positive).
    pub vertical_stress_error_max: Real,
    /// Mean of the same relative error.
    pub vertical_stress_error_mean: Real,
    /// Smallest, mean and largest σ_h/σ_v (σ_h the mean horizontal normal stress).
    pub lateral_ratio: (Real, Real, Real),
    /// Fraction of all particles that flowed plastically during the stage.
    pub plastic_fraction: Real,
    /// Wall particles removed at release.
    pub released_walls: usize,
}

impl std::fmt::Display for GeostaticReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "geostatic stage: {} steps, {:.4} s, {} (E_k ratio {:.1e}); residual rms {:.2e} g, max {:.2e} g; \
             sigma_v error max {:.2} %, mean {:.2} % over {} particles; sigma_h/sigma_v {:.3}..{:.3} (mean {:.3}); \
             plastic {:.1} %; {} wall particles released",
            self.steps,
            self.time,
            if self.converged {
                "at rest"
            } else {
                "NOT at rest"
            },
            self.kinetic_energy_ratio,
            self.residual_rms,
            self.residual_max,
            100.0 * self.vertical_stress_error_max,
            100.0 * self.vertical_stress_error_mean,
            self.checked_particles,
            self.lateral_ratio.0,
            self.lateral_ratio.2,
            self.lateral_ratio.1,
            100.0 * self.plastic_fraction,
            self.released_walls
        )
    }
}

/// The kinetic energy of `soil`, J (per metre in 2D).
pub(crate) fn kinetic_energy<const D: usize>(soil: &Particles<D>) -> Real {
    soil.velocity
        .iter()
        .zip(&soil.mass)
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum()
}

/// The scales of a damped relaxation of soil H high along gravity (the geostatic stage and the
/// strength-reduction trials): the damping μ = 2ζω₁ with ω₁ = πc/(2H), the shortest
/// relaxation 4H/c (one period of that mode) and the energy ½ M (gH/c)² that rest is measured
/// against (c the P-wave speed, M the soil's mass).
pub(crate) struct RelaxationScale {
    /// H, m.
    pub height: Real,
    /// μ, 1/s.
    pub damping: Real,
    /// 4H/c, s.
    pub min_time: Real,
    /// ½ M (gH/c)², J.
    pub reference_energy: Real,
}

impl RelaxationScale {
    /// The scales of `soil` in `solver` with damping ratio ζ = `damping_ratio`.
    pub fn of<const D: usize, K: Kernel<D>>(
        solver: &SoilSolver<D, K>,
        soil: &Particles<D>,
        damping_ratio: Real,
    ) -> Self {
        let system = &solver.system;
        let g = system.gravity.norm();
        let down = system.gravity / g;
        let (low, high) = soil
            .position
            .iter()
            .map(|x| -x.dot(&down))
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), h| {
                (lo.min(h), hi.max(h))
            });
        let height = high - low + system.spacing;
        let c = system.wave_speed;
        let omega = std::f64::consts::PI * c / (2.0 * height);
        let total_mass: Real = soil.mass.iter().sum();
        let speed = g * height / c;
        Self {
            height,
            damping: 2.0 * damping_ratio * omega,
            min_time: 4.0 * height / c,
            reference_energy: 0.5 * total_mass * speed * speed,
        }
    }
}

/// Runs the stage on `soil` with `solver`, then releases: removes the wall particles inside
/// `config.release` ([`SoilSystem::release_walls`]), zeroes velocity, displacement, strain and plastic
/// strain, and gives the solver back the run's damping and wall slip.
impl<const D: usize, K: Kernel<D>> SoilSolver<D, K> {
    /// Runs the geostatic stage `config` on `soil` ([`Solver::initial_stage`] calls it).
    pub fn run_geostatic_stage(
        &mut self,
        soil: &mut Particles<D>,
        config: &GeostaticConfig,
    ) -> Result<GeostaticReport, SoilError> {
        run_stage(self, soil, config)
    }
}

fn run_stage<const D: usize, K: Kernel<D>>(
    solver: &mut SoilSolver<D, K>,
    soil: &mut Particles<D>,
    config: &GeostaticConfig,
) -> Result<GeostaticReport, SoilError> {
    let gravity = solver.system.gravity;
    let g = gravity.norm();
    if g == 0.0 {
        return Err(SoilError::Config(ConfigError {
            field: "geostatic".into(),
            message: "a geostatic stage needs gravity".into(),
        }));
    }
    let down = gravity / g;
    let spacing = solver.system.spacing;
    let scale = RelaxationScale::of(solver, soil, config.damping_ratio);
    let run_damping = solver.system.damping_rate();
    solver.system.set_damping_rate(scale.damping);
    let run_slip = solver.system.wall_config.slip;
    if config.free_slip_walls {
        solver.system.wall_config.slip = WallSlip::FreeSlip;
    }
    let (mut time, mut steps, mut converged) = (0.0, 0, false);
    let mut ratio = Real::INFINITY;
    while time < config.max_time {
        let report = solver.step(soil, time, config.max_time - time)?;
        time += report.dt;
        steps += 1;
        if steps % 10 == 0 || time >= config.max_time {
            ratio = kinetic_energy(soil) / scale.reference_energy;
            if !ratio.is_finite() {
                return Err(SoilError::Config(ConfigError {
                    field: "geostatic".into(),
                    message: format!("the stage blew up after {steps} steps (t = {time:.4} s)"),
                }));
            }
            if time >= scale.min_time && ratio < config.kinetic_energy_tolerance {
                converged = true;
                break;
            }
        }
    }
    let mu = solver.system.damping_rate();
    let residuals: Vec<Real> = solver
        .system
        .acceleration()
        .iter()
        .zip(&soil.velocity)
        .map(|(a, v)| (a + v * mu).norm() / g)
        .collect();
    let residual_rms =
        (residuals.iter().map(|r| r * r).sum::<Real>() / residuals.len().max(1) as Real).sqrt();
    let residual_max = residuals.iter().copied().fold(0.0, Real::max);
    let mut report = stress_check(soil, &down, g, solver.system.rest_density, spacing);
    report.steps = steps;
    report.time = time;
    report.converged = converged;
    report.kinetic_energy_ratio = ratio;
    report.residual_rms = residual_rms;
    report.residual_max = residual_max;
    report.released_walls = solver.system.release_walls(config)?;
    solver.system.set_damping_rate(run_damping);
    solver.system.wall_config.slip = run_slip;
    let fields = soil
        .soil
        .as_mut()
        .expect("soil particles carry soil fields");
    soil.velocity.fill(Vector::zeros());
    fields.displacement.fill(nalgebra::Vector3::zeros());
    fields.strain.fill(geosph_core::Tensor3::zeros());
    fields.plastic_strain.fill(0.0);
    Ok(report)
}

impl<const D: usize, K: Kernel<D>> SoilSystem<D, K> {
    /// Removes the wall particles inside the stage's `release` boxes (the release at the end
    /// of the geostatic stage, applied again on a restart, whose solver is built with the walls
    /// of the scene) and returns how many.
    pub fn release_walls(&mut self, config: &GeostaticConfig) -> Result<usize, SearchError> {
        self.remove_walls(|x| {
            config
                .release
                .iter()
                .any(|b| (0..D).all(|k| x[k] >= b.min[k] && x[k] <= b.max[k]))
        })
    }
}

impl GeostaticReport {
    /// The report in the runner's material-neutral form, every field a named figure.
    pub fn stage_report(&self) -> StageReport {
        let figures = [
            ("time", self.time),
            ("converged", Real::from(u8::from(self.converged))),
            ("kinetic_energy_ratio", self.kinetic_energy_ratio),
            ("residual_rms", self.residual_rms),
            ("residual_max", self.residual_max),
            ("checked_particles", self.checked_particles as Real),
            ("vertical_stress_error_max", self.vertical_stress_error_max),
            (
                "vertical_stress_error_mean",
                self.vertical_stress_error_mean,
            ),
            ("lateral_ratio_min", self.lateral_ratio.0),
            ("lateral_ratio_mean", self.lateral_ratio.1),
            ("lateral_ratio_max", self.lateral_ratio.2),
            ("plastic_fraction", self.plastic_fraction),
            ("released_walls", self.released_walls as Real),
        ];
        StageReport {
            name: "geostatic".into(),
            steps: self.steps,
            text: self.to_string(),
            figures: figures
                .into_iter()
                .map(|(name, value)| (name.to_string(), value))
                .collect(),
        }
    }
}

/// σ_v and σ_h/σ_v of the particles deeper than two layers below the top of their column
/// (columns are bins of width dx across gravity).
fn stress_check<const D: usize>(
    soil: &Particles<D>,
    down: &Vector<D>,
    g: Real,
    rest_density: Real,
    spacing: Real,
) -> GeostaticReport {
    let fields = soil
        .soil
        .as_ref()
        .expect("soil particles carry soil fields");
    let column = |x: &Vector<D>| -> Vec<i64> {
        let across = x + down * (-x.dot(down));
        (0..D)
            .map(|k| (across[k] / spacing).round() as i64)
            .collect()
    };
    let mut top: HashMap<Vec<i64>, Real> = HashMap::new();
    for x in &soil.position {
        let height = -x.dot(down);
        let entry = top.entry(column(x)).or_insert(Real::NEG_INFINITY);
        *entry = entry.max(height);
    }
    let (mut count, mut error_max, mut error_sum) = (0, 0.0, 0.0);
    let (mut ratio_min, mut ratio_sum, mut ratio_max) = (Real::INFINITY, 0.0, Real::NEG_INFINITY);
    let mut plastic = 0;
    for (i, x) in soil.position.iter().enumerate() {
        if fields.plastic_strain[i] > 0.0 {
            plastic += 1;
        }
        let column_top = top[&column(x)] + 0.5 * spacing;
        let depth = column_top - (-x.dot(down));
        if depth < 2.0 * spacing {
            continue;
        }
        let sigma = &fields.stress[i];
        let mut sigma_v = 0.0;
        let mut trace = 0.0;
        for a in 0..D {
            trace += sigma[(a, a)];
            for b in 0..D {
                sigma_v += down[a] * sigma[(a, b)] * down[b];
            }
        }
        let sigma_h = (trace - sigma_v) / (D - 1) as Real;
        let reference = -rest_density * g * depth;
        let error = ((sigma_v - reference) / reference).abs();
        error_max = Real::max(error_max, error);
        error_sum += error;
        let ratio = sigma_h / sigma_v;
        ratio_min = ratio_min.min(ratio);
        ratio_max = ratio_max.max(ratio);
        ratio_sum += ratio;
        count += 1;
    }
    let n = count.max(1) as Real;
    GeostaticReport {
        steps: 0,
        time: 0.0,
        converged: false,
        kinetic_energy_ratio: 0.0,
        residual_rms: 0.0,
        residual_max: 0.0,
        checked_particles: count,
        vertical_stress_error_max: error_max,
        vertical_stress_error_mean: error_sum / n,
        lateral_ratio: (ratio_min, ratio_sum / n, ratio_max),
        plastic_fraction: plastic as Real / soil.len().max(1) as Real,
        released_walls: 0,
    }
}
