//! [`RunOptions`]: how to run a scene, beyond what the scene says.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use geosph_sph::Transport;

use crate::checkpoint::CheckpointEvery;
#[cfg(doc)]
use crate::error::RunError;

/// How to run a scene, beyond what the scene says.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder; `None` writes nothing.
    pub out_dir: Option<PathBuf>,
    /// The output folder on every rank of a distributed run (rank 0's `out_dir`, which the
    /// other ranks do not have): each rank writes its pieces of the frames and checkpoints
    /// into it. `None` on one process.
    pub pieces_dir: Option<PathBuf>,
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
    /// The ranks of a distributed run (MPI, started by `mpiexec`); `None` or one rank: the
    /// run is one process. Rank 0 writes the output, every rank its pieces into
    /// [`RunOptions::pieces_dir`] (without it, no frames or checkpoints). An error that ends
    /// the run on some ranks only leaves the others waiting in their next exchange: end the
    /// job (`Transport::abort`), as the apps do.
    pub transport: Option<Ranks>,
}

/// The transport of a distributed run, shared between the runner (which gathers the
/// particles for samples and frames) and the solver (which exchanges its halo).
#[derive(Clone)]
pub struct Ranks(pub Arc<dyn Transport + Sync>);

impl std::fmt::Debug for Ranks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "rank {} of {}", self.0.rank(), self.0.size())
    }
}

impl RunOptions {
    /// Runs `work` on a worker of a pool of `threads` workers, or without a thread count on the
    /// current pool (rayon's global pool, called from outside any pool).
    ///
    /// On a worker, so that the step's parallel loops are shared out by that worker and its
    /// siblings: run from a thread outside the pool, every loop was handed to the pool and
    /// the calling thread put to sleep and woken again, a third thread on the cores between
    /// loops (the default collapse, 5 000 particles and five loops per step, ran about 9 %
    /// slower that way on two cores, in the median of interleaved runs; the WCSPH dam break
    /// 12 %; docs/performance.md).
    pub fn install<T: Send>(
        &self,
        work: impl FnOnce() -> T + Send,
    ) -> Result<T, rayon::ThreadPoolBuildError> {
        match self.threads {
            Some(threads) => Ok(rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?
                .install(work)),
            // Called from outside any pool, `scope` runs its body on a worker of the global
            // pool; called from a worker, in place.
            None => Ok(rayon::scope(|_| work())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_runs_on_a_worker_of_the_pool() {
        let global = RunOptions::default();
        assert!(
            global
                .install(rayon::current_thread_index)
                .unwrap()
                .is_some()
        );
        let two = RunOptions {
            threads: Some(2),
            ..RunOptions::default()
        };
        let (index, threads) = two
            .install(|| (rayon::current_thread_index(), rayon::current_num_threads()))
            .unwrap();
        assert!(index.is_some());
        assert_eq!(threads, 2);
    }
}
