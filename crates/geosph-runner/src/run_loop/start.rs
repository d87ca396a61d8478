//! What [`RunLoop::start`](super::RunLoop::start) needs besides the scene's particles: the
//! solver the scene declares, the state of a checkpoint, and the output folder.

use std::path::Path;

use geosph_core::{Particles, Real};
use geosph_fluid::{IncompressibleMethod, build_incompressible, build_wcsph};
use geosph_scene::{Scene, SolverSpec};
use geosph_sph::{Solver, SphSetup};
use geosph_surface::SurfaceParameters;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::checkpoint::{Checkpoint, CheckpointError, Progress};
use crate::error::RunError;
use crate::observer::Observer;
use crate::options::RunOptions;
use crate::output::RunOutput;

/// The solver the scene declares (built for `fluid`, the particles of its set-up), and
/// nothing it does not.
pub fn build_solver<const D: usize>(
    scene: &Scene,
    inputs: SphSetup<D>,
    fluid: &mut Particles<D>,
) -> Result<Box<dyn Solver<D>>, RunError> {
    let incompressible = |method, config, inputs, fluid: &mut Particles<D>| {
        build_incompressible(method, config, inputs, fluid)
    };
    let built = match &scene.solver {
        SolverSpec::Wcsph(config) => build_wcsph(config, inputs, fluid),
        SolverSpec::Pcisph(config) => {
            incompressible(IncompressibleMethod::Pcisph, config, inputs, fluid)
        }
        SolverSpec::Iisph(config) => {
            incompressible(IncompressibleMethod::Iisph, config, inputs, fluid)
        }
        SolverSpec::Dfsph(config) => {
            incompressible(IncompressibleMethod::Dfsph, config, inputs, fluid)
        }
        SolverSpec::Soil(config) => return Ok(geosph_soil::build_soil(config, inputs, fluid)?),
    };
    built.map_err(|source| RunError::Solver {
        time: 0.0,
        step: 0,
        source: source.into(),
    })
}

/// Restores the particles, the solver and the observer from the checkpoint at `path`.
pub(super) fn restore<const D: usize>(
    path: &Path,
    scene: &Scene,
    fluid: &mut Particles<D>,
    solver: &mut dyn Solver<D>,
    observer: &mut dyn Observer<D>,
) -> Result<Progress, RunError> {
    let saved = Checkpoint::read::<D>(path, scene)?;
    *fluid = saved
        .particles
        .restore(fluid, saved.progress.escaped)
        .map_err(|error| restart_mismatch(path, error.0))?;
    solver
        .restore_state(saved.solver, fluid)
        .map_err(|error| restart_mismatch(path, error.to_string()))?;
    observer
        .restore_state(&saved.observer)
        .map_err(|reason| restart_mismatch(path, reason))?;
    Ok(saved.progress)
}

/// The run's output folder, created, or resumed after `restart`; `None` without one.
pub(super) fn open_output<const D: usize>(
    scene: &Scene,
    options: &RunOptions,
    observer: &dyn Observer<D>,
    gauges: [&[String]; 4],
    restart: Option<&Progress>,
) -> Result<Option<RunOutput>, RunError> {
    let Some(dir) = &options.out_dir else {
        return Ok(None);
    };
    let vtk = options.vtk.unwrap_or(scene.output.vtk);
    let surface = scene.output.surface.map(|spec| SurfaceParameters {
        dx: scene.dx,
        support: spec.support,
        cube: spec.cube,
        threshold: spec.threshold,
    });
    let mut columns = observer.columns();
    columns.extend(gauges.iter().flat_map(|c| c.iter()).map(String::as_str));
    Ok(Some(match restart {
        None => RunOutput::create(dir, &scene.name, vtk, surface, &columns)?,
        Some(progress) => RunOutput::resume(
            dir,
            &scene.name,
            vtk,
            surface,
            &columns,
            (
                progress.time,
                progress.frames as usize,
                progress.rows as usize,
            ),
        )
        .map_err(RunError::Resume)?,
    }))
}

/// A restart file that passed its own checks but does not fit the scene's particles or solver.
fn restart_mismatch(path: &Path, reason: String) -> RunError {
    RunError::Checkpoint(CheckpointError::Mismatch {
        path: path.to_path_buf(),
        reason,
    })
}

/// The progress bar to `end_time`, drawn on standard error when `shown`.
pub(super) fn progress_bar(shown: bool, end_time: Real) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some((end_time * 1e4).ceil() as u64),
        if shown {
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
