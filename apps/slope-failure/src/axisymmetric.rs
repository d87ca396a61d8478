//! The collapse of an axisymmetric column in 3D: a cylinder of soil, radius r₀ and height h₀
//! (aspect ratio a = h₀/r₀), released on a horizontal floor and spreading in every direction,
//! against the runout law of Lube, Huppert, Sparks & Hallworth (2004, J. Fluid Mech.
//! 508:175–199).
//!
//! Lube et al. released cylinders of dry sand and salt (and, for comparison, couscous, rice and
//! sugar; radii 1.7–9.7 cm) on wood, baize, Plexiglas and sandpaper and found the deposit's
//! final radius r∞ independent of the material and the floor (Lube et al. 2004, ICTAM
//! proceedings summary):
//! - (r∞ − r₀)/r₀ = 1.24 a for a ≤ 1.7 and 1.6 a^½ above ([`runout_ratio`]; as quoted by
//!   Staron & Hinch 2005, J. Fluid Mech. 545:1–27, and Szewc 2016, Granular Matter 18:42; the two
//!   branches meet at a = 1.7 within 1.1 %).
//!
//! The simulated r∞ is the deposit's grain toe about the column's axis
//! ([`AxisymmetricColumn::toe`]): the outermost radius where the deposit still covers its ring
//! one particle layer thick, as the 2D column's grain toe ([`crate::Column::grain_toe`]).

use geosph_core::{Particles, Real};
use geosph_runner::{Observer, RunOptions, Summary, push_records, take_records};
use geosph_scene::Scene;

use crate::Error;

/// The aspect ratio where the two branches of the runout law of Lube et al. (2004) meet.
pub const CROSSOVER_ASPECT_RATIO: Real = 1.7;

/// (r∞ − r₀)/r₀ at aspect ratio `a` (Lube et al. 2004): 1.24 a up to
/// [`CROSSOVER_ASPECT_RATIO`], 1.6 a^½ above.
pub fn runout_ratio(a: Real) -> Real {
    if a <= CROSSOVER_ASPECT_RATIO {
        1.24 * a
    } else {
        1.6 * a.sqrt()
    }
}

/// The initial column: its vertical axis, radius and height, from the soil particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisymmetricColumn {
    /// (x, y) of the vertical axis: the particles' mean.
    pub axis: [Real; 2],
    /// Radius r₀: that of the cylinder of height h₀ and the particles' volume N dx³.
    pub radius: Real,
    /// Height h₀: from the lowest particle's bottom to the highest particle's top.
    pub height: Real,
    /// z of the floor the column stands on (the lowest particle's bottom).
    pub base: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// Whether the particles fill a vertical cylinder: their outermost distance from the axis
    /// plus dx/2 is r₀ within dx (a box, a slope or a terrain slide is not one, and no law
    /// is compared).
    pub cylinder: bool,
}

impl AxisymmetricColumn {
    /// The column made of the 3D soil particles at `position` with spacing `dx`; `None` for no
    /// particles.
    pub fn of<const D: usize>(position: &[geosph_core::Vector<D>], dx: Real) -> Option<Self> {
        if D != 3 || position.is_empty() {
            return None;
        }
        let n = position.len() as Real;
        let axis = [0, 1].map(|k| position.iter().map(|x| x[k]).sum::<Real>() / n);
        let low = position
            .iter()
            .map(|x| x[2])
            .fold(Real::INFINITY, Real::min);
        let high = position
            .iter()
            .map(|x| x[2])
            .fold(Real::NEG_INFINITY, Real::max);
        let height = high - low + dx;
        // The cylinder of the particles' volume N dx³: the lattice's outermost sites lie up to
        // dx/2 inside the circle they fill.
        let radius = (n * dx.powi(3) / (std::f64::consts::PI * height)).sqrt();
        let outermost = position
            .iter()
            .map(|x| (x[0] - axis[0]).hypot(x[1] - axis[1]))
            .fold(0.0, Real::max);
        Some(Self {
            axis,
            radius,
            cylinder: (outermost + 0.5 * dx - radius).abs() <= dx,
            height,
            base: low - 0.5 * dx,
            spacing: dx,
        })
    }

    /// The aspect ratio a = h₀/r₀.
    pub fn aspect_ratio(&self) -> Real {
        self.height / self.radius
    }

    /// The distance of (x, y) from the axis.
    pub fn radial<const D: usize>(&self, x: &geosph_core::Vector<D>) -> Real {
        (x[0] - self.axis[0]).hypot(x[1] - self.axis[1])
    }

    /// The grain toe of particles at radii `r_descending` (sorted in descending order): the
    /// outer edge (r + dx/2) of the outermost particle that has, within b = h₀/10 inside it,
    /// enough particles to cover the ring r − b … r one layer (dx) thick,
    /// ⌈π b (2r − b) / dx²⌉ (itself included). Zero if no particle qualifies.
    pub fn toe(&self, r_descending: &[Real]) -> Real {
        let dx = self.spacing;
        let window = 0.1 * self.height;
        r_descending
            .iter()
            .enumerate()
            .find(|&(i, &r)| {
                let ring = std::f64::consts::PI * window * (2.0 * r - window).max(window);
                let needed = (ring / (dx * dx) - 1e-9).ceil().max(1.0) as usize;
                r_descending
                    .get(i + needed - 1)
                    .is_some_and(|&inner| r - inner <= window)
            })
            .map_or(0.0, |(_, &r)| r + 0.5 * dx)
    }
}

/// One sample of an axisymmetric collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialSample {
    /// t in s.
    pub time: Real,
    /// The deposit's radius r: the grain toe ([`AxisymmetricColumn::toe`]).
    pub runout: Real,
    /// The farthest particle's distance from the axis plus dx/2 (single particles count).
    pub farthest: Real,
    /// Height of the soil on the axis: the top of the particles within dx of it, climbing
    /// from the floor without a gap of 2 dx, plus dx/2, above the base.
    pub height: Real,
}

/// Samples the deposit's radius and its height on the axis; the column is taken from the first
/// sample.
#[derive(Clone, Debug, Default)]
pub struct RadialDeposit {
    /// Particle spacing dx.
    spacing: Real,
    /// The initial column, known from the first sample.
    pub column: Option<AxisymmetricColumn>,
    radii: Vec<Real>,
    heights: Vec<Real>,
    /// The samples so far.
    pub samples: Vec<RadialSample>,
}

impl RadialDeposit {
    /// A tracker for a soil of spacing `dx`.
    pub fn new(dx: Real) -> Self {
        Self {
            spacing: dx,
            ..Self::default()
        }
    }
}

impl<const D: usize> Observer<D> for RadialDeposit {
    fn columns(&self) -> Vec<&'static str> {
        vec!["radial_runout", "radial_farthest", "height_at_axis"]
    }

    fn sample(&mut self, time: Real, soil: &Particles<D>, row: &mut Vec<Real>) {
        let dx = self.spacing;
        if self.column.is_none() {
            self.column = AxisymmetricColumn::of(&soil.position, dx);
        }
        let Some(column) = self.column else {
            row.extend_from_slice(&[Real::NAN; 3]);
            return;
        };
        self.radii.clear();
        self.radii
            .extend(soil.position.iter().map(|x| column.radial(x)));
        self.radii.sort_by(|a, b| b.total_cmp(a));
        let runout = column.toe(&self.radii);
        let farthest = self.radii.first().map_or(0.0, |r| r + 0.5 * dx);
        self.heights.clear();
        self.heights.extend(
            soil.position
                .iter()
                .filter(|x| column.radial(*x) < dx)
                .map(|x| x[D - 1]),
        );
        self.heights.sort_by(Real::total_cmp);
        // From the centre of the first layer on the floor up, without a gap of 2 dx.
        let mut top = None;
        for &z in &self.heights {
            if z - top.unwrap_or(column.base + 0.5 * dx) > 2.0 * dx {
                break;
            }
            top = Some(z);
        }
        let height = top.map_or(0.0, |z| z + 0.5 * dx - column.base);
        row.extend_from_slice(&[runout, farthest, height]);
        self.samples.push(RadialSample {
            time,
            runout,
            farthest,
            height,
        });
    }

    fn save_state(&self) -> Vec<Real> {
        let mut state = Vec::new();
        push_records(
            &mut state,
            self.column.iter().map(AxisymmetricColumn::record),
        );
        push_records(&mut state, self.samples.iter().map(RadialSample::record));
        state
    }

    fn restore_state(&mut self, mut state: &[Real]) -> Result<(), String> {
        self.column = take_records(&mut state)?.first().map(
            |&[x, y, radius, height, base, spacing, cylinder]| AxisymmetricColumn {
                axis: [x, y],
                radius,
                height,
                base,
                spacing,
                cylinder: cylinder != 0.0,
            },
        );
        self.samples = take_records(&mut state)?
            .into_iter()
            .map(|[time, runout, farthest, height]| RadialSample {
                time,
                runout,
                farthest,
                height,
            })
            .collect();
        if state.is_empty() {
            Ok(())
        } else {
            Err("the radial deposit series in the checkpoint has another layout".into())
        }
    }
}

impl RadialSample {
    fn record(&self) -> [Real; 4] {
        [self.time, self.runout, self.farthest, self.height]
    }
}

impl AxisymmetricColumn {
    fn record(&self) -> [Real; 7] {
        [
            self.axis[0],
            self.axis[1],
            self.radius,
            self.height,
            self.base,
            self.spacing,
            Real::from(u8::from(self.cylinder)),
        ]
    }
}

/// The result of an axisymmetric collapse ([`run`]).
#[derive(Clone, Debug)]
pub struct AxisymmetricReport {
    /// The runner's summary.
    pub summary: Summary,
    /// The initial column.
    pub column: AxisymmetricColumn,
    /// The deposit at every sample time.
    pub samples: Vec<RadialSample>,
    /// The final sample.
    pub last: RadialSample,
}

impl AxisymmetricReport {
    /// The simulated (r∞ − r₀)/r₀: the final sample's grain toe.
    pub fn runout_ratio(&self) -> Real {
        (self.last.runout - self.column.radius) / self.column.radius
    }

    /// (r∞ − r₀)/r₀ of the law of Lube et al. (2004) at the column's aspect ratio.
    pub fn law(&self) -> Real {
        runout_ratio(self.column.aspect_ratio())
    }
}

impl std::fmt::Display for AxisymmetricReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let column = &self.column;
        writeln!(
            f,
            "column             axisymmetric: r0 = {:.4} m, h0 = {:.4} m, a = {:.2}, dx = {} m ({:.0} particles across r0)",
            column.radius,
            column.height,
            column.aspect_ratio(),
            column.spacing,
            column.radius / column.spacing
        )?;
        writeln!(
            f,
            "final radius       {:.4} m about the axis ((r - r0)/r0 = {:.3}; grain toe, one layer thick); farthest particle {:.4} m",
            self.last.runout,
            self.runout_ratio(),
            self.last.farthest
        )?;
        if column.cylinder {
            writeln!(
                f,
                "  vs Lube et al. (2004)  (r - r0)/r0 = {:.3} at a = {:.2}: {:+.1} %",
                self.law(),
                column.aspect_ratio(),
                100.0 * (self.runout_ratio() / self.law() - 1.0)
            )?;
        } else {
            writeln!(
                f,
                "  the soil is not a vertical cylinder: no axisymmetric law compared"
            )?;
        }
        write!(
            f,
            "height on the axis {:.4} m (h/r0 = {:.3}, h/h0 = {:.3})",
            self.last.height,
            self.last.height / column.radius,
            self.last.height / column.height
        )
    }
}

/// Runs the 3D `scene` whose soil is an axisymmetric column on a floor and measures its
/// deposit radially about the column's axis (the runner's `diagnostics.csv` gets the columns
/// radial_runout, radial_farthest and height_at_axis).
pub fn run(scene: &Scene, options: &RunOptions) -> Result<AxisymmetricReport, Error> {
    if scene.dimension != 3 {
        return Err(Error::Scene(
            "an axisymmetric column is a 3D scene (dimension: 3)".into(),
        ));
    }
    let mut tracker = RadialDeposit::new(scene.dx);
    let summary = geosph_runner::run(scene, options, &mut tracker)?;
    let (Some(column), Some(&last)) = (tracker.column, tracker.samples.last()) else {
        return Err(Error::Scene("the run produced no sample".into()));
    };
    Ok(AxisymmetricReport {
        summary,
        column,
        samples: tracker.samples,
        last,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Vector;

    #[test]
    fn the_law_is_continuous_at_the_crossover() {
        let a = CROSSOVER_ASPECT_RATIO;
        let (below, above) = (1.24 * a, 1.6 * a.sqrt());
        assert!((below - above).abs() / above < 0.011);
        assert_eq!(runout_ratio(1.0), 1.24);
    }

    /// A lattice disc one layer thick of radius R: the toe is its edge (within dx); with a
    /// ring of sparse particles outside it the toe stays there.
    #[test]
    fn the_toe_of_a_disc_is_its_edge_and_ignores_sparse_particles() {
        let dx = 0.01;
        let radius = 0.3;
        let mut position = Vec::new();
        let n = (radius / dx) as i64 + 1;
        for i in -n..n {
            for j in -n..n {
                let (x, y) = ((i as Real + 0.5) * dx, (j as Real + 0.5) * dx);
                if x.hypot(y) < radius {
                    position.push(Vector::<3>::new(x, y, 0.5 * dx));
                }
            }
        }
        // The column's geometry for a 0.1 m tall column of the same axis.
        let column = AxisymmetricColumn {
            axis: [0.0, 0.0],
            radius: 0.1,
            height: 0.1,
            base: 0.0,
            spacing: dx,
            cylinder: true,
        };
        let toe = |position: &[Vector<3>]| {
            let mut r: Vec<Real> = position.iter().map(|x| column.radial(x)).collect();
            r.sort_by(|a, b| b.total_cmp(a));
            column.toe(&r)
        };
        assert!((toe(&position) - radius).abs() <= dx, "{}", toe(&position));
        // Eight particles on a circle of radius 0.5 m.
        for k in 0..8 {
            let angle = k as Real * std::f64::consts::FRAC_PI_4;
            position.push(Vector::<3>::new(
                0.5 * angle.cos(),
                0.5 * angle.sin(),
                0.005,
            ));
        }
        assert!((toe(&position) - radius).abs() <= dx);
        let measured = AxisymmetricColumn::of(&position[..1], dx).unwrap();
        assert_eq!(measured.height, dx);
    }

    /// Lattice sites of spacing dx in the box `[-half, half]² × [0, height]` whose distance
    /// from the z axis is below `radius`.
    fn lattice(half: Real, height: Real, radius: Real, dx: Real) -> Vec<Vector<3>> {
        let (n, layers) = ((half / dx).round() as i64, (height / dx).round() as i64);
        let mut position = Vec::new();
        for k in 0..layers {
            for j in -n..n {
                for i in -n..n {
                    let x = Vector::<3>::new(
                        (i as Real + 0.5) * dx,
                        (j as Real + 0.5) * dx,
                        (k as Real + 0.5) * dx,
                    );
                    if x[0].hypot(x[1]) < radius {
                        position.push(x);
                    }
                }
            }
        }
        position
    }

    #[test]
    fn a_cylinder_is_measured_and_a_box_is_not_one() {
        let dx = 0.01;
        let cylinder = AxisymmetricColumn::of(&lattice(0.1, 0.1, 0.1, dx), dx).unwrap();
        assert!(cylinder.cylinder);
        assert!(
            (cylinder.radius - 0.1).abs() < 0.01 * 0.1,
            "{}",
            cylinder.radius
        );
        assert!((cylinder.height - 0.1).abs() < 1e-12);
        assert!((cylinder.aspect_ratio() - 1.0).abs() < 0.01);
        let square = AxisymmetricColumn::of(&lattice(0.1, 0.1, 1.0, dx), dx).unwrap();
        assert!(!square.cylinder);
    }

    /// The series and the column survive a checkpoint: restored into a fresh tracker, the
    /// state saves to the same numbers.
    #[test]
    fn the_radial_series_is_restored_from_its_saved_state() {
        let dx = 0.01;
        let soil = Particles::at_rest(lattice(0.1, 0.1, 0.1, dx), 1.0, 1000.0);
        let mut tracker = RadialDeposit::new(dx);
        let mut row = Vec::new();
        for time in [0.0, 0.1] {
            Observer::<3>::sample(&mut tracker, time, &soil, &mut row);
        }
        let state = Observer::<3>::save_state(&tracker);
        let mut restored = RadialDeposit::new(dx);
        Observer::<3>::restore_state(&mut restored, &state).unwrap();
        assert_eq!(restored.column, tracker.column);
        assert_eq!(restored.samples, tracker.samples);
        // The column's height on its axis: ten layers.
        assert!((tracker.samples[1].height - 0.1).abs() < 1e-12);
        assert!(Observer::<3>::restore_state(&mut restored, &state[..state.len() - 1]).is_err());
    }
}
