//! The pair loop of one WCSPH rate evaluation, monomorphised over the terms a scene has.

use geosph_boundary::WallParticles;
use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_sph::{
    NoShift, NoSps, Pair, PairLists, ShiftStep, ShiftSums, ShiftTerm, SubParticleStress,
    TurbulenceTerm, Viscosity, ViscousVisitor,
};
use geosph_time::Rates;
use rayon::iter::Either;
use rayon::prelude::*;

use crate::diffusion::{DensityDiffusion, DiffusionTerm, DiffusionVisitor};
use crate::gas::{Barotropic, EnergyEquation};

/// The pair loop of one rate evaluation: dv_i/dt and dρ_i/dt of every particle, dispatched
/// by [`ViscousTerm::visit`] and then [`DiffusionTerm::visit`] to [`RatePass::run`],
/// monomorphised over both terms.
pub(super) struct RatePass<'a, const D: usize, K: Kernel<D>> {
    pub(super) kernel: K,
    pub(super) lists: &'a PairLists<D>,
    pub(super) gravity: Vector<D>,
    pub(super) walls: &'a WallParticles<D>,
    pub(super) volume: &'a [Real],
    /// `pressure_term` = c p/ρ² with c the gradient correction, which the wall terms take too
    /// (a gas's: c p V², [`EnergyEquation::pressure_weight`]).
    pub(super) pressure_term: &'a [Real],
    pub(super) gradient_correction: Real,
    pub(super) summation: bool,
    pub(super) fluid: &'a Particles<D>,
    pub(super) rates: &'a mut Rates<D>,
    pub(super) diffusion: &'a DiffusionTerm<D>,
    /// The shift of this step, when shifting is on: its sums ride along in the pair loop.
    pub(super) shift: Option<ShiftStep>,
    /// The SPS stresses of this evaluation, when SPS is on.
    pub(super) sps: Option<&'a SubParticleStress<D>>,
}

impl<const D: usize, K: Kernel<D>> ViscousVisitor<D> for RatePass<'_, D, K> {
    type Output = ();

    fn visit<V: Viscosity<D>>(self, viscosity: V) {
        let diffusion = self.diffusion;
        diffusion.visit(WithViscosity {
            pass: self,
            viscosity,
        });
    }
}

/// [`RatePass`] with its viscous term resolved, waiting for the diffusion term.
struct WithViscosity<'a, const D: usize, K: Kernel<D>, V> {
    pass: RatePass<'a, D, K>,
    viscosity: V,
}

impl<const D: usize, K: Kernel<D>, V: Viscosity<D>> DiffusionVisitor<D>
    for WithViscosity<'_, D, K, V>
{
    type Output = ();

    fn visit<F: DensityDiffusion<D>>(self, diffusion: &F) {
        let viscosity = self.viscosity;
        match (self.pass.shift, self.pass.sps) {
            (None, None) => self
                .pass
                .run(viscosity, diffusion, NoShift, NoSps, Barotropic),
            (Some(step), None) => self.pass.run(viscosity, diffusion, step, NoSps, Barotropic),
            (None, Some(sps)) => {
                self.pass
                    .run(viscosity, diffusion, NoShift, sps.term(), Barotropic)
            }
            (Some(step), Some(sps)) => {
                self.pass
                    .run(viscosity, diffusion, step, sps.term(), Barotropic)
            }
        }
    }
}

impl<const D: usize, K: Kernel<D>> RatePass<'_, D, K> {
    pub(super) fn run<
        V: Viscosity<D>,
        F: DensityDiffusion<D>,
        S: ShiftTerm,
        T: TurbulenceTerm<D>,
        E: EnergyEquation<D>,
    >(
        self,
        viscosity: V,
        diffusion: &F,
        shift: S,
        sps: T,
        energy: E,
    ) {
        let Self {
            kernel,
            lists,
            gravity,
            walls,
            volume,
            pressure_term,
            gradient_correction,
            summation,
            fluid,
            rates,
            ..
        } = self;
        let h = kernel.smoothing_length();
        let Particles {
            position,
            velocity,
            mass,
            density,
            ..
        } = fluid;
        // The energy rates exist only for a gas: a liquid's loop zips an empty stand-in.
        let n = rates.acceleration.len();
        assert!(
            !E::ON || rates.energy_rate.len() == n,
            "a gas's integrator carries its energy rate (Integrator::enable_energy)"
        );
        let energy_rate = if E::ON {
            Either::Left(rates.energy_rate.par_iter_mut().map(Some))
        } else {
            Either::Right(rayon::iter::repeat_n((), n).map(|()| None))
        };
        // Likewise the position correction, which only shifting writes here.
        assert!(
            !S::ON || rates.position_correction.len() == n,
            "a shifted fluid's integrator carries a position correction \
             (Integrator::enable_position_correction)"
        );
        let correction = if S::ON {
            Either::Left(rates.position_correction.par_iter_mut().map(Some))
        } else {
            Either::Right(rayon::iter::repeat_n((), n).map(|()| None))
        };
        (
            rates.acceleration.par_iter_mut(),
            rates.density_rate.par_iter_mut(),
            correction,
            energy_rate,
        )
            .into_par_iter()
            .enumerate()
            .for_each(
                |(i, (acceleration, density_rate, correction, energy_rate))| {
                    let (v_i, rho_i, mass_i) = (velocity[i], density[i], mass[i]);
                    let p_over_rho2_i = pressure_term[i];
                    let eta2 = 0.01 * h * h;
                    let mut a_i = gravity;
                    let mut drho_i = 0.0;
                    let mut de_i = 0.0;
                    let mut sums = ShiftSums::<D>::default();
                    lists.for_each_neighbour(&kernel, position, i, |neighbour| {
                        let (j, grad) = (neighbour.index, neighbour.grad);
                        let pair = Pair::new(
                            neighbour.r_ij,
                            neighbour.r2,
                            eta2,
                            grad,
                            v_i - velocity[j],
                            rho_i,
                            density[j],
                            mass[j],
                        );
                        a_i -= grad
                            * E::pressure_weight(mass_i, mass[j], p_over_rho2_i, pressure_term[j]);
                        a_i += viscosity.acceleration(&pair);
                        if T::ON {
                            a_i += sps.acceleration(i, j, mass[j], &grad);
                        }
                        if E::ON {
                            let (a_viscous, heating) = energy.viscous(i, j, &pair);
                            a_i += a_viscous;
                            de_i += p_over_rho2_i / mass_i * pair.v_ij.dot(&grad) + heating;
                        }
                        drho_i += E::continuity_mass(mass_i, mass[j]) * pair.v_ij.dot(&grad);
                        drho_i += diffusion.rate(i, j, &pair, volume[j]);
                        if S::ON {
                            let w = kernel.value(neighbour.r);
                            shift.add(&mut sums, neighbour.r_ij, w, grad * volume[j]);
                        }
                    });
                    lists.for_each_wall(&kernel, position, &walls.position, i, |neighbour| {
                        let (w, grad) = (neighbour.index, neighbour.grad);
                        let rho_w = walls.density[w];
                        let mass_w = rho_w * walls.volume[w];
                        let pair = Pair::new(
                            neighbour.r_ij,
                            neighbour.r2,
                            eta2,
                            grad,
                            v_i - V::wall_velocity(walls, w),
                            rho_i,
                            rho_w,
                            mass_w,
                        );
                        let p_over_rho2_w =
                            gradient_correction * walls.pressure[w] / (rho_w * rho_w);
                        a_i -= grad * (mass_w * (p_over_rho2_i + p_over_rho2_w));
                        a_i += viscosity.acceleration(&pair);
                        if T::ON {
                            a_i += sps.wall_acceleration(i, mass_w, &grad);
                        }
                        drho_i += mass_w * (v_i - walls.velocity[w]).dot(&grad);
                        if S::ON {
                            let (w_iw, weighted) =
                                (kernel.value(neighbour.r), grad * walls.volume[w]);
                            shift.add(&mut sums, neighbour.r_ij, w_iw, weighted);
                        }
                    });
                    *acceleration = a_i;
                    *density_rate = if summation { 0.0 } else { drho_i };
                    if let Some(correction) = correction {
                        *correction = shift.finish(&sums);
                    }
                    if let Some(energy_rate) = energy_rate {
                        *energy_rate = de_i;
                    }
                },
            );
    }
}
