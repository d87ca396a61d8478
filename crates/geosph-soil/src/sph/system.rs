//! The soil SPH system: kinematics, stress update and momentum of one explicit step (the
//! wall-stress and momentum passes in `system/forces.rs`).

use geosph_boundary::{RepulsiveLiu2012, WallParticles};
use geosph_core::{Matrix, Particles, Real, Tensor3, Vector};
use geosph_kernels::Kernel;
use geosph_kernels::cspm::{MAX_CONDITION_NUMBER, well_conditioned_inverse};
use geosph_neighbours::SearchError;
use geosph_sph::lattice::lattice_gradient_factor;
use geosph_sph::{ArtificialMonaghan1992, PairLists, SolverError, SphSetup};
use rayon::prelude::*;

use crate::constitutive::Constitutive;
use crate::invariants::mean_pressure;
use crate::kinematics::{spin, strain_rate};
use crate::model::SoilModel;
use crate::sph::config::SoilWallConfig;
use crate::sph::diffusion::MeanStressDiffusion;
use crate::sph::terms::{ArtificialStressGray2001, block};
use crate::sph::walls::dummy_velocity;

mod forces;

/// Smallest number of particles a parallel task handles.
const MIN_CHUNK: usize = 256;

/// One explicit step of elastoplastic soil SPH (Bui et al. 2008, Int. J. Numer. Anal. Meth.
/// Geomech. 32:1537), monomorphised over the kernel `K`; the artificial viscosity and the
/// artificial stress are options tested once per pair (a predictable branch). With r_ij = x_i − x_j, ∇_i W_ij = r_ij W'(r)/r, V_j = m_j/ρ_j:
///
/// - velocity gradient (antisymmetric form): L_i = Σ_j V_j (v_j − v_i) ⊗ ∇_i W_ij, then
///   ε̇ = ½(L + Lᵀ), ω = ½(L − Lᵀ), embedded in 3×3 (plane strain in 2D); optionally
///   CSPM-corrected ([`SoilSystem::set_velocity_gradient_correction`]);
/// - continuity: dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij;
/// - stress: σ_i ← [`Constitutive::update`](σ_i, ε̇ Δt, ω Δt) (Jaumann rate, return map),
///   after the optional diffusion of the mean stress ([`MeanStressDiffusion`], from σ^n, with
///   ρ_i following it);
/// - momentum (symmetric form, Bui et al. 2008 eq. 32, with eq. 33 and Gray et al. 2001):
///   dv_i/dt = Σ_j m_j (σ_i/ρ_i² + σ_j/ρ_j² − Π_ij 1 + f_ij^n (R_i + R_j))·∇_i W_ij + g
///   − μ_d v_i, the stresses multiplied by the lattice correction 1/f
///   ([`SoilSystem::gradient_correction`]).
///
/// j runs over soil and dummy wall particles; a dummy particle has mass ρ₀ V_w, the velocity of
/// Bui's rule ([`dummy_velocity`]) and the stress of [`WallStress`](crate::sph::config::WallStress). Artificial viscosity acts
/// between soil particles (Bui et al. 2008) and, with [`SoilWallConfig::viscous`], also
/// between soil and dummy particles.
///
/// The step is staggered like explicit finite elements: the velocity gradient of v^n updates
/// ρ and σ to n+1, the momentum equation with σ^{n+1} gives v^{n+1} = v^n + Δt a, and
/// x^{n+1} = x^n + Δt v^{n+1} (symplectic Euler). Each particle sums its own neighbours
/// (gather), so the result does not depend on the number of threads.
pub struct SoilSystem<const D: usize, K: Kernel<D>> {
    /// Smoothing kernel.
    pub kernel: K,
    /// Soil–soil, soil–wall and wall–soil pairs, with their Verlet skin and Z-order schedule.
    pub lists: PairLists<D>,
    /// Constitutive model.
    pub model: SoilModel,
    /// Gravity g.
    pub gravity: Vector<D>,
    /// Dummy wall particles (their `pressure` holds p = −tr σ_w/3, for output and the
    /// mean-stress diffusion).
    pub walls: WallParticles<D>,
    /// Wall condition.
    pub wall_config: SoilWallConfig,
    /// Reference density ρ₀ of the soil (and of the dummy particles).
    pub rest_density: Real,
    /// Initial particle spacing dx.
    pub spacing: Real,
    /// Elastic P-wave speed c = √((K + 4G/3)/ρ₀).
    pub wave_speed: Real,
    /// 1/f of [`lattice_gradient_factor`] with the particles' volume dx^D, on the stress terms
    /// σ/ρ² of soil and wall particles: the fluid solvers' correction, so that the stress
    /// holding a soil layer up is ρ₀ g (H − y) on the lattice (f = 0.974 for Wendland C2 at
    /// h = 1.3 dx in 2D, which otherwise makes σ_v 2.7 % too large in magnitude).
    pub gradient_correction: Real,
    viscosity: Option<ArtificialMonaghan1992>,
    artificial_stress: Option<ArtificialStressGray2001>,
    repulsive: Option<RepulsiveLiu2012>,
    /// μ_d of the velocity damping (0: off).
    damping_rate: Real,
    /// Whether L_i is CSPM-corrected.
    correct_velocity_gradient: bool,
    diffusion: Option<MeanStressDiffusion<D>>,
    /// g·x̄_w, x̄_w the kernel-weighted centre of the soil around each wall particle (with the
    /// mean-stress diffusion only).
    wall_centre: Vec<Real>,
    wall_stress: Vec<Tensor3>,
    wall_term: Vec<Matrix<D>>,
    /// V_i = m_i/ρ_i, gathered once per step for the kinematics' pair sums.
    particle_volume: Vec<Real>,
    /// p_i = −tr σ_i/3 of σ^n, gathered likewise (with the mean-stress diffusion only).
    particle_pressure: Vec<Real>,
    stress_term: Vec<Matrix<D>>,
    tensile_term: Vec<Matrix<D>>,
    acceleration: Vec<Vector<D>>,
}

impl<const D: usize, K: Kernel<D>> SoilSystem<D, K> {
    /// A system for the soil of `setup` (its `walls`, `domain`, `gravity`, `rest_density`),
    /// whose pair lists have a Verlet skin of `skin_fraction` × the support radius
    /// ([`PairLists`]).
    pub fn new(
        kernel: K,
        setup: SphSetup<D>,
        model: SoilModel,
        viscosity: Option<ArtificialMonaghan1992>,
        artificial_stress: Option<ArtificialStressGray2001>,
        wall_config: SoilWallConfig,
        spacing: Real,
        skin_fraction: Real,
    ) -> Result<Self, SearchError> {
        let lists = PairLists::new(
            setup.domain,
            kernel.support_radius(),
            skin_fraction,
            &setup.walls.position,
            true,
        )?;
        let wave_speed = (model.elastic().p_wave_modulus() / setup.rest_density).sqrt();
        let repulsive = wall_config.repulsive.then_some(RepulsiveLiu2012 {
            sound_speed: wave_speed,
            spacing,
            smoothing_length: kernel.smoothing_length(),
        });
        let mut walls = setup.walls;
        walls.density.fill(setup.rest_density);
        Ok(Self {
            kernel,
            lists,
            model,
            gravity: setup.gravity,
            walls,
            wall_config,
            rest_density: setup.rest_density,
            spacing,
            wave_speed,
            gradient_correction: 1.0
                / lattice_gradient_factor(&kernel, spacing, spacing.powi(D as i32)),
            viscosity,
            artificial_stress,
            repulsive,
            damping_rate: 0.0,
            correct_velocity_gradient: false,
            diffusion: None,
            wall_centre: Vec::new(),
            wall_stress: Vec::new(),
            wall_term: Vec::new(),
            particle_volume: Vec::new(),
            particle_pressure: Vec::new(),
            stress_term: Vec::new(),
            tensile_term: Vec::new(),
            acceleration: Vec::new(),
        })
    }

    /// Sets the velocity damping of Nguyen et al. (2017): μ_d = ξ √(E/(ρ₀ h²)) (0: off).
    pub fn set_damping(&mut self, xi: Real) {
        let h = self.kernel.smoothing_length();
        self.damping_rate =
            xi * (self.model.elastic().youngs_modulus / (self.rest_density * h * h)).sqrt();
    }

    /// Sets μ_d of the velocity damping directly, in 1/s (0: off).
    pub fn set_damping_rate(&mut self, rate: Real) {
        self.damping_rate = rate;
    }

    /// μ_d of the velocity damping.
    pub fn damping_rate(&self) -> Real {
        self.damping_rate
    }

    /// Switches the CSPM correction of the velocity gradient (Chen, Beraun & Carney 1999;
    /// Bonet & Lok 1999; see [`geosph_kernels::cspm`]): L_i = L_i^SPH C_iᵀ with
    /// C_i = B_i⁻¹, B_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i) over soil and dummy particles, so that
    /// L_i is exact for every linear velocity field, also at free surfaces. Where B_i is
    /// singular or ill-conditioned (κ_F > [`MAX_CONDITION_NUMBER`]) L_i stays uncorrected.
    /// The continuity equation is not corrected. Off by default; off costs nothing (the
    /// kinematics pass is compiled twice).
    pub fn set_velocity_gradient_correction(&mut self, on: bool) {
        self.correct_velocity_gradient = on;
    }

    /// Switches the diffusion of the mean stress ([`MeanStressDiffusion`]; `None`: off, which
    /// costs nothing: the kinematics pass is compiled with and without it).
    pub fn set_mean_stress_diffusion(&mut self, diffusion: Option<MeanStressDiffusion<D>>) {
        self.diffusion = diffusion;
    }

    /// The diffusion of the mean stress, if on.
    pub fn mean_stress_diffusion(&self) -> Option<MeanStressDiffusion<D>> {
        self.diffusion
    }

    /// The accelerations of the last step, damping included.
    pub fn acceleration(&self) -> &[Vector<D>] {
        &self.acceleration
    }

    /// Forgets the last step: its accelerations (which bound the next time step) and the pair
    /// lists.
    pub fn forget_last_step(&mut self) {
        self.acceleration.fill(Vector::zeros());
        self.lists.invalidate();
    }

    /// Removes the wall particles for which `remove` is true (e.g. a retaining wall at release)
    /// and returns how many were removed.
    pub fn remove_walls(
        &mut self,
        remove: impl Fn(&Vector<D>) -> bool,
    ) -> Result<usize, SearchError> {
        let keep: Vec<bool> = self.walls.position.iter().map(|x| !remove(x)).collect();
        let removed = keep.iter().filter(|&&k| !k).count();
        if removed == 0 {
            return Ok(0);
        }
        self.walls.retain(&keep);
        self.lists.set_walls(&self.walls.position)?;
        Ok(removed)
    }

    /// Removes the particles without `keep[i]` (those that left the domain) from `soil` and
    /// their last accelerations ([`PairLists::remove_particles`]; in a distributed run
    /// collective, a set-up follows).
    pub fn remove_particles(
        &mut self,
        soil: &mut Particles<D>,
        keep: &[bool],
    ) -> Result<(), SolverError> {
        self.acceleration.resize(soil.len(), Vector::zeros());
        self.lists
            .remove_particles(soil, &mut self.acceleration, keep)
    }

    /// Restores what the next step depends on besides the particles (a restart): the
    /// accelerations of the last step (they bound Δt) and, when given, the neighbour lists
    /// built at `listed`, positions saved from
    /// [`PairLists::listed_positions`](geosph_sph::PairLists::listed_positions).
    pub fn restore(
        &mut self,
        acceleration: Vec<Vector<D>>,
        listed: Option<Vec<Vector<D>>>,
    ) -> Result<(), SearchError> {
        self.acceleration = acceleration;
        self.lists.invalidate();
        if let Some(listed) = listed {
            self.lists.rebuild_at(listed, &self.walls.position)?;
        }
        Ok(())
    }

    /// Between steps: the Z-order sort, or in a distributed run the set-up, when due
    /// ([`PairLists::reorder_if_due`]); the accelerations of the last step (which bound the
    /// next step) go with their particles.
    pub fn reorder_if_due(
        &mut self,
        step: usize,
        soil: &mut Particles<D>,
    ) -> Result<bool, SolverError> {
        self.acceleration.resize(soil.len(), Vector::zeros());
        self.lists
            .reorder_if_due(step, soil, &mut self.acceleration)
    }

    /// Refreshes the halo of a distributed run, wraps periodic positions and rebuilds stale
    /// neighbour lists; sizes the scratch arrays.
    pub fn update_lists(&mut self, soil: &mut Particles<D>) -> Result<(), SearchError> {
        self.lists.exchange_halo(soil);
        self.lists
            .update(&mut soil.position, &self.walls.position)?;
        let n = soil.len();
        self.particle_volume.resize(n, 0.0);
        self.particle_pressure.resize(n, 0.0);
        self.stress_term.resize(n, Matrix::zeros());
        self.tensile_term.resize(n, Matrix::zeros());
        self.acceleration.resize(n, Vector::zeros());
        self.wall_stress.resize(self.walls.len(), Tensor3::zeros());
        self.wall_centre.resize(self.walls.len(), 0.0);
        self.wall_term.resize(self.walls.len(), Matrix::zeros());
        Ok(())
    }

    /// Advances the soil by `dt` (see the type's documentation for the scheme).
    pub fn step(&mut self, soil: &mut Particles<D>, dt: Real) -> Result<(), SearchError> {
        self.update_lists(soil)?;
        if self.diffusion.is_some() {
            // The diffusion towards the walls needs σ_w of σ^n.
            self.update_walls(soil);
        }
        match (self.correct_velocity_gradient, self.diffusion.is_some()) {
            (false, false) => self.kinematics_and_stress::<false, false>(soil, dt),
            (true, false) => self.kinematics_and_stress::<true, false>(soil, dt),
            (false, true) => self.kinematics_and_stress::<false, true>(soil, dt),
            (true, true) => self.kinematics_and_stress::<true, true>(soil, dt),
        }
        // In a distributed run the halo's new stresses were summed over part of their
        // neighbours (the walls' stress reads them two cells from the owned particles, the
        // momentum their σ/ρ² and R): they are taken from their owners.
        if self.lists.distribution().is_some() {
            self.lists.exchange_halo(soil);
            self.halo_stress_terms(soil);
        }
        self.update_walls(soil);
        self.momentum(soil, dt);
        let Particles {
            position,
            velocity,
            soil: fields,
            ..
        } = soil;
        let fields = fields.as_mut().expect("soil particles carry soil fields");
        let (acceleration, damping) = (&self.acceleration, self.damping_rate);
        (
            position.par_iter_mut(),
            velocity.par_iter_mut(),
            fields.displacement.par_iter_mut(),
            acceleration.par_iter(),
        )
            .into_par_iter()
            .with_min_len(MIN_CHUNK)
            .for_each(|(x, v, u, a)| {
                // Damping implicit in v, so any μ_d Δt is stable: v ← (v + Δt a)/(1 + μ_d Δt).
                *v = (*v + a * dt) / (1.0 + damping * dt);
                *x += *v * dt;
                for k in 0..D {
                    u[k] += v[k] * dt;
                }
            });
        Ok(())
    }

    /// σ/ρ² and R of the halo's particles from their σ and ρ, after a refresh brought them
    /// from their owners.
    fn halo_stress_terms(&mut self, soil: &Particles<D>) {
        let owned = self.lists.owned(soil.len());
        let stress = &soil
            .soil
            .as_ref()
            .expect("soil particles carry soil fields")
            .stress;
        let (correction, artificial_stress) = (self.gradient_correction, self.artificial_stress);
        for i in owned..soil.len() {
            let (sigma, rho) = (&stress[i], soil.density[i]);
            self.stress_term[i] = stress_terms(sigma, rho, correction);
            if let Some(artificial_stress) = &artificial_stress {
                self.tensile_term[i] = artificial_stress.particle_term(sigma, rho);
            }
        }
    }

    /// L_i and dρ_i/dt of every soil particle from v^n (with `CORRECT`, L_i CSPM-corrected;
    /// with `DIFFUSE`, (dp_i/dt)_diff of the mean-stress diffusion from σ^n), and at once
    /// ρ^{n+1}, σ^{n+1}, strain, plastic strain, σ/ρ² and the artificial stress of the
    /// particle ([`StressStep::advance`]). The pair sums read the neighbours' V_j and p_j
    /// gathered before the pass (and the walls' σ_w of σ^n), never their ρ_j or σ_j, so a
    /// particle's own update cannot be seen by another's sums: one pass instead of two, the
    /// same numbers.
    fn kinematics_and_stress<const CORRECT: bool, const DIFFUSE: bool>(
        &mut self,
        soil: &mut Particles<D>,
        dt: Real,
    ) {
        let Self {
            kernel,
            lists,
            walls,
            wall_config,
            rest_density,
            diffusion,
            wall_centre,
            particle_volume,
            particle_pressure,
            stress_term,
            tensile_term,
            ..
        } = self;
        let diffusion = *diffusion;
        let (kernel, lists, walls, rest_density) = (*kernel, &*lists, &*walls, *rest_density);
        let free_slip = wall_config.slip.slips();
        let beta_max = wall_config.beta_max;
        let stress_update = StressStep {
            model: self.model,
            artificial_stress: self.artificial_stress,
            diffusion: diffusion.filter(|_| DIFFUSE),
            correction: self.gradient_correction,
            dt,
        };
        let Particles {
            position,
            velocity,
            mass,
            density,
            soil: fields,
            ..
        } = soil;
        let (position, velocity, mass) = (&*position, &*velocity, &*mass);
        let fields = fields.as_mut().expect("soil particles carry soil fields");
        (
            particle_volume.par_iter_mut(),
            particle_pressure.par_iter_mut(),
        )
            .into_par_iter()
            .enumerate()
            .with_min_len(MIN_CHUNK)
            .for_each(|(i, (volume, pressure))| {
                *volume = mass[i] / density[i];
                if DIFFUSE {
                    *pressure = mean_pressure(&fields.stress[i]);
                }
            });
        let (volumes, pressures) = (&*particle_volume, &*particle_pressure);
        (
            density.par_iter_mut(),
            fields.stress.par_iter_mut(),
            fields.strain.par_iter_mut(),
            fields.plastic_strain.par_iter_mut(),
            stress_term.par_iter_mut(),
            tensile_term.par_iter_mut(),
        )
            .into_par_iter()
            .enumerate()
            .with_min_len(MIN_CHUNK)
            .for_each(|(i, particle)| {
                let (x_i, v_i) = (position[i], velocity[i]);
                let mut l = Matrix::<D>::zeros();
                let mut moment = Matrix::<D>::zeros();
                let mut drho = 0.0;
                let (p_i, level_i) = match &diffusion {
                    Some(diffusion) if DIFFUSE => (pressures[i], diffusion.level(&x_i)),
                    _ => (0.0, 0.0),
                };
                let mut diffusion_sum = 0.0;
                lists.for_each_neighbour(&kernel, position, i, |pair| {
                    let (j, grad) = (pair.index, pair.grad);
                    let dv = velocity[j] - v_i;
                    let volume = volumes[j];
                    l += (dv * volume) * grad.transpose();
                    if CORRECT {
                        moment -= (grad * volume) * pair.r_ij.transpose();
                    }
                    if DIFFUSE && let Some(diffusion) = &diffusion {
                        diffusion_sum +=
                            diffusion.pair(p_i, pressures[j], &pair.r_ij, &grad, volume);
                    }
                    drho -= mass[j] * dv.dot(&grad);
                });
                lists.for_each_wall(&kernel, position, &walls.position, i, |pair| {
                    let (w, grad) = (pair.index, pair.grad);
                    let v_w = dummy_velocity(
                        &x_i,
                        &v_i,
                        &(x_i - pair.r_ij),
                        &walls.normal[w],
                        walls.depth[w],
                        &walls.velocity[w],
                        beta_max,
                        free_slip,
                    );
                    let dv = v_w - v_i;
                    let volume = walls.volume[w];
                    l += (dv * volume) * grad.transpose();
                    if CORRECT {
                        moment -= (grad * volume) * pair.r_ij.transpose();
                    }
                    if DIFFUSE && let Some(diffusion) = &diffusion {
                        diffusion_sum += diffusion.wall_pair(
                            p_i,
                            walls.pressure[w],
                            &pair.r_ij,
                            level_i - wall_centre[w],
                            &grad,
                            volume,
                        );
                    }
                    drho -= rest_density * volume * dv.dot(&grad);
                });
                if CORRECT
                    && let Some(correction) =
                        well_conditioned_inverse(&moment, MAX_CONDITION_NUMBER)
                {
                    l *= correction.transpose();
                }
                stress_update.advance(particle, &l, drho, diffusion_sum);
            });
    }
}

/// c σ/ρ² of a particle (its D × D block; c the lattice gradient correction), as the momentum
/// sums it.
#[inline(always)]
fn stress_terms<const D: usize>(sigma: &Tensor3, rho: Real, correction: Real) -> Matrix<D> {
    block::<D>(sigma) * (correction / (rho * rho))
}

/// What the stress update of one step needs besides the particle.
struct StressStep<const D: usize> {
    /// The constitutive model.
    model: SoilModel,
    /// Gray et al.'s (2001) artificial stress, if on.
    artificial_stress: Option<ArtificialStressGray2001>,
    /// The mean-stress diffusion, when the pass computes it.
    diffusion: Option<MeanStressDiffusion<D>>,
    /// 1/f, the lattice gradient correction of σ/ρ² ([`SoilSystem::gradient_correction`]).
    correction: Real,
    /// Δt.
    dt: Real,
}

/// The fields of one soil particle that its stress update writes, as the pass zips them: ρ, σ,
/// strain, equivalent plastic strain, σ/ρ² and the artificial stress R.
type StressFields<'a, const D: usize> = (
    &'a mut Real,
    &'a mut Tensor3,
    &'a mut Tensor3,
    &'a mut Real,
    &'a mut Matrix<D>,
    &'a mut Matrix<D>,
);

impl<const D: usize> StressStep<D> {
    /// ρ^{n+1}, σ^{n+1}, strain, plastic strain, σ/ρ² and R of one particle from its velocity
    /// gradient `l`, dρ/dt and the diffusion's pair sum.
    #[inline(always)]
    fn advance(
        &self,
        particle: StressFields<'_, D>,
        l: &Matrix<D>,
        density_rate: Real,
        diffusion_sum: Real,
    ) {
        let (rho, sigma, strain, plastic, term, tensile) = particle;
        let dt = self.dt;
        if let Some(diffusion) = &self.diffusion {
            let pressure_change = diffusion.rate(diffusion_sum) * dt;
            *sigma -= Tensor3::identity() * pressure_change;
            *rho *= 1.0 + diffusion.volumetric_strain(pressure_change);
        }
        *rho += density_rate * dt;
        let strain_increment = strain_rate(l) * dt;
        let update = self.model.update(sigma, &strain_increment, &(spin(l) * dt));
        *sigma = update.stress;
        *strain += strain_increment;
        *plastic += update.equivalent_plastic_strain_increment;
        *term = stress_terms(sigma, *rho, self.correction);
        if let Some(artificial_stress) = &self.artificial_stress {
            *tensile = artificial_stress.particle_term(sigma, *rho);
        }
    }
}
