//! The time series of a run as a VTK Collection file (`.pvd`), which ParaView opens as one
//! animated data set.
//!
//! Format: VTK XML `type="Collection"` (ParaView's PVD reader; described in the VTK file-format
//! documentation, <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>, and
//! the ParaView wiki "ParaView/Data formats"):
//!
//! ```xml
//! <?xml version="1.0"?>
//! <VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
//!   <Collection>
//!     <DataSet timestep="0.5" group="" part="0" file="frame_000001.vtu"/>
//!   </Collection>
//! </VTKFile>
//! ```
//!
//! [`PvdCollection`] rewrites the whole file atomically after each added frame, so a killed run
//! leaves a valid `.pvd` that lists every frame added before the kill. The file names are
//! relative to the `.pvd`'s folder, so an output folder can be moved or copied as a whole.

use std::borrow::Cow;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use geosph_core::Real;

use crate::{Error, write_atomically};

/// One frame of a collection: a simulation time and a data file.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    /// Simulation time of the frame (the `timestep` attribute, which ParaView shows as time).
    pub time: Real,
    /// Data file (`.vtu`), relative to the folder of the `.pvd`, with `/` separators.
    pub file: String,
}

/// A `.pvd` file and the frames it lists, kept in memory and rewritten on every change.
#[derive(Clone, Debug)]
pub struct PvdCollection {
    path: PathBuf,
    entries: Vec<PvdEntry>,
    /// Reused text of the file, so that rewriting allocates only when the file grows.
    text: String,
}

impl PvdCollection {
    /// Starts a new, empty collection at `path` and writes it (replacing any existing file).
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, Error> {
        let mut collection = Self {
            path: path.into(),
            entries: Vec::new(),
            text: String::new(),
        };
        collection.rewrite()?;
        Ok(collection)
    }

    /// Reopens the collection at `path` with the entries it lists (for a restart), or creates
    /// an empty one when `path` does not exist.
    ///
    /// # Errors
    /// [`Error::Io`] when the file exists but cannot be read; [`Error::PvdSyntax`] when a
    /// `<DataSet` element lacks a `timestep` or `file` attribute or its time is not a number.
    pub fn open_or_create(path: impl Into<PathBuf>) -> Result<Self, Error> {
        let path = path.into();
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                let entries = parse(&path, &text)?;
                Ok(Self {
                    path,
                    entries,
                    text,
                })
            }
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => Self::create(path),
            Err(error) => Err(Error::io(path, error)),
        }
    }

    /// Path of the `.pvd` file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The frames listed, in the order they were added.
    pub fn entries(&self) -> &[PvdEntry] {
        &self.entries
    }

    /// Lists the data file `file` at simulation time `time` and rewrites the `.pvd`.
    ///
    /// Add a frame only after its data file is completely written. `file` is stored relative to
    /// the `.pvd`'s folder: a path inside that folder (e.g. `output_folder.join("frame.vtu")`)
    /// is made relative, any other path is stored as given.
    pub fn add(&mut self, time: Real, file: impl AsRef<Path>) -> Result<(), Error> {
        let file = file.as_ref();
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let relative = file.strip_prefix(folder).unwrap_or(file);
        let file = relative
            .components()
            .map(|part| part.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        self.entries.push(PvdEntry { time, file });
        self.rewrite()
    }

    /// Drops the frames later than `time` and rewrites the `.pvd`; for a restart from a
    /// checkpoint at `time`, whose later frames will be written again.
    pub fn truncate_after(&mut self, time: Real) -> Result<(), Error> {
        self.entries.retain(|entry| entry.time <= time);
        self.rewrite()
    }

    /// Writes the collection to its path, atomically.
    fn rewrite(&mut self) -> Result<(), Error> {
        self.text.clear();
        format(&self.entries, &mut self.text);
        let text = &self.text;
        write_atomically(&self.path, |w| w.write_all(text.as_bytes()))
    }
}

/// Appends the `.pvd` text listing `entries` to `text`.
fn format(entries: &[PvdEntry], text: &mut String) {
    text.push_str(concat!(
        "<?xml version=\"1.0\"?>\n",
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n",
        "  <Collection>\n",
    ));
    for entry in entries {
        // `{:?}` is the shortest text that parses back to the same f64 (with an exponent for
        // very large or small values), which VTK's `strtod` reads.
        let _ = writeln!(
            text,
            "    <DataSet timestep=\"{:?}\" group=\"\" part=\"0\" file=\"{}\"/>",
            entry.time,
            escape(&entry.file)
        );
    }
    text.push_str("  </Collection>\n</VTKFile>\n");
}

/// Reads the entries of `.pvd` text: every `<DataSet …/>` element's `timestep` and `file`.
fn parse(path: &Path, text: &str) -> Result<Vec<PvdEntry>, Error> {
    let mut entries = Vec::new();
    for (start, _) in text.match_indices("<DataSet") {
        let element = &text[start..];
        let element = &element[..element.find('>').unwrap_or(element.len())];
        let syntax = |reason: String| Error::PvdSyntax {
            path: path.to_path_buf(),
            line: text[..start].lines().count() + 1,
            reason,
        };
        let attribute = |name: &str| {
            attribute(element, name)
                .ok_or_else(|| syntax(format!("<DataSet> without a `{name}` attribute")))
        };
        let time = attribute("timestep")?;
        let time = time
            .trim()
            .parse()
            .map_err(|_| syntax(format!("timestep `{time}` is not a number")))?;
        let file = attribute("file")?.into_owned();
        entries.push(PvdEntry { time, file });
    }
    Ok(entries)
}

/// The unescaped value of attribute `name` in the start tag `element` (quoted with `"` or `'`).
fn attribute<'t>(element: &'t str, name: &str) -> Option<Cow<'t, str>> {
    let mut rest = element;
    while let Some(at) = rest.find(name) {
        let preceded_by_space = rest[..at].ends_with(char::is_whitespace);
        rest = &rest[at + name.len()..];
        let after_equals = rest.trim_start().strip_prefix('=').map(str::trim_start);
        if let (true, Some(value)) = (preceded_by_space, after_equals) {
            let quote = value.chars().next().filter(|c| *c == '"' || *c == '\'')?;
            let value = &value[1..];
            return Some(unescape(&value[..value.find(quote)?]));
        }
    }
    None
}

/// `text` with the five XML special characters escaped.
fn escape(text: &str) -> Cow<'_, str> {
    if !text.contains(['&', '<', '>', '"', '\'']) {
        return Cow::Borrowed(text);
    }
    let mut escaped = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            c => escaped.push(c),
        }
    }
    Cow::Owned(escaped)
}

/// Reverses [`escape`] (the five predefined XML entities; others are kept as written).
fn unescape(text: &str) -> Cow<'_, str> {
    if !text.contains('&') {
        return Cow::Borrowed(text);
    }
    let mut plain = text.to_owned();
    for (entity, c) in [
        ("&lt;", "<"),
        ("&gt;", ">"),
        ("&quot;", "\""),
        ("&apos;", "'"),
        ("&amp;", "&"),
    ] {
        plain = plain.replace(entity, c);
    }
    Cow::Owned(plain)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::scratch_folder;

    #[test]
    fn three_frames_are_listed_and_parse_back() {
        let folder = scratch_folder("pvd-three");
        let path = folder.join("particles.pvd");
        let mut collection = PvdCollection::create(&path).unwrap();
        let times = [0.0, 0.1, 2.5e-7];
        for (i, time) in times.into_iter().enumerate() {
            collection
                .add(time, folder.join(format!("frame_{i:06}.vtu")))
                .unwrap();
        }
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\""));
        assert!(text.ends_with("</Collection>\n</VTKFile>\n"));
        assert_eq!(text.matches("<DataSet ").count(), 3);
        assert!(text.contains("timestep=\"0.1\" group=\"\" part=\"0\" file=\"frame_000001.vtu\""));

        let reopened = PvdCollection::open_or_create(&path).unwrap();
        assert_eq!(reopened.entries(), collection.entries());
        assert_eq!(reopened.entries()[2].time, 2.5e-7);
        assert_eq!(reopened.entries()[2].file, "frame_000002.vtu");
        std::fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn restart_appends_after_truncation() {
        let folder = scratch_folder("pvd-restart");
        let path = folder.join("particles.pvd");
        let mut collection = PvdCollection::open_or_create(&path).unwrap();
        assert!(collection.entries().is_empty());
        for i in 0..4 {
            collection.add(i as Real, format!("frame_{i}.vtu")).unwrap();
        }
        let mut restarted = PvdCollection::open_or_create(&path).unwrap();
        restarted.truncate_after(1.0).unwrap();
        restarted.add(2.0, "sub/frame_2b.vtu").unwrap();
        let files: Vec<_> = PvdCollection::open_or_create(&path)
            .unwrap()
            .entries()
            .iter()
            .map(|entry| entry.file.clone())
            .collect();
        assert_eq!(files, ["frame_0.vtu", "frame_1.vtu", "sub/frame_2b.vtu"]);
        std::fs::remove_dir_all(folder).unwrap();
    }

    #[test]
    fn parse_accepts_other_writers_and_reports_bad_elements() {
        let path = Path::new("other.pvd");
        let text = "<VTKFile type='Collection'>\n<Collection>\n\
            <DataSet part='0' file='a&amp;b.vtu' timestep='1e-3'/><DataSet timestep=\"2\"\n\
            file=\"c.vtu\"></DataSet>\n</Collection></VTKFile>";
        let entries = parse(path, text).unwrap();
        assert_eq!(
            entries,
            [
                PvdEntry {
                    time: 1e-3,
                    file: "a&b.vtu".into()
                },
                PvdEntry {
                    time: 2.0,
                    file: "c.vtu".into()
                }
            ]
        );
        let error = parse(path, "<Collection>\n\n<DataSet file=\"x.vtu\"/>").unwrap_err();
        assert!(matches!(error, Error::PvdSyntax { line: 3, .. }), "{error}");
        let error = parse(path, "<DataSet timestep=\"soon\" file=\"x.vtu\"/>").unwrap_err();
        assert!(error.to_string().contains("soon"), "{error}");
    }

    #[test]
    fn file_names_are_escaped() {
        let mut text = String::new();
        let entries = [PvdEntry {
            time: 1.0,
            file: "a<b>&\"c\".vtu".into(),
        }];
        format(&entries, &mut text);
        assert!(text.contains("file=\"a&lt;b&gt;&amp;&quot;c&quot;.vtu\""));
        assert_eq!(parse(Path::new("x.pvd"), &text).unwrap(), entries);
    }
}
