//! Starting a distributed program under `mpiexec`, as tests and tools do.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How long a test lets a distributed app run before it kills it: the apps' coarse cases end
/// within a minute here, so a run past this is stuck (a rank waiting in a collective).
pub const APP_TIMEOUT: Duration = Duration::from_secs(600);

/// The folder `name` under `base` (a test's `CARGO_TARGET_TMPDIR`), emptied of an earlier
/// run's output so that a test never reads stale files.
pub fn fresh_folder(base: impl AsRef<Path>, name: &str) -> PathBuf {
    let folder = base.as_ref().join(name);
    let _ = std::fs::remove_dir_all(&folder);
    folder
}

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

/// Runs `command` to its end, or kills it after `timeout` and returns an error. Its output is
/// read while it runs, so that a program that writes much never blocks on a full pipe.
pub fn run(command: &mut Command, timeout: Duration) -> std::io::Result<Output> {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let stdout = read_all(child.stdout.take());
    let stderr = read_all(child.stderr.take());
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        if started.elapsed() > timeout {
            child.kill()?;
            return Err(std::io::Error::new(
                std::io::ErrorKind::TimedOut,
                format!("{command:?} did not end within {timeout:?}"),
            ));
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let joined = |reader: std::thread::JoinHandle<std::io::Result<Vec<u8>>>| {
        reader
            .join()
            .unwrap_or_else(|_| Err(std::io::Error::other("the output reader panicked")))
    };
    Ok(Output {
        status,
        stdout: joined(stdout)?,
        stderr: joined(stderr)?,
    })
}

/// A thread reading `pipe` to its end.
fn read_all(
    pipe: Option<impl Read + Send + 'static>,
) -> std::thread::JoinHandle<std::io::Result<Vec<u8>>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            pipe.read_to_end(&mut bytes)?;
        }
        Ok(bytes)
    })
}

/// The standard output and error of `output`, as text.
pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}
