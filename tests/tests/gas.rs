//! A gas with its energy equation (issue 27): Sod's shock tube (Sod 1978, J. Comput. Phys.
//! 27:1) against the exact solution of its Riemann problem, and the scene errors of a gas.
//!
//! **The shock tube.** An ideal gas (γ = 1.4) at rest, ρ = 1, p = 1 for |x| < 0.5 and
//! ρ = 0.125, p = 0.1 outside, fills a strip periodic in x (period 2) and in y (16 particles
//! across), so the flow is one-dimensional. The two interfaces start two mirrored Riemann
//! problems whose waves do not reach each other before t = 0.2 (the shocks are at
//! x = ±0.85, the rarefactions' heads at ±0.26), so x ∈ [0, 1] holds Sod's problem about
//! x = 0.5: a rarefaction, a contact and a shock. Errors are L1 norms over that interval,
//! ∫|q − q_exact| dx / 1 with the particles' volumes m/ρ as weights, against
//! `geosph_fluid::riemann::RiemannSolution` (its star state checked against Toro 2009,
//! Table 4.2, in its own tests); `geosph_tests::shock_tube` runs and compares.
//!
//! What must hold, from the theory of shock capturing: the L1 errors of a discontinuous
//! solution converge at order 1 at a shock and ½ at a contact (LeVeque 2002, *Finite Volume
//! Methods for Hyperbolic Problems*, §8.7), so each of ρ, u and p must fall from dx = 0.01
//! to dx = 0.005 at an observed order of at least 0.4 (below the contact's ½, the slowest
//! of the two), and the spatial terms conserve mass, momentum and total energy: the energy
//! must hold to 10⁻³ of the initial, the leap-frog's bound O((c Δt/h)²) at C = 0.25 being
//! smaller.

use geosph_core::Real;
use geosph_scene::Scene;
use geosph_tests::shock_tube::compare;

#[test]
fn sod_shock_tube_converges_to_the_exact_solution() {
    let (coarse, fine) = (compare(0.01), compare(0.005));
    let (coarse_drift, fine_drift, fluid) = (coarse.energy_drift, fine.energy_drift, fine.fluid);
    let (coarse, fine) = (coarse.l1, fine.l1);
    let names = ["density", "velocity", "pressure"];
    for k in 0..3 {
        let order = (coarse[k] / fine[k]).log2();
        println!(
            "L1 {}: {:.4e} at dx 0.01, {:.4e} at dx 0.005 (order {order:.2})",
            names[k], coarse[k], fine[k]
        );
        assert!(
            order >= 0.4,
            "L1 {} error {:.3e} → {:.3e}: order {order:.2} < 0.4",
            names[k],
            coarse[k],
            fine[k]
        );
    }
    println!("energy drift {coarse_drift:.2e} at dx 0.01, {fine_drift:.2e} at dx 0.005");
    assert!(coarse_drift < 1e-3 && fine_drift < 1e-3);
    // The flow stays one-dimensional: |v_y| ≤ 10⁻⁶ of the star speed 0.93 m/s.
    let across = fluid
        .velocity
        .iter()
        .map(|v| v[1].abs())
        .fold(0.0, Real::max);
    println!("largest |v_y| {across:.2e} m/s");
    assert!(across < 1e-6, "|v_y| up to {across} m/s");
}

#[test]
fn gas_scene_errors_name_the_field() {
    let base = include_str!("../../data/scenes/sod-shock-tube.ron");
    for (change, field, words) in [
        (
            "        pressure: 0.1,\n",
            "fluid.pressure",
            "needs the gas's initial pressure",
        ),
        (
            "IdealGas(gamma: 1.4)",
            "solver.equation_of_state.gamma",
            "(1, 10]",
        ),
        ("diffusion: None", "solver.diffusion", "barotropic liquid"),
        ("density: Continuity", "solver.density", "Continuity"),
        ("(block: 0,", "fluid.states[0].block", "one of the 2 blocks"),
        ("pressure: 1.0)", "fluid.states[0].pressure", "above −p∞"),
        (
            "gravity: [0.0, 0.0]",
            "fluid.hydrostatic",
            "hydrostatic: false",
        ),
        ("cfl: 0.25,", "solver.xsph", "energy balance"),
        ("states: [", "fluid.states[1].block", "has a state already"),
    ] {
        let changed = match change {
            "        pressure: 0.1,\n" => base.replacen(change, "", 1),
            "IdealGas(gamma: 1.4)" => base.replace(change, "IdealGas(gamma: 1.0)"),
            "diffusion: None" => base.replace(change, "diffusion: Fourtakas(delta: 0.1)"),
            "density: Continuity" => base.replace(change, "density: Summation"),
            "(block: 0," => base.replace(change, "(block: 2,"),
            "pressure: 1.0)" => base.replace(change, "pressure: -1.0)"),
            "cfl: 0.25," => base.replace(change, "cfl: 0.25, xsph: 0.5,"),
            "states: [" => {
                base.replace(change, "states: [(block: 0, density: 2.0, pressure: 2.0), ")
            }
            _ => base
                .replace(change, "gravity: [0.0, -9.81]")
                .replace("hydrostatic: false", "hydrostatic: true"),
        };
        assert_ne!(changed, base, "{change}");
        geosph_tests::assert_refused(&changed, field, words, change);
    }
    // A liquid refuses a gas's fields.
    let liquid = base.replace("equation_of_state: IdealGas(gamma: 1.4),", "");
    let liquid = liquid.replace("diffusion: None,", "sound_speed: Some(10.0),");
    let message = Scene::from_ron(&liquid)
        .unwrap()
        .validate()
        .unwrap_err()
        .to_string();
    assert!(message.contains("fluid.pressure") && message.contains("only for a gas"));
}
