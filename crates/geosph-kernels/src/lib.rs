//! Smoothing kernels of geosph and the corrections that restore their consistency.
//!
//! Every kernel is a small `Copy` value implementing [`Kernel<D>`] for `D = 2` and `D = 3`; hot
//! loops take it as a type parameter (`fn density<K: Kernel<D>, const D: usize>(kernel: &K, ..)`)
//! so that each kernel is monomorphised and inlined. A scene names its kernel with a
//! [`KernelKind`] and dispatches once, through [`KernelKind::dispatch`], to such a generic
//! function. Conventions: `r_ij = x_i − x_j`, `r = |r_ij|`, `q = r/h`, and
//! `∇_i W_ij = (dW/dr) r_ij / r` (it points from `j` to `i` times `dW/dr ≤ 0`, i.e. towards `j`).
//!
//! Modules:
//! - [`kernel`]: the [`Kernel`] trait, the run-time choice [`KernelKind`] and [`KernelVisitor`].
//! - [`spline`]: the cubic ([`CubicSpline`]) and quintic ([`QuinticSpline`]) B-splines.
//! - [`wendland`]: the Wendland functions [`WendlandC2`], [`WendlandC4`], [`WendlandC6`].
//! - [`gaussian`]: the [`Gaussian`], truncated at `3h` and renormalised.
//! - [`quadrature`]: Gauss–Legendre rules and radial integrals `∫ f(|x|) dx` over ℝ^D, used to
//!   check normalisations.
//! - [`report`]: the [`CorrectionReport`] every correction returns (particles that fell back).
//! - [`shepard`]: zeroth-order (Shepard) kernel normalisation sums `Σ_j V_j W_ij`.
//! - [`cspm`]: kernel-gradient correction matrices `L_i` (Bonet & Lok 1999; Chen et al. 1999).
//! - [`mls`]: first-order moving-least-squares kernel coefficients (Dilts 1999).
//!
//! The derivations, constants, sign conventions and measured convergence orders are collected
//! in `docs/theory.md` at the repository root.
//!
//! # Example
//!
//! Evaluate a kernel, then correct its gradient at the corner of a small particle block, where
//! the plain SPH gradient of a linear field is wrong and the CSPM-corrected one is exact. The
//! neighbour list is built by brute force here (the `geosph-neighbours` crate does it fast):
//!
//! ```
//! use geosph_core::{Domain, Matrix, NeighbourList, Vector};
//! use geosph_kernels::{Kernel, WendlandC2, cspm};
//!
//! let (dx, h) = (0.1, 0.13);
//! let kernel = WendlandC2::<2>::new(h);
//! assert!(kernel.value(0.0) > kernel.value(0.5 * h));
//! assert_eq!(kernel.value(kernel.support_radius()), 0.0);
//! // ∇_i W_ij for r_ij = x_i − x_j points towards x_j.
//! let gradient = kernel.gradient(&Vector::<2>::new(0.1, 0.0));
//! assert!(gradient[0] < 0.0 && gradient[1] == 0.0);
//!
//! // A 6 × 6 block of particles, each of volume dx².
//! let x: Vec<Vector<2>> = (0..36)
//!     .map(|k| Vector::<2>::new((k % 6) as f64 * dx, (k / 6) as f64 * dx))
//!     .collect();
//! let volume = vec![dx * dx; x.len()];
//! let mut list = NeighbourList::new();
//! for x_i in &x {
//!     let near = (0..x.len() as u32).filter(|&j| (x_i - x[j as usize]).norm() < kernel.support_radius());
//!     list.indices.extend(near);
//!     list.offsets.push(list.indices.len() as u32);
//! }
//! let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(2.0)).unwrap();
//! let mut correction = vec![Matrix::<2>::identity(); x.len()];
//! let report = cspm::gradient_correction(&kernel, &domain, &x, &volume, &list, &mut correction);
//! assert_eq!(report.fallbacks, 0);
//!
//! // The gradient of f = 3x + 2y at the corner particle 0, plain and corrected.
//! let f = |p: &Vector<2>| 3.0 * p[0] + 2.0 * p[1];
//! let (mut plain, mut corrected) = (Vector::<2>::zeros(), Vector::<2>::zeros());
//! for &j in list.neighbours(0) {
//!     let j = j as usize;
//!     let grad_w = kernel.gradient(&(x[0] - x[j]));
//!     plain += volume[j] * (f(&x[j]) - f(&x[0])) * grad_w;
//!     corrected += volume[j] * (f(&x[j]) - f(&x[0])) * (correction[0] * grad_w);
//! }
//! assert!((plain - Vector::<2>::new(3.0, 2.0)).norm() > 0.5);
//! assert!((corrected - Vector::<2>::new(3.0, 2.0)).norm() < 1e-12);
//! ```
#![warn(missing_docs)]

pub mod cspm;
pub mod gaussian;
pub mod kernel;
pub mod mls;
pub mod quadrature;
pub mod report;
pub mod shepard;
pub mod spline;
pub mod wendland;

#[cfg(test)]
mod test_support;

pub use gaussian::Gaussian;
pub use kernel::{Kernel, KernelKind, KernelVisitor, UnknownKernel};
pub use mls::MlsCoefficients;
pub use report::CorrectionReport;
pub use spline::{CubicSpline, QuinticSpline};
pub use wendland::{WendlandC2, WendlandC4, WendlandC6};
