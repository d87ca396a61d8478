//! The exact solution of the Riemann problem of the 1D Euler equations for a gas of
//! [`GasLaw`], the reference of shock-tube tests (Sod 1978, J. Comput. Phys. 27:1).
//!
//! The method of Toro (2009, *Riemann Solvers and Numerical Methods for Fluid Dynamics*,
//! 3rd ed., ch. 4): Newton iteration on the star-region pressure p* of
//! f_L(p) + f_R(p) + u_R − u_L = 0 (eqs. 4.5–4.8), then the self-similar solution sampled at
//! x/t (§4.5). A stiffened gas is solved as the ideal gas of p + p∞ (Ivings, Causon & Toro
//! 1998, Int. J. Numer. Meth. Fluids 28:395): its sound speed, isentropes and shock
//! relations are those of the ideal gas in p + p∞.

use geosph_core::Real;
use geosph_sph::GasLaw;

/// A uniform state of the gas: density ρ, velocity u, pressure p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasState {
    /// ρ in kg/m³.
    pub density: Real,
    /// u in m/s.
    pub velocity: Real,
    /// p in Pa.
    pub pressure: Real,
}

/// The Riemann problem of a left and a right state meeting at x = 0 at t = 0, solved.
#[derive(Clone, Copy, Debug)]
pub struct RiemannSolution {
    law: GasLaw,
    left: GasState,
    right: GasState,
    /// p* + p∞ of the star region.
    star_pressure: Real,
    /// u* of the star region.
    star_velocity: Real,
}

/// f_K(p) and f_K'(p) of Toro (2009, eqs. 4.6–4.7, 4.37) for the state `k` with the
/// pressures shifted by p∞ (`p` and `k.pressure` are p + p∞).
fn wave_function(p: Real, density: Real, pressure: Real, gamma: Real) -> (Real, Real) {
    let c = (gamma * pressure / density).sqrt();
    if p > pressure {
        // shock
        let a = 2.0 / ((gamma + 1.0) * density);
        let b = (gamma - 1.0) / (gamma + 1.0) * pressure;
        let root = (a / (p + b)).sqrt();
        (
            (p - pressure) * root,
            root * (1.0 - 0.5 * (p - pressure) / (p + b)),
        )
    } else {
        // rarefaction
        let exponent = (gamma - 1.0) / (2.0 * gamma);
        let ratio = p / pressure;
        (
            2.0 * c / (gamma - 1.0) * (ratio.powf(exponent) - 1.0),
            ratio.powf(-(gamma + 1.0) / (2.0 * gamma)) / (density * c),
        )
    }
}

impl RiemannSolution {
    /// Solves the problem of `left` and `right` for the gas `law`.
    ///
    /// # Panics
    /// If the states generate a vacuum (u_R − u_L ≥ 2 (c_L + c_R)/(γ − 1), Toro 2009,
    /// eq. 4.40), which no shock tube of this workspace asks for.
    pub fn new(law: GasLaw, left: GasState, right: GasState) -> Self {
        let gamma = law.gamma;
        let shift = law.stiffness;
        let (p_l, p_r) = (left.pressure + shift, right.pressure + shift);
        let c_l = (gamma * p_l / left.density).sqrt();
        let c_r = (gamma * p_r / right.density).sqrt();
        let du = right.velocity - left.velocity;
        assert!(
            2.0 * (c_l + c_r) / (gamma - 1.0) > du,
            "the Riemann problem generates a vacuum"
        );
        // The two-rarefaction guess (Toro 2009, eq. 4.46), then Newton (eq. 4.44).
        let z = (gamma - 1.0) / (2.0 * gamma);
        let guess =
            (c_l + c_r - 0.5 * (gamma - 1.0) * du) / (c_l / p_l.powf(z) + c_r / p_r.powf(z));
        let mut p = guess.powf(1.0 / z).max(1e-12 * (p_l + p_r));
        for _ in 0..100 {
            let (f_l, df_l) = wave_function(p, left.density, p_l, gamma);
            let (f_r, df_r) = wave_function(p, right.density, p_r, gamma);
            let next = (p - (f_l + f_r + du) / (df_l + df_r)).max(1e-12 * (p_l + p_r));
            let change = 2.0 * (next - p).abs() / (next + p);
            p = next;
            if change < 1e-14 {
                break;
            }
        }
        let (f_l, _) = wave_function(p, left.density, p_l, gamma);
        let (f_r, _) = wave_function(p, right.density, p_r, gamma);
        Self {
            law,
            left,
            right,
            star_pressure: p,
            star_velocity: 0.5 * (left.velocity + right.velocity) + 0.5 * (f_r - f_l),
        }
    }

    /// p* of the star region.
    pub fn star_pressure(&self) -> Real {
        self.star_pressure - self.law.stiffness
    }

    /// u* of the star region (the contact's speed).
    pub fn star_velocity(&self) -> Real {
        self.star_velocity
    }

    /// The state at x/t = `speed` (Toro 2009, §4.5; `speed` = 0 is the initial interface).
    pub fn sample(&self, speed: Real) -> GasState {
        let gamma = self.law.gamma;
        let (p_star, u_star) = (self.star_pressure, self.star_velocity);
        // The side of the contact, mirrored to the left: u → −u on the right.
        let (state, sign) = if speed <= u_star {
            (self.left, 1.0)
        } else {
            (self.right, -1.0)
        };
        let (s, u_k, u_s) = (sign * speed, sign * state.velocity, sign * u_star);
        let p_k = state.pressure + self.law.stiffness;
        let rho_k = state.density;
        let c_k = (gamma * p_k / rho_k).sqrt();
        let g = (gamma - 1.0) / (gamma + 1.0);
        let shifted = |density: Real, velocity: Real, pressure: Real| GasState {
            density,
            velocity: sign * velocity,
            pressure: pressure - self.law.stiffness,
        };
        if p_star > p_k {
            // shock of speed S_K (eq. 4.52)
            let shock = u_k
                - c_k
                    * ((gamma + 1.0) / (2.0 * gamma) * p_star / p_k
                        + (gamma - 1.0) / (2.0 * gamma))
                        .sqrt();
            if s <= shock {
                shifted(rho_k, u_k, p_k)
            } else {
                let ratio = p_star / p_k;
                shifted(rho_k * (ratio + g) / (g * ratio + 1.0), u_s, p_star)
            }
        } else {
            // rarefaction between its head and tail (eqs. 4.53–4.56)
            let c_star = c_k * (p_star / p_k).powf((gamma - 1.0) / (2.0 * gamma));
            let (head, tail) = (u_k - c_k, u_s - c_star);
            if s <= head {
                shifted(rho_k, u_k, p_k)
            } else if s >= tail {
                shifted(rho_k * (p_star / p_k).powf(1.0 / gamma), u_s, p_star)
            } else {
                let factor = 2.0 / (gamma + 1.0) + g / c_k * (u_k - s);
                shifted(
                    rho_k * factor.powf(2.0 / (gamma - 1.0)),
                    2.0 / (gamma + 1.0) * (c_k + 0.5 * (gamma - 1.0) * u_k + s),
                    p_k * factor.powf(2.0 * gamma / (gamma - 1.0)),
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sod() -> RiemannSolution {
        RiemannSolution::new(
            GasLaw {
                gamma: 1.4,
                stiffness: 0.0,
            },
            GasState {
                density: 1.0,
                velocity: 0.0,
                pressure: 1.0,
            },
            GasState {
                density: 0.125,
                velocity: 0.0,
                pressure: 0.1,
            },
        )
    }

    /// Sod's problem is test 1 of Toro (2009, Tables 4.1–4.3): p* = 0.30313,
    /// u* = 0.92745, ρ*_L = 0.42632, ρ*_R = 0.26557 (five digits as tabled).
    #[test]
    fn sod_star_region_as_tabled() {
        let solution = sod();
        assert!((solution.star_pressure() - 0.30313).abs() < 5e-6);
        assert!((solution.star_velocity() - 0.92745).abs() < 5e-6);
        let u = solution.star_velocity();
        assert!((solution.sample(u - 1e-9).density - 0.42632).abs() < 5e-6);
        assert!((solution.sample(u + 1e-9).density - 0.26557).abs() < 5e-6);
        // Undisturbed far away, continuous across the rarefaction's head and tail.
        assert_eq!(solution.sample(-5.0).pressure, 1.0);
        assert_eq!(solution.sample(5.0).density, 0.125);
        let c_l = 1.4_f64.sqrt();
        let head = solution.sample(-c_l + 1e-9);
        assert!((head.density - 1.0).abs() < 1e-8 && head.velocity.abs() < 1e-8);
    }

    /// A stiffened gas is the ideal gas of p + p∞: shifting both states' pressures by
    /// p∞ and solving the ideal gas gives the same waves.
    #[test]
    fn stiffened_gas_is_shifted_ideal_gas() {
        let stiff = 3.0;
        let law = GasLaw {
            gamma: 1.4,
            stiffness: stiff,
        };
        let (left, right) = (
            GasState {
                density: 1.0,
                velocity: 0.0,
                pressure: 1.0 - stiff,
            },
            GasState {
                density: 0.125,
                velocity: 0.0,
                pressure: 0.1 - stiff,
            },
        );
        let shifted = RiemannSolution::new(law, left, right);
        let ideal = sod();
        for speed in [-1.0, -0.5, 0.3, 0.95, 1.5, 1.8] {
            let (a, b) = (shifted.sample(speed), ideal.sample(speed));
            assert!((a.density - b.density).abs() < 1e-12);
            assert!((a.pressure + stiff - b.pressure).abs() < 1e-12);
        }
    }
}
