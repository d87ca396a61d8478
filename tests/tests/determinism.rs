//! Determinism: the same scene run by the same binary with 1, 2 and 4 worker threads gives
//! bitwise identical results: every field of the final particles, every number of the run
//! summary except the wall-clock ones, and every output file byte for byte (the VTU frames,
//! the `.pvd` series and `diagnostics.csv`).
//!
//! Four threads on a two-core machine still split every parallel loop four ways, which is what
//! matters: the results must not depend on how rayon divides the work.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geosph_runner::{RunOptions, Summary, run};
use geosph_scene::Scene;
use geosph_tests::FinalState;

const THREADS: [usize; 3] = [1, 2, 4];

/// What one run leaves: the final particles and the summary as text, and the output files.
type Outcome = (String, String, BTreeMap<PathBuf, Vec<u8>>);

/// Every file under `dir` (relative path → bytes).
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut found = BTreeMap::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                let bytes = std::fs::read(&path).unwrap();
                found.insert(path.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    found
}

/// The summary without its wall-clock numbers.
fn deterministic_part(summary: &Summary) -> String {
    let mut summary = summary.clone();
    summary.wall_time = 0.0;
    summary.particle_steps_per_second = 0.0;
    format!("{summary:?}")
}

/// Runs `scene` with each thread count; the final state (as its `Debug` text, which prints
/// every field of every particle with the shortest exactly round-tripping decimals), the
/// summary and the output files.
fn run_with_threads(scene: &Scene, label: &str) -> Vec<Outcome> {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("determinism-{label}"));
    let _ = std::fs::remove_dir_all(&root);
    THREADS
        .iter()
        .map(|&threads| {
            let out = root.join(format!("threads-{threads}"));
            let mut state = FinalState::default();
            let options = RunOptions {
                out_dir: Some(out.clone()),
                threads: Some(threads),
                ..Default::default()
            };
            let summary = run(scene, &options, &mut state).unwrap();
            let particles = match (&state.plane, &state.space) {
                (Some((time, fluid)), _) => format!("t = {time:?}\n{fluid:?}"),
                (_, Some((time, fluid))) => format!("t = {time:?}\n{fluid:?}"),
                _ => panic!("no sample was taken"),
            };
            (particles, deterministic_part(&summary), files(&out))
        })
        .collect()
}

fn assert_identical(results: &[Outcome]) {
    let (particles, summary, outputs) = &results[0];
    assert!(
        outputs.len() >= 3,
        "too few output files: {:?}",
        outputs.keys()
    );
    for (k, (other_particles, other_summary, other_outputs)) in results.iter().enumerate().skip(1) {
        let threads = THREADS[k];
        assert!(
            particles == other_particles,
            "final particles differ between 1 and {threads} threads"
        );
        assert_eq!(summary, other_summary, "summary, 1 vs {threads} threads");
        assert_eq!(
            outputs.keys().collect::<Vec<_>>(),
            other_outputs.keys().collect::<Vec<_>>(),
            "output files, 1 vs {threads} threads"
        );
        for (file, bytes) in outputs {
            assert!(
                bytes == &other_outputs[file],
                "{} differs between 1 and {threads} threads",
                file.display()
            );
        }
    }
}

#[test]
fn dam_break_2d_is_bitwise_identical_for_1_2_and_4_threads() {
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.05;
    scene.end_time = 0.12;
    scene.output.interval = 0.03;
    // Z-order sorts within the run, so that reordering is covered too.
    let geosph_scene::SolverSpec::Wcsph(config) = &mut scene.solver else {
        unreachable!("the dam-break scene names WCSPH")
    };
    config.reorder_every = 20;
    let results = run_with_threads(&scene, "2d");
    assert_identical(&results);
}

#[test]
fn incompressible_dam_break_is_identical_for_1_2_4_threads() {
    // DFSPH runs both of its solves; their error sums and the time-step rule reduce in index
    // order. Z-order sorts within the run permute its warm-start arrays.
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.05;
    scene.end_time = 0.12;
    scene.output.interval = 0.03;
    scene.solver = geosph_scene::SolverSpec::Dfsph(geosph_fluid::IncompressibleConfig {
        reorder_every: 20,
        ..Default::default()
    });
    let results = run_with_threads(&scene, "2d-dfsph");
    assert_identical(&results);
}

#[test]
fn dam_break_3d_is_bitwise_identical_for_1_2_and_4_threads() {
    let mut scene = Scene::from_ron(include_str!("../../data/scenes/dam-break-3d.ron")).unwrap();
    // At its own dx: the period across y must hold twice the support radius.
    scene.end_time = 0.04;
    scene.output.interval = 0.02;
    // Its free surfaces too (the shipped scene has them on).
    scene.output.surface = Some(Default::default());
    let results = run_with_threads(&scene, "3d");
    assert_identical(&results);
}

/// 3D soil: the axisymmetric collapse (`data/scenes/axisymmetric-collapse.ron`), coarse (five
/// particles across the column's radius), through its geostatic stage and the release.
#[test]
fn soil_3d_collapse_is_bitwise_identical_for_1_2_and_4_threads() {
    let mut scene =
        Scene::from_ron(include_str!("../../data/scenes/axisymmetric-collapse.ron")).unwrap();
    scene.folder = Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes"));
    scene.dx = 0.04;
    scene.end_time = 0.06;
    scene.output.interval = 0.03;
    let results = run_with_threads(&scene, "soil-3d");
    assert_identical(&results);
}
