//! The normal modes of a 2D viscous drop in a fluid of the same density and viscosity: the
//! reference of the oscillating drop, whose inviscid limit is Lamb's (1932, §275) frequency.
//!
//! The linearised Navier–Stokes equations about a circle of radius R, for a perturbation
//! ∝ e^{st + inθ}, split the velocity into u = ∇φ + ∇×(ψ ẑ) with ∇²φ = 0 and
//! (∇² − q²) ψ = 0, q² = s/ν; the pressure is p = −ρ s φ. Bounded fields are
//!
//!   inside:  φ = A rⁿ,  ψ = C Iₙ(qr);   outside:  φ = B r⁻ⁿ,  ψ = D Kₙ(qr),
//!
//! with u_r = ∂_r φ + (in/r) ψ and u_θ = (in/r) φ − ∂_r ψ. At r = R, u_r, u_θ and (the
//! viscosities being equal) ∂_r u_θ are continuous, and the normal stress jumps by the
//! capillary pressure of the displaced interface, s η = u_r:
//!
//!   (p − 2μ ∂_r u_r)_in − (p − 2μ ∂_r u_r)_out = σ (n² − 1) η / R²
//!
//! (the curvature of r = R + η e^{inθ} is 1/R + (n² − 1) η/R²). The four conditions are
//! linear in (A, C, B, D): the mode's s is a root of their determinant, found by the secant
//! method from Lamb's s = iω₀, ω₀² = n (n² − 1) σ / (2ρR³). The same analysis of a 3D drop
//! is Miller & Scriven's (1968, J. Fluid Mech. 32:417); as there, the shear layer at the
//! interface, of thickness √(2ν/ω), lowers the frequency and damps the mode by equal amounts
//! O(√(νω)/R) at small ν. `docs/surface-tension.md` gives the figures.

use nalgebra::{Complex, Matrix4};

use geosph_core::Real;

type C = Complex<Real>;

/// The sum Σ_k (∓1)^k a_k(n)/z^k of the asymptotic expansions of Iₙ and Kₙ
/// (Abramowitz & Stegun 9.7.1–2), a_k = Π_{j≤k} (4n² − (2j − 1)²) / (k! 8^k), cut at its
/// smallest term.
fn asymptotic_sum(n: u32, z: C, alternating: bool) -> C {
    let mu = 4.0 * Real::from(n * n);
    let sign = if alternating { -1.0 } else { 1.0 };
    let (mut term, mut sum) = (C::new(1.0, 0.0), C::new(1.0, 0.0));
    for k in 1..60u32 {
        let factor = (mu - Real::from((2 * k - 1) * (2 * k - 1))) / (8.0 * Real::from(k));
        let next = term * sign * factor / z;
        if next.norm() > term.norm() || next.norm() < 1e-17 * sum.norm() {
            break;
        }
        term = next;
        sum += term;
    }
    sum
}

/// e^{−z} Iₙ(z): by its power series Σ_k (z/2)^{n+2k} / (k! (n+k)!) for |z| < 25, else by
/// the asymptotic expansion e^{−z} Iₙ ≈ Σ/√(2πz) (Re z > 0).
fn scaled_bessel_i(n: u32, z: C) -> C {
    if z.norm() >= 25.0 {
        return asymptotic_sum(n, z, true) / (z * 2.0 * std::f64::consts::PI).sqrt();
    }
    let quarter = z * z / 4.0;
    let mut term = (z / 2.0).powu(n) / (1..=n).map(Real::from).product::<Real>();
    let mut sum = term;
    for k in 1..200u32 {
        term *= quarter / Real::from(k * (k + n));
        sum += term;
        if term.norm() < 1e-17 * sum.norm() {
            break;
        }
    }
    sum * (-z).exp()
}

/// e^{z} Kₙ(z) by the asymptotic expansion √(π/2z) Σ.
///
/// # Panics
/// If |z| < 8, where the expansion's smallest term is not below 10⁻⁷ of the sum.
fn scaled_bessel_k(n: u32, z: C) -> C {
    assert!(
        z.norm() >= 8.0,
        "|qR| = {} < 8: the viscous layer is not thin",
        z.norm()
    );
    (C::new(std::f64::consts::PI / 2.0, 0.0) / z).sqrt() * asymptotic_sum(n, z, false)
}

/// f'/f and f''/f at z of f = Iₙ or Kₙ (scaled alike by `scaled`), from the recurrence
/// f' = ±f_{n−1} − (n/z) f and the Bessel equation f'' = (1 + n²/z²) f − f'/z.
fn log_derivatives(scaled: fn(u32, C) -> C, sign: Real, n: u32, z: C) -> [C; 2] {
    let slope = scaled(n - 1, z) / scaled(n, z) * sign - Real::from(n) / z;
    let curvature = (1.0 + Real::from(n * n) / (z * z)) - slope / z;
    [slope, curvature]
}

/// The determinant of the interface conditions of mode `n` at growth rate `s`.
fn determinant(s: C, n: u32, radius: Real, viscosity: Real, sigma: Real, density: Real) -> C {
    let (r, nn, i) = (radius, Real::from(n), C::i());
    let q = (s / viscosity).sqrt();
    // Columns C and D are divided by Iₙ(qR) and Kₙ(qR): the roots stay.
    let (bi, bk) = (C::new(1.0, 0.0), C::new(1.0, 0.0));
    let [dbi, ddbi] = log_derivatives(scaled_bessel_i, 1.0, n, q * r);
    let [dbk, ddbk] = log_derivatives(scaled_bessel_k, -1.0, n, q * r);
    let mu = density * viscosity;
    let power = |k: i32| C::new(r.powi(k), 0.0);
    // Columns A, C (inside) and B, D (outside, with a minus sign: the rows are jumps).
    let radial_in = [power(n as i32 - 1) * nn, i * nn / r * bi];
    let radial_out = [power(-(n as i32) - 1) * -nn, i * nn / r * bk];
    let azimuthal_in = [i * nn * power(n as i32 - 1), -q * dbi];
    let azimuthal_out = [i * nn * power(-(n as i32) - 1), -q * dbk];
    let shear_in = [i * nn * (nn - 1.0) * power(n as i32 - 2), -q * q * ddbi];
    let shear_out = [i * nn * (-nn - 1.0) * power(-(n as i32) - 2), -q * q * ddbk];
    let stretch_in = [
        power(n as i32 - 2) * nn * (nn - 1.0),
        i * nn * (q * dbi / r - bi / (r * r)),
    ];
    let stretch_out = [
        power(-(n as i32) - 2) * nn * (nn + 1.0),
        i * nn * (q * dbk / r - bk / (r * r)),
    ];
    let pressure_in = [-s * density * power(n as i32), C::new(0.0, 0.0)];
    let pressure_out = [-s * density * power(-(n as i32)), C::new(0.0, 0.0)];
    let capillary = sigma * (nn * nn - 1.0) / (r * r) / s;
    let normal_in =
        |k: usize| pressure_in[k] - stretch_in[k] * (2.0 * mu) - capillary * radial_in[k];
    let normal_out = |k: usize| pressure_out[k] - stretch_out[k] * (2.0 * mu);
    Matrix4::new(
        radial_in[0],
        radial_in[1],
        -radial_out[0],
        -radial_out[1],
        azimuthal_in[0],
        azimuthal_in[1],
        -azimuthal_out[0],
        -azimuthal_out[1],
        shear_in[0],
        shear_in[1],
        -shear_out[0],
        -shear_out[1],
        normal_in(0),
        normal_in(1),
        -normal_out(0),
        -normal_out(1),
    )
    .determinant()
}

/// Lamb's (1932, §275) frequency ω₀ of mode `n` of a 2D drop of radius `radius` in a fluid of
/// its density `density`, both inviscid: ω₀² = n (n² − 1) σ / ((ρ_in + ρ_out) R³) with
/// ρ_in = ρ_out = ρ.
pub fn lamb_frequency(n: u32, radius: Real, sigma: Real, density: Real) -> Real {
    let n = Real::from(n);
    (n * (n * n - 1.0) * sigma / (2.0 * density * radius.powi(3))).sqrt()
}

/// The complex rate s = −γ + iω of mode `n` of a 2D drop of radius `radius` (m), kinematic
/// viscosity `viscosity` (m²/s) inside and out, surface tension `sigma` (N/m) and density
/// `density` (kg/m³) inside and out: its period is 2π/ω and its amplitude decays as e^{−γt}.
///
/// # Panics
/// If the secant method does not converge in 100 steps, or the viscous layer is not thin
/// (|R √(s/ν)| < 8).
pub fn viscous_mode(n: u32, radius: Real, viscosity: Real, sigma: Real, density: Real) -> C {
    let lamb = lamb_frequency(n, radius, sigma, density);
    let f = |s: C| determinant(s, n, radius, viscosity, sigma, density);
    let (mut s0, mut s1) = (
        C::new(-1e-3 * lamb, lamb),
        C::new(-0.05 * lamb, 0.98 * lamb),
    );
    let (mut f0, mut f1) = (f(s0), f(s1));
    for _ in 0..100 {
        let s2 = s1 - f1 * (s1 - s0) / (f1 - f0);
        (s0, f0, s1) = (s1, f1, s2);
        f1 = f(s1);
        if (s1 - s0).norm() < 1e-12 * s1.norm() {
            return s1;
        }
    }
    panic!("the viscous mode {n} of R = {radius} m, ν = {viscosity} m²/s did not converge");
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At small ν the shear layer shifts the rate by (1 + i) × O(√(νω)) from Lamb's iω₀,
    /// equal parts damping and lowered frequency, growing as √ν; the mode is damped.
    #[test]
    fn the_viscous_mode_tends_to_lambs_as_the_viscosity_vanishes() {
        let omega = (3.0_f64 / 0.008).sqrt();
        let shift = |nu: Real| {
            let s = viscous_mode(2, 0.2, nu, 1.0, 1.0);
            (-s.re, omega - s.im)
        };
        let (damping, lowering) = shift(1e-6);
        assert!(damping > 0.0 && lowering > 0.0);
        assert!(
            (damping / lowering - 1.0).abs() < 0.02,
            "{damping} {lowering}"
        );
        let (larger, _) = shift(1e-4);
        assert!(
            (larger / damping / 10.0 - 1.0).abs() < 0.02,
            "√ν: {larger} {damping}"
        );
    }
}
