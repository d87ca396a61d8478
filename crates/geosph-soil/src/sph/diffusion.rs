//! Diffusion of the mean stress against the particle-scale (checkerboard) noise of the stress
//! field, with the density following it.

use geosph_core::{Real, Vector};

/// A diffusive term in the mean stress p = −tr σ/3, after the stress diffusion of Feng,
/// Fourtakas, Rogers & Lombardi (2021, Comput. Geotech. 138:104356), itself the analogue for σ
/// of the density diffusion of δ-SPH (Molteni & Colagrossi 2009), with the lithostatic part of
/// the difference taken out (as Fourtakas et al. 2019 take out the hydrostatic part):
///
/// ```text
/// (dp_i/dt)_diff = 2 δ h c Σ_j V_j [(p_i − p_j) − (p^L_i − p^L_j)] (r_ij·∇_i W_ij)/(r_ij² + 0.01 h²)
/// p^L_i − p^L_j = ρ₀ (g·r_ij) (1 + 2K₀)/3            (soil j: σ^L = −ρ₀ g d (ĝĝᵀ + K₀(1 − ĝĝᵀ)))
/// p^L_i − p^L_w = ρ₀ (g·r_iw)/3 + 2K₀ρ₀ g·(x_i − x̄_w)/3   (wall j = w)
/// σ_i ← σ_i − Δt (dp_i/dt)_diff 1,   ρ_i ← ρ_i (1 + Δt (dp_i/dt)_diff / K)
/// ```
///
/// c is the P-wave speed, K the bulk modulus; j runs over soil and wall particles (a wall
/// particle with the mean of the stress σ_w it shows the soil). σ_w is the kernel average
/// of the soil around w with σ_v extrapolated along g to x_w
/// ([`WallStress::Extrapolated`](crate::sph::config::WallStress)), so of a lithostatic
/// field it holds σ_v at x_w and σ_h at x̄_w, the kernel-weighted centre of that soil; with
/// [`WallStress::Shepard`](crate::sph::config::WallStress) (no extrapolation) both are at
/// x̄_w and the wall term is (1 + 2K₀)ρ₀ g·(x_i − x̄_w)/3. The sum approximates δ h c ∇²p (Brookshaw
/// 1985): a checkerboard decays in about dx²/(δ h c), a smooth field changes by O(h).
///
/// Why the mean stress only, and why the density follows (`docs/soil.md`, "Stress noise"): a
/// checkerboard exerts no force in the symmetric momentum equation, so nothing else removes it,
/// and in the collapse it sits in p. Diffusing σ while ρ stays lets a particle lose the
/// pressure its compression earned, so it compresses further (the collapse blew up at 20 %
/// compression on the floor); moving ρ with p by the bulk modulus keeps the two consistent.
/// Diffusing the deviator as well lets a resting pile's shear stresses relax, so the pile
/// creeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanStressDiffusion<const D: usize> {
    /// 2 δ h c.
    coefficient: Real,
    /// 0.01 h².
    softening: Real,
    /// g.
    gravity: Vector<D>,
    /// ρ₀ (1 + 2K₀)/3: the lithostatic difference of p between soil particles per unit g·r_ij.
    soil_lithostatic: Real,
    /// ρ₀/3 towards a wall particle whose σ_v is extrapolated to it (0 without extrapolation).
    wall_vertical: Real,
    /// The rest of the wall term, about the soil's centre x̄_w.
    wall_centre: Real,
    /// 1/K.
    compliance: Real,
}

impl<const D: usize> MeanStressDiffusion<D> {
    /// The term with coefficient `delta` (δ; Feng et al. 2021 use 0.1), smoothing length
    /// `smoothing_length`, wave speed `wave_speed`, bulk modulus `bulk_modulus`, and the
    /// lithostatic state of `gravity`, `rest_density` and lateral ratio `lateral_ratio`
    /// (K₀ = σ_h/σ_v); `extrapolated_walls` when the wall stress is extrapolated along g.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        delta: Real,
        smoothing_length: Real,
        wave_speed: Real,
        bulk_modulus: Real,
        gravity: Vector<D>,
        rest_density: Real,
        lateral_ratio: Real,
        extrapolated_walls: bool,
    ) -> Self {
        let vertical = rest_density / 3.0;
        let lateral = 2.0 * lateral_ratio * rest_density / 3.0;
        Self {
            coefficient: 2.0 * delta * smoothing_length * wave_speed,
            softening: 0.01 * smoothing_length * smoothing_length,
            gravity,
            soil_lithostatic: vertical + lateral,
            wall_vertical: if extrapolated_walls { vertical } else { 0.0 },
            wall_centre: if extrapolated_walls {
                lateral
            } else {
                vertical + lateral
            },
            compliance: 1.0 / bulk_modulus,
        }
    }

    /// A soil pair's term of the sum, without 2 δ h c:
    /// V_j [(p_i − p_j) − (p^L_i − p^L_j)] (r_ij·∇_i W_ij)/(r² + 0.01 h²).
    #[inline(always)]
    pub fn pair(
        &self,
        pressure_i: Real,
        pressure_j: Real,
        r_ij: &Vector<D>,
        gradient: &Vector<D>,
        volume_j: Real,
    ) -> Real {
        let difference = pressure_i - pressure_j - self.soil_lithostatic * self.gravity.dot(r_ij);
        self.flux(difference, r_ij, gradient, volume_j)
    }

    /// g·x, the height coordinate the lithostatic terms use (for x̄_w of [`Self::wall_pair`]).
    #[inline(always)]
    pub fn level(&self, x: &Vector<D>) -> Real {
        self.gravity.dot(x)
    }

    /// A wall pair's term, with the mean stress p_w of the wall particle's σ_w and
    /// `centre_offset` = g·(x_i − x̄_w):
    /// V_w [(p_i − p_w) − (p^L_i − p^L_w)] (r_iw·∇_i W_iw)/(r² + 0.01 h²).
    #[inline(always)]
    pub fn wall_pair(
        &self,
        pressure_i: Real,
        pressure_w: Real,
        r_iw: &Vector<D>,
        centre_offset: Real,
        gradient: &Vector<D>,
        volume_w: Real,
    ) -> Real {
        let lithostatic =
            self.wall_vertical * self.gravity.dot(r_iw) + self.wall_centre * centre_offset;
        self.flux(
            pressure_i - pressure_w - lithostatic,
            r_iw,
            gradient,
            volume_w,
        )
    }

    /// V_j Δp (r_ij·∇_i W_ij)/(r² + 0.01 h²), the Brookshaw (1985) form both pair terms share.
    #[inline(always)]
    fn flux(&self, difference: Real, r_ij: &Vector<D>, gradient: &Vector<D>, volume: Real) -> Real {
        difference * volume * r_ij.dot(gradient) / (r_ij.norm_squared() + self.softening)
    }

    /// (dp_i/dt)_diff from the sum of the pair terms.
    #[inline(always)]
    pub fn rate(&self, sum: Real) -> Real {
        sum * self.coefficient
    }

    /// The relative density change Δρ/ρ = Δp/K that goes with a change Δp of the mean stress.
    #[inline(always)]
    pub fn volumetric_strain(&self, pressure_change: Real) -> Real {
        pressure_change * self.compliance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use geosph_kernels::{Kernel, WendlandC2};

    /// (dp/dt)_diff at the origin of a unit square lattice carrying p(x); `below_only` cuts
    /// the lattice at the origin's row (a free surface).
    fn rate_at_origin(
        diffusion: &MeanStressDiffusion<2>,
        pressure: impl Fn(&Vector<2>) -> Real,
        below_only: bool,
    ) -> Real {
        let kernel = WendlandC2::<2>::new(1.3);
        let origin = Vector::<2>::zeros();
        let mut sum = 0.0;
        for a in -4_i32..=4 {
            for b in -4_i32..=4 {
                if (a, b) == (0, 0) || (below_only && b > 0) {
                    continue;
                }
                let x_j = Vector::<2>::new(a as Real, b as Real);
                let r_ij = origin - x_j;
                if r_ij.norm() >= kernel.support_radius() {
                    continue;
                }
                sum += diffusion.pair(
                    pressure(&origin),
                    pressure(&x_j),
                    &r_ij,
                    &kernel.gradient(&r_ij),
                    1.0,
                );
            }
        }
        diffusion.rate(sum)
    }

    #[test]
    fn a_lithostatic_field_does_not_diffuse_even_at_a_free_surface() {
        let (rho, g, k0) = (2000.0, 9.81, 0.5);
        let gravity = Vector::<2>::new(0.0, -g);
        let diffusion = MeanStressDiffusion::<2>::new(0.1, 1.3, 10.0, 1e6, gravity, rho, k0, true);
        // σ_v = −ρ g (H − y), σ_h = K₀ σ_v with H = 0: p = −ρ g y (1 + 2K₀)/3.
        let lithostatic = |x: &Vector<2>| -rho * g * x[1] * (1.0 + 2.0 * k0) / 3.0;
        let full = rate_at_origin(&diffusion, lithostatic, false);
        let surface = rate_at_origin(&diffusion, lithostatic, true);
        assert!(full.abs() < 1e-9 * rho * g, "{full}");
        assert!(surface.abs() < 1e-9 * rho * g, "{surface}");
        // Without the lithostatic part the surface particle would change (the check can fail).
        let plain =
            MeanStressDiffusion::<2>::new(0.1, 1.3, 10.0, 1e6, Vector::zeros(), rho, k0, true);
        assert!(rate_at_origin(&plain, lithostatic, true).abs() > 1e-3 * rho * g);
    }

    /// Next to a floor of dummy particles whose stress is the extrapolated kernel average of the
    /// soil around them (`WallStress::Extrapolated`), a lithostatic field does not diffuse.
    #[test]
    fn a_lithostatic_field_does_not_diffuse_next_to_a_wall() {
        use crate::invariants::mean_pressure;
        use crate::sph::walls::gravity_extrapolation;
        use geosph_core::Tensor3;
        let (rho, g, k0) = (2000.0, 9.81, 0.5);
        let gravity = Vector::<2>::new(0.0, -g);
        let diffusion = MeanStressDiffusion::<2>::new(0.1, 1.3, 10.0, 1e6, gravity, rho, k0, true);
        let kernel = WendlandC2::<2>::new(1.3);
        let radius = kernel.support_radius();
        let lithostatic = |x: &Vector<2>| {
            let v = rho * g * x[1];
            Tensor3::from_diagonal(&Vector::<3>::new(k0 * v, v, k0 * v))
        };
        // Soil on rows y ≥ −1 (the particle at the origin is the second layer), walls below.
        let soil: Vec<Vector<2>> = (-6_i32..=6)
            .flat_map(|a| (-1_i32..=4).map(move |b| Vector::<2>::new(a as Real, b as Real)))
            .collect();
        let walls: Vec<Vector<2>> = (-6_i32..=6)
            .flat_map(|a| (-4_i32..=-2).map(move |b| Vector::<2>::new(a as Real, b as Real)))
            .collect();
        let origin = Vector::<2>::zeros();
        let p_i = mean_pressure(&lithostatic(&origin));
        let mut sum = 0.0;
        for x_j in soil.iter().filter(|x| x.norm() > 0.0 && x.norm() < radius) {
            let r_ij = origin - x_j;
            let p_j = mean_pressure(&lithostatic(x_j));
            sum += diffusion.pair(p_i, p_j, &r_ij, &kernel.gradient(&r_ij), 1.0);
        }
        for x_w in walls.iter().filter(|x| x.norm() < radius) {
            let (mut stress, mut level, mut weight) = (Tensor3::zeros(), 0.0, 0.0);
            for x_k in soil.iter().filter(|x| (*x - x_w).norm() < radius) {
                let w = kernel.value((x_k - x_w).norm());
                stress +=
                    (lithostatic(x_k) + gravity_extrapolation(rho, &gravity, &(x_k - x_w))) * w;
                level += diffusion.level(x_k) * w;
                weight += w;
            }
            let p_w = mean_pressure(&(stress / weight));
            let r_iw = origin - x_w;
            let offset = diffusion.level(&origin) - level / weight;
            sum += diffusion.wall_pair(p_i, p_w, &r_iw, offset, &kernel.gradient(&r_iw), 1.0);
        }
        assert!(
            diffusion.rate(sum).abs() < 1e-9 * rho * g,
            "{}",
            diffusion.rate(sum)
        );
    }

    #[test]
    fn a_checkerboard_decays_and_the_density_follows() {
        let diffusion =
            MeanStressDiffusion::<2>::new(0.1, 1.3, 10.0, 1e6, Vector::zeros(), 1.0, 0.5, true);
        let amplitude = 100.0;
        let checkerboard = |x: &Vector<2>| {
            if (x[0].round() + x[1].round()) as i64 % 2 == 0 {
                amplitude
            } else {
                -amplitude
            }
        };
        // The origin holds +A: its pressure falls, and a uniform field does not change.
        assert!(rate_at_origin(&diffusion, checkerboard, false) < 0.0);
        assert_relative_eq!(rate_at_origin(&diffusion, |_| amplitude, false), 0.0);
        assert_relative_eq!(diffusion.volumetric_strain(2e3), 2e-3);
    }
}
