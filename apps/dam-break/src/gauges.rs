//! Pressure gauges of dam-break experiments, compared with a run when a scene is one of their
//! set-ups ([`GaugeSetUp::of`]): the downstream wall of Lobovsky, Botia-Vera, Castellana,
//! Mas-Soler & Souto-Iglesias (2014, J. Fluids Struct. 48:407–434), 2D, and the box obstacle
//! of Kleefsman, Fekken, Veldman, Iwanowski & Buchner (2005, J. Comput. Phys. 206:363–393,
//! SPHERIC test 2), 3D.
//!
//! Pressures are compared as p/(ρ g H) against t* = t √(g/H), H the initial water depth, with
//! the measures of [`GaugeComparison`].

use std::path::Path;

use geosph_core::Real;
use geosph_io::{PlotSpec, Series, line_plot_png};
use geosph_runner::{PressureProbes, Share, push_records, take_records};
use geosph_scene::{ProbeSpec, Scene};

use crate::Column;
use crate::gauge_comparison::{GaugeComparison, WallPressureValidation};
use crate::martin_moyce::{downward_gravity, tank_at_column};
use crate::reference::{ReferenceCurve, kleefsman_obstacle_pressure, lobovsky_wall_pressure};

/// One pressure sensor of an experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensor {
    /// Its name, e.g. "sensor 1".
    pub name: &'static str,
    /// Its position from the tank's inner lower corner, in water depths H (x, then y in 3D,
    /// then the height).
    pub position: &'static [Real],
}

/// A dam-break experiment with pressure gauges: a column of water H deep and `column_length`
/// H long against the upstream wall of a tank `tank_length` H long.
#[derive(Clone, Copy, Debug)]
pub struct GaugeExperiment {
    /// Who measured it, e.g. "Lobovsky et al. (2014)".
    pub name: &'static str,
    /// Where its gauges are, for the plot's title.
    pub face: &'static str,
    /// 2 (a narrow tank, compared in plane flow) or 3.
    pub dimension: usize,
    /// The column's length in water depths.
    pub column_length: Real,
    /// The tank's inner length in water depths.
    pub tank_length: Real,
    /// The sensors, in the order of [`GaugeExperiment::reference`]'s curves.
    pub sensors: &'static [Sensor],
    /// The plateau after the impact over which the mean pressure is compared, t* from, to.
    pub plateau: (Real, Real),
    /// The measured p/(ρ g H) against t* of each sensor.
    pub reference: fn() -> Vec<ReferenceCurve>,
    /// Whether the measurement is a continuous record (else points digitised from a figure).
    pub continuous: bool,
}

/// Experiments are told apart by name.
impl PartialEq for GaugeExperiment {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

/// Lobovsky et al. (2014): H = 0.3 m, the column 2H long, the tank 1.61 m long; sensors on the
/// downstream wall 3, 30 and 80 mm above the bed. The plateau t* = 3–5.5 follows the impact
/// and precedes the returning wave (`docs/validation.md`, "Wall pressure").
pub const LOBOVSKY_2014: GaugeExperiment = GaugeExperiment {
    name: "Lobovsky et al. (2014)",
    face: "the downstream wall",
    dimension: 2,
    column_length: 2.0,
    tank_length: 1.61 / 0.3,
    sensors: &[
        Sensor {
            name: "sensor 1",
            position: &[1.61 / 0.3, 0.003 / 0.3],
        },
        Sensor {
            name: "sensor 3",
            position: &[1.61 / 0.3, 0.030 / 0.3],
        },
        Sensor {
            name: "sensor 4",
            position: &[1.61 / 0.3, 0.080 / 0.3],
        },
    ],
    plateau: (3.0, 5.5),
    reference: || lobovsky_wall_pressure().to_vec(),
    continuous: false,
};

/// Kleefsman et al. (2005), SPHERIC test 2: H = 0.55 m, the column 1.228 m long across the
/// 1 m wide tank, the tank 3.22 m long; a box 0.161 × 0.403 × 0.161 m whose front face is
/// 2.3955 m from the column's back wall; gauges P1 and P3 on that face at y = 0.471 m, 0.021
/// and 0.101 m above the floor (the positions of the SPHERIC test 2 description). The
/// plateau t* = 3–5.5 follows the impact and precedes the wave returning from the far wall.
/// The set-up is recognised by its column, tank and probes; the box itself is not checked.
pub const KLEEFSMAN_2005: GaugeExperiment = GaugeExperiment {
    name: "Kleefsman et al. (2005)",
    face: "the obstacle's front face",
    dimension: 3,
    column_length: 1.228 / 0.55,
    tank_length: 3.22 / 0.55,
    sensors: &[
        Sensor {
            name: "P1",
            position: &[2.3955 / 0.55, 0.471 / 0.55, 0.021 / 0.55],
        },
        Sensor {
            name: "P3",
            position: &[2.3955 / 0.55, 0.471 / 0.55, 0.101 / 0.55],
        },
    ],
    plateau: (3.0, 5.5),
    reference: || kleefsman_obstacle_pressure().to_vec(),
    continuous: true,
};

/// The experiments [`GaugeSetUp::of`] recognises.
pub const EXPERIMENTS: [&GaugeExperiment; 2] = [&LOBOVSKY_2014, &KLEEFSMAN_2005];

/// A scene matched to an experiment's set-up: its column (the first fluid block) and tank in
/// water depths, gravity straight down, and the scene's probes that sit at a sensor (each
/// coordinate within half a particle spacing).
#[derive(Clone, Debug, PartialEq)]
pub struct GaugeSetUp {
    /// The experiment.
    pub experiment: &'static GaugeExperiment,
    /// Initial water depth H in m.
    pub depth: Real,
    /// t* per second, √(g/H).
    pub time_scale: Real,
    /// ρ g H in Pa.
    pub pressure_scale: Real,
    /// (index into the experiment's sensors, the scene's probe at it), in sensor order.
    pub gauges: Vec<(usize, ProbeSpec)>,
}

impl GaugeSetUp {
    /// The set-up of `scene` with `column`, if it is one of [`EXPERIMENTS`] and has a probe at
    /// one of its sensors at least.
    pub fn of(scene: &Scene, column: &Column) -> Option<Self> {
        EXPERIMENTS
            .iter()
            .find_map(|experiment| Self::of_experiment(experiment, scene, column))
    }

    fn of_experiment(
        experiment: &'static GaugeExperiment,
        scene: &Scene,
        column: &Column,
    ) -> Option<Self> {
        if scene.dimension != experiment.dimension || !downward_gravity(scene) {
            return None;
        }
        let depth = column.height;
        let (inner_min, inner_max) = tank_at_column(scene)?;
        let length = inner_max[0] - inner_min[0];
        let half_dx = 0.5 * scene.dx;
        if (column.width - experiment.column_length * depth).abs() > 1e-6 * depth
            || (length - experiment.tank_length * depth).abs() > half_dx
        {
            return None;
        }
        let gauges: Vec<(usize, ProbeSpec)> = experiment
            .sensors
            .iter()
            .enumerate()
            .filter_map(|(k, sensor)| {
                let probe = scene.output.probes.iter().find(|probe| {
                    probe
                        .position
                        .iter()
                        .zip(sensor.position)
                        .zip(inner_min)
                        .all(|((x, s), origin)| (x - origin - s * depth).abs() <= half_dx)
                })?;
                Some((k, probe.clone()))
            })
            .collect();
        let density = scene.fluid.as_ref()?.density;
        (!gauges.is_empty()).then(|| Self {
            experiment,
            depth,
            time_scale: (column.gravity / depth).sqrt(),
            pressure_scale: density * column.gravity * depth,
            gauges,
        })
    }
}

/// Samples the gauges of a [`GaugeSetUp`] (the same interpolation as the scene's probes,
/// [`PressureProbes`]) in p/(ρ g H) against t*; a gauge without water reads 0.
pub struct WallGauges<const D: usize> {
    set_up: GaugeSetUp,
    probes: PressureProbes<D>,
    row: Vec<Real>,
    /// t* of each sample.
    pub time: Vec<Real>,
    /// p/(ρ g H) of each gauge (in [`GaugeSetUp::gauges`] order) at each sample.
    pub pressure: Vec<Vec<Real>>,
}

impl<const D: usize> WallGauges<D> {
    /// The gauges of `set_up`, read with the scene's kernel and smoothing length.
    pub fn new(scene: &Scene, set_up: GaugeSetUp) -> Self {
        let probes: Vec<ProbeSpec> = set_up.gauges.iter().map(|(_, p)| p.clone()).collect();
        let kernel = scene.kernel.parse().expect("a validated scene");
        let probes = PressureProbes::new(&probes, kernel, scene.smoothing_ratio * scene.dx);
        let pressure = vec![Vec::new(); set_up.gauges.len()];
        Self {
            set_up,
            probes,
            row: Vec::new(),
            time: Vec::new(),
            pressure,
        }
    }

    /// Records the gauges at `time` (s) from `share` (on several ranks each rank's sums are
    /// added over the ranks, [`PressureProbes::sample`]).
    pub fn sample(&mut self, time: Real, share: &Share<'_, D>) {
        self.row.clear();
        self.probes.sample(share, &mut self.row);
        self.time.push(time * self.set_up.time_scale);
        for (series, &p) in self.pressure.iter_mut().zip(&self.row) {
            let p = if p.is_finite() { p } else { 0.0 };
            series.push(p / self.set_up.pressure_scale);
        }
    }

    /// Appends the samples to an observer's saved state.
    pub fn save(&self, state: &mut Vec<Real>) {
        for series in &self.pressure {
            push_records(state, self.time.iter().zip(series).map(|(&t, &p)| [t, p]));
        }
    }

    /// Takes the samples saved by [`WallGauges::save`] from the front of `state`.
    pub fn restore(&mut self, state: &mut &[Real]) -> Result<(), String> {
        for k in 0..self.pressure.len() {
            let records = take_records::<2>(state)?;
            // Every gauge was saved with the same sample times.
            if k == 0 {
                self.time = records.iter().map(|r| r[0]).collect();
            }
            self.pressure[k] = records.iter().map(|r| r[1]).collect();
        }
        Ok(())
    }

    /// The comparison of every gauge with its sensor.
    pub fn compare(&self) -> WallPressureValidation {
        let experiment = self.set_up.experiment;
        let reference = (experiment.reference)();
        let gauges = self
            .set_up
            .gauges
            .iter()
            .zip(&self.pressure)
            .map(|(&(sensor, _), p)| {
                let name = experiment.sensors[sensor].name;
                GaugeComparison::of(name, &self.time, p, &reference[sensor], experiment.plateau)
            })
            .collect();
        WallPressureValidation {
            experiment: experiment.name,
            plateau: experiment.plateau,
            gauges,
        }
    }

    /// `wall-pressure.png` in `dir`: each gauge against its sensor.
    pub fn plot(&self, dir: &Path) -> Result<(), geosph_io::Error> {
        let experiment = self.set_up.experiment;
        let reference = (experiment.reference)();
        let labels: Vec<(String, String)> = self
            .set_up
            .gauges
            .iter()
            .map(|&(sensor, _)| {
                let sensor = experiment.sensors[sensor];
                let height = sensor.position.last().copied().unwrap_or(0.0);
                let mm = 1e3 * height * self.set_up.depth;
                (
                    format!("geosph, {} ({mm:.0} mm)", sensor.name),
                    format!("{}, {}", experiment.name, sensor.name),
                )
            })
            .collect();
        let mut lines: Vec<Series> = self
            .pressure
            .iter()
            .zip(&labels)
            .map(|(p, (label, _))| Series {
                label,
                x: &self.time,
                y: p,
            })
            .collect();
        let measured = self
            .set_up
            .gauges
            .iter()
            .zip(&labels)
            .map(|(&(sensor, _), (_, label))| Series {
                label,
                x: &reference[sensor].x,
                y: &reference[sensor].y,
            });
        // A continuous record reads as a line, digitised points as markers.
        let points = match experiment.continuous {
            true => {
                lines.extend(measured);
                Vec::new()
            }
            false => measured.collect(),
        };
        let end = self.time.last().copied().unwrap_or(1.0).max(7.0);
        let title = format!("Dam break: pressure on {}", experiment.face);
        line_plot_png(
            dir.join("wall-pressure.png"),
            &PlotSpec {
                title: &title,
                x_label: "t √(g/H)",
                y_label: "p / (ρ g H)",
                lines,
                points,
                x_range: Some((0.0, end)),
                y_range: Some((-0.5, 3.0)),
                ..Default::default()
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set_up_of(source: &str) -> (Scene, Column, Option<GaugeSetUp>) {
        let scene = Scene::from_ron(source).unwrap();
        let column = Column::of(&scene).unwrap();
        let set_up = GaugeSetUp::of(&scene, &column);
        (scene, column, set_up)
    }

    #[test]
    fn set_ups_are_recognised_only_with_their_geometry_and_gauges() {
        let lobovsky = include_str!("../../../data/scenes/lobovsky-wall-pressure.ron");
        let kleefsman = include_str!("../../../data/scenes/kleefsman-obstacle.ron");
        for (source, experiment, sensors, depth) in [
            (lobovsky, &LOBOVSKY_2014, vec![0, 1, 2], 0.3),
            (kleefsman, &KLEEFSMAN_2005, vec![0, 1], 0.55),
        ] {
            let (scene, column, set_up) = set_up_of(source);
            let set_up = set_up.unwrap();
            assert_eq!(set_up.experiment, experiment);
            let found: Vec<usize> = set_up.gauges.iter().map(|(k, _)| *k).collect();
            assert_eq!(found, sensors);
            assert!((set_up.pressure_scale - 1000.0 * 9.81 * depth).abs() < 1e-9);
            let mut no_probes = scene.clone();
            no_probes.output.probes.clear();
            assert_eq!(GaugeSetUp::of(&no_probes, &column), None);
        }
        let (_, _, set_up) = set_up_of(crate::DEFAULT_SCENE);
        assert_eq!(set_up, None);
    }
}
