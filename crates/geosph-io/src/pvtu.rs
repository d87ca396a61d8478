//! A particle frame written in pieces, one `.vtu` per rank of a distributed run, and the
//! parallel file (`.pvtu`) that ParaView opens as one data set.
//!
//! Format: VTK XML `type="PUnstructuredGrid"` (VTK file-format documentation, "Parallel
//! File Formats", <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>):
//! the arrays every piece holds (name, type, components) and the pieces' files, relative to
//! the `.pvtu`'s folder. Each piece is a `.vtu` of [`crate::write_vtu_sets`]; the arrays
//! listed here are those that function writes for the same particle sets, so a piece
//! without particles (a rank that owns none) still declares them.

use std::fmt::Write as _;
use std::path::Path;

use crate::vtu::{KIND_FIELD, union_of_fields};
use crate::{Error, FieldData, Frame, write_atomically};

/// Writes the parallel file `path` listing `pieces` (`.vtu` files relative to the folder of
/// `path`, each written by [`crate::write_vtu_sets`] with particle sets of the same fields as
/// `sets`, which may be any rank's, even empty), atomically. Write it once every piece is
/// complete.
///
/// # Errors
/// As [`crate::write_vtu_sets`] for the fields of `sets`; [`Error::Io`] naming `path`.
pub fn write_pvtu_sets<const D: usize>(
    path: impl AsRef<Path>,
    sets: &[Frame<'_, D>],
    pieces: &[String],
) -> Result<(), Error> {
    let fields = union_of_fields(sets, true)?;
    let active = |wanted: fn(&FieldData<'_, D>) -> bool| {
        fields
            .iter()
            .find(|(_, data)| wanted(data))
            .map(|(name, _)| *name)
    };
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData",
    );
    // The active attributes, as the pieces mark them (the first of each type).
    for (attribute, name) in [
        ("Scalars", active(|d| matches!(d, FieldData::Scalar(_)))),
        ("Vectors", active(|d| matches!(d, FieldData::Vector(_)))),
        ("Tensors", active(|d| matches!(d, FieldData::Tensor(_)))),
    ] {
        if let Some(name) = name {
            let _ = write!(text, " {attribute}=\"{}\"", escape(name));
        }
    }
    text.push_str(">\n");
    let arrays = fields
        .iter()
        .map(|(name, data)| (*name, data.vtk_type(), data.components()))
        .chain([(KIND_FIELD, "UInt32", 1)]);
    for (name, kind, components) in arrays {
        let _ = writeln!(
            text,
            "      <PDataArray type=\"{kind}\" Name=\"{}\" NumberOfComponents=\"{components}\"/>",
            escape(name)
        );
    }
    text.push_str(
        "    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n    <PCells>\n      <PDataArray type=\"UInt64\" Name=\"connectivity\"/>\n      <PDataArray type=\"UInt64\" Name=\"offsets\"/>\n      <PDataArray type=\"UInt8\" Name=\"types\"/>\n    </PCells>\n",
    );
    for piece in pieces {
        let _ = writeln!(text, "    <Piece Source=\"{}\"/>", escape(piece));
    }
    text.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    write_atomically(path.as_ref(), |w| w.write_all(text.as_bytes()))
}

/// `text` with the characters XML reserves in attribute values escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use geosph_core::{Real, Vector};

    use super::*;
    use crate::{Field, write_vtu_sets};

    #[test]
    fn the_parallel_file_lists_every_array_and_piece() {
        let dir = crate::atomic::tests::scratch_folder("pvtu");
        let position = [Vector::<2>::new(0.0, 0.0), Vector::<2>::new(0.1, 0.0)];
        let density: [Real; 2] = [1000.0, 1001.0];
        let id = [0u32, 1];
        let walls = [Vector::<2>::new(0.0, -0.1)];
        let sets = |n: usize| {
            [
                Frame::new(&position[..n])
                    .with(Field::scalar("density", &density[..n]))
                    .with(Field::vector("velocity", &position[..n]))
                    .with(Field::integer("id", &id[..n])),
                Frame::new(&walls[..n.min(1)]),
            ]
        };
        // Two pieces, the second without particles.
        write_vtu_sets(dir.join("pieces_0.vtu"), &sets(2)).unwrap();
        write_vtu_sets(dir.join("pieces_1.vtu"), &sets(0)).unwrap();
        let pieces = ["pieces_0.vtu".to_owned(), "pieces_1.vtu".to_owned()];
        write_pvtu_sets(dir.join("pieces.pvtu"), &sets(0), &pieces).unwrap();
        let text = std::fs::read_to_string(dir.join("pieces.pvtu")).unwrap();
        for wanted in [
            r#"<PPointData Scalars="density" Vectors="velocity">"#,
            r#"<PDataArray type="Float64" Name="velocity" NumberOfComponents="3"/>"#,
            r#"<PDataArray type="UInt32" Name="id" NumberOfComponents="1"/>"#,
            r#"<PDataArray type="UInt32" Name="kind" NumberOfComponents="1"/>"#,
            r#"<Piece Source="pieces_1.vtu"/>"#,
        ] {
            assert!(text.contains(wanted), "{wanted} in\n{text}");
        }
        if let Ok(sample) = std::env::var("GEOSPH_IO_SAMPLE_DIR") {
            let sample = Path::new(&sample);
            std::fs::create_dir_all(sample).unwrap();
            for file in ["pieces_0.vtu", "pieces_1.vtu", "pieces.pvtu"] {
                std::fs::copy(dir.join(file), sample.join(file)).unwrap();
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
