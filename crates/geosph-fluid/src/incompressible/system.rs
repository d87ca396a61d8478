//! The discrete operators that PCISPH, IISPH and DFSPH share: summation density, the pressure
//! acceleration with wall pressure mirroring, the velocity divergence and the diagonal of the
//! pressure system (the known, non-pressure acceleration in `system/known.rs`).

use geosph_boundary::{Slip, WallParticles};
use geosph_core::{Domain, Matrix, NeighbourList, Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_sph::pair_arrays::{ParticleView, for_each_particle};
use geosph_sph::{PairLists, ParticleShifting, ViscousTerm};
use rayon::prelude::*;

mod known;

/// How walls take part in the pressure force.
///
/// A wall particle b acts on fluid particle i with mass m_b = ρ₀ V_b (Akinci et al. 2012, with
/// the lattice volume V_b = dx^D of a filled wall) and the pressure
///
/// - [`WallPressure::Mirrored`]: p_b = p_i (Band et al. 2018, "pressure mirroring");
/// - [`WallPressure::Hydrostatic`]: p_b = p_i + ρ_i (g − a_b)·(x_b − x_i), the mirrored
///   pressure plus the hydrostatic head between the two particles, the pairwise form of the
///   extrapolation of Adami, Hu & Adams (2012, eq. 27), limited so that p_b ≥ 0 with the
///   previous step's p_i: a wall above the free surface must not pull the fluid up it.
///
/// Both give the pair term m_b (p_i/ρ_i² + p_b/ρ_i²) ∇_i W_ib. The head part does not depend on
/// the unknown pressures, so it enters the known (non-pressure) acceleration and the pressure
/// system keeps its form.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum WallPressure {
    /// p_b = p_i.
    Mirrored,
    /// p_b = p_i + ρ_i (g − a_b)·(x_b − x_i) (default): no pressure deficit at the bed.
    #[default]
    Hydrostatic,
}

/// Below this fraction of a filled lattice's diagonal a particle takes no pressure.
///
/// A spray particle whose only neighbours sit near the edge of the kernel support has a tiny
/// d_i (|∇W| vanishes at the edge as (1 − q/2)³ for Wendland C2), so the pressure that cancels
/// its approach rate, ∝ 1/|∇W|, is huge. Within the step the force, ∝ p |∇W|, stays bounded;
/// but the next step's warm start applies half that pressure with the larger |∇W| of a pair
/// that has moved closer. In the 20 m/s impact of `docs/stability.md` this threw a jet
/// particle from 45 m/s to 6 × 10⁵ m/s in one step. Such a particle is far below ρ₀ (330
/// kg/m³ there) and needs no pressure; SPlisHSPlasH's DFSPH likewise zeroes its factor below
/// an absolute threshold.
pub const DIAGONAL_FLOOR: Real = 1e-3;

/// Particle-pair data of one step: neighbour lists, kernel gradients, and the sums the
/// pressure solvers need, for a fluid with fixed or moving dummy walls.
///
/// Lists are exact ([`PairLists`] without a skin) and rebuilt after every position update: the
/// incompressible solvers iterate many times over them per step, so a list without empty pairs
/// pays off, and ∇_i W_ij is stored per pair so that each iteration reads it instead of
/// recomputing it.
pub struct PressureSystem<const D: usize, K: Kernel<D>> {
    /// Smoothing kernel.
    pub kernel: K,
    /// Fluid–fluid and fluid–wall pairs (exact), with the Z-order schedule.
    pub lists: PairLists<D>,
    /// Rest density ρ₀.
    pub rest_density: Real,
    /// Viscous term, resolved to its type once per pass (it enters the known acceleration
    /// only, once per step).
    pub viscosity: ViscousTerm,
    /// Body-force acceleration g.
    pub gravity: Vector<D>,
    /// Wall particles (their density and pressure fields are set for output).
    pub walls: WallParticles<D>,
    /// Wall pressure model.
    pub wall_pressure: WallPressure,
    /// Whether walls hold the flow's tangential velocity (no-slip) or let it slide; fixed at
    /// construction, which builds the wall-side list that free slip needs.
    wall_slip: Slip,
    /// Particle shifting of the drift (off: `None`).
    pub shifting: Option<ParticleShifting>,
    /// Constant c multiplying every pressure-gradient term (1: none). The solvers set it to
    /// 1/f of [`lattice_gradient_factor`](geosph_sph::lattice::lattice_gradient_factor), so
    /// that the pressure force of a linear pressure field on the initial lattice is exact.
    pub gradient_correction: Real,
    /// Replace every pair gradient of particle i by the renormalised c⁻¹ L_i ∇_i W_ij (off:
    /// false), with L_i = (Σ_j V_j x_ji ⊗ ∇_i W_ij)⁻¹ over fluid and wall neighbours,
    /// V = m/ρ₀ (Randles & Libersky 1996; Bonet & Lok 1999): the divergence and
    /// gradient of any linear field are then exact on any particle arrangement, not only on
    /// the lattice that `gradient_correction` c is calibrated on (where L_i = c I, so nothing
    /// changes there). Pair forces are no longer antisymmetric, so momentum is conserved only
    /// to the truncation error; and where the support is cut by a free surface L_i is
    /// ill-conditioned, so it is for flows without one (`docs/incompressible.md`, "The
    /// Taylor–Green vortex").
    pub renormalise_gradients: bool,
    /// λ_max of [`lattice_jacobi_bound`](geosph_sph::lattice::lattice_jacobi_bound) for the
    /// kernel and spacing (set by the solvers; 0: unknown, no limit), which bounds the
    /// relaxation of the Jacobi solves
    /// ([`PressureSystem::relaxation_limit`]).
    pub jacobi_bound: Real,
    /// Σ_k |∇W(x_k)|² over a filled lattice of the spacing (set by the solvers; 0: no floor),
    /// which scales the floor of the diagonal ([`PressureSystem::diagonal`]).
    pub lattice_gradient_squares: Real,
    /// ∇_i W_ij per listed fluid pair, aligned with the inner list's indices.
    fluid_gradient: Vec<Vector<D>>,
    /// ∇_i W_ib per listed wall pair, aligned with the contact list's indices.
    wall_gradient: Vec<Vector<D>>,
    /// Σ_b m_b ∇_i W_ib of each fluid particle.
    wall_gradient_sum: Vec<Vector<D>>,
    /// d_i of [`PressureSystem::diagonal`].
    diagonal: Vec<Real>,
}

impl<const D: usize, K: Kernel<D>> PressureSystem<D, K> {
    /// A system on `domain` with the given `walls` (their grid is built once here).
    pub fn new(
        kernel: K,
        domain: Domain<D>,
        rest_density: Real,
        viscosity: ViscousTerm,
        gravity: Vector<D>,
        walls: WallParticles<D>,
        wall_pressure: WallPressure,
        wall_slip: Slip,
    ) -> Result<Self, SearchError> {
        // A laminar term, or any term at a free-slip wall, needs the velocity of the flow near
        // each wall particle: the wall-side list.
        let laminar = viscosity.kinematic_viscosity() > 0.0;
        let wall_side = laminar || wall_slip == Slip::FreeSlip;
        let support = kernel.support_radius();
        let lists = PairLists::new(domain, support, 0.0, &walls.position, wall_side)?;
        Ok(Self {
            kernel,
            lists,
            rest_density,
            viscosity,
            gravity,
            walls,
            wall_pressure,
            wall_slip,
            shifting: None,
            gradient_correction: 1.0,
            renormalise_gradients: false,
            jacobi_bound: 0.0,
            lattice_gradient_squares: 0.0,
            fluid_gradient: Vec::new(),
            wall_gradient: Vec::new(),
            wall_gradient_sum: Vec::new(),
            diagonal: Vec::new(),
        })
    }

    /// The largest relaxation ω a Jacobi solve of the pressure system may use:
    /// 1.5 / λ_max with λ_max = [`PressureSystem::jacobi_bound`], so that the stiffest mode of
    /// the lattice is damped by |1 − ω λ_max| ≤ ½ per iteration instead of growing (it grows
    /// for ω λ_max > 2: ω = ½ with the quintic spline, λ_max = 4.11, or with Wendland C2 in 3D,
    /// 4.20). Infinite when the bound is unknown.
    pub fn relaxation_limit(&self) -> Real {
        if self.jacobi_bound > 0.0 {
            1.5 / self.jacobi_bound
        } else {
            Real::INFINITY
        }
    }

    /// Rebuilds the neighbour lists and per-pair gradients for the current positions, then the
    /// summation density ρ_i = Σ_j m_j W_ij + Σ_b ρ₀ V_b W_ib and the diagonal d_i.
    pub fn update(&mut self, fluid: &mut Particles<D>) -> Result<(), SearchError> {
        self.lists
            .update(&mut fluid.position, &self.walls.position)?;
        let (fluid_fluid, fluid_wall) = (self.lists.inner(), self.lists.contact());
        self.fluid_gradient
            .resize(fluid_fluid.pair_count(), Vector::zeros());
        self.wall_gradient
            .resize(fluid_wall.pair_count(), Vector::zeros());
        self.wall_gradient_sum.resize(fluid.len(), Vector::zeros());
        self.diagonal.resize(fluid.len(), 0.0);
        let (kernel, domain, rho0) = (self.kernel, self.lists.domain(), self.rest_density);
        let (walls, correction) = (&self.walls, self.gradient_correction);
        let renormalise = self.renormalise_gradients;
        let floor = DIAGONAL_FLOOR * correction * self.lattice_gradient_squares;
        let Particles {
            position,
            mass,
            density,
            ..
        } = fluid;
        let (position, mass) = (&*position, &*mass);
        // One pass: each particle's gradients ∇_i W_ij, its summation density and its diagonal
        // (which needs only the gradients), from one distance per pair.
        for_each_particle(
            (fluid_fluid, fluid_wall),
            &mut self.fluid_gradient,
            &mut self.wall_gradient,
            (
                density.as_mut_slice(),
                self.diagonal.as_mut_slice(),
                self.wall_gradient_sum.as_mut_slice(),
            ),
            |i, view: ParticleView<'_, Vector<D>, Vector<D>, Real, Real, Vector<D>>| {
                let x_i = position[i];
                let mut rho = 0.0;
                let mut fluid_sum = Vector::<D>::zeros();
                let mut squares = 0.0;
                for (&j, gradient) in view.fluid.iter().zip(view.fluid_values.iter_mut()) {
                    let j = j as usize;
                    let r_ij = domain.displacement(&x_i, &position[j]);
                    let r = r_ij.norm();
                    let m_j = mass[j];
                    *gradient = r_ij * kernel.gradient_factor(r);
                    rho += m_j * kernel.value(r);
                    fluid_sum += *gradient * m_j;
                    squares += m_j * gradient.norm_squared();
                }
                let mut wall_sum = Vector::<D>::zeros();
                for (&b, gradient) in view.wall.iter().zip(view.wall_values.iter_mut()) {
                    let b = b as usize;
                    let r_ib = domain.displacement(&x_i, &walls.position[b]);
                    let r = r_ib.norm();
                    let m_b = rho0 * walls.volume[b];
                    *gradient = r_ib * kernel.gradient_factor(r);
                    rho += m_b * kernel.value(r);
                    wall_sum += *gradient * m_b;
                }
                if renormalise {
                    // L_i from the gradients just stored, then the sums again with L_i ∇W.
                    let mut moment = Matrix::<D>::zeros();
                    for (&j, gradient) in view.fluid.iter().zip(view.fluid_values.iter()) {
                        let x_ji = domain.displacement(&position[j as usize], &x_i);
                        moment += x_ji * gradient.transpose() * (mass[j as usize] / rho0);
                    }
                    for (&b, gradient) in view.wall.iter().zip(view.wall_values.iter()) {
                        let x_bi = domain.displacement(&walls.position[b as usize], &x_i);
                        moment += x_bi * gradient.transpose() * walls.volume[b as usize];
                    }
                    if let Some(inverse) = moment.try_inverse() {
                        let renormalised = inverse / correction;
                        (fluid_sum, squares, wall_sum) = (Vector::zeros(), 0.0, Vector::zeros());
                        for (&j, gradient) in view.fluid.iter().zip(view.fluid_values.iter_mut()) {
                            *gradient = renormalised * *gradient;
                            fluid_sum += *gradient * mass[j as usize];
                            squares += mass[j as usize] * gradient.norm_squared();
                        }
                        for (&b, gradient) in view.wall.iter().zip(view.wall_values.iter_mut()) {
                            *gradient = renormalised * *gradient;
                            wall_sum += *gradient * (rho0 * walls.volume[b as usize]);
                        }
                    }
                }
                let (density, diagonal, wall_gradient_sum) = view.own;
                *density = rho;
                *wall_gradient_sum = wall_sum;
                let d_i = correction
                    * ((fluid_sum + wall_sum * 2.0).dot(&(fluid_sum + wall_sum))
                        + mass[i] * squares);
                *diagonal = if d_i > floor * mass[i] * mass[i] {
                    d_i
                } else {
                    0.0
                };
            },
        );
        Ok(())
    }

    /// The diagonal d_i of the pressure system for every particle:
    ///
    /// d_i = c (G_i·S_i + m_i Σ_j m_j |∇_i W_ij|²), with S_i = Σ_j m_j ∇_i W_ij + Σ_b m_b ∇_i W_ib,
    /// G_i = Σ_j m_j ∇_i W_ij + 2 Σ_b m_b ∇_i W_ib (the wall term doubled by mirroring) and c
    /// the [`PressureSystem::gradient_correction`]; 0 (the particle takes no pressure) where it
    /// is below 10⁻³ of a filled lattice's c m_i² Σ_k |∇W(x_k)|², see [`DIAGONAL_FLOOR`].
    ///
    /// A pressure change δp_i at particle i alone changes the predicted density of i by
    /// −Δt² d_i δp_i / ρ_i² (derived in `docs/incompressible.md`): d_i is the diagonal of the
    /// pressure system of IISPH (Ihmsen et al. 2014, a_ii of eq. 11, written with the mirrored
    /// walls), and ρ_i/d_i is the DFSPH factor α_i (Bender & Koschier 2017, eq. 9).
    pub fn diagonal(&self) -> &[Real] {
        &self.diagonal
    }

    /// The particles whose solves count: the first `owned` of the set (all of them on one
    /// process; in a distributed run the rest are the halo).
    pub(crate) fn owned(&self) -> usize {
        self.lists.owned(self.diagonal.len())
    }

    /// A solve's mean and largest error over every rank's owned particles from this rank's
    /// over its own ([`PairLists::figures_over_ranks`]; unchanged on one process), so that
    /// every rank stops its iterations alike.
    pub(crate) fn error_over_ranks(&self, (mean, max): (Real, Real)) -> (Real, Real) {
        let (mean, max, _) = self.lists.figures_over_ranks(mean, max, self.owned(), 0);
        (mean, max)
    }

    /// The pressure acceleration
    /// a_i = −c [Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij + (2 p_i/ρ_i²) Σ_b m_b ∇_i W_ib]
    /// (Monaghan 1992, eq. 3.3, with mirrored wall pressure and the constant
    /// [`PressureSystem::gradient_correction`] c), from `pressure_term` = p/ρ².
    pub fn pressure_acceleration(
        &self,
        mass: &[Real],
        pressure_term: &[Real],
        acceleration: &mut [Vector<D>],
    ) {
        acceleration
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, a_i)| *a_i = self.pressure_acceleration_at(i, mass, pressure_term));
    }

    /// [`Self::pressure_acceleration`] of particle `i`, for solvers that fuse it with their
    /// own per-particle update in one pass.
    #[inline]
    pub fn pressure_acceleration_at(
        &self,
        i: usize,
        mass: &[Real],
        pressure_term: &[Real],
    ) -> Vector<D> {
        let term_i = pressure_term[i];
        let (start, end) = range(self.lists.inner(), i);
        let mut sum = self.wall_gradient_sum[i] * (2.0 * term_i);
        for (&j, gradient) in self.lists.inner().indices[start..end]
            .iter()
            .zip(&self.fluid_gradient[start..end])
        {
            let j = j as usize;
            sum += gradient * (mass[j] * (term_i + pressure_term[j]));
        }
        sum * -self.gradient_correction
    }

    /// The density rate Σ_j m_j (a_i − a_j)·∇_i W_ij + a_i·Σ_b m_b ∇_i W_ib that the
    /// pressure accelerations `acceleration` cause, the walls held still: the linear part of
    /// [`Self::divergence_at`] in a pressure solve, whose walls' own motion is known.
    #[inline]
    pub fn pressure_divergence_at(
        &self,
        i: usize,
        mass: &[Real],
        acceleration: &[Vector<D>],
    ) -> Real {
        let a_i = acceleration[i];
        let (start, end) = range(self.lists.inner(), i);
        let mut sum = a_i.dot(&self.wall_gradient_sum[i]);
        for (&j, gradient) in self.lists.inner().indices[start..end]
            .iter()
            .zip(&self.fluid_gradient[start..end])
        {
            let j = j as usize;
            sum += mass[j] * (a_i - acceleration[j]).dot(gradient);
        }
        sum
    }

    /// The SPH divergence Σ_j m_j (u_i − u_j)·∇_i W_ij + Σ_b m_b (u_i − u_b)·∇_i W_ib of a
    /// velocity-like field `u` (continuity equation, Monaghan 1992, eq. 2.9), with `wall` the
    /// walls' value of the field (their velocity or acceleration).
    pub fn divergence(
        &self,
        mass: &[Real],
        field: &[Vector<D>],
        wall: &[Vector<D>],
        divergence: &mut [Real],
    ) {
        divergence
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, div_i)| *div_i = self.divergence_at(i, mass, field, wall));
    }

    /// [`Self::divergence`] of particle `i`, for solvers that fuse it with their own
    /// per-particle update in one pass.
    #[inline]
    pub fn divergence_at(
        &self,
        i: usize,
        mass: &[Real],
        field: &[Vector<D>],
        wall: &[Vector<D>],
    ) -> Real {
        let u_i = field[i];
        let (start, end) = range(self.lists.inner(), i);
        let mut sum = 0.0;
        for (&j, gradient) in self.lists.inner().indices[start..end]
            .iter()
            .zip(&self.fluid_gradient[start..end])
        {
            let j = j as usize;
            sum += mass[j] * (u_i - field[j]).dot(gradient);
        }
        self.add_wall_divergence(i, u_i, wall, sum)
    }

    /// `sum` plus the walls' part Σ_b m_b (u_i − u_b)·∇_i W_ib of [`Self::divergence_at`],
    /// for the field value `u_i` of particle `i` and the walls' values `wall` (added term by
    /// term to `sum`, so [`Self::divergence_at`] keeps its rounding).
    #[inline]
    pub fn add_wall_divergence(
        &self,
        i: usize,
        u_i: Vector<D>,
        wall: &[Vector<D>],
        mut sum: Real,
    ) -> Real {
        let (start, end) = range(self.lists.contact(), i);
        for (&b, gradient) in self.lists.contact().indices[start..end]
            .iter()
            .zip(&self.wall_gradient[start..end])
        {
            let b = b as usize;
            sum += self.rest_density * self.walls.volume[b] * (u_i - wall[b]).dot(gradient);
        }
        sum
    }
}

/// Fewest particles per rayon task in the per-particle passes of the solves.
pub(crate) const MIN_LEN: usize = 256;

#[inline(always)]
fn range(list: &NeighbourList, i: usize) -> (usize, usize) {
    (list.offsets[i] as usize, list.offsets[i + 1] as usize)
}

#[cfg(test)]
mod tests {
    use geosph_core::{Real, Vector};
    use geosph_kernels::{CubicSpline, Kernel, QuinticSpline, WendlandC2};
    use geosph_sph::lattice::for_each_lattice_offset;

    /// |Σ_j (p_i + p_j) ∇_i W_ij| over a filled lattice for p_j = (−1)^(row of j) (p_i = 1 at
    /// row 0) and for p_j = row of j (p_i = 0).
    fn row_mode_forces<K: Kernel<2>>(kernel: &K, dx: Real) -> (Real, Real) {
        let (mut alternating, mut linear) = (Vector::<2>::zeros(), Vector::<2>::zeros());
        for_each_lattice_offset::<2>(kernel.support_radius(), dx, |x| {
            let row = (x[1] / dx).round() as i64;
            let sign = if row % 2 == 0 { 1.0 } else { -1.0 };
            alternating += kernel.gradient(&-x) * (1.0 + sign);
            linear += kernel.gradient(&-x) * row as Real;
        });
        (alternating.norm(), linear.norm())
    }

    /// The pressure p_j = (−1)^(row of j) is a null mode of the symmetric pressure force on a
    /// lattice (`docs/incompressible.md`, "Still water"): its force vanishes for every kernel,
    /// while a pressure rising by one per row, of the same size, is felt.
    #[test]
    fn alternating_row_pressure_exerts_no_force_on_a_lattice_particle() {
        let dx: Real = 0.01;
        for (name, (alternating, linear)) in [
            (
                "wendland-c2",
                row_mode_forces(&WendlandC2::<2>::new(1.3 * dx), dx),
            ),
            ("cubic", row_mode_forces(&CubicSpline::<2>::new(dx), dx)),
            (
                "quintic",
                row_mode_forces(&QuinticSpline::<2>::new(1.3 * dx), dx),
            ),
        ] {
            println!("{name}: |F| alternating {alternating:.3e}, linear {linear:.3e}");
            assert!(alternating < 1e-9 * linear, "{name}");
        }
    }
}
