//! Running a scene: [`run`] and its [`RunOptions`]; the loop itself is `run_loop`'s.

use geosph_scene::Scene;

pub use crate::error::RunError;
use crate::observer::Observer;
pub use crate::options::RunOptions;
use crate::run_loop::RunLoop;
pub use crate::summary::Summary;

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
    options
        .install(|| match scene.dimension {
            2 => run_plane(scene, options, observer),
            _ => run_space(scene, options, observer),
        })
        .map_err(|error| RunError::Threads(error.to_string()))?
}

/// A 2D run. Not generic, so that every solver is compiled once, in this crate, rather than
/// again in each crate that calls [`run`] (Rust monomorphises generics where they are used).
fn run_plane(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Observer<2>,
) -> Result<Summary, RunError> {
    RunLoop::<2>::start(scene, options, observer)?.run()
}

/// A 3D run, see [`run_plane`].
fn run_space(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Observer<3>,
) -> Result<Summary, RunError> {
    RunLoop::<3>::start(scene, options, observer)?.run()
}
