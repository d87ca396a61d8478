//! Kernel-gradient correction (CSPM / gradient renormalisation).
//!
//! With `r_ij = x_i − x_j` and `∇_i W_ij = (dW/dr) r_ij/r`, the difference-form SPH gradient
//!
//! ```text
//! ⟨∇f⟩_i = Σ_j V_j (f_j − f_i) ∇_i W_ij
//! ```
//!
//! applied to a linear field `f = f_i + g·(x − x_i)` gives `B_i g`, with the moment matrix
//!
//! ```text
//! B_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)          (B_i)_{αβ} = Σ_j V_j ∂_α W_ij (x_j − x_i)_β
//! ```
//!
//! `B_i = I` for a full, well-resolved support (integration by parts, `∫ ∇W ⊗ (x' − x) dV' = I`)
//! but not at free surfaces or on disordered particles. The corrected kernel gradient
//! (Bonet & Lok 1999; Chen, Beraun & Carney 1999, "CSPM"; Randles & Libersky 1996)
//!
//! ```text
//! ∇̃_i W_ij = L_i ∇_i W_ij,     L_i = B_i⁻¹
//! ```
//!
//! makes `Σ_j V_j (f_j − f_i) ∇̃_i W_ij = g` exact for every linear field, at interior and
//! surface particles alike. Because `∇_i W_ij ∥ r_ij` for radial kernels,
//! `B_i = −Σ_j V_j (1/r dW/dr) r_ij ⊗ r_ij` is symmetric, so `B_i⁻¹ = B_i⁻ᵀ` and the order of
//! the outer product (written both ways in the literature) does not matter here.
//!
//! Two pitfalls in the design notes: with `r_ij = x_i − x_j`, `Σ_j V_j r_ij ⊗ ∇_i W_ij` is
//! `−B_i ≈ −I`, so inverting it flips the sign of every gradient; and the corrected
//! *non-difference* form `Σ_j V_j f_j ∇̃_i W_ij` is not exact for linear fields at a surface,
//! because `Σ_j V_j ∇̃_i W_ij ≠ 0` there. Use the difference form `(f_j − f_i)`.

use geosph_core::{Domain, Matrix, NeighbourList, Real, Vector};
use rayon::prelude::*;

use crate::kernel::Kernel;
use crate::report::{CorrectionReport, check_lengths};

/// Largest accepted Frobenius condition number `κ_F(B) = ‖B‖_F ‖B⁻¹‖_F` of a moment matrix.
///
/// `κ_F = D` for `B = I` (full support) and stays below 4 for every kernel at the surfaces and
/// corners of the jittered, plane-cut 2D lattice of the tests (`h = 1.3 dx`). Sharp 3D
/// corners are worse: at the tip of the 29° wedge in the 3D test `κ_F` reaches 1 × 10², 3 × 10²,
/// 1.1 × 10³ and 4.6 × 10³ (Gaussian, cubic/C2, C4, C6; the narrower the kernel, the fewer
/// neighbours carry weight), yet the correction is still exact there. Degenerate
/// neighbourhoods (isolated particles, one neighbour, all neighbours on a line in 2D or a
/// plane in 3D) make `B` singular (or `κ_F` of order `1/ε` in floating point), and nearly
/// degenerate ones amplify the gradient along one direction by `κ_F`, turning truncation and
/// round-off errors into spurious forces. `10⁵` lies 20× above the worst resolved case measured and
/// keeps the round-off in `L_i` below `κ_F ε ≈ 10⁻¹¹`.
pub const MAX_CONDITION_NUMBER: Real = 1.0e5;

/// The moment matrix `B_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)` of query particle `i` over the
/// neighbours `neighbours_of_i` (indices into `position`, `volume`).
///
/// `r_ij` is the minimum image `domain.displacement(x_i, x_j)`; the self-pair contributes
/// nothing (`∇W = 0` at `r = 0`).
pub fn moment_matrix<K: Kernel<D>, const D: usize>(
    kernel: &K,
    domain: &Domain<D>,
    position: &[Vector<D>],
    volume: &[Real],
    i: usize,
    neighbours_of_i: &[u32],
) -> Matrix<D> {
    let x_i = &position[i];
    let mut moment = Matrix::<D>::zeros();
    for &j in neighbours_of_i {
        let j = j as usize;
        let r_ij = domain.displacement(x_i, &position[j]);
        let grad_w = kernel.gradient(&r_ij);
        // ∇_i W_ij ⊗ (x_j − x_i) = −∇_i W_ij r_ijᵀ
        moment -= (volume[j] * grad_w) * r_ij.transpose();
    }
    moment
}

/// `M⁻¹` if `M` is invertible with `κ_F(M) = ‖M‖_F ‖M⁻¹‖_F ≤ max_condition`, else `None`
/// (also for non-finite entries). With a moment matrix `B_i` and [`MAX_CONDITION_NUMBER`] this
/// is the correction `L_i` of [`gradient_correction`], for callers that sum `B_i` in their own
/// pair loop.
pub fn well_conditioned_inverse<const D: usize>(
    matrix: &Matrix<D>,
    max_condition: Real,
) -> Option<Matrix<D>> {
    let inverse = matrix.try_inverse()?;
    let condition = matrix.norm() * inverse.norm();
    (condition <= max_condition).then_some(inverse)
}

/// The correction matrices `L_i = B_i⁻¹` (see the [module](self) documentation), written to
/// `out[i]` for every query particle `i < out.len()`, so that `∇̃_i W_ij = L_i ∇_i W_ij`.
///
/// The corrected gradient of a field is then `Σ_j V_j (f_j − f_i) L_i ∇_i W_ij`, exact for
/// linear `f` (Bonet & Lok 1999; Chen et al. 1999).
///
/// Where `B_i` is singular or `κ_F(B_i) >` [`MAX_CONDITION_NUMBER`] (isolated particles,
/// neighbours on a line or plane), `out[i]` is the identity (no correction) and the particle is
/// counted in the returned [`CorrectionReport`], which also names the smallest such index.
///
/// Slices and neighbour lists follow [`crate::shepard::shepard_sums`]: `position[i]` is query
/// particle `i`, neighbour indices refer to `position` and `volume`. Runs in parallel over `i`
/// with sums in list order: the result does not depend on the number of threads.
///
/// # Panics
/// On inconsistent slice lengths (see [`crate::shepard::shepard_sums`]).
pub fn gradient_correction<K: Kernel<D>, const D: usize>(
    kernel: &K,
    domain: &Domain<D>,
    position: &[Vector<D>],
    volume: &[Real],
    neighbours: &NeighbourList,
    out: &mut [Matrix<D>],
) -> CorrectionReport {
    check_lengths(
        "gradient_correction",
        position,
        volume,
        neighbours,
        out.len(),
    );
    out.par_iter_mut()
        .enumerate()
        .map(|(i, correction)| {
            let moment = moment_matrix(
                kernel,
                domain,
                position,
                volume,
                i,
                neighbours.neighbours(i),
            );
            match well_conditioned_inverse(&moment, MAX_CONDITION_NUMBER) {
                Some(inverse) => {
                    *correction = inverse;
                    CorrectionReport::single(i, false)
                }
                None => {
                    *correction = Matrix::identity();
                    CorrectionReport::single(i, true)
                }
            }
        })
        .reduce(CorrectionReport::default, CorrectionReport::merge)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CubicSpline;
    use crate::test_support::{brute_force_neighbours, square_lattice};
    use approx::assert_relative_eq;

    /// Particle 0 sits 4h away from the rest (isolated), 1–2 are a pair, 3–5 are collinear;
    /// the 3×3 block 6.. is a proper little lattice.
    #[test]
    fn degenerate_neighbourhoods_fall_back_and_are_reported() {
        let h = 1.0;
        let kernel = CubicSpline::<2>::new(h);
        let domain = Domain::new(Vector::<2>::repeat(-100.0), Vector::<2>::repeat(100.0)).unwrap();
        let mut position = vec![
            Vector::<2>::new(-50.0, 0.0),
            Vector::<2>::new(-30.0, 0.0),
            Vector::<2>::new(-29.0, 0.5),
            Vector::<2>::new(20.0, 20.0),
            Vector::<2>::new(21.0, 21.0),
            Vector::<2>::new(22.0, 22.0),
        ];
        position.extend(
            square_lattice(3, 0.8)
                .iter()
                .map(|x| x + Vector::<2>::new(40.0, 0.0)),
        );
        let neighbours = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![0.64; position.len()];
        let mut out = vec![Matrix::<2>::zeros(); position.len()];
        let report =
            gradient_correction(&kernel, &domain, &position, &volume, &neighbours, &mut out);
        assert_eq!(report.particles, position.len());
        assert_eq!(report.fallbacks, 6, "{report}");
        assert_eq!(report.first_fallback, Some(0));
        for l in &out[..6] {
            assert_eq!(*l, Matrix::<2>::identity());
        }
        for l in &out[6..] {
            assert_ne!(*l, Matrix::<2>::identity());
            assert_relative_eq!(*l, l.transpose(), max_relative = 1e-12);
        }
    }

    /// A 3D particle sheet with out-of-plane noise of 10⁻⁹ h is nearly coplanar: the
    /// out-of-plane eigenvalue of `B` is `O(10⁻¹⁸)`, far past the threshold, so every particle
    /// falls back.
    #[test]
    fn nearly_coplanar_sheet_in_3d_falls_back() {
        let h = 1.0;
        let kernel = CubicSpline::<3>::new(h);
        let domain = Domain::new(Vector::<3>::repeat(-10.0), Vector::<3>::repeat(10.0)).unwrap();
        let position: Vec<Vector<3>> = square_lattice(5, 0.7)
            .iter()
            .enumerate()
            .map(|(k, x)| Vector::<3>::new(x[0], x[1], 1e-9 * h * (k as Real).sin()))
            .collect();
        let neighbours = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![0.343; position.len()];
        let mut out = vec![Matrix::<3>::zeros(); position.len()];
        let report =
            gradient_correction(&kernel, &domain, &position, &volume, &neighbours, &mut out);
        assert_eq!(report.fallbacks, position.len(), "{report}");
        // …while the same sheet in 2D is perfectly well conditioned.
        let flat: Vec<Vector<2>> = position.iter().map(|x| x.xy()).collect();
        let kernel_2d = CubicSpline::<2>::new(h);
        let domain_2d = Domain::new(Vector::<2>::repeat(-10.0), Vector::<2>::repeat(10.0)).unwrap();
        let mut out_2d = vec![Matrix::<2>::zeros(); flat.len()];
        let report = gradient_correction(
            &kernel_2d,
            &domain_2d,
            &flat,
            &volume,
            &neighbours,
            &mut out_2d,
        );
        assert!(report.all_corrected(), "{report}");
    }

    /// The same matrices, bit for bit, on one thread and on three.
    #[test]
    fn result_does_not_depend_on_thread_count() {
        let dx = 0.1;
        let position: Vec<Vector<2>> = square_lattice(12, dx)
            .into_iter()
            .enumerate()
            .map(|(k, x)| {
                x + Vector::<2>::new((k as Real * 0.7).sin(), (k as Real * 1.3).cos()) * 0.02
            })
            .collect();
        let kernel = CubicSpline::<2>::new(1.3 * dx);
        let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(2.0)).unwrap();
        let neighbours = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![dx * dx; position.len()];
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = vec![Matrix::<2>::zeros(); position.len()];
            let report = pool.install(|| {
                gradient_correction(&kernel, &domain, &position, &volume, &neighbours, &mut out)
            });
            (out, report)
        };
        assert_eq!(run(1), run(3));
    }
}
