//! First-order moving-least-squares (MLS) kernel correction.
//!
//! The corrected kernel (Dilts 1999; Colagrossi & Landrini 2003; Nguyen et
//! al. 2017) is
//!
//! ```text
//! W^MLS_ij = (β₀ + β · r_ij) W_ij,        r_ij = x_i − x_j,
//! [β₀, β]ᵀ = A_i⁻¹ e₁,   A_i = Σ_j V_j W_ij p(r_ij) p(r_ij)ᵀ,   p(r) = [1, r]ᵀ,
//! ```
//!
//! and `Σ_j V_j f_j W^MLS_ij` reproduces every linear field exactly. Instead of a
//! `(D+1)×(D+1)` matrix (whose size `D + 1` cannot be a const-generic expression on stable
//! Rust) the system is solved by blocks, with no allocation and for any `D`:
//!
//! ```text
//! A_i = [ a  bᵀ ]   a = Σ V_j W_ij,  b = Σ V_j W_ij r_ij,  C = Σ V_j W_ij r_ij ⊗ r_ij
//!       [ b  C  ]
//! β₀ = 1 / s,   β = −β₀ C⁻¹ b,   s = a − bᵀ C⁻¹ b   (Schur complement of C)
//! ```
//!
//! `r_ij` is scaled by `1/h` while solving, so that `a`, `b`, `C` are dimensionless.
//! `a/s − 1 = m̄ᵀ Σ⁻¹ m̄ ≥ 0` is the squared Mahalanobis distance of `x_i` from the
//! kernel-weighted centroid `m̄ = b/a` of its neighbours (`Σ` their weighted covariance):
//! small in the bulk, larger at a surface, infinite when `x_i` is outside a degenerate
//! (collinear/coplanar) neighbourhood.

use geosph_core::{Domain, Matrix, NeighbourList, Real, Vector};
use rayon::prelude::*;

use crate::cspm::{MAX_CONDITION_NUMBER, well_conditioned_inverse};
use crate::kernel::Kernel;
use crate::report::{CorrectionReport, check_lengths};

/// The coefficients `β₀, β` of the first-order MLS kernel `W^MLS_ij = (β₀ + β · r_ij) W_ij`
/// of one particle `i` (Dilts 1999).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MlsCoefficients<const D: usize> {
    /// β₀ (dimensionless).
    pub beta0: Real,
    /// β (unit 1/length), multiplying `r_ij = x_i − x_j`.
    pub beta: Vector<D>,
}

impl<const D: usize> Default for MlsCoefficients<D> {
    /// The uncorrected kernel, `β₀ = 1`, `β = 0`.
    fn default() -> Self {
        Self {
            beta0: 1.0,
            beta: Vector::zeros(),
        }
    }
}

impl<const D: usize> MlsCoefficients<D> {
    /// The Shepard kernel `W_ij / S_i` (`β₀ = 1/S_i`, `β = 0`), zeroth-order consistent only;
    /// the uncorrected kernel if `S_i` is not positive and finite.
    pub fn shepard(shepard_sum: Real) -> Self {
        if shepard_sum > 0.0 && shepard_sum.is_finite() {
            Self {
                beta0: 1.0 / shepard_sum,
                beta: Vector::zeros(),
            }
        } else {
            Self::default()
        }
    }

    /// `W^MLS_ij = (β₀ + β · r_ij) w` for `r_ij = x_i − x_j` and `w = W_ij`.
    #[inline]
    pub fn corrected(&self, r_ij: &Vector<D>, w: Real) -> Real {
        (self.beta0 + self.beta.dot(r_ij)) * w
    }
}

/// The MLS coefficients of every query particle `i < out.len()` (see the [module](self)
/// documentation).
///
/// Falls back to the Shepard kernel ([`MlsCoefficients::shepard`]) where the moment matrix is
/// singular or ill-conditioned: `κ_F(C/h²) >` [`MAX_CONDITION_NUMBER`] or
/// `s < a /` [`MAX_CONDITION_NUMBER`] (the same threshold as [`crate::cspm`]). In the bulk
/// `κ_F(C/h²) ≈ D` and `s ≈ a`; on the plane-cut jittered lattices of the tests `a/s ≤ 3`
/// and `κ_F(C/h²)` reaches 7 × 10³ only at the tip of a 29° wedge in 3D (Wendland C6).
/// Fallbacks are counted in the returned [`CorrectionReport`].
///
/// Slices and neighbour lists follow [`crate::shepard::shepard_sums`] (the self-pair must be
/// listed; it carries the largest weight `W(0)`). Runs in parallel over `i` with sums in list
/// order: the result does not depend on the number of threads.
///
/// # Panics
/// On inconsistent slice lengths (see [`crate::shepard::shepard_sums`]).
pub fn mls_coefficients<K: Kernel<D>, const D: usize>(
    kernel: &K,
    domain: &Domain<D>,
    position: &[Vector<D>],
    volume: &[Real],
    neighbours: &NeighbourList,
    out: &mut [MlsCoefficients<D>],
) -> CorrectionReport {
    check_lengths("mls_coefficients", position, volume, neighbours, out.len());
    let inv_h = 1.0 / kernel.smoothing_length();
    out.par_iter_mut()
        .enumerate()
        .map(|(i, coefficients)| {
            let x_i = &position[i];
            let mut a = 0.0;
            let mut b = Vector::<D>::zeros();
            let mut c = Matrix::<D>::zeros();
            for &j in neighbours.neighbours(i) {
                let j = j as usize;
                let r_ij = domain.displacement(x_i, &position[j]);
                let weight = volume[j] * kernel.value(r_ij.norm());
                let r_scaled = r_ij * inv_h;
                a += weight;
                b += weight * r_scaled;
                c += (weight * r_scaled) * r_scaled.transpose();
            }
            match solve(a, &b, &c) {
                Some((beta0, beta_scaled)) => {
                    *coefficients = MlsCoefficients {
                        beta0,
                        beta: beta_scaled * inv_h,
                    };
                    CorrectionReport::single(i, false)
                }
                None => {
                    *coefficients = MlsCoefficients::shepard(a);
                    CorrectionReport::single(i, true)
                }
            }
        })
        .reduce(CorrectionReport::default, CorrectionReport::merge)
}

/// Solves `[a bᵀ; b C] [β₀; β] = e₁` by the Schur complement, or `None` if ill-conditioned.
fn solve<const D: usize>(a: Real, b: &Vector<D>, c: &Matrix<D>) -> Option<(Real, Vector<D>)> {
    let c_inverse = well_conditioned_inverse(c, MAX_CONDITION_NUMBER)?;
    let c_inverse_b = c_inverse * b;
    let schur = a - b.dot(&c_inverse_b);
    if !(schur * MAX_CONDITION_NUMBER >= a && a > 0.0) {
        return None;
    }
    let beta0 = 1.0 / schur;
    Some((beta0, -beta0 * c_inverse_b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WendlandC4;
    use crate::test_support::{brute_force_neighbours, square_lattice};
    use approx::assert_relative_eq;

    /// A small 3D cube cut by a plane: MLS interpolates a linear field exactly everywhere.
    #[test]
    fn reproduces_a_linear_field_in_3d() {
        let n = 6;
        let dx = 0.2;
        let mut position = Vec::new();
        for k in 0..n * n * n {
            let index = Vector::<3>::new(
                (k % n) as Real,
                ((k / n) % n) as Real,
                (k / (n * n)) as Real,
            );
            let wobble = Vector::<3>::new(
                (k as Real).sin(),
                (2.0 * k as Real).cos(),
                (3.0 * k as Real).sin(),
            );
            let x = (index + Vector::<3>::repeat(0.5) + 0.2 * wobble) * dx;
            if x[0] + x[1] + 2.0 * x[2] < 1.6 {
                position.push(x);
            }
        }
        let kernel = WendlandC4::<3>::new(1.5 * dx);
        let domain = Domain::new(Vector::<3>::repeat(-1.0), Vector::<3>::repeat(3.0)).unwrap();
        let neighbours = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![dx * dx * dx; position.len()];
        let mut out = vec![MlsCoefficients::default(); position.len()];
        let report = mls_coefficients(&kernel, &domain, &position, &volume, &neighbours, &mut out);
        assert!(report.all_corrected(), "{report}");
        let field = |x: &Vector<3>| 1.5 - 2.0 * x[0] + 0.5 * x[1] + 3.0 * x[2];
        for (i, x_i) in position.iter().enumerate() {
            let interpolated: Real = neighbours
                .neighbours(i)
                .iter()
                .map(|&j| {
                    let j = j as usize;
                    let r_ij = x_i - position[j];
                    volume[j]
                        * field(&position[j])
                        * out[i].corrected(&r_ij, kernel.value(r_ij.norm()))
                })
                .sum();
            assert_relative_eq!(interpolated, field(x_i), max_relative = 1e-11);
        }
    }

    #[test]
    fn isolated_and_collinear_particles_fall_back_to_shepard() {
        let kernel = WendlandC4::<2>::new(1.0);
        let domain = Domain::new(Vector::<2>::repeat(-100.0), Vector::<2>::repeat(100.0)).unwrap();
        let mut position: Vec<Vector<2>> = (0..4)
            .map(|k| Vector::<2>::new(k as Real * 0.7, -50.0))
            .collect();
        position.push(Vector::<2>::new(50.0, 50.0));
        position.extend(square_lattice(4, 0.7));
        let neighbours = brute_force_neighbours(&domain, &position, kernel.support_radius());
        let volume = vec![0.49; position.len()];
        let mut out = vec![MlsCoefficients::default(); position.len()];
        let report = mls_coefficients(&kernel, &domain, &position, &volume, &neighbours, &mut out);
        assert_eq!(report.fallbacks, 5, "{report}");
        assert_eq!(report.first_fallback, Some(0));
        // Isolated: only the self term, so β₀ = 1/(V W(0)).
        assert_relative_eq!(
            out[4].beta0,
            1.0 / (0.49 * kernel.value(0.0)),
            max_relative = 1e-14
        );
        assert_eq!(out[4].beta, Vector::<2>::zeros());
    }
}
