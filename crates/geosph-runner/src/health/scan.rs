//! One pass over the particles for the blow-up checks.

use geosph_core::{Particles, Real};

use super::{Limits, Quantity};

/// What one sequential pass over the particles finds: sums in index order (the same for any
/// number of threads), the first non-finite value, the first particle outside the domain and
/// the largest stress. Allocates nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scan {
    /// Σ ½ m |v|², J.
    pub kinetic_energy: Real,
    /// Σ m g·x, J (minus the potential energy).
    pub gravity_moment: Real,
    /// The particle with the largest ½ m |v|².
    pub most_energetic: usize,
    /// The first particle with a non-finite position, velocity, density or stress (checked in
    /// that order), the quantity and the value.
    pub non_finite: Option<(usize, Quantity, Real)>,
    /// The first particle outside the domain on a non-periodic axis, and how far out it is, m.
    pub outside: Option<(usize, Real)>,
    /// The largest stress magnitude ‖σ‖ = √(σ:σ), Pa, and its particle (0 without soil).
    pub max_stress: (Real, usize),
}

impl Scan {
    /// Scans `fluid` against the domain and gravity of `limits`.
    pub fn of<const D: usize>(fluid: &Particles<D>, limits: &Limits<D>) -> Self {
        let domain = &limits.domain;
        let mut scan = Self {
            kinetic_energy: 0.0,
            gravity_moment: 0.0,
            most_energetic: 0,
            non_finite: None,
            outside: None,
            max_stress: (0.0, 0),
        };
        let mut most_energy: Real = 0.0;
        let stress = fluid.soil.as_ref().map(|soil| soil.stress.as_slice());
        for (i, (((x, v), m), rho)) in fluid
            .position
            .iter()
            .zip(&fluid.velocity)
            .zip(&fluid.mass)
            .zip(&fluid.density)
            .enumerate()
        {
            let energy = 0.5 * m * v.norm_squared();
            scan.kinetic_energy += energy;
            if energy > most_energy {
                most_energy = energy;
                scan.most_energetic = i;
            }
            scan.gravity_moment += m * limits.gravity.dot(x);
            let stress_norm = stress.map_or(0.0, |stress| stress[i].norm());
            if stress_norm > scan.max_stress.0 {
                scan.max_stress = (stress_norm, i);
            }
            if scan.non_finite.is_none() {
                let first_bad = |values: &[Real]| values.iter().copied().find(|c| !c.is_finite());
                scan.non_finite = if let Some(c) = first_bad(x.as_slice()) {
                    Some((i, Quantity::Position, c))
                } else if let Some(c) = first_bad(v.as_slice()) {
                    Some((i, Quantity::Velocity, c))
                } else if !rho.is_finite() {
                    Some((i, Quantity::Density, *rho))
                } else if !stress_norm.is_finite() {
                    Some((i, Quantity::Stress, stress_norm))
                } else {
                    None
                };
            }
            if scan.outside.is_none() {
                let mut distance: Real = 0.0;
                for k in (0..D).filter(|&k| !domain.periodic[k]) {
                    distance = distance.max(domain.min[k] - x[k]).max(x[k] - domain.max[k]);
                    if x[k] >= domain.max[k] && distance == 0.0 {
                        // On the half-open upper face: out by round-off.
                        distance = Real::MIN_POSITIVE;
                    }
                }
                if distance > 0.0 {
                    scan.outside = Some((i, distance));
                }
            }
        }
        scan
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
        fluid.velocity[2] = Vector::<2>::new(Real::NAN, 0.0);
        let scan = Scan::of(&fluid, &limits);
        assert!(scan.kinetic_energy.is_nan());
        assert_eq!(scan.most_energetic, 0);
        assert_eq!(scan.gravity_moment, -2.0 * 10.0 * (0.5 + 1.25 + 0.25));
        assert_eq!(scan.outside, Some((1, 0.25)));
        let (i, quantity, value) = scan.non_finite.unwrap();
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
        assert_eq!(Scan::of(&fluid, &limits).outside, None);
    }
}
