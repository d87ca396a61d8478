//! Pressure probes: the fluid's pressure at fixed points, sampled with the diagnostics.

use std::path::Path;

use geosph_core::{Real, Vector};
use geosph_io::{Error, PlotSpec, Series, line_plot_png};
use geosph_kernels::shepard::interpolation_sums;
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use geosph_scene::ProbeSpec;

use crate::share::Share;

/// Pressure gauges at fixed points (the scene's `output.probes`): at each sample, the Shepard
/// interpolant (Shepard 1968) of the particle pressures at each probe,
///
/// p(x) = Σ_j p_j V_j W(|x − x_j|) / Σ_j V_j W(|x − x_j|),  V_j = m_j / ρ_j,
///
/// over the fluid particles within the kernel's support of x, with the scene's kernel and
/// smoothing length; NaN where there is no fluid particle within it. Like the gauge of an
/// experiment, a probe averages over a finite area (radius 2h), so it does not read the
/// particle-scale alternation of the incompressible solvers' pressure
/// (`docs/incompressible.md`, "Still water"). A probe on a wall's face averages only the
/// fluid on its side of the wall, so it reads the pressure somewhat away from the face.
pub struct PressureProbes<const D: usize> {
    columns: Vec<String>,
    positions: Vec<Vector<D>>,
    kernel: KernelKind,
    smoothing_length: Real,
    /// V_j of the last sample, kept to avoid an allocation per sample.
    volume: Vec<Real>,
    /// Each probe's two Shepard sums of the last sample, likewise.
    sums: Vec<Real>,
}

impl<const D: usize> PressureProbes<D> {
    /// The probes of a validated scene (positions with D coordinates) with the scene's
    /// kernel and smoothing length.
    pub fn new(probes: &[ProbeSpec], kernel: KernelKind, smoothing_length: Real) -> Self {
        Self {
            columns: probes.iter().map(|p| format!("p_{}", p.name)).collect(),
            positions: probes
                .iter()
                .map(|p| Vector::<D>::from_iterator(p.position.iter().copied()))
                .collect(),
            kernel,
            smoothing_length,
            volume: Vec::new(),
            sums: Vec::new(),
        }
    }

    /// The CSV column of each probe, `p_<name>`.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Appends each probe's pressure (Pa) to `row`; NaN for a probe without fluid nearby, and
    /// for all when the fluid carries no pressure. On several ranks each rank sums over its
    /// own particles and the sums are added over the ranks (one collective for all probes).
    pub fn sample(&mut self, share: &Share<'_, D>, row: &mut Vec<Real>) {
        if self.positions.is_empty() {
            return;
        }
        let Some(pressure) = share.pressure() else {
            row.extend(self.positions.iter().map(|_| Real::NAN));
            return;
        };
        self.volume.clear();
        let (mass, density) = (share.mass(), share.density());
        self.volume
            .extend(mass.iter().zip(density).map(|(m, rho)| m / rho));
        self.sums.clear();
        for x in &self.positions {
            let probe = Probe {
                x,
                position: share.position(),
                volume: &self.volume,
                pressure,
            };
            let (weighted, weights) = self.kernel.dispatch(self.smoothing_length, probe);
            self.sums.extend_from_slice(&[weighted, weights]);
        }
        share.sum_each(&mut self.sums);
        row.extend(self.sums.chunks_exact(2).map(|sums| match sums {
            &[weighted, weights] if weights > 0.0 => weighted / weights,
            _ => Real::NAN,
        }));
    }
}

/// One probe's Shepard sums over a set of particles, run with whichever kernel the scene
/// names.
struct Probe<'a, const D: usize> {
    x: &'a Vector<D>,
    position: &'a [Vector<D>],
    volume: &'a [Real],
    pressure: &'a [Real],
}

impl<const D: usize> KernelVisitor<D> for Probe<'_, D> {
    type Output = (Real, Real);
    fn visit<K: Kernel<D>>(self, kernel: K) -> (Real, Real) {
        interpolation_sums(&kernel, self.x, self.position, self.volume, self.pressure)
    }
}

/// Plots every probe's pressure against time from `diagnostics.csv` in `dir` into
/// `probes.png` in kPa, one line per probe (samples without fluid at the probe left out). The
/// CSV holds the whole run, a restarted one included, so the plot does too.
pub fn plot_probes(dir: &Path, columns: &[String]) -> Result<(), Error> {
    plot_columns(
        dir,
        columns,
        ColumnPlot {
            file: "probes.png",
            title: "Pressure probes",
            y_label: "p (kPa)",
            scale: 1e-3,
            prefix: "p_",
        },
    )
}

/// How [`plot_columns`] draws its columns.
pub(crate) struct ColumnPlot<'a> {
    pub file: &'a str,
    pub title: &'a str,
    pub y_label: &'a str,
    /// Factor from the CSV's unit to the plot's.
    pub scale: Real,
    /// Left out of the columns' names in the legend.
    pub prefix: &'a str,
}

/// Plots `columns` of `diagnostics.csv` in `dir` against time into `plot.file`, one line per
/// column, non-finite samples left out; nothing when there is no column.
pub(crate) fn plot_columns(
    dir: &Path,
    columns: &[String],
    plot: ColumnPlot<'_>,
) -> Result<(), Error> {
    if columns.is_empty() {
        return Ok(());
    }
    let path = dir.join("diagnostics.csv");
    let text = std::fs::read_to_string(&path).map_err(|source| Error::Io {
        path: path.clone(),
        source,
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let index = |name: &str| header.iter().position(|h| *h == name);
    let (Some(time), Some(probes)) = (
        index("time"),
        columns.iter().map(|c| index(c)).collect::<Option<Vec<_>>>(),
    ) else {
        return Err(Error::Shape(format!(
            "{}: no `time` or plotted column",
            path.display()
        )));
    };
    let mut series = vec![(Vec::new(), Vec::new()); probes.len()];
    for line in lines {
        let values: Vec<Real> = line
            .split(',')
            .map(|v| v.parse().unwrap_or(Real::NAN))
            .collect();
        for (k, &column) in probes.iter().enumerate() {
            let (t, p) = (
                values[time],
                values.get(column).copied().unwrap_or(Real::NAN),
            );
            if t.is_finite() && p.is_finite() {
                series[k].0.push(t);
                series[k].1.push(plot.scale * p);
            }
        }
    }
    let labels: Vec<&str> = columns
        .iter()
        .map(|c| c.trim_start_matches(plot.prefix))
        .collect();
    let lines: Vec<Series<'_>> = series
        .iter()
        .zip(&labels)
        .filter(|((t, _), _)| !t.is_empty())
        .map(|((t, p), label)| Series { label, x: t, y: p })
        .collect();
    if lines.is_empty() {
        return Ok(());
    }
    // From t = 0, so the dry time before the flow reaches a gauge shows.
    let end = lines
        .iter()
        .filter_map(|line| line.x.last().copied())
        .fold(0.0, Real::max);
    line_plot_png(
        dir.join(plot.file),
        &PlotSpec {
            title: plot.title,
            x_label: "t (s)",
            y_label: plot.y_label,
            lines,
            x_range: (end > 0.0).then_some((0.0, end)),
            ..Default::default()
        },
    )
}
