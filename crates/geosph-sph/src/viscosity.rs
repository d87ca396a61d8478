//! Viscous terms of the momentum equation, as type parameters of the pair loop.

use geosph_boundary::WallParticles;
use geosph_core::{Real, Vector};

/// The geometry and state of one interacting pair (i, j), as the pair loop has it.
#[derive(Clone, Copy, Debug)]
pub struct Pair<const D: usize> {
    /// x_i − x_j.
    pub r_ij: Vector<D>,
    /// |x_i − x_j|².
    pub r2: Real,
    /// 1 / (|x_i − x_j|² + 0.01 h²), shared by the terms that divide by the distance.
    pub inv_r2_eta2: Real,
    /// ∇_i W_ij.
    pub grad: Vector<D>,
    /// v_i − v_j.
    pub v_ij: Vector<D>,
    /// ρ_i.
    pub rho_i: Real,
    /// ρ_j.
    pub rho_j: Real,
    /// m_j.
    pub mass_j: Real,
}

impl<const D: usize> Pair<D> {
    /// The pair of displacement `r_ij` (|r_ij|² = `r2`), kernel gradient `grad`, relative
    /// velocity `v_ij`, densities `rho_i`, `rho_j` and mass `mass_j`, with the softening
    /// η² = `eta2` (0.01 h²).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn new(
        r_ij: Vector<D>,
        r2: Real,
        eta2: Real,
        grad: Vector<D>,
        v_ij: Vector<D>,
        rho_i: Real,
        rho_j: Real,
        mass_j: Real,
    ) -> Self {
        Self {
            r_ij,
            r2,
            inv_r2_eta2: 1.0 / (r2 + eta2),
            grad,
            v_ij,
            rho_i,
            rho_j,
            mass_j,
        }
    }
}

/// A viscous acceleration term. The pair loop is monomorphised over it, so [`Inviscid`] costs
/// nothing.
pub trait Viscosity<const D: usize>: Copy + Send + Sync + 'static {
    /// The velocity wall particle `w` shows this term, ũ_w (the wall condition sets it by
    /// the slip condition and the kind of term, `geosph_boundary::Slip::viscous_velocity`).
    #[inline(always)]
    fn wall_velocity(walls: &WallParticles<D>, w: usize) -> Vector<D> {
        walls.viscous_velocity[w]
    }

    /// The contribution of neighbour j to dv_i/dt.
    fn acceleration(&self, pair: &Pair<D>) -> Vector<D>;

    /// The kinematic viscosity ν that limits the time step (0 when it does not).
    fn kinematic_viscosity(&self) -> Real;
}

/// No viscous term.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inviscid;

impl<const D: usize> Viscosity<D> for Inviscid {
    #[inline(always)]
    fn acceleration(&self, _pair: &Pair<D>) -> Vector<D> {
        Vector::zeros()
    }

    fn kinematic_viscosity(&self) -> Real {
        0.0
    }
}

/// The artificial viscosity of Monaghan (1992, Annu. Rev. Astron. Astrophys. 30:543, eq. 4.1),
///
/// dv_i/dt ∋ −Σ_j m_j Π_ij ∇_i W_ij,  Π_ij = (−α c̄ μ_ij + β μ_ij²) / ρ̄_ij  for v_ij·x_ij < 0
/// (else 0),  μ_ij = h v_ij·x_ij / (|x_ij|² + 0.01 h²),
///
/// with ρ̄_ij = (ρ_i + ρ_j)/2 and c̄ the signal speed: the reference sound speed c₀ of a fluid,
/// the elastic P-wave speed of a soil (Bui et al. 2008, eq. 33).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtificialMonaghan1992 {
    /// α (linear term).
    pub alpha: Real,
    /// β (quadratic term).
    pub beta: Real,
    /// h.
    pub smoothing_length: Real,
    /// c̄: c₀ of a fluid, the P-wave speed √((K + 4G/3)/ρ₀) of a soil.
    pub sound_speed: Real,
}

impl ArtificialMonaghan1992 {
    /// Π_ij = (−α c̄ μ_ij + β μ_ij²)/ρ̄_ij of an approaching pair with μ_ij = `mu` and
    /// ρ̄_ij = `rho_mean` (the caller forms μ_ij and skips receding pairs).
    #[inline(always)]
    pub fn pi(&self, mu: Real, rho_mean: Real) -> Real {
        (-self.alpha * self.sound_speed * mu + self.beta * mu * mu) / rho_mean
    }

    /// The same Π_ij (up to rounding) from a = `h_approach` = h v_ij·x_ij (< 0 for an
    /// approaching pair) and d = `softened_r2` = |x_ij|² + 0.01 h², with one division instead
    /// of two: μ_ij = a/d, so Π_ij = a (β a − α c̄ d)/(d² ρ̄_ij). The soil adds it to the stress
    /// term of the pair as −Π_ij 1 (Bui et al. 2008, eq. 32).
    #[inline(always)]
    pub fn pi_of_approach(&self, h_approach: Real, softened_r2: Real, rho_mean: Real) -> Real {
        h_approach * (self.beta * h_approach - self.alpha * self.sound_speed * softened_r2)
            / (softened_r2 * softened_r2 * rho_mean)
    }
}

impl<const D: usize> Viscosity<D> for ArtificialMonaghan1992 {
    #[inline(always)]
    fn acceleration(&self, pair: &Pair<D>) -> Vector<D> {
        // min(v_ij·x_ij, 0) is zero for a receding pair, so μ_ij = Π_ij = 0 there with no
        // branch the processor could mispredict (the result is the branch's to the bit).
        let approach = pair.v_ij.dot(&pair.r_ij).min(0.0);
        let mu = self.smoothing_length * approach * pair.inv_r2_eta2;
        let pi = self.pi(mu, 0.5 * (pair.rho_i + pair.rho_j));
        pair.grad * (-pair.mass_j * pi)
    }

    fn kinematic_viscosity(&self) -> Real {
        0.0
    }
}

/// The laminar viscosity of Morris, Fox & Zhu (1997, J. Comput. Phys. 136:214, eq. 8),
///
/// dv_i/dt ∋ Σ_j m_j (μ_i + μ_j) x_ij·∇_i W_ij / (ρ_i ρ_j (|x_ij|² + 0.01 h²)) v_ij,
///
/// with the dynamic viscosity μ = ρ ν of a fluid of kinematic viscosity ν, times the constant
/// 1/f_ν of [`lattice_laplacian_factor`](crate::lattice::lattice_laplacian_factor) that makes
/// it exact for a quadratic velocity on the initial lattice (as the incompressible solvers'
/// pressure gradient is made exact for a linear pressure).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaminarMorris1997 {
    /// ν.
    pub kinematic_viscosity: Real,
    /// 1/f_ν (1: uncorrected).
    pub lattice_correction: Real,
}

impl<const D: usize> Viscosity<D> for LaminarMorris1997 {
    #[inline(always)]
    fn acceleration(&self, pair: &Pair<D>) -> Vector<D> {
        // (μ_i + μ_j)/(ρ_i ρ_j) = ν (ρ_i + ρ_j)/(ρ_i ρ_j)
        let mu_sum = self.kinematic_viscosity * self.lattice_correction * (pair.rho_i + pair.rho_j)
            / (pair.rho_i * pair.rho_j);
        pair.v_ij * (pair.mass_j * mu_sum * pair.r_ij.dot(&pair.grad) * pair.inv_r2_eta2)
    }

    fn kinematic_viscosity(&self) -> Real {
        self.kinematic_viscosity
    }
}

/// A viscous term chosen at run time, for a pass that runs once per step and need not be
/// compiled once per term (the known acceleration of the incompressible solvers, whose
/// pressure iterations, where the time goes, have no viscous term). [`ViscousTerm::visit`]
/// resolves it to its type once per call, so the pair loop inside is monomorphised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViscousTerm {
    /// [`Inviscid`].
    Inviscid,
    /// [`ArtificialMonaghan1992`].
    Artificial(ArtificialMonaghan1992),
    /// [`LaminarMorris1997`].
    Laminar(LaminarMorris1997),
}

/// A computation generic over the viscous term, called by [`ViscousTerm::visit`].
pub trait ViscousVisitor<const D: usize> {
    /// What the computation returns.
    type Output;

    /// Runs the computation with the term `viscosity`.
    fn visit<V: Viscosity<D>>(self, viscosity: V) -> Self::Output;
}

impl ViscousTerm {
    /// Calls `visitor` with the term as its own type.
    #[inline]
    pub fn visit<const D: usize, T: ViscousVisitor<D>>(self, visitor: T) -> T::Output {
        match self {
            Self::Inviscid => visitor.visit(Inviscid),
            Self::Artificial(term) => visitor.visit(term),
            Self::Laminar(term) => visitor.visit(term),
        }
    }

    /// The term calibrated on the initial lattice of `spacing` whose particles have volume
    /// `volume`: a laminar term gets its 1/f_ν
    /// ([`lattice_laplacian_factor`](crate::lattice::lattice_laplacian_factor)); the others
    /// are returned as they are.
    pub fn calibrated<const D: usize, K: geosph_kernels::Kernel<D>>(
        self,
        kernel: &K,
        spacing: Real,
        volume: Real,
    ) -> Self {
        match self {
            Self::Laminar(term) => Self::Laminar(LaminarMorris1997 {
                lattice_correction: 1.0
                    / crate::lattice::lattice_laplacian_factor(kernel, spacing, volume),
                ..term
            }),
            other => other,
        }
    }

    /// The kinematic viscosity ν that limits the time step (0 when it does not).
    pub fn kinematic_viscosity(&self) -> Real {
        match self {
            Self::Laminar(term) => term.kinematic_viscosity,
            Self::Inviscid | Self::Artificial(_) => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn pair(v_ij: Vector<2>) -> Pair<2> {
        let r_ij = Vector::<2>::new(0.01, 0.0);
        let r2 = r_ij.norm_squared();
        Pair::new(
            r_ij,
            r2,
            0.01 * 0.013 * 0.013,
            r_ij * -1000.0,
            v_ij,
            1000.0,
            1000.0,
            0.1,
        )
    }

    #[test]
    fn artificial_viscosity_acts_only_on_approach_and_decelerates() {
        let av = ArtificialMonaghan1992 {
            alpha: 0.1,
            beta: 0.0,
            smoothing_length: 0.013,
            sound_speed: 30.0,
        };
        let receding = pair(Vector::<2>::new(1.0, 0.0));
        assert_eq!(av.acceleration(&receding), Vector::<2>::zeros());
        let approaching = pair(Vector::<2>::new(-1.0, 0.0));
        // i moves towards j (−x); the force pushes i back (+x).
        assert!(av.acceleration(&approaching)[0] > 0.0);
    }

    /// The pair term equals −m_j Π_ij ∇_i W_ij with Π_ij of eq. 4.1 formed directly, with the
    /// quadratic term on, and is zero for a receding pair.
    #[test]
    fn artificial_viscosity_is_monaghans_pi_with_both_terms() {
        let av = ArtificialMonaghan1992 {
            alpha: 0.5,
            beta: 1.0,
            smoothing_length: 0.013,
            sound_speed: 30.0,
        };
        let v_ij = Vector::<2>::new(-2.0, 0.5);
        let approaching = pair(v_ij);
        let mu = 0.013 * v_ij.dot(&approaching.r_ij) * approaching.inv_r2_eta2;
        let pi = (-0.5 * 30.0 * mu + mu * mu) / 1000.0;
        let expected = approaching.grad * (-approaching.mass_j * pi);
        assert_relative_eq!(
            av.acceleration(&approaching),
            expected,
            max_relative = 1e-14
        );
        assert_eq!(av.acceleration(&pair(-v_ij)), Vector::<2>::zeros());
    }

    /// Π_ij as the soil adds it to its stress term (Bui et al. 2008, eq. 33, with the P-wave
    /// speed), by hand for two pairs.
    #[test]
    fn artificial_pressure_of_an_approaching_pair() {
        let av = ArtificialMonaghan1992 {
            alpha: 0.1,
            beta: 0.0,
            smoothing_length: 1.0,
            sound_speed: 10.0,
        };
        // r_ij = (1, 0), v_ij = (−1, 0): μ = −1/1.01, Π = 0.1 · 10 / 1.01 / ρ̄ with ρ̄ = 2.
        assert_relative_eq!(av.pi(-1.0 / 1.01, 2.0), 0.5 / 1.01, epsilon = 1e-12);
        // β adds β μ²/ρ̄.
        let quadratic = ArtificialMonaghan1992 { beta: 1.0, ..av };
        assert_relative_eq!(quadratic.pi(-2.0, 2.0), (2.0 + 4.0) / 2.0, epsilon = 1e-12);
        // One division: the same Π from a = h v·x and d = r² + 0.01 h².
        for (a, d, rho) in [(-0.3, 1.01, 2.0), (-2.0e-4, 3.1e-6, 2650.0)] {
            assert_relative_eq!(
                quadratic.pi_of_approach(a, d, rho),
                quadratic.pi(a / d, rho),
                max_relative = 1e-14
            );
        }
    }

    #[test]
    fn laminar_viscosity_opposes_relative_velocity() {
        let nu = 1e-3;
        let visc = LaminarMorris1997 {
            kinematic_viscosity: nu,
            lattice_correction: 1.0,
        };
        let shear = pair(Vector::<2>::new(0.0, 2.0));
        let a = visc.acceleration(&shear);
        assert_eq!(a[0], 0.0);
        assert!(a[1] < 0.0);
        let expected = 0.1 * 2.0 * nu / 1000.0 * (-0.1) / (1e-4 + 0.01 * 0.013 * 0.013) * 2.0;
        assert_relative_eq!(a[1], expected, max_relative = 1e-12);
    }
}
