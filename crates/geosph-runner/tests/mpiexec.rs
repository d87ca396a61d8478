//! Issue 26's validation: the 2D dam break (WCSPH with three integrators and with SPS,
//! PCISPH, IISPH and DFSPH) and the soil
//! collapse on 1, 2 and 4 ranks under `mpiexec`, every particle against the same run in one
//! process (`geosph-distributed-check`;
//! its documentation states the round-off bounds). Needs the feature `mpi` and an MPI
//! installation (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use geosph_mpi::launch::{APP_TIMEOUT as TIMEOUT, mpiexec, text};

const CHECK: &str = env!("CARGO_BIN_EXE_geosph-distributed-check");

/// The cases of the check, by name.
const CASES: [&str; 10] = [
    "dam-break-2d",
    "dam-break-2d/pcisph",
    "dam-break-2d/iisph",
    "dam-break-2d/iisph-bicgstab",
    "dam-break-2d/dfsph",
    "dam-break-2d-options",
    "dam-break-2d-runge-kutta",
    "dam-break-2d-predictor-corrector",
    "dam-break-2d-sps",
    "granular-collapse",
];

#[test]
fn dam_break_and_soil_collapse_on_1_2_and_4_ranks_match_one_process() {
    for ranks in [1, 2, 4] {
        let output = mpiexec(ranks, CHECK, &[], TIMEOUT)
            .expect("mpiexec must be on the PATH (Debian: apt-get install mpich libmpich-dev)");
        let text = text(&output);
        println!("{text}");
        assert!(output.status.success(), "{ranks} ranks:\n{text}");
        for case in CASES {
            assert!(
                text.contains(&format!("{case} dx ="))
                    && text.contains(&format!("on {ranks} ranks")),
                "{ranks} ranks, {case}:\n{text}"
            );
        }
        assert!(!text.contains("FAILED"), "{text}");
        assert_eq!(
            text.matches("largest differences").count(),
            CASES.len(),
            "{text}"
        );
    }
}

#[test]
fn bad_arguments_are_named() {
    let output = mpiexec(1, CHECK, &["--dx-scale", "-1"], TIMEOUT).unwrap();
    let text = text(&output);
    assert_eq!(output.status.code(), Some(2), "{text}");
    assert!(text.contains("--dx-scale -1"), "{text}");
}
