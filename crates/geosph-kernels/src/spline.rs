//! B-spline kernels: the cubic (M4) and quintic (M6) splines.
//!
//! Both are written with truncated powers `(a − q)₊^k`; on the innermost interval the sum is
//! expanded into a polynomial in `q`, which is cheaper and makes `(1/q) dŴ/dq` free of the
//! cancellation that the truncated-power form suffers near `q = 0`.

use std::f64::consts::PI;

use geosph_core::Real;

use crate::kernel::{Kernel, Scaling};

/// The cubic B-spline (M4) kernel, support `2h` (Monaghan & Lattanzio 1985; Monaghan 1992).
///
/// ```text
/// Ŵ(q) = (2 − q)₊³/4 − (1 − q)₊³ = { 1 − 3q²/2 + 3q³/4     0 ≤ q < 1
///                                   { (2 − q)³/4             1 ≤ q < 2
/// W = σ_D/h^D Ŵ(r/h),   σ_2 = 10/(7π),   σ_3 = 1/π
/// ```
///
/// The same kernel appears as `k (2/3 − q² + q³/2)` with `k_2 = 15/(7πh²)`, `k_3 = 3/(2πh³)`
/// (Bui et al. 2008), and with support `h` as `6(q³ − q²) + 1` with `k_2 = 40/(7πh²)`,
/// `k_3 = 8/(πh³)` (Koschier et al. 2019).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicSpline<const D: usize> {
    scaling: Scaling,
}

impl<const D: usize> Kernel<D> for CubicSpline<D> {
    const SUPPORT_FACTOR: Real = 2.0;
    const NAME: &'static str = "cubic-spline";

    fn new(h: Real) -> Self {
        Self {
            scaling: Scaling::new::<D>(
                Self::NAME,
                h,
                Self::SUPPORT_FACTOR,
                10.0 / (7.0 * PI),
                1.0 / PI,
            ),
        }
    }

    #[inline]
    fn smoothing_length(&self) -> Real {
        self.scaling.h
    }

    #[inline]
    fn value(&self, r: Real) -> Real {
        // Both pieces, then a select: q < 1 is a coin toss over a particle's neighbours, and
        // a branch on it is mispredicted about half the time. (2 − q)₊ ends the support.
        let q = r * self.scaling.inv_h;
        let t = (2.0 - q).max(0.0);
        let inner = 1.0 - q * q * (1.5 - 0.75 * q);
        let outer = 0.25 * t * t * t;
        self.scaling.value * if q < 1.0 { inner } else { outer }
    }

    #[inline]
    fn radial_derivative(&self, r: Real) -> Real {
        let q = r * self.scaling.inv_h;
        let shape = if q < 1.0 {
            q * (2.25 * q - 3.0)
        } else if r < self.scaling.support {
            let t = (2.0 - q).max(0.0);
            -0.75 * t * t
        } else {
            0.0
        };
        self.scaling.derivative * shape
    }

    #[inline]
    fn gradient_factor(&self, r: Real) -> Real {
        // Branch-free as `value`; the outer piece's 1/q is not used at q = 0.
        let q = r * self.scaling.inv_h;
        let t = (2.0 - q).max(0.0);
        let inner = 2.25 * q - 3.0;
        let outer = -0.75 * t * t / q;
        self.scaling.factor * if q < 1.0 { inner } else { outer }
    }
}

/// The quintic B-spline (M6) kernel, support `3h` (Morris, Fox & Zhu 1997; Liu & Liu 2003).
///
/// ```text
/// Ŵ(q) = (3 − q)₊⁵ − 6 (2 − q)₊⁵ + 15 (1 − q)₊⁵
///      = 66 − 60q² + 30q⁴ − 10q⁵                  on 0 ≤ q < 1 (expanded)
/// W = σ_D/h^D Ŵ(r/h),   σ_2 = 7/(478π),   σ_3 = 1/(120π)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuinticSpline<const D: usize> {
    scaling: Scaling,
}

impl<const D: usize> Kernel<D> for QuinticSpline<D> {
    const SUPPORT_FACTOR: Real = 3.0;
    const NAME: &'static str = "quintic-spline";

    fn new(h: Real) -> Self {
        Self {
            scaling: Scaling::new::<D>(
                Self::NAME,
                h,
                Self::SUPPORT_FACTOR,
                7.0 / (478.0 * PI),
                1.0 / (120.0 * PI),
            ),
        }
    }

    #[inline]
    fn smoothing_length(&self) -> Real {
        self.scaling.h
    }

    #[inline]
    fn value(&self, r: Real) -> Real {
        let q = r * self.scaling.inv_h;
        let shape = if q < 1.0 {
            let q2 = q * q;
            66.0 + q2 * (-60.0 + q2 * (30.0 - 10.0 * q))
        } else if r < self.scaling.support {
            let t3 = (3.0 - q).max(0.0);
            let t2 = (2.0 - q).max(0.0);
            let (t3_2, t2_2) = (t3 * t3, t2 * t2);
            t3_2 * t3_2 * t3 - 6.0 * t2_2 * t2_2 * t2
        } else {
            0.0
        };
        self.scaling.value * shape
    }

    #[inline]
    fn radial_derivative(&self, r: Real) -> Real {
        let q = r * self.scaling.inv_h;
        let shape = if q < 1.0 {
            let q2 = q * q;
            q * (-120.0 + q2 * (120.0 - 50.0 * q))
        } else if r < self.scaling.support {
            let t3 = (3.0 - q).max(0.0);
            let t2 = (2.0 - q).max(0.0);
            let (t3_2, t2_2) = (t3 * t3, t2 * t2);
            -5.0 * (t3_2 * t3_2 - 6.0 * t2_2 * t2_2)
        } else {
            0.0
        };
        self.scaling.derivative * shape
    }

    #[inline]
    fn gradient_factor(&self, r: Real) -> Real {
        let q = r * self.scaling.inv_h;
        let shape = if q < 1.0 {
            -120.0 + q * q * (120.0 - 50.0 * q)
        } else if r < self.scaling.support {
            let t3 = (3.0 - q).max(0.0);
            let t2 = (2.0 - q).max(0.0);
            let (t3_2, t2_2) = (t3 * t3, t2 * t2);
            -5.0 * (t3_2 * t3_2 - 6.0 * t2_2 * t2_2) / q
        } else {
            0.0
        };
        self.scaling.factor * shape
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The expanded inner polynomials equal the truncated-power forms.
    #[test]
    fn expanded_polynomials_match_truncated_powers() {
        let cubic = CubicSpline::<2>::new(1.0);
        let quintic = QuinticSpline::<3>::new(1.0);
        let sigma_cubic = 10.0 / (7.0 * PI);
        let sigma_quintic = 1.0 / (120.0 * PI);
        for k in 0..=40 {
            let q = k as Real * 0.025;
            let pow = |a: Real, n: i32| (a - q).max(0.0).powi(n);
            assert_relative_eq!(
                cubic.value(q),
                sigma_cubic * (pow(2.0, 3) / 4.0 - pow(1.0, 3)),
                max_relative = 1e-13
            );
            assert_relative_eq!(
                quintic.value(q),
                sigma_quintic * (pow(3.0, 5) - 6.0 * pow(2.0, 5) + 15.0 * pow(1.0, 5)),
                max_relative = 1e-13
            );
            let derivative = -5.0 * (pow(3.0, 4) - 6.0 * pow(2.0, 4) + 15.0 * pow(1.0, 4));
            assert_relative_eq!(
                quintic.radial_derivative(q),
                sigma_quintic * derivative,
                epsilon = 1e-13,
                max_relative = 1e-12
            );
        }
    }

    #[test]
    fn central_values() {
        // Ŵ(0) = 1 (cubic) and 66 (quintic).
        assert_relative_eq!(CubicSpline::<3>::new(2.0).value(0.0), 1.0 / (8.0 * PI));
        assert_relative_eq!(
            QuinticSpline::<2>::new(0.5).value(0.0),
            66.0 * 7.0 / (478.0 * PI * 0.25),
            max_relative = 1e-15
        );
        // (1/r) dW/dr → d²W/dr²(0) = −3σ/h^{D+2} for the cubic spline.
        assert_relative_eq!(
            CubicSpline::<2>::new(1.0).gradient_factor(0.0),
            -3.0 * 10.0 / (7.0 * PI)
        );
    }
}
