//! Gas dynamics in WCSPH: the internal-energy equation and the artificial viscosity of a gas,
//! whose sound speed varies from particle to particle.
//!
//! With the pressure p = p(ρ, e) of a [`GasLaw`], the particles carry their specific internal
//! energy e. A gas's particles keep the lattice spacing, so a denser gas has heavier
//! particles, and the equations take the particle-volume form of Hu & Adams (2006,
//! J. Comput. Phys. 213:844, §2), which stays consistent across a jump of density (a
//! contact): with V_i = m_i/ρ_i,
//!
//! dρ_i/dt = m_i Σ_j v_ij·∇_i W_ij,
//! dv_i/dt = −(1/m_i) Σ_j (p_i V_i² + p_j V_j²) ∇_i W_ij − Σ_j m_j Π_ij ∇_i W_ij,
//! de_i/dt = (p_i V_i²/m_i) Σ_j v_ij·∇_i W_ij + ½ Σ_j m_j Π_ij v_ij·∇_i W_ij,
//!
//! the last the thermal energy equation that goes with the momentum equation (Monaghan 1992,
//! Annu. Rev. Astron. Astrophys. 30:543, §2.5, for equal masses): the reversible work of the
//! pressure and the heating by the artificial viscosity Π_ij. The total energy
//! Σ_i m_i (½ v_i² + e_i) is conserved to round-off by every pair. (With equal masses the
//! form is the standard m_j (p_i/ρ_i² + p_j/ρ_j²); the standard continuity equation
//! Σ_j m_j v_ij·∇W drives a light particle beside heavy ones to a negative density within a
//! few steps of a shock tube's start.)

use geosph_core::{Real, Vector};
use geosph_sph::{ConfigError, EosKind, GasLaw, Pair};

use crate::config::{DensityConfig, DiffusionConfig, ViscosityConfig, WcsphConfig};

/// The energy equation of the WCSPH pair loop, which is monomorphised over it: [`Barotropic`]
/// (a liquid whose pressure depends on its density alone) compiles it away.
pub trait EnergyEquation<const D: usize>: Copy + Send + Sync {
    /// Whether the particles integrate an internal energy.
    const ON: bool;

    /// The factor w of the pressure term −w ∇_i W_ij of dv_i/dt from the particles' masses and
    /// pressure terms P (the pair loop's `pressure_term`): m_j (P_i + P_j) with P = p/ρ² for a
    /// liquid, (P_i + P_j)/m_i with P = p V² for a gas.
    fn pressure_weight(mass_i: Real, mass_j: Real, term_i: Real, term_j: Real) -> Real;

    /// The mass of dρ_i/dt = Σ_j m v_ij·∇_i W_ij: m_j for a liquid, m_i for a gas.
    fn continuity_mass(mass_i: Real, mass_j: Real) -> Real;

    /// The viscous contribution of neighbour j to dv_i/dt and its heating of particle i,
    /// ½ m_j Π_ij v_ij·∇_i W_ij.
    fn viscous(&self, i: usize, j: usize, pair: &Pair<D>) -> (Vector<D>, Real);
}

/// No energy equation.
#[derive(Clone, Copy, Debug, Default)]
pub struct Barotropic;

impl<const D: usize> EnergyEquation<D> for Barotropic {
    const ON: bool = false;

    #[inline(always)]
    fn pressure_weight(_mass_i: Real, mass_j: Real, term_i: Real, term_j: Real) -> Real {
        mass_j * (term_i + term_j)
    }

    #[inline(always)]
    fn continuity_mass(_mass_i: Real, mass_j: Real) -> Real {
        mass_j
    }

    #[inline(always)]
    fn viscous(&self, _i: usize, _j: usize, _pair: &Pair<D>) -> (Vector<D>, Real) {
        (Vector::zeros(), 0.0)
    }
}

/// The artificial viscosity of a gas (Monaghan 1992, eq. 4.1) with the mean sound speed of
/// the pair, c̄_ij = (c_i + c_j)/2 (Monaghan & Gingold 1983, J. Comput. Phys. 52:374),
///
/// Π_ij = (−α c̄_ij μ_ij + β μ_ij²)/ρ̄_ij for v_ij·x_ij < 0 (else 0),
/// μ_ij = h v_ij·x_ij/(|x_ij|² + 0.01 h²),
///
/// and the heating it does, both halves of the pair's dissipated work going to its two
/// particles.
#[derive(Clone, Copy, Debug)]
pub struct GasViscosity<'a> {
    /// c_i of every particle (owned and halo), from [`GasLaw::sound_speed`].
    pub sound_speed: &'a [Real],
    /// α (linear term; 1 for shocks).
    pub alpha: Real,
    /// β (quadratic term, against interpenetration in strong shocks; 2 for shocks).
    pub beta: Real,
    /// h.
    pub smoothing_length: Real,
}

impl<const D: usize> EnergyEquation<D> for GasViscosity<'_> {
    const ON: bool = true;

    #[inline(always)]
    fn pressure_weight(mass_i: Real, _mass_j: Real, term_i: Real, term_j: Real) -> Real {
        (term_i + term_j) / mass_i
    }

    #[inline(always)]
    fn continuity_mass(mass_i: Real, _mass_j: Real) -> Real {
        mass_i
    }

    #[inline(always)]
    fn viscous(&self, i: usize, j: usize, pair: &Pair<D>) -> (Vector<D>, Real) {
        let approach = pair.v_ij.dot(&pair.r_ij).min(0.0);
        let mu = self.smoothing_length * approach * pair.inv_r2_eta2;
        let c_mean = 0.5 * (self.sound_speed[i] + self.sound_speed[j]);
        let pi =
            (-self.alpha * c_mean * mu + self.beta * mu * mu) / (0.5 * (pair.rho_i + pair.rho_j));
        let weighted = pair.mass_j * pi;
        (
            pair.grad * -weighted,
            0.5 * weighted * pair.v_ij.dot(&pair.grad),
        )
    }
}

/// A gas in WCSPH: its law and the coefficients of its artificial viscosity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasDynamics {
    /// p(ρ, e).
    pub law: GasLaw,
    /// α of [`GasViscosity`].
    pub alpha: Real,
    /// β of [`GasViscosity`].
    pub beta: Real,
}

impl GasDynamics {
    /// The gas of `config`, `None` when its equation of state is a liquid's. Its artificial
    /// viscosity takes α and β of `viscosity: Artificial` (none: α = β = 0).
    pub fn of(config: &WcsphConfig) -> Option<Self> {
        let law = config.equation_of_state.gas_law()?;
        let (alpha, beta) = match config.viscosity {
            ViscosityConfig::Artificial { alpha, beta } => (alpha, beta),
            ViscosityConfig::None | ViscosityConfig::Laminar { .. } => (0.0, 0.0),
        };
        Some(Self { law, alpha, beta })
    }
}

/// Checks what a gas asks of a WCSPH configuration (fields relative to the solver block):
/// γ in (1, 10], p∞ ≥ 0, and none of the terms written for a barotropic liquid (density
/// diffusion, shifting, XSPH, SPS, laminar viscosity, a pressure clamp, summation density)
/// nor a sound speed or background pressure, which the gas's state sets.
pub fn validate(config: &WcsphConfig) -> Result<(), ConfigError> {
    let (gamma, stiffness) = match config.equation_of_state {
        EosKind::Tait { .. } | EosKind::Linear => return Ok(()),
        EosKind::IdealGas { gamma } => (gamma, 0.0),
        EosKind::StiffenedGas { gamma, stiffness } => (gamma, stiffness),
    };
    if !(gamma.is_finite() && gamma > 1.0 && gamma <= 10.0) {
        return Err(ConfigError::new(
            "equation_of_state.gamma",
            format!("must lie in (1, 10] for a gas (1.4 for air), got {gamma}"),
        ));
    }
    if !(stiffness.is_finite() && stiffness >= 0.0) {
        return Err(ConfigError::new(
            "equation_of_state.stiffness",
            format!("must be a finite number ≥ 0 Pa, got {stiffness}"),
        ));
    }
    let refuse = |field: &str, what: &str| {
        Err(ConfigError::new(
            field,
            format!("must be left out with a gas equation of state: {what}"),
        ))
    };
    if config.diffusion != DiffusionConfig::None {
        return refuse(
            "diffusion",
            "δ-SPH's density diffusion is written for a barotropic liquid (set `diffusion: None`)",
        );
    }
    if matches!(config.viscosity, ViscosityConfig::Laminar { .. }) {
        return refuse(
            "viscosity",
            "a gas takes `Artificial(alpha, beta)` (1 and 2 for shocks) or `None`",
        );
    }
    if config.shifting.is_some() {
        return refuse(
            "shifting",
            "shifting moves particles without carrying their energy",
        );
    }
    if config.xsph != 0.0 {
        return refuse(
            "xsph",
            "XSPH moves particles off their velocity, which breaks the energy balance",
        );
    }
    if config.clamp_negative_pressure {
        return refuse(
            "clamp_negative_pressure",
            "a gas's pressure follows from its energy (a negative one is a blow-up)",
        );
    }
    if config.sps.is_some() {
        return refuse(
            "sps",
            "SPS turbulence is not coupled to the energy equation",
        );
    }
    if config.surface_tension.is_some() {
        return refuse(
            "surface_tension",
            "surface tension acts between two phases of a liquid",
        );
    }
    if config.density != DensityConfig::Continuity || config.shepard_every > 0 {
        return Err(ConfigError::new(
            if config.shepard_every > 0 {
                "shepard_every"
            } else {
                "density"
            },
            "a gas integrates its density (`density: Continuity`, `shepard_every: 0`): a kernel \
             sum of unequal masses smears the jump of density at a contact",
        ));
    }
    if config.sound_speed.is_some() {
        return refuse(
            "sound_speed",
            "a gas's sound speed follows from its state, c² = γ (p + p∞)/ρ",
        );
    }
    if config.background_pressure != 0.0 {
        return refuse(
            "background_pressure",
            "a gas's pressure is absolute (set its initial state with `fluid.pressure`)",
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pair's viscous force on i and on j is equal and opposite and their heating is the
    /// work it dissipates: m_i m_j (a_ij·v_i + a_ji·v_j) + m_i ė_i + m_j ė_j = 0.
    #[test]
    fn viscous_work_becomes_heat() {
        let sound_speed = [1.2, 0.9];
        let term = GasViscosity {
            sound_speed: &sound_speed,
            alpha: 1.0,
            beta: 2.0,
            smoothing_length: 0.02,
        };
        let (m_i, m_j) = (2e-4, 0.5e-4);
        let (rho_i, rho_j) = (1.0, 0.25);
        let r_ij = Vector::<2>::new(0.012, -0.004);
        let grad = r_ij * -310.0;
        let (v_i, v_j) = (Vector::<2>::new(-0.7, 0.1), Vector::<2>::new(0.2, 0.05));
        let eta2 = 0.01 * 0.02 * 0.02;
        let on_i = Pair::new(
            r_ij,
            r_ij.norm_squared(),
            eta2,
            grad,
            v_i - v_j,
            rho_i,
            rho_j,
            m_j,
        );
        let on_j = Pair::new(
            -r_ij,
            r_ij.norm_squared(),
            eta2,
            -grad,
            v_j - v_i,
            rho_j,
            rho_i,
            m_i,
        );
        let (a_i, heat_i) = EnergyEquation::<2>::viscous(&term, 0, 1, &on_i);
        let (a_j, heat_j) = EnergyEquation::<2>::viscous(&term, 1, 0, &on_j);
        assert!(heat_i > 0.0 && heat_j > 0.0, "an approaching pair heats");
        let momentum = a_i * m_i + a_j * m_j;
        assert!(momentum.norm() < 1e-15 * (a_i * m_i).norm());
        let power = m_i * a_i.dot(&v_i) + m_j * a_j.dot(&v_j) + m_i * heat_i + m_j * heat_j;
        assert!(
            power.abs() < 1e-12 * (m_i * heat_i),
            "power balance {power}"
        );
        // A receding pair neither brakes nor heats.
        let apart = Pair::new(
            r_ij,
            r_ij.norm_squared(),
            eta2,
            grad,
            v_j - v_i,
            rho_i,
            rho_j,
            m_j,
        );
        assert_eq!(EnergyEquation::<2>::viscous(&term, 0, 1, &apart).1, 0.0);
    }
}
