//! Density diffusion (δ-SPH) terms of the continuity equation: each a type the WCSPH pair loop
//! is monomorphised over, and [`DiffusionTerm`], the one a scene chooses at run time.

use geosph_core::{Domain, Matrix, NeighbourList, Real, Vector};
use geosph_kernels::{Kernel, cspm};
use rayon::prelude::*;

use geosph_sph::Pair;

/// A density-diffusion term D_i added to dρ_i/dt. The pair loop is monomorphised over it, so
/// [`NoDiffusion`] costs nothing.
pub trait DensityDiffusion<const D: usize>: Send + Sync + 'static {
    /// Per-evaluation preparation before the pair loop (e.g. density gradients).
    fn prepare<K: Kernel<D>>(
        &mut self,
        _kernel: &K,
        _domain: &Domain<D>,
        _position: &[Vector<D>],
        _density: &[Real],
        _volume: &[Real],
        _neighbours: &NeighbourList,
    ) {
    }

    /// The contribution of fluid neighbour j to dρ_i/dt, with V_j = m_j/ρ_j.
    fn rate(&self, i: usize, j: usize, pair: &Pair<D>, volume_j: Real) -> Real;
}

/// No density diffusion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoDiffusion;

impl<const D: usize> DensityDiffusion<D> for NoDiffusion {
    #[inline(always)]
    fn rate(&self, _i: usize, _j: usize, _pair: &Pair<D>, _volume_j: Real) -> Real {
        0.0
    }
}

/// The δ-SPH diffusion of Molteni & Colagrossi (2009, Comput. Phys. Commun. 180:861, eq. 9),
///
/// D_i = δ h c₀ Σ_j ψ_ij · ∇_i W_ij V_j,  ψ_ij = 2 (ρ_j − ρ_i) x_ji / |x_ji|²,
///
/// i.e. 2 δ h c₀ Σ_j (ρ_i − ρ_j) x_ij·∇_i W_ij / (|x_ij|² + 0.01 h²) V_j with x_ij = x_i − x_j
/// (the 0.01 h² guards coincident particles; h is the kernel's, as in [`Pair::inv_r2_eta2`]).
/// It diffuses density differences, including the hydrostatic stratification, which
/// [`DeltaAntuono2010`] leaves alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaMolteni2009 {
    /// δ (0.1 is usual).
    pub delta: Real,
    /// h.
    pub smoothing_length: Real,
    /// c₀.
    pub sound_speed: Real,
}

impl DeltaMolteni2009 {
    #[inline(always)]
    fn plain_rate<const D: usize>(&self, pair: &Pair<D>, volume_j: Real) -> Real {
        2.0 * self.delta
            * self.smoothing_length
            * self.sound_speed
            * (pair.rho_i - pair.rho_j)
            * pair.r_ij.dot(&pair.grad)
            * pair.inv_r2_eta2
            * volume_j
    }
}

impl<const D: usize> DensityDiffusion<D> for DeltaMolteni2009 {
    #[inline(always)]
    fn rate(&self, _i: usize, _j: usize, pair: &Pair<D>, volume_j: Real) -> Real {
        self.plain_rate(pair, volume_j)
    }
}

/// The density diffusion of Fourtakas, Domínguez, Vacondio & Rogers (2019, Comput. Fluids
/// 190:346, eq. 14): Molteni & Colagrossi's term applied to the density's departure from
/// hydrostatics,
///
/// D_i = 2 δ h c₀ Σ_j [(ρ_i − ρ_j) − ρᴴ_ij] x_ij·∇_i W_ij / (|x_ij|² + 0.01 h²) V_j,
/// ρᴴ_ij = ρ₀ g·x_ij / c₀²,
///
/// ρᴴ_ij being the hydrostatic density difference between i and j (the pressure difference
/// ρ₀ g·x_ij through the equation of state, linearised as in `docs/fluid.md`, "Density
/// diffusion"). A column at rest under gravity is not diffused, so it does not drift as with
/// [`DeltaMolteni2009`]; unlike [`DeltaAntuono2010`] it needs no density gradients, so it
/// costs one dot product per pair and is defined for a particle with any neighbours (a
/// droplet of two or three).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaFourtakas2019<const D: usize> {
    /// The Molteni–Colagrossi part.
    pub base: DeltaMolteni2009,
    /// ρ₀ g / c₀², the hydrostatic density gradient.
    pub hydrostatic_gradient: Vector<D>,
}

impl<const D: usize> DensityDiffusion<D> for DeltaFourtakas2019<D> {
    #[inline(always)]
    fn rate(&self, _i: usize, _j: usize, pair: &Pair<D>, volume_j: Real) -> Real {
        let base = &self.base;
        let hydrostatic = self.hydrostatic_gradient.dot(&pair.r_ij);
        2.0 * base.delta
            * base.smoothing_length
            * base.sound_speed
            * (pair.rho_i - pair.rho_j - hydrostatic)
            * pair.r_ij.dot(&pair.grad)
            * pair.inv_r2_eta2
            * volume_j
    }
}

/// The δ-SPH diffusion of Antuono, Colagrossi, Marrone & Molteni (2010, Comput. Phys. Commun.
/// 181:532, eq. 6), which subtracts the renormalised density gradients,
///
/// ψ_ij = 2 (ρ_j − ρ_i) x_ji / |x_ji|² − (⟨∇ρ⟩ᴸ_i + ⟨∇ρ⟩ᴸ_j),
/// ⟨∇ρ⟩ᴸ_i = Σ_j (ρ_j − ρ_i) L_i ∇_i W_ij V_j,
///
/// with the CSPM matrix L_i ([`geosph_kernels::cspm`]). For a linear density field the two
/// parts cancel pair by pair, so a hydrostatic column is not diffused.
#[derive(Clone, Debug, PartialEq)]
pub struct DeltaAntuono2010<const D: usize> {
    /// The Molteni–Colagrossi part.
    pub base: DeltaMolteni2009,
    correction: Vec<Matrix<D>>,
    gradient: Vec<Vector<D>>,
}

impl<const D: usize> DeltaAntuono2010<D> {
    /// The term with diffusion coefficient δ.
    pub fn new(delta: Real, smoothing_length: Real, sound_speed: Real) -> Self {
        Self {
            base: DeltaMolteni2009 {
                delta,
                smoothing_length,
                sound_speed,
            },
            correction: Vec::new(),
            gradient: Vec::new(),
        }
    }

    /// The renormalised density gradients of the last preparation.
    pub fn density_gradient(&self) -> &[Vector<D>] {
        &self.gradient
    }
}

impl<const D: usize> DensityDiffusion<D> for DeltaAntuono2010<D> {
    fn prepare<K: Kernel<D>>(
        &mut self,
        kernel: &K,
        domain: &Domain<D>,
        position: &[Vector<D>],
        density: &[Real],
        volume: &[Real],
        neighbours: &NeighbourList,
    ) {
        let n = position.len();
        self.correction.resize(n, Matrix::identity());
        self.gradient.resize(n, Vector::zeros());
        // Particles with too few neighbours keep L = I (reported by cspm, harmless here).
        cspm::gradient_correction(
            kernel,
            domain,
            position,
            volume,
            neighbours,
            &mut self.correction,
        );
        let correction = &self.correction;
        self.gradient
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, gradient)| {
                let mut sum = Vector::<D>::zeros();
                for &j in neighbours.neighbours(i) {
                    let j = j as usize;
                    let r_ij = domain.displacement(&position[i], &position[j]);
                    sum += kernel.gradient(&r_ij) * ((density[j] - density[i]) * volume[j]);
                }
                *gradient = correction[i] * sum;
            });
    }

    #[inline(always)]
    fn rate(&self, i: usize, j: usize, pair: &Pair<D>, volume_j: Real) -> Real {
        let base = &self.base;
        let gradient_sum = self.gradient[i] + self.gradient[j];
        base.plain_rate(pair, volume_j)
            - base.delta
                * base.smoothing_length
                * base.sound_speed
                * gradient_sum.dot(&pair.grad)
                * volume_j
    }
}

/// A density-diffusion term chosen at run time. The WCSPH rate pass resolves it to its type
/// once per evaluation ([`DiffusionTerm::visit`]), so the pair loop is monomorphised over the
/// term while the rest of the solver is compiled once per kernel.
#[derive(Clone, Debug, PartialEq)]
pub enum DiffusionTerm<const D: usize> {
    /// [`NoDiffusion`].
    None,
    /// [`DeltaMolteni2009`].
    Molteni(DeltaMolteni2009),
    /// [`DeltaAntuono2010`].
    Antuono(DeltaAntuono2010<D>),
    /// [`DeltaFourtakas2019`].
    Fourtakas(DeltaFourtakas2019<D>),
}

/// A computation generic over the diffusion term, called by [`DiffusionTerm::visit`].
pub trait DiffusionVisitor<const D: usize> {
    /// What the computation returns.
    type Output;

    /// Runs the computation with the term `diffusion`.
    fn visit<F: DensityDiffusion<D>>(self, diffusion: &F) -> Self::Output;
}

impl<const D: usize> DiffusionTerm<D> {
    /// [`DensityDiffusion::prepare`] of the term.
    pub fn prepare<K: Kernel<D>>(
        &mut self,
        kernel: &K,
        domain: &Domain<D>,
        position: &[Vector<D>],
        density: &[Real],
        volume: &[Real],
        neighbours: &NeighbourList,
    ) {
        match self {
            Self::None => {}
            Self::Molteni(term) => {
                term.prepare(kernel, domain, position, density, volume, neighbours)
            }
            Self::Antuono(term) => {
                term.prepare(kernel, domain, position, density, volume, neighbours)
            }
            Self::Fourtakas(_) => {}
        }
    }

    /// Calls `visitor` with the term as its own type.
    #[inline]
    pub fn visit<T: DiffusionVisitor<D>>(&self, visitor: T) -> T::Output {
        match self {
            Self::None => visitor.visit(&NoDiffusion),
            Self::Molteni(term) => visitor.visit(term),
            Self::Antuono(term) => visitor.visit(term),
            Self::Fourtakas(term) => visitor.visit(term),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pair in hydrostatic equilibrium, i one spacing below j: Fourtakas et al.'s term is
    /// zero, Molteni's lowers the deeper particle's density.
    #[test]
    fn hydrostatic_pair_is_not_diffused() {
        let (rho0, c0, h, dx) = (1000.0, 20.0, 0.013, 0.01);
        let gravity = Vector::<2>::new(0.0, -9.81);
        let r_ij = Vector::<2>::new(0.0, -dx);
        // ρ_i − ρ_j = ρ₀ g dx / c₀² for the linear equation of state.
        let rho_j = rho0;
        let rho_i = rho_j + rho0 * 9.81 * dx / (c0 * c0);
        let r2: Real = dx * dx;
        // ∇_i W_ij points along −x_ij for a decreasing kernel.
        let grad = -r_ij * 100.0;
        let pair = Pair::new(
            r_ij,
            r2,
            0.01 * h * h,
            grad,
            Vector::zeros(),
            rho_i,
            rho_j,
            rho0 * dx * dx,
        );
        let molteni = DeltaMolteni2009 {
            delta: 0.1,
            smoothing_length: h,
            sound_speed: c0,
        };
        let fourtakas = DeltaFourtakas2019 {
            base: molteni,
            hydrostatic_gradient: gravity * (rho0 / (c0 * c0)),
        };
        let volume = dx * dx;
        assert!(DensityDiffusion::<2>::rate(&molteni, 0, 1, &pair, volume) < 0.0);
        let rate = DensityDiffusion::<2>::rate(&fourtakas, 0, 1, &pair, volume);
        assert!(rate.abs() < 1e-12, "{rate}");
    }
}
