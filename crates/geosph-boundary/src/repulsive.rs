//! The soft repulsive wall force.

use geosph_core::{Real, Vector};

/// The soft repulsive force of Liu et al. (2012), as used with dummy particles by Chalk et al.
/// (2020, Comput. Geotech.), a smoothed descendant of Monaghan's (1994) boundary force.
///
/// A layer of repulsive particles on the wall surface pushes a flow particle i at distance
/// r = |x_ij| < 1.5 dx away with the acceleration
///
/// a_i = Σ_j 0.01 c² χ(r) f(γ) x_ij / r²,
/// χ = 1 − r / (1.5 dx),  γ = r / (0.75 h),
/// f = 2/3 (0 < γ ≤ 2/3),  2γ − 1.5γ² (2/3 < γ ≤ 1),  0.5 (2 − γ)² (1 < γ < 2),  0 (γ ≥ 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepulsiveLiu2012 {
    /// Sound speed c of the flow.
    pub sound_speed: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// Smoothing length h.
    pub smoothing_length: Real,
}

impl RepulsiveLiu2012 {
    /// Range of the force, 1.5 dx.
    pub fn range(&self) -> Real {
        1.5 * self.spacing
    }

    /// The acceleration of particle i from one repulsive particle j, for x_ij = x_i − x_j.
    #[inline]
    pub fn acceleration<const D: usize>(&self, x_ij: &Vector<D>) -> Vector<D> {
        let r2 = x_ij.norm_squared();
        let r = r2.sqrt();
        if r <= 0.0 || r >= self.range() {
            return Vector::zeros();
        }
        let chi = 1.0 - r / self.range();
        let gamma = r / (0.75 * self.smoothing_length);
        let shape = if gamma <= 2.0 / 3.0 {
            2.0 / 3.0
        } else if gamma <= 1.0 {
            2.0 * gamma - 1.5 * gamma * gamma
        } else if gamma < 2.0 {
            0.5 * (2.0 - gamma) * (2.0 - gamma)
        } else {
            0.0
        };
        x_ij * (0.01 * self.sound_speed * self.sound_speed * chi * shape / r2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pushes_away_and_vanishes_at_range() {
        let force = RepulsiveLiu2012 {
            sound_speed: 10.0,
            spacing: 0.01,
            smoothing_length: 0.013,
        };
        let near = force.acceleration(&Vector::<2>::new(0.0, 0.005));
        assert!(near[1] > 0.0 && near[0] == 0.0);
        let farther = force.acceleration(&Vector::<2>::new(0.0, 0.01));
        assert!(farther[1] < near[1]);
        assert_eq!(
            force.acceleration(&Vector::<2>::new(0.0, 0.015)),
            Vector::<2>::zeros()
        );
    }
}
