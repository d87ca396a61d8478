//! The error type shared by all output modules.

use std::path::PathBuf;

/// What went wrong while writing (or, for restarts, reading) an output file.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file-system or encoding error while writing or reading `path`.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file the operation was about.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A field of a particle frame does not have one value per point.
    #[error("field `{name}` has {len} values, but the particle set has {points} points")]
    FieldLength {
        /// Name of the offending field.
        name: String,
        /// Number of values in the field.
        len: usize,
        /// Number of points (positions) of the particle set.
        points: usize,
    },
    /// Two fields of a frame share a name but not a type, a field repeats a name within one
    /// particle set, or a field uses a name the writer reserves (`kind`).
    #[error("field `{name}`: {reason}")]
    FieldName {
        /// Name of the offending field.
        name: String,
        /// Why the name is rejected.
        reason: &'static str,
    },
    /// A `.pvd` file could not be understood when reopening it.
    #[error("{}:{line}: {reason}", path.display())]
    PvdSyntax {
        /// The `.pvd` file.
        path: PathBuf,
        /// 1-based line of the `<DataSet` element.
        line: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A CSV row or plot series does not match the shape it must have.
    #[error("{0}")]
    Shape(String),
    /// Drawing a plot failed.
    #[error("{}: plot: {reason}", path.display())]
    Plot {
        /// The PNG file being drawn.
        path: PathBuf,
        /// The plotting library's message.
        reason: String,
    },
}

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
