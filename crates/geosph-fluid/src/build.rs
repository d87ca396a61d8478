//! The factory that builds a fluid solver from its [`crate::config`], every option resolved to
//! a type once (kernel, viscosity, diffusion, density mode, pressure method), so the hot loops
//! carry no option flags.

use geosph_boundary::DummyAdami2012;
use geosph_core::Particles;
use geosph_kernels::{Kernel, KernelVisitor};
use geosph_neighbours::SearchError;
use geosph_sph::eos::EquationOfState;
use geosph_sph::lattice::{lattice_gradient_factor, lattice_kernel_sum};
use geosph_sph::{Solver, SphSetup, SubParticleStress, ViscousTerm};
use geosph_time::Integrator;

use crate::config::{DensityConfig, IncompressibleConfig, IncompressibleMethod, WcsphConfig};
use crate::gas::GasDynamics;
use crate::incompressible::{
    Dfsph, Iisph, Incompressible, Pcisph, PressureMethod, PressureSolveSettings, PressureSystem,
};
use crate::surface_tension::SurfaceTension;
use crate::wcsph::{DensityMode, WcsphSystem};
use crate::wcsph_solver::Wcsph;

/// Builds the WCSPH solver that `config` describes, monomorphised over the kernel it names
/// (its pair loop over the viscosity and diffusion as well, [`WcsphSystem`]).
pub fn build_wcsph<const D: usize>(
    config: &WcsphConfig,
    setup: SphSetup<D>,
    fluid: &mut Particles<D>,
) -> Result<Box<dyn Solver<D>>, SearchError> {
    let (kernel, h) = (setup.kernel, setup.smoothing_length);
    kernel.dispatch::<D, _>(
        h,
        WcsphBuilder {
            config,
            setup,
            fluid,
        },
    )
}

struct WcsphBuilder<'a, const D: usize> {
    config: &'a WcsphConfig,
    setup: SphSetup<D>,
    fluid: &'a mut Particles<D>,
}

impl<const D: usize> KernelVisitor<D> for WcsphBuilder<'_, D> {
    type Output = Result<Box<dyn Solver<D>>, SearchError>;

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let config = self.config;
        let setup = self.setup;
        let (h, c0) = (kernel.smoothing_length(), setup.sound_speed);
        // A gas's reference state (ρ₀, p₀) has c₀² = γ (p₀ + p∞)/ρ₀.
        let background_pressure = match config.equation_of_state.gas_law() {
            Some(law) => setup.rest_density * c0 * c0 / law.gamma - law.stiffness,
            None => config.background_pressure,
        };
        let eos = EquationOfState {
            kind: config.equation_of_state,
            rest_density: setup.rest_density,
            sound_speed: c0,
            background_pressure,
        };
        let wall_condition = DummyAdami2012 {
            gravity: setup.gravity,
            slip: config.wall_slip,
            physical_viscosity: config.viscosity.is_physical(),
            clamp_negative: config.clamp_wall_pressure,
        };
        let cell_index = setup.cell_index;
        // A gas has its own artificial viscosity, with the particles' sound speeds.
        let gas = GasDynamics::of(config);
        let viscosity = match gas {
            Some(_) => ViscousTerm::Inviscid,
            None => config.viscosity.term(h, c0).calibrated(
                &kernel,
                setup.spacing,
                setup.spacing.powi(D as i32),
            ),
        };
        let mut system = WcsphSystem::new(
            kernel,
            setup.domain,
            eos,
            viscosity,
            config
                .diffusion
                .term(h, c0, setup.rest_density, setup.gravity),
            setup.gravity,
            setup.walls,
            wall_condition,
            config.neighbour_skin,
        )?;
        system
            .lists
            .use_cell_index(cell_index, &system.walls.position)?;
        system.gradient_correction =
            1.0 / lattice_gradient_factor(&kernel, setup.spacing, setup.spacing.powi(D as i32));
        system.xsph = config.xsph;
        system.gas = gas;
        system.shifting = config.shifting;
        system.sps = config
            .sps
            .map(|sps| SubParticleStress::new(sps, setup.spacing));
        system.surface_tension = config
            .surface_tension
            .as_ref()
            .map(|tension| SurfaceTension::new(tension, &setup.block_ids));
        system.spacing = setup.spacing;
        system.clamp_negative_pressure = config.clamp_negative_pressure;
        system.density_mode = match config.density {
            DensityConfig::Continuity => DensityMode::Continuity,
            DensityConfig::Summation => DensityMode::Summation,
        };
        let integrator = Integrator::new(config.integrator, self.fluid.len());
        system.lists.reorder_every = config.reorder_every;
        let mut solver = Wcsph::new(system, integrator, self.fluid);
        solver.cfl = config.cfl;
        solver.shepard_every = config.shepard_every;
        Ok(Box::new(solver))
    }
}

/// Builds the incompressible solver `method` that `config` describes, monomorphised over the
/// kernel it names (the viscous term is resolved once per pass: it acts once per step).
/// `config` must have passed [`IncompressibleConfig::validate_for`] `method` (a scene's
/// validation does that): DFSPH, for one, ignores a `source` it refuses there.
pub fn build_incompressible<const D: usize>(
    method: IncompressibleMethod,
    config: &IncompressibleConfig,
    setup: SphSetup<D>,
    fluid: &mut Particles<D>,
) -> Result<Box<dyn Solver<D>>, SearchError> {
    let (kernel, h) = (setup.kernel, setup.smoothing_length);
    kernel.dispatch::<D, _>(
        h,
        IncompressibleBuilder {
            method,
            config,
            setup,
            fluid,
        },
    )
}

struct IncompressibleBuilder<'a, const D: usize> {
    method: IncompressibleMethod,
    config: &'a IncompressibleConfig,
    setup: SphSetup<D>,
    fluid: &'a mut Particles<D>,
}

impl<const D: usize> KernelVisitor<D> for IncompressibleBuilder<'_, D> {
    type Output = Result<Box<dyn Solver<D>>, SearchError>;

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let config = self.config;
        let spacing = self.setup.spacing;
        match self.method {
            IncompressibleMethod::Pcisph => {
                let mass = self.setup.rest_density / lattice_kernel_sum(&kernel, spacing);
                let mut method = Pcisph::new::<D, K>(&kernel, spacing, mass);
                // The system's diagonals carry the gradient correction; so must the prototype's.
                let volume = 1.0 / lattice_kernel_sum(&kernel, spacing);
                method.prototype_diagonal /= lattice_gradient_factor(&kernel, spacing, volume);
                self.finish(kernel, method)
            }
            IncompressibleMethod::Iisph => {
                let method = Iisph {
                    relaxation: config.relaxation,
                    iteration: config.iteration,
                    ..Iisph::default()
                };
                self.finish(kernel, method)
            }
            IncompressibleMethod::Dfsph => {
                let method = Dfsph::new(config.divergence_solve, config.target_divergence_error);
                self.finish(kernel, method)
            }
        }
    }
}

impl<const D: usize> IncompressibleBuilder<'_, D> {
    fn finish<K: Kernel<D>, M: PressureMethod<D> + 'static>(
        self,
        kernel: K,
        method: M,
    ) -> Result<Box<dyn Solver<D>>, SearchError> {
        let (config, setup) = (self.config, self.setup);
        // The particles' volume on the lattice is 1/Σ_k W (`Incompressible::new`).
        let volume = 1.0 / lattice_kernel_sum(&kernel, setup.spacing);
        let viscosity = config
            .viscosity
            .term(kernel.smoothing_length(), setup.sound_speed)
            .calibrated(&kernel, setup.spacing, volume);
        let cell_index = setup.cell_index;
        let mut system = PressureSystem::new(
            kernel,
            setup.domain,
            setup.rest_density,
            viscosity,
            setup.gravity,
            setup.walls,
            config.wall_pressure,
            config.wall_slip,
        )?;
        system
            .lists
            .use_cell_index(cell_index, &system.walls.position)?;
        system.shifting = config.shifting;
        system.renormalise_gradients = config.renormalise_gradients;
        let settings = PressureSolveSettings {
            target_density_error: config.target_density_error,
            max_compression: config.max_compression,
            min_iterations: config.min_iterations,
            max_iterations: config.max_iterations,
            cfl: config.cfl,
            max_time_step: config.max_time_step,
            negative_pressure: config.negative_pressure,
            source: config.source,
        };
        let mut solver = Incompressible::new(system, method, settings, setup.spacing, self.fluid)?;
        solver.system.lists.reorder_every = config.reorder_every;
        Ok(Box::new(solver))
    }
}
