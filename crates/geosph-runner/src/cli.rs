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

    /// The run options into `out`, with Ctrl-C installed to stop the run at a checkpoint.
    pub fn options(&self, out: PathBuf) -> Result<RunOptions, String> {
        Ok(RunOptions {
            out_dir: Some(out),
            vtk: self.no_vtk.then_some(false),
            threads: self.threads,
            progress: !self.quiet,
            checkpoint_every: self.checkpoint_every,
            restart: self.restart.clone(),
            interrupt: Some(interrupt::on_ctrl_c()?),
        })
    }
}
