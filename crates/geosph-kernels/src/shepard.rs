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

/// The two sums of the Shepard interpolant at `x` ([`shepard_interpolation`]),
/// (Σ_j f_j V_j W(|x − x_j|), Σ_j V_j W(|x − x_j|)), over every particle of `position`,
/// added in index order: sums over parts of the particles (one rank's each) add up to the
/// sums over all of them.
pub fn interpolation_sums<K: Kernel<D>, const D: usize>(
    kernel: &K,
    x: &Vector<D>,
    position: &[Vector<D>],
    volume: &[Real],
    value: &[Real],
) -> (Real, Real) {
    let support = kernel.support_radius();
    position.iter().zip(volume).zip(value).fold(
        (0.0, 0.0),
        |(weighted, weights), ((x_j, &v_j), &f_j)| {
            let r = (x - x_j).norm();
            if r < support {
                let w = v_j * kernel.value(r);
                (weighted + w * f_j, weights + w)
            } else {
                (weighted, weights)
            }
        },
    )
}

/// The Shepard interpolant of a particle field at a point `x` (Shepard 1968),
///
/// ```text
/// f(x) = Σ_j f_j V_j W(|x − x_j|) / Σ_j V_j W(|x − x_j|),
/// ```
///
/// summed over every particle `j` of `position` (a linear scan: meant for a few probe points
/// per sample, not for every particle). It reproduces constants exactly, and linear fields
/// wherever the support around `x` is filled symmetrically; where a free surface or a wall
/// truncates the support it returns the weighted mean of the particles present. `None` when
/// no particle lies within the kernel's support of `x`.
///
/// # Panics
/// If `position`, `volume` and `value` differ in length.
pub fn shepard_interpolation<K: Kernel<D>, const D: usize>(
    kernel: &K,
    x: &Vector<D>,
    position: &[Vector<D>],
    volume: &[Real],
    value: &[Real],
) -> Option<Real> {
    assert!(
        position.len() == volume.len() && volume.len() == value.len(),
        "shepard_interpolation: {} positions, {} volumes, {} values",
        position.len(),
        volume.len(),
        value.len()
    );
    let (weighted, weights) = interpolation_sums(kernel, x, position, volume, value);
    (weights > 0.0).then(|| weighted / weights)
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

    /// Inside a lattice the interpolant reproduces constant and linear fields at any point;
    /// far from every particle there is nothing to interpolate.
    #[test]
    fn interpolation_reproduces_linear_fields_inside_a_lattice() {
        let (n, dx) = (12, 0.1);
        let position = square_lattice(n, dx);
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let volume = vec![dx * dx; n * n];
        let constant = vec![3.5; n * n];
        let linear: Vec<Real> = position
            .iter()
            .map(|x| 2.0 - 4.0 * x[0] + 7.0 * x[1])
            .collect();
        let exact = |x: &Vector<2>| 2.0 - 4.0 * x[0] + 7.0 * x[1];
        // At a lattice point the support is symmetric and the interpolant exact; at a general
        // point the lattice's weights are nearly, not exactly, symmetric.
        for (x, tolerance) in [
            (Vector::<2>::new(0.55, 0.55), 1e-13),
            (Vector::<2>::new(0.613, 0.472), 2e-3),
        ] {
            let c = shepard_interpolation(&kernel, &x, &position, &volume, &constant).unwrap();
            assert_relative_eq!(c, 3.5, max_relative = 1e-14);
            let f = shepard_interpolation(&kernel, &x, &position, &volume, &linear).unwrap();
            assert_relative_eq!(f, exact(&x), max_relative = tolerance);
        }
        let far = Vector::<2>::new(5.0, 5.0);
        assert_eq!(
            shepard_interpolation(&kernel, &far, &position, &volume, &linear),
            None
        );
    }
}
