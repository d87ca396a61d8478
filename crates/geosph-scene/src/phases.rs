//! Two phases of one fluid: what a scene with surface tension must give and refuse.

use crate::checks::fail;
use crate::format::{FluidSpec, Scene, SolverSpec};
use crate::validate::SceneError;

/// Checks `solver.surface_tension` against the fluid's blocks: each named block exists and is
/// named once, some block is left for the phase around them, and the fluid touches no walls
/// or bodies (a contact angle is not modelled: a wall would see the colour of neither phase).
pub(crate) fn validate(scene: &Scene, fluid: &FluidSpec) -> Result<(), SceneError> {
    let SolverSpec::Wcsph(config) = &scene.solver else {
        return Ok(());
    };
    let Some(tension) = &config.surface_tension else {
        return Ok(());
    };
    let count = fluid.blocks.len();
    for (k, &block) in tension.blocks.iter().enumerate() {
        let field = format!("solver.surface_tension.blocks[{k}]");
        if block >= count {
            return Err(fail(
                field,
                format!(
                    "must be the index of a fluid block, 0 to {}, got {block}",
                    count - 1
                ),
            ));
        }
        if tension.blocks[..k].contains(&block) {
            return Err(fail(field, format!("names block {block} twice")));
        }
    }
    if tension.blocks.len() == count {
        return Err(fail(
            "solver.surface_tension.blocks",
            "names every fluid block: surface tension acts between the named blocks and the \
             others, so leave the phase around them out (a free surface against empty space \
             is not modelled)",
        ));
    }
    if !scene.walls.is_empty() {
        return Err(fail(
            "walls",
            "surface tension runs without walls for now (a periodic domain): the contact \
             angle of the interface at a wall is not modelled",
        ));
    }
    if !scene.bodies.is_empty() {
        return Err(fail(
            "bodies",
            "surface tension runs without bodies for now: the contact angle of the interface \
             at a body is not modelled",
        ));
    }
    Ok(())
}
