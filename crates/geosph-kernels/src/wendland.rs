//! Wendland kernels C2, C4, C6 with support `2h`.
//!
//! Wendland (1995) built compactly supported, positive-definite radial functions
//! `ψ(s)`, `s = r/R ∈ [0, 1]`, that are polynomials on their support; the ones used here are
//! positive definite in up to three dimensions. With support radius `R = 2h`, i.e. `s = q/2`,
//! they read as below (Dehnen & Aly 2012, Table 1, rescaled to support `2h`; DualSPHysics uses
//! the C2 form). All three are written with `t = (1 − q/2)₊`.

use std::f64::consts::PI;

use geosph_core::Real;

use crate::kernel::{Kernel, Scaling};

/// The Wendland C2 kernel, support `2h` (Wendland 1995; Dehnen & Aly 2012).
///
/// ```text
/// Ŵ(q) = (1 − q/2)₊⁴ (1 + 2q),        dŴ/dq = −5q (1 − q/2)₊³
/// W = σ_D/h^D Ŵ(r/h),   σ_2 = 7/(4π),   σ_3 = 21/(16π)
/// ```
///
/// (The design note `000` gives `σ_3 = 21/(2π)`; with it the kernel integrates to 8.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WendlandC2<const D: usize> {
    scaling: Scaling,
}

impl<const D: usize> Kernel<D> for WendlandC2<D> {
    const SUPPORT_FACTOR: Real = 2.0;
    const NAME: &'static str = "wendland-c2";

    fn new(h: Real) -> Self {
        Self {
            scaling: Scaling::new::<D>(
                Self::NAME,
                h,
                Self::SUPPORT_FACTOR,
                7.0 / (4.0 * PI),
                21.0 / (16.0 * PI),
            ),
        }
    }

    #[inline]
    fn smoothing_length(&self) -> Real {
        self.scaling.h
    }

    #[inline]
    fn value(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            self.scaling.value * t2 * t2 * (1.0 + 2.0 * q)
        } else {
            0.0
        }
    }

    #[inline]
    fn radial_derivative(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            self.scaling.derivative * -5.0 * q * t * t * t
        } else {
            0.0
        }
    }

    #[inline]
    fn gradient_factor(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            self.scaling.factor * -5.0 * t * t * t
        } else {
            0.0
        }
    }
}

/// The Wendland C4 kernel, support `2h` (Wendland 1995; Dehnen & Aly 2012).
///
/// ```text
/// Ŵ(q) = (1 − q/2)₊⁶ (1 + 3q + 35q²/12),   dŴ/dq = −(14/3) q (1 + 5q/2) (1 − q/2)₊⁵
/// W = σ_D/h^D Ŵ(r/h),   σ_2 = 9/(4π),   σ_3 = 495/(256π)
/// ```
///
/// (The design note `001` has the polynomial `1 + 3q + 8q²/5` and `σ_2 = 9/π`; both are wrong.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WendlandC4<const D: usize> {
    scaling: Scaling,
}

impl<const D: usize> Kernel<D> for WendlandC4<D> {
    const SUPPORT_FACTOR: Real = 2.0;
    const NAME: &'static str = "wendland-c4";

    fn new(h: Real) -> Self {
        Self {
            scaling: Scaling::new::<D>(
                Self::NAME,
                h,
                Self::SUPPORT_FACTOR,
                9.0 / (4.0 * PI),
                495.0 / (256.0 * PI),
            ),
        }
    }

    #[inline]
    fn smoothing_length(&self) -> Real {
        self.scaling.h
    }

    #[inline]
    fn value(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            self.scaling.value * t2 * t2 * t2 * (1.0 + q * (3.0 + q * (35.0 / 12.0)))
        } else {
            0.0
        }
    }

    #[inline]
    fn radial_derivative(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            self.scaling.derivative * (-14.0 / 3.0) * q * (1.0 + 2.5 * q) * t2 * t2 * t
        } else {
            0.0
        }
    }

    #[inline]
    fn gradient_factor(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            self.scaling.factor * (-14.0 / 3.0) * (1.0 + 2.5 * q) * t2 * t2 * t
        } else {
            0.0
        }
    }
}

/// The Wendland C6 kernel, support `2h` (Wendland 1995; Dehnen & Aly 2012).
///
/// ```text
/// Ŵ(q) = (1 − q/2)₊⁸ (1 + 4q + 25q²/4 + 4q³),
/// dŴ/dq = −(11/2) q (1 + 7q/2 + 4q²) (1 − q/2)₊⁷
/// W = σ_D/h^D Ŵ(r/h),   σ_2 = 39/(14π),   σ_3 = 1365/(512π)
/// ```
///
/// (The design note `001` has the polynomial `1 + 4q + 17q²/5 + 32q³/15`, which is wrong.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WendlandC6<const D: usize> {
    scaling: Scaling,
}

impl<const D: usize> Kernel<D> for WendlandC6<D> {
    const SUPPORT_FACTOR: Real = 2.0;
    const NAME: &'static str = "wendland-c6";

    fn new(h: Real) -> Self {
        Self {
            scaling: Scaling::new::<D>(
                Self::NAME,
                h,
                Self::SUPPORT_FACTOR,
                39.0 / (14.0 * PI),
                1365.0 / (512.0 * PI),
            ),
        }
    }

    #[inline]
    fn smoothing_length(&self) -> Real {
        self.scaling.h
    }

    #[inline]
    fn value(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            let t4 = t2 * t2;
            self.scaling.value * t4 * t4 * (1.0 + q * (4.0 + q * (6.25 + 4.0 * q)))
        } else {
            0.0
        }
    }

    #[inline]
    fn radial_derivative(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            let t4 = t2 * t2;
            self.scaling.derivative * -5.5 * q * (1.0 + q * (3.5 + 4.0 * q)) * t4 * t2 * t
        } else {
            0.0
        }
    }

    #[inline]
    fn gradient_factor(&self, r: Real) -> Real {
        if r < self.scaling.support {
            let q = r * self.scaling.inv_h;
            let t = (1.0 - 0.5 * q).max(0.0);
            let t2 = t * t;
            let t4 = t2 * t2;
            self.scaling.factor * -5.5 * (1.0 + q * (3.5 + 4.0 * q)) * t4 * t2 * t
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The central values are σ_D/h^D, since Ŵ(0) = 1 for all three.
    #[test]
    fn central_value_is_the_normalisation() {
        let h: Real = 0.3;
        assert_relative_eq!(
            WendlandC2::<3>::new(h).value(0.0),
            21.0 / (16.0 * PI * h.powi(3)),
            max_relative = 1e-15
        );
        assert_relative_eq!(
            WendlandC4::<2>::new(h).value(0.0),
            9.0 / (4.0 * PI * h * h),
            max_relative = 1e-15
        );
        assert_relative_eq!(
            WendlandC6::<3>::new(h).value(0.0),
            1365.0 / (512.0 * PI * h.powi(3)),
            max_relative = 1e-15
        );
    }

    /// Ŵ(q) at q = 1 from the closed forms: C2 3/16, C4 (1/64)(1 + 3 + 35/12), C6 (1/256)(15.25).
    #[test]
    fn values_at_q_one() {
        let sigma = |kernel_value: Real, s: Real| kernel_value / s;
        assert_relative_eq!(
            sigma(WendlandC2::<2>::new(1.0).value(1.0), 7.0 / (4.0 * PI)),
            3.0 / 16.0,
            max_relative = 1e-15
        );
        assert_relative_eq!(
            sigma(WendlandC4::<2>::new(1.0).value(1.0), 9.0 / (4.0 * PI)),
            (4.0 + 35.0 / 12.0) / 64.0,
            max_relative = 1e-15
        );
        assert_relative_eq!(
            sigma(WendlandC6::<2>::new(1.0).value(1.0), 39.0 / (14.0 * PI)),
            15.25 / 256.0,
            max_relative = 1e-15
        );
    }
}
