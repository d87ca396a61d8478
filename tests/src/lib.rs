//! Shared set-ups for the geosph validation tests: particle lattices and random point sets,
//! the shock tube ([`shock_tube`]) and drops under surface tension ([`drops`]).
#![warn(missing_docs)]

pub mod drops;
pub mod shock_tube;
pub mod viscous_drop;

use geosph_core::{Real, Vector};
use rand::{Rng, SeedableRng, rngs::StdRng};

/// A regular lattice of `counts[k]` points per axis with spacing `dx`, the first point at
/// `origin + dx/2` on every axis, each point moved by a uniform random offset in
/// `[−jitter, jitter]·dx` per axis (seeded, so the set is reproducible).
pub fn jittered_lattice<const D: usize>(
    origin: Vector<D>,
    counts: [usize; D],
    dx: Real,
    jitter: Real,
    seed: u64,
) -> Vec<Vector<D>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let total: usize = counts.iter().product();
    let mut points = Vec::with_capacity(total);
    for linear in 0..total {
        let mut rest = linear;
        let mut x = origin;
        for k in 0..D {
            let index = rest % counts[k];
            rest /= counts[k];
            let offset = if jitter > 0.0 {
                rng.random_range(-jitter..=jitter)
            } else {
                0.0
            };
            x[k] += (index as Real + 0.5 + offset) * dx;
        }
        points.push(x);
    }
    points
}

/// `n` points drawn uniformly from the box `[min, max)` (seeded).
pub fn random_points<const D: usize>(
    min: Vector<D>,
    max: Vector<D>,
    n: usize,
    seed: u64,
) -> Vec<Vector<D>> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| Vector::<D>::from_fn(|k, _| rng.random_range(min[k]..max[k])))
        .collect()
}

/// Asserts that the scene `text` is refused with a message naming `field` and containing
/// `words`; `case` names the change in the failure.
///
/// # Panics
/// If the scene parses and validates, or its message lacks `field` or `words`.
pub fn assert_refused(text: &str, field: &str, words: &str, case: &str) {
    let message = geosph_scene::Scene::from_ron(text)
        .and_then(|scene| scene.validate().map(|()| scene))
        .expect_err(case)
        .to_string();
    assert!(
        message.contains(field) && message.contains(words),
        "{case}: {message}"
    );
}

/// An observer that keeps a copy of the fluid at the latest sample time, so a test can inspect
/// the final state of a run.
#[derive(Clone, Debug, Default)]
pub struct FinalState {
    /// The last 2D sample.
    pub plane: Option<(Real, geosph_core::Particles<2>)>,
    /// The last 3D sample.
    pub space: Option<(Real, geosph_core::Particles<3>)>,
}

impl geosph_runner::Observer<2> for FinalState {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn sample(&mut self, time: Real, fluid: &geosph_core::Particles<2>, _row: &mut Vec<Real>) {
        self.plane = Some((time, fluid.clone()));
    }
}

impl geosph_runner::Observer<3> for FinalState {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn sample(&mut self, time: Real, fluid: &geosph_core::Particles<3>, _row: &mut Vec<Real>) {
        self.space = Some((time, fluid.clone()));
    }
}
