//! What every SPH solver needs besides its own configuration.

use geosph_boundary::WallParticles;
use geosph_core::{Domain, Real, Vector};
use geosph_kernels::KernelKind;
use geosph_neighbours::CellIndex;

use crate::eos::EosKind;

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
    /// How the pair lists' grids index their cells (the scene's `domain.cells`).
    pub cell_index: CellIndex,
    /// The particle ids of each fluid block, in the scene's order (a term that acts on some
    /// blocks only, such as surface tension between two phases, finds its particles by them).
    pub block_ids: Vec<std::ops::Range<u32>>,
}

/// How a solver's particles start, decided by its configuration (`particle_start` of each
/// solver config) and applied by the scene when it builds them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleStart {
    /// The form of ρ(p) that sets the initial density under pressure (a hydrostatic start, an
    /// initial pressure field).
    pub equation_of_state: EosKind,
    /// Its background pressure p_b.
    pub background_pressure: Real,
    /// c₀ fixed by the configuration; `None`: the scene's rule, 10 × the largest expected
    /// speed (max(√(2 |g| H), the largest initial speed)).
    pub sound_speed: Option<Real>,
    /// Whether the particles may start in hydrostatic equilibrium when the scene asks (a
    /// liquid), or always start at ρ₀ (a solid, whose stress comes from its geostatic stage).
    pub hydrostatic: bool,
}
