//! Adaptive time-step limits of explicit SPH.

use geosph_core::Real;

/// What bounds the time step of an explicit SPH step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepLimits {
    /// Courant number C applied to the acoustic/advective limit (Monaghan 1992: C ≈ 0.25–0.4).
    pub cfl: Real,
    /// Smoothing length h.
    pub smoothing_length: Real,
    /// Sound speed c (0 for incompressible solvers, leaving the advective limit).
    pub sound_speed: Real,
    /// Largest particle speed |v|max.
    pub max_speed: Real,
    /// Largest acceleration |a|max (including gravity).
    pub max_acceleration: Real,
    /// Kinematic viscosity ν (0 when inviscid).
    pub kinematic_viscosity: Real,
}

/// The time step
/// Δt = min( C h / (c + |v|max),  ¼ √(h / |a|max),  ⅛ h² / ν ),
/// the acoustic CFL (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30, §10), the body-force limit
/// and the viscous-diffusion limit (Morris, Fox & Zhu 1997, J. Comput. Phys. 136, eqs. 12–13).
/// Limits whose denominator is zero are skipped; with all of them zero the result is infinite.
pub fn time_step(limits: &StepLimits) -> Real {
    let h = limits.smoothing_length;
    let mut dt = Real::INFINITY;
    let signal = limits.sound_speed + limits.max_speed;
    if signal > 0.0 {
        dt = dt.min(limits.cfl * h / signal);
    }
    if limits.max_acceleration > 0.0 {
        dt = dt.min(0.25 * (h / limits.max_acceleration).sqrt());
    }
    if limits.kinematic_viscosity > 0.0 {
        dt = dt.min(0.125 * h * h / limits.kinematic_viscosity);
    }
    dt
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn smallest_limit_wins() {
        let mut limits = StepLimits {
            cfl: 0.25,
            smoothing_length: 0.02,
            sound_speed: 60.0,
            max_speed: 4.0,
            max_acceleration: 9.81,
            kinematic_viscosity: 0.0,
        };
        assert_relative_eq!(time_step(&limits), 0.25 * 0.02 / 64.0);
        limits.kinematic_viscosity = 1.0;
        assert_relative_eq!(time_step(&limits), 0.125 * 0.02 * 0.02);
        limits.sound_speed = 0.0;
        limits.max_speed = 0.0;
        limits.kinematic_viscosity = 0.0;
        assert_relative_eq!(time_step(&limits), 0.25 * (0.02_f64 / 9.81).sqrt());
    }
}
