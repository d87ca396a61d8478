//! Scalar and small vector/tensor aliases.
//!
//! The dimension is a const generic `D` (2 or 3) so that one crate serves both 2D and 3D
//! applications, each monomorphised separately. Stress-like tensors are always 3×3
//! ([`Tensor3`]): in 2D geosph works in plane strain, where σ_zz is non-zero.

use nalgebra::{SMatrix, SVector};

/// The floating-point type of all physical quantities.
pub type Real = f64;

/// A position, velocity or gradient in `D` dimensions.
pub type Vector<const D: usize> = SVector<Real, D>;

/// A `D × D` matrix, e.g. a kernel-gradient correction matrix or a velocity gradient.
pub type Matrix<const D: usize> = SMatrix<Real, D, D>;

/// A 3×3 tensor (Cauchy stress, strain, spin), used in 2D (plane strain) and 3D alike.
pub type Tensor3 = SMatrix<Real, 3, 3>;
