//! Why a run stopped early: [`RunError`], and the exit status an app reports for it.

use std::path::PathBuf;

use geosph_core::Real;
use geosph_scene::SceneError;
use geosph_sph::SolverError;

use crate::checkpoint::CheckpointError;
use crate::health::{self, Diagnosis, report::BlowUpFiles};

/// Why a run stopped early.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The solver failed (e.g. a particle left the domain).
    #[error("at t = {time:.5} s, step {step}: {source}")]
    Solver {
        /// Simulated time of the failure.
        time: Real,
        /// Step of the failure.
        step: usize,
        /// The failure.
        source: SolverError,
    },
    /// The run blew up: a check of [`health`] failed after a step, or a particle left the
    /// domain during one. With an output folder, the state before the failed step is in
    /// `blowup.vtu`, the failed state in `blowup-failed.vtu` and the report in `blowup.txt`.
    #[error(
        "blow-up at t = {time:.5} s, step {step}: {quantity}{particle}: {explanation}; {files}",
        quantity = diagnosis.quantity,
        particle = diagnosis.particle.map(|(i, id)| format!(" of particle {i} (id {id})")).unwrap_or_default(),
        explanation = diagnosis.explanation
    )]
    BlowUp {
        /// Simulated time at the end of the failed step (at its start when the solver failed
        /// inside it).
        time: Real,
        /// The failed step (1 is the first step of the run).
        step: usize,
        /// What went wrong.
        diagnosis: Diagnosis,
        /// Where the last good state and the report are.
        files: Box<BlowUpFiles>,
    },
    /// The solver, or what the scene asks of it, does not run on several ranks, or the domain
    /// cannot be shared between them ([`geosph_sph::Solver::distribute`]); found alike on
    /// every rank before the first step.
    #[error("{0}")]
    NotDistributed(SolverError),
    /// The output folder cannot be created or written; found before any work is done.
    #[error("output folder `{}`: {reason}", path.display())]
    OutputFolder {
        /// The folder asked for.
        path: PathBuf,
        /// Why it cannot be used.
        reason: String,
    },
    /// Writing output failed.
    #[error("output: {0}")]
    Output(#[from] geosph_io::Error),
    /// The thread pool could not be built.
    #[error("threads: {0}")]
    Threads(String),
    /// The soil solver could not be built or its geostatic stage failed.
    #[error(transparent)]
    Soil(#[from] geosph_soil::SoilError),
    /// A checkpoint cannot be written, or the restart file cannot be used.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// The restart's output folder does not continue the checkpoint's run.
    #[error("restart: {0}")]
    Resume(String),
    /// The run was interrupted ([`crate::RunOptions::interrupt`]); its state is saved.
    #[error(
        "interrupted at t = {time:.5} s, step {step}{saved}",
        saved = match (checkpoint, frame) {
            (Some(checkpoint), Some(frame)) => format!(
                ": frame `{}`, checkpoint `{}` (continue with --restart {})",
                frame.display(), checkpoint.display(), checkpoint.display()
            ),
            _ => " (no output folder: nothing saved)".to_owned(),
        }
    )]
    Interrupted {
        /// Simulated time reached.
        time: Real,
        /// Steps taken.
        step: usize,
        /// The checkpoint written, when there is an output folder.
        checkpoint: Option<PathBuf>,
        /// The current frame written, when there is an output folder.
        frame: Option<PathBuf>,
    },
}

impl RunError {
    /// The exit status an app reports for this error: [`health::EXIT_BLOW_UP`] (3) for a
    /// blow-up, [`crate::interrupt::EXIT_INTERRUPTED`] (130) for Ctrl-C, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::BlowUp { .. } => health::EXIT_BLOW_UP,
            Self::Interrupted { .. } => crate::interrupt::EXIT_INTERRUPTED,
            _ => 1,
        }
    }
}
