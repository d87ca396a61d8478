//! Start-up of plane Poiseuille and Couette flow (Morris, Fox & Zhu 1997, Sec. 4): the laminar
//! viscosity and the no-slip walls against the series solutions of the diffusion equation.
//!
//! Both flows fill a channel of width L = 1 mm between plates at y = 0 and y = L, periodic in
//! x, with ν = 10⁻⁶ m²/s and ρ = 10³ kg/m³, starting at rest:
//!
//! - Poiseuille: a body force F = 2 × 10⁻⁴ m/s² along x drives the flow to the parabola
//!   u = F y (L − y)/(2ν), u_max = F L²/(8ν) = 2.5 × 10⁻⁵ m/s (Re = 0.0125 on u_max and L);
//! - Couette: the upper plate moves at u₀ = 2.5 × 10⁻⁵ m/s, the flow tends to u = u₀ y/L.
//!
//! The profiles are compared at the times Morris et al. plot (0.0225, 0.045 and 0.1125 s),
//! at 0.225 s, and at 0.9 s, where the slowest transient mode has decayed to e^{−π²νt/L²} =
//! 1.4 × 10⁻⁴ of its start (steady state).

use std::f64::consts::PI;

use geosph_core::{Particles, Real};

/// Channel width L, m.
pub const WIDTH: Real = 1e-3;
/// Kinematic viscosity ν, m²/s.
pub const VISCOSITY: Real = 1e-6;
/// Body force of the Poiseuille flow, m/s².
pub const BODY_FORCE: Real = 2e-4;
/// Velocity scale of both flows: the steady u_max of the Poiseuille flow and the plate
/// speed of the Couette flow, m/s.
pub const SPEED: Real = BODY_FORCE * WIDTH * WIDTH / (8.0 * VISCOSITY);
/// The comparison times, s.
pub const TIMES: [Real; 5] = [0.0225, 0.045, 0.1125, 0.225, 0.9];
/// Terms of the series: the first omitted mode of the earliest time is below 10⁻³⁰⁰.
const TERMS: usize = 400;

/// Which flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Body-force-driven flow between fixed plates.
    Poiseuille,
    /// Flow driven by the upper plate.
    Couette,
}

impl Flow {
    /// The series solution u(y, t) (Morris, Fox & Zhu 1997, Sec. 4).
    ///
    /// Poiseuille: u = F y (L − y)/(2ν) − Σ_{n≥0} 4FL²/(νπ³(2n+1)³) sin((2n+1)πy/L)
    /// e^{−(2n+1)²π²νt/L²}. Couette: u = u₀ y/L + Σ_{n≥1} 2u₀(−1)ⁿ/(nπ) sin(nπy/L)
    /// e^{−n²π²νt/L²}.
    pub fn velocity(self, y: Real, t: Real) -> Real {
        let (l, nu) = (WIDTH, VISCOSITY);
        let decay = |m: Real| (-m * m * PI * PI * nu * t / (l * l)).exp();
        match self {
            Flow::Poiseuille => {
                let f = BODY_FORCE;
                let transient: Real = (0..TERMS)
                    .map(|n| {
                        let m = (2 * n + 1) as Real;
                        4.0 * f * l * l / (nu * PI.powi(3) * m.powi(3))
                            * (m * PI * y / l).sin()
                            * decay(m)
                    })
                    .sum();
                f * y * (l - y) / (2.0 * nu) - transient
            }
            Flow::Couette => {
                let transient: Real = (1..=TERMS)
                    .map(|n| {
                        let m = n as Real;
                        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                        2.0 * SPEED * sign / (m * PI) * (m * PI * y / l).sin() * decay(m)
                    })
                    .sum();
                SPEED * y / l + transient
            }
        }
    }

    /// The scene at spacing `dx` (the harness sets the solver, kernel and times).
    pub fn scene(self) -> String {
        let (gravity, lid) = match self {
            Flow::Poiseuille => (BODY_FORCE, 0.0),
            Flow::Couette => (0.0, SPEED),
        };
        format!(
            "Scene(name: \"{name}\", dimension: 2, dx: 5e-5, gravity: [{gravity:e}, 0.0],
               end_time: 0.9,
               domain: (min: [0.0, -5e-4], max: [{WIDTH:e}, 1.5e-3], periodic: [true, false]),
               fluid: (blocks: [Box(min: [0.0, 0.0], max: [{WIDTH:e}, {WIDTH:e}])],
                       hydrostatic: false),
               walls: [Polyline(points: [(0.0, 0.0), ({WIDTH:e}, 0.0)]),
                       Polyline(points: [({WIDTH:e}, {WIDTH:e}), (0.0, {WIDTH:e})],
                                velocity: ({lid:e}, 0.0))],
               solver: Wcsph(()))",
            name = self.name(),
        )
    }

    /// The harness's name of the flow.
    pub fn name(self) -> &'static str {
        match self {
            Flow::Poiseuille => "poiseuille",
            Flow::Couette => "couette",
        }
    }
}

/// The largest error of the layer-averaged velocity profile against [`Flow::velocity`] over
/// the samples at [`TIMES`], relative to [`SPEED`].
#[derive(Clone, Debug)]
pub struct ProfileError {
    flow: Flow,
    dx: Real,
    /// The largest error so far.
    pub error: Real,
    /// The comparison times sampled so far.
    pub compared: usize,
    /// Per layer: Σ y, Σ u, count (reused every sample).
    layers: Vec<(Real, Real, Real)>,
}

impl ProfileError {
    /// An observer of `flow` at spacing `dx`.
    pub fn new(flow: Flow, dx: Real) -> Self {
        Self {
            flow,
            dx,
            error: 0.0,
            compared: 0,
            layers: Vec::new(),
        }
    }

    /// Compares the profile of `fluid` at `time` if it is one of [`TIMES`].
    pub fn measure<const D: usize>(&mut self, time: Real, fluid: &Particles<D>) {
        if !TIMES.iter().any(|t| (t - time).abs() < 1e-9) {
            return;
        }
        let count = (WIDTH / self.dx).round() as usize;
        self.layers.clear();
        self.layers.resize(count, (0.0, 0.0, 0.0));
        for (x, v) in fluid.position.iter().zip(&fluid.velocity) {
            let layer = (x[1] / self.dx).floor();
            if layer >= 0.0 && (layer as usize) < count {
                let sum = &mut self.layers[layer as usize];
                *sum = (sum.0 + x[1], sum.1 + v[0], sum.2 + 1.0);
            }
        }
        for &(y, u, n) in self.layers.iter().filter(|layer| layer.2 > 0.0) {
            let (y, u) = (y / n, u / n);
            let error = (u - self.flow.velocity(y, time)).abs() / SPEED;
            self.error = self.error.max(error);
        }
        self.compared += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_start_at_rest_and_reach_the_steady_profiles() {
        // Couette's series converges like 1/n where the plate's jump sits, so only its lower
        // half is checked at t = 0.
        for (flow, top) in [(Flow::Poiseuille, 10), (Flow::Couette, 6)] {
            for k in 1..top {
                let y = k as Real * WIDTH / 10.0;
                assert!(
                    flow.velocity(y, 0.0).abs() < 2e-3 * SPEED,
                    "{flow:?} at y = {y}"
                );
            }
        }
        let mid = Flow::Poiseuille.velocity(0.5 * WIDTH, 10.0);
        assert!((mid / SPEED - 1.0).abs() < 1e-12);
        let quarter = Flow::Couette.velocity(0.25 * WIDTH, 10.0);
        assert!((quarter / SPEED - 0.25).abs() < 1e-12);
    }
}
