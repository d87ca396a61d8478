//! The initial state of a gas: what a gas scene must give and refuse, and each particle's
//! density, mass, pressure and internal energy from its block's state.

use geosph_core::{Particles, Real};
use geosph_sph::GasLaw;

use crate::checks::{fail, positive};
use crate::format::{FluidSpec, InitialVelocity, Scene};
use crate::regions::BlockReport;
use crate::validate::SceneError;

/// The gas law of the scene's equation of state, `None` for a liquid.
pub(crate) fn gas_law(scene: &Scene) -> Option<GasLaw> {
    scene.solver.particle_start().equation_of_state.gas_law()
}

/// A pressure a gas of stiffness p∞ can have: finite and above −p∞ (c² = γ (p + p∞)/ρ > 0).
fn gas_pressure(field: &str, pressure: Real, law: &GasLaw) -> Result<(), SceneError> {
    if pressure.is_finite() && pressure > -law.stiffness {
        Ok(())
    } else {
        Err(fail(
            field,
            format!(
                "must be a finite pressure above −p∞ = {} Pa (the gas's sound speed \
                 c² = γ (p + p∞)/ρ must be positive), got {pressure}",
                -law.stiffness
            ),
        ))
    }
}

/// Checks the fluid's gas fields against the equation of state: a gas needs
/// `fluid.pressure`, a liquid refuses it and `fluid.states`; a gas runs without walls or
/// bodies (the energy they exchange with it is not written) and starts from its given state.
pub(crate) fn validate(scene: &Scene, fluid: &FluidSpec) -> Result<(), SceneError> {
    let Some(law) = gas_law(scene) else {
        let liquid = "only for a gas equation of state (`IdealGas` or `StiffenedGas` in the \
                      solver block); a liquid's pressure follows from its density";
        if fluid.pressure.is_some() {
            return Err(fail("fluid.pressure", liquid));
        }
        if !fluid.states.is_empty() {
            return Err(fail("fluid.states", liquid));
        }
        return Ok(());
    };
    let Some(pressure) = fluid.pressure else {
        return Err(fail(
            "fluid.pressure",
            "a gas equation of state needs the gas's initial pressure in Pa: with \
             `fluid.density` it sets each particle's internal energy e = (p + γ p∞)/((γ − 1) ρ)",
        ));
    };
    gas_pressure("fluid.pressure", pressure, &law)?;
    for (index, state) in fluid.states.iter().enumerate() {
        let field = format!("fluid.states[{index}]");
        if state.block >= fluid.blocks.len() {
            return Err(fail(
                format!("{field}.block"),
                format!(
                    "must name one of the {} blocks (0 to {}), got {}",
                    fluid.blocks.len(),
                    fluid.blocks.len() - 1,
                    state.block
                ),
            ));
        }
        if fluid.states[..index]
            .iter()
            .any(|earlier| earlier.block == state.block)
        {
            return Err(fail(
                format!("{field}.block"),
                format!(
                    "block {} has a state already: give each block one",
                    state.block
                ),
            ));
        }
        positive(&format!("{field}.density"), state.density)?;
        gas_pressure(&format!("{field}.pressure"), state.pressure, &law)?;
    }
    if !scene.walls.is_empty() {
        return Err(fail(
            "walls",
            "a gas runs without walls for now (a periodic or open domain): the energy it \
             exchanges with walls is not written",
        ));
    }
    if !scene.bodies.is_empty() {
        return Err(fail(
            "bodies",
            "a gas runs without bodies for now: the energy it exchanges with them is not written",
        ));
    }
    let gravity = scene
        .gravity
        .as_ref()
        .is_none_or(|g| g.iter().any(|&g| g != 0.0));
    if fluid.hydrostatic && gravity {
        return Err(fail(
            "fluid.hydrostatic",
            "a gas starts from its given state: set `hydrostatic: false` (or gravity to zero)",
        ));
    }
    if matches!(fluid.velocity, InitialVelocity::TaylorGreen { .. }) {
        return Err(fail(
            "fluid.velocity",
            "the Taylor–Green start sets a liquid's pressure field, not a gas's",
        ));
    }
    Ok(())
}

/// Sets each particle's state: (`fluid.density`, `fluid.pressure`), or its block's in
/// `fluid.states`, with mass ρ `volume` (the lattice volume dx^D) and internal energy
/// e = [`GasLaw::energy`]. The particles are in block order, `blocks[k].particles` of block k.
pub(crate) fn set_state<const D: usize>(
    particles: &mut Particles<D>,
    fluid: &FluidSpec,
    blocks: &[BlockReport],
    law: GasLaw,
    volume: Real,
) {
    let base = (fluid.density, fluid.pressure.expect("validated"));
    let mut state = vec![base; blocks.len()];
    for given in &fluid.states {
        state[given.block] = (given.density, given.pressure);
    }
    let mut pressure = Vec::with_capacity(particles.len());
    let mut energy = Vec::with_capacity(particles.len());
    let mut i = 0;
    for (block, report) in blocks.iter().enumerate() {
        let (rho, p) = state[block];
        for _ in 0..report.particles {
            particles.density[i] = rho;
            particles.mass[i] = rho * volume;
            pressure.push(p);
            energy.push(law.energy(rho, p));
            i += 1;
        }
    }
    assert_eq!(
        i,
        particles.len(),
        "the blocks' reports count every particle"
    );
    particles.pressure = Some(pressure);
    particles.energy = Some(energy);
}
