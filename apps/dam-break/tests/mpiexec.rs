//! `mpiexec -n 2` and `-n 4 dam-break` (feature `mpi`): the run distributed over the ranks
//! writes the diagnostics and front of the same run in one process, within round-off, once
//! (rank 0), its frames in pieces (one per rank, under a `.pvtu`), and reports each rank's
//! load; what does not run distributed yet is an error.
//! Needs an MPI installation (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use geosph_mpi::launch::{self, mpiexec, text};

const APP: &str = env!("CARGO_BIN_EXE_dam-break");

const TIMEOUT: Duration = Duration::from_secs(600);

/// The coarse dam break of `geosph-distributed-check` (1 250 particles to 0.3 s).
const ARGS: [&str; 5] = ["--dx", "0.04", "--end-time", "0.3", "--quiet"];

fn folder(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    folder
}

/// The numbers of a CSV file, by row.
fn numbers(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn distributed_runs_write_what_one_process_writes() {
    let alone = folder("dam-break-mpi-1");
    let output = launch::run(
        Command::new(APP).args(ARGS).arg("--out").arg(&alone),
        TIMEOUT,
    )
    .unwrap();
    assert!(output.status.success(), "{}", text(&output));
    for ranks in [2, 4] {
        let out = folder(&format!("dam-break-mpi-{ranks}"));
        let mut args = ARGS.to_vec();
        args.extend(["--out", out.to_str().unwrap()]);
        let output = mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH");
        let text = text(&output);
        assert!(output.status.success(), "{ranks} ranks:\n{text}");
        // Rank 0 reports, once, with every rank's load.
        assert_eq!(
            text.matches("scene              dam-break-2d").count(),
            1,
            "{text}"
        );
        for rank in 0..ranks {
            assert!(text.contains(&format!("rank {rank} ")), "{text}");
        }
        // Every number within round-off of one process: the runs differ only in the order
        // each particle sums its neighbours (docs/parallel.md, "The validation").
        for file in ["diagnostics.csv", "front.csv"] {
            let (expected, got) = (numbers(&alone.join(file)), numbers(&out.join(file)));
            assert_eq!(expected.len(), got.len(), "{file}: rows");
            for (row, (a, b)) in expected.iter().zip(&got).enumerate() {
                for (column, (x, y)) in a.iter().zip(b).enumerate() {
                    let scale = x.abs().max(y.abs()).max(1e-300);
                    assert!(
                        (x - y).abs() <= 1e-9 * scale,
                        "{ranks} ranks, {file} row {row} column {column}: {x} against {y}"
                    );
                }
            }
        }
        // The frames in pieces, one per rank, under one `.pvtu` each (.ci/run reads them with
        // VTK and compares the last with one process's: compare_frames.py).
        let pvd = std::fs::read_to_string(out.join("dam-break-2d.pvd")).unwrap();
        assert_eq!(pvd.matches(".pvtu").count(), 7, "{pvd}");
        for rank in 0..ranks {
            let piece = format!("frames/dam-break-2d_000006_rank{rank:04}.vtu");
            assert!(out.join(&piece).is_file(), "{piece}");
        }
    }
}

#[test]
fn checkpoints_are_not_distributed_yet_and_say_so() {
    let out = folder("dam-break-mpi-checkpoint");
    let mut args = ARGS.to_vec();
    args.extend(["--out", out.to_str().unwrap(), "--checkpoint-every", "0.1"]);
    let output = mpiexec(2, APP, &args, TIMEOUT).expect("mpiexec on the PATH");
    let text = text(&output);
    assert!(!output.status.success(), "{text}");
    assert!(
        text.contains("checkpoints and restarts") && text.contains("several ranks"),
        "{text}"
    );
}
