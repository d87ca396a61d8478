//! The initial state beyond the lattice: a random disorder of the particles and their initial
//! velocity field.

use geosph_core::{Particles, Real, Vector};
use geosph_sph::EquationOfState;

use crate::format::InitialVelocity;

/// Moves every point by a uniform random offset in [−amplitude, amplitude] per axis, drawn
/// from a SplitMix64 sequence with a fixed seed (Steele et al. 2014), so that a scene always
/// gives the same particles whatever the library versions.
pub(crate) fn jitter<const D: usize>(points: &mut [Vector<D>], amplitude: Real) {
    let mut state: u64 = 0x005e_ed0f_9e05;
    let mut uniform = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        // 53 random bits as a number in [0, 1), then in [−1, 1).
        2.0 * ((z >> 11) as Real / (1u64 << 53) as Real) - 1.0
    };
    for x in points {
        for k in 0..D {
            x[k] += amplitude * uniform();
        }
    }
}

/// The largest initial speed of particles at `position`.
pub(crate) fn initial_speed<const D: usize>(
    field: &InitialVelocity,
    position: &[Vector<D>],
) -> Real {
    match field {
        InitialVelocity::Rest => 0.0,
        InitialVelocity::Uniform(velocity) => velocity.iter().map(|v| v * v).sum::<Real>().sqrt(),
        InitialVelocity::Stretch { centre, rate } => {
            let centre = vector::<D>(centre);
            position
                .iter()
                .map(|x| (x - centre).norm() * rate.abs())
                .fold(0.0, Real::max)
        }
        InitialVelocity::TaylorGreen { speed, .. } => *speed,
    }
}

/// Sets the initial velocity of the particles (and, for the Taylor–Green vortex, its
/// pressure and the density of that pressure).
pub(crate) fn set_velocity<const D: usize>(
    fluid: &mut Particles<D>,
    field: &InitialVelocity,
    eos: &EquationOfState,
) {
    match field {
        InitialVelocity::Rest => {}
        InitialVelocity::Uniform(velocity) => fluid.velocity.fill(vector::<D>(velocity)),
        InitialVelocity::Stretch { centre, rate } => {
            let centre = vector::<D>(centre);
            for (v, x) in fluid.velocity.iter_mut().zip(&fluid.position) {
                *v = (x - centre) * *rate;
            }
        }
        &InitialVelocity::TaylorGreen { speed, wavelength } => {
            let k = 2.0 * std::f64::consts::PI / wavelength;
            let mut pressure = vec![0.0; fluid.len()];
            for i in 0..fluid.len() {
                let (x, y) = (fluid.position[i][0], fluid.position[i][1]);
                fluid.velocity[i][0] = -speed * (k * x).cos() * (k * y).sin();
                fluid.velocity[i][1] = speed * (k * x).sin() * (k * y).cos();
                pressure[i] = eos.background_pressure
                    - 0.25
                        * eos.rest_density
                        * speed
                        * speed
                        * ((2.0 * k * x).cos() + (2.0 * k * y).cos());
                fluid.density[i] = eos.density(pressure[i]);
            }
            fluid.pressure = Some(pressure);
        }
    }
}

/// The first `D` of `values` as a vector (after validation, exactly `D`).
pub(crate) fn vector<const D: usize>(values: &[Real]) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| values[k])
}

#[cfg(test)]
mod tests {
    use crate::Scene;
    use geosph_core::Real;

    #[test]
    fn jitter_is_bounded_and_reproducible() {
        let text = "Scene(name: \"j\", dimension: 2, dx: 0.1, end_time: 1.0,
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])], jitter: 0.3),
            walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0])],
            solver: Wcsph(()))";
        let scene = Scene::from_ron(text).unwrap();
        let first = crate::build::<2>(&scene).unwrap().fluid.position;
        let again = crate::build::<2>(&scene).unwrap().fluid.position;
        assert_eq!(first, again);
        let mut lattice = scene.clone();
        lattice.fluid.as_mut().unwrap().jitter = 0.0;
        let sites = crate::build::<2>(&lattice).unwrap().fluid.position;
        let moved: Vec<_> = first.iter().zip(&sites).map(|(a, b)| a - b).collect();
        assert!(moved.iter().all(|d| d.amax() <= 0.3 * 0.1 + 1e-12));
        // Uniform in [−0.3, 0.3] dx: the mean |offset| per axis is 0.15 dx.
        let mean = moved.iter().map(|d| d.abs().sum()).sum::<Real>() / (2 * moved.len()) as Real;
        assert!((mean / 0.1 - 0.15).abs() < 0.02, "mean offset {mean}");
    }

    #[test]
    fn taylor_green_start_and_default_sound_speed() {
        let text = "Scene(name: \"tg\", dimension: 2, dx: 0.05, end_time: 1.0, gravity: [0.0, 0.0],
            domain: (min: [0.0, 0.0], max: [1.0, 1.0], periodic: [true, true]),
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])],
                    velocity: TaylorGreen(speed: 2.0, wavelength: 1.0)),
            solver: Wcsph(()))";
        let setup = crate::build::<2>(&Scene::from_ron(text).unwrap()).unwrap();
        // c₀ = 10 U without gravity.
        assert_eq!(setup.sound_speed, 20.0);
        let pi = std::f64::consts::PI;
        for (x, v) in setup.fluid.position.iter().zip(&setup.fluid.velocity) {
            let u = -2.0 * (2.0 * pi * x[0]).cos() * (2.0 * pi * x[1]).sin();
            assert!((v[0] - u).abs() < 1e-12);
        }
        // (0, 0) is a vortex centre (the velocity gradient there is a pure rotation): the
        // pressure is lowest there, −ρ₀U²/2, and highest, +ρ₀U²/2, at the saddles such as (L/4, L/4).
        let pressure = setup.fluid.pressure.as_ref().unwrap();
        let at = |x: Real, y: Real| {
            let i = setup
                .fluid
                .position
                .iter()
                .position(|p| (p[0] - x).abs() < 1e-9 && (p[1] - y).abs() < 1e-9)
                .unwrap();
            pressure[i]
        };
        assert!(at(0.025, 0.025) < -1900.0 && at(0.275, 0.275) > 1900.0);
        // The velocity field is divergence-free and has zero mean.
        let mean: Real = setup.fluid.velocity.iter().map(|v| v[0] + v[1]).sum();
        assert!(mean.abs() < 1e-9);
    }

    #[test]
    fn initial_velocity_fields_are_checked() {
        let base = "Scene(name: \"v\", dimension: 2, dx: 0.1, end_time: 1.0,
            fluid: (blocks: [Box(min: [0.0, 0.0], max: [1.0, 1.0])], VELOCITY),
            walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0])],
            solver: Wcsph(()))";
        for (field, message) in [
            (
                "velocity: Uniform([1.0])",
                "`fluid.velocity.Uniform`: needs 2 coordinates",
            ),
            (
                "jitter: 0.5",
                "`fluid.jitter`: must lie in [0, 0.4], got 0.5",
            ),
            (
                "velocity: Stretch(centre: [0.0, 0.0], rate: inf)",
                "`fluid.velocity.Stretch.rate`: must be finite",
            ),
        ] {
            let scene = Scene::from_ron(&base.replace("VELOCITY", field)).unwrap();
            let error = scene.validate().unwrap_err().to_string();
            assert!(error.contains(message), "{field}: {error}");
        }
    }
}
