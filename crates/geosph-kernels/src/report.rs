//! What a correction reports: how many particles could not be corrected.

use std::fmt;

use geosph_core::{NeighbourList, Real, Vector};

/// The outcome of a correction pass ([`crate::cspm::gradient_correction`],
/// [`crate::mls::mls_coefficients`]).
///
/// A particle whose moment matrix is singular or ill-conditioned (isolated, too few or
/// degenerate neighbours) gets a documented fallback instead of a correction; those particles
/// are counted here, never silently. The report is the same for any number of threads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CorrectionReport {
    /// Number of particles processed.
    pub particles: usize,
    /// Number of particles that fell back.
    pub fallbacks: usize,
    /// Smallest index among the particles that fell back.
    pub first_fallback: Option<usize>,
}

impl CorrectionReport {
    /// Whether every particle was corrected.
    pub fn all_corrected(&self) -> bool {
        self.fallbacks == 0
    }

    /// The report of one particle `index`.
    pub(crate) fn single(index: usize, fell_back: bool) -> Self {
        Self {
            particles: 1,
            fallbacks: usize::from(fell_back),
            first_fallback: fell_back.then_some(index),
        }
    }

    /// Combines two reports; associative and commutative, so a parallel reduction gives the
    /// same result in any order.
    pub(crate) fn merge(self, other: Self) -> Self {
        let first_fallback = match (self.first_fallback, other.first_fallback) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Self {
            particles: self.particles + other.particles,
            fallbacks: self.fallbacks + other.fallbacks,
            first_fallback,
        }
    }
}

impl fmt::Display for CorrectionReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.first_fallback {
            None => write!(f, "all {} particles corrected", self.particles),
            Some(first) => write!(
                f,
                "{} of {} particles fell back (singular or ill-conditioned moment matrix), \
                 the first is particle {first}",
                self.fallbacks, self.particles
            ),
        }
    }
}

/// Checks the slice lengths every correction shares: one output per query particle, query
/// particle `i` at `position[i]`, neighbours indexing `position` and `volume`.
pub(crate) fn check_lengths<const D: usize>(
    correction: &str,
    position: &[Vector<D>],
    volume: &[Real],
    neighbours: &NeighbourList,
    out_len: usize,
) {
    assert_eq!(
        position.len(),
        volume.len(),
        "{correction}: {} positions but {} volumes",
        position.len(),
        volume.len()
    );
    assert_eq!(
        neighbours.len(),
        out_len,
        "{correction}: the neighbour list has {} query particles but the output has {} slots",
        neighbours.len(),
        out_len
    );
    assert!(
        out_len <= position.len(),
        "{correction}: {out_len} query particles but only {} positions",
        position.len()
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_counts_and_keeps_the_smallest_index() {
        let reports = [
            CorrectionReport::single(7, true),
            CorrectionReport::single(2, false),
            CorrectionReport::single(3, true),
        ];
        let forward = reports
            .iter()
            .fold(CorrectionReport::default(), |a, &b| a.merge(b));
        let backward = reports
            .iter()
            .rev()
            .fold(CorrectionReport::default(), |a, &b| a.merge(b));
        assert_eq!(forward, backward);
        assert_eq!(forward.particles, 3);
        assert_eq!(forward.fallbacks, 2);
        assert_eq!(forward.first_fallback, Some(3));
        assert!(!forward.all_corrected());
        assert!(forward.to_string().contains("2 of 3"), "{forward}");
    }
}
