//! The axis-aligned simulation domain and its periodic axes.

use crate::types::{Real, Vector};

/// An axis-aligned box `[min, max)` that contains every particle, with optional periodic axes.
///
/// On a periodic axis of length `L = max − min` a particle leaving through one face re-enters
/// through the other ([`Domain::wrap`]) and the displacement between two particles is the
/// minimum image ([`Domain::displacement`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Domain<const D: usize> {
    /// Lower corner.
    pub min: Vector<D>,
    /// Upper corner.
    pub max: Vector<D>,
    /// `periodic[k]` is true when axis `k` wraps around.
    pub periodic: [bool; D],
}

/// Why a [`Domain`] could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DomainError {
    /// An upper bound is not strictly above its lower bound, or a bound is not finite.
    #[error("domain axis {axis}: need finite min < max, got min = {min}, max = {max}")]
    EmptyAxis {
        /// The axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// Its lower bound.
        min: Real,
        /// Its upper bound.
        max: Real,
    },
}

impl<const D: usize> Domain<D> {
    /// A domain with no periodic axis.
    pub fn new(min: Vector<D>, max: Vector<D>) -> Result<Self, DomainError> {
        Self::with_periodic(min, max, [false; D])
    }

    /// A domain whose axes `k` with `periodic[k]` wrap around.
    pub fn with_periodic(
        min: Vector<D>,
        max: Vector<D>,
        periodic: [bool; D],
    ) -> Result<Self, DomainError> {
        for axis in 0..D {
            let (lo, hi) = (min[axis], max[axis]);
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(DomainError::EmptyAxis {
                    axis,
                    min: lo,
                    max: hi,
                });
            }
        }
        Ok(Self { min, max, periodic })
    }

    /// Edge lengths `max − min`.
    pub fn extent(&self) -> Vector<D> {
        self.max - self.min
    }

    /// Whether any axis is periodic.
    pub fn is_periodic(&self) -> bool {
        self.periodic.iter().any(|&p| p)
    }

    /// Whether `x` lies inside `[min, max)` on every axis.
    pub fn contains(&self, x: &Vector<D>) -> bool {
        (0..D).all(|k| x[k] >= self.min[k] && x[k] < self.max[k])
    }

    /// Whether `x` has left the domain: it lies outside `[min, max)` on a non-periodic axis
    /// (a NaN coordinate there counts as outside). Periodic axes have no boundary.
    pub fn has_left(&self, x: &Vector<D>) -> bool {
        (0..D).any(|k| !(self.periodic[k] || (x[k] >= self.min[k] && x[k] < self.max[k])))
    }

    /// The minimum-image displacement `x_i − x_j`.
    ///
    /// On a periodic axis of length `L` the component `d` is replaced by `d − L·round(d/L)`,
    /// so that `|d| ≤ L/2`.
    #[inline]
    pub fn displacement(&self, x_i: &Vector<D>, x_j: &Vector<D>) -> Vector<D> {
        let mut d = x_i - x_j;
        for k in 0..D {
            if self.periodic[k] {
                let length = self.max[k] - self.min[k];
                d[k] -= length * (d[k] / length).round();
            }
        }
        d
    }

    /// Maps `x` back into `[min, max)` along the periodic axes; other axes are left alone.
    pub fn wrap(&self, x: &mut Vector<D>) {
        for k in 0..D {
            if self.periodic[k] {
                let length = self.max[k] - self.min[k];
                let mut offset = (x[k] - self.min[k]).rem_euclid(length);
                // rem_euclid can round up to `length` itself for tiny negative offsets.
                if offset >= length {
                    offset = 0.0;
                }
                x[k] = self.min[k] + offset;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn minimum_image_on_periodic_axis_only() {
        let domain = Domain::with_periodic(
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(1.0, 1.0),
            [true, false],
        )
        .unwrap();
        let d = domain.displacement(&Vector::<2>::new(0.95, 0.9), &Vector::<2>::new(0.05, 0.1));
        assert_relative_eq!(d[0], -0.1, epsilon = 1e-14);
        assert_relative_eq!(d[1], 0.8, epsilon = 1e-14);
    }

    #[test]
    fn wrap_maps_into_half_open_box() {
        let domain = Domain::with_periodic(
            Vector::<2>::new(-1.0, 0.0),
            Vector::<2>::new(1.0, 2.0),
            [true, true],
        )
        .unwrap();
        let mut x = Vector::<2>::new(1.25, -0.5);
        domain.wrap(&mut x);
        assert_relative_eq!(x[0], -0.75, epsilon = 1e-14);
        assert_relative_eq!(x[1], 1.5, epsilon = 1e-14);
        let mut edge = Vector::<2>::new(-1e-18, 2.0);
        domain.wrap(&mut edge);
        assert!(domain.contains(&edge), "{edge:?}");
    }

    #[test]
    fn rejects_empty_axis() {
        let err = Domain::new(Vector::<2>::new(0.0, 1.0), Vector::<2>::new(1.0, 1.0)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "domain axis 1: need finite min < max, got min = 1, max = 1"
        );
    }
}
