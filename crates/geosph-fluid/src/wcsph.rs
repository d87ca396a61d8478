//! Weakly compressible SPH: the rates of the momentum and continuity equations.

use geosph_boundary::adami::FlowView;
use geosph_boundary::{DummyAdami2012, WallParticles};
use geosph_core::{Domain, NeighbourList, Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::{CellGrid, SearchError};
use geosph_time::{ExplicitSystem, Rates};
use rayon::prelude::*;

use crate::diffusion::DensityDiffusion;
use crate::eos::EquationOfState;
use crate::viscosity::{Pair, Viscosity};

/// How the density evolves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DensityMode {
    /// Integrate the continuity equation dρ_i/dt = Σ_j m_j v_ij·∇_i W_ij (+ diffusion).
    Continuity,
    /// Sum ρ_i = Σ_j m_j W_ij over fluid and wall neighbours after every neighbour update.
    Summation,
}

/// The physics of one WCSPH rate evaluation, monomorphised over the kernel `K`, the viscosity
/// `V` and the density diffusion `F`.
///
/// Momentum in the symmetric, momentum-conserving form (Monaghan 1992, eq. 3.3):
///
/// dv_i/dt = −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij + viscosity + g,
///
/// where j runs over fluid and wall neighbours; a wall particle has mass ρ₀ V_w and the
/// pressure and density of [`DummyAdami2012`]. Continuity:
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij + D_i, with the prescribed wall velocity for walls
/// and the diffusion D_i over fluid neighbours only.
pub struct WcsphSystem<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>> {
    /// Smoothing kernel.
    pub kernel: K,
    /// Domain (periodic axes, minimum image).
    pub domain: Domain<D>,
    /// Equation of state.
    pub eos: EquationOfState,
    /// Viscous term.
    pub viscosity: V,
    /// Density diffusion.
    pub diffusion: F,
    /// Body-force acceleration g.
    pub gravity: Vector<D>,
    /// XSPH factor ε (0: off) of dx/dt = v + ε Σ_j m_j/ρ̄_ij (v_j − v_i) W_ij (Monaghan 1989).
    pub xsph: Real,
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
    fluid_grid: CellGrid<D>,
    wall_grid: CellGrid<D>,
    fluid_fluid: NeighbourList,
    fluid_wall: NeighbourList,
    wall_fluid: NeighbourList,
    volume: Vec<Real>,
    /// p_i / ρ_i² of every particle, computed once per evaluation.
    pressure_term: Vec<Real>,
    /// Verlet skin added to the search radius.
    skin: Real,
    /// Positions at the last list build.
    listed_position: Vec<Vector<D>>,
    lists_valid: bool,
    list_builds: usize,
}

impl<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>>
    WcsphSystem<D, K, V, F>
{
    /// A system on `domain` with fixed `walls` (their grid is built once here).
    ///
    /// Neighbour lists are searched with the support radius plus a Verlet skin of
    /// `skin_fraction` × support radius and rebuilt only when some particle has moved more
    /// than half the skin since the last build (Verlet 1967), so every pair within the support
    /// is always listed; pairs in the skin contribute zero through the kernel.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        kernel: K,
        domain: Domain<D>,
        eos: EquationOfState,
        viscosity: V,
        diffusion: F,
        gravity: Vector<D>,
        walls: WallParticles<D>,
        wall_condition: DummyAdami2012<D>,
        skin_fraction: Real,
    ) -> Result<Self, SearchError> {
        let skin = skin_fraction.max(0.0) * kernel.support_radius();
        let radius = kernel.support_radius() + skin;
        let fluid_grid = CellGrid::new(domain.clone(), radius)?;
        let mut wall_grid = CellGrid::new(domain.clone(), radius)?;
        wall_grid.build(&walls.position)?;
        Ok(Self {
            kernel,
            domain,
            eos,
            viscosity,
            diffusion,
            gravity,
            xsph: 0.0,
            density_mode: DensityMode::Continuity,
            clamp_negative_pressure: false,
            walls,
            wall_condition,
            shepard_due: false,
            fluid_grid,
            wall_grid,
            fluid_fluid: NeighbourList::new(),
            fluid_wall: NeighbourList::new(),
            wall_fluid: NeighbourList::new(),
            volume: Vec::new(),
            pressure_term: Vec::new(),
            skin,
            listed_position: Vec::new(),
            lists_valid: false,
            list_builds: 0,
        })
    }

    /// The fluid–fluid neighbour list of the last update.
    pub fn fluid_neighbours(&self) -> &NeighbourList {
        &self.fluid_fluid
    }

    /// The fluid grid, rebuilt for a Z-order sort; the neighbour lists are invalidated.
    pub fn fluid_grid_for_sorting(&mut self) -> &mut CellGrid<D> {
        self.lists_valid = false;
        &mut self.fluid_grid
    }

    /// Forgets the neighbour lists (after particles were removed); the next update rebuilds
    /// them.
    pub fn invalidate_lists(&mut self) {
        self.lists_valid = false;
    }

    /// How often the neighbour lists were built.
    pub fn list_builds(&self) -> usize {
        self.list_builds
    }

    /// The positions the neighbour lists were built at, while they are valid (a checkpoint
    /// saves them: the lists' neighbour order decides the summation order).
    pub fn listed_positions(&self) -> Option<&[Vector<D>]> {
        self.lists_valid.then_some(self.listed_position.as_slice())
    }

    /// Builds the neighbour lists at `listed`, positions saved from
    /// [`WcsphSystem::listed_positions`], so they are those of the saved run (a restart).
    pub fn rebuild_lists_at(&mut self, listed: Vec<Vector<D>>) -> Result<(), SearchError> {
        self.build_lists(&listed)?;
        self.listed_position = listed;
        Ok(())
    }

    /// Builds the grid and the three neighbour lists at `position`.
    fn build_lists(&mut self, position: &[Vector<D>]) -> Result<(), SearchError> {
        self.fluid_grid.build(position)?;
        self.fluid_grid
            .neighbour_list(position, position, &mut self.fluid_fluid);
        self.wall_grid
            .neighbour_list(&self.walls.position, position, &mut self.fluid_wall);
        self.fluid_grid
            .neighbour_list(position, &self.walls.position, &mut self.wall_fluid);
        self.lists_valid = true;
        self.list_builds += 1;
        Ok(())
    }

    /// Whether a particle moved more than half the skin since the lists were built.
    fn lists_stale(&self, position: &[Vector<D>]) -> bool {
        if !self.lists_valid || self.listed_position.len() != position.len() {
            return true;
        }
        let domain = &self.domain;
        let largest = position
            .par_iter()
            .zip(self.listed_position.par_iter())
            .map(|(x, x0)| domain.displacement(x, x0).norm_squared())
            .reduce(|| 0.0, Real::max);
        4.0 * largest > self.skin * self.skin
    }

    /// p_i = p(ρ_i) for every particle (clamped at zero when asked).
    pub fn update_pressure(&self, fluid: &mut Particles<D>) {
        let eos = self.eos;
        let clamp = self.clamp_negative_pressure;
        let Particles {
            density, pressure, ..
        } = fluid;
        let pressure = pressure.get_or_insert_with(Vec::new);
        pressure.resize(density.len(), 0.0);
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
        let kernel = self.kernel;
        let domain = &self.domain;
        let rest_density = self.eos.rest_density;
        let (fluid_fluid, fluid_wall, walls) = (&self.fluid_fluid, &self.fluid_wall, &self.walls);
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
            for &j in fluid_fluid.neighbours(i) {
                let j = j as usize;
                let w = kernel.value(domain.displacement(&position[i], &position[j]).norm());
                mass_sum += mass[j] * w;
                volume_sum += volume[j] * w;
            }
            for &w_index in fluid_wall.neighbours(i) {
                let w_index = w_index as usize;
                let r = domain
                    .displacement(&position[i], &walls.position[w_index])
                    .norm();
                let w = kernel.value(r);
                mass_sum += rest_density * walls.volume[w_index] * w;
                volume_sum += walls.volume[w_index] * w;
            }
            *rho_i = if shepard {
                mass_sum / volume_sum
            } else {
                mass_sum
            };
        });
    }

    /// XSPH position correction δv_i = ε Σ_j m_j / ρ̄_ij (v_j − v_i) W_ij (Monaghan 1989).
    fn xsph_correction(&self, fluid: &Particles<D>, correction: &mut [Vector<D>]) {
        let epsilon = self.xsph;
        let (kernel, domain, list) = (self.kernel, &self.domain, &self.fluid_fluid);
        correction.par_iter_mut().enumerate().for_each(|(i, dv)| {
            let mut sum = Vector::<D>::zeros();
            for &j in list.neighbours(i) {
                let j = j as usize;
                let w = kernel.value(
                    domain
                        .displacement(&fluid.position[i], &fluid.position[j])
                        .norm(),
                );
                let rho_mean = 0.5 * (fluid.density[i] + fluid.density[j]);
                sum += (fluid.velocity[j] - fluid.velocity[i]) * (fluid.mass[j] / rho_mean * w);
            }
            *dv = sum * epsilon;
        });
    }
}

impl<const D: usize, K: Kernel<D>, V: Viscosity<D>, F: DensityDiffusion<D>> ExplicitSystem<D>
    for WcsphSystem<D, K, V, F>
{
    type Error = SearchError;

    fn prepare(&mut self, fluid: &mut Particles<D>) -> Result<(), SearchError> {
        if self.domain.is_periodic() {
            let domain = &self.domain;
            fluid.position.par_iter_mut().for_each(|x| domain.wrap(x));
        }
        if self.lists_stale(&fluid.position) {
            self.build_lists(&fluid.position)?;
            self.listed_position.clone_from(&fluid.position);
        }
        let shepard = std::mem::take(&mut self.shepard_due);
        if shepard || self.density_mode == DensityMode::Summation {
            self.sum_density(
                fluid,
                shepard && self.density_mode == DensityMode::Continuity,
            );
            self.update_pressure(fluid);
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
            &self.domain,
            &mut self.walls,
            FlowView {
                position: &fluid.position,
                velocity: &fluid.velocity,
                pressure,
                density: &fluid.density,
            },
            &self.wall_fluid,
            |p| eos.density(p),
        );
        self.volume.resize(fluid.len(), 0.0);
        self.pressure_term.resize(fluid.len(), 0.0);
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
                *term = p / (rho * rho);
            });
        self.diffusion.prepare(
            &self.kernel,
            &self.domain,
            &fluid.position,
            &fluid.density,
            &self.volume,
            &self.fluid_fluid,
        );

        let Self {
            kernel,
            domain,
            viscosity,
            diffusion,
            gravity,
            walls,
            fluid_fluid,
            fluid_wall,
            volume,
            pressure_term,
            ..
        } = self;
        let (kernel, viscosity, diffusion, gravity) = (*kernel, *viscosity, &*diffusion, *gravity);
        let summation = self.density_mode == DensityMode::Summation;
        let h = kernel.smoothing_length();
        let Particles {
            position,
            velocity,
            mass,
            density,
            ..
        } = fluid;
        rates
            .acceleration
            .par_iter_mut()
            .zip(rates.density_rate.par_iter_mut())
            .enumerate()
            .for_each(|(i, (acceleration, density_rate))| {
                let (x_i, v_i, rho_i) = (position[i], velocity[i], density[i]);
                let p_over_rho2_i = pressure_term[i];
                let eta2 = 0.01 * h * h;
                let mut a_i = gravity;
                let mut drho_i = 0.0;
                for &j in fluid_fluid.neighbours(i) {
                    let j = j as usize;
                    if j == i {
                        continue;
                    }
                    let r_ij = domain.displacement(&x_i, &position[j]);
                    let r2 = r_ij.norm_squared();
                    let grad = r_ij * kernel.gradient_factor(r2.sqrt());
                    let rho_j = density[j];
                    let pair = Pair {
                        r_ij,
                        r2,
                        inv_r2_eta2: 1.0 / (r2 + eta2),
                        grad,
                        v_ij: v_i - velocity[j],
                        rho_i,
                        rho_j,
                        mass_j: mass[j],
                    };
                    a_i -= grad * (mass[j] * (p_over_rho2_i + pressure_term[j]));
                    a_i += viscosity.acceleration(&pair);
                    drho_i += mass[j] * pair.v_ij.dot(&grad);
                    drho_i += diffusion.rate(i, j, &pair, volume[j]);
                }
                for &w in fluid_wall.neighbours(i) {
                    let w = w as usize;
                    let r_iw = domain.displacement(&x_i, &walls.position[w]);
                    let r2 = r_iw.norm_squared();
                    let grad = r_iw * kernel.gradient_factor(r2.sqrt());
                    let rho_w = walls.density[w];
                    let mass_w = rho_w * walls.volume[w];
                    let pair = Pair {
                        r_ij: r_iw,
                        r2,
                        inv_r2_eta2: 1.0 / (r2 + eta2),
                        grad,
                        v_ij: v_i
                            - if V::PHYSICAL {
                                walls.viscous_velocity[w]
                            } else {
                                walls.velocity[w]
                            },
                        rho_i,
                        rho_j: rho_w,
                        mass_j: mass_w,
                    };
                    a_i -= grad * (mass_w * (p_over_rho2_i + walls.pressure[w] / (rho_w * rho_w)));
                    a_i += viscosity.acceleration(&pair);
                    drho_i += mass_w * (v_i - walls.velocity[w]).dot(&grad);
                }
                *acceleration = a_i;
                *density_rate = if summation { 0.0 } else { drho_i };
            });
        if self.xsph > 0.0 {
            self.xsph_correction(fluid, &mut rates.position_correction);
        }
    }

    fn finish_stage(&mut self, fluid: &mut Particles<D>) {
        self.update_pressure(fluid);
    }
}
