//! Starting a distributed program under `mpiexec`, as tests and tools do.

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs `program` with `args` on `ranks` ranks under `mpiexec` (on the PATH) and returns its
/// output; a run still going after `timeout` (a rank stuck in a collective) is killed and
/// reported as an error, so that a test fails instead of hanging.
pub fn mpiexec(
    ranks: usize,
    program: &str,
    args: &[&str],
    timeout: Duration,
) -> std::io::Result<Output> {
    let mut command = Command::new("mpiexec");
    command.args(["-n", &ranks.to_string(), program]).args(args);
    run(&mut command, timeout)
}

/// Runs `command` to its end, or kills it after `timeout` and returns an error.
pub fn run(command: &mut Command, timeout: Duration) -> std::io::Result<Output> {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let started = Instant::now();
    while child.try_wait()?.is_none() {
        if started.elapsed() > timeout {
            child.kill()?;
            return Err(std::io::Error::new(
                std::io::ErrorKind::TimedOut,
                format!("{command:?} did not end within {timeout:?}"),
            ));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output()
}

/// The standard output and error of `output`, as text.
pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}
