//! The slope-failure application: runs a soil scene (by default the granular column collapse of
//! Bui et al. 2008) with the geosph runner, tracks the runout front and the height of the soil at
//! the back wall, and writes `runout.csv`, `runout.png` (front and wall height against time)
//! and `deposit.png` (initial and final surface profiles) next to the runner's VTU frames.
//!
//! The column is the scene's first soil block (a box) with its back wall at the box's lower x;
//! the soil runs out towards +x. `main.rs` is a thin command line around [`run`].
#![warn(missing_docs)]

use std::path::Path;

use geosph_core::{Particles, Real};
use geosph_io::{PlotSpec, Series, line_plot_png, write_csv_atomically};
use geosph_runner::{Observer, RunOptions, Summary, push_records, take_records};
use geosph_scene::{Region, Scene};

/// The embedded default scene (`data/scenes/granular-collapse.ron`).
pub const DEFAULT_SCENE: &str = include_str!("../../../data/scenes/granular-collapse.ron");

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
    /// Initial length L (along x).
    pub length: Real,
    /// Initial height H.
    pub height: Real,
    /// Particle spacing dx.
    pub spacing: Real,
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
                "the first soil block must be a Box (the column)".into(),
            ));
        };
        let up = scene.dimension - 1;
        Ok(Self {
            wall: min[0],
            length: max[0] - min[0],
            height: max[up] - min[up],
            spacing: scene.dx,
        })
    }
}

/// One sample of the flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// t in s.
    pub time: Real,
    /// Runout front: x of the foremost particle that has at least two others within 1.5 dx
    /// (so single detached particles do not count), plus dx/2, measured from the back wall.
    pub front: Real,
    /// Height of the continuous soil column within 2 dx of the back wall, plus dx/2.
    pub height_at_wall: Real,
    /// Kinetic energy of the soil, J (per metre in 2D).
    pub kinetic_energy: Real,
}

/// Samples the front, the height at the wall and the kinetic energy, and keeps the (x, up)
/// positions of the first and the last sample for the deposit profile.
#[derive(Clone, Debug)]
pub struct RunoutTracker {
    column: Column,
    order: Vec<usize>,
    heights: Vec<Real>,
    /// The samples so far.
    pub samples: Vec<Sample>,
    /// (x, height) of every particle at the first sample.
    pub initial: Vec<(Real, Real)>,
    /// (x, height) of every particle at the latest sample.
    pub latest: Vec<(Real, Real)>,
}

impl RunoutTracker {
    /// A tracker for `column`.
    pub fn new(column: Column) -> Self {
        Self {
            column,
            order: Vec::new(),
            heights: Vec::new(),
            samples: Vec::new(),
            initial: Vec::new(),
            latest: Vec::new(),
        }
    }
}

impl<const D: usize> Observer<D> for RunoutTracker {
    fn columns(&self) -> Vec<&'static str> {
        vec!["runout_front", "height_at_wall"]
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
        row.extend_from_slice(&[front, height_at_wall]);
        self.samples.push(Sample {
            time,
            front,
            height_at_wall,
            kinetic_energy,
        });
        self.latest.clear();
        self.latest.extend(x.iter().map(|p| (p[0], p[up])));
        if self.initial.is_empty() {
            self.initial.clone_from(&self.latest);
        }
    }

    fn save_state(&self) -> Vec<Real> {
        let mut state = Vec::new();
        let samples = self.samples.iter();
        push_records(
            &mut state,
            samples.map(|s| [s.time, s.front, s.height_at_wall, s.kinetic_energy]),
        );
        push_records(&mut state, self.initial.iter().map(|&(x, y)| [x, y]));
        push_records(&mut state, self.latest.iter().map(|&(x, y)| [x, y]));
        state
    }

    fn restore_state(&mut self, mut state: &[Real]) -> Result<(), String> {
        self.samples = take_records(&mut state)?
            .into_iter()
            .map(|[time, front, height_at_wall, kinetic_energy]| Sample {
                time,
                front,
                height_at_wall,
                kinetic_energy,
            })
            .collect();
        let points = |state: &mut &[Real]| -> Result<Vec<(Real, Real)>, String> {
            Ok(take_records(state)?
                .into_iter()
                .map(|[x, y]| (x, y))
                .collect())
        };
        self.initial = points(&mut state)?;
        self.latest = points(&mut state)?;
        Ok(())
    }
}

/// The result of a run.
#[derive(Clone, Debug)]
pub struct Report {
    /// The runner's summary (with the geostatic report, if the scene had a stage).
    pub summary: Summary,
    /// The initial column.
    pub column: Column,
    /// Front, wall height and kinetic energy at every sample time.
    pub samples: Vec<Sample>,
    /// The final sample.
    pub last: Sample,
    /// Largest kinetic energy of the run.
    pub peak_kinetic_energy: Real,
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "column             L = {:.3} m, H = {:.3} m, dx = {} m",
            self.column.length, self.column.height, self.column.spacing
        )?;
        writeln!(
            f,
            "final runout       {:.4} m from the wall (L_f/L = {:.3}), height at the wall {:.4} m (H_f/H = {:.3})",
            self.last.front,
            self.last.front / self.column.length,
            self.last.height_at_wall,
            self.last.height_at_wall / self.column.height
        )?;
        write!(
            f,
            "kinetic energy     peak {:.3e} J, final {:.3e} J (ratio {:.1e})",
            self.peak_kinetic_energy,
            self.last.kinetic_energy,
            self.last.kinetic_energy / self.peak_kinetic_energy.max(Real::MIN_POSITIVE)
        )
    }
}

/// Runs `scene`; with an output folder, also writes `runout.csv`, `runout.png` and
/// `deposit.png`.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<Report, Error> {
    let column = Column::of(scene)?;
    let mut tracker = RunoutTracker::new(column);
    let summary = geosph_runner::run(scene, options, &mut tracker)?;
    if let Some(dir) = &options.out_dir {
        write_outputs(dir, &column, &tracker)?;
    }
    let samples = tracker.samples;
    let last = *samples
        .last()
        .ok_or_else(|| Error::Scene("the run produced no sample".into()))?;
    let peak_kinetic_energy = samples
        .iter()
        .map(|s| s.kinetic_energy)
        .fold(0.0, Real::max);
    Ok(Report {
        summary,
        column,
        samples,
        last,
        peak_kinetic_energy,
    })
}

/// The surface of a particle set: the highest particle (+ dx/2) in each x bin of width dx.
pub fn surface_profile(points: &[(Real, Real)], spacing: Real) -> (Vec<Real>, Vec<Real>) {
    let mut bins: Vec<(i64, Real)> = points
        .iter()
        .map(|&(x, y)| ((x / spacing).floor() as i64, y))
        .collect();
    bins.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
    bins.dedup_by_key(|bin| bin.0);
    bins.iter()
        .map(|&(k, y)| ((k as Real + 0.5) * spacing, y + 0.5 * spacing))
        .unzip()
}

fn write_outputs(dir: &Path, column: &Column, tracker: &RunoutTracker) -> Result<(), Error> {
    let samples = &tracker.samples;
    write_csv_atomically(
        dir.join("runout.csv"),
        &["t", "runout_front", "height_at_wall", "kinetic_energy"],
        samples
            .iter()
            .map(|s| [s.time, s.front, s.height_at_wall, s.kinetic_energy]),
    )?;
    let t: Vec<Real> = samples.iter().map(|s| s.time).collect();
    let front: Vec<Real> = samples.iter().map(|s| s.front).collect();
    let height: Vec<Real> = samples.iter().map(|s| s.height_at_wall).collect();
    line_plot_png(
        dir.join("runout.png"),
        &PlotSpec {
            title: "Runout front and soil height at the wall",
            x_label: "t (s)",
            y_label: "distance from the wall / height (m)",
            lines: vec![
                Series {
                    label: "runout front",
                    x: &t,
                    y: &front,
                },
                Series {
                    label: "height at the wall",
                    x: &t,
                    y: &height,
                },
            ],
            ..Default::default()
        },
    )?;
    let (x0, y0) = surface_profile(&tracker.initial, column.spacing);
    let (x1, y1) = surface_profile(&tracker.latest, column.spacing);
    line_plot_png(
        dir.join("deposit.png"),
        &PlotSpec {
            title: "Deposit profile",
            x_label: "x (m)",
            y_label: "surface height (m)",
            lines: vec![
                Series {
                    label: "initial",
                    x: &x0,
                    y: &y0,
                },
                Series {
                    label: "final",
                    x: &x1,
                    y: &y1,
                },
            ],
            ..Default::default()
        },
    )?;
    Ok(())
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
    fn shipped_scenes_parse_validate_and_have_a_column() {
        for (name, text) in SCENES {
            let scene = Scene::from_ron(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            scene.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            Column::of(&scene).unwrap();
        }
    }
}
