//! The measures of a gauge against its sensor (`docs/validation.md`, "Wall pressure"): the
//! arrival (first crossing of 0.1 ρ g H), the mean over the experiment's plateau, the raw
//! signal's scatter about its running mean (window 0.1 in t*) on the plateau, the lowest value
//! after arrival, and the peak (reported only: an impact peak scatters strongly between
//! repetitions of an experiment, Lobovsky et al. 2014, §4).

use std::fmt;

use geosph_core::Real;
use geosph_io::interpolate;

use crate::reference::ReferenceCurve;

/// The pressure (in ρ g H) whose first crossing is the arrival.
const ARRIVAL_LEVEL: Real = 0.1;
/// The running mean's window, in t*.
const RUNNING_WINDOW: Real = 0.1;

/// One gauge against its sensor, in p/(ρ g H) and t √(g/H). A measure is `None` where the
/// run or the data do not cover it.
#[derive(Clone, Debug, PartialEq)]
pub struct GaugeComparison {
    /// The sensor's name.
    pub sensor: &'static str,
    /// First crossing of 0.1 ρ g H: (geosph, experiment).
    pub arrival: (Option<Real>, Option<Real>),
    /// Mean over the experiment's plateau: (geosph, experiment).
    pub plateau: (Option<Real>, Option<Real>),
    /// RMS of the raw signal about its running mean (window 0.1) on the plateau.
    pub scatter: Option<Real>,
    /// Lowest value after arrival.
    pub lowest: Option<Real>,
    /// Largest value: (geosph, experiment).
    pub peak: (Real, Real),
}

impl GaugeComparison {
    /// The measures of the gauge `sensor` sampled as (`time`, `p`) against its `reference`
    /// curve, with the experiment's `plateau` (t* from, to).
    pub fn of(
        sensor: &'static str,
        time: &[Real],
        p: &[Real],
        reference: &ReferenceCurve,
        plateau: (Real, Real),
    ) -> Self {
        let arrival = first_crossing(time, p, ARRIVAL_LEVEL);
        let covers_plateau = time.last().is_some_and(|&t| t >= plateau.1);
        let on_plateau = || {
            time.iter()
                .zip(p)
                .filter(|(t, _)| (plateau.0..=plateau.1).contains(*t))
        };
        let mean = covers_plateau.then(|| {
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
            sensor,
            arrival: (
                arrival,
                first_crossing(&reference.x, &reference.y, ARRIVAL_LEVEL),
            ),
            plateau: (mean, curve_mean(reference, plateau)),
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
    /// The experiment, e.g. "Lobovsky et al. (2014)".
    pub experiment: &'static str,
    /// Its plateau, t* from, to.
    pub plateau: (Real, Real),
    /// One per gauge, in sensor order.
    pub gauges: Vec<GaugeComparison>,
}

impl fmt::Display for WallPressureValidation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let show = |v: Option<Real>| v.map_or("-".to_owned(), |v| format!("{v:.3}"));
        writeln!(
            f,
            "wall pressure      against {}, p/(ρgH) at t√(g/H); raw signals",
            self.experiment
        )?;
        let (from, to) = self.plateau;
        writeln!(
            f,
            "  gauge     arrival (exp)    plateau {from}-{to} (exp)   scatter  lowest   peak (exp)"
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
        assert!((curve_mean(&curve, (3.0, 5.5)).unwrap() - exact).abs() < 1e-12);
        assert_eq!(curve_mean(&curve, (1.0, 3.0)), None);
    }
}
