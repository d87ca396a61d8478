//! The generalised wall boundary condition of Adami, Hu & Adams (2012).

use geosph_core::{Domain, NeighbourList, Real, Vector};
use geosph_kernels::Kernel;
use rayon::prelude::*;

use crate::walls::{Slip, WallParticles};

/// The flow fields that walls read (borrowed from the fluid's particles).
#[derive(Clone, Copy, Debug)]
pub struct FlowView<'a, const D: usize> {
    /// Positions x_f.
    pub position: &'a [Vector<D>],
    /// Velocities v_f.
    pub velocity: &'a [Vector<D>],
    /// Pressures p_f.
    pub pressure: &'a [Real],
    /// Densities ρ_f.
    pub density: &'a [Real],
}

/// Dummy particles with the generalised wall condition of Adami, Hu & Adams (2012),
/// J. Comput. Phys. 231:7057–7075.
///
/// Every wall particle w takes the Shepard-weighted pressure of its flow neighbours f plus the
/// hydrostatic head between them (eq. 27):
///
/// p_w = [ Σ_f p_f W_wf + (g − a_w) · Σ_f ρ_f (x_w − x_f) W_wf ] / Σ_f W_wf,
///
/// its density from the equation of state, ρ_w = ρ(p_w), and for viscous terms the velocity
/// ũ_w of [`Slip::viscous_velocity`] with the flow's Shepard velocity Σ_f v_f W_wf / Σ_f W_wf
/// (no-slip: eq. 22 for a physical term). A wall particle without flow neighbours gets
/// p_w = 0 and ũ_w = u_w.
///
/// With `clamp_negative` the wall pressure is max(p_w, 0): a wall pushes but never pulls, so
/// free-surface particles next to a wall (negative pressure from the truncated kernel) do not
/// stick to it. This departs from Adami et al., who use no clamp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DummyAdami2012<const D: usize> {
    /// Body-force acceleration g.
    pub gravity: Vector<D>,
    /// No-slip or free-slip.
    pub slip: Slip,
    /// Whether the flow's viscous term is physical (laminar) rather than artificial.
    pub physical_viscosity: bool,
    /// Clamp negative wall pressure to zero.
    pub clamp_negative: bool,
}

impl<const D: usize> DummyAdami2012<D> {
    /// Recomputes pressure, density and viscous velocity of every wall particle.
    ///
    /// `wall_flow` lists, for each wall particle, its flow neighbours; `density_from_pressure`
    /// inverts the flow's equation of state.
    pub fn update<K: Kernel<D>>(
        &self,
        kernel: &K,
        domain: &Domain<D>,
        walls: &mut WallParticles<D>,
        flow: FlowView<'_, D>,
        wall_flow: &NeighbourList,
        density_from_pressure: impl Fn(Real) -> Real + Sync,
    ) {
        let WallParticles {
            position,
            velocity,
            acceleration,
            pressure,
            density,
            viscous_velocity,
            ..
        } = walls;
        // Most wall particles of a tank have no flow near them: they skip the inversion.
        let density_at_zero = density_from_pressure(0.0);
        pressure
            .par_iter_mut()
            .zip(density.par_iter_mut())
            .zip(viscous_velocity.par_iter_mut())
            .enumerate()
            .for_each(|(w, ((p_w, rho_w), u_w))| {
                let body = self.gravity - acceleration[w];
                let mut weight_sum = 0.0;
                let mut pressure_sum = 0.0;
                let mut head_sum = Vector::<D>::zeros();
                let mut velocity_sum = Vector::<D>::zeros();
                for &f in wall_flow.neighbours(w) {
                    let f = f as usize;
                    let r_wf = domain.displacement(&position[w], &flow.position[f]);
                    let weight = kernel.value(r_wf.norm());
                    weight_sum += weight;
                    pressure_sum += flow.pressure[f] * weight;
                    head_sum += r_wf * (flow.density[f] * weight);
                    velocity_sum += flow.velocity[f] * weight;
                }
                if weight_sum > 0.0 {
                    let extrapolated = (pressure_sum + body.dot(&head_sum)) / weight_sum;
                    *p_w = if self.clamp_negative {
                        extrapolated.max(0.0)
                    } else {
                        extrapolated
                    };
                    *u_w = self.slip.viscous_velocity(
                        self.physical_viscosity,
                        velocity[w],
                        velocity_sum / weight_sum,
                    );
                } else {
                    *p_w = 0.0;
                    *u_w = velocity[w];
                }
                *rho_w = if *p_w == 0.0 {
                    density_at_zero
                } else {
                    density_from_pressure(*p_w)
                };
            });
    }
}
