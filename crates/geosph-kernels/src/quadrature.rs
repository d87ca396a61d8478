//! Gauss–Legendre quadrature and radial integrals over ℝ^D.
//!
//! Used to check kernel normalisations `∫ W dV = 1` and to compute kernel moments. A kernel
//! that is a polynomial between breakpoints (the splines, Wendland) is integrated exactly, up
//! to rounding, by a rule of enough points on each piece.

use std::f64::consts::PI;

use geosph_core::Real;

/// An `n`-point Gauss–Legendre rule on `[−1, 1]`, exact for polynomials of degree `2n − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<Real>,
    weights: Vec<Real>,
}

impl GaussLegendre {
    /// The `n`-point rule; nodes are the roots of the Legendre polynomial `P_n`, found by Newton
    /// iteration from `cos(π(k − 1/4)/(n + 1/2))`, weights `2 / ((1 − x²) P_n'(x)²)`
    /// (Abramowitz & Stegun 1964, eq. 25.4.29).
    ///
    /// # Panics
    /// If `n == 0`.
    pub fn new(n: usize) -> Self {
        assert!(n > 0, "a Gauss–Legendre rule needs at least one point");
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as Real;
        for k in 0..n.div_ceil(2) {
            let mut x = (PI * (k as Real + 0.75) / (nf + 0.5)).cos();
            let mut derivative = 0.0;
            for _ in 0..100 {
                // Three-term recurrence (j+1) P_{j+1} = (2j+1) x P_j − j P_{j−1}.
                let (mut p_prev, mut p) = (1.0, x);
                for j in 1..n {
                    let jf = j as Real;
                    let p_next = ((2.0 * jf + 1.0) * x * p - jf * p_prev) / (jf + 1.0);
                    p_prev = p;
                    p = p_next;
                }
                derivative = nf * (x * p - p_prev) / (x * x - 1.0);
                let step = p / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
            nodes[k] = -x;
            nodes[n - 1 - k] = x;
            weights[k] = weight;
            weights[n - 1 - k] = weight;
        }
        Self { nodes, weights }
    }

    /// Nodes on `[−1, 1]`, ascending.
    pub fn nodes(&self) -> &[Real] {
        &self.nodes
    }

    /// Weights, summing to 2.
    pub fn weights(&self) -> &[Real] {
        &self.weights
    }

    /// `∫_a^b f(x) dx` with this rule mapped to `[a, b]`.
    pub fn integrate(&self, f: impl Fn(Real) -> Real, a: Real, b: Real) -> Real {
        let (centre, half) = (0.5 * (a + b), 0.5 * (b - a));
        let sum: Real = self
            .nodes
            .iter()
            .zip(&self.weights)
            .map(|(&x, &w)| w * f(centre + half * x))
            .sum();
        half * sum
    }
}

/// Area of the unit sphere `S^{D−1}` in ℝ^D: 2, 2π, 4π for D = 1, 2, 3.
///
/// # Panics
/// For other `D`.
pub fn unit_sphere_area(dimension: usize) -> Real {
    match dimension {
        1 => 2.0,
        2 => 2.0 * PI,
        3 => 4.0 * PI,
        _ => panic!("unit_sphere_area: D = {dimension} is not supported (1, 2 or 3)"),
    }
}

/// `∫_{a ≤ |x| ≤ b} f(|x|) dx` over ℝ^D, i.e. `∫_a^b f(r) |S^{D−1}| r^{D−1} dr`, for
/// `breakpoints = [a, …, b]` ascending.
///
/// Each interval between consecutive breakpoints is split into 16 equal panels, each
/// integrated with a 12-point Gauss–Legendre rule (exact to degree 23). Split at the points
/// where `f` is not smooth (for the splines at every multiple of h) to get exact results for
/// piecewise polynomials and errors near 1e-16 for smooth `f`.
///
/// # Panics
/// If `D` is not 1, 2 or 3, or the breakpoints are not ascending.
pub fn radial_integral<const D: usize>(f: impl Fn(Real) -> Real, breakpoints: &[Real]) -> Real {
    const PANELS: usize = 16;
    let rule = GaussLegendre::new(12);
    let area = unit_sphere_area(D);
    let integrand = |r: Real| f(r) * area * r.powi(D as i32 - 1);
    let mut total = 0.0;
    for piece in breakpoints.windows(2) {
        let (a, b) = (piece[0], piece[1]);
        assert!(
            a <= b,
            "radial_integral: breakpoints must ascend, got {a} > {b}"
        );
        let width = (b - a) / PANELS as Real;
        for panel in 0..PANELS {
            let lo = a + panel as Real * width;
            total += rule.integrate(integrand, lo, lo + width);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn rule_is_exact_to_degree_2n_minus_1() {
        for n in 1..=12 {
            let rule = GaussLegendre::new(n);
            assert_relative_eq!(rule.weights().iter().sum::<Real>(), 2.0, epsilon = 1e-14);
            let degree = 2 * n as i32 - 1;
            // ∫_0^1 x^k dx = 1/(k+1)
            for k in 0..=degree {
                let integral = rule.integrate(|x| x.powi(k), 0.0, 1.0);
                assert_relative_eq!(integral, 1.0 / (k as Real + 1.0), epsilon = 1e-14);
            }
            if n > 1 {
                // …and not beyond (the error of degree 2n is non-zero).
                let integral = rule.integrate(|x| x.powi(degree + 1), 0.0, 1.0);
                assert!((integral - 1.0 / (degree as Real + 2.0)).abs() > 1e-16);
            }
        }
    }

    #[test]
    fn ball_volumes() {
        // ∫_{|x|≤2} 1 dx = 4π (2D), 32π/3 (3D)
        assert_relative_eq!(
            radial_integral::<2>(|_| 1.0, &[0.0, 2.0]),
            4.0 * PI,
            max_relative = 1e-14
        );
        assert_relative_eq!(
            radial_integral::<3>(|_| 1.0, &[0.0, 1.0, 2.0]),
            32.0 * PI / 3.0,
            max_relative = 1e-14
        );
        // ∫ exp(−r²) over ℝ³ = π^{3/2}; truncation at 8 leaves < 1e-27.
        assert_relative_eq!(
            radial_integral::<3>(|r| (-r * r).exp(), &[0.0, 2.0, 4.0, 8.0]),
            PI.powf(1.5),
            max_relative = 1e-14
        );
    }
}
