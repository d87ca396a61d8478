//! Load gauges: the force and moment of the fluid's pressure on mesh walls, sampled with the
//! diagnostics.

use geosph_core::{Domain, Particles, Real, Vector};
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use geosph_neighbours::CellGrid;
use geosph_scene::LoadSurface;

/// The loads on the scene's `output.loads` walls: at each sample, for each gauge,
///
/// F = −Σ_q p(x_q) n_q A_q,  M = Σ_q (x_q − x_c) × (−p(x_q) n_q A_q)
///
/// over the quadrature points x_q of its surface (normal n_q into the flow, area A_q), with the
/// pressure at the surface extrapolated from the fluid as Adami, Hu & Adams (2012, eq. 27)
/// extrapolate it to their wall particles, hydrostatically with gravity g:
///
/// p(x_q) = Σ_j V_j W_qj (p_j + ρ_j g·(x_q − x_j)) / Σ_j V_j W_qj,  V_j = m_j/ρ_j,
///
/// clamped at p ≥ 0 as the walls' pressure is (above a free surface it would read a tension),
/// 0 where no fluid is within the kernel's support (a dry surface). The extrapolation makes a
/// hydrostatic field exact on faces of any orientation: a plain Shepard average over the fluid
/// on one side of a face would read the pressure about a particle spacing into the fluid.
pub struct WallLoads<const D: usize> {
    surfaces: Vec<LoadSurface<D>>,
    columns: Vec<String>,
    kernel: KernelKind,
    smoothing_length: Real,
    gravity: Vector<D>,
    grid: Option<CellGrid<D>>,
}

impl<const D: usize> WallLoads<D> {
    /// The gauges of a set-up's `loads`; `domain` bounds the fluid.
    pub fn new(
        surfaces: Vec<LoadSurface<D>>,
        kernel: KernelKind,
        smoothing_length: Real,
        gravity: Vector<D>,
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

    /// Appends each gauge's force (N; 2D: N/m) and moment (N m; 2D: N m/m) to `row`.
    pub fn sample(&mut self, fluid: &Particles<D>, row: &mut Vec<Real>) {
        let Some(grid) = self.grid.as_mut() else {
            return;
        };
        let pressure = fluid.pressure.as_deref();
        if pressure.is_none() || grid.build(&fluid.position).is_err() {
            row.extend(self.columns.iter().map(|_| Real::NAN));
            return;
        }
        let pressure = pressure.expect("checked");
        for surface in &self.surfaces {
            let gauge = Gauge {
                surface,
                grid,
                fluid,
                pressure,
                gravity: self.gravity,
            };
            let (force, moment) = self.kernel.dispatch(self.smoothing_length, gauge);
            row.extend(force.iter());
            row.extend(if D == 2 { &moment[2..] } else { &moment[..] });
        }
    }
}

/// One gauge's integral, run with whichever kernel the scene names.
struct Gauge<'a, const D: usize> {
    surface: &'a LoadSurface<D>,
    grid: &'a CellGrid<D>,
    fluid: &'a Particles<D>,
    pressure: &'a [Real],
    gravity: Vector<D>,
}

impl<const D: usize> KernelVisitor<D> for Gauge<'_, D> {
    /// The force and the moment (in 2D its z component only is not zero).
    type Output = (Vector<D>, [Real; 3]);

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let Particles {
            position,
            mass,
            density,
            ..
        } = self.fluid;
        let mut force = Vector::<D>::zeros();
        let mut moment = [0.0; 3];
        for point in &self.surface.points {
            let x = point.position;
            let (mut weighted, mut weights) = (0.0, 0.0);
            self.grid.for_each_neighbour(position, &x, |j, x_qj, r| {
                let j = j as usize;
                let w = mass[j] / density[j] * kernel.value(r);
                let hydrostatic = density[j] * self.gravity.dot(&x_qj);
                weighted += w * (self.pressure[j] + hydrostatic);
                weights += w;
            });
            if weights <= 0.0 {
                continue;
            }
            // Clamped at zero, as the walls' own pressure is: above a free surface the
            // extrapolation would read a tension that the water does not exert.
            let load = point.normal * (-(weighted / weights).max(0.0) * point.area);
            force += load;
            let arm = x - self.surface.about;
            if D == 2 {
                moment[2] += arm[0] * load[1] - arm[1] * load[0];
            } else {
                moment[0] += arm[1] * load[2] - arm[2] * load[1];
                moment[1] += arm[2] * load[0] - arm[0] * load[2];
                moment[2] += arm[0] * load[1] - arm[1] * load[0];
            }
        }
        (force, moment)
    }
}
