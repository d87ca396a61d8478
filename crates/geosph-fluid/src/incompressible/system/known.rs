//! The known (non-pressure) acceleration of the pressure solvers: gravity, the viscous term
//! and the walls' hydrostatic head, and the velocity the walls show the viscous term.

use geosph_boundary::{Slip, WallParticles};
use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_sph::{Pair, Viscosity, ViscousVisitor};
use rayon::prelude::*;

use super::{PressureSystem, WallPressure, range};

impl<const D: usize, K: Kernel<D>> PressureSystem<D, K> {
    /// The known acceleration: gravity, the viscous term, and with
    /// [`WallPressure::Hydrostatic`] the wall head −c Σ_b m_b (h_b/ρ_i) ∇_i W_ib,
    /// h_b = max((g − a_b)·(x_b − x_i), −p_i/ρ_i) with p_i the pressure in `fluid` (the last
    /// step's).
    pub fn non_pressure_acceleration(&self, fluid: &Particles<D>, acceleration: &mut [Vector<D>]) {
        self.viscosity.visit(KnownAcceleration {
            system: self,
            fluid,
            dt: None,
            out: acceleration,
        });
    }

    /// The velocity ũ_w every wall particle shows the viscous term, by the walls' slip
    /// condition ([`Slip::viscous_velocity`]): for a laminar term at a no-slip wall
    /// ũ_w = 2 u_w − Σ_f v_f W_wf / Σ_f W_wf (Adami, Hu & Adams 2012, eq. 22), so that the
    /// flow's velocity extrapolated to the wall surface is the wall's (without it the no-slip
    /// plane sits about a spacing inside the wall); at a free-slip wall the flow's own
    /// Shepard velocity; for an artificial term at a no-slip wall u_w. u_w where no fluid is
    /// near.
    pub fn wall_viscous_velocity(&mut self, fluid: &Particles<D>) {
        let physical = self.viscosity.kinematic_viscosity() > 0.0;
        let slip = self.wall_slip;
        let (kernel, lists) = (&self.kernel, &self.lists);
        let WallParticles {
            position: wall_position,
            velocity: wall_velocity,
            viscous_velocity,
            ..
        } = &mut self.walls;
        if !physical && slip == Slip::NoSlip {
            viscous_velocity.copy_from_slice(wall_velocity);
            return;
        }
        let (wall_position, wall_velocity) = (&*wall_position, &*wall_velocity);
        viscous_velocity
            .par_iter_mut()
            .enumerate()
            .for_each(|(w, shown)| {
                let (mut sum, mut weight) = (Vector::<D>::zeros(), 0.0);
                lists.for_each_particle_near_wall(
                    kernel,
                    &fluid.position,
                    wall_position,
                    w,
                    |pair| {
                        let value = kernel.value(pair.r);
                        sum += fluid.velocity[pair.index] * value;
                        weight += value;
                    },
                );
                *shown = if weight > 0.0 {
                    slip.viscous_velocity(physical, wall_velocity[w], sum / weight)
                } else {
                    wall_velocity[w]
                };
            });
    }

    /// The predicted velocity v*_i = v_i + Δt a*_i of every particle into `predicted`, with
    /// a* the [known acceleration](Self::non_pressure_acceleration).
    pub fn predict_velocity(&self, fluid: &Particles<D>, dt: Real, predicted: &mut [Vector<D>]) {
        self.viscosity.visit(KnownAcceleration {
            system: self,
            fluid,
            dt: Some(dt),
            out: predicted,
        });
    }

    /// [`Self::non_pressure_acceleration`] of particle `i` with the viscous term `viscosity`.
    #[inline]
    fn non_pressure_acceleration_at<V: Viscosity<D>>(
        &self,
        viscosity: V,
        i: usize,
        fluid: &Particles<D>,
    ) -> Vector<D> {
        let (kernel, domain, gravity) = (self.kernel, self.lists.domain(), self.gravity);
        let walls = &self.walls;
        let rho0 = self.rest_density;
        let eta2 = 0.01 * kernel.smoothing_length().powi(2);
        let Particles {
            position,
            velocity,
            mass,
            density,
            pressure,
            ..
        } = fluid;
        let previous_pressure = pressure.as_deref().expect("pressure is enabled");
        let (x_i, v_i, rho_i) = (position[i], velocity[i], density[i]);
        let mut sum = gravity;
        let (start, end) = range(self.lists.inner(), i);
        for (&j, &grad) in self.lists.inner().indices[start..end]
            .iter()
            .zip(&self.fluid_gradient[start..end])
        {
            let j = j as usize;
            if j == i {
                continue;
            }
            let r_ij = domain.displacement(&x_i, &position[j]);
            let r2 = r_ij.norm_squared();
            sum += viscosity.acceleration(&Pair::new(
                r_ij,
                r2,
                eta2,
                grad,
                v_i - velocity[j],
                rho_i,
                density[j],
                mass[j],
            ));
        }
        let (start, end) = range(self.lists.contact(), i);
        for (&b, &grad) in self.lists.contact().indices[start..end]
            .iter()
            .zip(&self.wall_gradient[start..end])
        {
            let b = b as usize;
            let r_ib = domain.displacement(&x_i, &walls.position[b]);
            let r2 = r_ib.norm_squared();
            let mass_b = rho0 * walls.volume[b];
            sum += viscosity.acceleration(&Pair::new(
                r_ib,
                r2,
                eta2,
                grad,
                v_i - V::wall_velocity(walls, b),
                rho_i,
                rho_i,
                mass_b,
            ));
            if self.wall_pressure == WallPressure::Hydrostatic {
                // h_b = (g − a_b)·(x_b − x_i) with x_b − x_i = −r_ib, limited so
                // that p_b = p_i + ρ_i h_b stays ≥ 0 for the last step's p_i.
                let h_b = (-(gravity - walls.acceleration[b]).dot(&r_ib))
                    .max(-previous_pressure[i] / rho_i);
                sum -= grad * (self.gradient_correction * mass_b * h_b / rho_i);
            }
        }
        sum
    }
}

/// One pass of the known acceleration a*, monomorphised over the viscous term: into `out` as
/// a*, or, with `dt`, as the predicted velocity v + Δt a*.
struct KnownAcceleration<'a, const D: usize, K: Kernel<D>> {
    system: &'a PressureSystem<D, K>,
    fluid: &'a Particles<D>,
    dt: Option<Real>,
    out: &'a mut [Vector<D>],
}

impl<const D: usize, K: Kernel<D>> ViscousVisitor<D> for KnownAcceleration<'_, D, K> {
    type Output = ();

    fn visit<V: Viscosity<D>>(self, viscosity: V) -> Self::Output {
        let Self {
            system,
            fluid,
            dt,
            out,
        } = self;
        let known = |i| system.non_pressure_acceleration_at(viscosity, i, fluid);
        match dt {
            Some(dt) => out
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, v)| *v = fluid.velocity[i] + known(i) * dt),
            None => out
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, a_i)| *a_i = known(i)),
        }
    }
}
