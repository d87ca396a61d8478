//! Output of geosph runs: particle frames for ParaView, diagnostics as CSV, plots as PNG.
//!
//! Every file is written atomically (temporary file in the same folder, `sync_all`, `rename`),
//! so a run killed at any moment leaves each output file either in its previous complete state
//! or in its new complete state, never half-written.
//!
//! Modules:
//! - [`atomic`]: [`write_atomically`] and [`replace_atomically`], the write-to-temporary-then-rename
//!   primitive every other module uses.
//! - [`vtu`]: one particle frame (positions and per-particle fields, one or several particle
//!   sets) as a compressed binary VTK XML UnstructuredGrid (`.vtu`) of vertex cells.
//! - [`vtp`]: a triangle surface (a free surface, a mesh) as a compressed binary VTK XML
//!   PolyData (`.vtp`).
//! - [`pvtu`]: [`write_pvtu_sets`], the parallel file (`.pvtu`) of a frame written in pieces,
//!   one `.vtu` per rank of a distributed run, which ParaView opens as one data set.
//! - [`pvd`]: [`PvdCollection`], the VTK Collection (`.pvd`) that lists the `.vtu` frames of a
//!   run with their times, rewritten after every frame and reopened on restart.
//! - [`csv`]: [`CsvSeries`], a time-series CSV writer flushed row by row, and
//!   [`write_csv_atomically`] for whole tables.
//! - [`plot`]: [`line_plot_png`], line plots (simulation) with point markers (reference data),
//!   linear or log–log axes, as PNG.
//!
//! Errors of all modules are one [`Error`] type; every file-system error names its path.
//!
//! # Example
//!
//! Write a 2D frame of three particles with a pressure field and list it in a `.pvd`:
//!
//! ```
//! use geosph_core::{Real, Vector};
//! use geosph_io::{write_vtu, Field, FieldData, Frame, PvdCollection};
//!
//! let dir = std::env::temp_dir().join(format!("geosph-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//!
//! let position = [Vector::<2>::new(0.0, 0.0), Vector::<2>::new(0.1, 0.0), Vector::<2>::new(0.0, 0.1)];
//! let pressure: [Real; 3] = [1.0e3, 2.0e3, 3.0e3];
//! let frame = Frame {
//!     position: &position,
//!     fields: vec![Field { name: "pressure", data: FieldData::Scalar(&pressure) }],
//! };
//! write_vtu(dir.join("frame_000000.vtu"), &frame)?;
//!
//! let mut series = PvdCollection::open_or_create(dir.join("particles.pvd"))?;
//! series.add(0.0, "frame_000000.vtu")?;
//! assert_eq!(series.entries().len(), 1);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod atomic;
pub mod csv;
pub mod plot;
pub mod pvd;
pub mod pvtu;
pub mod reference;
pub mod vtp;
pub mod vtu;

mod error;

pub use atomic::{replace_atomically, write_atomically};
pub use csv::{CsvSeries, write_csv_atomically};
pub use error::Error;
pub use plot::{Axes, PlotSpec, Series, line_plot_png};
pub use pvd::{PvdCollection, PvdEntry};
pub use pvtu::write_pvtu_sets;
pub use reference::{ReferenceCurve, interpolate};
pub use vtp::write_vtp_triangles;
pub use vtu::{Field, FieldData, Frame, write_vtu, write_vtu_sets};

#[cfg(test)]
mod tests {
    use geosph_core::{Real, Tensor3, Vector};

    use super::*;

    /// Writes a small run (frames covering every field type, particle sets, the compressed-block
    /// corner cases, and their `.pvd`) to `$GEOSPH_IO_SAMPLE_DIR`, for `tests/check_vtk.py` to
    /// read with VTK; without the variable, to a scratch folder that is removed.
    #[test]
    fn sample_output_for_vtk_check() {
        let keep = std::env::var_os("GEOSPH_IO_SAMPLE_DIR").map(std::path::PathBuf::from);
        let folder = match &keep {
            Some(folder) => {
                std::fs::create_dir_all(folder).unwrap();
                folder.clone()
            }
            None => atomic::tests::scratch_folder("sample-output"),
        };
        let mut series = PvdCollection::create(folder.join("particles.pvd")).unwrap();
        // 4096 fluid particles alone: arrays of exactly 1 and 3 compressed blocks (32 KiB).
        for (frame, (n, walls)) in [(3, 2), (0, 0), (4096, 0), (5000, 100)]
            .into_iter()
            .enumerate()
        {
            let position: Vec<_> = (0..n)
                .map(|i| Vector::<2>::new((i % 64) as Real * 0.01, (i / 64) as Real * 0.01))
                .collect();
            let velocity: Vec<_> = position
                .iter()
                .map(|x| Vector::<2>::new(-x[1], x[0]))
                .collect();
            let pressure: Vec<_> = position.iter().map(|x| 9810.0 * (1.0 - x[1])).collect();
            let stress: Vec<_> = pressure.iter().map(|p| Tensor3::identity() * -p).collect();
            let id: Vec<_> = (0..n as u32).collect();
            let wall: Vec<_> = (0..walls)
                .map(|i| Vector::<2>::new(i as Real * 0.01, -0.01))
                .collect();
            let fluid = Frame::new(&position)
                .with(Field::scalar("pressure", &pressure))
                .with(Field::vector("velocity", &velocity))
                .with(Field::tensor("stress", &stress))
                .with(Field::integer("id", &id));
            let file = folder.join(format!("frame_{frame:06}.vtu"));
            write_vtu_sets(&file, &[fluid, Frame::new(&wall)]).unwrap();
            series.add(0.1 * frame as Real, &file).unwrap();
        }
        let position = [
            Vector::<3>::new(0.0, 0.0, 0.0),
            Vector::<3>::new(1.0, 2.0, 3.0),
        ];
        let density = [1000.0, 1001.0];
        let frame = Frame::new(&position).with(Field::scalar("density", &density));
        write_vtu(folder.join("single_3d.vtu"), &frame).unwrap();
        assert_eq!(series.entries().len(), 4);
        if keep.is_none() {
            std::fs::remove_dir_all(folder).unwrap();
        }
    }
}
