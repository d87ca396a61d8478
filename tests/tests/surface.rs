//! Free-surface meshes written with the frames (issue 23): a 3D still tank's surface, read
//! back as ParaView reads it, is closed and lies on the water.

use std::path::{Path, PathBuf};

use geosph_core::Vector;
use geosph_geometry::SurfaceMesh;
use geosph_io::PvdCollection;
use geosph_runner::{NoObserver, RunOptions, run};
use geosph_scene::SurfaceSpec;
use vtkio::model::{DataSet, IOBuffer, Piece, VertexNumbers, Vtk};

use crate::wcsph::hydrostatic_scene;

/// The triangles of the `.vtp` surface `file`.
fn read_surface(file: &Path) -> SurfaceMesh {
    let vtk = Vtk::import(file).unwrap();
    let DataSet::PolyData { pieces, .. } = vtk.data else {
        panic!("{} is not polydata", file.display())
    };
    let Some(Piece::Inline(piece)) = pieces.into_iter().next() else {
        panic!("{} has no inline piece", file.display())
    };
    let IOBuffer::F64(points) = piece.points else {
        panic!("points are not f64")
    };
    let Some(VertexNumbers::XML {
        connectivity,
        offsets,
    }) = piece.polys
    else {
        panic!("no polygons")
    };
    assert!(
        offsets
            .iter()
            .enumerate()
            .all(|(k, &o)| o == 3 * (k as u64 + 1))
    );
    let vertices = points
        .chunks(3)
        .map(|p| Vector::<3>::new(p[0], p[1], p[2]))
        .collect();
    let triangles = connectivity
        .chunks(3)
        .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
        .collect();
    SurfaceMesh::new("surface", vertices, triangles).unwrap()
}

#[test]
fn a_still_tanks_free_surface_is_closed_and_lies_on_the_water() {
    // The 3D still tank (0.4 m × 0.4 m, 0.2 m of water, dx = 0.025 m: 2048 particles), WCSPH
    // for 0.2 s, a frame and a surface every 0.1 s. The folder is kept for CI's VTK check.
    let (dx, depth) = (0.025, 0.2);
    let mut scene = hydrostatic_scene(3, dx, depth, 0.2);
    scene.name = "surface-tank".into();
    scene.output.vtk = true;
    scene.output.interval = 0.1;
    scene.output.surface = Some(SurfaceSpec::default());
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("surface-tank");
    let _ = std::fs::remove_dir_all(&out);
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    run(&scene, &options, &mut NoObserver).unwrap();
    let series = PvdCollection::open_or_create(out.join("surface-tank-surface.pvd")).unwrap();
    let times: Vec<f64> = series.entries().iter().map(|e| e.time).collect();
    assert_eq!(times, [0.0, 0.1, 0.2]);
    for entry in series.entries() {
        let surface = read_surface(&out.join(&entry.file));
        surface.check_closed().unwrap();
        let (lo, hi) = surface.bounds();
        let volume = surface.signed_volume();
        println!(
            "t = {} s: {} triangles, z {:.4}…{:.4} m, x {:.4}…{:.4} m, volume {volume:.5} m³ against {:.5}",
            entry.time,
            surface.triangles.len(),
            lo[2],
            hi[2],
            lo[0],
            hi[0],
            0.4 * 0.4 * depth
        );
        // The water fills [0, 0.4]² × [0, 0.2]; its particles sit dx/2 inside each face, so a
        // surface that follows them lies within dx/2 of every face of the water, and its
        // volume within the box grown and shrunk by dx/2 on each of its six faces.
        for k in 0..3 {
            let top = if k == 2 { depth } else { 0.4 };
            assert!(lo[k].abs() < dx / 2.0, "axis {k} from {}", lo[k]);
            assert!((hi[k] - top).abs() < dx / 2.0, "axis {k} to {}", hi[k]);
        }
        let shrunk = (0.4 - dx) * (0.4 - dx) * (depth - dx);
        let grown = (0.4 + dx) * (0.4 + dx) * (depth + dx);
        assert!(volume > shrunk && volume < grown, "volume {volume}");
    }
}

#[test]
fn surface_options_out_of_range_are_refused_naming_the_field() {
    let mut scene = hydrostatic_scene(3, 0.025, 0.2, 0.2);
    scene.output.vtk = true;
    for (spec, expected) in [
        (
            SurfaceSpec {
                support: 10.0,
                ..Default::default()
            },
            "scene field `output.surface.support`: must lie in [1.5, 6], got 10",
        ),
        (
            SurfaceSpec {
                threshold: 1.0,
                ..Default::default()
            },
            "scene field `output.surface.threshold`: must lie in [0.05, 0.95], got 1",
        ),
    ] {
        scene.output.surface = Some(spec);
        let error = scene.validate().unwrap_err().to_string();
        assert!(error.starts_with(expected), "{error}");
    }
    // Without frames there is nothing to draw the surface with.
    scene.output.surface = Some(SurfaceSpec::default());
    scene.output.vtk = false;
    let error = scene.validate().unwrap_err().to_string();
    assert!(
        error
            .starts_with("scene field `output.surface`: free surfaces are written with the frames"),
        "{error}"
    );
}
