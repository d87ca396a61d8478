//! The load of a dam break on the downstream wall, compared with the pressure gauges of
//! Lobovsky, Botia-Vera, Castellana, Mas-Soler & Souto-Iglesias (2014, J. Fluids Struct.
//! 48:407–434) when a scene is their set-up ([`LobovskySetUp::of`]).
//!
//! Pressures are compared as p/(ρ g H) against t* = t √(g/H), H the initial water depth. The
//! measures are those of `docs/validation.md`, "Wall pressure": the arrival (first crossing of
//! 0.1 ρ g H), the mean over the plateau t* = 3–5.5, the raw signal's scatter about its running
//! mean (window 0.1 in t*) on the plateau, the lowest value after arrival, and the peak
//! (reported only: the impact peak scatters strongly between repetitions of the experiment,
//! Lobovsky et al. 2014, §4).

use std::fmt;
use std::path::Path;

use geosph_core::{Particles, Real};
use geosph_io::{PlotSpec, Series, line_plot_png};
use geosph_runner::{PressureProbes, push_records, take_records};
use geosph_scene::{ProbeSpec, Scene};

use crate::Column;
use crate::martin_moyce::{downward_gravity, tank_at_column};
use crate::reference::{ReferenceCurve, lobovsky_wall_pressure};
use geosph_io::interpolate;

/// Lobovsky et al.'s sensors on the downstream wall: name and height above the bed as a
/// fraction of the water depth H = 0.3 m (3, 30 and 80 mm), in the order of
/// [`lobovsky_wall_pressure`].
pub const SENSORS: [(&str, Real); 3] = [
    ("sensor 1", 0.003 / 0.3),
    ("sensor 3", 0.030 / 0.3),
    ("sensor 4", 0.080 / 0.3),
];

/// The tank's length in water depths, 1.61 m / 0.3 m.
const TANK_LENGTH: Real = 1.61 / 0.3;
/// The pressure (in ρ g H) whose first crossing is the arrival.
const ARRIVAL_LEVEL: Real = 0.1;
/// The plateau after the impact, in t*.
const PLATEAU: (Real, Real) = (3.0, 5.5);
/// The running mean's window, in t*.
const RUNNING_WINDOW: Real = 0.1;

/// A scene matched to Lobovsky et al.'s set-up: a column 2H long and H deep (a 2D scene)
/// against the upstream wall of a tank 1.61/0.3 H long, gravity straight down, and the scene's
/// probes that sit on the downstream wall at a sensor's height (within half a particle
/// spacing, scaled by H/0.3 m).
#[derive(Clone, Debug, PartialEq)]
pub struct LobovskySetUp {
    /// Initial water depth H in m.
    pub depth: Real,
    /// t* per second, √(g/H).
    pub time_scale: Real,
    /// ρ g H in Pa.
    pub pressure_scale: Real,
    /// (index into [`SENSORS`], the scene's probe at it), in sensor order.
    pub gauges: Vec<(usize, ProbeSpec)>,
}

impl LobovskySetUp {
    /// The set-up of `scene` with `column`, if it is Lobovsky et al.'s and has a probe at one
    /// of their sensors at least.
    pub fn of(scene: &Scene, column: &Column) -> Option<Self> {
        if scene.dimension != 2 || !downward_gravity(scene) {
            return None;
        }
        let depth = column.height;
        let (inner_min, inner_max) = tank_at_column(scene)?;
        let length = inner_max[0] - inner_min[0];
        let half_dx = 0.5 * scene.dx;
        if (column.width - 2.0 * depth).abs() > 1e-6 * depth
            || (length - TANK_LENGTH * depth).abs() > half_dx
        {
            return None;
        }
        let gauges: Vec<(usize, ProbeSpec)> = SENSORS
            .iter()
            .enumerate()
            .filter_map(|(k, &(_, height))| {
                let probe = scene.output.probes.iter().find(|probe| {
                    (probe.position[0] - inner_max[0]).abs() <= half_dx
                        && (probe.position[1] - inner_min[1] - height * depth).abs() <= half_dx
                })?;
                Some((k, probe.clone()))
            })
            .collect();
        let density = scene.fluid.as_ref()?.density;
        (!gauges.is_empty()).then(|| Self {
            depth,
            time_scale: (column.gravity / depth).sqrt(),
            pressure_scale: density * column.gravity * depth,
            gauges,
        })
    }
}

/// Samples the gauges of a [`LobovskySetUp`] (the same interpolation as the scene's probes,
/// [`PressureProbes`]) in p/(ρ g H) against t*; a gauge without water reads 0.
pub struct WallGauges {
    set_up: LobovskySetUp,
    probes: PressureProbes<2>,
    row: Vec<Real>,
    /// t* of each sample.
    pub time: Vec<Real>,
    /// p/(ρ g H) of each gauge (in [`LobovskySetUp::gauges`] order) at each sample.
    pub pressure: Vec<Vec<Real>>,
}

impl WallGauges {
    /// The gauges of `set_up`, read with the scene's kernel and smoothing length.
    pub fn new(scene: &Scene, set_up: LobovskySetUp) -> Self {
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

    /// Records the gauges for `fluid` at `time` (s).
    pub fn sample(&mut self, time: Real, fluid: &Particles<2>) {
        self.row.clear();
        self.probes.sample(fluid, &mut self.row);
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
        let reference = lobovsky_wall_pressure();
        let gauges = self
            .set_up
            .gauges
            .iter()
            .zip(&self.pressure)
            .map(|(&(sensor, _), p)| GaugeComparison::of(sensor, &self.time, p, &reference[sensor]))
            .collect();
        WallPressureValidation { gauges }
    }

    /// `wall-pressure.png` in `dir`: each gauge against its sensor.
    pub fn plot(&self, dir: &Path) -> Result<(), geosph_io::Error> {
        let reference = lobovsky_wall_pressure();
        let labels: Vec<(String, String)> = self
            .set_up
            .gauges
            .iter()
            .map(|&(sensor, _)| {
                let (name, height) = SENSORS[sensor];
                let mm = 1e3 * height * 0.3;
                (
                    format!("geosph, {name} ({mm:.0} mm)"),
                    format!("Lobovsky et al. (2014), {name}"),
                )
            })
            .collect();
        let lines = self
            .pressure
            .iter()
            .zip(&labels)
            .map(|(p, (label, _))| Series {
                label,
                x: &self.time,
                y: p,
            })
            .collect();
        let points = self
            .set_up
            .gauges
            .iter()
            .zip(&labels)
            .map(|(&(sensor, _), (_, label))| Series {
                label,
                x: &reference[sensor].x,
                y: &reference[sensor].y,
            })
            .collect();
        let end = self.time.last().copied().unwrap_or(1.0).max(7.0);
        line_plot_png(
            dir.join("wall-pressure.png"),
            &PlotSpec {
                title: "Dam break: pressure on the downstream wall",
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

/// One gauge against its sensor, in p/(ρ g H) and t √(g/H). A measure is `None` where the
/// run or the data do not cover it.
#[derive(Clone, Debug, PartialEq)]
pub struct GaugeComparison {
    /// The sensor's name.
    pub sensor: &'static str,
    /// First crossing of 0.1 ρ g H: (geosph, experiment).
    pub arrival: (Option<Real>, Option<Real>),
    /// Mean over the plateau t* = 3–5.5: (geosph, experiment).
    pub plateau: (Option<Real>, Option<Real>),
    /// RMS of the raw signal about its running mean (window 0.1) on the plateau.
    pub scatter: Option<Real>,
    /// Lowest value after arrival.
    pub lowest: Option<Real>,
    /// Largest value: (geosph, experiment).
    pub peak: (Real, Real),
}

impl GaugeComparison {
    fn of(sensor: usize, time: &[Real], p: &[Real], reference: &ReferenceCurve) -> Self {
        let arrival = first_crossing(time, p, ARRIVAL_LEVEL);
        let covers_plateau = time.last().is_some_and(|&t| t >= PLATEAU.1);
        let on_plateau = || {
            time.iter()
                .zip(p)
                .filter(|(t, _)| (PLATEAU.0..=PLATEAU.1).contains(*t))
        };
        let plateau = covers_plateau.then(|| {
            let (sum, count) = on_plateau().fold((0.0, 0), |(s, n), (_, p)| (s + p, n + 1));
            sum / count as Real
        });
        let scatter = covers_plateau.then(|| {
            let (sum, count) = on_plateau().fold((0.0, 0), |(s, n), (&t, &p_t)| {
                let deviation = p_t - running_mean(time, p, t);
                (s + deviation * deviation, n + 1)
            });
            (sum / count as Real).sqrt()
        });
        let lowest = arrival.map(|t_a| {
            time.iter()
                .zip(p)
                .filter(|(t, _)| **t >= t_a)
                .map(|(_, &p)| p)
                .fold(Real::INFINITY, Real::min)
        });
        Self {
            sensor: SENSORS[sensor].0,
            arrival: (
                arrival,
                first_crossing(&reference.x, &reference.y, ARRIVAL_LEVEL),
            ),
            plateau: (plateau, curve_mean(reference, PLATEAU)),
            scatter,
            lowest,
            peak: (
                p.iter().copied().fold(0.0, Real::max),
                reference.y.iter().copied().fold(0.0, Real::max),
            ),
        }
    }
}

/// The first time the linear interpolant of (t, p) reaches `level` from below.
fn first_crossing(t: &[Real], p: &[Real], level: Real) -> Option<Real> {
    let k = p.iter().position(|&p| p >= level)?;
    if k == 0 {
        return Some(t[0]);
    }
    let fraction = (level - p[k - 1]) / (p[k] - p[k - 1]);
    Some(t[k - 1] + fraction * (t[k] - t[k - 1]))
}

/// The mean of the samples (t, p) within half a [`RUNNING_WINDOW`] of `at` (t ascending).
fn running_mean(t: &[Real], p: &[Real], at: Real) -> Real {
    let start = t.partition_point(|&s| s < at - 0.5 * RUNNING_WINDOW);
    let end = t.partition_point(|&s| s <= at + 0.5 * RUNNING_WINDOW);
    p[start..end].iter().sum::<Real>() / (end - start) as Real
}

/// The mean of the linear interpolant of `curve` over `range` (trapezoidal rule on the
/// digitised points and the interpolated ends); `None` if the curve does not cover it.
fn curve_mean(curve: &ReferenceCurve, (a, b): (Real, Real)) -> Option<Real> {
    let (x, y) = (&curve.x, &curve.y);
    if x.first().is_none_or(|&x0| x0 > a) || x.last().is_none_or(|&x1| x1 < b) {
        return None;
    }
    // Covered, so the interpolant exists at every knot.
    let at = |s: Real| interpolate(x, y, s).unwrap_or(Real::NAN);
    let mut knots: Vec<Real> = x.iter().copied().filter(|&s| s > a && s < b).collect();
    knots.insert(0, a);
    knots.push(b);
    let integral: Real = knots
        .windows(2)
        .map(|w| 0.5 * (w[1] - w[0]) * (at(w[0]) + at(w[1])))
        .sum();
    Some(integral / (b - a))
}

/// The comparison of every gauge of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct WallPressureValidation {
    /// One per gauge, in sensor order.
    pub gauges: Vec<GaugeComparison>,
}

impl fmt::Display for WallPressureValidation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let show = |v: Option<Real>| v.map_or("-".to_owned(), |v| format!("{v:.3}"));
        writeln!(
            f,
            "wall pressure      against Lobovsky et al. (2014), p/(ρgH) at t√(g/H); raw signals"
        )?;
        writeln!(
            f,
            "  gauge     arrival (exp)    plateau 3-5.5 (exp)   scatter  lowest   peak (exp)"
        )?;
        for g in &self.gauges {
            writeln!(
                f,
                "  {:<9} {:>6} ({:>5})   {:>6} ({:>5})        {:>6}   {:>6}   {:.2} ({:.2})",
                g.sensor,
                show(g.arrival.0),
                show(g.arrival.1),
                show(g.plateau.0),
                show(g.plateau.1),
                show(g.scatter),
                show(g.lowest),
                g.peak.0,
                g.peak.1
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_means_and_running_mean() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let p = [0.0, 0.05, 0.15, 1.0];
        assert!((first_crossing(&t, &p, 0.1).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(first_crossing(&t, &p, 2.0), None);
        // A sine of period 0.1 about 0.6: the running mean over one period is 0.6.
        let t: Vec<Real> = (0..=400).map(|k| 3.0 + k as Real * 0.005).collect();
        let p: Vec<Real> = t
            .iter()
            .map(|t| 0.6 + 0.2 * (std::f64::consts::TAU * t / 0.1).sin())
            .collect();
        assert!((running_mean(&t, &p, 4.0) - 0.6).abs() < 0.2 / 20.0);
        // The trapezoidal mean of a piecewise-linear curve is exact.
        let curve = ReferenceCurve {
            x: vec![2.0, 4.0, 6.0],
            y: vec![0.0, 1.0, 1.0],
        };
        let exact = (0.5 * (0.5 + 1.0) * 1.0 + 1.5) / 2.5;
        assert!((curve_mean(&curve, PLATEAU).unwrap() - exact).abs() < 1e-12);
        assert_eq!(curve_mean(&curve, (1.0, 3.0)), None);
    }

    #[test]
    fn set_up_is_recognised_only_with_its_geometry_and_gauges() {
        let scene = Scene::from_ron(include_str!(
            "../../../data/scenes/lobovsky-wall-pressure.ron"
        ))
        .unwrap();
        let column = Column::of(&scene).unwrap();
        let set_up = LobovskySetUp::of(&scene, &column).unwrap();
        let sensors: Vec<usize> = set_up.gauges.iter().map(|(k, _)| *k).collect();
        assert_eq!(sensors, [0, 1, 2]);
        assert!((set_up.pressure_scale - 1000.0 * 9.81 * 0.3).abs() < 1e-9);
        let mut no_probes = scene.clone();
        no_probes.output.probes.clear();
        assert_eq!(LobovskySetUp::of(&no_probes, &column), None);
        let dam_break = Scene::from_ron(crate::DEFAULT_SCENE).unwrap();
        let column = Column::of(&dam_break).unwrap();
        assert_eq!(LobovskySetUp::of(&dam_break, &column), None);
    }
}
