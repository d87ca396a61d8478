//! Equations of state of weakly compressible SPH, also the initial density ρ(p) of a liquid
//! that starts under pressure (hydrostatic, or an initial pressure field), and the gas laws
//! p(ρ, e) of a fluid that carries its internal energy ([`GasLaw`]).

use geosph_core::Real;
use serde::{Deserialize, Serialize};

/// The form of the pressure–density relation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EosKind {
    /// Tait's equation, p = B [(ρ/ρ₀)^γ − 1], B = ρ₀ c₀² / γ (Monaghan 1994, J. Comput. Phys.
    /// 110:399, eq. 3.3; Batchelor 1967). γ = 7 for water.
    Tait {
        /// Exponent γ.
        gamma: Real,
    },
    /// Linear equation, p = c₀² (ρ − ρ₀) (Morris et al. 1997, eq. 10 with p₀ = 0).
    Linear,
    /// Ideal gas, p = (γ − 1) ρ e with the specific internal energy e ([`GasLaw`]); γ = 1.4
    /// for air. The particles carry e and integrate its equation.
    IdealGas {
        /// Ratio of specific heats γ.
        gamma: Real,
    },
    /// Stiffened gas, p = (γ − 1) ρ e − γ p∞ ([`GasLaw`]; Harlow & Amsden 1971, LANL report
    /// LA-4700, in the form of Le Métayer, Massoni & Saurel 2004, Int. J. Therm. Sci. 43:265,
    /// eq. 1): a liquid or solid under shock, e.g. water with γ = 4.4, p∞ = 6 × 10⁸ Pa.
    StiffenedGas {
        /// γ.
        gamma: Real,
        /// The stiffness p∞ in Pa (≥ 0; 0 is the ideal gas).
        stiffness: Real,
    },
}

impl EosKind {
    /// The gas law of a gas kind, `None` for a barotropic one (Tait, linear).
    pub fn gas_law(&self) -> Option<GasLaw> {
        match *self {
            Self::Tait { .. } | Self::Linear => None,
            Self::IdealGas { gamma } => Some(GasLaw {
                gamma,
                stiffness: 0.0,
            }),
            Self::StiffenedGas { gamma, stiffness } => Some(GasLaw { gamma, stiffness }),
        }
    }
}

/// The pressure of a gas from its density and specific internal energy,
///
/// p = (γ − 1) ρ e − γ p∞,  c² = γ (p + p∞)/ρ,
///
/// the stiffened gas of Harlow & Amsden (1971) as written by Le Métayer et al. (2004, eqs. 1
/// and 4); p∞ = 0 is the ideal gas. Its isentropes are (p + p∞) ∝ ρ^γ: Tait's equation with
/// B = p₀ + p∞ is the isentrope through (ρ₀, p₀).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasLaw {
    /// γ.
    pub gamma: Real,
    /// p∞ in Pa.
    pub stiffness: Real,
}

impl GasLaw {
    /// p(ρ, e) = (γ − 1) ρ e − γ p∞.
    #[inline(always)]
    pub fn pressure(&self, density: Real, energy: Real) -> Real {
        (self.gamma - 1.0) * density * energy - self.gamma * self.stiffness
    }

    /// e(ρ, p) = (p + γ p∞) / ((γ − 1) ρ), the inverse of [`GasLaw::pressure`].
    #[inline]
    pub fn energy(&self, density: Real, pressure: Real) -> Real {
        (pressure + self.gamma * self.stiffness) / ((self.gamma - 1.0) * density)
    }

    /// c(ρ, p) = √(γ (p + p∞)/ρ) (0 where p + p∞ < 0, a state no gas reaches).
    #[inline(always)]
    pub fn sound_speed(&self, density: Real, pressure: Real) -> Real {
        (self.gamma * (pressure + self.stiffness) / density)
            .max(0.0)
            .sqrt()
    }
}

/// An equation of state with its reference density, sound speed and background pressure.
///
/// For a gas kind, p(ρ), ρ(p) and c(ρ) are those of the isentrope through the reference state
/// (ρ₀, p_b), the Tait form with γ and c₀² = γ (p_b + p∞)/ρ₀ ([`GasLaw`]), for what needs a
/// barotropic relation (a hydrostatic start, the density of a wall from its pressure); the
/// gas's own pressure comes from [`GasLaw::pressure`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquationOfState {
    /// The form.
    pub kind: EosKind,
    /// Reference (rest) density ρ₀.
    pub rest_density: Real,
    /// Reference sound speed c₀.
    pub sound_speed: Real,
    /// Background pressure p_b added to the form, p = p_form(ρ) + p_b (Morris et al. 1997,
    /// eq. 10, their p₀). For a gas kind, the pressure of the reference state (ρ₀, p_b). A constant does not change the pressure gradient of the continuum,
    /// but it keeps the pressure positive in confined flows with suction (e.g. a vortex), where
    /// negative pressure makes SPH particles clump (the tensile instability, Swegle et al.
    /// 1995). 0 for free-surface flows: p_b would pull the surface inwards.
    pub background_pressure: Real,
}

impl EquationOfState {
    /// Pressure p(ρ).
    #[inline]
    pub fn pressure(&self, density: Real) -> Real {
        let c2 = self.sound_speed * self.sound_speed;
        match self.kind {
            EosKind::Tait { gamma }
            | EosKind::IdealGas { gamma }
            | EosKind::StiffenedGas { gamma, .. } => {
                let b = self.rest_density * c2 / gamma;
                let ratio = density / self.rest_density;
                // γ = 7 (water) by multiplication: 3× faster than powf and exact to round-off.
                let power = if gamma == 7.0 {
                    let r2 = ratio * ratio;
                    r2 * r2 * r2 * ratio
                } else {
                    ratio.powf(gamma)
                };
                b * (power - 1.0) + self.background_pressure
            }
            EosKind::Linear => c2 * (density - self.rest_density) + self.background_pressure,
        }
    }

    /// Density ρ(p), the inverse of [`EquationOfState::pressure`]. For Tait, pressures below
    /// p_b − B (which no density reaches) give ρ = 0.
    #[inline]
    pub fn density(&self, pressure: Real) -> Real {
        let c2 = self.sound_speed * self.sound_speed;
        let pressure = pressure - self.background_pressure;
        match self.kind {
            EosKind::Tait { gamma }
            | EosKind::IdealGas { gamma }
            | EosKind::StiffenedGas { gamma, .. } => {
                let b = self.rest_density * c2 / gamma;
                self.rest_density * (pressure / b + 1.0).max(0.0).powf(1.0 / gamma)
            }
            EosKind::Linear => self.rest_density + pressure / c2,
        }
    }

    /// The local sound speed c(ρ) = √(dp/dρ).
    #[inline]
    pub fn local_sound_speed(&self, density: Real) -> Real {
        match self.kind {
            EosKind::Tait { gamma }
            | EosKind::IdealGas { gamma }
            | EosKind::StiffenedGas { gamma, .. } => {
                self.sound_speed * (density / self.rest_density).powf(0.5 * (gamma - 1.0))
            }
            EosKind::Linear => self.sound_speed,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn gas_law_inverse_sound_speed_and_isentrope() {
        for law in [
            GasLaw {
                gamma: 1.4,
                stiffness: 0.0,
            },
            GasLaw {
                gamma: 4.4,
                stiffness: 6e8,
            },
        ] {
            let (rho, p) = (1.3, 2.5e5);
            let e = law.energy(rho, p);
            assert_relative_eq!(law.pressure(rho, e), p, max_relative = 1e-12);
            // c² = (∂p/∂ρ) at constant entropy = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ (de = p/ρ² dρ).
            let slope = (law.pressure(rho * (1.0 + 1e-6), e) - law.pressure(rho * (1.0 - 1e-6), e))
                / (2e-6 * rho)
                + p / (rho * rho) * (law.gamma - 1.0) * rho;
            assert_relative_eq!(law.sound_speed(rho, p).powi(2), slope, max_relative = 1e-6);
            // The Tait form through (ρ₀, p₀) is the isentrope (p + p∞) ∝ ρ^γ.
            let kind = EosKind::StiffenedGas {
                gamma: law.gamma,
                stiffness: law.stiffness,
            };
            let eos = EquationOfState {
                kind,
                rest_density: rho,
                sound_speed: law.sound_speed(rho, p),
                background_pressure: p,
            };
            let rho2 = 1.7 * rho;
            assert_relative_eq!(
                eos.pressure(rho2) + law.stiffness,
                (p + law.stiffness) * 1.7_f64.powf(law.gamma),
                max_relative = 1e-12
            );
        }
    }

    #[test]
    fn inverse_and_sound_speed() {
        for (kind, background_pressure) in [
            (EosKind::Tait { gamma: 7.0 }, 0.0),
            (EosKind::Linear, 0.0),
            (EosKind::Tait { gamma: 7.0 }, 500.0),
        ] {
            let eos = EquationOfState {
                kind,
                rest_density: 1000.0,
                sound_speed: 50.0,
                background_pressure,
            };
            assert_eq!(eos.pressure(1000.0), background_pressure);
            for rho in [990.0, 1000.5, 1012.0] {
                assert_relative_eq!(eos.density(eos.pressure(rho)), rho, max_relative = 1e-12);
                // c² = dp/dρ by central difference
                let slope = (eos.pressure(rho + 1e-4) - eos.pressure(rho - 1e-4)) / 2e-4;
                assert_relative_eq!(
                    eos.local_sound_speed(rho).powi(2),
                    slope,
                    max_relative = 1e-6
                );
            }
        }
    }
}
