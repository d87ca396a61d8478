//! The cases of the fluid models that only WCSPH has, run from their shipped scenes with the
//! measures of the validation tests (`geosph_tests`): the square drop under surface tension
//! against the Laplace jump, and Sod's shock tube of an ideal gas against the exact Riemann
//! solution. Their variants switch one option of the scene: `off` removes the surface
//! tension (the cost of its passes; the jump is then zero, an error of 1), `hashed` indexes
//! the neighbour search's cells by a hash (the same results, another cost).

use std::time::Instant;

use geosph_core::Real;
use geosph_scene::{Scene, SolverSpec};
use geosph_tests::{drops, shock_tube};

use crate::case::{Measurement, hash_cells};
use crate::{Case, Config};

/// The scene of `config` for the square drop or the shock tube, run to `end_time`.
pub fn scene(case: Case, config: &Config, end_time: Real) -> Result<Scene, String> {
    let mut scene = match case {
        Case::SquareDrop => drops::square_drop(config.dx, end_time, end_time),
        Case::ShockTube => shock_tube::scene(config.dx),
        _ => return Err(format!("{} is not a case of this module", case.name())),
    };
    if config.kernel != scene.kernel {
        return Err(format!(
            "the {} scene runs `{}` only",
            case.name(),
            scene.kernel
        ));
    }
    let SolverSpec::Wcsph(wcsph) = &mut scene.solver else {
        return Err(format!("the {} scene is not WCSPH", case.name()));
    };
    if config.solver != "wcsph" {
        return Err(format!("{} runs WCSPH only", case.name()));
    }
    wcsph.cfl *= config.dt_factor;
    match (config.variant, case) {
        ("default", _) => {}
        ("off", Case::SquareDrop) => wcsph.surface_tension = None,
        ("hashed", _) => hash_cells(&mut scene)?,
        (other, _) => return Err(format!("unknown {} variant `{other}`", case.name())),
    }
    Ok(scene)
}

/// Runs `config` of the square drop or the shock tube and measures it. The drop's error is
/// |Δp/(σ/R) − 1| of its jump Δp at the end (its value Δp in Pa), the tube's the L1 error
/// of the density over the initial jump 0.875 (its value the L1 error of the pressure).
pub fn run(case: Case, config: &Config, quick: bool) -> Result<Measurement, String> {
    let scene = scene(case, config, case.end_time(quick))?;
    let started = Instant::now();
    let (particles, steps, value, error) = match case {
        Case::SquareDrop => {
            let record = drops::try_record(&scene)?;
            let support = 2.0 * scene.smoothing_ratio * scene.dx;
            let drop = drops::relaxed(&record, scene.dx, support);
            let particles = record.last.as_ref().map_or(0, |fluid| fluid.len());
            let error = (drop.jump / drop.laplace - 1.0).abs();
            (particles, record.steps, drop.jump, error)
        }
        Case::ShockTube => {
            let comparison = shock_tube::compare_scene(&scene)?;
            let [density, _, pressure] = comparison.l1;
            (
                comparison.fluid.len(),
                comparison.steps,
                pressure,
                density / 0.875,
            )
        }
        _ => unreachable!("scene() refused it"),
    };
    Ok(Measurement {
        particles,
        steps,
        wall_time: started.elapsed().as_secs_f64(),
        value,
        error,
    })
}
