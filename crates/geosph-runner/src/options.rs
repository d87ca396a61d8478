//! [`RunOptions`]: how to run a scene, beyond what the scene says.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crate::checkpoint::CheckpointEvery;
#[cfg(doc)]
use crate::error::RunError;

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

impl RunOptions {
    /// Runs `work` on a pool of `threads` workers, or on rayon's global pool without a
    /// thread count.
    pub fn install<T: Send>(
        &self,
        work: impl FnOnce() -> T + Send,
    ) -> Result<T, rayon::ThreadPoolBuildError> {
        match self.threads {
            Some(threads) => Ok(rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?
                .install(work)),
            None => Ok(work()),
        }
    }
}
