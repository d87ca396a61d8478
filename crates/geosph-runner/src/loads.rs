//! Load gauges: the force and moment of the fluid's pressure, or of the soil's stress, on mesh
//! walls, sampled with the diagnostics.

use geosph_core::{Domain, Real, Vector};
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use geosph_neighbours::CellGrid;
use geosph_scene::LoadSurface;
use geosph_sph::surface_load::{
    FluidField, LoadPoint, PRESSURE_SUMS, STRESS_SUMS, SoilField, pressure_load_from_sums,
    pressure_sums, stress_load_from_sums, stress_sums,
};

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
    /// The extrapolation's sums at every quadrature point of the last sample, reused.
    sums: Vec<Real>,
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
        let grid = (!surfaces.is_empty()).then(|| {
            CellGrid::fitting(domain.clone(), radius).expect("the run's domain holds a grid")
        });
        Self {
            surfaces,
            columns,
            kernel,
            smoothing_length,
            gravity,
            background_pressure,
            grid,
            sums: Vec::new(),
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

    /// Appends each gauge's force (N; 2D: N/m) and moment (N m; 2D: N m/m) to `row`. On
    /// several ranks each rank sums the extrapolation at every quadrature point over its own
    /// particles and the sums are added over the ranks (one collective for every gauge), so
    /// no rank needs the others' particles; NaN for every gauge when the fluid carries no
    /// pressure or stress, or some rank's particles could not be binned.
    pub fn sample(&mut self, share: &Share<'_, D>, row: &mut Vec<Real>) {
        let Some(grid) = self.grid.as_mut() else {
            return;
        };
        let (pressure, stress) = (share.pressure(), share.stress());
        if pressure.is_none() && stress.is_none() {
            row.extend(self.columns.iter().map(|_| Real::NAN));
            return;
        }
        let per_point = match stress {
            Some(_) => STRESS_SUMS,
            None => PRESSURE_SUMS,
        };
        let points: usize = self.surfaces.iter().map(|s| s.points.len()).sum();
        self.sums.clear();
        let binned = grid.build(share.position()).is_ok();
        if binned {
            let grid = &*grid;
            let (position, mass, density) = (share.position(), share.mass(), share.density());
            // Soil first: its stress is what it carries, whatever pressure field it started
            // with.
            let field = match (stress, pressure) {
                (Some(stress), _) => LoadField::Soil(SoilField {
                    position,
                    mass,
                    density,
                    stress,
                    grid,
                    gravity: self.gravity,
                }),
                (None, Some(pressure)) => LoadField::Fluid(FluidField {
                    position,
                    mass,
                    density,
                    pressure,
                    grid,
                    gravity: self.gravity,
                    background_pressure: self.background_pressure,
                }),
                (None, None) => unreachable!("checked above"),
            };
            for surface in &self.surfaces {
                let sums = &mut self.sums;
                let gauge = Gauge {
                    surface,
                    field,
                    sums,
                };
                self.kernel.dispatch(self.smoothing_length, gauge);
            }
        } else {
            self.sums.resize(points * per_point, 0.0);
        }
        // The count of ranks that could not bin their particles, summed with the rest.
        self.sums.push(Real::from(u8::from(!binned)));
        share.sum_each(&mut self.sums);
        if self.sums[points * per_point] > 0.0 {
            row.extend(self.columns.iter().map(|_| Real::NAN));
            return;
        }
        let mut sums = &self.sums[..];
        for surface in &self.surfaces {
            let (here, rest) = sums.split_at(surface.points.len() * per_point);
            sums = rest;
            let points = load_points(surface);
            let about = &surface.about;
            let (force, moment) = match per_point {
                STRESS_SUMS => stress_load_from_sums(points, here, about, &self.gravity),
                _ => pressure_load_from_sums(points, here, about, self.background_pressure),
            };
            row.extend(force.iter());
            row.extend(if D == 2 {
                &moment.as_slice()[2..]
            } else {
                moment.as_slice()
            });
        }
    }
}

/// The quadrature points of `surface` as the load integrals take them.
fn load_points<const D: usize>(surface: &LoadSurface<D>) -> impl Iterator<Item = LoadPoint<D>> {
    surface.points.iter().map(|point| LoadPoint {
        position: point.position,
        normal: point.normal,
        area: point.area,
    })
}

/// What loads a gauge: a fluid's pressure or a soil's stress.
#[derive(Clone, Copy)]
enum LoadField<'a, const D: usize> {
    Fluid(FluidField<'a, D>),
    Soil(SoilField<'a, D>),
}

/// One gauge's sums over a set of particles, run with whichever kernel the scene names.
struct Gauge<'a, const D: usize> {
    surface: &'a LoadSurface<D>,
    field: LoadField<'a, D>,
    sums: &'a mut Vec<Real>,
}

impl<const D: usize> KernelVisitor<D> for Gauge<'_, D> {
    /// The extrapolation's sums at each quadrature point, appended to the gauge's `sums`.
    type Output = ();

    fn visit<K: Kernel<D>>(self, kernel: K) {
        let points = load_points(self.surface);
        match &self.field {
            LoadField::Fluid(field) => pressure_sums(&kernel, field, points, self.sums),
            LoadField::Soil(field) => stress_sums(&kernel, field, points, self.sums),
        }
    }
}
