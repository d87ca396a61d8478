//! The output folder of a run.

use std::ops::Range;
use std::path::{Path, PathBuf};

use geosph_core::{Particles, Real, Vector};
use geosph_io::{
    CsvSeries, Error, Field, Frame, PvdCollection, write_pvtu_sets, write_vtp_triangles,
    write_vtu_sets,
};
use geosph_sph::Solver;
use geosph_surface::SurfaceParameters;

/// Frames (`frames/<name>_NNNNNN.vtu`), their series `<name>.pvd` and `diagnostics.csv` in one
/// folder; with free surfaces on, a surface per frame (`frames/<name>-surface_NNNNNN.vtp`)
/// and its series `<name>-surface.pvd`. Every file is written atomically, so a killed run
/// leaves only complete files.
pub struct RunOutput {
    dir: PathBuf,
    name: String,
    pvd: Option<PvdCollection>,
    surfaces: Option<(SurfaceParameters, PvdCollection)>,
    csv: CsvSeries,
    frames: usize,
}

/// Columns of `diagnostics.csv` that every run writes, before the observer's; `escaped` is
/// the number of particles that have left the domain so far.
pub const DIAGNOSTIC_COLUMNS: [&str; 10] = [
    "time",
    "step",
    "dt",
    "kinetic_energy",
    "density_error_mean",
    "density_error_max",
    "max_speed",
    "iterations",
    "divergence_iterations",
    "escaped",
];

/// The files a run of `scene` writes beside its frames, `<name>.pvd` and `diagnostics.csv`,
/// for an app's closing line: the free-surface series (when `vtk`, the frames, are written),
/// and the probe, water-level and load plots.
pub fn scene_outputs(scene: &geosph_scene::Scene, vtk: bool) -> Vec<String> {
    let output = &scene.output;
    let mut files = Vec::new();
    if vtk && output.surface.is_some() {
        files.push(format!("{}-surface.pvd", scene.name));
    }
    if !output.probes.is_empty() {
        files.push("probes.png".to_owned());
    }
    if !output.heights.is_empty() {
        files.push("heights.png".to_owned());
    }
    if !output.loads.is_empty() {
        files.push("loads.png".to_owned());
    }
    if !scene.bodies.is_empty() {
        files.push("bodies.png".to_owned());
    }
    files
}

/// Checks, without creating anything, that the folder `dir` exists and can be written, or that
/// it can be created: its nearest existing ancestor is a folder in which a file can be made
/// (a probe file is created and removed at once). Returns a one-line reason otherwise.
pub fn check_folder(dir: &Path) -> Result<(), String> {
    let mut existing = dir;
    loop {
        match std::fs::metadata(existing) {
            Ok(metadata) if metadata.is_dir() => break,
            Ok(_) if existing == dir => return Err("exists and is not a folder".into()),
            Ok(_) => {
                return Err(format!(
                    "cannot be created: `{}` is a file, not a folder",
                    existing.display()
                ));
            }
            Err(error)
                if matches!(
                    error.kind(),
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
                ) =>
            {
                existing = match existing.parent() {
                    Some(parent) if !parent.as_os_str().is_empty() => parent,
                    _ if existing != Path::new(".") => Path::new("."),
                    _ => return Err(format!("cannot be created: {error}")),
                }
            }
            Err(error) => return Err(format!("cannot be inspected: {error}")),
        }
    }
    let probe = existing.join(format!(".geosph-write-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(error) if existing == dir => Err(format!("cannot be written: {error}")),
        Err(error) => Err(format!(
            "cannot be created in `{}`: {error}",
            existing.display()
        )),
    }
}

impl RunOutput {
    /// Creates `dir` (and `dir/frames` when `vtk`) and the CSV with `extra_columns`; with
    /// `surface` and `vtk`, a free surface is drawn with every frame.
    pub fn create(
        dir: &Path,
        name: &str,
        vtk: bool,
        surface: Option<SurfaceParameters>,
        extra_columns: &[&str],
    ) -> Result<Self, Error> {
        let frames = dir.join("frames");
        let make = |path: &Path| {
            std::fs::create_dir_all(path).map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })
        };
        make(dir)?;
        let pvd = if vtk {
            make(&frames)?;
            Some(PvdCollection::create(dir.join(format!("{name}.pvd")))?)
        } else {
            None
        };
        let surfaces = match surface.filter(|_| vtk) {
            Some(parameters) => Some((
                parameters,
                PvdCollection::create(dir.join(format!("{name}-surface.pvd")))?,
            )),
            None => None,
        };
        let mut columns: Vec<&str> = DIAGNOSTIC_COLUMNS.to_vec();
        columns.extend_from_slice(extra_columns);
        let csv = CsvSeries::create(dir.join("diagnostics.csv"), &columns)?;
        Ok(Self {
            dir: dir.to_path_buf(),
            name: name.to_owned(),
            pvd,
            surfaces,
            csv,
            frames: 0,
        })
    }

    /// Reopens the output of a run restarted from a checkpoint at `time` after `frames`
    /// frames and `rows` CSV rows: the `.pvd` keeps the frames up to `time` (the later ones
    /// are written again), `diagnostics.csv` its first `rows` rows, both rewritten atomically.
    pub fn resume(
        dir: &Path,
        name: &str,
        vtk: bool,
        surface: Option<SurfaceParameters>,
        extra_columns: &[&str],
        (time, frames, rows): (Real, usize, usize),
    ) -> Result<Self, String> {
        let series = |file: String| {
            let path = dir.join(file);
            let mut pvd = PvdCollection::open_or_create(&path).map_err(|e| e.to_string())?;
            pvd.truncate_after(time).map_err(|e| e.to_string())?;
            if pvd.entries().len() != frames {
                return Err(format!(
                    "`{}` lists {} frames up to t = {time} s, the checkpoint {frames}: restart into the run's own output folder",
                    path.display(),
                    pvd.entries().len()
                ));
            }
            Ok(pvd)
        };
        let pvd = if vtk {
            Some(series(format!("{name}.pvd"))?)
        } else {
            None
        };
        let surfaces = match surface.filter(|_| vtk) {
            Some(parameters) => Some((parameters, series(format!("{name}-surface.pvd"))?)),
            None => None,
        };
        let mut columns: Vec<&str> = DIAGNOSTIC_COLUMNS.to_vec();
        columns.extend_from_slice(extra_columns);
        let path = dir.join("diagnostics.csv");
        let text = std::fs::read_to_string(&path)
            .map_err(|error| format!("`{}`: {error}", path.display()))?;
        let kept: String = text.split_inclusive('\n').take(1 + rows).collect();
        if kept.lines().count() != 1 + rows || !kept.ends_with('\n') {
            return Err(format!(
                "`{}` holds fewer than the checkpoint's {rows} rows: restart into the run's own output folder",
                path.display()
            ));
        }
        geosph_io::write_atomically(&path, |w| w.write_all(kept.as_bytes()))
            .map_err(|e| e.to_string())?;
        let csv = CsvSeries::append_or_create(&path, &columns).map_err(|e| e.to_string())?;
        Ok(Self {
            dir: dir.to_path_buf(),
            name: name.to_owned(),
            pvd,
            surfaces,
            csv,
            frames,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Number of frames written.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Writes the particles (set 0) and the walls of `solver` (set 1) at `time` as the next
    /// frame and adds it to the `.pvd`, and the particles' free surface to its own series
    /// when surfaces are on; does nothing when VTK output is off.
    pub fn write_frame<const D: usize>(
        &mut self,
        time: Real,
        fluid: &Particles<D>,
        solver: &dyn Solver<D>,
    ) -> Result<(), Error> {
        let Some(pvd) = &mut self.pvd else {
            return Ok(());
        };
        let file = format!("frames/{}_{:06}.vtu", self.name, self.frames);
        write_particles(&self.dir.join(&file), fluid, solver)?;
        pvd.add(time, &file)?;
        self.write_surface(time, fluid)?;
        self.frames += 1;
        Ok(())
    }

    /// Lists the frame at `time` that `ranks` ranks wrote in pieces ([`piece_file`]) as the
    /// next one: writes its `.pvtu`, for particle sets with the fields of `sets` (any rank's),
    /// adds it to the `.pvd`, and draws the free surface of `whole` (every particle) when
    /// surfaces are on. Nothing when VTK output is off.
    pub(crate) fn add_pieces<const D: usize>(
        &mut self,
        time: Real,
        sets: &[Frame<'_, D>],
        ranks: usize,
        whole: Option<&Particles<D>>,
    ) -> Result<(), Error> {
        let Some(pvd) = &mut self.pvd else {
            return Ok(());
        };
        let pieces: Vec<String> = (0..ranks)
            .map(|rank| piece_file(&self.name, self.frames, rank))
            .collect();
        let file = format!("frames/{}_{:06}.pvtu", self.name, self.frames);
        write_pvtu_sets(self.dir.join(&file), sets, &pieces)?;
        pvd.add(time, &file)?;
        if let Some(whole) = whole {
            self.write_surface(time, whole)?;
        }
        self.frames += 1;
        Ok(())
    }

    /// The free surface of `fluid` at `time` as the next surface frame, when surfaces are on.
    fn write_surface<const D: usize>(
        &mut self,
        time: Real,
        fluid: &Particles<D>,
    ) -> Result<(), Error> {
        let Some((parameters, series)) = &mut self.surfaces else {
            return Ok(());
        };
        let file = format!("frames/{}-surface_{:06}.vtp", self.name, self.frames);
        let position: Vec<Vector<3>> = fluid
            .position
            .iter()
            .map(|x| Vector::<3>::from_fn(|k, _| if k < D { x[k] } else { 0.0 }))
            .collect();
        let path = self.dir.join(&file);
        let surface =
            geosph_surface::reconstruct(&position, parameters).map_err(|error| Error::Io {
                path: path.clone(),
                source: std::io::Error::other(error.to_string()),
            })?;
        write_vtp_triangles(&path, &surface.vertices, &surface.triangles)?;
        series.add(time, &file)
    }

    /// Writes the particles and the walls of `solver` to `file` in the folder, outside the
    /// series (the frame of an interrupted run), whether or not VTK output is on; returns its
    /// path.
    pub fn write_snapshot<const D: usize>(
        &self,
        file: &str,
        fluid: &Particles<D>,
        solver: &dyn Solver<D>,
    ) -> Result<PathBuf, Error> {
        let path = self.dir.join(file);
        write_particles(&path, fluid, solver)?;
        Ok(path)
    }
}

/// Writes the particles (set 0), with their fields and the quantities `solver` derives from
/// them ([`Solver::output_scalars`]), and the solver's walls (set 1) to the VTU file `path`:
/// the frames of a run, and any state an application wants to show the same way.
///
/// (A distributed run writes each frame in pieces, one per rank, listed by a `.pvtu`:
/// [`piece_file`].)
pub fn write_particles<const D: usize>(
    path: &Path,
    fluid: &Particles<D>,
    solver: &dyn Solver<D>,
) -> Result<(), Error> {
    with_frame_sets(fluid, 0..fluid.len(), solver, &|_| true, |sets| {
        write_vtu_sets(path, sets)
    })
}

/// Calls `write` with the particle sets of a frame: the particles `fluid[particles]` (set 0)
/// with their fields and what `solver` derives from them, and the walls of `solver` for
/// which `wall` holds (set 1); all of them in one process, one rank's piece in a distributed
/// run.
pub(crate) fn with_frame_sets<const D: usize>(
    fluid: &Particles<D>,
    particles: Range<usize>,
    solver: &dyn Solver<D>,
    wall: &dyn Fn(usize) -> bool,
    write: impl FnOnce(&[Frame<'_, D>]) -> Result<(), Error>,
) -> Result<(), Error> {
    let range = particles;
    let walls = solver.walls();
    let chosen: Vec<usize> = (0..walls.len()).filter(|&i| wall(i)).collect();
    let pick = |values: &[Real]| -> Vec<Real> { chosen.iter().map(|&i| values[i]).collect() };
    let wall_position: Vec<Vector<D>> = chosen.iter().map(|&i| walls.position[i]).collect();
    let wall_velocity: Vec<Vector<D>> = chosen.iter().map(|&i| walls.velocity[i]).collect();
    let (wall_density, wall_pressure) = (pick(&walls.density), pick(&walls.pressure));
    let mut fluid_frame = Frame::new(&fluid.position[range.clone()])
        .with(Field::vector("velocity", &fluid.velocity[range.clone()]))
        .with(Field::scalar("density", &fluid.density[range.clone()]))
        .with(Field::integer("id", &fluid.id[range.clone()]));
    if let Some(pressure) = &fluid.pressure {
        fluid_frame = fluid_frame.with(Field::scalar("pressure", &pressure[range.clone()]));
    }
    if let Some(energy) = &fluid.energy {
        fluid_frame = fluid_frame.with(Field::scalar("internal_energy", &energy[range.clone()]));
    }
    // The particles' stress, then what the solver derives from it, then the other soil fields.
    let derived = solver.output_scalars(fluid);
    let soil = fluid.soil.as_ref().map(|fields| {
        let displacement: Vec<Vector<D>> = fields.displacement[range.clone()]
            .iter()
            .map(|u| Vector::<D>::from_fn(|k, _| u[k]))
            .collect();
        (fields, displacement)
    });
    if let Some((fields, _)) = &soil {
        fluid_frame = fluid_frame.with(Field::tensor("stress", &fields.stress[range.clone()]));
    }
    for (name, values) in &derived {
        fluid_frame = fluid_frame.with(Field::scalar(name, &values[range.clone()]));
    }
    if let Some((fields, displacement)) = &soil {
        fluid_frame = fluid_frame
            .with(Field::scalar(
                "plastic_strain",
                &fields.plastic_strain[range.clone()],
            ))
            .with(Field::vector("displacement", displacement));
    }
    let wall_frame = Frame::new(&wall_position)
        .with(Field::vector("velocity", &wall_velocity))
        .with(Field::scalar("density", &wall_density))
        .with(Field::scalar("pressure", &wall_pressure));
    write(&[fluid_frame, wall_frame])
}

/// The file of rank `rank`'s piece of frame `frame` of the run `name` in a distributed run,
/// in the folder `frames` (beside the frame's `.pvtu`, which lists the pieces).
pub fn piece_file(name: &str, frame: usize, rank: usize) -> String {
    format!("{name}_{frame:06}_rank{rank:04}.vtu")
}

impl RunOutput {
    /// Appends a row to `diagnostics.csv`.
    pub fn sample(&mut self, row: &[Real]) -> Result<(), Error> {
        self.csv.push(row)
    }

    /// Flushes the CSV.
    pub fn flush(&mut self) -> Result<(), Error> {
        self.csv.flush()
    }
}
