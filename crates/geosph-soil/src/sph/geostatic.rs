//! The geostatic stage: a damped relaxation to rest under gravity from σ = 0 or from the K₀
//! state, a check of the reached stress against the state that applies, and the release.

use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_sph::StageReport;

use crate::sph::config::{ConfigError, GeostaticConfig, InitialStress, SoilError, WallSlip};
use crate::sph::relaxation::{Relaxation, RelaxationScale, relax};
use crate::sph::solver::SoilSolver;
use crate::sph::stress_check::{
    CheckSetup, Columns, OedometricRatio, StressCheck, ZoneCheck, check_stress,
};
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
    /// σ_v and σ_h/σ_v below the top three layers: the free field against the 1D state, the
    /// soil next to rough side walls against Janssen's arching ([`check_stress`]).
    pub stress: StressCheck,
    /// Fraction of all particles that flowed plastically during the stage.
    pub plastic_fraction: Real,
    /// Wall particles removed at release.
    pub released_walls: usize,
}

impl std::fmt::Display for GeostaticReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "geostatic stage: {} steps, {:.4} s, {} (E_k ratio {:.1e}); residual rms {:.2e} g, max {:.2e} g",
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
        )?;
        let stress = &self.stress;
        let zone = |f: &mut std::fmt::Formatter<'_>, name: &str, z: &ZoneCheck| {
            if z.particles == 0 {
                return write!(f, "; {name}: no particles");
            }
            write!(
                f,
                "; {name}: {} particles, sigma_v error max {:.2} %, mean {:.2} % (sigma_v/rho g (H - y) mean {:.3}), \
                 sigma_h/sigma_v {:.3}..{:.3} (mean {:.3}, oedometric ratio error max {:.1} %)",
                z.particles,
                100.0 * z.vertical_stress_error_max,
                100.0 * z.vertical_stress_error_mean,
                z.vertical_stress_ratio_mean,
                z.lateral_ratio.0,
                z.lateral_ratio.2,
                z.lateral_ratio.1,
                100.0 * z.lateral_ratio_error_max,
            )
        };
        let free = if stress.free_field_distance.is_finite() {
            format!(
                "free field (> {:.3} m from rough side walls)",
                stress.free_field_distance
            )
        } else {
            "free field (no wall carries shear)".to_string()
        };
        zone(f, &free, &stress.free_field)?;
        if stress.wall_zone.particles > 0 {
            zone(f, "wall zone", &stress.wall_zone)?;
        }
        if let Some(j) = &stress.janssen {
            write!(
                f,
                "; Janssen (tan delta {:.3}, K {:.3}, B {:.3} m) over {} layers: error max {:.1} % of rho g z, \
                 deepest layer {:.3} (Janssen {:.3}), {} layers outside [Janssen, 1D]",
                j.wall_friction,
                j.lateral_ratio,
                j.width,
                j.layers,
                100.0 * j.error_max,
                j.deepest.0,
                j.deepest.1,
                j.outside_bounds
            )?;
        }
        write!(
            f,
            "; plastic {:.1} %; {} wall particles released",
            100.0 * self.plastic_fraction,
            self.released_walls
        )
    }
}

/// Runs the stage on `soil` with `solver` (a damped relaxation to rest), then releases: removes the wall particles
/// inside `config.release` ([`SoilSystem::release_walls`]), zeroes velocity, displacement,
/// strain and plastic strain, and gives the solver back the run's wall slip.
impl<const D: usize, K: Kernel<D>> SoilSolver<D, K> {
    /// Runs the geostatic stage `config` on `soil` ([`geosph_sph::Solver::initial_stage`] calls it).
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
    let oedometric_start = config.initial_stress == InitialStress::Oedometric;
    if oedometric_start && down.iter().filter(|c| c.abs() == 1.0).count() != 1 {
        return Err(SoilError::Config(ConfigError {
            field: "geostatic.initial_stress".into(),
            message: format!(
                "Oedometric needs gravity along a coordinate axis (its columns are the \
                 lattice's), got the direction {:?}; use `initial_stress: Zero` (gravity loading)",
                down.as_slice()
            ),
        }));
    }
    let scale = RelaxationScale::of(solver, soil, config.damping_ratio);
    let run_slip = solver.system.wall_config.slip;
    if config.free_slip_walls {
        solver.system.wall_config.slip = WallSlip::FreeSlip;
    }
    let unit_weight = solver.system.rest_density * g;
    let oedometer = OedometricRatio::for_column(&solver.system.model, unit_weight, scale.height);
    if oedometric_start {
        set_oedometric_stress(soil, down, unit_weight, solver.system.spacing, &oedometer);
    }
    // The stage seeks a static state without a checkerboard (η ≤ 0.014, docs/soil.md), and the
    // diffusion's lithostatic K₀ need not be the state's (Jaky's 1 − sin φ against the
    // oedometric ratio on the cone): the diffusion acts in the run only.
    let relaxation = solver.without_mean_stress_diffusion(|solver| {
        relax(
            solver,
            soil,
            &scale,
            config.max_time,
            config.kinetic_energy_tolerance,
            |_| false,
        )
    });
    let Relaxation {
        steps,
        time,
        kinetic_energy_ratio,
        at_rest,
    } = relaxation.map_err(|failure| {
        solver.system.wall_config.slip = run_slip;
        SoilError::Config(ConfigError {
            field: "geostatic".into(),
            message: format!("the stage blew up: {failure}"),
        })
    })?;
    // The equilibrium residual of the damped equation the stage solved.
    let mu = scale.damping;
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
    let system = &solver.system;
    // `free_slip_walls` has made the walls free-slip for the stage.
    let no_shear = system.wall_config.slip == WallSlip::FreeSlip;
    let setup = CheckSetup {
        down,
        unit_weight,
        spacing: system.spacing,
        height: scale.height,
        rough_walls: if no_shear {
            &[]
        } else {
            &system.walls.position
        },
        wall_friction: system.wall_config.slip.friction_coefficient(),
    };
    let stress = check_stress(soil, &oedometer, &setup);
    let fields = soil
        .soil
        .as_ref()
        .expect("soil particles carry soil fields");
    let plastic = fields.plastic_strain.iter().filter(|&&e| e > 0.0).count();
    let report = GeostaticReport {
        steps,
        time,
        converged: at_rest,
        kinetic_energy_ratio,
        residual_rms,
        residual_max,
        stress,
        plastic_fraction: plastic as Real / soil.len().max(1) as Real,
        released_walls: solver.system.release_walls(config)?,
    };
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

/// Sets the stress of every soil particle to the 1D state of a level layer
/// ([`InitialStress::Oedometric`]): σ = σ_v n ⊗ n + K(σ_v) σ_v (I − n ⊗ n) with n = `down`,
/// σ_v = −γ d (γ = `unit_weight`) with d the depth below the top of the particle's column
/// ([`Columns`], width `spacing`), K the `oedometer` ratio of the scene's model (in plane
/// strain the out-of-plane σ_zz is K σ_v as well: the oedometer holds both lateral strains).
fn set_oedometric_stress<const D: usize>(
    soil: &mut Particles<D>,
    down: Vector<D>,
    unit_weight: Real,
    spacing: Real,
    oedometer: &OedometricRatio,
) {
    let columns = Columns::of(&soil.position, down, spacing);
    let n = nalgebra::Vector3::from_fn(|k, _| if k < D { down[k] } else { 0.0 });
    let vertical = n * n.transpose();
    let horizontal = geosph_core::Tensor3::identity() - vertical;
    let fields = soil
        .soil
        .as_mut()
        .expect("soil particles carry soil fields");
    for (x, stress) in soil.position.iter().zip(&mut fields.stress) {
        let sigma_v = -unit_weight * columns.depth(x);
        *stress = vertical * sigma_v + horizontal * (oedometer.at(-sigma_v) * sigma_v);
    }
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
        let (free, wall) = (&self.stress.free_field, &self.stress.wall_zone);
        let janssen = self.stress.janssen.as_ref();
        let figures = [
            ("time", self.time),
            ("converged", Real::from(u8::from(self.converged))),
            ("kinetic_energy_ratio", self.kinetic_energy_ratio),
            ("residual_rms", self.residual_rms),
            ("residual_max", self.residual_max),
            ("checked_particles", free.particles as Real),
            ("vertical_stress_error_max", free.vertical_stress_error_max),
            (
                "vertical_stress_error_mean",
                free.vertical_stress_error_mean,
            ),
            ("lateral_ratio_min", free.lateral_ratio.0),
            ("lateral_ratio_mean", free.lateral_ratio.1),
            ("lateral_ratio_max", free.lateral_ratio.2),
            ("lateral_ratio_error_max", free.lateral_ratio_error_max),
            ("wall_zone_particles", wall.particles as Real),
            (
                "wall_zone_stress_ratio_mean",
                wall.vertical_stress_ratio_mean,
            ),
            (
                "wall_zone_vertical_stress_error_max",
                wall.vertical_stress_error_max,
            ),
            (
                "wall_zone_lateral_ratio_error_max",
                wall.lateral_ratio_error_max,
            ),
            ("janssen_layers", janssen.map_or(0.0, |j| j.layers as Real)),
            (
                "janssen_error_max",
                janssen.map_or(Real::NAN, |j| j.error_max),
            ),
            (
                "janssen_outside_bounds",
                janssen.map_or(0.0, |j| j.outside_bounds as Real),
            ),
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
