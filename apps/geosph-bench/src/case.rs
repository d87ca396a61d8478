//! The cases of the harness: their scenes and their errors against a reference.

use std::time::Instant;

use geosph_core::Real;
use geosph_fluid::config::{DiffusionConfig, ViscosityConfig};
use geosph_fluid::incompressible::{PressureIteration, PressureSource};
use geosph_kernels::KernelKind;
use geosph_runner::{NoObserver, Observer, RunOptions, Summary};
use geosph_scene::format::CellIndexSpec;
use geosph_scene::{Scene, SolverSpec, WallSpec};
use geosph_sph::{ParticleShifting, SpsConfig};

use crate::Config;
use crate::laminar::{self, Flow, ProfileError};
use crate::measures::{DEPTH, LayerPressure, TaylorGreenError};

/// A case with a reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Case {
    /// 2D Taylor–Green vortex in a periodic unit box, U = 1 m/s, ν = 0.01 m²/s (Re = 100).
    TaylorGreen,
    /// Start-up of plane Poiseuille flow (Morris, Fox & Zhu 1997), [`laminar`].
    Poiseuille,
    /// Start-up of plane Couette flow (Morris, Fox & Zhu 1997), [`laminar`].
    Couette,
    /// Still water 0.5 m deep in a 1 m wide tank.
    Hydrostatic,
    /// Martin & Moyce's 2D dam break, column 1 m × 2 m.
    DamBreak,
    /// The dam break against a wall of Lobovsky et al. (2014), H = 0.3 m, three gauges
    /// (`data/scenes/lobovsky-wall-pressure.ron`).
    WallPressure,
    /// Bui et al.'s (2008) granular column collapse, 0.2 m × 0.1 m.
    Collapse,
    /// A level elastic soil layer 0.1 m deep, periodic over 0.2 m, under gravity (geostatic
    /// stage only).
    K0Column,
    /// The square drop under surface tension (`data/scenes/square-drop.ron`), WCSPH only.
    SquareDrop,
    /// Sod's (1978) shock tube of an ideal gas (`data/scenes/sod-shock-tube.ron`), WCSPH only.
    ShockTube,
}

impl Case {
    /// Every case, in report order.
    pub const ALL: [Case; 10] = [
        Case::TaylorGreen,
        Case::Poiseuille,
        Case::Couette,
        Case::Hydrostatic,
        Case::DamBreak,
        Case::WallPressure,
        Case::Collapse,
        Case::K0Column,
        Case::SquareDrop,
        Case::ShockTube,
    ];

    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Case::TaylorGreen => "taylor-green",
            Case::Poiseuille => Flow::Poiseuille.name(),
            Case::Couette => Flow::Couette.name(),
            Case::Hydrostatic => "hydrostatic",
            Case::DamBreak => "dam-break",
            Case::WallPressure => "wall-pressure",
            Case::Collapse => "collapse",
            Case::K0Column => "k0-column",
            Case::SquareDrop => "square-drop",
            Case::ShockTube => "shock-tube",
        }
    }

    /// The case of `name`.
    pub fn from_name(name: &str) -> Option<Case> {
        Case::ALL.into_iter().find(|case| case.name() == name)
    }

    /// Whether the case is soil (run by the soil solver only).
    pub fn is_soil(self) -> bool {
        matches!(self, Case::Collapse | Case::K0Column)
    }

    /// Whether the case runs its own scene's WCSPH solver only (a model no other solver has),
    /// [`crate::fluid_models`].
    pub fn is_wcsph_model(self) -> bool {
        matches!(self, Case::SquareDrop | Case::ShockTube)
    }

    /// Simulated end time in s (`quick`: the shorter time of the CI matrix).
    pub fn end_time(self, quick: bool) -> Real {
        match (self, quick) {
            // Two turnovers L/U; the kinetic energy has decayed to e^(−16π²νt/L²) = 4.3 %.
            (Case::TaylorGreen, false) => 2.0,
            (Case::TaylorGreen, true) => 1.0,
            // Steady state (laminar::TIMES); quick: the first three comparison times.
            (Case::Poiseuille | Case::Couette, false) => 0.9,
            (Case::Poiseuille | Case::Couette, true) => 0.1125,
            (Case::Hydrostatic, false) => 1.0,
            (Case::Hydrostatic, true) => 0.4,
            (Case::DamBreak, false) => 0.5,
            (Case::DamBreak, true) => 0.3,
            // t√(g/H) = 5.72, past the plateau's end 5.5.
            (Case::WallPressure, _) => 1.0,
            (Case::Collapse, false) => 1.0,
            (Case::Collapse, true) => 0.15,
            (Case::K0Column, _) => 0.01,
            // At rest but for parasitic currents (docs/surface-tension.md); quick: rounding.
            (Case::SquareDrop, false) => 2.0,
            (Case::SquareDrop, true) => 0.5,
            (Case::ShockTube, _) => geosph_tests::shock_tube::END_TIME,
        }
    }

    /// What the error is, for the report.
    pub fn error_definition(self) -> &'static str {
        match self {
            Case::TaylorGreen => {
                "relative L2 error of the velocity at the end time, ‖v − v_exact‖/‖v_exact‖ over \
                 the particles, with v_exact the Taylor–Green field (Taylor & Green 1937) decayed \
                 by e^(−8π²νt/L²) and evaluated at each particle's position"
            }
            Case::Poiseuille | Case::Couette => {
                "largest error of the layer-averaged velocity profile against the series solution \
                 (Morris, Fox & Zhu 1997) at t = 0.0225, 0.045, 0.1125, 0.225 and 0.9 s (those \
                 within the run), over the steady centreline or plate speed 2.5e-5 m/s"
            }
            Case::Hydrostatic => {
                "RMS over the particle layers (all but the top three) of (p̄ − ρ₀g(H − y))/(ρ₀gH), \
                 p̄ the layer's pressure averaged over the second half of the run"
            }
            Case::DamBreak => {
                "mean of the RMS differences from Martin & Moyce (1952) of the front Z = z/a \
                 against T = t√(2g/a) and of the column height H/(2a) against T = t√(g/a), over \
                 the measured points within the run"
            }
            Case::WallPressure => {
                "mean over the three gauges of |p̄ − p̄_exp|/(ρgH), p̄ the raw gauge's mean over \
                 the plateau t√(g/H) = 3–5.5 against Lobovsky et al.'s (2014); the value column \
                 is the mean scatter of the raw signals about their running mean (window 0.1 \
                 in t√(g/H)) on the plateau, in ρgH"
            }
            Case::Collapse => {
                "the free-surface error P_d = √(Σ(f − f_exp)²/Σ f_exp²) of the deposit at the \
                 end time against the final surface measured by Bui et al. (2008) at 27 points \
                 (Feng et al. 2021, eq. 46; `slope_failure::bui2008`); the value column is the \
                 runout (the deposit toe, 0.1 H thick; measured 0.365 m)"
            }
            Case::K0Column => {
                "the larger of the mean relative error of σ_v against ρg(H − y) and the relative \
                 error of the mean σ_h/σ_v against K₀ = ν/(1 − ν) = 0.4286, below the top two \
                 layers, after the geostatic stage"
            }
            Case::SquareDrop => {
                "|Δp/(σ/R) − 1| of the pressure jump Δp (the mean within R/2 of the centroid \
                 minus the mean beyond R + 2 supports) at the end against Laplace's σ/R, R the \
                 radius of the square's area; the value column is Δp in Pa; variant `off`: \
                 no surface tension"
            }
            Case::ShockTube => {
                "the L1 error of the density over x ∈ [0, 1] at t = 0.2 against the exact \
                 solution of Sod's Riemann problem, over the initial jump 0.875; the value \
                 column is the L1 error of the pressure"
            }
        }
    }

    /// The scene of `config`.
    pub fn scene(self, config: &Config, quick: bool) -> Result<Scene, String> {
        let end_time = self.end_time(quick);
        if self.is_wcsph_model() {
            return crate::fluid_models::scene(self, config, end_time);
        }
        let mut scene = match self {
            Case::TaylorGreen => Scene::from_ron(&format!(
                "Scene(name: \"taylor-green\", dimension: 2, dx: 0.1, smoothing_ratio: 2.0,
                   gravity: [0.0, 0.0],
                   end_time: 1.0,
                   domain: (min: [0.0, 0.0], max: [1.0, 1.0], periodic: [true, true]),
                   fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])], hydrostatic: false,
                           velocity: TaylorGreen(speed: {TG_SPEED}, wavelength: {TG_LENGTH})),
                   solver: Wcsph(()))"
            )),
            Case::Poiseuille => Scene::from_ron(&Flow::Poiseuille.scene()),
            Case::Couette => Scene::from_ron(&Flow::Couette.scene()),
            Case::Hydrostatic => Scene::from_ron(&format!(
                "Scene(name: \"hydrostatic\", dimension: 2, dx: 0.1, end_time: 1.0,
                   fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, {DEPTH}])]),
                   walls: [Tank(min: [0.0, 0.0], max: [1.0, 1.0])],
                   solver: Wcsph(()))"
            )),
            Case::DamBreak => {
                Scene::from_ron(include_str!("../../../data/scenes/dam-break-2d.ron"))
            }
            Case::WallPressure => Scene::from_ron(include_str!(
                "../../../data/scenes/lobovsky-wall-pressure.ron"
            )),
            Case::Collapse => {
                Scene::from_ron(include_str!("../../../data/scenes/granular-collapse.ron"))
            }
            Case::SquareDrop | Case::ShockTube => unreachable!("returned above"),
            Case::K0Column => Scene::from_ron(
                "Scene(name: \"k0-column\", dimension: 2, dx: 0.005, smoothing_ratio: 1.3,
                   end_time: 0.01,
                   domain: (min: [0.0, -0.1], max: [0.2, 0.3], periodic: [true, false]),
                   soil: (density: 2650.0, blocks: [Box(min: [0.0, 0.0], max: [0.2, 0.1])]),
                   walls: [Polyline(points: [(0.0, 0.0), (0.2, 0.0)], layers: 4)],
                   solver: Soil((
                       constitutive: LinearElastic(youngs_modulus: 0.84e6, poisson_ratio: 0.3),
                       geostatic: (),
                   )))",
            ),
        }
        .map_err(|error| error.to_string())?;
        scene.dx = config.dx;
        scene.kernel = config.kernel.to_owned();
        // Walls as thick as the kernel's support (the quintic spline needs 4 layers at 1.3 dx).
        let kernel: KernelKind = config
            .kernel
            .parse()
            .map_err(|_| format!("unknown kernel `{}`", config.kernel))?;
        let needed = (kernel.support_factor() * scene.smoothing_ratio - 1e-9).ceil() as usize;
        for wall in &mut scene.walls {
            let (WallSpec::Tank { layers, .. }
            | WallSpec::Polyline { layers, .. }
            | WallSpec::Mesh { layers, .. }) = wall;
            *layers = (*layers).max(needed);
        }
        scene.end_time = end_time;
        scene.output.interval = end_time;
        scene.output.vtk = false;
        scene.output.sample_interval = match self {
            Case::Hydrostatic => 0.01,
            Case::TaylorGreen => end_time / 10.0,
            Case::Poiseuille | Case::Couette => laminar::TIMES[0],
            _ => scene.output.sample_interval.min(end_time / 10.0),
        };
        scene.solver = solver(self, config, scene.solver)?;
        if config.variant == "hashed" {
            hash_cells(&mut scene)?;
        }
        Ok(scene)
    }

    /// Runs `config` and measures it; `Err` with a one-line reason when the run fails.
    pub fn run(self, config: &Config, quick: bool) -> Result<Measurement, String> {
        if self.is_wcsph_model() {
            return crate::fluid_models::run(self, config, quick);
        }
        let scene = self.scene(config, quick)?;
        let options = RunOptions::default();
        let started = Instant::now();
        let (summary, value, error) = match self {
            Case::TaylorGreen => {
                let mut observer = TaylorGreenError::default();
                let summary = run(&scene, &options, &mut observer)?;
                (summary, observer.kinetic_energy_ratio, observer.error)
            }
            Case::Poiseuille | Case::Couette => {
                let flow = if self == Case::Poiseuille {
                    Flow::Poiseuille
                } else {
                    Flow::Couette
                };
                let mut observer = ProfileError::new(flow, scene.dx);
                let summary = run(&scene, &options, &mut observer)?;
                if observer.compared == 0 {
                    return Err("no comparison time within the run".into());
                }
                (summary, observer.error, observer.error)
            }
            Case::Hydrostatic => {
                let mut observer = LayerPressure::new(scene.dx, 0.5 * scene.end_time);
                let summary = run(&scene, &options, &mut observer)?;
                let error = observer.error();
                (summary, error, error)
            }
            Case::DamBreak => {
                let report = dam_break::run(&scene, &options).map_err(|e| e.to_string())?;
                let validation = report.validation.ok_or("the column is not n² = 2")?;
                if validation.front_points == 0 || validation.height_points == 0 {
                    return Err("no measured point within the run".into());
                }
                let error = 0.5 * (validation.front_rms + validation.height_rms);
                (report.summary, validation.front_rms, error)
            }
            Case::WallPressure => {
                let report = dam_break::run(&scene, &options).map_err(|e| e.to_string())?;
                let comparison = report
                    .wall_pressure
                    .ok_or("not Lobovsky et al.'s set-up with gauges")?;
                let count = comparison.gauges.len() as Real;
                let mut plateau_error = 0.0;
                let mut scatter = 0.0;
                for gauge in &comparison.gauges {
                    let (Some(sim), Some(exp), Some(noise)) =
                        (gauge.plateau.0, gauge.plateau.1, gauge.scatter)
                    else {
                        return Err("the run does not cover the plateau".into());
                    };
                    plateau_error += (sim - exp).abs() / count;
                    scatter += noise / count;
                }
                (report.summary, scatter, plateau_error)
            }
            Case::Collapse => {
                let report = slope_failure::run(&scene, &options).map_err(|e| e.to_string())?;
                let error = report
                    .experiment
                    .as_ref()
                    .ok_or("the collapse scene is not the experiment's set-up")?
                    .surface_error;
                (report.summary, report.last.runout, error)
            }
            Case::K0Column => {
                let summary = run(&scene, &options, &mut NoObserver)?;
                let stage = summary
                    .stage
                    .as_ref()
                    .ok_or("the scene has no geostatic stage")?;
                let figure = |name| {
                    stage
                        .figure(name)
                        .ok_or(format!("the geostatic stage reports no {name}"))
                };
                let lateral_ratio = figure("lateral_ratio_mean")?;
                let k0 = 0.3 / 0.7;
                let error =
                    figure("vertical_stress_error_mean")?.max((lateral_ratio / k0 - 1.0).abs());
                (summary, lateral_ratio, error)
            }
            Case::SquareDrop | Case::ShockTube => unreachable!("returned above"),
        };
        let wall_time = started.elapsed().as_secs_f64();
        let steps = summary.steps + summary.stage.as_ref().map_or(0, |stage| stage.steps);
        Ok(Measurement {
            particles: summary.fluid_particles,
            steps,
            wall_time,
            value,
            error,
        })
    }
}

/// What [`Case::run`] measured; the harness adds the configuration and the rates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// Moving particles.
    pub particles: usize,
    /// Time steps, geostatic stage included.
    pub steps: usize,
    /// Wall-clock time, s.
    pub wall_time: Real,
    /// The case's measured quantity.
    pub value: Real,
    /// The error.
    pub error: Real,
}

/// The Taylor–Green vortex's speed U, m/s.
pub(crate) const TG_SPEED: Real = 1.0;
/// The Taylor–Green vortex's wavelength L, m.
pub(crate) const TG_LENGTH: Real = 1.0;
/// ν = U L / Re with Re = 100.
pub(crate) const TG_VISCOSITY: Real = TG_SPEED * TG_LENGTH / 100.0;

/// Indexes the neighbour search's cells of `scene` by a hash (variant `hashed`); `Err` if the
/// scene has no domain box (its automatic box is dense).
pub(crate) fn hash_cells(scene: &mut Scene) -> Result<(), String> {
    let domain = scene
        .domain
        .as_mut()
        .ok_or("the scene has no domain box to hash")?;
    domain.cells = CellIndexSpec::Hashed;
    Ok(())
}

/// Runs `scene` through the runner; the error as one line.
pub(crate) fn run<O>(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut O,
) -> Result<Summary, String>
where
    O: Observer<2> + Observer<3> + Send,
{
    geosph_runner::run(scene, options, observer).map_err(|error| error.to_string())
}

/// The solver of `config` for `case`: the defaults of the named fluid solver (or the soil
/// scene's `own` solver), the variant, the Courant number scaled by the time-step factor, and a
/// laminar viscosity for the Taylor–Green vortex.
fn solver(case: Case, config: &Config, own: SolverSpec) -> Result<SolverSpec, String> {
    let laminar = ViscosityConfig::Laminar {
        kinematic_viscosity: match case {
            Case::Poiseuille | Case::Couette => laminar::VISCOSITY,
            _ => TG_VISCOSITY,
        },
    };
    let channel = matches!(case, Case::Poiseuille | Case::Couette);
    let mut spec = if config.solver == "soil" {
        if !case.is_soil() {
            return Err(format!("{} is not a soil case", case.name()));
        }
        match own {
            SolverSpec::Soil(mut soil) => {
                soil.cfl *= config.dt_factor;
                SolverSpec::Soil(soil)
            }
            _ => return Err(format!("the {} scene has no soil solver", case.name())),
        }
    } else {
        if case.is_soil() {
            return Err(format!("{} is a soil case", case.name()));
        }
        SolverSpec::from_name(config.solver)
            .ok_or_else(|| format!("unknown solver `{}`", config.solver))?
    };
    match &mut spec {
        SolverSpec::Wcsph(wcsph) => {
            wcsph.cfl *= config.dt_factor;
            wcsph.diffusion = match config.variant {
                "fourtakas" | "default" | "sps" | "hashed" => {
                    DiffusionConfig::Fourtakas { delta: 0.1 }
                }
                "molteni" => DiffusionConfig::Molteni { delta: 0.1 },
                "antuono" => DiffusionConfig::Antuono { delta: 0.1 },
                "none" => DiffusionConfig::None,
                other => return Err(format!("unknown WCSPH variant `{other}`")),
            };
            // SPS turbulence with Dalrymple & Rogers' coefficients, beside the default terms.
            if config.variant == "sps" {
                wcsph.sps = Some(SpsConfig::default());
            }
            if case == Case::TaylorGreen {
                wcsph.viscosity = laminar;
                // Shifting keeps the particles ordered under the suction of the vortex cores
                // (−ρ₀U²/2), so no background pressure is needed; one dissipates: p_b = ρ₀U²
                // loses 4.5 % of the kinetic energy by t = 2 (docs/fluid.md).
                wcsph.shifting = Some(ParticleShifting::default());
            }
            if channel {
                wcsph.viscosity = laminar;
                // Ten times the largest speed, as the scene rule would for a free surface.
                wcsph.sound_speed = Some(10.0 * laminar::SPEED);
            }
        }
        SolverSpec::Pcisph(incompressible)
        | SolverSpec::Iisph(incompressible)
        | SolverSpec::Dfsph(incompressible) => {
            incompressible.cfl *= config.dt_factor;
            incompressible.iteration = match config.variant {
                "default" => PressureIteration::RelaxedJacobi,
                "bicgstab" => PressureIteration::Bicgstab(Default::default()),
                other => return Err(format!("unknown {} variant `{other}`", config.solver)),
            };
            if case == Case::TaylorGreen {
                incompressible.viscosity = laminar;
                incompressible.negative_pressure = true;
                incompressible.shifting = Some(ParticleShifting::default());
                // Exact divergences on the disordered particles and a tight projection of the
                // velocity divergence alone: a density solve would chase the summation
                // density's scatter on those particles, which is not compression
                // (docs/incompressible.md, "The Taylor–Green vortex"). DFSPH keeps its density
                // solve only as a 3 % bound on the compression; PCISPH and IISPH take the
                // velocity-divergence source instead of the density (Cornelis et al. 2019).
                incompressible.renormalise_gradients = true;
                // A quarter of the default Courant number (replacing the 0.4 × dt_factor
                // above): at the default the shifting's per-step bounds (D ≤ h²/2, 0.1 Δx) cut
                // its strength per unit time to between 2/3 and 1/5, the particles cluster at
                // the stagnation points and PCISPH and IISPH blow up at 50 × 50
                // (docs/incompressible.md).
                incompressible.cfl = 0.1 * config.dt_factor;
                if config.solver == "dfsph" {
                    incompressible.target_density_error = 0.03;
                    incompressible.min_iterations = 0;
                    incompressible.target_divergence_error = 1e-6;
                } else {
                    incompressible.source = PressureSource::VelocityDivergence;
                    incompressible.target_density_error = 1e-6;
                }
            }
            if channel {
                incompressible.viscosity = laminar;
            }
        }
        SolverSpec::Soil(_) => {}
    }
    Ok(spec)
}
