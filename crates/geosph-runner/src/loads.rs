//! Load gauges: the force and moment of the fluid's pressure, or of the soil's stress, on mesh
//! walls, sampled with the diagnostics.

use geosph_core::{Domain, Particles, Real, Vector};
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use geosph_neighbours::CellGrid;
use geosph_scene::LoadSurface;
use geosph_sph::surface_load::{FluidField, LoadPoint, SoilField, pressure_load, stress_load};

use crate::share::Share;

/// The loads on the scene's `output.loads` walls: at each sample, for each gauge, the force
/// F = −Σ_q p(x_q) n_q A_q and moment M = Σ_q (x_q − x_c) × (−p(x_q) n_q A_q) over the
/// quadrature points of its surface, with the pressure extrapolated to them from the fluid
/// ([`geosph_sph::surface_load::pressure_load`]); for soil F = Σ_q σ(x_q) n_q A_q with the
/// soil's stress ([`geosph_sph::surface_load::stress_load`]).
pub struct WallLoads<const D: usize> {
    surfaces: Vec<LoadSurface<D>>,
    columns: Vec<String>,
    kernel: KernelKind,
    smoothing_length: Real,
    gravity: Vector<D>,
    background_pressure: Real,
    grid: Option<CellGrid<D>>,
}

impl<const D: usize> WallLoads<D> {
    /// The gauges of a set-up's `loads`; `domain` bounds the fluid, whose equation of state
    /// has the background pressure `background_pressure`.
    pub fn new(
        surfaces: Vec<LoadSurface<D>>,
        kernel: KernelKind,
        smoothing_length: Real,
        (gravity, background_pressure): (Vector<D>, Real),
        domain: &Domain<D>,
    ) -> Self {
        let axes = ["x", "y", "z"];
        let mut columns = Vec::new();
        for surface in &surfaces {
            let name = &surface.name;
            columns.extend(axes[..D].iter().map(|a| format!("F_{name}_{a}")));
            if D == 2 {
                columns.push(format!("M_{name}"));
            } else {
                columns.extend(axes.iter().map(|a| format!("M_{name}_{a}")));
            }
        }
        let radius = kernel.support_factor() * smoothing_length;
        let grid = (!surfaces.is_empty())
            .then(|| CellGrid::new(domain.clone(), radius).expect("the run's domain holds a grid"));
        Self {
            surfaces,
            columns,
            kernel,
            smoothing_length,
            gravity,
            background_pressure,
            grid,
        }
    }

    /// The CSV columns, `F_<name>_x`, … and `M_<name>` (3D: `M_<name>_x`, …) per gauge.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Plots the forces (kN; 2D: kN/m) against time from `diagnostics.csv` in `dir` into
    /// `loads.png` (moments stay in the CSV).
    pub fn plot(&self, dir: &std::path::Path) -> Result<(), geosph_io::Error> {
        let forces: Vec<String> = self
            .columns
            .iter()
            .filter(|c| c.starts_with("F_"))
            .cloned()
            .collect();
        let unit = if D == 2 { "F (kN/m)" } else { "F (kN)" };
        crate::probes::plot_columns(
            dir,
            &forces,
            crate::probes::ColumnPlot {
                file: "loads.png",
                title: "Loads on walls",
                y_label: unit,
                scale: 1e-3,
                prefix: "F_",
            },
        )
    }

    /// [`WallLoads::sample`] at a sample of a run: on several ranks from every particle,
    /// gathered ([`Share::whole`]), only when the scene has load gauges.
    pub fn sample_share(&mut self, share: &mut Share<'_, D>, row: &mut Vec<Real>) {
        if self.grid.is_some() {
            self.sample(share.whole(), row);
        }
    }

    /// Appends each gauge's force (N; 2D: N/m) and moment (N m; 2D: N m/m) to `row`.
    pub fn sample(&mut self, fluid: &Particles<D>, row: &mut Vec<Real>) {
        let Some(grid) = self.grid.as_mut() else {
            return;
        };
        let carried = fluid.soil.is_some() || fluid.pressure.is_some();
        if !carried || grid.build(&fluid.position).is_err() {
            row.extend(self.columns.iter().map(|_| Real::NAN));
            return;
        }
        let grid = &*grid;
        // Soil first: its stress is what it carries, whatever pressure field it started with.
        let field = match (&fluid.soil, &fluid.pressure) {
            (Some(soil), _) => LoadField::Soil(SoilField {
                soil: fluid,
                stress: &soil.stress,
                grid,
                gravity: self.gravity,
            }),
            (None, Some(pressure)) => LoadField::Fluid(FluidField {
                fluid,
                pressure,
                grid,
                gravity: self.gravity,
                background_pressure: self.background_pressure,
            }),
            (None, None) => unreachable!("checked above"),
        };
        for surface in &self.surfaces {
            let gauge = Gauge { surface, field };
            let (force, moment) = self.kernel.dispatch(self.smoothing_length, gauge);
            row.extend(force.iter());
            row.extend(if D == 2 {
                &moment.as_slice()[2..]
            } else {
                moment.as_slice()
            });
        }
    }
}

/// What loads a gauge: a fluid's pressure or a soil's stress.
#[derive(Clone, Copy)]
enum LoadField<'a, const D: usize> {
    Fluid(FluidField<'a, D>),
    Soil(SoilField<'a, D>),
}

/// One gauge's integral, run with whichever kernel the scene names.
struct Gauge<'a, const D: usize> {
    surface: &'a LoadSurface<D>,
    field: LoadField<'a, D>,
}

impl<const D: usize> KernelVisitor<D> for Gauge<'_, D> {
    /// The force and the moment (in 2D its z component only is not zero).
    type Output = (Vector<D>, Vector<3>);

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let points = self.surface.points.iter().map(|point| LoadPoint {
            position: point.position,
            normal: point.normal,
            area: point.area,
        });
        let about = &self.surface.about;
        match &self.field {
            LoadField::Fluid(field) => pressure_load(&kernel, field, points, about),
            LoadField::Soil(field) => stress_load(&kernel, field, points, about),
        }
    }
}
