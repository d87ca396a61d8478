//! Sub-particle-scale (SPS) turbulence: the Smagorinsky eddy viscosity with Favre averaging
//! that Dalrymple & Rogers (2006, Coastal Eng. 53:141, eqs. 11–14) brought into weakly
//! compressible SPH after Gotoh et al. (2001), beside the laminar or artificial viscous term.
//!
//! With S the strain rate, the symmetric part of the velocity gradient, and
//! |S| = √(2 S:S), the Favre-filtered SPS stress per unit density is
//!
//! τ/ρ = 2 ν_t (S − ⅓ tr S 1) − ⅔ C_I Δ² |S|² 1,   ν_t = (C_s Δ)² |S|,
//!
//! with the Smagorinsky constant C_s (0.12), the isotropic (Yoshizawa) constant C_I (0.0066)
//! and the filter width Δ, the particle spacing. Its divergence joins the momentum equation in
//! the symmetric form of the pressure term (Dalrymple & Rogers 2006, eq. 14):
//!
//! dv_i/dt ∋ Σ_j m_j (τ_i/ρ_i² + τ_j/ρ_j²)·∇_i W_ij.
//!
//! Per particle, ∇v_i = c Σ_j V_j (v_j − v_i) ⊗ ∇_i W_ij over the fluid and wall neighbours
//! (a wall shows the velocity its viscous term sees, ũ_w), with c the lattice gradient
//! correction of the pressure term, so that a linear velocity field gives its exact gradient
//! inside the initial lattice. A wall particle carries the stress of the fluid particle it
//! faces (τ_w/ρ_w² = τ_i/ρ_i²): a uniform stress then exerts no force next to a wall either.
//! A plane (2D) flow is a 3D flow without its third component, so the trace is divided by 3.
//! `docs/turbulence.md` has the derivation and the checks.

use geosph_boundary::WallParticles;
use geosph_core::{Matrix, Real, Vector};
use geosph_kernels::Kernel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::config_error::{ConfigError, in_range};
use crate::lists::PairLists;

/// The coefficients of the SPS model (the scene's `sps: Some(())` takes the defaults of
/// Dalrymple & Rogers 2006).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SpsConfig {
    /// Smagorinsky constant C_s (default 0.12).
    pub smagorinsky: Real,
    /// Isotropic constant C_I of the SPS turbulent kinetic energy k = C_I Δ² |S|²
    /// (default 0.0066).
    pub isotropic: Real,
}

impl Default for SpsConfig {
    fn default() -> Self {
        Self {
            smagorinsky: 0.12,
            isotropic: 0.0066,
        }
    }
}

impl SpsConfig {
    /// Checks the coefficients: C_s in [0, 2] (0.1–0.2 is the usual range; larger values
    /// are for verification), C_I in [0, 0.1]; `field` is the block's name in the scene.
    pub fn validate(&self, field: &str) -> Result<(), ConfigError> {
        in_range(&format!("{field}.smagorinsky"), self.smagorinsky, 0.0, 2.0)?;
        in_range(&format!("{field}.isotropic"), self.isotropic, 0.0, 0.1)
    }

    /// τ/ρ and ν_t of the velocity gradient `gradient` (∂v_a/∂x_b in row a, column b) with
    /// the filter width `width` Δ.
    pub fn stress_per_density<const D: usize>(
        &self,
        width: Real,
        gradient: &Matrix<D>,
    ) -> (Matrix<D>, Real) {
        let strain = (gradient + gradient.transpose()) * 0.5;
        let magnitude2 = 2.0 * strain.norm_squared();
        let width2 = width * width;
        let eddy_viscosity = self.smagorinsky * self.smagorinsky * width2 * magnitude2.sqrt();
        let isotropic = -2.0 / 3.0 * self.isotropic * width2 * magnitude2
            - 2.0 / 3.0 * eddy_viscosity * strain.trace();
        let stress = strain * (2.0 * eddy_viscosity) + Matrix::<D>::identity() * isotropic;
        (stress, eddy_viscosity)
    }
}

/// The SPS stress of every particle, computed once per rate evaluation.
#[derive(Clone, Debug)]
pub struct SubParticleStress<const D: usize> {
    /// The model's coefficients.
    pub config: SpsConfig,
    /// The filter width Δ: the particle spacing.
    pub spacing: Real,
    /// c τ_i/ρ_i² of every particle, c the lattice gradient correction.
    stress_over_rho2: Vec<Matrix<D>>,
    /// The halo's stresses as they travel between ranks (scratch of a distributed run).
    records: Vec<Real>,
    /// The largest ν_t of the particles this rank owned at the last update.
    max_eddy_viscosity: Real,
}

impl<const D: usize> SubParticleStress<D> {
    /// The model with `config` on particles of spacing `spacing`.
    pub fn new(config: SpsConfig, spacing: Real) -> Self {
        Self {
            config,
            spacing,
            stress_over_rho2: Vec::new(),
            records: Vec::new(),
            max_eddy_viscosity: 0.0,
        }
    }

    /// The stress of every particle from its velocity gradient over the fluid and wall
    /// neighbours of `lists`; `correction` is the lattice gradient correction c. The largest
    /// ν_t is taken over the particles the rank owns (the first [`PairLists::owned`]); in a
    /// distributed run the halo's stresses are then refreshed from their owners (collective).
    #[allow(clippy::too_many_arguments)]
    pub fn update<K: Kernel<D>>(
        &mut self,
        kernel: &K,
        lists: &PairLists<D>,
        position: &[Vector<D>],
        velocity: &[Vector<D>],
        volume: &[Real],
        density: &[Real],
        walls: &WallParticles<D>,
        correction: Real,
    ) {
        let n = position.len();
        self.stress_over_rho2.resize(n, Matrix::zeros());
        let (config, spacing) = (self.config, self.spacing);
        let owned = lists.owned(n);
        self.max_eddy_viscosity = self
            .stress_over_rho2
            .par_iter_mut()
            .enumerate()
            .map(|(i, stress_i)| {
                let v_i = velocity[i];
                let mut gradient = Matrix::<D>::zeros();
                lists.for_each_neighbour(kernel, position, i, |pair| {
                    let j = pair.index;
                    gradient += (velocity[j] - v_i) * (pair.grad * volume[j]).transpose();
                });
                lists.for_each_wall(kernel, position, &walls.position, i, |pair| {
                    let w = pair.index;
                    let weighted = pair.grad * walls.volume[w];
                    gradient += (walls.viscous_velocity[w] - v_i) * weighted.transpose();
                });
                let (stress, nu) = config.stress_per_density(spacing, &(gradient * correction));
                *stress_i = stress * (correction / density[i]);
                if i < owned { nu } else { 0.0 }
            })
            .reduce(|| 0.0, Real::max);
        if lists.distribution().is_some() {
            self.refresh_halo(lists);
        }
    }

    /// The halo's stresses from their owners: a halo particle's gradient reads the walls'
    /// ũ_w, which a rank extrapolates from its own particles only, so next to a wall the
    /// halo's own result is not the owner's (docs/turbulence.md).
    fn refresh_halo(&mut self, lists: &PairLists<D>) {
        let width = D * D;
        self.records.clear();
        for stress in &self.stress_over_rho2 {
            self.records.extend_from_slice(stress.as_slice());
        }
        lists.exchange_halo_records(&mut self.records, width);
        let owned = lists.owned(self.stress_over_rho2.len());
        for (i, stress) in self.stress_over_rho2.iter_mut().enumerate().skip(owned) {
            stress.copy_from_slice(&self.records[i * width..(i + 1) * width]);
        }
    }

    /// The largest eddy viscosity ν_t of the particles this rank owned at the last
    /// [`Self::update`] (0 before the first), for the viscous limit of the next time step.
    pub fn max_eddy_viscosity(&self) -> Real {
        self.max_eddy_viscosity
    }

    /// Sets the largest ν_t: at a restart, the one of the checkpoint (the largest over the
    /// ranks, so that the next step's limit is the same on any number of ranks).
    pub fn restore_max_eddy_viscosity(&mut self, value: Real) {
        self.max_eddy_viscosity = value;
    }

    /// The term the pair loop adds, reading the stresses of the last [`Self::update`].
    pub fn term(&self) -> SpsTerm<'_, D> {
        SpsTerm {
            stress_over_rho2: &self.stress_over_rho2,
        }
    }
}

/// Whether a pair loop adds a sub-particle stress: [`NoSps`] (nothing in the loop) or an
/// [`SpsTerm`]. The pair loop is generic over it, so a scene without SPS pays nothing.
pub trait TurbulenceTerm<const D: usize>: Copy + Send + Sync {
    /// Whether the term acts at all.
    const ON: bool;

    /// The contribution of fluid neighbour j (mass `mass_j`, ∇_i W_ij = `grad`) to dv_i/dt.
    fn acceleration(&self, i: usize, j: usize, mass_j: Real, grad: &Vector<D>) -> Vector<D>;

    /// The contribution of a wall neighbour of mass `mass_w` to dv_i/dt.
    fn wall_acceleration(&self, i: usize, mass_w: Real, grad: &Vector<D>) -> Vector<D>;
}

/// No SPS stress.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoSps;

impl<const D: usize> TurbulenceTerm<D> for NoSps {
    const ON: bool = false;

    #[inline(always)]
    fn acceleration(&self, _: usize, _: usize, _: Real, _: &Vector<D>) -> Vector<D> {
        Vector::zeros()
    }

    #[inline(always)]
    fn wall_acceleration(&self, _: usize, _: Real, _: &Vector<D>) -> Vector<D> {
        Vector::zeros()
    }
}

/// The SPS stress of the last [`SubParticleStress::update`] in the pair loop.
#[derive(Clone, Copy, Debug)]
pub struct SpsTerm<'a, const D: usize> {
    stress_over_rho2: &'a [Matrix<D>],
}

impl<const D: usize> TurbulenceTerm<D> for SpsTerm<'_, D> {
    const ON: bool = true;

    #[inline(always)]
    fn acceleration(&self, i: usize, j: usize, mass_j: Real, grad: &Vector<D>) -> Vector<D> {
        (self.stress_over_rho2[i] + self.stress_over_rho2[j]) * grad * mass_j
    }

    #[inline(always)]
    fn wall_acceleration(&self, i: usize, mass_w: Real, grad: &Vector<D>) -> Vector<D> {
        self.stress_over_rho2[i] * grad * (2.0 * mass_w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A simple shear u = γ y: S_xy = γ/2, |S| = γ, ν_t = (C_s Δ)² γ, τ_xy/ρ = ν_t γ, and
    /// the isotropic part −⅔ C_I Δ² γ² on the diagonal (no trace: the flow is isochoric).
    #[test]
    fn simple_shear_gives_the_smagorinsky_stress() {
        let model = SpsConfig::default();
        let gamma = 3.0;
        let gradient = Matrix::<2>::new(0.0, gamma, 0.0, 0.0);
        let (stress, nu) = model.stress_per_density(0.01, &gradient);
        let expected_nu = (0.12 * 0.01_f64).powi(2) * gamma;
        approx::assert_relative_eq!(nu, expected_nu, max_relative = 1e-14);
        approx::assert_relative_eq!(stress[(0, 1)], expected_nu * gamma, max_relative = 1e-14);
        approx::assert_relative_eq!(stress[(1, 0)], expected_nu * gamma, max_relative = 1e-14);
        let k = 2.0 / 3.0 * 0.0066 * 1e-4 * gamma * gamma;
        approx::assert_relative_eq!(stress[(0, 0)], -k, max_relative = 1e-14);
        approx::assert_relative_eq!(stress[(1, 1)], -k, max_relative = 1e-14);
    }

    /// A rigid rotation strains nothing: no stress, no eddy viscosity.
    #[test]
    fn a_rigid_rotation_has_no_sub_particle_stress() {
        let model = SpsConfig::default();
        let omega = Vector::<3>::new(0.3, -1.0, 2.0);
        let gradient = omega.cross_matrix();
        let (stress, nu) = model.stress_per_density(0.02, &gradient);
        assert_eq!(nu, 0.0);
        assert_eq!(stress, Matrix::<3>::zeros());
    }

    /// A uniform expansion v = e x: S = e 1, |S|² = 2 D e², the deviatoric part vanishes and
    /// only the isotropic part remains: −⅔ C_I Δ² |S|² on the diagonal.
    #[test]
    fn a_uniform_expansion_has_only_the_isotropic_part() {
        let model = SpsConfig::default();
        let (stress, nu) = model.stress_per_density(0.02, &(Matrix::<3>::identity() * 0.5));
        approx::assert_relative_eq!(nu, 0.0144 * 4e-4 * (1.5_f64).sqrt(), max_relative = 1e-14);
        let expected = -2.0 / 3.0 * 0.0066 * 4e-4 * 1.5;
        for a in 0..3 {
            for b in 0..3 {
                let value = if a == b { expected } else { 0.0 };
                approx::assert_relative_eq!(stress[(a, b)], value, epsilon = 1e-18);
            }
        }
    }

    #[test]
    fn coefficients_out_of_range_name_their_field() {
        let config = SpsConfig {
            smagorinsky: -0.1,
            ..Default::default()
        };
        let error = config.validate("sps").unwrap_err();
        assert_eq!(error.field, "sps.smagorinsky");
        assert!(error.message.contains("[0, 2]"), "{error}");
    }
}
