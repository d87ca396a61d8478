//! `slope-failure --aspect-ratios`: columns of the aluminium bars of the default scene at
//! aspect ratios a = 0.5, 1, 2 and 4 in turn ([`column_scene`]), each into its own folder
//! `bar-column-a<a>`, and their deposits side by side against the experiments:
//! `aspect-ratios.csv` and `aspect-ratios.png` (the normalised run-out
//! d∞/d₀ and final height h∞/h₀ against a, with the laws of Nguyen et al. 2015,
//! [`crate::nguyen2015`], and the measured deposit of Bui et al. 2008 at a = 0.5).

use std::path::Path;

use geosph_core::Real;
use geosph_io::{Axes, PlotSpec, Series, line_plot_png, write_csv_atomically};
use geosph_runner::RunOptions;
use geosph_scene::{Region, Scene, SolverSpec, WallSpec};
use geosph_soil::sph::ReleaseBox;

use crate::{DEFAULT_SCENE, Error, Report, bui2008, nguyen2015};

/// The aspect ratios a = h₀/d₀ of the series: the experiment of Bui et al. (2008), 0.5, and
/// three in the range of the laws of Nguyen et al. (2015), a ≥ 0.65 (the issue asks for
/// a = 1, 2 and one larger).
pub const ASPECT_RATIOS: [Real; 4] = [0.5, 1.0, 2.0, 4.0];

/// The collapse of a column of the bars with aspect ratio `a`: the default scene (Bui et al.
/// 2008, a = 0.5) with the column h₀ = 0.1 m high up to a = 1 and 0.2 m above (the tall
/// column's), d₀ = h₀/a long, its retaining wall and released region moved to x = d₀, and a
/// tank 1.5 times the experiments' run-out long (at least the default's 0.7 m).
pub fn column_scene(a: Real) -> Scene {
    let mut scene = Scene::from_ron(DEFAULT_SCENE).expect("the default scene parses");
    let height = if a <= 1.0 { 0.1 } else { 0.2 };
    let length = height / a;
    let tank = Real::max(
        0.7,
        1.5 * length * nguyen2015::runout_ratio(a).unwrap_or(0.0),
    );
    scene.name = format!("bar-column-a{a}");
    if let Some(soil) = scene.fluid.as_mut() {
        soil.blocks[0] = Region::Box {
            min: vec![0.0, 0.0],
            max: vec![length, height],
        };
    }
    // The default scene's walls: the tank and one polyline, the retaining wall.
    for wall in &mut scene.walls {
        match wall {
            WallSpec::Tank { max, .. } => *max = vec![tank, height + 0.15],
            WallSpec::Polyline { points, .. } => {
                *points = vec![(length, 0.0), (length, height + 0.02)];
            }
            WallSpec::Mesh { .. } => unreachable!("the default scene has no mesh wall"),
        }
    }
    if let SolverSpec::Soil(config) = &mut scene.solver
        && let Some(stage) = config.geostatic.as_mut()
    {
        stage.release = vec![ReleaseBox {
            min: vec![length, 0.0],
            max: vec![length + 0.1, height + 0.1],
        }];
    }
    scene
}

/// Runs the column of every aspect ratio of [`ASPECT_RATIOS`] ([`column_scene`]) with the
/// spacing `dx` (else the scene's) into `out/<scene name>/` and writes the series' table and
/// plot into `out`; `started` is told each scene before it runs.
pub fn run(
    dx: Option<Real>,
    options: &RunOptions,
    started: &mut dyn FnMut(&Scene),
) -> Result<Vec<Report>, Error> {
    let mut reports = Vec::with_capacity(ASPECT_RATIOS.len());
    for a in ASPECT_RATIOS {
        let mut scene = column_scene(a);
        if let Some(dx) = dx {
            scene.dx = dx;
        }
        let mut options = options.clone();
        options.out_dir = options.out_dir.map(|dir| dir.join(&scene.name));
        started(&scene);
        reports.push(crate::run(&scene, &options)?);
    }
    if let Some(dir) = &options.out_dir {
        write_series(dir, &reports)?;
    }
    Ok(reports)
}

fn write_series(dir: &Path, reports: &[Report]) -> Result<(), Error> {
    let rows: Vec<_> = reports
        .iter()
        .filter_map(|report| report.aspect_ratio)
        .collect();
    let nan = Real::NAN;
    write_csv_atomically(
        dir.join("aspect-ratios.csv"),
        &[
            "a",
            "final_height_ratio",
            "final_height_ratio_experiments",
            "runout_ratio_grain_toe",
            "runout_ratio_experiments",
            "runout_ratio_experiments_spread_law",
            "runout_ratio_deposit_toe",
            "runout_ratio_farthest",
        ],
        rows.iter().map(|row| {
            [
                row.aspect_ratio,
                row.final_height.0,
                row.final_height.1,
                row.runout.0,
                row.runout.1.unwrap_or(nan),
                row.runout.2.unwrap_or(nan),
                row.other_runouts.0,
                row.other_runouts.1,
            ]
        }),
    )?;
    let a: Vec<Real> = rows.iter().map(|row| row.aspect_ratio).collect();
    let runout: Vec<Real> = rows.iter().map(|row| row.runout.0).collect();
    let height: Vec<Real> = rows.iter().map(|row| row.final_height.0).collect();
    // From just above a = 0.65, where the height law begins (h∞ = h₀ at and below).
    let (low, high) = (nguyen2015::LOW_ASPECT_RATIO + 1e-6, 6.0);
    let law_a: Vec<Real> = (0..=40)
        .map(|k| low * (high / low).powf(k as Real / 40.0))
        .collect();
    let law_runout: Vec<Real> = law_a
        .iter()
        .map(|&a| nguyen2015::runout_ratio(a).unwrap_or(nan))
        .collect();
    let law_height: Vec<Real> = law_a
        .iter()
        .map(|&a| nguyen2015::final_height_ratio(a))
        .collect();
    let bui_runout = bui2008::measured_grain_toe() / bui2008::COLUMN_LENGTH;
    let bui_height = bui2008::final_surface().y[0] / bui2008::COLUMN_HEIGHT;
    line_plot_png(
        dir.join("aspect-ratios.png"),
        &PlotSpec {
            title: "Aluminium-bar columns: run-out and final height against aspect ratio",
            x_label: "aspect ratio a = h0/d0",
            y_label: "d/d0 (run-out), h/h0 (final height)",
            lines: vec![
                Series {
                    label: "experiments, d/d0 = 4.30 a^0.72 (Nguyen et al. 2015)",
                    x: &law_a,
                    y: &law_runout,
                },
                Series {
                    label: "experiments, h/h0 = 1/(1.42 a^(2/3)) (Nguyen et al. 2015)",
                    x: &law_a,
                    y: &law_height,
                },
            ],
            points: vec![
                Series {
                    label: "geosph, d/d0 (grain toe)",
                    x: &a,
                    y: &runout,
                },
                Series {
                    label: "geosph, h/h0 (at the wall)",
                    x: &a,
                    y: &height,
                },
                Series {
                    label: "experiment a = 0.5, d/d0 (Bui et al. 2008)",
                    x: &[0.5],
                    y: &[bui_runout],
                },
                Series {
                    label: "experiment a = 0.5, h/h0 (Bui et al. 2008)",
                    x: &[0.5],
                    y: &[bui_height],
                },
            ],
            x_range: Some((0.3, 10.0)),
            y_range: Some((0.1, 100.0)),
            axes: Axes::LogLog,
            ..Default::default()
        },
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_scenes_are_valid_and_of_their_aspect_ratio() {
        for a in ASPECT_RATIOS {
            let scene = column_scene(a);
            scene.validate().unwrap_or_else(|e| panic!("a = {a}: {e}"));
            let column = crate::Column::of(&scene).unwrap();
            assert!((column.height / column.length - a).abs() < 1e-12);
            assert!(bui2008::is_aluminium_bars(&scene));
        }
        let bui = column_scene(0.5);
        assert!(bui2008::is_experiment(
            &bui,
            &crate::Column::of(&bui).unwrap()
        ));
    }
}
