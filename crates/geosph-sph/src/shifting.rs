//! Particle shifting: small displacements that keep the particle distribution regular.
//!
//! A Lagrangian SPH particle set follows the flow's strain: at a stagnation point of a vortex
//! (Taylor–Green) or under a jet, particles line up along the stretching direction and leave
//! voids across it. The kernel sums of a disordered set are no longer consistent (Σ_j V_j ∇W_ij
//! ≠ 0), so the discrete divergence of a divergence-free flow is not zero, the density drifts
//! and the pressure becomes noise. Particle shifting moves each particle down the gradient of
//! the particle concentration, a few per cent of dx per step, back towards a uniform
//! distribution (Xu, Stansby & Laurence 2009; Lind et al. 2012).
//!
//! This is the particle shifting of δ⁺-SPH (Sun, Colagrossi, Marrone & Zhang 2017):
//!
//! δr_i = −D_i Σ_j V_j [1 + R (W_ij / W(Δx))ⁿ] ∇_i W_ij,  D_i = min(ζ U_max Δt R_s²/h, D_max),
//!
//! where the sum runs over fluid and wall neighbours (walls hold the concentration up at a
//! wall, so nothing is shifted into it) and R_s is the support radius. With R_s = 2h (Sun et
//! al.'s kernel) ζ = 1 is their δr_i = −CFL·Ma·(2h)² Σ_j …, CFL·Ma = U_max Δt / h; the default
//! ζ = 3 is measured: on the Taylor–Green vortex at Re = 100, 100 × 100 particles, t = 2, ζ = 1
//! leaves a 0.82 % velocity error and 1.0 % kinetic-energy loss, ζ = 3 0.32 % and +0.3 %
//! (`docs/fluid.md`, "Particle shifting"). The bracket is the anti-clustering term of Monaghan
//! (2000) with R = 0.2, n = 4. Written with U_max Δt the
//! rule holds for the incompressible solvers, whose Δt is not tied to a sound speed, and
//! D_max = ½ h² bounds the per-step diffusion where Δt is large (a bound chosen here, not taken
//! from the papers; at the default ζ only the incompressible solvers' longest steps reach it),
//! and no shift exceeds 0.1 Δx per step: without that limit the splash speed of a dam break
//! made the shift of particles resting on wall particles large enough to enter the wall
//! (`docs/fluid.md`, "Free surfaces").
//!
//! At a free surface the concentration falls because the fluid ends, not because particles
//! are disordered, so shifting along its gradient would throw surface particles outward.
//! Surface particles are found with Marrone et al. (2010): λ_i, the smallest eigenvalue of
//! B_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i) (1 inside a full support, about 0.5 or less at a
//! surface). Particles with λ_i < λ_surface (0.4) are not shifted; those with λ_i <
//! λ_near (0.75) are shifted tangentially only, δr ← (I − n n) δr, with n the outward unit
//! normal −B_i⁻¹ Σ_j V_j ∇_i W_ij / |…| (the renormalised gradient of the colour function).

use geosph_core::{Matrix, Real, Vector};
use geosph_kernels::Kernel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::config_error::{ConfigError, in_range};
use crate::lists::PairLists;

/// Settings of the δ⁺-SPH particle shifting (see the [module](self) documentation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ParticleShifting {
    /// ζ, the scale of the shifting coefficient (default 3; 1 is Sun et al. 2017's).
    pub coefficient: Real,
    /// R of the anti-clustering term (default 0.2).
    pub anti_clustering: Real,
    /// λ below which a particle is on the free surface and not shifted (default 0.4).
    pub surface_threshold: Real,
    /// λ below which a particle is near the free surface and shifted tangentially only
    /// (default 0.75).
    pub near_surface_threshold: Real,
}

impl Default for ParticleShifting {
    fn default() -> Self {
        Self {
            coefficient: 3.0,
            anti_clustering: 0.2,
            surface_threshold: 0.4,
            near_surface_threshold: 0.75,
        }
    }
}

/// Exponent n of the anti-clustering term (Monaghan 2000).
const ANTI_CLUSTERING_EXPONENT: i32 = 4;

/// The largest shift per step, in units of Δx.
const MAX_STEP: Real = 0.1;

/// D_max / h²: the largest shifting coefficient per step.
const MAX_COEFFICIENT: Real = 0.5;

/// The shift of one step ([`ParticleShifting::step`]): what [`ShiftSums`] are turned into a
/// shifting velocity with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShiftStep {
    settings: ParticleShifting,
    /// D_i / Δt.
    coefficient: Real,
    /// 1 / W(Δx).
    reference: Real,
    /// The largest shifting velocity, [`MAX_STEP`] Δx / Δt.
    max_shift_speed: Real,
}

impl ShiftStep {
    /// The shifting velocity of a particle with `sums`.
    #[inline]
    pub fn finish<const D: usize>(&self, sums: &ShiftSums<D>) -> Vector<D> {
        let value = self.settings.limit(
            &sums.moment,
            &sums.colour,
            sums.concentration * -self.coefficient,
        );
        let speed = value.norm();
        if speed > self.max_shift_speed {
            value * (self.max_shift_speed / speed)
        } else {
            value
        }
    }
}

/// The per-particle sums of a shift, accumulated pair by pair: B_i, the colour gradient
/// Σ_j V_j ∇_i W_ij and the concentration gradient with its anti-clustering term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShiftSums<const D: usize> {
    moment: Matrix<D>,
    colour: Vector<D>,
    concentration: Vector<D>,
}

impl<const D: usize> Default for ShiftSums<D> {
    fn default() -> Self {
        Self {
            moment: Matrix::zeros(),
            colour: Vector::zeros(),
            concentration: Vector::zeros(),
        }
    }
}

impl<const D: usize> ShiftSums<D> {
    /// Adds neighbour j: `r_ij` = x_i − x_j, `w` = W_ij, `weighted` = V_j ∇_i W_ij.
    #[inline(always)]
    pub fn add(&mut self, step: &ShiftStep, r_ij: Vector<D>, w: Real, weighted: Vector<D>) {
        self.moment -= weighted * r_ij.transpose();
        self.colour += weighted;
        let ratio = w * step.reference;
        self.concentration +=
            weighted * (1.0 + step.settings.anti_clustering * ratio.powi(ANTI_CLUSTERING_EXPONENT));
    }
}

/// Whether a pair loop carries a shift: [`NoShift`] (nothing in the loop) or a [`ShiftStep`].
/// A solver's pair loop is generic over it, so a scene without shifting pays nothing.
pub trait ShiftTerm: Copy + Send + Sync {
    /// Whether this term shifts at all (a loop skips the pair work when it does not).
    const ON: bool;

    /// Adds neighbour j to `sums` (see [`ShiftSums::add`]).
    fn add<const D: usize>(
        &self,
        sums: &mut ShiftSums<D>,
        r_ij: Vector<D>,
        w: Real,
        weighted: Vector<D>,
    );

    /// The shifting velocity from `sums` (zero for [`NoShift`]).
    fn finish<const D: usize>(&self, sums: &ShiftSums<D>) -> Vector<D>;
}

/// No shifting.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoShift;

impl ShiftTerm for NoShift {
    const ON: bool = false;

    #[inline(always)]
    fn add<const D: usize>(&self, _: &mut ShiftSums<D>, _: Vector<D>, _: Real, _: Vector<D>) {}

    #[inline(always)]
    fn finish<const D: usize>(&self, _sums: &ShiftSums<D>) -> Vector<D> {
        Vector::zeros()
    }
}

impl ShiftTerm for ShiftStep {
    const ON: bool = true;

    #[inline(always)]
    fn add<const D: usize>(
        &self,
        sums: &mut ShiftSums<D>,
        r_ij: Vector<D>,
        w: Real,
        weighted: Vector<D>,
    ) {
        sums.add(self, r_ij, w, weighted);
    }

    #[inline(always)]
    fn finish<const D: usize>(&self, sums: &ShiftSums<D>) -> Vector<D> {
        ShiftStep::finish(self, sums)
    }
}

/// The arrays of a particle set that shifting reads.
#[derive(Clone, Copy, Debug)]
pub struct ShiftingInput<'a, const D: usize> {
    /// Particle positions.
    pub position: &'a [Vector<D>],
    /// Particle volumes V_j = m_j / ρ_j.
    pub volume: &'a [Real],
    /// Wall particle positions.
    pub wall_position: &'a [Vector<D>],
    /// Wall particle volumes.
    pub wall_volume: &'a [Real],
    /// The largest particle speed U_max.
    pub max_speed: Real,
    /// The step Δt the shift is applied over.
    pub time_step: Real,
}

impl ParticleShifting {
    /// Checks every setting; `field` is where the settings sit in the solver block.
    pub fn validate(&self, field: &str) -> Result<(), ConfigError> {
        in_range(&format!("{field}.coefficient"), self.coefficient, 0.0, 10.0)?;
        in_range(
            &format!("{field}.anti_clustering"),
            self.anti_clustering,
            0.0,
            1.0,
        )?;
        in_range(
            &format!("{field}.surface_threshold"),
            self.surface_threshold,
            0.0,
            1.0,
        )?;
        in_range(
            &format!("{field}.near_surface_threshold"),
            self.near_surface_threshold,
            self.surface_threshold,
            1.0,
        )
    }

    /// The shift of one step: the coefficient and limits for `kernel` on the lattice of
    /// `spacing`, the largest particle speed `max_speed` and the step `time_step`.
    pub fn step<const D: usize, K: Kernel<D>>(
        &self,
        kernel: &K,
        spacing: Real,
        max_speed: Real,
        time_step: Real,
    ) -> ShiftStep {
        let h = kernel.smoothing_length();
        let support = kernel.support_radius();
        let coefficient = if time_step > 0.0 {
            (self.coefficient * max_speed * time_step * support * support / h)
                .min(MAX_COEFFICIENT * h * h)
                / time_step
        } else {
            0.0
        };
        ShiftStep {
            settings: *self,
            coefficient,
            reference: 1.0 / kernel.value(spacing),
            max_shift_speed: MAX_STEP * spacing / time_step.max(Real::MIN_POSITIVE),
        }
    }

    /// The shifting velocity δr_i / Δt of every particle into `velocity` (so a solver adds it
    /// to the drift, x ← x + Δt (v + δr/Δt)), in a pass of its own over `lists`; a solver
    /// that walks the pairs anyway carries a [`ShiftSums`] in its own loop instead
    /// ([`ShiftTerm`]).
    pub fn velocity<const D: usize, K: Kernel<D>>(
        &self,
        kernel: &K,
        spacing: Real,
        lists: &PairLists<D>,
        input: ShiftingInput<'_, D>,
        velocity: &mut [Vector<D>],
    ) {
        let step = self.step(kernel, spacing, input.max_speed, input.time_step);
        let ShiftingInput {
            position,
            volume,
            wall_position,
            wall_volume,
            ..
        } = input;
        velocity.par_iter_mut().enumerate().for_each(|(i, shift)| {
            let mut sums = ShiftSums::default();
            lists.for_each_neighbour(kernel, position, i, |pair| {
                sums.add(
                    &step,
                    pair.r_ij,
                    kernel.value(pair.r),
                    pair.grad * volume[pair.index],
                );
            });
            lists.for_each_wall(kernel, position, wall_position, i, |pair| {
                let weighted = pair.grad * wall_volume[pair.index];
                sums.add(&step, pair.r_ij, kernel.value(pair.r), weighted);
            });
            *shift = step.finish(&sums);
        });
    }

    /// The shift `shift` of a particle with moment matrix B_i = `moment` and colour gradient
    /// `colour`, after the free-surface rule.
    fn limit<const D: usize>(
        &self,
        moment: &Matrix<D>,
        colour: &Vector<D>,
        shift: Vector<D>,
    ) -> Vector<D> {
        let lambda = smallest_eigenvalue(moment);
        if lambda < self.surface_threshold {
            return Vector::zeros();
        }
        if lambda >= self.near_surface_threshold {
            return shift;
        }
        let Some(normal) = moment
            .try_inverse()
            .map(|inverse| -(inverse * colour))
            .and_then(|n| n.try_normalize(Real::EPSILON))
        else {
            return Vector::zeros();
        };
        shift - normal * normal.dot(&shift)
    }
}

/// λ_i of [`ParticleShifting`]: the smallest eigenvalue of the symmetric part of `m`, in
/// closed form (the trigonometric solution of the characteristic cubic in 3D; Smith 1961).
pub fn smallest_eigenvalue<const D: usize>(m: &Matrix<D>) -> Real {
    let s = (m + m.transpose()) * 0.5;
    match D {
        1 => s[(0, 0)],
        2 => {
            let (a, b, d) = (s[(0, 0)], s[(0, 1)], s[(1, 1)]);
            0.5 * (a + d) - (0.25 * (a - d) * (a - d) + b * b).sqrt()
        }
        _ => {
            let q = s.trace() / D as Real;
            let off = s[(0, 1)].powi(2) + s[(0, 2)].powi(2) + s[(1, 2)].powi(2);
            let diagonal =
                (s[(0, 0)] - q).powi(2) + (s[(1, 1)] - q).powi(2) + (s[(2, 2)] - q).powi(2);
            let p = ((diagonal + 2.0 * off) / 6.0).sqrt();
            if p == 0.0 {
                return q;
            }
            let b = (s - Matrix::<D>::identity() * q) / p;
            let determinant = b[(0, 0)] * (b[(1, 1)] * b[(2, 2)] - b[(1, 2)] * b[(2, 1)])
                - b[(0, 1)] * (b[(1, 0)] * b[(2, 2)] - b[(1, 2)] * b[(2, 0)])
                + b[(0, 2)] * (b[(1, 0)] * b[(2, 1)] - b[(1, 1)] * b[(2, 0)]);
            let half_det: Real = 0.5 * determinant;
            let phi = half_det.clamp(-1.0, 1.0).acos() / 3.0;
            q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::Matrix3;

    #[test]
    fn smallest_eigenvalue_matches_a_full_decomposition() {
        let a = Matrix3::new(2.0, 0.3, -0.4, 0.3, 1.0, 0.2, -0.4, 0.2, 0.5);
        let expected = a.symmetric_eigen().eigenvalues.min();
        assert_relative_eq!(smallest_eigenvalue(&a), expected, epsilon = 1e-12);
        let b = nalgebra::Matrix2::new(1.0, 0.4, 0.4, 0.2);
        let expected = b.symmetric_eigen().eigenvalues.min();
        assert_relative_eq!(smallest_eigenvalue(&b), expected, epsilon = 1e-12);
        assert_relative_eq!(smallest_eigenvalue(&Matrix3::identity()), 1.0);
    }

    /// On a periodic lattice a particle pushed off its site is shifted back towards it, and the
    /// others hardly move: the shift reduces the disorder it measures.
    #[test]
    fn a_displaced_particle_is_shifted_back_to_its_site() {
        use geosph_core::Domain;
        use geosph_kernels::WendlandC2;
        let (n, dx) = (12, 0.1);
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let side = n as Real * dx;
        let domain = Domain::with_periodic(
            nalgebra::Vector2::zeros(),
            nalgebra::Vector2::repeat(side),
            [true, true],
        )
        .unwrap();
        let mut position: Vec<Vector<2>> = (0..n * n)
            .map(|k| Vector::<2>::new((k % n) as Real + 0.5, (k / n) as Real + 0.5) * dx)
            .collect();
        let displaced = 6 * n + 6;
        let offset = Vector::<2>::new(0.2 * dx, 0.1 * dx);
        position[displaced] += offset;
        let mut lists = PairLists::new(domain, kernel.support_radius(), 0.0, &[], false).unwrap();
        lists.update(&mut position, &[]).unwrap();
        let volume = vec![dx * dx; position.len()];
        let input = ShiftingInput {
            position: &position,
            volume: &volume,
            wall_position: &[],
            wall_volume: &[],
            max_speed: 1.0,
            time_step: 1e-3,
        };
        let mut shift = vec![Vector::<2>::zeros(); position.len()];
        let shifting = ParticleShifting::default();
        shifting.velocity(&kernel, dx, &lists, input, &mut shift);
        let back = shift[displaced];
        // Against the offset, and mostly along it.
        assert!(
            back.dot(&offset) < -0.9 * back.norm() * offset.norm(),
            "{back:?}"
        );
        let others = (0..position.len())
            .filter(|&k| k != displaced)
            .map(|k| shift[k].norm())
            .fold(0.0, Real::max);
        assert!(others < back.norm(), "{others} vs {}", back.norm());
    }

    #[test]
    fn a_surface_particle_is_not_shifted_and_a_near_one_only_along_the_surface() {
        let shifting = ParticleShifting::default();
        let shift = nalgebra::Vector2::new(0.3, 0.4);
        // Half a support: λ = 0.3, on the surface.
        let surface = nalgebra::Matrix2::new(1.0, 0.0, 0.0, 0.3);
        let colour = nalgebra::Vector2::new(0.0, -1.0);
        assert_eq!(
            shifting.limit(&surface, &colour, shift),
            nalgebra::Vector2::zeros()
        );
        // λ = 0.6: the outward normal is +y, so only the x part is kept.
        let near = nalgebra::Matrix2::new(1.0, 0.0, 0.0, 0.6);
        let limited = shifting.limit(&near, &colour, shift);
        assert_relative_eq!(limited, nalgebra::Vector2::new(0.3, 0.0), epsilon = 1e-15);
        // Inside: unchanged.
        let inside = nalgebra::Matrix2::identity();
        assert_eq!(shifting.limit(&inside, &colour, shift), shift);
    }
}
