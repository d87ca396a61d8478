//! The command-line options every geosph app shares (feature `cli`): output, threads,
//! progress, checkpoints and restart, flattened into an app's own clap parser.

use std::path::PathBuf;

use crate::{CheckpointEvery, RunOptions, interrupt};

/// Output, threads, progress, checkpoint and restart options, for `#[command(flatten)]`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Output folder [default: out/ and the app's name, or with --restart the checkpoint's folder].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Do not write VTU frames.
    #[arg(long)]
    pub no_vtk: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Write the complete state to `checkpoint.bin` in the output folder (replacing the
    /// previous one) at this interval: a bare number is simulated seconds (`0.5`), a number
    /// with a unit is wall-clock time (`30s`, `10min`, `2h`). Ctrl-C always writes one, with
    /// the current frame as `interrupted.vtu`, and exits with status 130.
    #[arg(long, value_name = "INTERVAL")]
    pub checkpoint_every: Option<CheckpointEvery>,
    /// Continue the run saved in this checkpoint, into its output folder; give the same scene
    /// and overrides. The frames and the `.pvd` continue bitwise as if never stopped.
    #[arg(long, value_name = "FILE")]
    pub restart: Option<PathBuf>,
}

impl RunArgs {
    /// The output folder: `--out`, else the restart file's folder, else `default`.
    pub fn out(&self, default: &str) -> PathBuf {
        match (&self.out, &self.restart) {
            (Some(out), _) => out.clone(),
            (None, Some(restart)) => restart
                .parent()
                .filter(|dir| !dir.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), PathBuf::from),
            (None, None) => PathBuf::from(default),
        }
    }

    /// The run options into `out`, with Ctrl-C installed to stop the run at a checkpoint. Built
    /// with the feature `mpi` and started by `mpiexec` on several ranks, the run is
    /// distributed over them: each rank writes its pieces of the frames into `out`, rank 0
    /// alone the rest, and only it shows the progress.
    pub fn options(&self, out: PathBuf) -> Result<RunOptions, String> {
        let transport = ranks()?;
        let root = transport.as_ref().is_none_or(|ranks| ranks.0.rank() == 0);
        let several = transport.as_ref().is_some_and(|ranks| ranks.0.size() > 1);
        Ok(RunOptions {
            pieces_dir: several.then(|| out.clone()),
            out_dir: root.then_some(out),
            vtk: self.no_vtk.then_some(false),
            threads: self.threads,
            progress: !self.quiet && root,
            checkpoint_every: self.checkpoint_every,
            restart: self.restart.clone(),
            interrupt: Some(interrupt::on_ctrl_c(launch_root())?),
            transport,
        })
    }
}

/// Whether this process is rank 0 of its launch, known before MPI starts (from the rank
/// `mpiexec` gives it in the environment: MPICH's `PMI_RANK`, Open MPI's
/// `OMPI_COMM_WORLD_RANK`, PMIx's `PMIX_RANK`); true for a program started alone. An app
/// checks its output folder and prints its report on rank 0 only.
pub fn launch_root() -> bool {
    ["PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK"]
        .iter()
        .find_map(|name| std::env::var(name).ok())
        .is_none_or(|rank| rank.trim() == "0")
}

/// Exit status `code`; in a distributed run every rank's at once (`Transport::abort`): an
/// error on some ranks, a failed write on rank 0, must not leave the others waiting in their
/// next exchange. Not for an error that ended every rank at the same step
/// ([`ends_together`]): that is [`end_together`].
pub fn end_ranks(options: &RunOptions, code: u8) -> std::process::ExitCode {
    if let Some(ranks) = distributed(options) {
        ranks.0.abort(i32::from(code));
    }
    std::process::ExitCode::from(code)
}

/// Exit status `code` for an error that ended every rank at the same step
/// ([`ends_together`]), called by rank 0 once it has printed the error and written its files.
/// In a distributed run every rank waits there for rank 0 (the launcher ends the whole job
/// when one rank exits with a failure, so a rank that left first could stop rank 0 before
/// its message or its `blowup.txt`); then the ranks other than 0 exit with success and the
/// job's status is rank 0's.
pub fn end_together(options: &RunOptions, code: u8) -> std::process::ExitCode {
    if let Some(ranks) = distributed(options) {
        ranks.0.barrier();
        if ranks.0.rank() != 0 {
            return std::process::ExitCode::SUCCESS;
        }
    }
    std::process::ExitCode::from(code)
}

/// The ranks of a run over more than one.
fn distributed(options: &RunOptions) -> Option<&crate::Ranks> {
    options
        .transport
        .as_ref()
        .filter(|ranks| ranks.0.size() > 1)
}

/// Whether `error` ended every rank of a distributed run at the same step: an interrupt, a
/// blow-up (found by the health check, whose outcome the ranks agree; a failed step is a
/// solver error there, on the rank that failed), or a solver that does not run distributed
/// (every rank finds it before the first step). Every rank then ends with [`end_together`].
pub fn ends_together(error: &crate::RunError) -> bool {
    matches!(
        error,
        crate::RunError::Interrupted { .. }
            | crate::RunError::BlowUp { .. }
            | crate::RunError::NotDistributed(_)
    )
}

/// Whether the run is distributed over more than one rank (`what`, a mode that is not one
/// run, is then refused with a message saying so).
pub fn refuse_ranks(options: &RunOptions, what: &str) -> Result<(), String> {
    match distributed(options) {
        Some(_) => Err(format!(
            "{what} does not run on several ranks yet: start it without mpiexec"
        )),
        None => Ok(()),
    }
}

/// The ranks of this launch when built with the feature `mpi` (MPI started with serialised
/// threading; a failed rank aborts the job rather than leaving the others waiting); `None`
/// otherwise.
fn ranks() -> Result<Option<crate::Ranks>, String> {
    #[cfg(feature = "mpi")]
    {
        let ranks = geosph_mpi::Ranks::init().map_err(|error| error.to_string())?;
        ranks.abort_on_panic();
        Ok(Some(crate::Ranks(std::sync::Arc::new(ranks))))
    }
    #[cfg(not(feature = "mpi"))]
    Ok(None)
}
