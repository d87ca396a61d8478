//! The slope-failure application: runs a soil scene (by default the granular column collapse of
//! Bui et al. 2008) with the geosph runner, tracks the runout front and the height of the soil at
//! the back wall, and writes `runout.csv`, `runout.png` (front and wall height against time),
//! `deposit.csv` (the final position and displacement of every soil particle, by id) and
//! `deposit.png` (initial and final surface profiles, with the experiment's surface and failure
//! line when the scene is the set-up of Bui et al. 2008, see [`bui2008`], and the run-out and
//! final height of the laws of Nguyen et al. 2015 for any column of the same bars, see
//! [`nguyen2015`]) next to the runner's VTU frames.
//!
//! The column is the scene's first soil block (a box) with its back wall at the box's lower x;
//! the soil runs out towards +x. A 3D scene whose first soil block is not a box (a cylinder
//! from a mesh) is measured about the soil's vertical axis instead ([`axisymmetric`]).
//! `main.rs` is a thin command line around [`run`], the factor-of-safety search
//! ([`factor_of_safety`]) and the aspect-ratio series ([`aspect_ratios`]).
#![warn(missing_docs)]

use geosph_core::{Particles, Real};
use geosph_runner::{Observer, RunOptions, push_records, take_records};
use geosph_scene::{Region, Scene};

pub mod aspect_ratios;
pub mod axisymmetric;
pub mod bui2008;
pub mod factor_of_safety;
pub mod nguyen2015;
mod output;
mod report;

pub use output::surface_profile;
use output::write_outputs;

pub use bui2008::ExperimentComparison;
pub use nguyen2015::AspectRatioComparison;
pub use report::Report;

/// The embedded default scene (`data/scenes/granular-collapse.ron`).
pub const DEFAULT_SCENE: &str = include_str!("../../../data/scenes/granular-collapse.ron");

/// The slope of Griffiths & Lane (1999) for `--factor-of-safety`
/// (`data/scenes/homogeneous-slope.ron`; not a column, so not a scene [`run`] can measure).
pub const SLOPE_SCENE: &str = include_str!("../../../data/scenes/homogeneous-slope.ron");

/// The shipped scenes, by file name (also registered in the scene crate's parse test).
pub const SCENES: [(&str, &str); 3] = [
    ("granular-collapse.ron", DEFAULT_SCENE),
    (
        "tall-column.ron",
        include_str!("../../../data/scenes/tall-column.ron"),
    ),
    (
        "cohesive-slope.ron",
        include_str!("../../../data/scenes/cohesive-slope.ron"),
    ),
];

/// Errors of a slope-failure run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene is not one this app can measure.
    #[error("scene: {0}")]
    Scene(String),
    /// The run failed.
    #[error(transparent)]
    Run(#[from] geosph_runner::RunError),
    /// Writing the app's own output failed.
    #[error(transparent)]
    Output(#[from] geosph_io::Error),
}

/// The initial soil column: back wall, length and height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Column {
    /// x of the back wall (the column's left face).
    pub wall: Real,
    /// Height of the column's base (the floor it stands on).
    pub base: Real,
    /// Initial length L (along x).
    pub length: Real,
    /// Initial height H.
    pub height: Real,
    /// Extent across the runout direction (y in 3D; 1 m, unit depth, in 2D).
    pub breadth: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// Number of dimensions.
    pub dimension: usize,
    /// In plane strain: a 2D scene, or a 3D slab whose domain is periodic across y with every
    /// soil block a box across the whole period (no side walls, no motion across y but what
    /// the flow itself makes), which the plane-strain experiments are compared with.
    pub plane_strain: bool,
}

impl Column {
    /// The column of `scene`: its first soil block, which must be a box.
    pub fn of(scene: &Scene) -> Result<Self, Error> {
        let soil = scene
            .fluid
            .as_ref()
            .ok_or_else(|| Error::Scene("the scene has no soil block".into()))?;
        let Some(Region::Box { min, max }) = soil.blocks.first() else {
            return Err(Error::Scene(
                "the first soil block must be a Box (the column whose runout this app measures; \
                 `slope-failure` runs other shapes without runout measures, and searches their \
                 factor of safety with --factor-of-safety)"
                    .into(),
            ));
        };
        let up = scene.dimension - 1;
        Ok(Self {
            wall: min[0],
            base: min[up],
            length: max[0] - min[0],
            height: max[up] - min[up],
            breadth: if scene.dimension == 3 {
                max[1] - min[1]
            } else {
                1.0
            },
            spacing: scene.dx,
            dimension: scene.dimension,
            plane_strain: scene.dimension == 2 || spans_a_period_across_y(scene, &soil.blocks),
        })
    }

    /// The deposit toe (the runout), measured from the back wall, of particles at `x` (along
    /// the runout direction) sorted in descending order: [`Column::toe`] with a layer
    /// [`TOE_THICKNESS`] × H thick.
    ///
    /// The foremost particles of a collapse are a sparse layer about one particle thick whose
    /// length grows as dx shrinks; this toe belongs to the deposit, a thickness in metres
    /// rather than in particles, so it is comparable between resolutions.
    pub fn deposit_toe(&self, x_descending: &[Real]) -> Real {
        self.toe(x_descending, TOE_THICKNESS * self.height)
    }

    /// The grain toe: [`Column::toe`] with a layer [`GRAIN_THICKNESS`] thick, where the
    /// deposit thins to one grain of the aluminium bars, or one particle layer (dx) thick
    /// when dx is coarser than a grain (a particle stands for soil dx thick, and a lone
    /// particle is not a deposit). Compared with the maximum run-out of the experiments of
    /// Nguyen, Bui & Fukagawa (2015).
    pub fn grain_toe(&self, x_descending: &[Real]) -> Real {
        self.toe(x_descending, GRAIN_THICKNESS.max(self.spacing))
    }

    /// The front edge (x + dx/2), measured from the back wall, of the foremost particle that
    /// has, within a distance b = H/10 behind it, enough soil for a layer `thickness` thick,
    /// i.e. at least ⌈thickness · b · B / dx^D⌉ particles (itself included; B the breadth,
    /// dx^D the volume of a particle); `x_descending` sorted in descending order. Zero if no
    /// particle qualifies.
    pub fn toe(&self, x_descending: &[Real], thickness: Real) -> Real {
        let window = 0.1 * self.height;
        let particle_volume = self.spacing.powi(self.dimension as i32);
        let needed = (thickness * window * self.breadth / particle_volume - 1e-9)
            .ceil()
            .max(1.0) as usize;
        x_descending
            .windows(needed)
            .find(|group| group[0] - group[needed - 1] <= window)
            .map_or(0.0, |group| group[0] + 0.5 * self.spacing - self.wall)
    }
}

/// Whether the scene's domain is periodic across y and every soil block is a box spanning that
/// period: a 3D slab in plane strain (a block narrower than the period would be a row of
/// separate columns).
fn spans_a_period_across_y(scene: &Scene, blocks: &[Region]) -> bool {
    let Some(domain) = scene.domain.as_ref() else {
        return false;
    };
    let close = |a: Real, b: Real| (a - b).abs() <= 1e-9 * scene.dx;
    domain.periodic.get(1) == Some(&true)
        && blocks.iter().all(|block| match block {
            Region::Box { min, max } => {
                close(min[1], domain.min[1]) && close(max[1], domain.max[1])
            }
            _ => false,
        })
}

/// Thickness of the deposit at its toe, as a fraction of the column height H
/// ([`Column::deposit_toe`]).
pub const TOE_THICKNESS: Real = 0.1;

/// Thickness of the deposit at its grain toe ([`Column::grain_toe`]), m: one grain of the
/// aluminium bars of Bui et al. (2008) (1 and 1.5 mm in diameter), rounded up to 2 mm.
pub const GRAIN_THICKNESS: Real = 0.002;

/// One sample of the flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// t in s.
    pub time: Real,
    /// Runout: the deposit toe ([`Column::deposit_toe`]), measured from the back wall.
    pub runout: Real,
    /// Farthest particles: x of the foremost particle that has at least two others within
    /// 1.5 dx (so single detached particles do not count), plus dx/2, measured from the back
    /// wall. Grows as dx shrinks (the thin leading layer); use `runout` to compare runs.
    pub front: Real,
    /// The grain toe ([`Column::grain_toe`]), measured from the back wall: where the deposit
    /// thins to one grain, the experiments' maximum run-out.
    pub grain_toe: Real,
    /// Height of the continuous soil column within 2 dx of the back wall, plus dx/2.
    pub height_at_wall: Real,
    /// Kinetic energy of the soil, J (per metre in 2D).
    pub kinetic_energy: Real,
    /// Checkerboard noise of the stress field, η = ‖σ − ⟨σ⟩_MLS‖/‖σ‖ over all particles
    /// ([`geosph_soil::sph::stress_noise()`]; NaN if it could not be measured).
    pub stress_noise: Real,
}

impl Sample {
    /// Column names of [`Sample::record`] in `runout.csv`.
    pub const COLUMNS: [&'static str; 7] = [
        "t",
        "runout",
        "runout_front",
        "runout_grain",
        "height_at_wall",
        "kinetic_energy",
        "stress_noise",
    ];

    /// The sample as one row: t, runout, front, grain toe, height at the wall, kinetic energy,
    /// stress noise (the order of `runout.csv` and of the checkpointed series).
    pub fn record(&self) -> [Real; 7] {
        [
            self.time,
            self.runout,
            self.front,
            self.grain_toe,
            self.height_at_wall,
            self.kinetic_energy,
            self.stress_noise,
        ]
    }

    /// The inverse of [`Sample::record`].
    pub fn from_record(
        [
            time,
            runout,
            front,
            grain_toe,
            height_at_wall,
            kinetic_energy,
            stress_noise,
        ]: [Real; 7],
    ) -> Self {
        Self {
            time,
            runout,
            front,
            grain_toe,
            height_at_wall,
            kinetic_energy,
            stress_noise,
        }
    }
}

/// Samples the front, the height at the wall and the kinetic energy, and keeps the (x, up)
/// positions of the first and the last sample for the deposit profile.
#[derive(Clone, Debug)]
pub struct RunoutTracker {
    column: Column,
    order: Vec<usize>,
    sorted_x: Vec<Real>,
    heights: Vec<Real>,
    /// The samples so far.
    pub samples: Vec<Sample>,
    /// (x, height) of every particle at the first sample.
    pub initial: Vec<(Real, Real)>,
    /// (x, height) of every particle at the latest sample, in id order.
    pub latest: Vec<(Real, Real)>,
    /// Displacement |u| of every particle since the release (t = 0) at the latest sample, in
    /// the order of `latest` (zero for a scene without soil fields).
    pub displacement: Vec<Real>,
    /// The largest displacement across the runout direction, max |u_y| over every particle
    /// and sample so far (3D; zero in 2D): how far a slab in plane strain has left it.
    pub out_of_plane: Real,
}

impl RunoutTracker {
    /// A tracker for `column`.
    pub fn new(column: Column) -> Self {
        Self {
            column,
            order: Vec::new(),
            sorted_x: Vec::new(),
            heights: Vec::new(),
            samples: Vec::new(),
            initial: Vec::new(),
            latest: Vec::new(),
            displacement: Vec::new(),
            out_of_plane: 0.0,
        }
    }
}

impl<const D: usize> Observer<D> for RunoutTracker {
    fn columns(&self) -> Vec<&'static str> {
        vec![
            "runout",
            "runout_front",
            "runout_grain",
            "height_at_wall",
            "stress_noise",
        ]
    }

    fn sample(&mut self, time: Real, soil: &Particles<D>, row: &mut Vec<Real>) {
        let up = D - 1;
        let column = self.column;
        let dx = column.spacing;
        let x = &soil.position;
        self.order.clear();
        self.order.extend(0..x.len());
        self.order.sort_by(|&a, &b| x[b][0].total_cmp(&x[a][0]));
        let close = (1.5 * dx) * (1.5 * dx);
        let front_particle = self.order.iter().copied().find(|&i| {
            x.iter()
                .enumerate()
                .filter(|&(j, x_j)| j != i && (x_j - x[i]).norm_squared() <= close)
                .take(2)
                .count()
                == 2
        });
        let front = front_particle.map_or(0.0, |i| x[i][0] + 0.5 * dx - column.wall);
        self.sorted_x.clear();
        self.sorted_x.extend(self.order.iter().map(|&i| x[i][0]));
        let runout = column.deposit_toe(&self.sorted_x);
        let grain_toe = column.grain_toe(&self.sorted_x);
        self.heights.clear();
        self.heights.extend(
            x.iter()
                .filter(|p| p[0] - column.wall < 2.0 * dx)
                .map(|p| p[up]),
        );
        self.heights.sort_by(Real::total_cmp);
        let bottom = self.heights.first().copied().unwrap_or(0.0);
        let mut height = bottom;
        for &y in &self.heights {
            if y - height > 2.0 * dx {
                break;
            }
            height = y;
        }
        let height_at_wall = if self.heights.is_empty() {
            0.0
        } else {
            height + 0.5 * dx - (bottom - 0.5 * dx)
        };
        let kinetic_energy = soil
            .velocity
            .iter()
            .zip(&soil.mass)
            .map(|(v, m)| 0.5 * m * v.norm_squared())
            .sum();
        let stress_noise = geosph_soil::sph::stress_noise(soil, dx).unwrap_or(Real::NAN);
        row.extend_from_slice(&[runout, front, grain_toe, height_at_wall, stress_noise]);
        self.samples.push(Sample {
            time,
            runout,
            front,
            grain_toe,
            height_at_wall,
            kinetic_energy,
            stress_noise,
        });
        // In id order, so that the deposit does not depend on the order the run holds its
        // particles in (which differs between one process and several ranks).
        let mut by_id: Vec<usize> = (0..x.len()).collect();
        by_id.sort_unstable_by_key(|&i| soil.id[i]);
        self.latest.clear();
        self.latest
            .extend(by_id.iter().map(|&i| (x[i][0], x[i][up])));
        self.displacement.clear();
        match &soil.soil {
            Some(fields) => self
                .displacement
                .extend(by_id.iter().map(|&i| fields.displacement[i].norm())),
            None => self.displacement.resize(x.len(), 0.0),
        }
        if let (Some(fields), 3) = (&soil.soil, D) {
            let across = fields.displacement.iter().map(|u| u[1].abs());
            self.out_of_plane = across.fold(self.out_of_plane, Real::max);
        }
        if self.initial.is_empty() {
            self.initial.clone_from(&self.latest);
        }
    }

    fn save_state(&self) -> Vec<Real> {
        let mut state = Vec::new();
        let samples = self.samples.iter();
        push_records(&mut state, samples.map(Sample::record));
        push_records(&mut state, self.initial.iter().map(|&(x, y)| [x, y]));
        push_records(&mut state, self.latest.iter().map(|&(x, y)| [x, y]));
        push_records(&mut state, self.displacement.iter().map(|&u| [u]));
        push_records(&mut state, [[self.out_of_plane]].into_iter());
        state
    }

    fn restore_state(&mut self, mut state: &[Real]) -> Result<(), String> {
        self.samples = take_records(&mut state)?
            .into_iter()
            .map(Sample::from_record)
            .collect();
        let points = |state: &mut &[Real]| -> Result<Vec<(Real, Real)>, String> {
            Ok(take_records(state)?
                .into_iter()
                .map(|[x, y]| (x, y))
                .collect())
        };
        self.initial = points(&mut state)?;
        self.latest = points(&mut state)?;
        self.displacement = take_records(&mut state)?.into_iter().map(|[u]| u).collect();
        // Checkpoints written before the series had it end here: the maximum restarts from
        // zero at the restart.
        self.out_of_plane = if state.is_empty() {
            0.0
        } else {
            let out_of_plane: Vec<[Real; 1]> = take_records(&mut state)?;
            out_of_plane.first().map_or(0.0, |[u]| *u)
        };
        if state.is_empty() {
            Ok(())
        } else {
            Err(
                "the runout series in the checkpoint has another layout (written by another \
                 version of slope-failure)"
                    .into(),
            )
        }
    }
}

/// Runs `scene`; with an output folder, also writes `runout.csv`, `runout.png`,
/// `deposit.csv` and `deposit.png`.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<Report, Error> {
    let column = Column::of(scene)?;
    let mut tracker = RunoutTracker::new(column);
    let summary = geosph_runner::run(scene, options, &mut tracker)?;
    let last = *tracker
        .samples
        .last()
        .ok_or_else(|| Error::Scene("the run produced no sample".into()))?;
    let experiment = bui2008::is_experiment(scene, &column)
        .then(|| ExperimentComparison::new(&column, &tracker.latest, &tracker.displacement, &last));
    let aspect_ratio =
        nguyen2015::applies(scene, &column).then(|| AspectRatioComparison::new(&column, &last));
    if let Some(dir) = &options.out_dir {
        write_outputs(
            dir,
            &column,
            &tracker,
            experiment.as_ref(),
            aspect_ratio.as_ref(),
        )?;
    }
    let samples = tracker.samples;
    let peak_kinetic_energy = samples
        .iter()
        .map(|s| s.kinetic_energy)
        .fold(0.0, Real::max);
    let out_of_plane =
        (column.dimension == 3 && column.plane_strain).then_some(tracker.out_of_plane);
    Ok(Report {
        summary,
        column,
        out_of_plane,
        samples,
        last,
        peak_kinetic_energy,
        experiment,
        aspect_ratio,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_profile_takes_the_top_of_each_bin() {
        let points = [(0.05, 0.05), (0.05, 0.15), (0.15, 0.05)];
        let (x, y) = surface_profile(&points, 0.1);
        assert_eq!(x.len(), 2);
        assert!((y[0] - 0.2).abs() < 1e-12 && (y[1] - 0.1).abs() < 1e-12);
    }

    #[test]
    fn deposit_toe_ignores_a_thin_leading_layer() {
        let dx = 0.004;
        let column = Column {
            wall: 0.0,
            base: 0.0,
            length: 0.2,
            height: 0.1,
            breadth: 1.0,
            spacing: dx,
            dimension: 2,
            plane_strain: true,
        };
        let centre = |i: usize| (i as Real + 0.5) * dx;
        // A 0.2 m × 0.1 m block (50 × 25 particles) and a layer one particle (0.04 H) thick to
        // x = 0.4 m: 7 particles are needed within H/10, which the block's face and the first
        // two layer particles (x = 0.202, 0.206 m) hold.
        let mut x: Vec<Real> = (0..50)
            .flat_map(|i| [centre(i); 25])
            .chain((50..100).map(centre))
            .collect();
        x.sort_by(|a, b| b.total_cmp(a));
        assert!((column.deposit_toe(&x) - (0.206 + 0.5 * dx)).abs() < 1e-12);
        // Three particles (0.12 H) thick, the layer is part of the deposit.
        x.extend((50..100).flat_map(|i| [centre(i); 2]));
        x.sort_by(|a, b| b.total_cmp(a));
        assert!((column.deposit_toe(&x) - 0.4).abs() < 1e-12);
        assert_eq!(column.deposit_toe(&[0.3, 0.2]), 0.0);
    }

    #[test]
    fn shipped_scenes_parse_validate_and_have_a_column() {
        for (name, text) in SCENES {
            let scene = Scene::from_ron(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            scene.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            Column::of(&scene).unwrap();
        }
        let slope = Scene::from_ron(SLOPE_SCENE).unwrap();
        slope.validate().unwrap();
        assert!(factor_of_safety::settings(&slope).is_ok());
        assert!(Column::of(&slope).is_err());
    }
}
