//! The granular collapse against the experiment of Bui, Fukagawa, Sako & Ohno (2008, Int. J.
//! Numer. Anal. Meth. Geomech. 32:1537): aluminium bars in plane strain, a column 0.2 m long
//! and 0.1 m high against a wall, released on its free side. The measured final surface and
//! failure line are embedded from `data/validation/` (where they were read from is stated
//! there).
//!
//! Measures, all from the back wall and the column's base:
//! - **surface error** P_d = √(Σ_k (f_num(x_k) − f_exp(x_k))² / Σ_k f_exp(x_k)²) over the
//!   experiment's points x_k (Feng, Fourtakas, Rogers & Liang 2021, Comput. Geotech.
//!   138:104356, eq. 46), f_num(x_k) the top (+ dx/2) of the particles in the bin of width dx
//!   centred on x_k (at the wall [0, dx]), 0 where there are none;
//! - **toe**: the deposit toe of [`Column::deposit_toe`] (0.1 H thick over H/10), for the
//!   experiment the largest x at which the measured surface holds 0.1 H of soil on average
//!   over the H/10 behind it (the same rule applied to the area under the curve);
//! - **failure line**: the edge of the region that did not deform (the experiment's
//!   definition, Ghaïtanellis et al. 2018, Adv. Water Resour. 111:156, Sect. 5): in ten
//!   horizontal bands of height H/10 the front (+ dx/2) of the particles that moved less than
//!   [`UNDEFORMED_DISPLACEMENT`] × H, a least-squares line x = x_b + s y through them, its
//!   angle to the floor atan(−1/s) and its foot x_b; the experiment's points are fitted the
//!   same way.

use geosph_core::Real;
use geosph_io::ReferenceCurve;
use geosph_scene::{Scene, SolverSpec};
use geosph_soil::ConstitutiveConfig;

use crate::{Column, GRAIN_THICKNESS, TOE_THICKNESS};

/// A particle that moved less than this fraction of H since the release belongs to the
/// non-deformed region (2 mm in the experiment: about one bar's diameter, below what its
/// 5 cm marker grid shows).
pub const UNDEFORMED_DISPLACEMENT: Real = 0.02;

/// The measured final surface height against x (m, from the back wall).
pub fn final_surface() -> ReferenceCurve {
    ReferenceCurve::from_csv(include_str!(
        "../../../data/validation/bui-2008-final-surface.csv"
    ))
}

/// The measured failure line: points (x, height) (m) on the edge of the non-deformed region.
pub fn failure_line() -> ReferenceCurve {
    ReferenceCurve::from_csv(include_str!(
        "../../../data/validation/bui-2008-failure-line.csv"
    ))
}

/// Length d₀ of the experiment's column, m.
pub const COLUMN_LENGTH: Real = 0.2;

/// Height h₀ of the experiment's column, m.
pub const COLUMN_HEIGHT: Real = 0.1;

/// Whether `a` and `b` agree to rounding.
fn close(a: Real, b: Real) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

/// Whether `scene` is the experiment's set-up: a column [`COLUMN_LENGTH`] ×
/// [`COLUMN_HEIGHT`] of the aluminium bars ([`is_aluminium_bars`]) in plane strain (2D, or a
/// 3D slab periodic across y; [`Column::plane_strain`]).
pub fn is_experiment(scene: &Scene, column: &Column) -> bool {
    column.plane_strain
        && close(column.length, COLUMN_LENGTH)
        && close(column.height, COLUMN_HEIGHT)
        && is_aluminium_bars(scene)
}

/// Whether the soil of `scene` is the experiment's material: Drucker–Prager soil with
/// ρ = 2650 kg/m³, φ = 19.8° and c = 0.
pub fn is_aluminium_bars(scene: &Scene) -> bool {
    let material = match &scene.solver {
        SolverSpec::Soil(config) => match &config.constitutive {
            ConstitutiveConfig::DruckerPrager { material, .. } => Some(material),
            _ => None,
        },
        _ => None,
    };
    let density = scene.fluid.as_ref().map(|soil| soil.density);
    density.is_some_and(|rho| close(rho, 2650.0))
        && material.is_some_and(|m| close(m.friction_angle_deg, 19.8) && m.cohesion == 0.0)
}

/// The grain toe of the measured surface (m from the wall): the rule of
/// [`Column::grain_toe`] applied to the curve, [`GRAIN_THICKNESS`] of soil over the H/10
/// behind it.
pub fn measured_grain_toe() -> Real {
    measured_toe(&final_surface(), COLUMN_HEIGHT, GRAIN_THICKNESS)
}

/// A straight failure line: its angle to the floor and where it meets the floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FailureLine {
    /// Angle to the horizontal, degrees.
    pub angle_deg: Real,
    /// x where it meets the floor, m from the back wall.
    pub foot: Real,
}

impl FailureLine {
    /// The least-squares line x = x_b + s y through `points` (x, height); `None` for fewer
    /// than two points or a line that does not fall towards +x.
    pub fn fit(points: &[(Real, Real)]) -> Option<Self> {
        let n = points.len() as Real;
        if points.len() < 2 {
            return None;
        }
        let (mean_x, mean_y) = points
            .iter()
            .fold((0.0, 0.0), |(sx, sy), &(x, y)| (sx + x / n, sy + y / n));
        let (sxy, syy) = points.iter().fold((0.0, 0.0), |(sxy, syy), &(x, y)| {
            (
                sxy + (x - mean_x) * (y - mean_y),
                syy + (y - mean_y).powi(2),
            )
        });
        let slope = sxy / syy;
        (slope < 0.0).then(|| Self {
            angle_deg: (-1.0 / slope).atan().to_degrees(),
            foot: mean_x - slope * mean_y,
        })
    }
}

/// The simulated deposit against the experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct ExperimentComparison {
    /// The free-surface error P_d (a fraction).
    pub surface_error: Real,
    /// The simulated surface height at each experimental x (m).
    pub surface: Vec<Real>,
    /// The simulated and the measured toe (m from the wall).
    pub toe: (Real, Real),
    /// The simulated and the measured grain toe (m from the wall).
    pub grain_toe: (Real, Real),
    /// The simulated and the measured height at the wall (m).
    pub height_at_wall: (Real, Real),
    /// The simulated failure line (none when no band has a non-deformed particle) and the
    /// measured one.
    pub failure_line: (Option<FailureLine>, FailureLine),
}

impl ExperimentComparison {
    /// Compares the particles at `points` (x, height) that moved by `displacement` since the
    /// release, with the last sample `last` (its toes and height at the wall).
    pub fn new(
        column: &Column,
        points: &[(Real, Real)],
        displacement: &[Real],
        last: &crate::Sample,
    ) -> Self {
        let measured = final_surface();
        let dx = column.spacing;
        let surface: Vec<Real> = measured
            .x
            .iter()
            .map(|&x_k| {
                // The bin of width dx centred on x_k, shifted off the wall at x_k = 0.
                let low = (x_k - 0.5 * dx).max(0.0);
                points
                    .iter()
                    .filter(|&&(x, _)| (low..low + dx).contains(&(x - column.wall)))
                    .map(|&(_, y)| y + 0.5 * dx - column.base)
                    .fold(0.0, Real::max)
            })
            .collect();
        let (squares, norm) = surface.iter().zip(&measured.y).fold(
            (0.0, 0.0),
            |(squares, norm), (&f_num, &f_exp)| {
                (squares + (f_num - f_exp).powi(2), norm + f_exp * f_exp)
            },
        );
        let mut edges: [Option<Real>; 10] = [None; 10];
        let band = 0.1 * column.height;
        for (&(x, y), &u) in points.iter().zip(displacement) {
            let k = ((y - column.base) / band).floor();
            if u < UNDEFORMED_DISPLACEMENT * column.height && (0.0..10.0).contains(&k) {
                let edge = &mut edges[k as usize];
                *edge = Some(Real::max(edge.unwrap_or(Real::MIN), x + 0.5 * dx));
            }
        }
        let simulated_line: Vec<(Real, Real)> = edges
            .iter()
            .enumerate()
            .filter_map(|(k, edge)| edge.map(|x| (x - column.wall, (k as Real + 0.5) * band)))
            .collect();
        let line = failure_line();
        let measured_line: Vec<(Real, Real)> =
            line.x.iter().copied().zip(line.y.iter().copied()).collect();
        Self {
            surface_error: (squares / norm).sqrt(),
            surface,
            toe: (
                last.runout,
                measured_toe(&measured, column.height, TOE_THICKNESS * column.height),
            ),
            grain_toe: (last.grain_toe, measured_grain_toe()),
            height_at_wall: (last.height_at_wall, measured.y[0]),
            failure_line: (
                FailureLine::fit(&simulated_line),
                FailureLine::fit(&measured_line).expect("the stored failure line falls"),
            ),
        }
    }
}

/// The largest x at which the area under `surface` over [x − H/10, x] is `thickness` · H/10
/// (the rule of [`Column::toe`] for a measured curve), by bisection on each segment.
pub fn measured_toe(surface: &ReferenceCurve, height: Real, thickness: Real) -> Real {
    let window = 0.1 * height;
    let area_behind = |x: Real| integrate(surface, x - window, x) - thickness * window;
    let (first, last) = (surface.x[0], *surface.x.last().expect("a measured surface"));
    let step = 0.25 * window;
    let mut high = last;
    if area_behind(high) >= 0.0 {
        return high;
    }
    // Walk back to a point with enough soil behind it, then bisect.
    while area_behind(high - step) < 0.0 {
        high -= step;
        if high - step < first + window {
            return first + window;
        }
    }
    let mut low = high - step;
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if area_behind(mid) >= 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}

/// ∫_a^b of the piecewise-linear `curve` (zero outside its points).
fn integrate(curve: &ReferenceCurve, a: Real, b: Real) -> Real {
    let value = |x: Real| curve.at(x).unwrap_or(0.0);
    // The curve's points inside (a, b) and the ends: exact for a piecewise-linear curve.
    let mut nodes: Vec<Real> = std::iter::once(a)
        .chain(curve.x.iter().copied().filter(|&x| x > a && x < b))
        .chain(std::iter::once(b))
        .collect();
    nodes.dedup();
    nodes
        .windows(2)
        .map(|w| 0.5 * (value(w[0]) + value(w[1])) * (w[1] - w[0]))
        .sum()
}

impl std::fmt::Display for ExperimentComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (line, measured_line) = self.failure_line;
        writeln!(
            f,
            "experiment         Bui et al. (2008), final surface and failure line (data/validation/)"
        )?;
        writeln!(
            f,
            "  surface error    P_d = {:.1} % over {} points (Feng et al. 2021, eq. 46)",
            100.0 * self.surface_error,
            self.surface.len()
        )?;
        writeln!(
            f,
            "  toe              {:.4} m, experiment {:.4} m ({:+.1} %)",
            self.toe.0,
            self.toe.1,
            100.0 * (self.toe.0 / self.toe.1 - 1.0)
        )?;
        writeln!(
            f,
            "  grain toe        {:.4} m, experiment {:.4} m ({:+.1} %; the measured surface is 1-3 mm high there, read to +-1.5 mm)",
            self.grain_toe.0,
            self.grain_toe.1,
            100.0 * (self.grain_toe.0 / self.grain_toe.1 - 1.0)
        )?;
        writeln!(
            f,
            "  height at wall   {:.4} m, experiment {:.4} m",
            self.height_at_wall.0, self.height_at_wall.1
        )?;
        match line {
            Some(line) => write!(
                f,
                "  failure line     {:.1}° meeting the floor at {:.3} m, experiment {:.1}° at {:.3} m",
                line.angle_deg, line.foot, measured_line.angle_deg, measured_line.foot
            ),
            None => write!(
                f,
                "  failure line     none (no particle moved less than {} H), experiment {:.1}° at {:.3} m",
                UNDEFORMED_DISPLACEMENT, measured_line.angle_deg, measured_line.foot
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_experiment_is_complete() {
        let surface = final_surface();
        assert_eq!(surface.x.len(), 27);
        assert_eq!((surface.y[0], surface.x[26]), (0.1, 0.52));
        let line = FailureLine::fit(&{
            let l = failure_line();
            l.x.into_iter().zip(l.y).collect::<Vec<_>>()
        })
        .unwrap();
        assert!((line.angle_deg - 33.09).abs() < 0.01 && (line.foot - 0.180).abs() < 1e-3);
    }

    #[test]
    fn measured_toe_applies_the_deposit_rule_to_the_curve() {
        // A wedge falling linearly from 0.1 m at x = 0 to 0 at x = 0.4 m: the mean height
        // over [x − 0.01, x] is 0.1 (0.4 − x + 0.005)/0.4 = 0.01 at x = 0.365 m.
        let wedge = ReferenceCurve {
            x: vec![0.0, 0.4, 0.5],
            y: vec![0.1, 0.0, 0.0],
        };
        assert!((measured_toe(&wedge, 0.1, 0.01) - 0.365).abs() < 1e-9);
        assert!((integrate(&wedge, 0.3, 0.5) - 0.5 * 0.1 * 0.025).abs() < 1e-12);
    }
}
