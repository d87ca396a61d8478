//! The decomposition's exchanges over MPI on 1, 2 and 4 ranks (`geosph-mpi-check`, which
//! compares them with a brute-force search), started with `mpiexec` as a user would; and the
//! binary started without `mpiexec`, which must run as one rank. Needs the feature `mpi` and
//! an MPI installation with `mpiexec` on the PATH (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use std::process::{Command, Output};
use std::time::Duration;

use geosph_mpi::launch::{self, text};

const CHECK: &str = env!("CARGO_BIN_EXE_geosph-mpi-check");

/// Longest a run may take (they take about a second): a rank stuck in a collective fails the
/// test instead of hanging CI.
const TIMEOUT: Duration = Duration::from_secs(300);

fn mpiexec(ranks: usize, args: &[&str]) -> Output {
    launch::mpiexec(ranks, CHECK, args, TIMEOUT)
        .expect("mpiexec must be on the PATH (Debian: apt-get install mpich libmpich-dev)")
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
    let output = launch::run(&mut Command::new(CHECK), TIMEOUT).unwrap();
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
