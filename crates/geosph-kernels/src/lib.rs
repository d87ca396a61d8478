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
