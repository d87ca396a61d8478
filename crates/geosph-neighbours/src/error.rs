//! Why a neighbour search could not be set up or built.

use geosph_core::Real;

/// Why a [`crate::CellGrid`] could not be made or filled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// The search radius is not a finite positive number.
    #[error("search radius must be finite and > 0, got {radius}")]
    InvalidRadius {
        /// The radius that was given.
        radius: Real,
    },

    /// A periodic axis is shorter than twice the search radius, so a particle could interact
    /// with more than one image of another and the minimum image would miss some of them.
    #[error(
        "periodic axis {axis} has length {length}, less than 2 × search radius {radius}: a \
         particle would see several images of another; enlarge the period or shrink the radius"
    )]
    PeriodTooShort {
        /// The axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// Its period `max − min`.
        length: Real,
        /// The search radius.
        radius: Real,
    },

    /// The grid would need more cells than it can index (or than its Morton codes can hold
    /// along one axis).
    #[error(
        "cell grid of {cells_per_axis:?} cells per axis is too large (at most {limit} cells in \
         all, and 2^(64/D) along one axis): the domain is too large for this search radius \
         (a hashed cell index, a scene's `domain.cells: Hashed`, holds the occupied cells only)"
    )]
    TooManyCells {
        /// Cells each axis would need (saturated at `usize::MAX`).
        cells_per_axis: Vec<usize>,
        /// Largest total number of cells.
        limit: usize,
    },

    /// More particles than a `u32` index can number.
    #[error("{count} particles cannot be indexed by u32 (at most {limit})")]
    TooManyParticles {
        /// Number of particles given.
        count: usize,
        /// Largest number of particles.
        limit: usize,
    },

    /// A particle lies outside the half-open domain `[min, max)` or has a non-finite coordinate.
    #[error(
        "particle {index} at {position} lies outside the domain [{min}, {max}) of the cell grid \
         (positions on periodic axes must be wrapped into the domain first)",
        position = format_point(.position),
        min = format_point(.min),
        max = format_point(.max)
    )]
    OutsideDomain {
        /// Index of the particle in the slice given to [`crate::CellGrid::build`].
        index: usize,
        /// Its position.
        position: Vec<Real>,
        /// Lower corner of the domain.
        min: Vec<Real>,
        /// Upper corner of the domain.
        max: Vec<Real>,
    },

    /// In a distributed run, a particle moved farther since its rank's halo was made (the
    /// last set-up) than the halo covers (half the Verlet skin): some neighbours may be
    /// missing.
    #[error(
        "a particle moved {moved} m since the ranks last exchanged their halos, more than \
         half the Verlet skin ({limit} m) that a halo covers: lower `cfl` or enlarge the skin"
    )]
    HaloOutdated {
        /// The largest displacement since the halo was made.
        moved: Real,
        /// Half the skin.
        limit: Real,
    },

    /// In a distributed run, another rank's search failed (its own error is in its output);
    /// every rank stops.
    #[error("the neighbour search failed on another rank of the run (its message says why)")]
    OnAnotherRank,
}

/// `(x, y, z)` with Rust's shortest round-trip formatting of each coordinate.
fn format_point(point: &[Real]) -> String {
    let parts: Vec<String> = point.iter().map(|x| format!("{x}")).collect();
    format!("({})", parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outside_domain_message_names_index_position_and_bounds() {
        let err = SearchError::OutsideDomain {
            index: 7,
            position: vec![1.5, Real::NAN],
            min: vec![0.0, 0.0],
            max: vec![1.0, 2.0],
        };
        assert_eq!(
            err.to_string(),
            "particle 7 at (1.5, NaN) lies outside the domain [(0, 0), (1, 2)) of the cell grid \
             (positions on periodic axes must be wrapped into the domain first)"
        );
    }
}
