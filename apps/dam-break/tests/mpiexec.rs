//! `mpiexec -n 2` and `-n 4 dam-break` (feature `mpi`): the run distributed over the ranks
//! writes the diagnostics and front of the same run in one process, within round-off, once
//! (rank 0), its frames in pieces (one per rank, under a `.pvtu`), and reports each rank's
//! load; a checkpoint in pieces restarts bitwise on as many ranks, within round-off on
//! others; pressure probes, water levels and wall loads reduced over the ranks read what one
//! process reads.
//! Needs an MPI installation (`.ci/run` installs MPICH).
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::Command;

use geosph_mpi::launch::{self, APP_TIMEOUT as TIMEOUT, mpiexec, text};

const APP: &str = env!("CARGO_BIN_EXE_dam-break");

/// The coarse dam break of `geosph-distributed-check` (1 250 particles to 0.3 s).
const ARGS: [&str; 5] = ["--dx", "0.04", "--end-time", "0.3", "--quiet"];

fn folder(name: &str) -> PathBuf {
    launch::fresh_folder(env!("CARGO_TARGET_TMPDIR"), name)
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

/// The Kleefsman et al. (2005) box in a 3D tank, coarse (780 particles), to just after the
/// water reaches the box (0.45 s): the scene's pressure probes, water levels and the load on
/// the box all read water on their last samples.
const GAUGED: [&str; 7] = [
    "--dx",
    "0.1",
    "--end-time",
    "0.45",
    "--quiet",
    "--no-vtk",
    "--scene",
];

/// `diagnostics.csv`'s header and rows.
fn table(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = text.lines().next().unwrap().split(',').map(String::from);
    (header.collect(), numbers(path))
}

#[test]
fn distributed_probes_levels_and_loads_are_those_of_one_process() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/kleefsman-obstacle.ron"
    );
    let run = |ranks: usize| {
        let out = folder(&format!("gauges-mpi-{ranks}"));
        let mut args = GAUGED.to_vec();
        args.extend([scene, "--out", out.to_str().unwrap()]);
        let output = match ranks {
            1 => launch::run(Command::new(APP).args(&args), TIMEOUT).unwrap(),
            _ => mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH"),
        };
        assert!(output.status.success(), "{ranks} ranks:\n{}", text(&output));
        table(&out.join("diagnostics.csv"))
    };
    let (header, alone) = run(1);
    // Each probe, level and load column must read water on some samples, or the comparison
    // below would compare zeros and NaN only.
    for (column, name) in header.iter().enumerate() {
        if ["p_", "h_", "F_obstacle_x"]
            .iter()
            .any(|p| name.starts_with(p))
        {
            let wet = alone.iter().filter(|row| row[column].abs() > 0.0).count();
            assert!(wet >= 5, "{name}: {wet} samples with water");
        }
    }
    for ranks in [2, 4] {
        let (_, got) = run(ranks);
        assert_eq!(alone.len(), got.len(), "{ranks} ranks: rows");
        // The particles of the runs differ by round-off (the order each particle sums its
        // neighbours, docs/parallel.md), which the front tip and the first wet samples of a
        // gauge amplify to 10⁻⁸–10⁻⁷ of the columns' largest magnitude (measured: 2.3 × 10⁻⁷
        // on 2 ranks, 2.7 × 10⁻⁸ on 4, both in the moment about the vertical); a reduction
        // that missed a rank or counted a halo particle would be off by a whole share. A
        // force's or moment's components share one scale: the box's symmetry cancels some.
        let largest = |columns: &[usize]| {
            let values = alone.iter().flat_map(|row| columns.iter().map(|&c| row[c]));
            values.map(f64::abs).fold(0.0, f64::max)
        };
        for (column, name) in header.iter().enumerate() {
            let vector = ["F_", "M_"].into_iter().find(|p| name.starts_with(p));
            let scale = match vector {
                Some(prefix) => largest(
                    &(0..header.len())
                        .filter(|&c| header[c].starts_with(prefix))
                        .collect::<Vec<_>>(),
                ),
                None => largest(&[column]),
            };
            for (row, (a, b)) in alone.iter().zip(&got).enumerate() {
                let (x, y) = (a[column], b[column]);
                assert!(
                    (x - y).abs() <= 1e-5 * scale || (x.is_nan() && y.is_nan()),
                    "{ranks} ranks, {name} row {row}: {x} against {y} (scale {scale})"
                );
            }
        }
    }
}

/// Copies the files of `from` and of its sub-folders (one level) to `to`.
fn copy_run(from: &Path, to: &Path) {
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_run(&entry.path(), &target);
        } else {
            std::fs::create_dir_all(to).unwrap();
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// The largest difference between the numbers of two CSV files of the same shape, relative
/// to the larger magnitude of each pair.
fn largest_difference(a: &Path, b: &Path) -> f64 {
    let (a, b) = (numbers(a), numbers(b));
    assert_eq!(a.len(), b.len(), "rows");
    a.iter()
        .zip(&b)
        .flat_map(|(x, y)| x.iter().zip(y))
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-300))
        .fold(0.0, f64::max)
}

#[test]
fn distributed_checkpoints_restart_bitwise_on_as_many_ranks() {
    // 5 000 particles: at dx = 0.04 m no particle had changed cells since the last set-up at
    // the checkpoint, and the restart matched even without the set-up that follows a
    // checkpoint (`Distribution::set_up_next_step`); at 0.02 m it does not.
    let dam_break = [
        "--dx",
        "0.02",
        "--end-time",
        "0.3",
        "--checkpoint-every",
        "0.1",
    ];
    restarts_match(
        "dam-break",
        &dam_break,
        &[(2, true), (4, false), (1, false)],
    );
    // The soil collapse (1 250 particles, checkpoint at 0.09 s): its state is the particles'
    // stress, strain and displacement and the solver's last accelerations.
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/granular-collapse.ron"
    );
    let collapse = [
        "--scene",
        scene,
        "--dx",
        "0.004",
        "--end-time",
        "0.1",
        "--checkpoint-every",
        "0.03",
    ];
    restarts_match("collapse", &collapse, &[(2, true), (1, false)]);
    // DFSPH (1 250 particles, checkpoint at 0.05 s): besides the pressure, each particle
    // carries both solves' warm starts, and the solver its acceleration bound.
    let dfsph = [
        "--solver",
        "dfsph",
        "--dx",
        "0.04",
        "--end-time",
        "0.1",
        "--checkpoint-every",
        "0.05",
    ];
    restarts_match("dfsph", &dfsph, &[(2, true), (4, false), (1, false)]);
}

/// Runs `args` on 2 ranks with checkpoints, then restarts from the last checkpoint on each
/// of `restarts`' rank counts (1: one process without `mpiexec`): bitwise the same files, or
/// within round-off of them.
fn restarts_match(name: &str, args: &[&str], restarts: &[(usize, bool)]) {
    let run = folder(&format!("{name}-mpi-checkpoint"));
    let with_out = |out: &Path| {
        let mut args = args.to_vec();
        args.extend(["--quiet", "--out", out.to_str().unwrap()]);
        args.into_iter().map(str::to_owned).collect::<Vec<_>>()
    };
    let launch = |ranks: usize, args: &[String]| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = match ranks {
            1 => launch::run(Command::new(APP).args(&args), TIMEOUT).unwrap(),
            _ => mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH"),
        };
        assert!(output.status.success(), "{ranks} ranks:\n{}", text(&output));
    };
    launch(2, &with_out(&run));
    // The last checkpoint: a manifest and one piece per rank, the earlier checkpoints'
    // pieces removed.
    let pieces: Vec<_> = std::fs::read_dir(run.join("checkpoint-pieces"))
        .unwrap()
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(pieces.len(), 2, "{pieces:?}");
    for &(ranks, bitwise) in restarts {
        let restarted = folder(&format!("{name}-mpi-restart-{ranks}"));
        copy_run(&run, &restarted);
        let mut args = with_out(&restarted);
        args.extend([
            "--restart".into(),
            restarted.join("checkpoint.bin").display().to_string(),
        ]);
        launch(ranks, &args);
        for file in ["diagnostics.csv", "front.csv"] {
            let (a, b) = (run.join(file), restarted.join(file));
            let difference = largest_difference(&a, &b);
            match bitwise {
                // On as many ranks the restart cuts the cells and orders the particles as the
                // run did after its checkpoint: the same files, bit for bit.
                true => assert_eq!(
                    std::fs::read(&a).unwrap(),
                    std::fs::read(&b).unwrap(),
                    "{file}: {difference:e}"
                ),
                // On another rank count (or one process) each particle sums its neighbours in
                // another order: round-off (docs/parallel.md, "The validation").
                false => assert!(
                    difference <= 1e-9,
                    "{name} on {ranks} ranks, {file}: {difference:e}"
                ),
            }
        }
        if bitwise {
            for entry in std::fs::read_dir(run.join("frames")).unwrap().flatten() {
                let other = restarted.join("frames").join(entry.file_name());
                assert_eq!(
                    std::fs::read(entry.path()).unwrap(),
                    std::fs::read(&other).unwrap(),
                    "{}",
                    other.display()
                );
            }
        }
    }
}

/// A blow-up on several ranks: the sound speed of 1 m/s makes the acoustic step far too long
/// for the collapse (tests/tests/blow_up.rs), the density error passes its bound within a few
/// steps; the ranks agree on it, rank 0 writes the report and the last good state of every
/// particle and says so once, and the job ends with the blow-up's status.
#[test]
fn a_distributed_blow_up_is_reported_once_with_its_files() {
    let out = folder("dam-break-mpi-blow-up");
    std::fs::create_dir_all(&out).unwrap();
    let scene = include_str!("../../../data/scenes/dam-break-2d.ron")
        .replace("hydrostatic: true", "hydrostatic: false")
        .replace("cfl: 0.25,", "cfl: 0.25, sound_speed: Some(1.0),");
    let scene_file = out.join("blow-up.ron");
    std::fs::write(&scene_file, scene).unwrap();
    assert_blow_up_on_two_ranks(
        &scene_file,
        &out,
        &["--dx", "0.05", "--quiet"],
        "error: blow-up at",
        &["blowup.txt", "blowup.vtu"],
    );
}

/// Runs `scene` on 2 ranks into `out` with `args` and checks that the job ends with the
/// blow-up status, prints `message` once and writes `files` (rank 0's report).
fn assert_blow_up_on_two_ranks(
    scene: &Path,
    out: &Path,
    args: &[&str],
    message: &str,
    files: &[&str],
) {
    let mut all = vec![
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let output = mpiexec(2, APP, &all, TIMEOUT).expect("mpiexec on the PATH");
    let text = text(&output);
    assert_eq!(output.status.code(), Some(3), "{text}");
    assert_eq!(text.matches(message).count(), 1, "{text}");
    for file in files {
        assert!(out.join(file).is_file(), "{file}: {text}");
    }
}

/// A box floating in a 2D tank (the scene of `tests/tests/bodies.rs`, 920 particles), to
/// 0.3 s: on several ranks every rank sums the pressure on the box's surface over the
/// particles it owns, the sums are added over the ranks, and every rank moves the box
/// alike. Its position, velocity and load, and every other column, are those of one process
/// within 10⁻⁹ of their scale (a force's or position's components share one): the particles
/// differ by round-off, while a load summed over one rank's particles only, or over a halo
/// counted twice, is off by a whole share of the box's weight.
#[test]
fn rigid_bodies_move_on_several_ranks_as_on_one_process() {
    let out = folder("bodies-mpi");
    std::fs::create_dir_all(&out).unwrap();
    let scene = include_str!("../../../data/scenes/tests/floating-box.ron");
    let scene_file = out.join("float.ron");
    std::fs::write(&scene_file, scene).unwrap();
    let run = |ranks: usize| {
        let folder = out.join(format!("ranks-{ranks}"));
        let args = [
            "--scene",
            scene_file.to_str().unwrap(),
            "--end-time",
            "0.3",
            "--quiet",
            "--out",
            folder.to_str().unwrap(),
        ];
        let output = match ranks {
            1 => launch::run(Command::new(APP).args(args), TIMEOUT).unwrap(),
            _ => mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH"),
        };
        assert!(output.status.success(), "{ranks} ranks:\n{}", text(&output));
        table(&folder.join("diagnostics.csv"))
    };
    let (header, alone) = run(1);
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    // The box moves and the water pushes it: the comparison is not one of zeros.
    let last = alone.last().unwrap();
    assert!(last[column("box_Fy")] > 100.0, "{last:?}");
    assert!(
        alone.iter().any(|row| row[column("box_vy")].abs() > 1e-3),
        "the box does not move"
    );
    let groups = [
        vec!["box_x", "box_y"],
        vec!["box_vx", "box_vy"],
        vec!["box_Fx", "box_Fy"],
    ];
    for ranks in [2, 4] {
        let (_, got) = run(ranks);
        assert_eq!(alone.len(), got.len(), "{ranks} ranks: rows");
        for (c, name) in header.iter().enumerate() {
            let members = match groups.iter().find(|g| g.contains(&name.as_str())) {
                Some(group) => group.iter().map(|m| column(m)).collect(),
                // An angle's scale is a radian.
                None if name == "box_angle" => vec![],
                None => vec![c],
            };
            let scale = match members.is_empty() {
                true => 1.0,
                false => alone
                    .iter()
                    .flat_map(|row| members.iter().map(|&m| row[m].abs()))
                    .fold(0.0, f64::max),
            };
            for (row, (a, b)) in alone.iter().zip(&got).enumerate() {
                let (x, y) = (a[c], b[c]);
                assert!(
                    (x - y).abs() <= 1e-9 * scale,
                    "{ranks} ranks, {name} row {row}: {x} against {y} (scale {scale})"
                );
            }
        }
    }
}

/// The lone particle of `tests/tests/escape.rs` thrown up out of the domain while the water
/// stays in its tank (101 particles): on several ranks the rank that owns it finds it outside
/// after the step in which it left (the lists bin it in their edge cells until then, as one
/// process's do), every rank removes together, and the run counts it as one process does:
/// with WCSPH, DFSPH and the soil solver on 2 and 4 ranks every column within 10⁻⁹ of its
/// scale of one process's (measured: 2.4 × 10⁻¹³ with WCSPH), one particle leaving within
/// a step of the moment it crosses the top at t = 0.099 s. DFSPH's runs are compared to
/// 0.12 s, past the escape: its round-off grows tenfold every 0.03 s or so here, as without
/// an escape (docs/parallel.md; 3 × 10⁻¹¹ at 0.12 s, 2 × 10⁻⁹ at 0.15 s, 10⁻⁵ at 0.27 s,
/// with the same steps, iterations and escape). With `health.max_escaped_fraction` below one
/// particle in 101, the escape is the blow-up one process diagnoses, reported once (every
/// particle gathered for it) with its `blowup.txt`.
#[test]
fn a_particle_leaving_the_domain_leaves_a_distributed_run() {
    let out = folder("escape-mpi");
    std::fs::create_dir_all(&out).unwrap();
    // With `health.max_escaped_fraction` below one particle in 101 ("too many"), the escape
    // is a blow-up.
    let scene = |solver: &str| {
        let (solver, health) = match solver.strip_suffix(" too many") {
            Some(solver) => (solver, "health: (max_escaped_fraction: 0.005),"),
            None => (solver, ""),
        };
        include_str!("../../../data/scenes/tests/lone-particle.ron")
            .replace("solver: Wcsph(()),", &format!("solver: {solver}, {health}"))
    };
    let run = |solver: &str, ranks: usize| {
        let scene_file = out.join(format!("{solver}.ron"));
        std::fs::write(&scene_file, scene(solver)).unwrap();
        let folder = out.join(format!("{solver}-{ranks}"));
        let args = [
            "--scene",
            scene_file.to_str().unwrap(),
            "--no-vtk",
            "--out",
            folder.to_str().unwrap(),
        ];
        let output = match ranks {
            1 => launch::run(Command::new(APP).args(args), TIMEOUT).unwrap(),
            _ => mpiexec(ranks, APP, &args, TIMEOUT).expect("mpiexec on the PATH"),
        };
        let text = text(&output);
        assert!(output.status.success(), "{solver}, {ranks} ranks:\n{text}");
        assert_eq!(
            text.matches("escaped            1 particles (0.990 % of the mass)")
                .count(),
            1,
            "{solver}, {ranks} ranks:\n{text}"
        );
        let first = text
            .split("first at t = ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|t| t.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no first escape time:\n{text}"));
        assert!(
            (first - 0.099).abs() < 0.01,
            "{solver}: first escape at {first} s"
        );
        table(&folder.join("diagnostics.csv"))
    };
    for solver in ["Wcsph(())", "Dfsph(())", "Soil(())"] {
        let (header, alone) = run(solver, 1);
        for ranks in [2, 4] {
            let (_, got) = run(solver, ranks);
            assert_eq!(alone.len(), got.len(), "{solver}, {ranks} ranks: rows");
            let until = if solver == "Dfsph(())" { 0.12 } else { 0.3 };
            for (c, name) in header.iter().enumerate() {
                let scale = alone.iter().map(|row| row[c].abs()).fold(0.0, f64::max);
                let compared = alone
                    .iter()
                    .zip(&got)
                    .take_while(|(a, _)| a[0] <= until + 1e-9);
                for (row, (a, b)) in compared.enumerate() {
                    assert!(
                        (a[c] - b[c]).abs() <= 1e-9 * scale,
                        "{solver}, {ranks} ranks, {name} row {row}: {} against {}",
                        a[c],
                        b[c]
                    );
                }
            }
        }
    }
    let scene_file = out.join("too-many.ron");
    std::fs::write(&scene_file, scene("Wcsph(()) too many")).unwrap();
    assert_blow_up_on_two_ranks(
        &scene_file,
        &out.join("too-many-2"),
        &["--no-vtk"],
        "1 of 101 particles (0.99 %) would have left the domain",
        &["blowup.txt"],
    );
}
