//! Sod's shock tube (`data/scenes/sod-shock-tube.ron`) run and compared with the exact
//! solution of its Riemann problem, for the validation test and the figure of `docs/gas.md`.

use geosph_core::{Particles, Real};
use geosph_fluid::GasLaw;
use geosph_fluid::riemann::{GasState, RiemannSolution};
use geosph_runner::{RunOptions, run};
use geosph_scene::{Region, Scene};

use crate::FinalState;

/// The time the tube is compared at, s.
pub const END_TIME: Real = 0.2;

/// The shipped scene at spacing `dx`, its strip 16 particles wide (the period across must
/// hold two supports), without frames, sampled once at the end.
pub fn scene(dx: Real) -> Scene {
    let mut scene = Scene::from_ron(include_str!("../../data/scenes/sod-shock-tube.ron"))
        .expect("the shipped scene parses");
    let width = 16.0 * dx;
    scene.dx = dx;
    scene.output.vtk = false;
    scene.output.sample_interval = END_TIME;
    scene.domain.as_mut().expect("a periodic box").max[1] = width;
    for block in &mut scene.fluid.as_mut().expect("a gas").blocks {
        if let Region::Box { max, .. } = block {
            max[1] = width;
        }
    }
    scene
}

/// Sod's problem: ρ = 1, p = 1 on the left, ρ = 0.125, p = 0.1 on the right, at rest, γ = 1.4.
pub fn exact() -> RiemannSolution {
    let state = |density, pressure| GasState {
        density,
        velocity: 0.0,
        pressure,
    };
    let law = GasLaw {
        gamma: 1.4,
        stiffness: 0.0,
    };
    RiemannSolution::new(law, state(1.0, 1.0), state(0.125, 0.1))
}

/// A run of the tube compared with [`exact`] at t = 0.2.
pub struct Comparison {
    /// L1 errors of ρ, u and p over x ∈ [0, 1] (Sod's problem about x = 0.5), weighted by
    /// the particles' volumes m/ρ: ∫|q − q_exact| dx over the interval's length.
    pub l1: [Real; 3],
    /// |E(t) − E(0)|/E(0) of the total energy E = Σ m (½ v² + e).
    pub energy_drift: Real,
    /// The particles at t = 0.2.
    pub fluid: Particles<2>,
    /// The run's time steps.
    pub steps: usize,
}

fn total_energy(particles: &Particles<2>) -> Real {
    let e = particles.energy.as_ref().expect("a gas carries its energy");
    (0..particles.len())
        .map(|i| particles.mass[i] * (0.5 * particles.velocity[i].norm_squared() + e[i]))
        .sum()
}

/// Runs the tube at spacing `dx` and compares it with the exact solution.
///
/// # Panics
/// If the run fails.
pub fn compare(dx: Real) -> Comparison {
    compare_scene(&scene(dx)).expect("the shock tube runs")
}

/// Runs `scene`, a variant of [`scene`] (e.g. another neighbour search), and compares it
/// with the exact solution; the reason as one line if the run fails.
///
/// # Panics
/// If the run does not end at t = 0.2.
pub fn compare_scene(scene: &Scene) -> Result<Comparison, String> {
    let mut state = FinalState::default();
    let summary =
        run(scene, &RunOptions::default(), &mut state).map_err(|error| error.to_string())?;
    let (time, fluid) = state.plane.expect("a 2D run");
    assert!((time - END_TIME).abs() < 1e-9, "sampled at {time}");
    let exact = exact();
    let pressure = fluid.pressure.as_ref().expect("a fluid's pressure");
    let (mut sums, mut length) = ([0.0; 3], 0.0);
    for i in 0..fluid.len() {
        let x = fluid.position[i][0];
        if (0.0..=1.0).contains(&x) {
            let volume = fluid.mass[i] / fluid.density[i];
            let reference = exact.sample((x - 0.5) / END_TIME);
            sums[0] += volume * (fluid.density[i] - reference.density).abs();
            sums[1] += volume * (fluid.velocity[i][0] - reference.velocity).abs();
            sums[2] += volume * (pressure[i] - reference.pressure).abs();
            length += volume;
        }
    }
    let initial = geosph_scene::build::<2>(scene)
        .map_err(|error| error.to_string())?
        .fluid;
    let start = total_energy(&initial);
    Ok(Comparison {
        l1: sums.map(|s| s / length),
        energy_drift: (total_energy(&fluid) - start).abs() / start,
        fluid,
        steps: summary.steps,
    })
}
