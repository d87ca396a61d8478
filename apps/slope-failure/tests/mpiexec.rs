//! `mpiexec -n 2` and `-n 4 slope-failure` (feature `mpi`): the granular column collapse of
//! Bui et al. (2008) distributed over the ranks writes the run-out, deposit and diagnostics
//! of one process within round-off, once (rank 0); the modes that are not one run refuse
//! several ranks with one message. Needs an MPI installation (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::Command;

use geosph_mpi::launch::{self, APP_TIMEOUT as TIMEOUT, mpiexec, text};

const APP: &str = env!("CARGO_BIN_EXE_slope-failure");

/// 1 250 particles to 0.04 s, the onset of the flow: later, the switches between elastic and
/// plastic response and between sticking and slipping amplify round-off (docs/parallel.md,
/// "The validation"), in one process as in several.
const ARGS: [&str; 5] = ["--dx", "0.004", "--end-time", "0.04", "--quiet"];

fn folder(name: &str) -> PathBuf {
    launch::fresh_folder(env!("CARGO_TARGET_TMPDIR"), name)
}

/// The header and the numbers of a CSV file, by row.
fn table(path: &Path) -> (String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default().to_owned();
    let rows = lines
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn a_distributed_collapse_writes_what_one_process_writes() {
    let alone = folder("slope-failure-mpi-1");
    let output = launch::run(
        Command::new(APP).args(ARGS).arg("--out").arg(&alone),
        TIMEOUT,
    )
    .unwrap();
    assert!(output.status.success(), "{}", text(&output));
    for ranks in [2, 4] {
        let out = folder(&format!("slope-failure-mpi-{ranks}"));
        let mut args = ARGS.to_vec();
        args.extend(["--out", out.to_str().unwrap()]);
        let output = mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH");
        let text = text(&output);
        assert!(output.status.success(), "{ranks} ranks:\n{text}");
        assert_eq!(text.matches("final runout").count(), 1, "{text}");
        for rank in 0..ranks {
            assert!(text.contains(&format!("rank {rank} ")), "{text}");
        }
        // Within round-off of one process: the runs differ only in the order each particle
        // sums its neighbours.
        // The deposit lists the particles by id, as every rank's run holds them alike.
        for file in ["diagnostics.csv", "runout.csv", "deposit.csv"] {
            let (expected, got) = (table(&alone.join(file)), table(&out.join(file)));
            assert_eq!(expected.0, got.0, "{file}: header");
            assert_eq!(expected.1.len(), got.1.len(), "{file}: rows");
            for (row, (a, b)) in expected.1.iter().zip(&got.1).enumerate() {
                assert_eq!(a.len(), b.len(), "{file} row {row}: columns");
                for (x, y) in a.iter().zip(b) {
                    // A measure that could not be taken is NaN in both.
                    let scale = x.abs().max(y.abs()).max(1e-300);
                    assert!(
                        (x - y).abs() <= 1e-9 * scale || (x.is_nan() && y.is_nan()),
                        "{ranks} ranks, {file} row {row}: {x} against {y}"
                    );
                }
            }
        }
    }
}

#[test]
fn searches_and_series_refuse_several_ranks() {
    let out = folder("slope-failure-mpi-refused");
    for mode in ["--factor-of-safety", "--aspect-ratios"] {
        let args = [mode, "--out", out.to_str().unwrap()];
        let output = mpiexec(2, APP, &args, TIMEOUT).expect("mpiexec on the PATH");
        let text = text(&output);
        assert!(!output.status.success(), "{mode}: {text}");
        // Once: rank 0 says it, the other ranks exit quietly.
        assert_eq!(
            text.matches("does not run on several ranks yet").count(),
            1,
            "{mode}: {text}"
        );
    }
}
