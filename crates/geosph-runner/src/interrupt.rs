//! Ctrl-C: a flag the time loop checks once per step ([`crate::RunOptions::interrupt`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit status of a run stopped by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs a Ctrl-C (SIGINT) handler for the process and returns the flag it sets: the run
/// then writes the current frame and a checkpoint and stops; with `speak`, the handler says
/// so on standard error (rank 0 of a distributed run, or a process alone: under `mpiexec`
/// every rank receives the signal). A second Ctrl-C, while that is being written, exits at
/// once with [`EXIT_INTERRUPTED`]. Call once per process.
pub fn on_ctrl_c(speak: bool) -> Result<Arc<AtomicBool>, String> {
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = Arc::clone(&flag);
    ctrlc::set_handler(move || {
        if handler_flag.swap(true, Ordering::Relaxed) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        if speak {
            eprintln!(
                "\ninterrupt: writing the current frame and a checkpoint (Ctrl-C again to quit at once)"
            );
        }
    })
    .map_err(|error| format!("cannot install the Ctrl-C handler: {error}"))?;
    Ok(flag)
}
