//! Atomic file replacement: write a temporary file next to the target, `sync_all`, `rename`.
//!
//! On POSIX file systems `rename` within one folder replaces the target atomically, so a reader
//! (ParaView, a restart, a CI check) sees either the old complete file or the new complete
//! file, whatever moment the writing process is killed at. The temporary file is
//! `.<stem>.tmp.<extension>` in the target's folder (hidden, same file system, and keeping the
//! extension for encoders that choose the format by it); a name that does not change between
//! attempts means a run killed mid-write leaves at most one stale temporary file per target,
//! overwritten by the next attempt (and that one target must have one writer at a time). After the rename the folder itself is synced (Unix), so the
//! new name survives a power loss too.

use std::ffi::OsString;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::Error;

/// Writes the file `path` atomically with the bytes `write` produces.
///
/// `write` receives a buffered writer to a temporary file in the same folder; when it returns
/// `Ok`, the data is flushed, synced to disk (`sync_all`) and renamed over `path`. When `write`
/// (or any later step) fails, the temporary file is removed, `path` keeps its previous content
/// and the error is returned with `path` attached.
///
/// ```
/// use std::io::Write;
/// let path = std::env::temp_dir().join(format!("geosph-atomic-doc-{}.txt", std::process::id()));
/// geosph_io::write_atomically(&path, |w| writeln!(w, "complete"))?;
/// assert_eq!(std::fs::read_to_string(&path)?, "complete\n");
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_atomically(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), Error> {
    let path = path.as_ref();
    replace_atomically(path, |temporary| {
        let file = File::create(temporary).map_err(|e| Error::io(path, e))?;
        let mut writer = BufWriter::new(file);
        write(&mut writer)
            .and_then(|()| writer.flush())
            .map_err(|e| Error::io(path, e))
    })
}

/// Replaces the file `path` atomically with a file that `create` writes at a temporary path.
///
/// For writers that insist on opening the file themselves (an image encoder choosing the format
/// by extension): `create` receives the temporary path `.<stem>.tmp.<extension>` in the folder
/// of `path` and must create the complete file there. It is then synced (`sync_all`) and
/// renamed over `path`. On failure the temporary file is removed and `path` is left unchanged.
pub fn replace_atomically(
    path: impl AsRef<Path>,
    create: impl FnOnce(&Path) -> Result<(), Error>,
) -> Result<(), Error> {
    let path = path.as_ref();
    let temporary = temporary_path(path)?;
    let result = create(&temporary).and_then(|()| {
        // Re-open to sync: `create` may have closed the file without syncing it.
        File::options()
            .write(true)
            .open(&temporary)
            .and_then(|file| file.sync_all())
            .and_then(|()| fs::rename(&temporary, path))
            .map_err(|e| Error::io(path, e))
    });
    match result {
        Ok(()) => {
            sync_folder(path);
            Ok(())
        }
        Err(error) => {
            // Best effort: the temporary may not exist if `create` failed early.
            let _ = fs::remove_file(&temporary);
            Err(error)
        }
    }
}

/// The temporary file `.<stem>.tmp.<extension>` next to `path`.
pub(crate) fn temporary_path(path: &Path) -> Result<PathBuf, Error> {
    let invalid = || {
        Error::io(
            path,
            io::Error::new(io::ErrorKind::InvalidInput, "not a path to a file"),
        )
    };
    let stem = path.file_stem().ok_or_else(invalid)?;
    let mut name = OsString::from(".");
    name.push(stem);
    name.push(".tmp");
    if let Some(extension) = path.extension() {
        name.push(".");
        name.push(extension);
    }
    Ok(path.with_file_name(name))
}

/// Syncs the folder holding `path` so that a completed rename is durable (Unix only; errors are
/// ignored because some file systems cannot sync folders and the data itself is already safe).
fn sync_folder(path: &Path) {
    #[cfg(unix)]
    {
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if let Ok(folder) = File::open(folder) {
            let _ = folder.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A fresh empty folder under the system temporary folder, unique per test.
    pub(crate) fn scratch_folder(test: &str) -> PathBuf {
        let folder = std::env::temp_dir().join(format!("geosph-io-{}-{test}", std::process::id()));
        let _ = fs::remove_dir_all(&folder);
        fs::create_dir_all(&folder).unwrap();
        folder
    }

    fn names_in(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(folder)
            .unwrap()
            .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn temporary_path_is_hidden_next_to_target_and_keeps_extension() {
        let path = Path::new("out/frame_000001.vtu");
        assert_eq!(
            temporary_path(path).unwrap(),
            Path::new("out/.frame_000001.tmp.vtu")
        );
        assert_eq!(
            temporary_path(Path::new("series")).unwrap(),
            Path::new(".series.tmp")
        );
        assert!(temporary_path(Path::new("/")).is_err());
    }

    #[test]
    fn write_replaces_content_and_leaves_no_temporary() {
        let folder = scratch_folder("atomic-replace");
        let path = folder.join("energy.txt");
        write_atomically(&path, |w| w.write_all(b"old")).unwrap();
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(names_in(&folder), ["energy.txt"]);
        fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn failing_writer_keeps_old_file_and_removes_temporary() {
        let folder = scratch_folder("atomic-failure");
        let path = folder.join("energy.txt");
        write_atomically(&path, |w| w.write_all(b"complete")).unwrap();
        let error = write_atomically(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("simulated failure"))
        })
        .unwrap_err();
        assert!(error.to_string().contains("energy.txt"), "{error}");
        assert!(error.to_string().contains("simulated failure"), "{error}");
        assert_eq!(fs::read_to_string(&path).unwrap(), "complete");
        assert_eq!(names_in(&folder), ["energy.txt"]);
        fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn missing_folder_is_reported_with_path() {
        let path = std::env::temp_dir().join("geosph-io-no-such-folder/x/energy.txt");
        let error = write_atomically(&path, |w| w.write_all(b"x")).unwrap_err();
        assert!(matches!(&error, Error::Io { path: p, .. } if *p == path));
    }
}
