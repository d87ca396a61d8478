//! One pass over the particles for the blow-up checks.

use geosph_core::{Particles, Real, Vector};
use geosph_sph::Transport;

use super::{Limits, Quantity};

/// What one sequential, branch-free pass over the particles finds: sums in index order (the
/// same for any number of threads), whether every value is finite, the bounding box of the
/// positions and the largest stress. Which particle is to blame is looked up only once a
/// check has failed ([`Scan::first_non_finite`], [`Scan::first_outside`],
/// [`Scan::most_energetic`], [`Scan::largest_stress`]). Allocates nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scan<const D: usize> {
    /// Σ ½ m |v|², J.
    pub kinetic_energy: Real,
    /// Σ m g·x, J (minus the potential energy).
    pub gravity_moment: Real,
    /// Whether every position, velocity, density and stress component is finite.
    pub finite: bool,
    /// Lower corner of the positions' bounding box.
    pub lowest: Vector<D>,
    /// Upper corner of the positions' bounding box.
    pub highest: Vector<D>,
    /// The largest stress magnitude ‖σ‖ = √(σ:σ), Pa (0 without soil).
    pub max_stress: Real,
}

impl<const D: usize> Scan<D> {
    /// Scans `fluid` with the gravity of `limits`.
    pub fn of(fluid: &Particles<D>, limits: &Limits<D>) -> Self {
        Self::of_first(fluid, fluid.len(), limits)
    }

    /// Scans the first `count` particles of `fluid` (a rank's own, its halo after them).
    pub fn of_first(fluid: &Particles<D>, count: usize, limits: &Limits<D>) -> Self {
        let mut kinetic_energy: Real = 0.0;
        let mut gravity_moment: Real = 0.0;
        // Any NaN or infinity makes this sum NaN or infinite (finite values overflowing it is
        // caught too, and then not pinned on a particle).
        let mut sum: Real = 0.0;
        let mut lowest = Vector::<D>::repeat(Real::INFINITY);
        let mut highest = Vector::<D>::repeat(Real::NEG_INFINITY);
        for (((x, v), m), rho) in fluid
            .position
            .iter()
            .zip(&fluid.velocity)
            .zip(&fluid.mass)
            .zip(&fluid.density)
            .take(count)
        {
            kinetic_energy += 0.5 * m * v.norm_squared();
            gravity_moment += m * limits.gravity.dot(x);
            sum += x.sum() + v.sum() + rho;
            lowest = lowest.inf(x);
            highest = highest.sup(x);
        }
        let mut max_stress_squared: Real = 0.0;
        if let Some(soil) = &fluid.soil {
            for stress in soil.stress.iter().take(count) {
                sum += stress.sum();
                max_stress_squared = max_stress_squared.max(stress.norm_squared());
            }
        }
        Self {
            kinetic_energy,
            gravity_moment,
            finite: sum.is_finite(),
            lowest,
            highest,
            max_stress: max_stress_squared.sqrt(),
        }
    }

    /// The scan of the particles of every rank from each rank's scan of its own (collective;
    /// one gather): the sums added in rank order, the box and the stress exact.
    pub fn over_ranks(&self, transport: &dyn Transport) -> Self {
        let mut mine = vec![
            self.kinetic_energy,
            self.gravity_moment,
            Real::from(u8::from(self.finite)),
            self.max_stress,
        ];
        mine.extend(self.lowest.iter().chain(self.highest.iter()));
        let all = transport.gather_each(&mine);
        let mut ranks = all.chunks_exact(mine.len()).map(|rank| Self {
            kinetic_energy: rank[0],
            gravity_moment: rank[1],
            finite: rank[2] > 0.0,
            max_stress: rank[3],
            lowest: Vector::from_column_slice(&rank[4..4 + D]),
            highest: Vector::from_column_slice(&rank[4 + D..]),
        });
        let first = ranks.next().unwrap_or(*self);
        ranks.fold(first, |all, rank| Self {
            kinetic_energy: all.kinetic_energy + rank.kinetic_energy,
            gravity_moment: all.gravity_moment + rank.gravity_moment,
            finite: all.finite && rank.finite,
            max_stress: all.max_stress.max(rank.max_stress),
            lowest: all.lowest.inf(&rank.lowest),
            highest: all.highest.sup(&rank.highest),
        })
    }

    /// Whether the bounding box leaves the domain of `limits` on a non-periodic axis.
    pub fn leaves_domain(&self, limits: &Limits<D>) -> bool {
        let domain = &limits.domain;
        (0..D).any(|k| {
            !domain.periodic[k]
                && (self.lowest[k] < domain.min[k] || self.highest[k] >= domain.max[k])
        })
    }

    /// The first particle with a non-finite position, velocity, density or stress (checked in
    /// that order), the quantity and the value.
    pub fn first_non_finite(fluid: &Particles<D>) -> Option<(usize, Quantity, Real)> {
        let first_bad = |values: &[Real]| values.iter().copied().find(|c| !c.is_finite());
        (0..fluid.len()).find_map(|i| {
            if let Some(c) = first_bad(fluid.position[i].as_slice()) {
                Some((i, Quantity::Position, c))
            } else if let Some(c) = first_bad(fluid.velocity[i].as_slice()) {
                Some((i, Quantity::Velocity, c))
            } else if !fluid.density[i].is_finite() {
                Some((i, Quantity::Density, fluid.density[i]))
            } else {
                let stress = fluid.soil.as_ref().map(|soil| soil.stress[i].as_slice());
                stress.and_then(first_bad).map(|c| (i, Quantity::Stress, c))
            }
        })
    }

    /// The first particle outside the domain of `limits` on a non-periodic axis, and how far
    /// out it is, m (the smallest positive number for a particle on the open upper face).
    pub fn first_outside(fluid: &Particles<D>, limits: &Limits<D>) -> Option<(usize, Real)> {
        let domain = &limits.domain;
        fluid.position.iter().enumerate().find_map(|(i, x)| {
            let mut distance: Real = 0.0;
            let mut out = false;
            for k in (0..D).filter(|&k| !domain.periodic[k]) {
                out |= x[k] < domain.min[k] || x[k] >= domain.max[k];
                distance = distance.max(domain.min[k] - x[k]).max(x[k] - domain.max[k]);
            }
            out.then_some((i, distance.max(Real::MIN_POSITIVE)))
        })
    }

    /// The particle with the largest ½ m |v|².
    pub fn most_energetic(fluid: &Particles<D>) -> usize {
        let energy = |i: usize| fluid.mass[i] * fluid.velocity[i].norm_squared();
        (0..fluid.len())
            .max_by(|&a, &b| energy(a).total_cmp(&energy(b)))
            .unwrap_or(0)
    }

    /// The particle with the largest ‖σ‖, and that norm (0 without soil).
    pub fn largest_stress(fluid: &Particles<D>) -> (usize, Real) {
        let Some(soil) = &fluid.soil else {
            return (0, 0.0);
        };
        soil.stress
            .iter()
            .map(|s| s.norm())
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use geosph_core::{Domain, Vector};

    use super::*;
    use crate::health::Limits;

    fn limits(domain: Domain<2>) -> Limits<2> {
        Limits {
            domain,
            gravity: Vector::<2>::new(0.0, -10.0),
            rest_density: 1000.0,
            spacing: 0.1,
            support_radius: 0.26,
            energy: None,
            max_stress: None,
        }
    }

    #[test]
    fn finds_energy_moment_non_finite_values_and_escapes() {
        let domain = Domain::new(Vector::<2>::zeros(), Vector::<2>::repeat(1.0)).unwrap();
        let limits = limits(domain);
        let mut fluid = Particles::at_rest(
            vec![
                Vector::<2>::new(0.5, 0.5),
                Vector::<2>::new(0.5, 1.25),
                Vector::<2>::new(0.5, 0.25),
            ],
            2.0,
            1000.0,
        );
        fluid.velocity[0] = Vector::<2>::new(3.0, 4.0);
        let scan = Scan::of(&fluid, &limits);
        assert_eq!(scan.kinetic_energy, 25.0);
        assert_eq!(scan.gravity_moment, -2.0 * 10.0 * (0.5 + 1.25 + 0.25));
        assert!(scan.finite && scan.leaves_domain(&limits));
        assert_eq!(Scan::first_outside(&fluid, &limits), Some((1, 0.25)));
        assert_eq!(Scan::most_energetic(&fluid), 0);

        fluid.velocity[2] = Vector::<2>::new(Real::NAN, 0.0);
        assert!(!Scan::of(&fluid, &limits).finite);
        let (i, quantity, value) = Scan::first_non_finite(&fluid).unwrap();
        assert_eq!((i, quantity), (2, Quantity::Velocity));
        assert!(value.is_nan());
    }

    #[test]
    fn periodic_axes_are_not_boundaries() {
        let domain = Domain::with_periodic(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [true, false],
        )
        .unwrap();
        let limits = limits(domain);
        let fluid = Particles::at_rest(vec![Vector::<2>::new(1.5, 0.5)], 1.0, 1000.0);
        assert!(!Scan::of(&fluid, &limits).leaves_domain(&limits));
        assert_eq!(Scan::first_outside(&fluid, &limits), None);
    }
}
