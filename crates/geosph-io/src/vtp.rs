//! Triangle surfaces (free surfaces, meshes) as VTK XML PolyData files (`.vtp`) for ParaView.
//!
//! Format: the VTK XML file format, type `PolyData` (VTK User's Guide, "VTK File Formats"),
//! encoded by [`vtkio`] as the particle frames are ([`crate::vtu`]): `Float64` points, the
//! triangles as `Polys` (connectivity and offsets), little-endian binary arrays, base64 inline,
//! LZ4-compressed.

use geosph_core::Vector;
use vtkio::model::{Attributes, DataSet, IOBuffer, PolyDataPiece, VertexNumbers};

use crate::Error;
use crate::vtu::write_xml;

/// Writes the triangles `triangles` (indices into `vertices`) to the `.vtp` file `path`,
/// atomically. A surface without vertices is a valid file with no points.
pub fn write_vtp_triangles(
    path: impl AsRef<std::path::Path>,
    vertices: &[Vector<3>],
    triangles: &[[u32; 3]],
) -> Result<(), Error> {
    let path = path.as_ref();
    let points: Vec<f64> = vertices.iter().flat_map(|v| [v[0], v[1], v[2]]).collect();
    let piece = PolyDataPiece {
        points: IOBuffer::F64(points),
        verts: None,
        lines: None,
        polys: Some(VertexNumbers::XML {
            connectivity: triangles.iter().flatten().map(|&v| u64::from(v)).collect(),
            offsets: (1..=triangles.len() as u64).map(|t| 3 * t).collect(),
        }),
        strips: None,
        data: Attributes::new(),
    };
    let empty = vertices.is_empty().then_some(
        r#"NumberOfPoints="0" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="0""#,
    );
    write_xml(path, DataSet::inline(piece), empty)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_is_written_with_its_points_and_triangles() {
        let dir = std::env::temp_dir().join(format!("geosph-vtp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let vertices = [
            Vector::<3>::zeros(),
            Vector::<3>::x(),
            Vector::<3>::y(),
            Vector::<3>::z(),
        ];
        let triangles = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let path = dir.join("tetrahedron.vtp");
        write_vtp_triangles(&path, &vertices, &triangles).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(r#"type="PolyData""#), "{text}");
        assert!(text.contains(r#"NumberOfPoints="4""#), "{text}");
        assert!(text.contains(r#"NumberOfPolys="4""#), "{text}");
        let empty = dir.join("empty.vtp");
        write_vtp_triangles(&empty, &[], &[]).unwrap();
        let text = std::fs::read_to_string(&empty).unwrap();
        assert!(text.contains(r#"NumberOfPolys="0""#), "{text}");
        if let Ok(sample) = std::env::var("GEOSPH_IO_SAMPLE_DIR") {
            std::fs::create_dir_all(&sample).unwrap();
            std::fs::copy(&path, std::path::Path::new(&sample).join("tetrahedron.vtp")).unwrap();
            std::fs::copy(&empty, std::path::Path::new(&sample).join("empty.vtp")).unwrap();
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
