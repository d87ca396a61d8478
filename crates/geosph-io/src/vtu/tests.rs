//! Round trips through vtkio's reader.

use std::path::Path;

use approx::assert_relative_eq;
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, UnstructuredGridPiece, Vtk};

use super::*;
use crate::atomic::tests::scratch_folder;

/// The single inline piece of the `.vtu` at `path`, read back with vtkio.
fn read_piece(path: &Path) -> UnstructuredGridPiece {
    let vtk = Vtk::import(path).unwrap();
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    assert_eq!(pieces.len(), 1);
    match pieces.remove(0) {
        Piece::Inline(piece) => *piece,
        _ => panic!("piece not inline"),
    }
}

/// Name, number of components and values (as f64) of every point array.
fn point_arrays(piece: &UnstructuredGridPiece) -> Vec<(String, u32, Vec<f64>)> {
    piece
        .data
        .point
        .iter()
        .map(|attribute| match attribute {
            Attribute::DataArray(array) => (
                array.name.clone(),
                array.elem.num_comp(),
                array.data.cast_into::<f64>().unwrap(),
            ),
            Attribute::Field { .. } => panic!("unexpected field attribute"),
        })
        .collect()
}

#[test]
fn frame_2d_round_trips_positions_and_all_field_types() {
    let folder = scratch_folder("vtu-2d");
    let path = folder.join("frame_000001.vtu");
    let position = [Vector::<2>::new(0.5, 1.5), Vector::<2>::new(-2.0, 3.25)];
    let pressure = [101.0, -7.5];
    let velocity = [Vector::<2>::new(1.0, 2.0), Vector::<2>::new(3.0, 4.0)];
    let stress = [
        Tensor3::from_fn(|i, j| (10 * i + j) as Real),
        Tensor3::identity() * -5.0,
    ];
    let id = [7_u32, 3];
    let frame = Frame::new(&position)
        .with(Field::scalar("pressure", &pressure))
        .with(Field::vector("velocity", &velocity))
        .with(Field::tensor("stress", &stress))
        .with(Field::integer("id", &id));
    write_vtu(&path, &frame).unwrap();

    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 2);
    let points = piece.points.cast_into::<f64>().unwrap();
    assert_eq!(points, [0.5, 1.5, 0.0, -2.0, 3.25, 0.0]);
    assert!(matches!(piece.points, IOBuffer::F64(_)));

    let arrays = point_arrays(&piece);
    let names: Vec<_> = arrays.iter().map(|(name, ..)| name.as_str()).collect();
    assert_eq!(names, ["pressure", "velocity", "stress", "id"]);
    let components: Vec<_> = arrays.iter().map(|(_, n, _)| *n).collect();
    assert_eq!(components, [1, 3, 9, 1]);
    assert_eq!(arrays[0].2, pressure);
    assert_eq!(arrays[1].2, [1.0, 2.0, 0.0, 3.0, 4.0, 0.0]);
    // Row-major: xx, xy, xz, yx, ...
    assert_eq!(
        arrays[2].2[..9],
        [0.0, 1.0, 2.0, 10.0, 11.0, 12.0, 20.0, 21.0, 22.0]
    );
    assert_relative_eq!(arrays[2].2[9], -5.0);
    assert_eq!(arrays[3].2, [7.0, 3.0]);
    let Attribute::DataArray(id_array) = &piece.data.point[3] else {
        unreachable!()
    };
    assert!(matches!(id_array.data, IOBuffer::U32(_)));
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn sets_are_concatenated_with_kind_and_missing_fields_filled() {
    let folder = scratch_folder("vtu-sets");
    let path = folder.join("frame.vtu");
    let fluid_position = [
        Vector::<3>::new(0.0, 0.0, 1.0),
        Vector::<3>::new(1.0, 0.0, 1.0),
    ];
    let wall_position = [Vector::<3>::new(0.0, 0.0, 0.0)];
    let pressure = [1.0, 2.0];
    let fluid_id = [0_u32, 1];
    let wall_normal = [Vector::<3>::new(0.0, 0.0, 1.0)];
    let sets = [
        Frame::new(&fluid_position)
            .with(Field::scalar("pressure", &pressure))
            .with(Field::integer("id", &fluid_id)),
        Frame::new(&wall_position).with(Field::vector("normal", &wall_normal)),
    ];
    write_vtu_sets(&path, &sets).unwrap();

    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 3);
    assert_eq!(
        piece.points.cast_into::<f64>().unwrap(),
        [0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    );
    let arrays = point_arrays(&piece);
    let names: Vec<_> = arrays.iter().map(|(name, ..)| name.as_str()).collect();
    assert_eq!(names, ["pressure", "id", "normal", "kind"]);
    assert_eq!(arrays[0].2[..2], [1.0, 2.0]);
    assert!(arrays[0].2[2].is_nan());
    assert_eq!(arrays[1].2, [0.0, 1.0, 0.0]);
    assert!(arrays[2].2[..6].iter().all(|x| x.is_nan()));
    assert_eq!(arrays[2].2[6..], [0.0, 0.0, 1.0]);
    assert_eq!(arrays[3].2, [0.0, 0.0, 1.0]);
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn wrong_field_length_is_an_error_naming_the_field() {
    let folder = scratch_folder("vtu-length");
    let path = folder.join("frame.vtu");
    let position = [Vector::<2>::zeros(); 3];
    let density = [1000.0; 2];
    let frame = Frame::new(&position).with(Field::scalar("density", &density));
    let error = write_vtu(&path, &frame).unwrap_err();
    assert!(matches!(&error, Error::FieldLength { name, len: 2, points: 3 } if name == "density"));
    assert!(error.to_string().contains("`density`"));
    assert!(!path.exists());
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn conflicting_and_reserved_names_are_rejected() {
    let position = [Vector::<2>::zeros()];
    let scalar = [1.0];
    let vector = [Vector::<2>::zeros()];
    let id = [0];
    let path = Path::new("never-written.vtu");
    let twice = Frame::new(&position)
        .with(Field::scalar("p", &scalar))
        .with(Field::scalar("p", &scalar));
    assert!(matches!(
        write_vtu(path, &twice),
        Err(Error::FieldName { .. })
    ));
    let mismatch = [
        Frame::new(&position).with(Field::scalar("p", &scalar)),
        Frame::new(&position).with(Field::vector("p", &vector)),
    ];
    assert!(matches!(
        write_vtu_sets(path, &mismatch),
        Err(Error::FieldName { .. })
    ));
    let reserved = [Frame::new(&position).with(Field::integer("kind", &id))];
    assert!(matches!(
        write_vtu_sets(path, &reserved),
        Err(Error::FieldName { .. })
    ));
    // Without sets, `kind` is an ordinary name.
    let folder = scratch_folder("vtu-kind");
    write_vtu(folder.join("kind.vtu"), &reserved[0]).unwrap();
    std::fs::remove_dir_all(folder).unwrap();
}

/// Array byte sizes that are exact multiples of vtkio's 32 KiB compression block, and an empty
/// frame, are the corner cases of the compressed-block header.
#[test]
fn block_size_multiples_and_empty_frames_round_trip() {
    let folder = scratch_folder("vtu-blocks");
    for n in [0, 1, 4096, 4097, 3 * 4096] {
        let path = folder.join(format!("frame_{n}.vtu"));
        let position: Vec<_> = (0..n).map(|i| Vector::<2>::new(i as Real, 0.5)).collect();
        let density: Vec<_> = (0..n).map(|i| 1000.0 + i as Real).collect();
        write_vtu(
            &path,
            &Frame::new(&position).with(Field::scalar("density", &density)),
        )
        .unwrap();
        let piece = read_piece(&path);
        assert_eq!(piece.num_points(), n, "{n} points");
        assert_eq!(point_arrays(&piece)[0].2, density, "{n} points");
    }
    std::fs::remove_dir_all(folder).unwrap();
}
