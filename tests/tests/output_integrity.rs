//! Output integrity: a run killed with SIGKILL at any moment, or stopped by a write error,
//! leaves an output folder whose `.pvd` is well-formed XML listing only complete, readable
//! `.vtu` frames, and whose `diagnostics.csv` holds only complete rows.
//!
//! The runs happen in child processes of the helper binary `integrity-child`
//! (`tests/src/bin/integrity-child.rs`), which runs a scene into a folder. The test kills it
//! (SIGKILL, via `Child::kill`) at a spread of moments, or starts it under a file-size limit
//! (`ulimit -f`, with SIGXFSZ ignored, so that a write past the limit fails with `EFBIG` as on
//! a full disk), and inspects what is left.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use geosph_io::PvdCollection;
use vtkio::model::{DataSet, Piece, Vtk};

/// Exit code of a child whose run returned an error (`tests/src/bin/integrity-child.rs`).
const RUN_FAILED: i32 = 3;

/// The helper binary `integrity-child` running the scene `kind` (`long`: killed; `small`: runs
/// into the file-size limit) into `out`; started by itself or, with `wrapper` (e.g.
/// `["bash", "-c", script]`), by a program that then execs it.
fn child_command(wrapper: &[&str], out: &Path, kind: &str) -> Command {
    let child = env!("CARGO_BIN_EXE_integrity-child");
    let mut command = match wrapper.split_first() {
        Some((program, args)) => {
            let mut command = Command::new(program);
            command.args(args).arg(child);
            command
        }
        None => Command::new(child),
    };
    command
        .arg(out)
        .arg(kind)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    command
}

fn scratch(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// Checks that `text` is well-formed XML as far as a `.pvd` needs: one optional `<?xml … ?>`
/// declaration, then properly nested and closed elements with quoted attributes, nothing
/// after the root element.
fn check_xml(text: &str) -> Result<(), String> {
    let mut open: Vec<&str> = Vec::new();
    let mut rest = text;
    let mut roots = 0;
    if let Some(after) = rest.strip_prefix("<?xml") {
        let end = after.find("?>").ok_or("unterminated XML declaration")?;
        rest = &after[end + 2..];
    }
    while let Some(start) = rest.find('<') {
        if open.is_empty() && !rest[..start].trim().is_empty() {
            return Err(format!(
                "text outside the root element: {:?}",
                &rest[..start]
            ));
        }
        let tag_end = rest[start..].find('>').ok_or("unterminated tag")? + start;
        let tag = &rest[start + 1..tag_end];
        if tag.matches('"').count() % 2 != 0 || tag.matches('\'').count() % 2 != 0 {
            return Err(format!("unbalanced quotes in <{tag}>"));
        }
        if let Some(name) = tag.strip_prefix('/') {
            match open.pop() {
                Some(opened) if opened == name.trim() => {}
                other => return Err(format!("</{name}> closes {other:?}")),
            }
        } else {
            let name = tag
                .split(|c: char| c.is_whitespace() || c == '/')
                .next()
                .unwrap_or("");
            if name.is_empty() {
                return Err(format!("element without a name: <{tag}>"));
            }
            if open.is_empty() {
                roots += 1;
            }
            if !tag.ends_with('/') {
                open.push(name);
            }
        }
        rest = &rest[tag_end + 1..];
    }
    if !open.is_empty() {
        return Err(format!("unclosed elements {open:?}"));
    }
    if roots != 1 || !rest.trim().is_empty() {
        return Err(format!("{roots} root elements, then {rest:?}"));
    }
    Ok(())
}

/// Checks what a stopped run left in `out`; the number of frames the `.pvd` lists.
fn check_output(out: &Path, name: &str) -> Result<usize, String> {
    let pvd = out.join(format!("{name}.pvd"));
    let mut frames = 0;
    if pvd.exists() {
        let text = std::fs::read_to_string(&pvd).map_err(|e| e.to_string())?;
        check_xml(&text).map_err(|e| format!("{}: {e}", pvd.display()))?;
        if !text.contains("<VTKFile type=\"Collection\"") {
            return Err(format!("{} is not a VTK collection", pvd.display()));
        }
        let collection = PvdCollection::open_or_create(&pvd).map_err(|e| e.to_string())?;
        for entry in collection.entries() {
            let file = out.join(&entry.file);
            if entry.file.contains(".tmp") {
                return Err(format!("the .pvd lists a temporary file {}", entry.file));
            }
            let vtk = Vtk::import(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
                return Err(format!("{} is not an unstructured grid", file.display()));
            };
            match pieces.first() {
                Some(Piece::Inline(piece)) if piece.num_points() > 0 => {}
                _ => return Err(format!("{} has no points", file.display())),
            }
        }
        frames = collection.entries().len();
    }
    let csv = out.join("diagnostics.csv");
    if csv.exists() {
        let text = std::fs::read_to_string(&csv).map_err(|e| e.to_string())?;
        if !text.is_empty() && !text.ends_with('\n') {
            return Err("diagnostics.csv ends with a partial row".into());
        }
        let mut lines = text.lines();
        let columns = lines.next().map_or(0, |header| header.split(',').count());
        for (i, line) in lines.enumerate() {
            let values: Vec<&str> = line.split(',').collect();
            if values.len() != columns || values.iter().any(|v| v.parse::<f64>().is_err()) {
                return Err(format!(
                    "diagnostics.csv row {} is incomplete: {line}",
                    i + 1
                ));
            }
        }
    }
    Ok(frames)
}

#[test]
fn sigkill_at_any_moment_leaves_complete_frames_and_a_valid_pvd() {
    let folder = scratch("integrity-sigkill");
    // Kill moments in ms after the start: during start-up, the first frames, and later.
    let delays = [0, 20, 70, 150, 260, 410, 630, 900, 1250];
    let mut listed = Vec::new();
    for (k, delay) in delays.into_iter().enumerate() {
        let out = folder.join(format!("kill-{k}"));
        let mut child = child_command(&[], &out, "long").spawn().unwrap();
        let started = Instant::now();
        std::thread::sleep(Duration::from_millis(delay));
        let still_running = child.try_wait().unwrap().is_none();
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        assert!(
            still_running,
            "the child ended by itself within {:?}",
            started.elapsed()
        );
        match check_output(&out, "dam-break-2d") {
            Ok(frames) => listed.push(frames),
            Err(problem) => panic!("killed after {delay} ms: {problem}"),
        }
    }
    println!("frames listed at each kill: {listed:?}");
    // The kills must have hit a run in progress, not only its start-up.
    assert!(
        listed.iter().filter(|&&frames| frames >= 3).count() >= 3,
        "{listed:?}"
    );
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn a_write_error_stops_the_run_with_a_message_and_leaves_complete_files() {
    let folder = scratch("integrity-write-error");
    let out = folder.join("out");
    // 64 KiB per file; SIGXFSZ ignored (kept across exec), so writes fail with EFBIG.
    let script = "trap '' XFSZ; ulimit -f 64; exec \"$0\" \"$@\"";
    let output = child_command(&["bash", "-c", script], &out, "small")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(RUN_FAILED), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        errors[0].contains("diagnostics.csv") && errors[0].contains("File too large"),
        "{}",
        errors[0]
    );
    let frames = check_output(&out, "dam-break-2d").unwrap();
    assert!(frames >= 2, "only {frames} frames before the limit");
    let csv = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    assert!(csv.len() <= 64 * 1024 && csv.lines().count() > 100);
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn the_xml_check_can_fail() {
    assert!(check_xml("<?xml version=\"1.0\"?>\n<a><b x=\"1\"/></a>\n").is_ok());
    assert!(check_xml("<a><b x=\"1\"/>").is_err());
    assert!(check_xml("<a><b></a></b>").is_err());
    assert!(check_xml("<a x=\"1></a>").is_err());
    assert!(check_xml("<a></a><a></a>").is_err());
}
