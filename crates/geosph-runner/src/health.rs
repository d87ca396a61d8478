//! Blow-up checks after every step.

use geosph_core::{Particles, Real};
use geosph_fluid::{FluidSolver, StepReport};

/// Largest relative density error |ρ/ρ₀ − 1| a weakly compressible run may reach before it is
/// declared blown up. WCSPH is designed for ≈ 1 % (Monaghan 1994); 20 % means the sound speed
/// or the time step is far off.
pub const MAX_DENSITY_ERROR: Real = 0.2;

/// What went wrong in a step.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnosis {
    /// The quantity that failed, e.g. "density error" or "velocity".
    pub quantity: &'static str,
    /// The offending particle (current index) and its persistent id, if one is to blame.
    pub particle: Option<(usize, u32)>,
    /// A one-line explanation.
    pub explanation: String,
}

/// Checks the state after a step; `None` when healthy.
pub fn check<const D: usize>(
    report: &StepReport,
    fluid: &Particles<D>,
    solver: &dyn FluidSolver<D>,
) -> Option<Diagnosis> {
    if !(report.dt.is_finite() && report.dt > 0.0) {
        return Some(Diagnosis {
            quantity: "time step",
            particle: None,
            explanation: format!("the time step became {}", report.dt),
        });
    }
    let bad_particle = |quantity: &'static str, i: usize, explanation: String| Diagnosis {
        quantity,
        particle: Some((i, fluid.id[i])),
        explanation,
    };
    if !(report.density_error_max.is_finite() && report.density_error_max <= MAX_DENSITY_ERROR) {
        let i = (0..fluid.len())
            .max_by(|&a, &b| {
                let error = |k: usize| {
                    let e = solver.density_error(fluid.density[k]);
                    if e.is_nan() { Real::INFINITY } else { e }
                };
                error(a).total_cmp(&error(b))
            })
            .unwrap_or(0);
        return Some(bad_particle(
            "density error",
            i,
            format!(
                "density {} is {:.1} % from the rest density (bound {:.0} %): {}",
                fluid.density[i],
                100.0 * solver.density_error(fluid.density[i]),
                100.0 * MAX_DENSITY_ERROR,
                solver.blow_up_advice()
            ),
        ));
    }
    if let Some(i) = fluid
        .velocity
        .iter()
        .zip(&fluid.position)
        .position(|(v, x)| !(v.iter().all(|c| c.is_finite()) && x.iter().all(|c| c.is_finite())))
    {
        return Some(bad_particle(
            "velocity",
            i,
            "position or velocity is not finite".to_owned(),
        ));
    }
    None
}
