//! The run loop.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use geosph_core::{Particles, Real};
use geosph_fluid::{IncompressibleMethod, build_incompressible, build_wcsph};
use geosph_scene::{Scene, SolverSpec};
use geosph_sph::Solver;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::checkpoint::{
    self, Checkpoint, CheckpointError, CheckpointEvery, ParticleState, Progress,
};
pub use crate::error::RunError;
use crate::escape::{Escapes, Removal};
use crate::health::report::{BlowUpFiles, BlowUpReport};
use crate::health::{self, Diagnosis, LimitInputs, Limits};
use crate::observer::Observer;
use crate::output::RunOutput;
use crate::probes::PressureProbes;

/// How to run a scene, beyond what the scene says.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder; `None` writes nothing.
    pub out_dir: Option<PathBuf>,
    /// Override the scene's VTU output switch.
    pub vtk: Option<bool>,
    /// Worker threads (default: rayon's, one per core).
    pub threads: Option<usize>,
    /// Show a progress bar on standard error.
    pub progress: bool,
    /// Write `checkpoint.bin` into the output folder at this interval (none without one).
    pub checkpoint_every: Option<CheckpointEvery>,
    /// Continue the run from this checkpoint, into the output folder it was written for.
    pub restart: Option<PathBuf>,
    /// Checked once per step: when set (e.g. by a Ctrl-C handler), the run writes the
    /// current frame and a checkpoint and stops with [`RunError::Interrupted`].
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Solver name.
    pub solver: &'static str,
    /// What the particles are ([`Solver::material`]): "fluid" or "soil".
    pub material: &'static str,
    /// Whether the solver iterates a pressure solve ([`Solver::iterates`]).
    pub iterative: bool,
    /// 2 or 3.
    pub dimension: usize,
    /// Fluid particles.
    pub fluid_particles: usize,
    /// Wall particles.
    pub wall_particles: usize,
    /// Time steps taken.
    pub steps: usize,
    /// Simulated time reached, s.
    pub simulated_time: Real,
    /// Wall-clock time of the stepping loop (output included), s.
    pub wall_time: Real,
    /// Fluid particle-steps per wall-clock second.
    pub particle_steps_per_second: Real,
    /// Largest relative density error seen at any step.
    pub max_density_error: Real,
    /// Mean relative density error over all steps.
    pub mean_density_error: Real,
    /// Mean pressure iterations per step (1 for WCSPH).
    pub mean_iterations: Real,
    /// Mean divergence-solve iterations per step (DFSPH; 0 otherwise).
    pub mean_divergence_iterations: Real,
    /// Bytes per fluid particle held by its fields.
    pub bytes_per_particle: usize,
    /// VTU frames written.
    pub frames: usize,
    /// Particles that left the domain and were removed from the run (included in neither
    /// `fluid_particles` nor the frames).
    pub escaped: usize,
    /// Their share of the initial fluid mass.
    pub escaped_mass_fraction: Real,
    /// Simulated time at which the first of them was removed, s.
    pub first_escape: Option<Real>,
    /// The stage the solver ran before t = 0 ([`Solver::initial_stage`]; the soil's
    /// geostatic stage), also after a restart from a checkpoint written after it.
    pub stage: Option<geosph_sph::StageReport>,
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "scene              {} ({}D, {})",
            self.scene, self.dimension, self.solver
        )?;
        let material = self.material;
        writeln!(
            f,
            "particles          {} {material} + {} wall ({} bytes of fields per {material} particle)",
            self.fluid_particles, self.wall_particles, self.bytes_per_particle
        )?;
        writeln!(
            f,
            "steps              {} to t = {:.4} s (mean dt = {:.3e} s)",
            self.steps,
            self.simulated_time,
            self.simulated_time / self.steps.max(1) as Real
        )?;
        writeln!(
            f,
            "wall time          {:.2} s, {:.3} M particle-steps/s",
            self.wall_time,
            self.particle_steps_per_second * 1e-6
        )?;
        writeln!(
            f,
            "density error      mean {:.3} %, max {:.3} %",
            100.0 * self.mean_density_error,
            100.0 * self.max_density_error
        )?;
        // The explicit solvers take one pass per step; only the pressure solvers iterate.
        if self.iterative {
            writeln!(
                f,
                "iterations         {:.1} per step (divergence solve {:.1})",
                self.mean_iterations, self.mean_divergence_iterations
            )?;
        }
        if let Some(first) = self.first_escape {
            writeln!(
                f,
                "escaped            {} particles ({:.3} % of the mass), first at t = {first:.3} s",
                self.escaped,
                100.0 * self.escaped_mass_fraction
            )?;
        }
        if let Some(stage) = &self.stage {
            write!(f, "\n{stage}")?;
        }
        Ok(())
    }
}

/// Runs `scene` to its end time, calling `observer` at every sample time.
pub fn run<O>(scene: &Scene, options: &RunOptions, observer: &mut O) -> Result<Summary, RunError>
where
    O: Observer<2> + Observer<3> + Send,
{
    scene.validate()?;
    if let Some(dir) = &options.out_dir {
        crate::output::check_folder(dir).map_err(|reason| RunError::OutputFolder {
            path: dir.clone(),
            reason,
        })?;
    }
    let mut work = || match scene.dimension {
        2 => run_plane(scene, options, observer),
        _ => run_space(scene, options, observer),
    };
    match options.threads {
        Some(threads) => rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|error| RunError::Threads(error.to_string()))?
            .install(work),
        None => work(),
    }
}

fn kinetic_energy<const D: usize>(fluid: &Particles<D>) -> Real {
    fluid
        .velocity
        .iter()
        .zip(&fluid.mass)
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum()
}

fn progress_bar(options: &RunOptions, end_time: Real) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some((end_time * 1e4).ceil() as u64),
        if options.progress {
            ProgressDrawTarget::stderr_with_hz(4)
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template("{bar:30} t = {msg} [{elapsed_precise}, ETA {eta}]")
            .expect("a valid template"),
    );
    bar
}

/// A 2D run. Not generic, so that every solver is compiled once, in this crate, rather than
/// again in each crate that calls [`run`] (Rust monomorphises generics where they are used).
fn run_plane(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Observer<2>,
) -> Result<Summary, RunError> {
    run_in::<2>(scene, options, observer)
}

/// A 3D run, see [`run_plane`].
fn run_space(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Observer<3>,
) -> Result<Summary, RunError> {
    run_in::<3>(scene, options, observer)
}

fn run_in<const D: usize>(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Observer<D>,
) -> Result<Summary, RunError> {
    let (mut fluid, solver_inputs) = geosph_scene::build::<D>(scene)?.split();
    let mut probes = PressureProbes::<D>::new(
        &scene.output.probes,
        solver_inputs.kernel,
        solver_inputs.smoothing_length,
    );
    let wall_particles = solver_inputs.walls.len();
    let limit_inputs = LimitInputs::of(&solver_inputs);
    let built = match &scene.solver {
        SolverSpec::Wcsph(config) => build_wcsph(config, solver_inputs, &mut fluid),
        SolverSpec::Pcisph(config) => build_incompressible(
            IncompressibleMethod::Pcisph,
            config,
            solver_inputs,
            &mut fluid,
        ),
        SolverSpec::Iisph(config) => build_incompressible(
            IncompressibleMethod::Iisph,
            config,
            solver_inputs,
            &mut fluid,
        ),
        SolverSpec::Dfsph(config) => build_incompressible(
            IncompressibleMethod::Dfsph,
            config,
            solver_inputs,
            &mut fluid,
        ),
        SolverSpec::Soil(config) => Ok(geosph_soil::build_soil(config, solver_inputs, &mut fluid)?),
    };
    let mut solver: Box<dyn Solver<D>> = built.map_err(|source| RunError::Solver {
        time: 0.0,
        step: 0,
        source: source.into(),
    })?;

    let vtk = options.vtk.unwrap_or(scene.output.vtk);
    let restart = match &options.restart {
        Some(path) => {
            let saved = Checkpoint::read::<D>(path, scene)?;
            fluid = saved
                .particles
                .restore(&fluid, saved.progress.escaped)
                .map_err(|error| restart_mismatch(path, error.0))?;
            solver
                .restore_state(saved.solver, &mut fluid)
                .map_err(|error| restart_mismatch(path, error.to_string()))?;
            observer
                .restore_state(&saved.observer)
                .map_err(|reason| restart_mismatch(path, reason))?;
            Some(saved.progress)
        }
        None => None,
    };
    // The solver's stage before t = 0 (the soil's geostatic stage), on a new run only: a
    // checkpoint holds the state after it.
    let stage = match &restart {
        Some(progress) => progress.stage.clone(),
        None => solver
            .initial_stage(&mut fluid)
            .map_err(|source| RunError::Solver {
                time: 0.0,
                step: 0,
                source,
            })?,
    };
    let mut columns = observer.columns();
    columns.extend(probes.columns().iter().map(String::as_str));
    let mut output = match (&options.out_dir, &restart) {
        (Some(dir), None) => Some(RunOutput::create(dir, &scene.name, vtk, &columns)?),
        (Some(dir), Some(progress)) => Some(
            RunOutput::resume(
                dir,
                &scene.name,
                vtk,
                &columns,
                (
                    progress.time,
                    progress.frames as usize,
                    progress.rows as usize,
                ),
            )
            .map_err(RunError::Resume)?,
        ),
        (None, _) => None,
    };
    let mut row = Vec::new();
    let mut sample = |time: Real,
                      step: usize,
                      report: &geosph_sph::StepReport,
                      escaped: u64,
                      fluid: &Particles<D>,
                      output: &mut Option<RunOutput>,
                      observer: &mut dyn Observer<D>|
     -> Result<(), RunError> {
        row.clear();
        row.extend_from_slice(&[
            time,
            step as Real,
            report.dt,
            kinetic_energy(fluid),
            report.density_error_mean,
            report.density_error_max,
            geosph_sph::max_speed(&fluid.velocity),
            report.iterations as Real,
            report.divergence_iterations as Real,
            escaped as Real,
        ]);
        observer.sample(time, fluid, &mut row);
        probes.sample(fluid, &mut row);
        if let Some(output) = output {
            output.sample(&row)?;
        }
        Ok(())
    };

    let end_time = scene.end_time;
    let bar = progress_bar(options, end_time);
    let started = Instant::now();
    let mut state = restart.unwrap_or_default();
    let first_step = state.steps as usize;
    if first_step == 0 {
        let mut report = geosph_sph::StepReport::default();
        for &rho in &fluid.density {
            let error = solver.density_error(rho);
            report.density_error_mean += error / fluid.len().max(1) as Real;
            report.density_error_max = report.density_error_max.max(error);
        }
        sample(0.0, 0, &report, 0, &fluid, &mut output, observer)?;
        if let Some(output) = &mut output {
            output.write_frame(0.0, &fluid, solver.walls())?;
        }
        state = Progress {
            outputs: 1,
            samples: 1,
            rows: 1,
            frames: output.as_ref().map_or(0, |o| o.frames() as u64),
            stage: stage.clone(),
            ..Progress::default()
        };
    }
    // The state before the step being taken, refreshed in place every step: allocated once.
    let mut last_good = fluid.clone();
    let mut limits = Limits::new(limit_inputs, &fluid, solver.as_ref());
    let mut escapes = Escapes::new(scene.health.max_escaped_fraction);
    let blow_up = |diagnosis: Diagnosis,
                   step: usize,
                   (time, last_good_time): (Real, Real),
                   (fluid, last_good): (&Particles<D>, &Particles<D>),
                   solver: &dyn Solver<D>,
                   limits: &Limits<D>,
                   output: &mut Option<RunOutput>| {
        bar.finish_and_clear();
        let files = match output {
            Some(output) => {
                // A failed flush has already cut the CSV back to its last complete row; the
                // blow-up is what to report.
                let _ = output.flush();
                BlowUpReport {
                    scene: &scene.name,
                    solver,
                    diagnosis: &diagnosis,
                    step,
                    time,
                    failed: fluid,
                    last_good: (last_good, last_good_time),
                    walls: solver.walls(),
                    limits,
                    frames: (health::report::LAST_GOOD_FILE, health::report::FAILED_FILE),
                }
                .save(output)
            }
            None => BlowUpFiles::NoOutput,
        };
        RunError::BlowUp {
            time,
            step,
            diagnosis,
            files: Box::new(files),
        }
    };
    let (output_interval, sample_interval) = (scene.output.interval, scene.output.sample_interval);
    // Event times as multiples of the intervals, so they do not accumulate round-off.
    let mut next_output = state.outputs as Real * output_interval;
    let mut next_sample = state.samples as Real * sample_interval;
    let mut checkpoints = CheckpointClock::new(options.checkpoint_every, state.time);
    let checkpoint_path = options
        .out_dir
        .as_ref()
        .map(|dir| dir.join(checkpoint::FILE_NAME));
    let save = |state: &Progress,
                fluid: &Particles<D>,
                solver: &dyn Solver<D>,
                observer: &dyn Observer<D>| {
        Checkpoint {
            scene: scene.name.clone(),
            scene_hash: checkpoint::scene_hash(scene),
            dimension: D as u32,
            progress: state.clone(),
            particles: ParticleState::save(fluid),
            solver: solver.save_state(),
            observer: observer.save_state(),
        }
    };
    let mut last_draw = Instant::now();
    // Times within this tolerance of an event count as reaching it.
    let tolerance = 1e-9 * end_time;
    while state.time < end_time - tolerance {
        let time = state.time;
        let next_event = next_output.min(next_sample).min(end_time);
        last_good.clone_from(&fluid);
        // A step that moved particles out of the domain is taken again without them.
        let report = loop {
            let source = match solver.step(&mut fluid, time, next_event - time) {
                Ok(report) => break report,
                Err(source) => source,
            };
            let (solver, step) = (solver.as_mut(), state.steps as usize + 1);
            let removal = escapes
                .during_step(
                    &source,
                    &mut fluid,
                    &last_good,
                    solver,
                    &mut limits,
                    &mut state,
                    time,
                )
                .map_err(|source| RunError::Solver { time, step, source })?;
            let diagnosis = match removal {
                Removal::Removed => {
                    last_good.clone_from(&fluid);
                    continue;
                }
                Removal::TooMany(diagnosis) => diagnosis,
                Removal::Nothing => match health::escaped(&source, &fluid, &limits) {
                    Some(diagnosis) => diagnosis,
                    None => {
                        let step = state.steps as usize;
                        return Err(RunError::Solver { time, step, source });
                    }
                },
            };
            let states = (&fluid, &last_good);
            let output = &mut output;
            let (times, limits) = ((time, time), &limits);
            return Err(blow_up(
                diagnosis, step, times, states, solver, limits, output,
            ));
        };
        let last_good_time = time;
        let time = time + report.dt;
        state.time = time;
        state.steps += 1;
        let steps = state.steps as usize;
        let escape = escapes
            .after_step(&mut fluid, solver.as_mut(), &mut limits, &mut state, time)
            .map_err(|source| RunError::Solver {
                time,
                step: steps,
                source,
            })?;
        let diagnosis = match escape {
            Removal::TooMany(diagnosis) => Some(diagnosis),
            _ => health::check(&report, &fluid, solver.as_ref(), &limits),
        };
        if let Some(diagnosis) = diagnosis {
            let (times, states) = ((time, last_good_time), (&fluid, &last_good));
            let (solver, output) = (solver.as_ref(), &mut output);
            return Err(blow_up(
                diagnosis, steps, times, states, solver, &limits, output,
            ));
        }
        state.max_density_error = state.max_density_error.max(report.density_error_max);
        state.density_error_sum += report.density_error_mean;
        state.iterations += report.iterations as u64;
        state.divergence_iterations += report.divergence_iterations as u64;
        if time >= next_sample - tolerance {
            let escaped = state.escaped;
            sample(time, steps, &report, escaped, &fluid, &mut output, observer)?;
            state.samples += 1;
            state.rows += 1;
            next_sample = state.samples as Real * sample_interval;
        }
        if time >= next_output - tolerance {
            if let Some(output) = &mut output {
                output.write_frame(time, &fluid, solver.walls())?;
                state.frames = output.frames() as u64;
            }
            state.outputs += 1;
            next_output = state.outputs as Real * output_interval;
        }
        let interrupted = options
            .interrupt
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed));
        let finished = time >= end_time - tolerance;
        if let (Some(path), Some(output)) = (&checkpoint_path, &mut output)
            && (interrupted || (!finished && checkpoints.due(time)))
        {
            output.flush()?;
            save(&state, &fluid, solver.as_ref(), observer).write(path)?;
        }
        if interrupted {
            bar.finish_and_clear();
            let frame = match &output {
                Some(output) => {
                    Some(output.write_snapshot("interrupted.vtu", &fluid, solver.walls())?)
                }
                None => None,
            };
            return Err(RunError::Interrupted {
                time,
                step: steps,
                checkpoint: checkpoint_path.filter(|_| frame.is_some()),
                frame,
            });
        }
        if last_draw.elapsed() > Duration::from_millis(250) {
            last_draw = Instant::now();
            bar.set_position((time * 1e4) as u64);
            let rate = (steps - first_step) as Real / started.elapsed().as_secs_f64();
            bar.set_message(format!("{time:.3} s, {rate:.0} steps/s"));
        }
    }
    bar.finish_and_clear();
    let wall_time = started.elapsed().as_secs_f64();
    let steps = state.steps as usize;
    let frames = match &mut output {
        Some(output) => {
            output.flush()?;
            output.frames()
        }
        None => 0,
    };
    Ok(Summary {
        scene: scene.name.clone(),
        solver: solver.name(),
        material: solver.material(),
        iterative: solver.iterates(),
        dimension: D,
        fluid_particles: fluid.len(),
        wall_particles,
        steps,
        simulated_time: state.time,
        wall_time,
        particle_steps_per_second: (fluid.len() * (steps - first_step)) as Real / wall_time,
        max_density_error: state.max_density_error,
        mean_density_error: state.density_error_sum / steps.max(1) as Real,
        mean_iterations: state.iterations as Real / steps.max(1) as Real,
        mean_divergence_iterations: state.divergence_iterations as Real / steps.max(1) as Real,
        bytes_per_particle: fluid.bytes_per_particle(),
        frames,
        escaped: state.escaped as usize,
        escaped_mass_fraction: state.escaped_mass
            / (fluid.mass.iter().sum::<Real>() + state.escaped_mass),
        first_escape: state.first_escape,
        stage,
    })
}

/// A restart file that passed its own checks but does not fit the scene's particles or solver.
fn restart_mismatch(path: &std::path::Path, reason: String) -> RunError {
    RunError::Checkpoint(CheckpointError::Mismatch {
        path: path.to_path_buf(),
        reason,
    })
}

/// When the next checkpoint is due. Checkpoints do not shorten steps (the run is the same
/// with or without them): one is written after the first step that reaches its time.
enum CheckpointClock {
    Never,
    Simulated { interval: Real, next: Real },
    Wall { interval: Duration, last: Instant },
}

impl CheckpointClock {
    fn new(every: Option<CheckpointEvery>, time: Real) -> Self {
        match every {
            None => Self::Never,
            Some(CheckpointEvery::Simulated(interval)) => Self::Simulated {
                interval,
                next: ((time / interval).floor() + 1.0) * interval,
            },
            Some(CheckpointEvery::Wall(interval)) => Self::Wall {
                interval,
                last: Instant::now(),
            },
        }
    }

    /// Whether a checkpoint is due at `time`; if so, the clock moves on to the next one.
    fn due(&mut self, time: Real) -> bool {
        match self {
            Self::Never => false,
            Self::Simulated { interval, next } => {
                let due = time >= *next;
                if due {
                    *next = ((time / *interval).floor() + 1.0) * *interval;
                }
                due
            }
            Self::Wall { interval, last } => {
                let due = last.elapsed() >= *interval;
                if due {
                    *last = Instant::now();
                }
                due
            }
        }
    }
}
