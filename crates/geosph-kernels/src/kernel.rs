//! The [`Kernel`] trait and the run-time choice of a kernel by name ([`KernelKind`]).

use std::fmt;
use std::str::FromStr;

use geosph_core::{Real, Vector};

use crate::{CubicSpline, Gaussian, QuinticSpline, WendlandC2, WendlandC4, WendlandC6};

/// A radial smoothing kernel `W(r, h) = σ_D / h^D · Ŵ(q)`, `q = r/h`, in `D` dimensions.
///
/// Implementations exist for `D = 2` and `D = 3`; the normalisation `σ_D` is picked by `D` in
/// [`Kernel::new`]. Any other `D` is rejected at compile time (a `const` assertion evaluated
/// when the kernel is instantiated), so `CubicSpline::<4>::new(1.0)` does not build:
///
/// ```compile_fail,E0080
/// use geosph_kernels::{CubicSpline, Kernel};
/// let kernel = CubicSpline::<4>::new(1.0);
/// ```
///
/// Every kernel satisfies `∫_{ℝ^D} W dV = 1`, `W ≥ 0`, and `W = dW/dr = 0` for
/// `r ≥ SUPPORT_FACTOR · h` (checked by quadrature and finite differences in the tests).
pub trait Kernel<const D: usize>: Copy + Send + Sync + fmt::Debug + 'static {
    /// Support radius divided by h (2 for cubic/Wendland, 3 for quintic and Gaussian).
    const SUPPORT_FACTOR: Real;
    /// Short name, e.g. "cubic-spline", "wendland-c2".
    const NAME: &'static str;

    /// The kernel with smoothing length `h`; precomputes `1/h` and `σ_D/h^D`, `σ_D/h^{D+1}`,
    /// `σ_D/h^{D+2}`.
    ///
    /// # Panics
    /// If `h` is not positive and finite.
    fn new(h: Real) -> Self;

    /// The smoothing length h.
    fn smoothing_length(&self) -> Real;

    /// The support radius `SUPPORT_FACTOR · h`: `W(r) = 0` for `r ≥` this.
    fn support_radius(&self) -> Real {
        Self::SUPPORT_FACTOR * self.smoothing_length()
    }

    /// `W(r, h)`; zero for `r ≥` [`Kernel::support_radius`].
    fn value(&self, r: Real) -> Real;

    /// `dW/dr`; zero for `r ≥` [`Kernel::support_radius`] and at `r = 0`.
    fn radial_derivative(&self, r: Real) -> Real;

    /// `(1/r) dW/dr`, with its finite limit `d²W/dr²(0)` at `r → 0` (used by Laplacian and
    /// viscosity terms, and by [`Kernel::gradient`]).
    fn gradient_factor(&self, r: Real) -> Real;

    /// `∇_i W(|r_ij|) = (1/r) dW/dr · r_ij` for `r_ij = x_i − x_j`; the zero vector at `r = 0`.
    ///
    /// It is antisymmetric, `∇_i W_ij = −∇_j W_ij = −∇_j W_ji`, and points from `x_i` towards
    /// `x_j` because `dW/dr ≤ 0`.
    #[inline]
    fn gradient(&self, r_ij: &Vector<D>) -> Vector<D> {
        r_ij * self.gradient_factor(r_ij.norm())
    }
}

/// Precomputed scale factors shared by all kernels: `W = value · Ŵ(q)`,
/// `dW/dr = derivative · dŴ/dq`, `(1/r) dW/dr = factor · (dŴ/dq)/q`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scaling {
    /// Smoothing length h.
    pub h: Real,
    /// 1/h.
    pub inv_h: Real,
    /// Support radius `SUPPORT_FACTOR · h`, compared with `r` directly so that `W(support) = 0`
    /// exactly whatever the rounding of `q`.
    pub support: Real,
    /// σ_D / h^D.
    pub value: Real,
    /// σ_D / h^{D+1}.
    pub derivative: Real,
    /// σ_D / h^{D+2}.
    pub factor: Real,
}

impl Scaling {
    /// Scale factors for dimensionless normalisations `sigma_2` (D = 2) and `sigma_3` (D = 3).
    pub fn new<const D: usize>(
        name: &str,
        h: Real,
        support_factor: Real,
        sigma_2: Real,
        sigma_3: Real,
    ) -> Self {
        const {
            assert!(
                D == 2 || D == 3,
                "geosph kernels are normalised for D = 2 and D = 3 only"
            )
        };
        assert!(
            h.is_finite() && h > 0.0,
            "{name}: the smoothing length must be positive and finite, got h = {h}"
        );
        let inv_h = 1.0 / h;
        let (sigma, inv_h_d) = if D == 2 {
            (sigma_2, inv_h * inv_h)
        } else {
            (sigma_3, inv_h * inv_h * inv_h)
        };
        let value = sigma * inv_h_d;
        Self {
            h,
            inv_h,
            support: support_factor * h,
            value,
            derivative: value * inv_h,
            factor: value * inv_h * inv_h,
        }
    }
}

/// A kernel chosen at run time by name, e.g. from a scene file.
///
/// Dispatch once per step with [`KernelKind::dispatch`]; inside, the kernel is a type parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelKind {
    /// [`CubicSpline`], "cubic-spline".
    CubicSpline,
    /// [`QuinticSpline`], "quintic-spline".
    QuinticSpline,
    /// [`WendlandC2`], "wendland-c2".
    WendlandC2,
    /// [`WendlandC4`], "wendland-c4".
    WendlandC4,
    /// [`WendlandC6`], "wendland-c6".
    WendlandC6,
    /// [`Gaussian`], "gaussian".
    Gaussian,
}

/// A generic computation run with whichever kernel a [`KernelKind`] names.
///
/// Rust has no generic closures; implement this on a struct holding the computation's inputs.
///
/// ```
/// use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
/// struct CentralValue;
/// impl KernelVisitor<2> for CentralValue {
///     type Output = f64;
///     fn visit<K: Kernel<2>>(self, kernel: K) -> f64 { kernel.value(0.0) }
/// }
/// let kind: KernelKind = "wendland-c2".parse().unwrap();
/// let w0 = kind.dispatch::<2, _>(1.0, CentralValue);
/// assert!((w0 - 7.0 / (4.0 * std::f64::consts::PI)).abs() < 1e-15);
/// ```
pub trait KernelVisitor<const D: usize> {
    /// What the computation returns.
    type Output;
    /// Runs the computation with `kernel`, monomorphised for its type `K`.
    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output;
}

impl KernelKind {
    /// Every kernel, in declaration order.
    pub const ALL: [KernelKind; 6] = [
        KernelKind::CubicSpline,
        KernelKind::QuinticSpline,
        KernelKind::WendlandC2,
        KernelKind::WendlandC4,
        KernelKind::WendlandC6,
        KernelKind::Gaussian,
    ];

    /// The kernel's [`Kernel::NAME`].
    pub const fn name(self) -> &'static str {
        match self {
            KernelKind::CubicSpline => <CubicSpline<2> as Kernel<2>>::NAME,
            KernelKind::QuinticSpline => <QuinticSpline<2> as Kernel<2>>::NAME,
            KernelKind::WendlandC2 => <WendlandC2<2> as Kernel<2>>::NAME,
            KernelKind::WendlandC4 => <WendlandC4<2> as Kernel<2>>::NAME,
            KernelKind::WendlandC6 => <WendlandC6<2> as Kernel<2>>::NAME,
            KernelKind::Gaussian => <Gaussian<2> as Kernel<2>>::NAME,
        }
    }

    /// The kernel's [`Kernel::SUPPORT_FACTOR`] (support radius / h).
    pub const fn support_factor(self) -> Real {
        match self {
            KernelKind::CubicSpline => <CubicSpline<2> as Kernel<2>>::SUPPORT_FACTOR,
            KernelKind::QuinticSpline => <QuinticSpline<2> as Kernel<2>>::SUPPORT_FACTOR,
            KernelKind::WendlandC2 => <WendlandC2<2> as Kernel<2>>::SUPPORT_FACTOR,
            KernelKind::WendlandC4 => <WendlandC4<2> as Kernel<2>>::SUPPORT_FACTOR,
            KernelKind::WendlandC6 => <WendlandC6<2> as Kernel<2>>::SUPPORT_FACTOR,
            KernelKind::Gaussian => <Gaussian<2> as Kernel<2>>::SUPPORT_FACTOR,
        }
    }

    /// Builds the named kernel with smoothing length `h` and runs `visitor` with it.
    ///
    /// # Panics
    /// If `h` is not positive and finite.
    pub fn dispatch<const D: usize, V: KernelVisitor<D>>(self, h: Real, visitor: V) -> V::Output {
        match self {
            KernelKind::CubicSpline => visitor.visit(CubicSpline::<D>::new(h)),
            KernelKind::QuinticSpline => visitor.visit(QuinticSpline::<D>::new(h)),
            KernelKind::WendlandC2 => visitor.visit(WendlandC2::<D>::new(h)),
            KernelKind::WendlandC4 => visitor.visit(WendlandC4::<D>::new(h)),
            KernelKind::WendlandC6 => visitor.visit(WendlandC6::<D>::new(h)),
            KernelKind::Gaussian => visitor.visit(Gaussian::<D>::new(h)),
        }
    }
}

impl fmt::Display for KernelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A kernel name that [`KernelKind::from_str`] does not know.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown kernel `{name}`; expected one of cubic-spline, quintic-spline, wendland-c2, \
     wendland-c4, wendland-c6, gaussian"
)]
pub struct UnknownKernel {
    /// The name that was given.
    pub name: String,
}

impl FromStr for KernelKind {
    type Err = UnknownKernel;

    /// Parses a [`Kernel::NAME`] exactly (case-sensitive, as scene files spell it).
    fn from_str(name: &str) -> Result<Self, Self::Err> {
        KernelKind::ALL
            .into_iter()
            .find(|kind| kind.name() == name)
            .ok_or_else(|| UnknownKernel {
                name: name.to_owned(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_match_the_kernel_constants() {
        for kind in KernelKind::ALL {
            assert_eq!(kind.name().parse::<KernelKind>(), Ok(kind));
            assert_eq!(kind.to_string(), kind.name());
        }
        assert_eq!(KernelKind::WendlandC4.name(), "wendland-c4");
        assert_eq!(
            <Gaussian<3> as Kernel<3>>::NAME,
            KernelKind::Gaussian.name()
        );
        let err = "wendland".parse::<KernelKind>().unwrap_err();
        assert!(err.to_string().contains("`wendland`"), "{err}");
    }

    struct Support;
    impl KernelVisitor<3> for Support {
        type Output = (Real, &'static str);
        fn visit<K: Kernel<3>>(self, kernel: K) -> Self::Output {
            (kernel.support_radius(), K::NAME)
        }
    }

    #[test]
    fn dispatch_builds_the_named_kernel() {
        for kind in KernelKind::ALL {
            let (support, name) = kind.dispatch::<3, _>(0.5, Support);
            assert_eq!(name, kind.name());
            assert_eq!(support, 0.5 * kind.support_factor());
        }
    }

    #[test]
    #[should_panic(expected = "smoothing length must be positive")]
    fn rejects_non_positive_smoothing_length() {
        let _ = CubicSpline::<2>::new(0.0);
    }
}
