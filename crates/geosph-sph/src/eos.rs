//! Equations of state of weakly compressible SPH, also the initial density ρ(p) of a liquid
//! that starts under pressure (hydrostatic, or an initial pressure field).

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
}

/// An equation of state with its reference density, sound speed and background pressure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquationOfState {
    /// The form.
    pub kind: EosKind,
    /// Reference (rest) density ρ₀.
    pub rest_density: Real,
    /// Reference sound speed c₀.
    pub sound_speed: Real,
    /// Background pressure p_b added to the form, p = p_form(ρ) + p_b (Morris et al. 1997,
    /// eq. 10, their p₀). A constant does not change the pressure gradient of the continuum,
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
            EosKind::Tait { gamma } => {
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
            EosKind::Tait { gamma } => {
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
            EosKind::Tait { gamma } => {
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
