//! Drops under surface tension (`data/scenes/square-drop.ron`): the square drop that relaxes
//! to a circle with the Laplace jump, and the elliptic drop that oscillates at Lamb's
//! frequency, for the validation tests and the figures of `docs/surface-tension.md`.

use std::f64::consts::PI;

use geosph_core::{Particles, Real, Vector};
use geosph_runner::{Observer, RunOptions, run};
use geosph_scene::format::SolverSpec;
use geosph_scene::{Region, Scene};

/// σ of the shipped scene, N/m.
pub const SURFACE_TENSION: Real = 1.0;
/// ρ of both phases, kg/m³.
pub const DENSITY: Real = 1.0;
/// The box's centre, where the drops sit.
const CENTRE: [Real; 2] = [0.5, 0.5];

/// The shipped square drop at spacing `dx`, run to `end_time`, without frames, sampled every
/// `sample_interval`.
pub fn square_drop(dx: Real, end_time: Real, sample_interval: Real) -> Scene {
    let mut scene = Scene::from_ron(include_str!("../../data/scenes/square-drop.ron"))
        .expect("the shipped scene parses");
    scene.dx = dx;
    scene.end_time = end_time;
    scene.output.vtk = false;
    scene.output.sample_interval = sample_interval;
    scene
}

/// The square drop's scene with the square replaced by the ellipse r(θ) = R (1 + ε cos 2θ)
/// about the box's centre (a polygon of 256 sides), of kinematic viscosity `viscosity`,
/// without density diffusion.
pub fn elliptic_drop(
    dx: Real,
    radius: Real,
    epsilon: Real,
    viscosity: Real,
    end_time: Real,
) -> Scene {
    let mut scene = square_drop(dx, end_time, 0.002);
    let sides = 256;
    let vertices = (0..sides)
        .map(|k| {
            let theta = 2.0 * PI * k as Real / sides as Real;
            let r = radius * (1.0 + epsilon * (2.0 * theta).cos());
            (CENTRE[0] + r * theta.cos(), CENTRE[1] + r * theta.sin())
        })
        .collect();
    scene.fluid.as_mut().expect("a fluid").blocks[0] = Region::Polygon { vertices };
    if let SolverSpec::Wcsph(config) = &mut scene.solver {
        config.viscosity = geosph_fluid::config::ViscosityConfig::Laminar {
            kinematic_viscosity: viscosity,
        };
        // At the drop's low viscosity, density diffusion down the Laplace jump feeds a
        // parasitic current that wrecks the oscillation (docs/surface-tension.md).
        config.diffusion = geosph_fluid::config::DiffusionConfig::None;
    }
    scene
}

/// Records, at every sample, the drop's shape moment Q = Σ (x − x̄)² − (y − ȳ)² over its
/// particles (ids below `drop`), and keeps the last sample.
#[derive(Clone, Debug, Default)]
pub struct DropRecord {
    /// The ids below this one are the drop's (block 0, made first).
    pub drop: u32,
    /// (t, Q) at every sample.
    pub moment: Vec<(Real, Real)>,
    /// The largest speed at every sample.
    pub max_speed: Vec<Real>,
    /// The particles at the last sample.
    pub last: Option<Particles<2>>,
    /// The run's time steps.
    pub steps: usize,
}

impl DropRecord {
    fn centroid(&self, fluid: &Particles<2>) -> Vector<2> {
        let (mut sum, mut count) = (Vector::<2>::zeros(), 0.0);
        for i in (0..fluid.len()).filter(|&i| fluid.id[i] < self.drop) {
            sum += fluid.position[i];
            count += 1.0;
        }
        sum / count
    }
}

impl Observer<2> for DropRecord {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn sample(&mut self, time: Real, fluid: &Particles<2>, _row: &mut Vec<Real>) {
        let centre = self.centroid(fluid);
        let moment = (0..fluid.len())
            .filter(|&i| fluid.id[i] < self.drop)
            .map(|i| {
                let r = fluid.position[i] - centre;
                r[0] * r[0] - r[1] * r[1]
            })
            .sum();
        self.moment.push((time, moment));
        let speed = fluid.velocity.iter().map(|v| v.norm()).fold(0.0, Real::max);
        self.max_speed.push(speed);
        self.last = Some(fluid.clone());
    }
}

/// The drops are 2D: a 3D sample is not recorded.
impl Observer<3> for DropRecord {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn sample(&mut self, _time: Real, _fluid: &Particles<3>, _row: &mut Vec<Real>) {}
}

/// Runs `scene` and records its drop (block 0).
///
/// # Panics
/// If the run fails.
pub fn record(scene: &Scene) -> DropRecord {
    try_record(scene).expect("the drop runs")
}

/// [`record`], with the reason as one line if the scene does not build or the run fails.
pub fn try_record(scene: &Scene) -> Result<DropRecord, String> {
    let setup = geosph_scene::build::<2>(scene).map_err(|error| error.to_string())?;
    let mut record = DropRecord {
        drop: setup.blocks[0].particles as u32,
        ..Default::default()
    };
    let summary =
        run(scene, &RunOptions::default(), &mut record).map_err(|error| error.to_string())?;
    record.steps = summary.steps;
    Ok(record)
}

/// A drop at rest compared with the circle of its area.
#[derive(Clone, Debug)]
pub struct Relaxed {
    /// R = √(N dx²/π) of the drop's N particles.
    pub radius: Real,
    /// Mean pressure of the drop's particles within R/2 of its centroid minus that of the
    /// other phase's farther than R + 2 supports, Pa.
    pub jump: Real,
    /// σ/R, Pa.
    pub laplace: Real,
    /// The drop's farthest particle from its centroid, over R.
    pub farthest_drop: Real,
    /// The other phase's nearest particle to the drop's centroid, over R.
    pub nearest_outside: Real,
    /// The largest speed at the end, m/s.
    pub max_speed: Real,
}

/// The drop of `record` at its last sample, compared with the circle of its area; `dx` and
/// `support` are the run's spacing and kernel support radius.
pub fn relaxed(record: &DropRecord, dx: Real, support: Real) -> Relaxed {
    let fluid = record.last.as_ref().expect("a sample");
    let pressure = fluid.pressure.as_ref().expect("a pressure");
    let centre = record.centroid(fluid);
    let radius = (record.drop as Real * dx * dx / PI).sqrt();
    let (mut inside, mut outside) = ((0.0, 0.0), (0.0, 0.0));
    let (mut farthest_drop, mut nearest_outside): (Real, Real) = (0.0, Real::INFINITY);
    for i in 0..fluid.len() {
        let r = (fluid.position[i] - centre).norm();
        if fluid.id[i] < record.drop {
            farthest_drop = farthest_drop.max(r);
            if r < 0.5 * radius {
                inside = (inside.0 + pressure[i], inside.1 + 1.0);
            }
        } else {
            nearest_outside = nearest_outside.min(r);
            if r > radius + 2.0 * support {
                outside = (outside.0 + pressure[i], outside.1 + 1.0);
            }
        }
    }
    Relaxed {
        radius,
        jump: inside.0 / inside.1 - outside.0 / outside.1,
        laplace: SURFACE_TENSION / radius,
        farthest_drop: farthest_drop / radius,
        nearest_outside: nearest_outside / radius,
        max_speed: record.max_speed.last().copied().unwrap_or(Real::NAN),
    }
}

/// Lamb's (1932, §275) frequency of mode n of the 2D drop of radius R at the scene's σ and ρ
/// (inside and out), [`crate::viscous_drop::lamb_frequency`].
pub fn lamb_frequency(mode: u32, radius: Real) -> Real {
    crate::viscous_drop::lamb_frequency(mode, radius, SURFACE_TENSION, DENSITY)
}

/// The rate s = −γ + iω of mode n of the 2D drop of radius R and the kinematic viscosity
/// `viscosity` inside and out, at the scene's σ and ρ (`crate::viscous_drop`); Lamb's
/// frequency is its inviscid limit.
pub fn viscous_rate(mode: u32, radius: Real, viscosity: Real) -> nalgebra::Complex<Real> {
    crate::viscous_drop::viscous_mode(mode, radius, viscosity, SURFACE_TENSION, DENSITY)
}

/// The times at which Q(t) of `moment` crosses zero (linearly interpolated).
fn zero_crossings(moment: &[(Real, Real)]) -> Vec<Real> {
    moment
        .windows(2)
        .filter(|pair| pair[0].1 != 0.0 && pair[0].1.signum() != pair[1].1.signum())
        .map(|pair| {
            let ((t0, q0), (t1, q1)) = (pair[0], pair[1]);
            t0 + (t1 - t0) * q0 / (q0 - q1)
        })
        .collect()
}

/// The decay rate γ of the oscillation of Q(t) in `moment`: ln(A₁/A_k)/(t_k − t₁) between
/// the largest |Q| of the first and of the last of its first `half_periods` half-periods
/// (between zero crossings); `None` if it has fewer or `half_periods` < 2.
pub fn decay_rate(moment: &[(Real, Real)], half_periods: usize) -> Option<Real> {
    let crossings = zero_crossings(moment);
    if half_periods < 2 || crossings.len() < half_periods + 1 {
        return None;
    }
    let peak = |k: usize| {
        moment
            .iter()
            .filter(|(t, _)| (crossings[k]..crossings[k + 1]).contains(t))
            .map(|&(t, q)| (t, q.abs()))
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    };
    let (first, last) = (peak(0), peak(half_periods - 1));
    Some((first.1 / last.1).ln() / (last.0 - first.0))
}

/// The period of the oscillation of Q(t) in `moment`: twice the mean spacing of its first
/// `half_periods` + 1 crossings of zero (linearly interpolated); `None` if it has fewer.
pub fn period(moment: &[(Real, Real)], half_periods: usize) -> Option<Real> {
    let crossings = zero_crossings(moment);
    if crossings.len() < half_periods + 1 {
        return None;
    }
    Some(2.0 * (crossings[half_periods] - crossings[0]) / half_periods as Real)
}
