//! Checkpoint and restart: a run stopped at a checkpoint and restarted writes bitwise the same
//! frames, `.pvd` series, `diagnostics.csv` and observer samples as the run that was never
//! stopped, for WCSPH, DFSPH and the soil solver on coarse cases, also after a particle left
//! the domain and in 3D with a mesh obstacle, probes and a load gauge; bad restart files are
//! refused with one clear line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use dam_break::FrontTracker;
use geosph_core::{Particles, Real};
use geosph_runner::{CheckpointEvery, NoObserver, Observer, RunError, RunOptions, Summary, run};
use geosph_scene::{Scene, SolverSpec};
use slope_failure::RunoutTracker;

/// Files a restart legitimately leaves different: the checkpoint itself and the frame of the
/// interruption.
const RUN_STATE_FILES: [&str; 2] = ["checkpoint.bin", "interrupted.vtu"];

/// Every output file under `dir` but [`RUN_STATE_FILES`] (relative path → bytes).
fn outputs(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut found = BTreeMap::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            let relative = path.strip_prefix(dir).unwrap().to_path_buf();
            if path.is_dir() {
                pending.push(path);
            } else if !RUN_STATE_FILES
                .iter()
                .any(|name| relative == Path::new(name))
            {
                found.insert(relative, std::fs::read(&path).unwrap());
            }
        }
    }
    found
}

/// An application observer that raises the interrupt flag (as Ctrl-C does) at `stop_at`.
struct StopAt<O> {
    observer: O,
    stop_at: Real,
    flag: Arc<AtomicBool>,
}

impl<O> StopAt<O> {
    fn new(observer: O, stop_at: Real) -> Self {
        Self {
            observer,
            stop_at,
            flag: Arc::new(AtomicBool::new(false)),
        }
    }
}

impl<const D: usize, O: Observer<D>> Observer<D> for StopAt<O> {
    fn columns(&self) -> Vec<&'static str> {
        self.observer.columns()
    }

    fn sample(&mut self, time: Real, fluid: &Particles<D>, row: &mut Vec<Real>) {
        self.observer.sample(time, fluid, row);
        if time >= self.stop_at {
            self.flag.store(true, Ordering::Relaxed);
        }
    }

    fn save_state(&self) -> Vec<Real> {
        self.observer.save_state()
    }

    fn restore_state(&mut self, state: &[Real]) -> Result<(), String> {
        self.observer.restore_state(state)
    }
}

fn scratch(label: &str) -> PathBuf {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("checkpoint-{label}"));
    let _ = std::fs::remove_dir_all(&root);
    root
}

fn options(out: &Path, observer_flag: &Arc<AtomicBool>) -> RunOptions {
    RunOptions {
        out_dir: Some(out.to_path_buf()),
        threads: Some(2),
        interrupt: Some(Arc::clone(observer_flag)),
        ..Default::default()
    }
}

/// A coarse dam break (dx = 0.05 m, ≈ 800 particles) to t = 0.3 s with `solver`.
fn coarse_dam_break(solver: &str) -> Scene {
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    scene.dx = 0.05;
    scene.end_time = 0.3;
    scene.solver = SolverSpec::from_name(solver).unwrap();
    scene
}

/// The granular collapse at dx = 1 cm (200 particles) to t = 0.1 s, after its geostatic stage.
fn coarse_collapse() -> Scene {
    let mut scene = Scene::from_ron(slope_failure::DEFAULT_SCENE).unwrap();
    scene.dx = 0.01;
    scene.end_time = 0.1;
    scene.output.interval = 0.01;
    scene
}

/// The deterministic part of a summary.
fn steps_and_time(summary: &Summary) -> (usize, u64) {
    (summary.steps, summary.simulated_time.to_bits())
}

/// Runs `scene` uninterrupted (with a checkpoint every 0.1 s, which must not change the run),
/// then stopped at `stop_at` and restarted from the checkpoint of the interruption; asserts
/// the two leave bitwise the same outputs and observer state. Returns the uninterrupted run's
/// folder.
fn assert_restart_is_bitwise<O>(
    scene: &Scene,
    label: &str,
    observer: impl Fn() -> O,
    stop_at: Real,
) -> PathBuf
where
    O: Observer<2> + Observer<3> + Send,
{
    let root = scratch(label);
    let (whole, parts) = (root.join("uninterrupted"), root.join("restarted"));

    let mut uninterrupted = StopAt::new(observer(), Real::INFINITY);
    let mut options_whole = options(&whole, &uninterrupted.flag);
    options_whole.checkpoint_every = Some(CheckpointEvery::Simulated(0.1));
    let summary = run(scene, &options_whole, &mut uninterrupted).unwrap();

    let mut first = StopAt::new(observer(), stop_at);
    let stopped = run(scene, &options(&parts, &first.flag), &mut first);
    let Err(RunError::Interrupted {
        time,
        checkpoint: Some(checkpoint),
        frame: Some(frame),
        ..
    }) = stopped
    else {
        panic!("the run was not interrupted: {stopped:?}");
    };
    assert!(
        time >= stop_at && time < scene.end_time,
        "stopped at t = {time}"
    );
    assert!(frame.is_file() && checkpoint.is_file());
    let frames_before = outputs(&parts)
        .keys()
        .filter(|p| p.starts_with("frames"))
        .count();
    let frames_whole = outputs(&whole)
        .keys()
        .filter(|p| p.starts_with("frames"))
        .count();
    assert!(
        0 < frames_before && frames_before < frames_whole,
        "stopped mid-run: {frames_before} of {frames_whole} frames"
    );

    let mut second = StopAt::new(observer(), Real::INFINITY);
    let mut restart = options(&parts, &second.flag);
    restart.restart = Some(checkpoint);
    let resumed = run(scene, &restart, &mut second).unwrap();
    assert_eq!(steps_and_time(&resumed), steps_and_time(&summary));
    assert_eq!(resumed.frames, summary.frames);

    let (expected, found) = (outputs(&whole), outputs(&parts));
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        found.keys().collect::<Vec<_>>()
    );
    for (file, bytes) in &expected {
        assert!(
            found[file] == *bytes,
            "{label}: `{}` differs after the restart",
            file.display()
        );
    }
    let saved = |o: &StopAt<O>| Observer::<2>::save_state(&o.observer);
    let bits = |state: Vec<Real>| state.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(saved(&second)), bits(saved(&uninterrupted)));
    whole
}

fn front_tracker(scene: &Scene) -> impl Fn() -> FrontTracker {
    let column = dam_break::Column::of(scene).unwrap();
    move || FrontTracker::new(column)
}

/// With SPS turbulence (C_s = 2, so that its stress is large) the restart is bitwise too: the
/// stresses come from the state, and the largest eddy viscosity of the last step, which
/// bounds the next step, is in the checkpoint.
#[test]
fn a_restarted_dam_break_with_sps_matches_the_uninterrupted_run_bitwise() {
    let mut scene = coarse_dam_break("wcsph");
    let SolverSpec::Wcsph(wcsph) = &mut scene.solver else {
        unreachable!("a WCSPH scene")
    };
    wcsph.sps = Some(geosph_sph::SpsConfig {
        smagorinsky: 2.0,
        ..Default::default()
    });
    assert_restart_is_bitwise(&scene, "wcsph-sps", || NoObserver, 0.12);
}

/// A gas: the particles' internal energy and its cached rate are in the checkpoint, and the
/// frames carry the energy.
#[test]
fn a_restarted_shock_tube_matches_the_uninterrupted_run_bitwise() {
    let mut scene = geosph_tests::shock_tube::scene(0.01);
    scene.end_time = 0.1;
    scene.output.interval = 0.025;
    scene.output.sample_interval = 0.005;
    scene.output.vtk = true;
    let whole = assert_restart_is_bitwise(&scene, "sod", || NoObserver, 0.04);
    let frame = std::fs::read_to_string(whole.join("frames/sod-shock-tube_000001.vtu"));
    assert!(frame.is_ok_and(|text| text.contains("internal_energy")));
}

#[test]
fn a_restarted_wcsph_dam_break_matches_the_uninterrupted_run_bitwise() {
    let scene = coarse_dam_break("wcsph");
    let whole = assert_restart_is_bitwise(&scene, "wcsph", front_tracker(&scene), 0.12);

    // The uninterrupted run's own periodic checkpoint (t ≈ 0.2 s), restarted into a copy of
    // its folder: the later frames, `.pvd` entries and CSV rows are written again, identically.
    let copy = scratch("wcsph-copy");
    copy_folder(&whole, &copy);
    std::fs::remove_file(copy.join("frames/dam-break-2d_000006.vtu")).unwrap();
    let mut tracker = StopAt::new(front_tracker(&scene)(), Real::INFINITY);
    let mut restart = options(&copy, &tracker.flag);
    restart.restart = Some(copy.join("checkpoint.bin"));
    run(&scene, &restart, &mut tracker).unwrap();
    assert_eq!(outputs(&copy), outputs(&whole));
}

#[test]
fn a_restarted_dfsph_dam_break_matches_the_uninterrupted_run_bitwise() {
    let scene = coarse_dam_break("dfsph");
    assert_restart_is_bitwise(&scene, "dfsph", front_tracker(&scene), 0.17);
}

#[test]
fn a_restarted_soil_collapse_matches_the_uninterrupted_run_bitwise() {
    let scene = coarse_collapse();
    let column = slope_failure::Column::of(&scene).unwrap();
    assert_restart_is_bitwise(&scene, "soil", move || RunoutTracker::new(column), 0.045);
}

/// SPHERIC test 2 (`data/scenes/kleefsman-obstacle.ron`), coarse: 3D, dx = 0.05 m, WCSPH with
/// δ⁺ shifting, the box a mesh wall, two probes and the box's load gauge; stopped at
/// t = 0.43 s, as the water strikes the box, and run on to 0.5 s.
#[test]
fn a_restarted_3d_impact_on_an_obstacle_matches_the_uninterrupted_run_bitwise() {
    let mut scene =
        Scene::from_ron(include_str!("../../data/scenes/kleefsman-obstacle.ron")).unwrap();
    scene.folder = Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes"));
    scene.dx = 0.05;
    scene.end_time = 0.5;
    scene.output.interval = 0.1;
    let whole = assert_restart_is_bitwise(&scene, "kleefsman", front_tracker(&scene), 0.43);
    let csv = std::fs::read_to_string(whole.join("diagnostics.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.contains("p_P1") && header.contains("h_H2") && header.contains("F_obstacle_x"),
        "the probes, water levels and load are sampled: {header}"
    );
}

/// A particle leaves the domain at t ≈ 0.1 s; the run stopped at 0.15 s restarts with 100 of
/// the scene's 101 particles and the escaped count, and continues bitwise (WCSPH and DFSPH,
/// whose escape is found inside the step).
#[test]
fn a_restart_after_a_particle_left_the_domain_matches_the_uninterrupted_run_bitwise() {
    for solver in ["wcsph", "dfsph"] {
        let scene = crate::escape::lone_particle_scene(solver);
        let label = format!("restart-escape-{solver}");
        let whole = assert_restart_is_bitwise(&scene, &label, || NoObserver, 0.15);
        let csv = std::fs::read_to_string(whole.join("diagnostics.csv")).unwrap();
        let last = csv.lines().last().unwrap();
        assert!(
            last.ends_with(",1.0"),
            "{solver}: the last row counts the escape: {last}"
        );
    }
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_folder(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

#[test]
fn bad_restart_files_are_refused_with_one_line() {
    let scene = coarse_dam_break("wcsph");
    let root = scratch("bad-files");
    let out = root.join("run");
    let mut stop = StopAt::new(front_tracker(&scene)(), 0.02);
    let Err(RunError::Interrupted {
        checkpoint: Some(good),
        ..
    }) = run(&scene, &options(&out, &stop.flag), &mut stop)
    else {
        panic!("the run was not interrupted");
    };
    let bytes = std::fs::read(&good).unwrap();
    let restart_with = |file: &Path, scene: &Scene| -> String {
        let mut observer = StopAt::new(front_tracker(scene)(), Real::INFINITY);
        let mut options = options(&root.join("restart"), &observer.flag);
        options.restart = Some(file.to_path_buf());
        let error = run(scene, &options, &mut observer).unwrap_err().to_string();
        assert!(!error.contains('\n'), "one line: {error}");
        error
    };
    let write = |name: &str, content: &[u8]| {
        let path = root.join(name);
        std::fs::write(&path, content).unwrap();
        path
    };

    let truncated = write("truncated.bin", &bytes[..bytes.len() / 2]);
    assert!(restart_with(&truncated, &scene).contains("truncated"));
    let mut flipped = bytes.clone();
    *flipped.last_mut().unwrap() ^= 1;
    let flipped = write("flipped.bin", &flipped);
    assert!(restart_with(&flipped, &scene).contains("checksum does not match"));
    let foreign = write("foreign.bin", b"P2\n1 1\n255\n0\n");
    assert!(restart_with(&foreign, &scene).contains("not a geosph checkpoint"));

    let mut longer = scene.clone();
    longer.end_time = 0.5;
    let error = restart_with(&good, &longer);
    assert!(error.contains("other settings"), "{error}");
    let mut renamed = scene.clone();
    renamed.name = "another-dam".into();
    let error = restart_with(&good, &renamed);
    assert!(
        error.contains("written for scene `dam-break-2d`"),
        "{error}"
    );
    let error = restart_with(&root.join("missing.bin"), &scene);
    assert!(error.contains("missing.bin"), "{error}");
}

/// Rigid bodies continue bitwise after a restart: their rapier world (contacts and their warm
/// start included) and accelerations are in the checkpoint. The floating box with WCSPH and
/// DFSPH, and the blocks on the slope (contacts, friction) with WCSPH.
#[test]
fn a_restart_with_rigid_bodies_matches_the_uninterrupted_run_bitwise() {
    let floating = crate::bodies::float_scene(0.3, 0.05);
    for solver in ["wcsph", "dfsph"] {
        let mut scene = floating.clone();
        scene.solver = SolverSpec::from_name(solver).unwrap();
        assert_restart_is_bitwise(&scene, &format!("float-{solver}"), || NoObserver, 0.15);
    }
    let meshes = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("checkpoint-slope-meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    let mut scene = Scene::from_ron(&crate::bodies::slope_scene(&meshes, 0.3, 0.05)).unwrap();
    scene.folder = Some(meshes);
    assert_restart_is_bitwise(&scene, "slope", || NoObserver, 0.15);
}
