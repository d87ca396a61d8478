//! The run of one scene in D dimensions: [`RunLoop`], from the built solver (or a restart) to
//! the [`Summary`].

use std::path::PathBuf;
use std::time::{Duration, Instant};

use geosph_core::{Particles, Real, Vector};
use geosph_scene::Scene;
use geosph_sph::{Solver, StepReport};
use indicatif::ProgressBar;

use crate::checkpoint::{self, CheckpointClock, Progress};
use crate::error::RunError;
use crate::escape::{Escapes, Removal};
use crate::health::report::{BlowUpFiles, BlowUpReport};
use crate::health::{self, Diagnosis, LimitInputs, Limits};
use crate::heights::HeightGauges;
use crate::loads::WallLoads;
use crate::observer::Observer;
use crate::options::RunOptions;
use crate::output::RunOutput;
use crate::probes::PressureProbes;
use crate::share::Share;
use crate::summary::Summary;

mod checkpoints;
mod frames;
mod ranks;
mod start;
use ranks::RankView;
pub use start::build_solver;
use start::{open_output, progress_bar, restore};

/// One run in progress: the particles, the solver, the output and where the time loop stands.
///
/// [`RunLoop::start`] builds the solver from the scene and either restores a checkpoint or
/// runs the solver's stage before t = 0 and writes the t = 0 sample and frame;
/// [`RunLoop::run`] then takes [`RunLoop::step`] until the end time and returns
/// [`RunLoop::finish`]. A step samples, writes frames and checkpoints at their times and ends
/// the run on a blow-up ([`RunLoop::blow_up`]) or an interrupt.
pub(crate) struct RunLoop<'a, const D: usize> {
    scene: &'a Scene,
    options: &'a RunOptions,
    observer: &'a mut dyn Observer<D>,
    solver: Box<dyn Solver<D>>,
    fluid: Particles<D>,
    /// The state before the step being taken, refreshed in place every step: allocated once.
    last_good: Particles<D>,
    probes: PressureProbes<D>,
    heights: HeightGauges<D>,
    loads: WallLoads<D>,
    output: Option<RunOutput>,
    state: Progress,
    limits: Limits<D>,
    escapes: Escapes,
    /// The `diagnostics.csv` row being sampled, reused.
    row: Vec<Real>,
    bar: ProgressBar,
    next_output: Real,
    next_sample: Real,
    checkpoints: CheckpointClock,
    checkpoint_path: Option<PathBuf>,
    wall_particles: usize,
    /// How the scene's blocks were filled, for the summary.
    blocks: Vec<geosph_scene::BlockReport>,
    first_step: usize,
    started: Instant,
    last_draw: Instant,
    /// Times within this tolerance of an event count as reaching it.
    tolerance: Real,
    /// This rank's view of a distributed run (`None` for one process).
    ranks: Option<RankView<D>>,
}

impl<'a, const D: usize> RunLoop<'a, D> {
    /// Builds the scene's particles and solver; restores `options.restart` if given, else runs
    /// the solver's stage before t = 0; opens the output and writes the t = 0 sample and frame
    /// of a new run.
    pub(crate) fn start(
        scene: &'a Scene,
        options: &'a RunOptions,
        observer: &'a mut dyn Observer<D>,
    ) -> Result<Self, RunError> {
        let mut setup = geosph_scene::build::<D>(scene)?;
        let background_pressure = scene.solver.particle_start().background_pressure;
        let blocks = setup.blocks.clone();
        let loads = WallLoads::new(
            std::mem::take(&mut setup.loads),
            setup.kernel,
            setup.smoothing_length,
            (setup.gravity, background_pressure),
            &setup.domain,
        );
        let bodies = std::mem::take(&mut setup.bodies);
        let fixed = std::mem::take(&mut setup.fixed);
        let coupling = geosph_bodies::Coupling {
            kernel: setup.kernel,
            smoothing_length: setup.smoothing_length,
            gravity: setup.gravity,
            domain: setup.domain.clone(),
            spacing: setup.spacing,
            background_pressure,
        };
        let (mut fluid, solver_inputs) = setup.split();
        let probes = PressureProbes::<D>::new(
            &scene.output.probes,
            solver_inputs.kernel,
            solver_inputs.smoothing_length,
        );
        let heights = HeightGauges::<D>::new(&scene.output.heights, scene.dx);
        let wall_particles = solver_inputs.walls.len();
        let mut limit_inputs = LimitInputs::of(&solver_inputs);
        limit_inputs.add_bodies(bodies.iter().map(|body| {
            geosph_bodies::mass_properties(&body.interior, body.cell_volume, body.density).mass
        }));
        let mut solver = build_solver(scene, solver_inputs, &mut fluid)?;
        if !bodies.is_empty() {
            let bodies = geosph_bodies::RigidBodies::new(bodies, &fixed, solver.walls(), coupling)
                .map_err(|error| {
                    RunError::Scene(geosph_scene::SceneError::Field {
                        field: "bodies".into(),
                        message: error.to_string(),
                    })
                })?;
            solver
                .set_wall_motion(Box::new(bodies))
                .map_err(|source| RunError::Solver {
                    time: 0.0,
                    step: 0,
                    source,
                })?;
        }
        let motion_columns = solver
            .wall_motion()
            .map(|motion| motion.columns())
            .unwrap_or_default();
        let restart = match &options.restart {
            Some(path) => Some(restore(path, scene, &mut fluid, solver.as_mut(), observer)?),
            None => None,
        };
        // The solver's stage before t = 0 (the soil's geostatic stage), on a new run only: a
        // checkpoint holds the state after it.
        let stage = match &restart {
            Some(_) => None,
            None => solver
                .initial_stage(&mut fluid)
                .map_err(|source| RunError::Solver {
                    time: 0.0,
                    step: 0,
                    source,
                })?,
        };
        let ranks = ranks::distribute(options, solver.as_mut(), &mut fluid)
            .map_err(RunError::NotDistributed)?;
        // Rank 0 of a distributed run writes the output and shows the progress.
        let root = ranks.as_ref().is_none_or(RankView::is_root);
        let columns = [
            probes.columns(),
            heights.columns(),
            loads.columns(),
            &motion_columns,
        ];
        let output = match root {
            true => open_output(scene, options, &*observer, columns, restart.as_ref())?,
            false => None,
        };
        let bar = progress_bar(options.progress && root, scene.end_time);
        let started = Instant::now();
        let state = restart.unwrap_or_default();
        let first_step = state.steps as usize;
        let limits = Limits::new(limit_inputs, &fluid, solver.as_ref());
        let mut run = Self {
            scene,
            options,
            observer,
            solver,
            last_good: fluid.clone(),
            fluid,
            probes,
            heights,
            loads,
            output,
            checkpoints: CheckpointClock::new(options.checkpoint_every, state.time),
            state,
            limits,
            escapes: Escapes::new(scene.health.max_escaped_fraction),
            row: Vec::new(),
            bar,
            next_output: 0.0,
            next_sample: 0.0,
            checkpoint_path: options
                .out_dir
                .as_ref()
                .map(|dir| dir.join(checkpoint::FILE_NAME)),
            wall_particles,
            blocks,
            first_step,
            started,
            last_draw: Instant::now(),
            tolerance: 1e-9 * scene.end_time,
            ranks,
        };
        if first_step == 0 {
            run.write_start(stage)?;
        }
        // Event times as multiples of the intervals, so they do not accumulate round-off.
        let output = &run.scene.output;
        run.next_output = run.state.outputs as Real * output.interval;
        run.next_sample = run.state.samples as Real * output.sample_interval;
        Ok(run)
    }

    /// Steps to the end time and reports.
    pub(crate) fn run(mut self) -> Result<Summary, RunError> {
        while self.state.time < self.scene.end_time - self.tolerance {
            self.step()?;
        }
        self.finish()
    }

    /// The t = 0 sample and frame of a new run, with the report of the solver's stage.
    fn write_start(&mut self, stage: Option<geosph_sph::StageReport>) -> Result<(), RunError> {
        let mut report = StepReport::default();
        for &rho in &self.fluid.density {
            let error = self.solver.density_error(rho);
            report.density_error_mean += error / self.fluid.len().max(1) as Real;
            report.density_error_max = report.density_error_max.max(error);
        }
        self.sample(0.0, 0, &report)?;
        self.write_frame(0.0)?;
        self.state = Progress {
            outputs: 1,
            samples: 1,
            rows: 1,
            frames: self.state.frames,
            stage,
            ..Progress::default()
        };
        Ok(())
    }

    /// One step up to at most the next event: the step, particles that left the domain, the
    /// health check, then the sample, frame, checkpoint and interrupt due at its end.
    pub(crate) fn step(&mut self) -> Result<(), RunError> {
        let time = self.state.time;
        let next_event = self
            .next_output
            .min(self.next_sample)
            .min(self.scene.end_time);
        self.last_good.clone_from(&self.fluid);
        let last_good_owned = self.owned_after_split();
        let report = self.advance(time, next_event - time)?;
        let last_good_time = time;
        let time = time + report.dt;
        self.state.time = time;
        self.state.steps += 1;
        let steps = self.state.steps as usize;
        let escape = match self.ranks {
            Some(_) => self.escapes_on_ranks(time, last_good_owned),
            None => self.escapes.after_step(
                &mut self.fluid,
                self.solver.as_mut(),
                &mut self.limits,
                &mut self.state,
                time,
            ),
        }
        .map_err(|source| RunError::Solver {
            time,
            step: steps,
            source,
        })?;
        let sample_due = time >= self.next_sample - self.tolerance;
        let output_due = time >= self.next_output - self.tolerance;
        let diagnosis = match escape {
            Removal::TooMany(diagnosis) => Some(diagnosis),
            _ => self.health(&report, last_good_owned),
        };
        if let Some(diagnosis) = diagnosis {
            return Err(self.blow_up(diagnosis, steps, (time, last_good_time)));
        }
        let state = &mut self.state;
        state.max_density_error = state.max_density_error.max(report.density_error_max);
        state.density_error_sum += report.density_error_mean;
        state.iterations += report.iterations as u64;
        state.divergence_iterations += report.divergence_iterations as u64;
        if report.wall_contacts > 0 {
            state.wall_contacts += report.wall_contacts as u64;
            state.first_wall_contact.get_or_insert(time);
        }
        if sample_due {
            self.sample(time, steps, &report)?;
            self.state.samples += 1;
            self.state.rows += 1;
            self.next_sample = self.state.samples as Real * self.scene.output.sample_interval;
        }
        if output_due {
            self.write_frame(time)?;
            self.state.outputs += 1;
            self.next_output = self.state.outputs as Real * self.scene.output.interval;
        }
        self.checkpoint_or_interrupt(time, steps)?;
        self.draw_progress(time, steps);
        Ok(())
    }

    /// The solver's step from `time` of at most `max_dt`. A particle that leaves the domain in
    /// it keeps its pairs (the lists bin it in their edge cells) and is removed after it; a
    /// step whose search met a position that is not finite ends the run with the blow-up
    /// report, one that failed otherwise with its error. On several ranks a failed step ends
    /// the run with the error that names it on the rank that found it ("failed on another
    /// rank" elsewhere), not with a blow-up report, which every rank must reach alike.
    fn advance(&mut self, time: Real, max_dt: Real) -> Result<StepReport, RunError> {
        let source = match self.solver.step(&mut self.fluid, time, max_dt) {
            Ok(report) => return Ok(report),
            Err(source) => source,
        };
        let step = self.state.steps as usize + 1;
        if self.ranks.is_some() {
            return Err(RunError::Solver { time, step, source });
        }
        match health::escaped(&source, &self.fluid, &self.limits) {
            Some(diagnosis) => Err(self.blow_up(diagnosis, step, (time, time))),
            None => {
                let step = self.state.steps as usize;
                Err(RunError::Solver { time, step, source })
            }
        }
    }

    /// One row of `diagnostics.csv`: the run's own columns, the observer's, the probes', the
    /// water levels' and the load gauges', each from this rank's [`Share`] of the particles
    /// (every particle in one process, and before the first step has shared them out).
    fn sample(&mut self, time: Real, step: usize, report: &StepReport) -> Result<(), RunError> {
        let owned = self.owned_after_split();
        let mut share = match (&mut self.ranks, owned) {
            (Some(view), Some(owned)) => view.share(&self.fluid, owned),
            _ => Share::whole_run(&self.fluid),
        };
        let mut energy = [kinetic_energy(share.mass(), share.velocity())];
        share.sum_each(&mut energy);
        let mut speed = [geosph_sph::max_speed(share.velocity())];
        share.max_each(&mut speed);
        self.row.clear();
        self.row.extend_from_slice(&[
            time,
            step as Real,
            report.dt,
            energy[0],
            report.density_error_mean,
            report.density_error_max,
            speed[0],
            report.iterations as Real,
            report.divergence_iterations as Real,
            self.state.escaped as Real,
        ]);
        self.observer.sample_share(time, &mut share, &mut self.row);
        self.probes.sample(&share, &mut self.row);
        self.heights.sample(&share, &mut self.row);
        self.loads.sample(&share, &mut self.row);
        if let Some(motion) = self.solver.wall_motion() {
            motion.sample(&mut self.row);
        }
        if let Some(output) = &mut self.output {
            output.sample(&self.row)?;
        }
        Ok(())
    }

    /// Ends the run on a blow-up found at step `step`: with an output folder, saves the
    /// state before the failed step (at `last_good_time`), the failed state (at `time`) and
    /// the report, and returns the error that says where they are.
    fn blow_up(
        &mut self,
        diagnosis: Diagnosis,
        step: usize,
        (time, last_good_time): (Real, Real),
    ) -> RunError {
        self.bar.finish_and_clear();
        let files = match &mut self.output {
            Some(output) => {
                // A failed flush has already cut the CSV back to its last complete row; the
                // blow-up is what to report.
                let _ = output.flush();
                let solver = self.solver.as_ref();
                BlowUpReport {
                    scene: &self.scene.name,
                    solver,
                    diagnosis: &diagnosis,
                    step,
                    time,
                    failed: &self.fluid,
                    last_good: (&self.last_good, last_good_time),
                    limits: &self.limits,
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
    }

    /// Moves the progress bar at most four times a second.
    fn draw_progress(&mut self, time: Real, steps: usize) {
        if self.last_draw.elapsed() > Duration::from_millis(250) {
            self.last_draw = Instant::now();
            self.bar.set_position((time * 1e4) as u64);
            let rate = (steps - self.first_step) as Real / self.started.elapsed().as_secs_f64();
            self.bar
                .set_message(format!("{time:.3} s, {rate:.0} steps/s"));
        }
    }

    /// Flushes the output and reports the run.
    pub(crate) fn finish(mut self) -> Result<Summary, RunError> {
        self.bar.finish_and_clear();
        let wall_time = self.started.elapsed().as_secs_f64();
        let ranks = match &self.ranks {
            Some(view) => view.loads(self.solver.as_ref()),
            None => Vec::new(),
        };
        self.take_whole();
        let state = &self.state;
        let steps = state.steps as usize;
        let frames = match &mut self.output {
            Some(output) => {
                output.flush()?;
                crate::probes::plot_probes(output.dir(), self.probes.columns())?;
                self.heights.plot(output.dir())?;
                self.loads.plot(output.dir())?;
                if let Some(motion) = self.solver.wall_motion() {
                    crate::probes::plot_columns(
                        output.dir(),
                        &motion.plotted(),
                        crate::probes::ColumnPlot {
                            file: "bodies.png",
                            title: "Rigid bodies: height of the centre of mass",
                            y_label: "height (m)",
                            scale: 1.0,
                            prefix: "",
                        },
                    )?;
                }
                output.frames()
            }
            None => 0,
        };
        let fluid = &self.fluid;
        let per_step = |total: u64| total as Real / steps.max(1) as Real;
        Ok(Summary {
            scene: self.scene.name.clone(),
            solver: self.solver.name(),
            material: self.solver.material(),
            iterative: self.solver.iterates(),
            dimension: D,
            fluid_particles: fluid.len(),
            wall_particles: self.wall_particles,
            blocks: self.blocks.clone(),
            steps,
            simulated_time: state.time,
            wall_time,
            particle_steps_per_second: (fluid.len() * (steps - self.first_step)) as Real
                / wall_time,
            max_density_error: state.max_density_error,
            mean_density_error: state.density_error_sum / steps.max(1) as Real,
            mean_iterations: per_step(state.iterations),
            mean_divergence_iterations: per_step(state.divergence_iterations),
            bytes_per_particle: fluid.bytes_per_particle(),
            frames,
            escaped: state.escaped as usize,
            escaped_mass_fraction: state.escaped_mass
                / (fluid.mass.iter().sum::<Real>() + state.escaped_mass),
            first_escape: state.first_escape,
            wall_contacts: state.wall_contacts as usize,
            first_wall_contact: state.first_wall_contact,
            stage: state.stage.clone(),
            ranks,
        })
    }
}

/// Σ ½ m |v|², summed in index order.
fn kinetic_energy<const D: usize>(mass: &[Real], velocity: &[Vector<D>]) -> Real {
    velocity
        .iter()
        .zip(mass)
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum()
}
