//! Storage of dummy wall particles.

use geosph_core::{Real, Vector};
use serde::{Deserialize, Serialize};

/// How a wall acts on the tangential velocity of the flow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Slip {
    /// The flow sticks to the wall: a physical viscous term sees the dummy velocity mirror the
    /// fluid's (Adami et al. 2012, eq. 22), so the flow's velocity at the wall surface is the
    /// wall's.
    #[default]
    NoSlip,
    /// The flow slides freely: the dummy velocity equals the fluid's, so no viscous term,
    /// physical or artificial, exerts shear at the wall (nor resists approach: the wall's
    /// pressure does). For flows whose boundary layer is far thinner than the particle
    /// spacing and does not matter to the result.
    FreeSlip,
}

impl Slip {
    /// The velocity ũ_w that a wall particle moving at `wall` (u_w) shows a viscous term, with
    /// `flow` the Shepard-weighted velocity of its flow neighbours:
    ///
    /// - no-slip, physical term: ũ_w = 2 u_w − flow (Adami, Hu & Adams 2012, eq. 22);
    /// - no-slip, artificial term: ũ_w = u_w, the wall particles as they move (Monaghan 1992's
    ///   approach-only term then also drags a flow along the wall, a friction set by α h c₀);
    /// - free-slip: ũ_w = flow.
    pub fn viscous_velocity<const D: usize>(
        self,
        physical: bool,
        wall: Vector<D>,
        flow: Vector<D>,
    ) -> Vector<D> {
        match self {
            Slip::NoSlip if physical => wall * 2.0 - flow,
            Slip::NoSlip => wall,
            Slip::FreeSlip => flow,
        }
    }
}

/// Dummy wall particles: the geometry is fixed at creation; pressure, density and the velocity
/// seen by viscous terms are recomputed every step from the neighbouring flow.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallParticles<const D: usize> {
    /// Positions.
    pub position: Vec<Vector<D>>,
    /// Prescribed wall velocity u_w (zero for a fixed wall).
    pub velocity: Vec<Vector<D>>,
    /// Prescribed wall acceleration a_w (zero for a fixed wall).
    pub acceleration: Vec<Vector<D>>,
    /// Volume V_w = dx^D of each particle.
    pub volume: Vec<Real>,
    /// Unit normal of the wall surface, pointing into the flow.
    pub normal: Vec<Vector<D>>,
    /// Distance from the particle to the wall surface (≥ 0), used by Bui's rule.
    pub depth: Vec<Real>,
    /// Extrapolated pressure p_w.
    pub pressure: Vec<Real>,
    /// Density ρ_w = ρ(p_w) from the equation of state.
    pub density: Vec<Real>,
    /// Velocity ũ_w that viscous terms see.
    pub viscous_velocity: Vec<Vector<D>>,
}

impl<const D: usize> WallParticles<D> {
    /// Fixed walls at `position`, each of volume `volume`, with normals and depths from the
    /// generator; the pressure starts at zero and the density at `rest_density`.
    pub fn fixed(
        position: Vec<Vector<D>>,
        normal: Vec<Vector<D>>,
        depth: Vec<Real>,
        volume: Real,
        rest_density: Real,
    ) -> Self {
        let n = position.len();
        assert_eq!(normal.len(), n, "one normal per wall particle");
        assert_eq!(depth.len(), n, "one depth per wall particle");
        Self {
            position,
            velocity: vec![Vector::zeros(); n],
            acceleration: vec![Vector::zeros(); n],
            volume: vec![volume; n],
            normal,
            depth,
            pressure: vec![0.0; n],
            density: vec![rest_density; n],
            viscous_velocity: vec![Vector::zeros(); n],
        }
    }

    /// Number of wall particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Keeps the particles `k` with `keep[k]`, in their order.
    ///
    /// # Panics
    /// If `keep` does not hold one flag per particle.
    pub fn retain(&mut self, keep: &[bool]) {
        use geosph_core::retain;
        retain(&mut self.position, keep);
        retain(&mut self.velocity, keep);
        retain(&mut self.acceleration, keep);
        retain(&mut self.volume, keep);
        retain(&mut self.normal, keep);
        retain(&mut self.depth, keep);
        retain(&mut self.pressure, keep);
        retain(&mut self.density, keep);
        retain(&mut self.viscous_velocity, keep);
    }

    /// Appends the particles of `other`.
    pub fn extend(&mut self, other: WallParticles<D>) {
        self.position.extend(other.position);
        self.velocity.extend(other.velocity);
        self.acceleration.extend(other.acceleration);
        self.volume.extend(other.volume);
        self.normal.extend(other.normal);
        self.depth.extend(other.depth);
        self.pressure.extend(other.pressure);
        self.density.extend(other.density);
        self.viscous_velocity.extend(other.viscous_velocity);
    }
}
