//! Diagnostics as comma-separated values (RFC 4180, <https://www.rfc-editor.org/rfc/rfc4180>):
//! a header line of column names, then one line of numbers per row.
//!
//! Numbers are written as the shortest text that parses back to the same `f64` (Rust's `{:?}`
//! format, with an exponent for very large or small values; `NaN`, `inf`), which numpy,
//! pandas and spreadsheet programs read. Column names containing `,`, `"` or line breaks are
//! quoted.
//!
//! [`CsvSeries`] appends rows as a run proceeds and hands complete rows to the operating system
//! (every row, or every `n` rows), so a killed run leaves a file of complete rows up to the
//! last flush. [`write_csv_atomically`] writes a whole table at once, atomically.

use std::fmt::Write as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use geosph_core::Real;

use crate::{Error, write_atomically};

/// A CSV time series written row by row, e.g. time, kinetic energy and front position.
///
/// Rows are formatted into an in-memory buffer and written with one `write_all` per flush, so
/// the file only ever holds whole lines at a flush point. The buffer is flushed every
/// `flush_every` rows (1 unless [`CsvSeries::flush_every`] says otherwise), by
/// [`CsvSeries::flush`] and on drop. Flushing hands data to the operating system, which keeps it
/// when the process is killed; it does not `fsync` (too slow per row).
#[derive(Debug)]
pub struct CsvSeries {
    path: PathBuf,
    file: File,
    columns: usize,
    pending: String,
    pending_rows: usize,
    flush_every: usize,
    /// Length of the file up to its last complete flush; a failed write is cut back to it.
    complete_len: u64,
}

impl CsvSeries {
    /// Creates (or truncates) the file `path` and writes the header line `columns`.
    pub fn create(path: impl Into<PathBuf>, columns: &[&str]) -> Result<Self, Error> {
        let path = path.into();
        let file = File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut series = Self::with_file(path, file, columns.len());
        push_header(&mut series.pending, columns);
        series.flush()?;
        Ok(series)
    }

    /// Opens `path` to append rows after a restart, when its header line is `columns`;
    /// otherwise (no file, or another header) starts it anew as [`CsvSeries::create`] does.
    pub fn append_or_create(path: impl Into<PathBuf>, columns: &[&str]) -> Result<Self, Error> {
        let path = path.into();
        let mut header = String::new();
        push_header(&mut header, columns);
        let matches = match std::fs::read_to_string(&path) {
            // Appending after a partial last line would merge two rows: require a complete one.
            Ok(text) => text.starts_with(&header) && text.ends_with('\n'),
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => false,
            Err(error) => return Err(Error::io(path, error)),
        };
        if !matches {
            return Self::create(path, columns);
        }
        let file = File::options()
            .append(true)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        let complete_len = file.metadata().map_err(|e| Error::io(&path, e))?.len();
        let mut series = Self::with_file(path, file, columns.len());
        series.complete_len = complete_len;
        Ok(series)
    }

    fn with_file(path: PathBuf, file: File, columns: usize) -> Self {
        Self {
            path,
            file,
            columns,
            pending: String::new(),
            pending_rows: 0,
            flush_every: 1,
            complete_len: 0,
        }
    }

    /// Flushes after every `rows` rows instead of after each row (builder style; 0 counts as 1).
    pub fn flush_every(mut self, rows: usize) -> Self {
        self.flush_every = rows.max(1);
        self
    }

    /// Path of the CSV file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends one row, flushing when `flush_every` rows are pending.
    ///
    /// # Errors
    /// [`Error::Shape`] when `row` does not have one value per column (nothing is written);
    /// [`Error::Io`] when flushing fails.
    pub fn push(&mut self, row: &[Real]) -> Result<(), Error> {
        check_row(&self.path, self.columns, row)?;
        push_row(&mut self.pending, row);
        self.pending_rows += 1;
        if self.pending_rows >= self.flush_every {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes all pending rows to the file.
    ///
    /// # Errors
    /// [`Error::Io`] when the write fails (a full disk, a file-size limit): the part of the
    /// rows that reached the file is cut off again, so the file ends with its last complete
    /// row, and the pending rows are dropped.
    pub fn flush(&mut self) -> Result<(), Error> {
        if !self.pending.is_empty() {
            let written = self.file.write_all(self.pending.as_bytes());
            let length = self.pending.len() as u64;
            self.pending.clear();
            self.pending_rows = 0;
            if let Err(error) = written {
                // Best effort: the file may not even accept truncation.
                let _ = self.file.set_len(self.complete_len);
                return Err(Error::io(&self.path, error));
            }
            self.complete_len += length;
        }
        self.pending_rows = 0;
        Ok(())
    }
}

impl Drop for CsvSeries {
    fn drop(&mut self) {
        // Errors cannot be returned from drop; call `flush` first to see them.
        let _ = self.flush();
    }
}

/// Writes the table `columns` + `rows` to `path` atomically (all or nothing).
///
/// # Errors
/// [`Error::Shape`] when a row does not have one value per column; [`Error::Io`] when writing
/// fails. In both cases `path` keeps its previous content.
pub fn write_csv_atomically<R: AsRef<[Real]>>(
    path: impl AsRef<Path>,
    columns: &[&str],
    rows: impl IntoIterator<Item = R>,
) -> Result<(), Error> {
    let path = path.as_ref();
    let mut text = String::new();
    push_header(&mut text, columns);
    for row in rows {
        check_row(path, columns.len(), row.as_ref())?;
        push_row(&mut text, row.as_ref());
    }
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

fn check_row(path: &Path, columns: usize, row: &[Real]) -> Result<(), Error> {
    if row.len() == columns {
        Ok(())
    } else {
        Err(Error::Shape(format!(
            "{}: row of {} values for {columns} columns",
            path.display(),
            row.len()
        )))
    }
}

fn push_header(text: &mut String, columns: &[&str]) {
    for (i, name) in columns.iter().enumerate() {
        if i > 0 {
            text.push(',');
        }
        if name.contains([',', '"', '\n', '\r']) {
            text.push('"');
            text.push_str(&name.replace('"', "\"\""));
            text.push('"');
        } else {
            text.push_str(name);
        }
    }
    text.push('\n');
}

fn push_row(text: &mut String, row: &[Real]) {
    for (i, value) in row.iter().enumerate() {
        if i > 0 {
            text.push(',');
        }
        let _ = write!(text, "{value:?}");
    }
    text.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::scratch_folder;

    /// `/dev/full` fails every write with "no space left on device": a full disk.
    #[test]
    #[cfg(target_os = "linux")]
    fn a_full_disk_is_an_error_naming_the_file() {
        let path = Path::new("/dev/full");
        if !path.exists() {
            return;
        }
        let error = CsvSeries::create(path, &["time", "energy"]).unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with("/dev/full: "), "{message}");
        assert!(matches!(&error, Error::Io { source, .. } if source.raw_os_error() == Some(28)));
    }

    #[test]
    fn series_writes_header_and_rows_flushed_each_row() {
        let folder = scratch_folder("csv-series");
        let path = folder.join("energy.csv");
        let mut series = CsvSeries::create(&path, &["time", "kinetic energy", "a,b"]).unwrap();
        series.push(&[0.0, 1.5, -2.0]).unwrap();
        series.push(&[1e-7, 1e20, Real::NAN]).unwrap();
        // Flushed without dropping.
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "time,kinetic energy,\"a,b\"\n0.0,1.5,-2.0\n1e-7,1e20,NaN\n"
        );
        assert!(matches!(series.push(&[1.0]), Err(Error::Shape(_))));
        drop(series);
        std::fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn batched_rows_are_written_on_drop_and_appended_after_restart() {
        let folder = scratch_folder("csv-batched");
        let path = folder.join("front.csv");
        let mut series = CsvSeries::create(&path, &["t", "x"])
            .unwrap()
            .flush_every(10);
        series.push(&[0.0, 1.0]).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,x\n");
        drop(series);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,x\n0.0,1.0\n");

        let mut series = CsvSeries::append_or_create(&path, &["t", "x"]).unwrap();
        series.push(&[0.5, 2.0]).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "t,x\n0.0,1.0\n0.5,2.0\n"
        );
        // Another header starts the file anew.
        drop(CsvSeries::append_or_create(&path, &["t", "y"]).unwrap());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,y\n");
        std::fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn table_is_written_atomically_or_not_at_all() {
        let folder = scratch_folder("csv-table");
        let path = folder.join("profile.csv");
        write_csv_atomically(&path, &["z", "p"], [[0.0, 9810.0], [1.0, 0.0]]).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "z,p\n0.0,9810.0\n1.0,0.0\n"
        );
        let rows = vec![vec![0.0, 1.0], vec![2.0]];
        assert!(write_csv_atomically(&path, &["z", "p"], &rows).is_err());
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "z,p\n0.0,9810.0\n1.0,0.0\n"
        );
        std::fs::remove_dir_all(folder).unwrap();
    }
}
