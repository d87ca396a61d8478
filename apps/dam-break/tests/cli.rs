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
