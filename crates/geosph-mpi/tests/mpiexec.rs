//! The decomposition's exchanges over MPI on 1, 2 and 4 ranks (`geosph-mpi-check`, which
//! compares them with a brute-force search), started with `mpiexec` as a user would; and the
//! binary started without `mpiexec`, which must run as one rank. Needs the feature `mpi` and
//! an MPI installation with `mpiexec` on the PATH (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const CHECK: &str = env!("CARGO_BIN_EXE_geosph-mpi-check");

/// Longest a run may take (they take about a second): a rank stuck in a collective fails the
/// test instead of hanging CI.
const TIMEOUT: Duration = Duration::from_secs(300);

/// Runs `command` to its end, or kills it after [`TIMEOUT`] and fails.
fn run(command: &mut Command) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpiexec must be on the PATH (Debian: apt-get install mpich libmpich-dev)");
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > TIMEOUT {
            child.kill().unwrap();
            panic!("{command:?} did not end within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

fn mpiexec(ranks: usize, args: &[&str]) -> Output {
    run(Command::new("mpiexec")
        .args(["-n", &ranks.to_string(), CHECK])
        .args(args))
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

#[test]
fn halo_and_migration_match_a_brute_force_search_on_1_2_and_4_ranks() {
    for ranks in [1, 2, 4] {
        let output = mpiexec(ranks, &[]);
        let text = text(&output);
        println!("{text}");
        assert!(output.status.success(), "{ranks} ranks:\n{text}");
        for case in ["2D, periodic along x", "2D, closed", "3D, periodic along y"] {
            assert!(
                text.contains(&format!("{ranks} ranks, {case}: ok")),
                "{ranks} ranks, {case}:\n{text}"
            );
        }
    }
}

#[test]
fn without_mpiexec_the_binary_is_one_rank() {
    let output = run(&mut Command::new(CHECK));
    let text = text(&output);
    assert!(output.status.success(), "{text}");
    assert!(text.contains("1 ranks, 2D, closed: ok"), "{text}");
}

#[test]
fn more_ranks_than_cells_is_a_clear_error() {
    let output = mpiexec(3, &["--two-cells"]);
    let text = text(&output);
    assert!(!output.status.success(), "{text}");
    assert!(
        text.contains("3 ranks for a domain of 2 cells") && text.contains("at most 2 ranks"),
        "{text}"
    );
}
