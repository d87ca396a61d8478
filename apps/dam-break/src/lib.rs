//! The dam-break application: runs a dam-break scene with the geosph runner, tracks the surge
//! front and the residual column height, and compares them with the experiments of Martin &
//! Moyce (1952) and the frictionless shallow-water bound of Ritter (1892).
//!
//! The column is a wide and n²a high with n² = 2 (the scene's first fluid block), released
//! against the wall at its left. Martin & Moyce scale the front as Z = x/a against
//! T = t √(2g/a) and the height as H = h/(2a) against τ = t √(g/a); the two time scales differ
//! by √2. `main.rs` is a thin command line around [`run`].
#![warn(missing_docs)]

mod gauge_comparison;
mod gauges;
mod martin_moyce;
mod reference;

use std::path::Path;

use geosph_core::{Particles, Real};
use geosph_io::{PlotSpec, Series, line_plot_png, write_csv_atomically};
use geosph_runner::{NoObserver, Observer, RunOptions, Share, Summary, push_records, take_records};
use geosph_scene::{Region, Scene};

pub use gauge_comparison::{GaugeComparison, WallPressureValidation};
pub use gauges::{
    EXPERIMENTS, GaugeExperiment, GaugeSetUp, KLEEFSMAN_2005, LOBOVSKY_2014, Sensor, WallGauges,
};
pub use martin_moyce::{GATE_DELAY, Validation, is_martin_moyce, validate};
pub use reference::{
    ReferenceCurve, kleefsman_obstacle_pressure, lobovsky_wall_pressure,
    martin_moyce_column_height, martin_moyce_front,
};

/// The embedded default scene (`data/scenes/dam-break-2d.ron`).
pub const DEFAULT_SCENE: &str = include_str!("../../../data/scenes/dam-break-2d.ron");

/// Errors of a dam-break run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene is not a dam break this app can measure.
    #[error("scene: {0}")]
    Scene(String),
    /// The run failed.
    #[error(transparent)]
    Run(#[from] geosph_runner::RunError),
    /// Writing the app's own output failed.
    #[error(transparent)]
    Output(#[from] geosph_io::Error),
}

/// The column: its back wall, width a and height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Column {
    /// x of the back wall (the column's left face).
    pub wall: Real,
    /// Width a.
    pub width: Real,
    /// Initial height.
    pub height: Real,
    /// Gravity magnitude g.
    pub gravity: Real,
    /// Band next to the wall in which the column height is measured.
    pub band: Real,
}

impl Column {
    /// The column of `scene`: its first fluid block, which must be a box.
    pub fn of(scene: &Scene) -> Result<Self, Error> {
        let fluid = scene
            .fluid
            .as_ref()
            .ok_or_else(|| Error::Scene("the scene has no fluid".into()))?;
        let Some(Region::Box { min, max }) = fluid.blocks.first() else {
            return Err(Error::Scene(
                "the first fluid block must be a Box (the column)".into(),
            ));
        };
        let up = scene.dimension - 1;
        let gravity = scene
            .gravity
            .as_ref()
            .map_or(9.81, |g| g.iter().map(|c| c * c).sum::<Real>().sqrt());
        Ok(Self {
            wall: min[0],
            width: max[0] - min[0],
            height: max[up] - min[up],
            gravity,
            band: 2.0 * scene.dx,
        })
    }

    /// Martin & Moyce's front time scale √(2g/a).
    pub fn front_time_scale(&self) -> Real {
        (2.0 * self.gravity / self.width).sqrt()
    }

    /// Martin & Moyce's height time scale √(g/a).
    pub fn height_time_scale(&self) -> Real {
        (self.gravity / self.width).sqrt()
    }

    /// The front of `samples` in Martin & Moyce's variables: T = t √(2g/a) and Z = x/a.
    pub fn front_curve(&self, samples: &[Sample]) -> (Vec<Real>, Vec<Real>) {
        let scale = self.front_time_scale();
        samples
            .iter()
            .map(|s| (s.time * scale, s.front / self.width))
            .unzip()
    }
}

/// One sample of the flow: time, front position and column height at the wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// t in s.
    pub time: Real,
    /// Front position measured from the back wall, m.
    pub front: Real,
    /// Height of the water at the back wall, m.
    pub height: Real,
}

/// Tracks the surge front (the largest x of any fluid particle) and the column height (the top
/// of the continuous water column within two dx of the back wall), at every sample time.
#[derive(Clone, Debug)]
pub struct FrontTracker {
    column: Column,
    heights: Vec<Real>,
    /// The samples so far.
    pub samples: Vec<Sample>,
}

impl FrontTracker {
    /// A tracker for `column`.
    pub fn new(column: Column) -> Self {
        Self {
            column,
            heights: Vec::new(),
            samples: Vec::new(),
        }
    }
}

impl<const D: usize> Observer<D> for FrontTracker {
    fn columns(&self) -> Vec<&'static str> {
        vec!["x_front", "column_height"]
    }

    fn sample(&mut self, time: Real, fluid: &Particles<D>, row: &mut Vec<Real>) {
        self.sample_share(time, &mut Share::whole_run(fluid), row);
    }

    /// The front is a maximum over the ranks; the heights in the band are gathered and
    /// sorted, so both are those of one process exactly.
    fn sample_share(&mut self, time: Real, share: &mut Share<'_, D>, row: &mut Vec<Real>) {
        let up = D - 1;
        let column = self.column;
        let mut front = [share
            .position()
            .iter()
            .map(|x| x[0] - column.wall)
            .fold(0.0, Real::max)];
        share.max_each(&mut front);
        let [front] = front;
        self.heights.clear();
        self.heights.extend(
            share
                .position()
                .iter()
                .filter(|x| x[0] - column.wall < column.band)
                .map(|x| x[up]),
        );
        if share.is_distributed() {
            self.heights = share.gather(&self.heights);
        }
        self.heights.sort_by(Real::total_cmp);
        // The top of the continuous column: climb from the bed until a vertical gap wider
        // than the band, so droplets clinging to the wall above do not count.
        let mut height = 0.0;
        for &y in &self.heights {
            if y - height > column.band {
                break;
            }
            height = y;
        }
        row.extend_from_slice(&[front, height]);
        self.samples.push(Sample {
            time,
            front,
            height,
        });
    }

    fn save_state(&self) -> Vec<Real> {
        let mut state = Vec::new();
        let records = self.samples.iter().map(|s| [s.time, s.front, s.height]);
        push_records(&mut state, records);
        state
    }

    fn restore_state(&mut self, mut state: &[Real]) -> Result<(), String> {
        self.restore(&mut state)
    }
}

impl FrontTracker {
    /// Takes the samples saved by [`Observer::save_state`] from the front of `state`.
    fn restore(&mut self, state: &mut &[Real]) -> Result<(), String> {
        self.samples = take_records(state)?
            .into_iter()
            .map(|[time, front, height]| Sample {
                time,
                front,
                height,
            })
            .collect();
        Ok(())
    }
}

/// What `run` observes: the front and column height, and in an experiment's set-up
/// ([`GaugeSetUp::of`]) its gauges, in the scene's dimension.
struct DamBreakObserver {
    tracker: FrontTracker,
    plane_gauges: Option<WallGauges<2>>,
    space_gauges: Option<WallGauges<3>>,
}

impl DamBreakObserver {
    fn new(scene: &Scene, column: Column) -> Self {
        let set_up = GaugeSetUp::of(scene, &column);
        let dimension = scene.dimension;
        Self {
            tracker: FrontTracker::new(column),
            plane_gauges: set_up
                .clone()
                .filter(|_| dimension == 2)
                .map(|set_up| WallGauges::new(scene, set_up)),
            space_gauges: set_up
                .filter(|_| dimension == 3)
                .map(|set_up| WallGauges::new(scene, set_up)),
        }
    }
}

/// The observer's gauges of dimension D (each run fills the one of its scene's dimension).
trait GaugesOf<const D: usize> {
    fn gauges(&self) -> Option<&WallGauges<D>>;
    fn gauges_mut(&mut self) -> Option<&mut WallGauges<D>>;
}

impl GaugesOf<2> for DamBreakObserver {
    fn gauges(&self) -> Option<&WallGauges<2>> {
        self.plane_gauges.as_ref()
    }
    fn gauges_mut(&mut self) -> Option<&mut WallGauges<2>> {
        self.plane_gauges.as_mut()
    }
}

impl GaugesOf<3> for DamBreakObserver {
    fn gauges(&self) -> Option<&WallGauges<3>> {
        self.space_gauges.as_ref()
    }
    fn gauges_mut(&mut self) -> Option<&mut WallGauges<3>> {
        self.space_gauges.as_mut()
    }
}

impl<const D: usize> Observer<D> for DamBreakObserver
where
    Self: GaugesOf<D>,
{
    fn columns(&self) -> Vec<&'static str> {
        Observer::<D>::columns(&self.tracker)
    }

    fn sample(&mut self, time: Real, fluid: &Particles<D>, row: &mut Vec<Real>) {
        self.sample_share(time, &mut Share::whole_run(fluid), row);
    }

    fn sample_share(&mut self, time: Real, share: &mut Share<'_, D>, row: &mut Vec<Real>) {
        self.tracker.sample_share(time, share, row);
        if let Some(gauges) = self.gauges_mut() {
            gauges.sample(time, share);
        }
    }

    fn save_state(&self) -> Vec<Real> {
        let mut state = Observer::<D>::save_state(&self.tracker);
        if let Some(gauges) = GaugesOf::<D>::gauges(self) {
            gauges.save(&mut state);
        }
        state
    }

    fn restore_state(&mut self, mut state: &[Real]) -> Result<(), String> {
        self.tracker.restore(&mut state)?;
        match self.gauges_mut() {
            Some(gauges) => gauges.restore(&mut state),
            None => Ok(()),
        }
    }
}

/// The result of a dam-break run.
#[derive(Clone, Debug)]
pub struct Report {
    /// The runner's summary.
    pub summary: Summary,
    /// Front and height samples (none when the scene has no gravity: nothing collapses).
    pub samples: Vec<Sample>,
    /// Comparison with the references (only for Martin & Moyce's set-up,
    /// [`is_martin_moyce`]).
    pub validation: Option<Validation>,
    /// The gauges against their experiment (only for Lobovsky et al.'s or Kleefsman et al.'s
    /// set-up with a probe at a sensor, [`GaugeSetUp::of`]).
    pub wall_pressure: Option<WallPressureValidation>,
}

/// Runs `scene`; under gravity it tracks the front and the column height and, with an output
/// folder, writes `front.csv`, `front.png` and `height.png`, with Martin & Moyce's data only
/// when the scene is their set-up ([`is_martin_moyce`]). In an experiment's set-up with pressure
/// gauges it also compares the probes at its sensors ([`GaugeSetUp::of`]) and writes
/// `wall-pressure.png`.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<Report, Error> {
    // Before `Column::of`, which indexes the scene's coordinates by its dimension.
    scene.validate().map_err(|error| Error::Run(error.into()))?;
    let column = Column::of(scene)?;
    if column.gravity == 0.0 {
        let summary = geosph_runner::run(scene, options, &mut NoObserver)?;
        return Ok(Report {
            summary,
            samples: Vec::new(),
            validation: None,
            wall_pressure: None,
        });
    }
    let mut observer = DamBreakObserver::new(scene, column);
    let summary = geosph_runner::run(scene, options, &mut observer)?;
    let DamBreakObserver {
        tracker,
        plane_gauges,
        space_gauges,
    } = observer;
    let samples = tracker.samples;
    let reference = is_martin_moyce(scene, &column);
    let validation = reference.then(|| validate(&column, &samples));
    if let Some(dir) = &options.out_dir {
        write_outputs(dir, &column, &samples, reference)?;
        if let Some(gauges) = &plane_gauges {
            gauges.plot(dir)?;
        }
        if let Some(gauges) = &space_gauges {
            gauges.plot(dir)?;
        }
    }
    let wall_pressure = match (plane_gauges, space_gauges) {
        (Some(gauges), _) => Some(gauges.compare()),
        (None, Some(gauges)) => Some(gauges.compare()),
        (None, None) => None,
    };
    Ok(Report {
        summary,
        samples,
        validation,
        wall_pressure,
    })
}

/// Martin & Moyce's `curve` as the markers of a plot, when the scene is their set-up.
fn measured(curve: &ReferenceCurve, shown: bool) -> Vec<Series<'_>> {
    match shown {
        true => vec![Series {
            label: "Martin & Moyce (1952)",
            x: &curve.x,
            y: &curve.y,
        }],
        false => Vec::new(),
    }
}

fn write_outputs(
    dir: &Path,
    column: &Column,
    samples: &[Sample],
    reference: bool,
) -> Result<(), Error> {
    write_csv_atomically(
        dir.join("front.csv"),
        &["t", "x_front", "column_height"],
        samples.iter().map(|s| [s.time, s.front, s.height]),
    )?;
    let (t_front, z) = column.front_curve(samples);
    let front_reference = martin_moyce_front();
    let t_max = match reference {
        true => 1.2 * front_reference.x.last().copied().unwrap_or(4.0),
        false => t_front.last().copied().unwrap_or(1.0).max(1e-9),
    };
    let z_max = 1.05 * z.iter().copied().fold(4.2, Real::max);
    // Ritter's (1892) dry-bed front x = a + 2 √(g h₀) t, in these variables
    // Z = 1 + 2T √(h₀ / 2a): an upper bound for any column.
    let speed = 2.0 * (column.height / (2.0 * column.width)).sqrt();
    let ritter_t = [0.0, ((z_max - 1.0) / speed).min(t_max)];
    let ritter_z = [1.0, 1.0 + speed * ritter_t[1]];
    line_plot_png(
        dir.join("front.png"),
        &PlotSpec {
            title: "Dam break: surge front",
            x_label: "T = t √(2g/a)",
            y_label: "Z = x / a",
            lines: vec![
                Series {
                    label: "geosph",
                    x: &t_front,
                    y: &z,
                },
                Series {
                    label: "Ritter (1892), dry bed",
                    x: &ritter_t,
                    y: &ritter_z,
                },
            ],
            points: measured(&front_reference, reference),
            x_range: Some((0.0, t_max)),
            y_range: Some((1.0, z_max)),
            ..Default::default()
        },
    )?;
    let t_height: Vec<Real> = samples
        .iter()
        .map(|s| s.time * column.height_time_scale())
        .collect();
    let h: Vec<Real> = samples.iter().map(|s| s.height / column.height).collect();
    let height_reference = martin_moyce_column_height();
    line_plot_png(
        dir.join("height.png"),
        &PlotSpec {
            title: "Dam break: residual column height at the wall",
            x_label: "τ = t √(g/a)",
            y_label: "h / h₀",
            lines: vec![Series {
                label: "geosph",
                x: &t_height,
                y: &h,
            }],
            points: measured(&height_reference, reference),
            y_range: Some((0.0, 1.05)),
            ..Default::default()
        },
    )?;
    Ok(())
}
