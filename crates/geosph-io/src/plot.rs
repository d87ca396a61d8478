//! Line plots as PNG images: simulation curves against reference data (experiments, analytical
//! solutions), e.g. a dam-break front position over time or an error against wall time.
//!
//! Drawn with `plotters` (bitmap backend, text by `ab_glyph` with the DejaVu Sans font embedded
//! by the `dejavu` crate, so no system fonts are needed) and encoded as PNG (W3C PNG
//! specification, <https://www.w3.org/TR/png/>) to a temporary file that then replaces the
//! target atomically.

use std::fmt::Display;
use std::path::Path;
use std::sync::Once;

use geosph_core::Real;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

use crate::{Error, replace_atomically};

/// How the axes map values to the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Axes {
    /// Both axes linear.
    #[default]
    Linear,
    /// Both axes logarithmic (power laws are straight lines, e.g. error against resolution or
    /// wall time). Points with a non-positive coordinate are left out.
    LogLog,
    /// Linear x, logarithmic y (exponential decay is a straight line, e.g. a residual against
    /// iterations). Points with a non-positive y are left out.
    LogY,
}

/// One named data series: the points `(x[i], y[i])`.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// Legend entry; an empty label leaves the series out of the legend.
    pub label: &'a str,
    /// Abscissae.
    pub x: &'a [Real],
    /// Ordinates, as many as abscissae.
    pub y: &'a [Real],
}

/// What [`line_plot_png`] draws.
///
/// Build with struct-update syntax: `PlotSpec { title: "…", lines: vec![…], ..Default::default() }`.
#[derive(Clone, Debug)]
pub struct PlotSpec<'a> {
    /// Caption above the plot.
    pub title: &'a str,
    /// Label of the x axis, with units, e.g. `"t (s)"`.
    pub x_label: &'a str,
    /// Label of the y axis, with units.
    pub y_label: &'a str,
    /// Series drawn as connected lines (simulation results), in the order given.
    pub lines: Vec<Series<'a>>,
    /// Series drawn as unconnected markers (reference data), drawn over the lines.
    pub points: Vec<Series<'a>>,
    /// Range of the x axis; `None` fits all data (for log axes: whole decades).
    pub x_range: Option<(Real, Real)>,
    /// Range of the y axis; `None` fits all data (for log axes: whole decades).
    pub y_range: Option<(Real, Real)>,
    /// Linear or logarithmic axes.
    pub axes: Axes,
    /// Image width and height in pixels.
    pub size: (u32, u32),
}

impl Default for PlotSpec<'_> {
    fn default() -> Self {
        Self {
            title: "",
            x_label: "",
            y_label: "",
            lines: Vec::new(),
            points: Vec::new(),
            x_range: None,
            y_range: None,
            axes: Axes::Linear,
            size: (1024, 768),
        }
    }
}

/// Tableau 10 colours, distinguishable and colour-blind friendly.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Font family name under which the embedded DejaVu Sans is registered.
const FONT: &str = "sans-serif";

/// Draws `spec` and writes it as a PNG image to `path` (extension `.png`), atomically.
///
/// # Errors
/// [`Error::Shape`] when a series has different numbers of x and y values, or a given range
/// is empty (or not positive on a log axis); [`Error::Plot`] when drawing or encoding fails.
pub fn line_plot_png(path: impl AsRef<Path>, spec: &PlotSpec<'_>) -> Result<(), Error> {
    let path = path.as_ref();
    for series in spec.lines.iter().chain(&spec.points) {
        if series.x.len() != series.y.len() {
            return Err(Error::Shape(format!(
                "{}: series `{}` has {} x values and {} y values",
                path.display(),
                series.label,
                series.x.len(),
                series.y.len()
            )));
        }
    }
    let (log_x, log_y) = match spec.axes {
        Axes::Linear => (false, false),
        Axes::LogLog => (true, true),
        Axes::LogY => (false, true),
    };
    let x_range = axis_range(path, "x", spec.x_range, log_x, spec.series_values(|s| s.x))?;
    let y_range = axis_range(path, "y", spec.y_range, log_y, spec.series_values(|s| s.y))?;
    register_fonts();
    replace_atomically(path, |temporary| match spec.axes {
        Axes::Linear => draw(path, temporary, spec, x_range, y_range),
        Axes::LogLog => draw(
            path,
            temporary,
            spec,
            x_range.log_scale(),
            y_range.log_scale(),
        ),
        Axes::LogY => draw(path, temporary, spec, x_range, y_range.log_scale()),
    })
}

impl<'a> PlotSpec<'a> {
    /// All values of one coordinate (selected by `coordinate`) over all series.
    fn series_values(
        &self,
        coordinate: fn(Series<'a>) -> &'a [Real],
    ) -> impl Iterator<Item = Real> + '_ {
        let series = self.lines.iter().chain(&self.points);
        series.flat_map(move |s| coordinate(*s).iter().copied())
    }

    /// Whether the point can be drawn on these axes.
    fn drawable(&self, (x, y): (Real, Real)) -> bool {
        let positive = |v: Real| v > 0.0;
        x.is_finite()
            && y.is_finite()
            && match self.axes {
                Axes::Linear => true,
                Axes::LogLog => positive(x) && positive(y),
                Axes::LogY => positive(y),
            }
    }
}

/// The given range (checked) or one fitted to the finite (on a log axis: positive) `values`.
fn axis_range(
    path: &Path,
    axis: &str,
    given: Option<(Real, Real)>,
    log: bool,
    values: impl Iterator<Item = Real>,
) -> Result<std::ops::Range<Real>, Error> {
    if let Some((low, high)) = given {
        return if low < high && (!log || low > 0.0) {
            Ok(low..high)
        } else {
            Err(Error::Shape(format!(
                "{}: {axis} range {low}..{high} is empty{}",
                path.display(),
                if log { " or not positive" } else { "" }
            )))
        };
    }
    let (low, high) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(low, high), v| {
            (low.min(v), high.max(v))
        });
    Ok(if low > high {
        // No data: a unit range.
        if log { 1.0..10.0 } else { 0.0..1.0 }
    } else if log {
        let low = 10.0_f64.powf(low.log10().floor());
        let high = 10.0_f64.powf(high.log10().ceil());
        if low < high {
            low..high
        } else {
            low..10.0 * high
        }
    } else {
        let pad = if high > low {
            0.05 * (high - low)
        } else {
            0.05 * high.abs().max(1.0)
        };
        (low - pad)..(high + pad)
    })
}

/// Tick label on a logarithmic axis: plain decimals from 0.001 to 9999, `1e-4` style beyond.
fn decade_label(value: &Real) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 || (1e-3..1e4).contains(&magnitude) {
        // Round away the noise of `10^k` computed in floating point, then print the shortest.
        let rounded: Real = format!("{value:.3e}").parse().unwrap_or(*value);
        format!("{rounded}")
    } else {
        let text = format!("{value:.2e}");
        // "1.00e-4" -> "1e-4", "2.50e5" -> "2.5e5"
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    }
}

/// Registers DejaVu Sans as the `sans-serif` family of plotters' text renderer, once.
fn register_fonts() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        for (style, bytes) in [
            (FontStyle::Normal, dejavu::sans::regular()),
            (FontStyle::Bold, dejavu::sans::bold()),
            (FontStyle::Oblique, dejavu::sans::oblique()),
        ] {
            // An invalid font would show up as a drawing error naming the missing font.
            let _ = plotters::style::register_font(FONT, style, bytes);
        }
    });
}

/// Draws the plot on the axes `x` × `y` and saves it as PNG to `temporary`.
fn draw<X, Y>(path: &Path, temporary: &Path, spec: &PlotSpec<'_>, x: X, y: Y) -> Result<(), Error>
where
    X: AsRangedCoord<Value = Real>,
    Y: AsRangedCoord<Value = Real>,
    X::CoordDescType: ValueFormatter<Real>,
    Y::CoordDescType: ValueFormatter<Real>,
{
    let fail = |error: &dyn Display| Error::Plot {
        path: path.to_path_buf(),
        reason: error.to_string(),
    };
    let root = BitMapBackend::new(temporary, spec.size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(spec.title, (FONT, 28))
        .margin(20)
        .margin_right(40)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(x, y)
        .map_err(|e| fail(&e))?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(spec.x_label)
        .y_desc(spec.y_label)
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .light_line_style(BLACK.mix(0.05))
        .bold_line_style(BLACK.mix(0.15));
    if matches!(spec.axes, Axes::LogLog) {
        mesh.x_label_formatter(&decade_label);
    }
    if matches!(spec.axes, Axes::LogLog | Axes::LogY) {
        mesh.y_label_formatter(&decade_label);
    }
    mesh.draw().map_err(|e| fail(&e))?;

    let drawable = |series: &Series<'_>| {
        let points = series.x.iter().copied().zip(series.y.iter().copied());
        points
            .filter(|point| spec.drawable(*point))
            .collect::<Vec<_>>()
    };
    for (index, series) in spec.lines.iter().enumerate() {
        let colour = PALETTE[index % PALETTE.len()];
        let style = colour.stroke_width(2);
        let annotation = chart
            .draw_series(LineSeries::new(drawable(series), style))
            .map_err(|e| fail(&e))?;
        if !series.label.is_empty() {
            annotation
                .label(series.label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
        }
    }
    for (index, series) in spec.points.iter().enumerate() {
        let colour = PALETTE[(spec.lines.len() + index) % PALETTE.len()];
        let style = colour.stroke_width(2);
        let data = drawable(series);
        // One marker shape per reference series: disc, triangle, cross, ring.
        let annotation = match index % 4 {
            0 => chart.draw_series(data.into_iter().map(|p| Circle::new(p, 5, style.filled()))),
            1 => chart.draw_series(
                data.into_iter()
                    .map(|p| TriangleMarker::new(p, 6, style.filled())),
            ),
            2 => chart.draw_series(data.into_iter().map(|p| Cross::new(p, 5, style))),
            _ => chart.draw_series(data.into_iter().map(|p| Circle::new(p, 5, colour))),
        }
        .map_err(|e| fail(&e))?;
        if !series.label.is_empty() {
            annotation.label(series.label).legend(move |(x, y)| {
                let centre = (x + 12, y);
                match index % 4 {
                    0 => Circle::new(centre, 5, style.filled()).into_dyn(),
                    1 => TriangleMarker::new(centre, 6, style.filled()).into_dyn(),
                    2 => Cross::new(centre, 5, style).into_dyn(),
                    _ => Circle::new(centre, 5, colour).into_dyn(),
                }
            });
        }
    }
    let labelled = spec.lines.iter().chain(&spec.points);
    if labelled.into_iter().any(|series| !series.label.is_empty()) {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 18))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .draw()
            .map_err(|e| fail(&e))?;
    }
    root.present().map_err(|e| fail(&e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::scratch_folder;

    const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

    #[test]
    fn linear_plot_with_lines_and_reference_points_is_a_png() {
        let folder = scratch_folder("plot-linear");
        let path = folder.join("front.png");
        let t: Vec<Real> = (0..50).map(|i| 0.05 * i as Real).collect();
        let front: Vec<Real> = t.iter().map(|t| 1.0 + 2.0 * t * t).collect();
        let coarse: Vec<Real> = t.iter().map(|t| 1.0 + 1.8 * t * t).collect();
        let experiment_t = [0.5, 1.0, 1.5, 2.0];
        let experiment_x = [1.4, 3.1, 5.3, 8.8];
        let spec = PlotSpec {
            title: "Dam break: surge front position",
            x_label: "t (s)",
            y_label: "front position x (m)",
            lines: vec![
                Series {
                    label: "SPH, dx = 0.01 m",
                    x: &t,
                    y: &front,
                },
                Series {
                    label: "SPH, dx = 0.02 m",
                    x: &t,
                    y: &coarse,
                },
            ],
            points: vec![Series {
                label: "Martin & Moyce (1952)",
                x: &experiment_t,
                y: &experiment_x,
            }],
            ..Default::default()
        };
        line_plot_png(&path, &spec).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.len() > 1000);
        assert_eq!(bytes[..8], PNG_SIGNATURE);
        assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 1);
        if std::env::var_os("GEOSPH_IO_KEEP_PLOTS").is_none() {
            std::fs::remove_dir_all(folder).unwrap();
        }
    }

    #[test]
    fn log_log_plot_fits_whole_decades() {
        let folder = scratch_folder("plot-loglog");
        let path = folder.join("convergence.png");
        let wall_time = [0.3, 2.0, 15.0, 110.0];
        let error = [3e-2, 8e-3, 2.1e-3, 5e-4];
        let reference = [0.0, 1.0, 10.0, 100.0]; // 0 cannot be shown and is left out
        let slope = [1e-2, 1e-2, 1e-3, 1e-4];
        let spec = PlotSpec {
            title: "L2 error of the hydrostatic pressure",
            x_label: "wall time (s)",
            y_label: "relative L2 error",
            lines: vec![Series {
                label: "WCSPH",
                x: &wall_time,
                y: &error,
            }],
            points: vec![Series {
                label: "",
                x: &reference,
                y: &slope,
            }],
            axes: Axes::LogLog,
            size: (640, 480),
            ..Default::default()
        };
        line_plot_png(&path, &spec).unwrap();
        assert_eq!(std::fs::read(&path).unwrap()[..8], PNG_SIGNATURE);
        let values = [0.3, 110.0, -1.0];
        assert_eq!(decade_label(&1e-4), "1e-4");
        assert_eq!(decade_label(&2.5e5), "2.5e5");
        assert_eq!(decade_label(&0.0010000000000000002), "0.001");
        assert_eq!(decade_label(&1000.0), "1000");
        let fitted = axis_range(&path, "x", None, true, values.into_iter()).unwrap();
        assert_eq!(fitted, 0.1..1000.0);
        if std::env::var_os("GEOSPH_IO_KEEP_PLOTS").is_none() {
            std::fs::remove_dir_all(folder).unwrap();
        }
    }

    #[test]
    fn mismatched_series_and_bad_ranges_are_errors() {
        let path = Path::new("never-drawn.png");
        let x = [1.0, 2.0];
        let y = [1.0];
        let spec = PlotSpec {
            lines: vec![Series {
                label: "a",
                x: &x,
                y: &y,
            }],
            ..Default::default()
        };
        assert!(matches!(line_plot_png(path, &spec), Err(Error::Shape(_))));
        let spec = PlotSpec {
            x_range: Some((0.0, 1.0)),
            axes: Axes::LogLog,
            ..Default::default()
        };
        assert!(matches!(line_plot_png(path, &spec), Err(Error::Shape(_))));
        assert!(!path.exists());
    }
}
