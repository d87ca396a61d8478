//! Zeroth-order (Shepard) kernel normalisation.
//!
//! Shepard (1968) interpolation divides the kernel by its discrete partition of unity,
//!
//! ```text
//! W̃_ij = W_ij / S_i,     S_i = Σ_j V_j W_ij,
//! ```
//!
//! so that `Σ_j V_j f_j W̃_ij` reproduces constants exactly, also where the support is
//! truncated by a free surface (Randles & Libersky 1996; Liu & Liu 2003; the
//! "Shepard filter" of density, `ρ̃_i = Σ_j m_j W̃_ij`, uses the same sums).

use geosph_core::{Domain, NeighbourList, Real, Vector};
use rayon::prelude::*;

use crate::kernel::Kernel;
use crate::report::check_lengths;

/// `S_i = Σ_j V_j W(|x_i − x_j|)` for each query particle `i`, so that `W̃_ij = W_ij / S_i`.
///
/// - `position[i]` is query particle `i` for `i < out.len()`; the neighbours `j` of `i`
///   (`neighbours.neighbours(i)`) index `position` and `volume` (so boundary particles may
///   follow the query particles in the same slices).
/// - The sum runs over the listed neighbours only. When a set is searched against itself the
///   list of `i` includes `i`, whose term `V_i W(0)` is part of `S_i`; a list without the
///   self-pair gives a different (wrong) normalisation.
/// - `r_ij` is the minimum image `domain.displacement(x_i, x_j)` on periodic axes.
/// - A particle with no neighbours gets `S_i = 0`; dividing by it is the caller's choice.
///
/// Runs in parallel over `i`; each sum is taken in list order, so the result does not depend
/// on the number of threads.
///
/// # Panics
/// If `position` and `volume` differ in length, the neighbour list does not have `out.len()`
/// query particles, or there are fewer positions than query particles.
pub fn shepard_sums<K: Kernel<D>, const D: usize>(
    kernel: &K,
    domain: &Domain<D>,
    position: &[Vector<D>],
    volume: &[Real],
    neighbours: &NeighbourList,
    out: &mut [Real],
) {
    check_lengths("shepard_sums", position, volume, neighbours, out.len());
    out.par_iter_mut().enumerate().for_each(|(i, sum)| {
        let x_i = &position[i];
        *sum = neighbours
            .neighbours(i)
            .iter()
            .map(|&j| {
                let j = j as usize;
                volume[j] * kernel.value(domain.displacement(x_i, &position[j]).norm())
            })
            .sum();
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WendlandC2;
    use crate::test_support::{brute_force_neighbours, square_lattice};
    use approx::assert_relative_eq;

    /// On a periodic regular lattice every particle has the same neighbourhood, so the sums
    /// are equal, also for particles whose neighbours are across a periodic face.
    #[test]
    fn periodic_lattice_gives_equal_sums() {
        let (n, dx) = (10, 0.1);
        let domain =
            Domain::with_periodic(Vector::<2>::zeros(), Vector::<2>::repeat(1.0), [true; 2])
                .unwrap();
        let position = square_lattice(n, dx);
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let list = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![dx * dx; n * n];
        let mut sums = vec![0.0; n * n];
        shepard_sums(&kernel, &domain, &position, &volume, &list, &mut sums);
        for &s in &sums {
            assert_relative_eq!(s, sums[0], max_relative = 1e-13);
        }
        // A regular lattice with h = 1.3 dx is a fair quadrature of ∫W = 1; Wendland kernels
        // overestimate it by about 1 % at this resolution (Dehnen & Aly 2012).
        assert_relative_eq!(sums[0], 1.0, max_relative = 2e-2);
        assert!(sums[0] > 1.005);
    }
}
