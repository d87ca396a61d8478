//! What every SPH solver needs besides its own configuration.

use geosph_boundary::WallParticles;
use geosph_core::{Domain, Real, Vector};
use geosph_kernels::KernelKind;

/// The scene-level inputs of a solver: kernel, domain, material reference values, gravity and
/// walls.
pub struct SphSetup<const D: usize> {
    /// The smoothing kernel's name.
    pub kernel: KernelKind,
    /// Smoothing length h.
    pub smoothing_length: Real,
    /// Domain.
    pub domain: Domain<D>,
    /// Rest (reference) density ρ₀.
    pub rest_density: Real,
    /// Reference sound speed c₀ of a fluid (already resolved from its configuration or the
    /// default rule); a soil derives its wave speed from its elastic constants instead.
    pub sound_speed: Real,
    /// Gravity.
    pub gravity: Vector<D>,
    /// Wall particles.
    pub walls: WallParticles<D>,
    /// Particle spacing dx.
    pub spacing: Real,
}
