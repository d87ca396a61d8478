//! Smoothing kernels: normalisation, derivatives, support, and the errors of the design notes.
//!
//! Every kernel in 2D and 3D must integrate to 1 (`∫ W dV`, by composite Gauss–Legendre
//! quadrature split at the spline breakpoints, exact for the piecewise polynomials), be
//! non-negative and non-increasing, vanish with its derivative at and beyond the support, and
//! have `dW/dr`, `(1/r) dW/dr` and `∇W` consistent with central finite differences of `W`.
//! The same quadrature applied to the constants and polynomials of the project's starting
//! design notes (quoted in `docs/theory.md`, "Errors in the design notes confirmed by tests")
//! shows they do not integrate to 1.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use geosph_core::{Real, Vector};
use geosph_kernels::quadrature::radial_integral;
use geosph_kernels::{CubicSpline, Gaussian, Kernel, KernelKind, KernelVisitor};
use rand::{Rng, SeedableRng, rngs::StdRng};

/// `[0, h, 2h, …, support]`: every breakpoint of every kernel here.
fn breakpoints(support_factor: Real, h: Real) -> Vec<Real> {
    (0..=support_factor as usize)
        .map(|k| k as Real * h)
        .collect()
}

/// Runs every property check on one kernel.
struct Properties {
    h: Real,
}

impl<const D: usize> KernelVisitor<D> for Properties {
    type Output = ();

    fn visit<K: Kernel<D>>(self, kernel: K) {
        let h = self.h;
        let name = K::NAME;
        let support = kernel.support_radius();
        assert_eq!(kernel.smoothing_length(), h);
        assert_eq!(support, K::SUPPORT_FACTOR * h);
        let peak = kernel.value(0.0);
        // Scale of dW/dr and of (1/r) dW/dr.
        let (derivative_scale, factor_scale) = (peak / h, peak / (h * h));

        // Normalisation, to round-off (the brief asks for ≤ 1e-6).
        let integral =
            radial_integral::<D>(|r| kernel.value(r), &breakpoints(K::SUPPORT_FACTOR, h));
        assert_relative_eq!(integral, 1.0, epsilon = 1e-12);

        // Non-negative and non-increasing; dW/dr = (1/r dW/dr)·r.
        let samples = 4000;
        let mut previous = Real::INFINITY;
        for k in 0..=samples {
            let r = 1.1 * support * k as Real / samples as Real;
            let w = kernel.value(r);
            assert!(w >= 0.0, "{name} {D}D: W({r}) = {w} < 0");
            assert!(w <= previous, "{name} {D}D: W increases at r = {r}");
            previous = w;
            let derivative = kernel.radial_derivative(r);
            assert!(
                derivative <= 0.0,
                "{name} {D}D: dW/dr({r}) = {derivative} > 0"
            );
            assert_relative_eq!(
                kernel.gradient_factor(r) * r,
                derivative,
                epsilon = 1e-14 * derivative_scale,
                max_relative = 1e-12
            );
        }

        // Zero at and beyond the support, in value, derivatives and gradient.
        for r in [
            support,
            support * (1.0 + 1e-15),
            1.5 * support,
            10.0 * support,
        ] {
            assert_eq!(kernel.value(r), 0.0, "{name} {D}D at r = {r}");
            assert_eq!(kernel.radial_derivative(r), 0.0, "{name} {D}D at r = {r}");
            assert_eq!(kernel.gradient_factor(r), 0.0, "{name} {D}D at r = {r}");
            let mut r_ij = Vector::<D>::zeros();
            r_ij[D - 1] = r;
            assert_eq!(kernel.gradient(&r_ij), Vector::<D>::zeros());
        }

        // dW/dr against a central difference of W, at points off the breakpoints (and, for
        // the Gaussian, more than the step away from its truncation jump).
        let step = 1e-5 * h;
        let mut r = 0.013 * h;
        while r < support - 2.0 * step {
            let difference = (kernel.value(r + step) - kernel.value(r - step)) / (2.0 * step);
            assert_relative_eq!(
                kernel.radial_derivative(r),
                difference,
                epsilon = 1e-8 * derivative_scale,
                max_relative = 1e-7
            );
            r += 0.05 * h;
        }
        // dW/dr(0) = 0 and (1/r) dW/dr → its value at 0.
        assert_eq!(kernel.radial_derivative(0.0), 0.0);
        assert!(kernel.gradient_factor(0.0).is_finite() && kernel.gradient_factor(0.0) < 0.0);
        assert_relative_eq!(
            kernel.gradient_factor(1e-10 * h),
            kernel.gradient_factor(0.0),
            epsilon = 1e-8 * factor_scale
        );

        // ∇W against central differences of W(|x|) along each axis, at random r_ij.
        let mut rng = StdRng::seed_from_u64(17 + D as u64);
        assert_eq!(kernel.gradient(&Vector::<D>::zeros()), Vector::<D>::zeros());
        for _ in 0..200 {
            let r_ij = Vector::<D>::from_fn(|_, _| rng.random_range(-1.0..1.0) * support * 0.55);
            if (r_ij.norm() - support).abs() < 4.0 * step {
                continue;
            }
            let gradient = kernel.gradient(&r_ij);
            for axis in 0..D {
                let mut plus = r_ij;
                let mut minus = r_ij;
                plus[axis] += step;
                minus[axis] -= step;
                let difference =
                    (kernel.value(plus.norm()) - kernel.value(minus.norm())) / (2.0 * step);
                assert_relative_eq!(
                    gradient[axis],
                    difference,
                    epsilon = 1e-8 * derivative_scale,
                    max_relative = 1e-7
                );
            }
            // ∇_i W_ij = −∇_j W_ij: the gradient is odd in r_ij.
            assert_eq!(kernel.gradient(&-r_ij), -gradient);
        }
    }
}

#[test]
fn every_kernel_is_normalised_smooth_and_compactly_supported() {
    for kind in KernelKind::ALL {
        for h in [1.0, 0.37, 2.5e-3] {
            kind.dispatch::<2, _>(h, Properties { h });
            kind.dispatch::<3, _>(h, Properties { h });
        }
    }
}

/// The Wendland C2 kernel's shape `(1 − q/2)⁴ (1 + 2q)`.
fn wendland_c2_shape(q: Real) -> Real {
    (1.0 - 0.5 * q).max(0.0).powi(4) * (1.0 + 2.0 * q)
}

/// Wendland C4's shape with the polynomial `p(q)`: `(1 − q/2)⁶ p(q)`.
fn wendland_c4_shape(q: Real, quadratic: Real) -> Real {
    (1.0 - 0.5 * q).max(0.0).powi(6) * (1.0 + 3.0 * q + quadratic * q * q)
}

/// Wendland C6's shape `(1 − q/2)⁸ (1 + 4q + a q² + b q³)`.
fn wendland_c6_shape(q: Real, a: Real, b: Real) -> Real {
    (1.0 - 0.5 * q).max(0.0).powi(8) * (1.0 + 4.0 * q + a * q * q + b * q * q * q)
}

/// The quadrature that validates the kernels rejects the constants and polynomials of the
/// design notes (`docs/theory.md`): it is a real check, not a tautology.
#[test]
fn quadrature_catches_the_design_note_errors() {
    let h: Real = 0.7;
    let support = [0.0, 2.0 * h];
    // 000: Wendland C2 in 3D with k₃ = 21/(2πh³) integrates to 8 (right: 21/(16πh³)).
    let wrong = radial_integral::<3>(
        |r| 21.0 / (2.0 * PI * h.powi(3)) * wendland_c2_shape(r / h),
        &support,
    );
    assert_relative_eq!(wrong, 8.0, max_relative = 1e-13);
    let right = radial_integral::<3>(
        |r| 21.0 / (16.0 * PI * h.powi(3)) * wendland_c2_shape(r / h),
        &support,
    );
    assert_relative_eq!(right, 1.0, max_relative = 1e-13);

    // 001: Wendland C4 in 2D with σ = 9/(πh²) integrates to 4 (right: 9/(4πh²)).
    let wrong = radial_integral::<2>(
        |r| 9.0 / (PI * h * h) * wendland_c4_shape(r / h, 35.0 / 12.0),
        &support,
    );
    assert_relative_eq!(wrong, 4.0, max_relative = 1e-13);

    // 001: the C4 polynomial 1 + 3q + 8q²/5 with the right constants integrates to 621/700
    // (2D) and 481/560 (3D).
    let wrong_2d = radial_integral::<2>(
        |r| 9.0 / (4.0 * PI * h * h) * wendland_c4_shape(r / h, 1.6),
        &support,
    );
    assert_relative_eq!(wrong_2d, 621.0 / 700.0, max_relative = 1e-13);
    let wrong_3d = radial_integral::<3>(
        |r| 495.0 / (256.0 * PI * h.powi(3)) * wendland_c4_shape(r / h, 1.6),
        &support,
    );
    assert_relative_eq!(wrong_3d, 481.0 / 560.0, max_relative = 1e-13);

    // 001: the C6 polynomial 1 + 4q + 17q²/5 + 32q³/15 with σ₃ = 1365/(512πh³) gives 6163/7920;
    // the right one 1 + 4q + 25q²/4 + 4q³ gives 1.
    let sigma_3 = 1365.0 / (512.0 * PI * h.powi(3));
    let wrong = radial_integral::<3>(
        |r| sigma_3 * wendland_c6_shape(r / h, 3.4, 32.0 / 15.0),
        &support,
    );
    assert_relative_eq!(wrong, 6163.0 / 7920.0, max_relative = 1e-13);
    let right = radial_integral::<3>(|r| sigma_3 * wendland_c6_shape(r / h, 6.25, 4.0), &support);
    assert_relative_eq!(right, 1.0, max_relative = 1e-13);

    // 001: the quintic "(1−q)⁵ − 6(0.5−q)⁵ + 15(0−q)⁵ on [0, 1)" is negative inside its
    // support, so it is not a kernel whatever its constant.
    let garbled = |q: Real| (1.0 - q).powi(5) - 6.0 * (0.5 - q).powi(5) + 15.0 * (-q).powi(5);
    assert!(garbled(0.9) < -1.0, "{}", garbled(0.9));
}

/// `∇²W = d²W/dr² + (D−1)/r dW/dr` for a radial kernel; the notes (000, 001) give only
/// `d²W/dr²` for the cubic spline. By the divergence theorem `∫_{r<R} ∇²W dV` equals the
/// flux `|S^{D−1}| R^{D−1} dW/dr(R)`, which is 0 for a compact kernel; `∫ d²W/dr² dV` is not.
#[test]
fn laplacian_needs_the_first_derivative_term() {
    let h = 0.5;
    let second_derivative = |kernel: &CubicSpline<2>, r: Real| {
        let step = 1e-5 * h;
        (kernel.radial_derivative(r + step) - kernel.radial_derivative(r - step)) / (2.0 * step)
    };
    let kernel = CubicSpline::<2>::new(h);
    let pieces = breakpoints(2.0, h);
    let laplacian = radial_integral::<2>(
        |r| second_derivative(&kernel, r) + kernel.gradient_factor(r),
        &pieces,
    );
    let only_second = radial_integral::<2>(|r| second_derivative(&kernel, r), &pieces);
    let scale = kernel.value(0.0);
    assert!(laplacian.abs() < 1e-7 * scale, "{laplacian}");
    // ∫ W'' 2πr dr = −2π ∫ W' dr = 2π W(0).
    assert_relative_eq!(only_second, 2.0 * PI * scale, max_relative = 1e-7);

    // Gaussian: ∇²W = σ/h² (4q² − 2D) e^{−q²}; note 001 has 4(2q² − D), twice as large.
    // Inside the truncation radius R = 3h the integral must equal the flux through |r| = R.
    let gaussian = Gaussian::<3>::new(h);
    let sigma_over_h5 = gaussian.value(0.0) / (h * h);
    let flux = 4.0 * PI * (3.0 * h).powi(2) * gaussian.radial_derivative(3.0 * h * (1.0 - 1e-15));
    let pieces = breakpoints(3.0, h);
    let laplacian = |r: Real, a: Real, b: Real| {
        let q = r / h;
        sigma_over_h5 * (a * q * q - b) * (-q * q).exp()
    };
    let right = radial_integral::<3>(|r| laplacian(r, 4.0, 6.0), &pieces);
    let note = radial_integral::<3>(|r| laplacian(r, 8.0, 12.0), &pieces);
    assert_relative_eq!(right, flux, max_relative = 1e-10);
    assert_relative_eq!(note, 2.0 * flux, max_relative = 1e-10);
}

/// The cubic spline in the three normalisations found in the literature is one kernel.
#[test]
fn cubic_spline_forms_agree() {
    let h = 0.8;
    let kernel_2d = CubicSpline::<2>::new(h);
    let kernel_3d = CubicSpline::<3>::new(h);
    {
        for step in 0..=40 {
            let q = step as Real * 0.05;
            let r = q * h;
            // Bui et al. (2008): k (2/3 − q² + q³/2), (2 − q)³/6; k₂ = 15/(7πh²), k₃ = 3/(2πh³).
            let bui = if q <= 1.0 {
                2.0 / 3.0 - q * q + 0.5 * q * q * q
            } else {
                (2.0 - q).max(0.0).powi(3) / 6.0
            };
            assert_relative_eq!(
                kernel_2d.value(r),
                15.0 / (7.0 * PI * h * h) * bui,
                epsilon = 1e-14
            );
            assert_relative_eq!(
                kernel_3d.value(r),
                3.0 / (2.0 * PI * h.powi(3)) * bui,
                epsilon = 1e-14
            );
            // Koschier et al. (2019), support H = 2h: k₂ = 40/(7πH²), k₃ = 8/(πH³).
            let (big_h, s) = (2.0 * h, q / 2.0);
            let koschier = if s <= 0.5 {
                6.0 * (s * s * s - s * s) + 1.0
            } else {
                2.0 * (1.0 - s).max(0.0).powi(3)
            };
            assert_relative_eq!(
                kernel_3d.value(r),
                8.0 / (PI * big_h.powi(3)) * koschier,
                epsilon = 1e-14
            );
        }
    }
}
