//! The measures of the harness's own cases against their references: the Taylor–Green
//! vortex's velocity field and the still tank's layer pressures (the channels' profiles are
//! in [`crate::laminar`]), observed in 2D and 3D alike.

use std::f64::consts::PI;

use geosph_core::{Particles, Real};
use geosph_runner::Observer;

use crate::case::{TG_LENGTH, TG_SPEED, TG_VISCOSITY};
use crate::laminar::ProfileError;

/// The Taylor–Green vortex (Taylor & Green 1937) against its exact decay, at the latest
/// sample: u = −U e^{bt} cos kx sin ky, v = U e^{bt} sin kx cos ky, b = −2νk², k = 2π/L.
#[derive(Clone, Debug, Default)]
pub struct TaylorGreenError {
    /// ‖v − v_exact‖ / ‖v_exact‖ over the particles, v_exact at each particle's position.
    pub error: Real,
    /// Σ|v|² / Σ|v_exact|²: the kinetic energy over the exact e^{2bt} decay.
    pub kinetic_energy_ratio: Real,
}

impl TaylorGreenError {
    fn measure<const D: usize>(&mut self, time: Real, fluid: &Particles<D>) {
        let k = 2.0 * PI / TG_LENGTH;
        let decay = (-2.0 * TG_VISCOSITY * k * k * time).exp();
        let (mut difference, mut norm, mut energy) = (0.0, 0.0, 0.0);
        for (x, v) in fluid.position.iter().zip(&fluid.velocity) {
            let u = -TG_SPEED * decay * (k * x[0]).cos() * (k * x[1]).sin();
            let w = TG_SPEED * decay * (k * x[0]).sin() * (k * x[1]).cos();
            difference += (v[0] - u).powi(2) + (v[1] - w).powi(2);
            norm += u * u + w * w;
            energy += v.norm_squared();
        }
        self.error = (difference / norm).sqrt();
        self.kinetic_energy_ratio = energy / norm;
    }
}

/// Layer-averaged pressure from `from` on, against ρ₀ g (H − y).
#[derive(Clone, Debug)]
pub(crate) struct LayerPressure {
    dx: Real,
    from: Real,
    samples: usize,
    /// Per layer: Σ y, Σ p, Σ count over the samples.
    sums: Vec<(Real, Real, Real)>,
}

/// Depth H of the water in the hydrostatic tanks (here and in the stability cases), m.
pub(crate) const DEPTH: Real = 0.5;
const WATER: Real = 1000.0;
const GRAVITY: Real = 9.81;

/// (p − ρ₀ g (H − y)) / (ρ₀ g H): the pressure error of a still tank of depth [`DEPTH`] at
/// height `y`.
pub(crate) fn hydrostatic_error(pressure: Real, y: Real) -> Real {
    (pressure - WATER * GRAVITY * (DEPTH - y)) / (WATER * GRAVITY * DEPTH)
}

impl LayerPressure {
    pub(crate) fn new(dx: Real, from: Real) -> Self {
        Self {
            dx,
            from,
            samples: 0,
            sums: Vec::new(),
        }
    }

    fn measure<const D: usize>(&mut self, time: Real, fluid: &Particles<D>) {
        let Some(pressure) = &fluid.pressure else {
            return;
        };
        if time < self.from - 1e-9 {
            return;
        }
        let layers = (DEPTH / self.dx).round() as usize;
        self.sums.resize(layers, (0.0, 0.0, 0.0));
        for (x, p) in fluid.position.iter().zip(pressure) {
            let layer = (x[D - 1] / self.dx).floor();
            if layer >= 0.0 && (layer as usize) < layers {
                let sum = &mut self.sums[layer as usize];
                sum.0 += x[D - 1];
                sum.1 += p;
                sum.2 += 1.0;
            }
        }
        self.samples += 1;
    }

    pub(crate) fn error(&self) -> Real {
        let kept = self.sums.len().saturating_sub(3);
        let squares: Vec<Real> = self.sums[..kept]
            .iter()
            .filter(|sum| sum.2 > 0.0)
            .map(|&(y, p, n)| {
                let (y, p) = (y / n, p / n);
                hydrostatic_error(p, y).powi(2)
            })
            .collect();
        if self.samples == 0 || squares.is_empty() {
            return Real::NAN;
        }
        (squares.iter().sum::<Real>() / squares.len() as Real).sqrt()
    }
}

macro_rules! observe_in_both_dimensions {
    ($observer:ty) => {
        impl<const D: usize> Observer<D> for $observer {
            fn columns(&self) -> Vec<&'static str> {
                Vec::new()
            }
            fn sample(&mut self, time: Real, fluid: &Particles<D>, _row: &mut Vec<Real>) {
                self.measure(time, fluid);
            }
        }
    };
}

observe_in_both_dimensions!(TaylorGreenError);
observe_in_both_dimensions!(ProfileError);
observe_in_both_dimensions!(LayerPressure);
