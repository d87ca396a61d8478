//! The files of a run: `runout.csv`, `runout.png`, `deposit.csv` and `deposit.png`.

use std::path::Path;

use geosph_core::Real;
use geosph_io::{PlotSpec, Series, line_plot_png, write_csv_atomically};

use crate::{
    AspectRatioComparison, Column, Error, ExperimentComparison, RunoutTracker, Sample, bui2008,
};

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

pub(crate) fn write_outputs(
    dir: &Path,
    column: &Column,
    tracker: &RunoutTracker,
    experiment: Option<&ExperimentComparison>,
    aspect_ratio: Option<&AspectRatioComparison>,
) -> Result<(), Error> {
    let samples = &tracker.samples;
    write_csv_atomically(
        dir.join("runout.csv"),
        &Sample::COLUMNS,
        samples.iter().map(Sample::record),
    )?;
    let t: Vec<Real> = samples.iter().map(|s| s.time).collect();
    let runout: Vec<Real> = samples.iter().map(|s| s.runout).collect();
    let front: Vec<Real> = samples.iter().map(|s| s.front).collect();
    let grain_toe: Vec<Real> = samples.iter().map(|s| s.grain_toe).collect();
    let height: Vec<Real> = samples.iter().map(|s| s.height_at_wall).collect();
    line_plot_png(
        dir.join("runout.png"),
        &PlotSpec {
            title: "Runout and soil height at the wall",
            x_label: "t (s)",
            y_label: "distance from the wall / height (m)",
            lines: vec![
                Series {
                    label: "runout (deposit toe)",
                    x: &t,
                    y: &runout,
                },
                Series {
                    label: "farthest particles",
                    x: &t,
                    y: &front,
                },
                Series {
                    label: "grain toe (one grain or one particle layer thick)",
                    x: &t,
                    y: &grain_toe,
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
    write_csv_atomically(
        dir.join("deposit.csv"),
        &["x", "height", "displacement"],
        tracker
            .latest
            .iter()
            .zip(&tracker.displacement)
            .map(|(&(x, y), &u)| [x, y, u]),
    )?;
    let (x0, y0) = surface_profile(&tracker.initial, column.spacing);
    let (x1, y1) = surface_profile(&tracker.latest, column.spacing);
    let mut lines = vec![
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
    ];
    // The experiment is drawn in the scene's coordinates (its x is from the back wall).
    let offset =
        |values: &[Real], by: Real| -> Vec<Real> { values.iter().map(|v| v + by).collect() };
    let measured = experiment.map(|_| {
        let (surface, line) = (bui2008::final_surface(), bui2008::failure_line());
        (
            offset(&surface.x, column.wall),
            offset(&surface.y, column.base),
            offset(&line.x, column.wall),
            offset(&line.y, column.base),
        )
    });
    if let Some((sx, sy, lx, ly)) = &measured {
        lines.push(Series {
            label: "experiment, final surface (Bui et al. 2008)",
            x: sx,
            y: sy,
        });
        lines.push(Series {
            label: "experiment, failure line",
            x: lx,
            y: ly,
        });
    }
    // The laws of Nguyen et al. (2015): the run-out on the floor, the final height at the wall.
    let laws = aspect_ratio.and_then(|comparison| {
        let runout = comparison.runout.1?;
        Some((
            [column.wall + runout * column.length, column.wall],
            [
                column.base,
                column.base + comparison.final_height.1 * column.height,
            ],
        ))
    });
    let points = laws
        .as_ref()
        .map(|(x, y)| {
            vec![Series {
                label: "experiments' run-out and final height (Nguyen et al. 2015)",
                x,
                y,
            }]
        })
        .unwrap_or_default();
    line_plot_png(
        dir.join("deposit.png"),
        &PlotSpec {
            title: "Deposit profile",
            x_label: "x (m)",
            y_label: "surface height (m)",
            lines,
            points,
            ..Default::default()
        },
    )?;
    Ok(())
}
