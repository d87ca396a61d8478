//! Weakly compressible SPH: the rates of the momentum and continuity equations.

use geosph_boundary::adami::FlowView;
use geosph_boundary::{DummyAdami2012, WallParticles};
use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::SearchError;
use geosph_sph::{
    Inviscid, NoShift, NoSps, PairLists, ParticleShifting, SubParticleStress, ViscousTerm,
    max_speed,
};
use geosph_time::{ExplicitSystem, Rates};
use rayon::prelude::*;

use crate::diffusion::{DiffusionTerm, NoDiffusion};
use crate::gas::{GasDynamics, GasViscosity};
use crate::surface_tension::SurfaceTension;
use geosph_sph::eos::EquationOfState;

mod rate_pass;

use rate_pass::RatePass;

/// How the density evolves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DensityMode {
    /// Integrate the continuity equation dρ_i/dt = Σ_j m_j v_ij·∇_i W_ij (+ diffusion).
    Continuity,
    /// Sum ρ_i = Σ_j m_j W_ij over fluid and wall neighbours after every neighbour update.
    Summation,
}

/// The physics of one WCSPH rate evaluation, monomorphised over the kernel `K`; the pair loop
/// of the rates is monomorphised over the viscous and diffusion terms, the particle shift
/// and the SPS stress as well, resolved from [`ViscousTerm`], [`DiffusionTerm`],
/// [`WcsphSystem::shifting`] ([`geosph_sph::ShiftTerm`]) and [`WcsphSystem::sps`]
/// ([`geosph_sph::TurbulenceTerm`]) once per evaluation.
///
/// Momentum in the symmetric, momentum-conserving form (Monaghan 1992, eq. 3.3):
///
/// dv_i/dt = −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij + viscosity + SPS stress + g,
///
/// where j runs over fluid and wall neighbours; a wall particle has mass ρ₀ V_w and the
/// pressure and density of [`DummyAdami2012`]. Continuity:
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij + D_i, with the prescribed wall velocity for walls
/// and the diffusion D_i over fluid neighbours only.
///
/// A gas ([`WcsphSystem::gas`]) takes its pressure from its density and internal energy and
/// integrates the energy equation of [`crate::gas`], with its own artificial viscosity in
/// place of the viscous term (the loop is then monomorphised over [`GasViscosity`], without
/// diffusion, shifting or SPS, which a gas scene refuses).
pub struct WcsphSystem<const D: usize, K: Kernel<D>> {
    /// Smoothing kernel.
    pub kernel: K,
    /// Fluid–fluid, fluid–wall and wall–fluid pairs, with their Verlet skin and Z-order
    /// schedule.
    pub lists: PairLists<D>,
    /// Equation of state.
    pub eos: EquationOfState,
    /// Viscous term.
    pub viscosity: ViscousTerm,
    /// Density diffusion.
    pub diffusion: DiffusionTerm<D>,
    /// Body-force acceleration g.
    pub gravity: Vector<D>,
    /// 1/f of [`lattice_gradient_factor`](geosph_sph::lattice::lattice_gradient_factor) with
    /// the particles' volume dx^D (1: off), on every pressure-gradient term, so that the
    /// pressure holding still water up is ρ₀ g (H − y) on the lattice (default 1; the scene
    /// builder sets it).
    pub gradient_correction: Real,
    /// XSPH factor ε (0: off) of dx/dt = v + ε Σ_j m_j/ρ̄_ij (v_j − v_i) W_ij (Monaghan 1989).
    pub xsph: Real,
    /// Particle shifting (off: `None`), added to the drift like XSPH.
    pub shifting: Option<ParticleShifting>,
    /// Sub-particle-scale turbulence (off: `None`).
    pub sps: Option<SubParticleStress<D>>,
    /// A gas: p = p(ρ, e) and the energy equation (off: `None`, a barotropic liquid).
    pub gas: Option<GasDynamics>,
    /// Surface tension between two phases (off: `None`), added after the pair loop.
    pub surface_tension: Option<SurfaceTension<D>>,
    /// Lattice spacing Δx (the reference distance of shifting's anti-clustering term).
    pub spacing: Real,
    /// The step Δt being taken (set by the solver before each step; shifting scales with it).
    pub time_step: Real,
    /// Continuity or summation.
    pub density_mode: DensityMode,
    /// Replace negative pressures by zero (suppresses tensile clumping at free surfaces at the
    /// price of a slightly compressive surface layer).
    pub clamp_negative_pressure: bool,
    /// Wall particles and their condition.
    pub walls: WallParticles<D>,
    /// Wall condition.
    pub wall_condition: DummyAdami2012<D>,
    /// Set by the solver when the next neighbour update should re-initialise the density
    /// with a Shepard filter.
    pub shepard_due: bool,
    volume: Vec<Real>,
    /// p_i / ρ_i² of every particle, computed once per evaluation.
    pressure_term: Vec<Real>,
    /// A gas's c_i of every particle, computed once per evaluation (empty for a liquid).
    sound_speed: Vec<Real>,
}

impl<const D: usize, K: Kernel<D>> WcsphSystem<D, K> {
    /// A system on `domain` with fixed `walls`, whose pair lists have a Verlet skin of
    /// `skin_fraction` × the support radius ([`PairLists`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        kernel: K,
        domain: geosph_core::Domain<D>,
        eos: EquationOfState,
        viscosity: ViscousTerm,
        diffusion: DiffusionTerm<D>,
        gravity: Vector<D>,
        walls: WallParticles<D>,
        wall_condition: DummyAdami2012<D>,
        skin_fraction: Real,
    ) -> Result<Self, SearchError> {
        let lists = PairLists::new(
            domain,
            kernel.support_radius(),
            skin_fraction,
            &walls.position,
            true,
        )?;
        Ok(Self {
            kernel,
            lists,
            eos,
            viscosity,
            diffusion,
            gravity,
            gradient_correction: 1.0,
            xsph: 0.0,
            shifting: None,
            sps: None,
            gas: None,
            surface_tension: None,
            spacing: 0.0,
            time_step: 0.0,
            density_mode: DensityMode::Continuity,
            clamp_negative_pressure: false,
            walls,
            wall_condition,
            shepard_due: false,
            volume: Vec::new(),
            pressure_term: Vec::new(),
            sound_speed: Vec::new(),
        })
    }

    /// p_i = p(ρ_i) for every particle (clamped at zero when asked); for a gas
    /// p_i = p(ρ_i, e_i).
    ///
    /// # Panics
    /// For a gas whose particles have no internal-energy field (a scene sets it from the
    /// fluid's initial pressure).
    pub fn update_pressure(&self, fluid: &mut Particles<D>) {
        let eos = self.eos;
        let clamp = self.clamp_negative_pressure;
        let Particles {
            density,
            pressure,
            energy,
            ..
        } = fluid;
        let pressure = pressure.get_or_insert_with(Vec::new);
        pressure.resize(density.len(), 0.0);
        if let Some(gas) = &self.gas {
            let energy = energy
                .as_deref()
                .expect("a gas's particles carry their internal energy");
            let law = gas.law;
            (
                pressure.par_iter_mut(),
                density.par_iter(),
                energy.par_iter(),
            )
                .into_par_iter()
                .with_min_len(1024)
                .for_each(|(p, &rho, &e)| *p = law.pressure(rho, e));
            return;
        }
        pressure
            .par_iter_mut()
            .zip(density.par_iter())
            .for_each(|(p, &rho)| {
                let value = eos.pressure(rho);
                *p = if clamp { value.max(0.0) } else { value };
            });
    }

    /// ρ_i = Σ_j m_j W_ij over fluid neighbours plus Σ_w ρ₀ V_w W_iw over walls, divided by
    /// the Shepard sum Σ_j V_j W_ij (with V_w for walls) when `shepard`.
    fn sum_density(&mut self, fluid: &mut Particles<D>, shepard: bool) {
        let (kernel, lists, walls) = (&self.kernel, &self.lists, &self.walls);
        let rest_density = self.eos.rest_density;
        let Particles {
            position,
            mass,
            density,
            ..
        } = fluid;
        self.volume.resize(position.len(), 0.0);
        self.volume
            .par_iter_mut()
            .zip(mass.par_iter())
            .zip(density.par_iter())
            .for_each(|((v, m), rho)| *v = m / rho);
        let volume = &self.volume;
        density.par_iter_mut().enumerate().for_each(|(i, rho_i)| {
            let (mut mass_sum, mut volume_sum) = (0.0, 0.0);
            lists.for_each_neighbour_and_self(kernel, position, i, |pair| {
                let w = kernel.value(pair.r);
                mass_sum += mass[pair.index] * w;
                volume_sum += volume[pair.index] * w;
            });
            lists.for_each_wall(kernel, position, &walls.position, i, |pair| {
                let w = kernel.value(pair.r);
                mass_sum += rest_density * walls.volume[pair.index] * w;
                volume_sum += walls.volume[pair.index] * w;
            });
            *rho_i = if shepard {
                mass_sum / volume_sum
            } else {
                mass_sum
            };
        });
    }

    /// XSPH position correction δv_i = ε Σ_j m_j / ρ̄_ij (v_j − v_i) W_ij (Monaghan 1989),
    /// added to `correction` when `add` (it holds the shift), written over it otherwise.
    /// Whether the rates carry a position correction δv (XSPH or shifting is on), which the
    /// integrator then adds to the drift ([`geosph_time::Integrator::enable_position_correction`]).
    pub fn corrects_position(&self) -> bool {
        self.xsph > 0.0 || self.shifting.is_some()
    }

    fn xsph_correction(&self, fluid: &Particles<D>, correction: &mut [Vector<D>], add: bool) {
        let epsilon = self.xsph;
        let (kernel, lists) = (&self.kernel, &self.lists);
        correction.par_iter_mut().enumerate().for_each(|(i, dv)| {
            let mut sum = Vector::<D>::zeros();
            lists.for_each_neighbour(kernel, &fluid.position, i, |pair| {
                let (j, w) = (pair.index, kernel.value(pair.r));
                let rho_mean = 0.5 * (fluid.density[i] + fluid.density[j]);
                sum += (fluid.velocity[j] - fluid.velocity[i]) * (fluid.mass[j] / rho_mean * w);
            });
            *dv = if add {
                *dv + sum * epsilon
            } else {
                sum * epsilon
            };
        });
    }
}

impl<const D: usize, K: Kernel<D>> ExplicitSystem<D> for WcsphSystem<D, K> {
    type Error = SearchError;

    fn prepare(&mut self, fluid: &mut Particles<D>) -> Result<(), SearchError> {
        self.lists.exchange_halo(fluid);
        self.lists
            .update(&mut fluid.position, &self.walls.position)?;
        let shepard = std::mem::take(&mut self.shepard_due);
        if shepard || self.density_mode == DensityMode::Summation {
            self.sum_density(
                fluid,
                shepard && self.density_mode == DensityMode::Continuity,
            );
            self.update_pressure(fluid);
            // The halo's new densities were summed over part of their neighbours.
            self.lists.exchange_halo(fluid);
        }
        Ok(())
    }

    fn rates(&mut self, fluid: &Particles<D>, _time: Real, rates: &mut Rates<D>) {
        let pressure = fluid
            .pressure
            .as_deref()
            .expect("WCSPH particles carry a pressure field");
        let eos = self.eos;
        self.wall_condition.update(
            &self.kernel,
            self.lists.domain(),
            &mut self.walls,
            FlowView {
                position: &fluid.position,
                velocity: &fluid.velocity,
                pressure,
                density: &fluid.density,
            },
            self.lists.wall_side(),
            |p| eos.density(p),
        );
        self.volume.resize(fluid.len(), 0.0);
        self.pressure_term.resize(fluid.len(), 0.0);
        let correction = self.gradient_correction;
        (
            self.volume.par_iter_mut(),
            self.pressure_term.par_iter_mut(),
            fluid.mass.par_iter(),
            fluid.density.par_iter(),
            pressure.par_iter(),
        )
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(v, term, m, rho, p)| {
                *v = m / rho;
                *term = correction * p / (rho * rho);
            });
        if let Some(gas) = &self.gas {
            // c_i, and the pressure term c p_i V_i² of the particle-volume form.
            self.sound_speed.resize(fluid.len(), 0.0);
            let law = gas.law;
            (
                self.sound_speed.par_iter_mut(),
                self.pressure_term.par_iter_mut(),
                self.volume.par_iter(),
                fluid.density.par_iter(),
                pressure.par_iter(),
            )
                .into_par_iter()
                .with_min_len(1024)
                .for_each(|(c, term, v, &rho, &p)| {
                    *c = law.sound_speed(rho, p);
                    *term = correction * p * v * v;
                });
        }
        self.diffusion.prepare(
            &self.kernel,
            self.lists.domain(),
            &fluid.position,
            &fluid.density,
            &self.volume,
            self.lists.inner(),
        );

        if let Some(sps) = &mut self.sps {
            sps.update(
                &self.kernel,
                &self.lists,
                &fluid.position,
                &fluid.velocity,
                &self.volume,
                &fluid.density,
                &self.walls,
                self.gradient_correction,
            );
        }
        let shift = self.shifting.map(|shifting| {
            let owned = self.lists.owned(fluid.len());
            let mut speed = [max_speed(&fluid.velocity[..owned])];
            self.lists.max_over_ranks(&mut speed);
            let speed = speed[0];
            shifting.step(&self.kernel, self.spacing, speed, self.time_step)
        });
        let pass = RatePass {
            kernel: self.kernel,
            lists: &self.lists,
            gravity: self.gravity,
            walls: &self.walls,
            volume: &self.volume,
            pressure_term: &self.pressure_term,
            gradient_correction: self.gradient_correction,
            summation: self.density_mode == DensityMode::Summation,
            fluid,
            rates: &mut *rates,
            diffusion: &self.diffusion,
            shift,
            sps: self.sps.as_ref(),
        };
        match &self.gas {
            None => self.viscosity.visit(pass),
            Some(gas) => {
                let viscosity = GasViscosity {
                    sound_speed: &self.sound_speed,
                    alpha: gas.alpha,
                    beta: gas.beta,
                    smoothing_length: self.kernel.smoothing_length(),
                };
                pass.run(Inviscid, &NoDiffusion, NoShift, NoSps, viscosity);
            }
        }
        if let Some(tension) = &mut self.surface_tension {
            tension.add_acceleration(
                &self.kernel,
                &self.lists,
                fluid,
                &self.volume,
                self.gradient_correction,
                &mut rates.acceleration,
            );
        }
        if self.xsph > 0.0 {
            let add = shift.is_some();
            self.xsph_correction(fluid, &mut rates.position_correction, add);
        }
    }

    fn finish_stage(&mut self, fluid: &mut Particles<D>) {
        self.update_pressure(fluid);
    }

    /// The halo's state from its owners: the last stage moved every particle of this rank by
    /// its own rates, which are right within one support of the owned particles only.
    fn begin_stage(&mut self, fluid: &mut Particles<D>) {
        self.lists.exchange_halo(fluid);
    }
}
