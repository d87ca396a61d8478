//! The command line refuses careless input with one line on standard error, exit code 1 and
//! no output folder.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch() -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-cli");
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// Runs `dam-break` with `args`; its exit code and standard error.
fn dam_break(args: &[&str]) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_dam-break"))
        .args(args)
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn careless_command_lines_fail_with_one_line() {
    let folder = scratch();
    let out = folder.join("out");
    let bad_scene = folder.join("bad.ron");
    std::fs::write(
        &bad_scene,
        "Scene(\n  name: \"x\",\n  dimension: 2,\n  dx: \"fine\",\n)",
    )
    .unwrap();
    let a_file = folder.join("a-file");
    std::fs::write(&a_file, "").unwrap();
    let under_file = a_file.join("out");
    let missing = folder.join("missing.ron");
    let cases: [(Vec<&str>, &str); 6] = [
        (
            vec!["--dx=-0.02"],
            "`dx`: must be a finite number > 0, got -0.02",
        ),
        (
            vec!["--dx", "NaN"],
            "`dx`: must be a finite number > 0, got NaN",
        ),
        (
            vec!["--end-time", "0"],
            "`end_time`: must be a finite number > 0, got 0",
        ),
        (vec!["--scene", text(&missing)], "cannot read scene"),
        (
            vec!["--scene", text(&bad_scene)],
            "bad.ron: scene file: line 4, column 6: field `dx`",
        ),
        (vec!["--out", text(&under_file)], "is a file, not a folder"),
    ];
    for (args, expected) in cases {
        let mut args = args;
        if !args.contains(&"--out") {
            args.extend(["--out", text(&out)]);
        }
        let (code, stderr) = dam_break(&args);
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(expected),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} created {}", out.display());
    }
    std::fs::remove_dir_all(folder).unwrap();
}

/// Ctrl-C writes a checkpoint and the current frame and exits with 130; `--restart` finishes
/// the run into the same folder, whose `.pvd` then lists every frame once.
#[test]
fn ctrl_c_saves_a_checkpoint_and_restart_finishes_the_run() {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-cli-interrupt");
    let _ = std::fs::remove_dir_all(&folder);
    let out = folder.join("out");
    let common = [
        "--dx",
        "0.02",
        "--end-time",
        "0.5",
        "--quiet",
        "--threads",
        "2",
    ];
    let child = Command::new(env!("CARGO_BIN_EXE_dam-break"))
        .args(common)
        .args(["--out", text(&out)])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the frame at t = 0.05 s is written (of 11 frames to t = 0.5 s).
    let second_frame = out.join("frames/dam-break-2d_000001.vtu");
    let started = std::time::Instant::now();
    while !second_frame.exists() && started.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    let checkpoint = out.join("checkpoint.bin");
    assert!(
        stderr.contains(&format!("--restart {}", checkpoint.display())),
        "{stderr}"
    );
    assert!(checkpoint.is_file() && out.join("interrupted.vtu").is_file());

    let (code, stderr) = dam_break(&[&common[..], &["--restart", text(&checkpoint)]].concat());
    assert_eq!(code, Some(0), "{stderr}");
    let pvd = std::fs::read_to_string(out.join("dam-break-2d.pvd")).unwrap();
    for frame in 0..=10 {
        let file = format!("file=\"frames/dam-break-2d_{frame:06}.vtu\"");
        assert_eq!(pvd.matches(&file).count(), 1, "{file} in\n{pvd}");
    }
    assert_eq!(pvd.matches("<DataSet").count(), 11, "{pvd}");
    std::fs::remove_dir_all(folder).unwrap();
}

/// A blow-up exits with status 3 and one error line naming the report and the last good
/// frame, both written into the output folder.
#[test]
fn a_blow_up_exits_with_3_and_names_its_report() {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("dam-break-cli-blow-up");
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    // A sound speed of 1 m/s: far too slow for a 2 m column, whose density error then runs
    // past 20 % within a few steps.
    let scene = dam_break::DEFAULT_SCENE
        .replace("hydrostatic: true", "hydrostatic: false")
        .replace("cfl: 0.25,", "cfl: 0.25, sound_speed: Some(1.0),");
    let scene_file = folder.join("slow.ron");
    std::fs::write(&scene_file, scene).unwrap();
    let out = folder.join("out");
    let (code, stderr) = dam_break(&[
        "--scene",
        text(&scene_file),
        "--dx",
        "0.05",
        "--quiet",
        "--out",
        text(&out),
    ]);
    assert_eq!(code, Some(3), "{stderr}");
    let error: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(error.len(), 1, "{stderr}");
    for file in ["blowup.txt", "blowup.vtu"] {
        assert!(error[0].contains(text(&out.join(file))), "{stderr}");
        assert!(out.join(file).is_file(), "{file}");
    }
    assert!(error[0].contains("density error"), "{stderr}");
    std::fs::remove_dir_all(folder).unwrap();
}
