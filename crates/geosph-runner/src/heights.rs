//! Water-level gauges: the height of the free surface along vertical lines, sampled with the
//! diagnostics.

use geosph_core::{Real, Vector};
use geosph_scene::HeightSpec;

use crate::share::Share;

/// The scene's `output.heights`: at each sample, for each gauge, the top of the continuous
/// column of particles within one particle spacing dx of its vertical line (the last axis),
///
/// h = z_top + dx/2,
///
/// with z_top the highest particle reached climbing from the lowest one without a vertical gap
/// wider than 2 dx, so spray and droplets above the surface do not count; NaN where no
/// particle is near (a dry bed). dx/2 is the half-layer a particle stands for: a still layer
/// of n particles reads n dx. Like a wave gauge, it reads the top of the water over a finite
/// footprint (radius dx).
pub struct HeightGauges<const D: usize> {
    columns: Vec<String>,
    positions: Vec<Vec<Real>>,
    spacing: Real,
    /// Heights near the last gauge, kept to avoid an allocation per sample.
    column: Vec<Real>,
    /// (gauge, height) of this rank's particles near the lines, likewise.
    near: Vec<Real>,
}

impl<const D: usize> HeightGauges<D> {
    /// The gauges of a validated scene (D − 1 horizontal coordinates each) with particle
    /// spacing `spacing`.
    pub fn new(gauges: &[HeightSpec], spacing: Real) -> Self {
        Self {
            columns: gauges.iter().map(|g| format!("h_{}", g.name)).collect(),
            positions: gauges.iter().map(|g| g.position.clone()).collect(),
            spacing,
            column: Vec::new(),
            near: Vec::new(),
        }
    }

    /// The CSV column of each gauge, `h_<name>`.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Plots the levels against time from `diagnostics.csv` in `dir` into `heights.png`.
    pub fn plot(&self, dir: &std::path::Path) -> Result<(), geosph_io::Error> {
        crate::probes::plot_columns(
            dir,
            &self.columns,
            crate::probes::ColumnPlot {
                file: "heights.png",
                title: "Water levels",
                y_label: "h (m)",
                scale: 1.0,
                prefix: "h_",
            },
        )
    }

    /// Appends each gauge's height (m) to `row`. On several ranks the heights of the
    /// particles near the lines are gathered (one collective for all gauges) and sorted, so
    /// the levels are those of one process exactly.
    pub fn sample(&mut self, share: &Share<'_, D>, row: &mut Vec<Real>) {
        if self.positions.is_empty() {
            return;
        }
        let up = D - 1;
        let dx = self.spacing;
        // (gauge, height) of each particle near a line.
        self.near.clear();
        for (k, line) in self.positions.iter().enumerate() {
            let near = |x: &&Vector<D>| {
                let squared: Real = (0..up).map(|a| (x[a] - line[a]).powi(2)).sum();
                squared <= dx * dx
            };
            let heights = share.position().iter().filter(near);
            self.near.extend(heights.flat_map(|x| [k as Real, x[up]]));
        }
        let near = share.gather(&self.near);
        for k in 0..self.positions.len() {
            self.column.clear();
            self.column.extend(
                near.chunks_exact(2)
                    .filter(|pair| pair[0] == k as Real)
                    .map(|pair| pair[1]),
            );
            self.column.sort_by(Real::total_cmp);
            let top = (!self.column.is_empty()).then(|| first_top(&self.column, 2.0 * dx));
            row.push(top.map_or(Real::NAN, |z| z + 0.5 * dx));
        }
    }
}

/// The highest of the ascending `heights` reached from the lowest without a step wider than
/// `gap`.
fn first_top(heights: &[Real], gap: Real) -> Real {
    let mut top = heights[0];
    for &z in &heights[1..] {
        if z - top > gap {
            break;
        }
        top = z;
    }
    top
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Particles;

    #[test]
    fn a_layer_reads_its_depth_and_spray_above_it_does_not_count() {
        let dx = 0.1;
        // Columns of 5 particles at x = 0.05, 0.15, …; a droplet at x = 0.25, height 1.
        let mut position: Vec<Vector<2>> = (0..10)
            .flat_map(|i| {
                (0..5).map(move |j| Vector::<2>::new(i as Real + 0.5, j as Real + 0.5) * dx)
            })
            .collect();
        position.push(Vector::<2>::new(0.25, 1.0));
        let particles = Particles::at_rest(position, 1.0, 1000.0);
        let specs = [
            HeightSpec {
                name: "a".into(),
                position: vec![0.25],
            },
            HeightSpec {
                name: "dry".into(),
                position: vec![3.0],
            },
        ];
        let mut gauges = HeightGauges::<2>::new(&specs, dx);
        let mut row = Vec::new();
        gauges.sample(&Share::whole_run(&particles), &mut row);
        assert_eq!(gauges.columns(), ["h_a", "h_dry"]);
        assert!((row[0] - 0.5).abs() < 1e-12, "{row:?}");
        assert!(row[1].is_nan());
    }
}
