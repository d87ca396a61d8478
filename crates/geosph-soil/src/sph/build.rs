//! [`build_soil`]: the soil solver a scene's [`SoilConfig`] describes, and
//! [`factor_of_safety`], the strength-reduction search on it.

use geosph_core::{Particles, Real};
use geosph_kernels::{Kernel, KernelVisitor};
use geosph_sph::{ArtificialMonaghan1992, Solver, SphSetup};

use crate::constitutive::Constitutive;
use crate::sph::config::StrengthReductionConfig;
use crate::sph::config::{ConfigError, SoilConfig, SoilError, WallStress};
use crate::sph::diffusion::MeanStressDiffusion;
use crate::sph::solver::SoilSolver;
use crate::sph::strength_reduction::{FactorOfSafety, Trial};
use crate::sph::system::SoilSystem;
use crate::sph::terms::ArtificialStressGray2001;

/// Builds the soil solver that `config` describes for `particles` (whose soil fields it
/// creates), monomorphised over the kernel. A geostatic stage in `config` is run by the
/// solver's [`Solver::initial_stage`], which the runner calls before t = 0 of a new run.
pub fn build_soil<const D: usize>(
    config: &SoilConfig,
    setup: SphSetup<D>,
    particles: &mut Particles<D>,
) -> Result<Box<dyn Solver<D>>, SoilError> {
    config.validate()?;
    let (kernel, h) = (setup.kernel, setup.smoothing_length);
    kernel.dispatch::<D, _>(
        h,
        SoilBuilder {
            config,
            setup,
            particles,
        },
    )
}

/// Builds the soil solver of `config` for `particles`, runs its geostatic stage and then the
/// strength-reduction search `search` ([`SoilSolver::factor_of_safety`], which calls
/// `on_trial` after each trial); on return `particles` holds the state of the smallest
/// failing trial factor, and the solver is returned with it (for output).
pub fn factor_of_safety<const D: usize>(
    config: &SoilConfig,
    search: &StrengthReductionConfig,
    setup: SphSetup<D>,
    particles: &mut Particles<D>,
    on_trial: &mut dyn FnMut(&Trial),
) -> Result<(FactorOfSafety, Box<dyn Solver<D>>), SoilError> {
    config.validate()?;
    search.validate()?;
    let (kernel, h) = (setup.kernel, setup.smoothing_length);
    kernel.dispatch::<D, _>(
        h,
        StrengthReduction {
            builder: SoilBuilder {
                config,
                setup,
                particles,
            },
            search,
            on_trial,
        },
    )
}

struct SoilBuilder<'a, const D: usize> {
    config: &'a SoilConfig,
    setup: SphSetup<D>,
    particles: &'a mut Particles<D>,
}

/// The solver of `config` for `particles` with `kernel` (both builders' common part).
fn soil_solver<const D: usize, K: Kernel<D>>(
    config: &SoilConfig,
    setup: SphSetup<D>,
    particles: &mut Particles<D>,
    kernel: K,
) -> Result<SoilSolver<D, K>, SoilError> {
    let model = config.constitutive.build().map_err(ConfigError::from)?;
    let wave_speed = (model.elastic().p_wave_modulus() / setup.rest_density).sqrt();
    let viscosity = config
        .artificial_viscosity
        .map(|av| ArtificialMonaghan1992 {
            alpha: av.alpha,
            beta: av.beta,
            smoothing_length: kernel.smoothing_length(),
            sound_speed: wave_speed,
        });
    let spacing = particle_spacing::<D>(particles, setup.rest_density);
    let artificial_stress = config.artificial_stress.map(|stress| {
        ArtificialStressGray2001::new(&kernel, stress.epsilon, stress.exponent, spacing)
    });
    particles.enable_soil();
    let cell_index = setup.cell_index;
    let mut system = SoilSystem::new(
        kernel,
        setup,
        model,
        viscosity,
        artificial_stress,
        config.walls,
        spacing,
        config.neighbour_skin,
    )?;
    system
        .lists
        .use_cell_index(cell_index, &system.walls.position)?;
    system.set_velocity_gradient_correction(config.velocity_gradient_correction);
    system.set_mean_stress_diffusion(config.stress_diffusion.map(|diffusion| {
        MeanStressDiffusion::new(
            diffusion.delta,
            kernel.smoothing_length(),
            wave_speed,
            model.elastic().bulk_modulus,
            system.gravity,
            system.rest_density,
            diffusion
                .lateral_ratio
                .unwrap_or(model.lateral_ratio_at_rest()),
            config.walls.stress == WallStress::Extrapolated,
        )
    }));
    system.lists.reorder_every = config.reorder_every;
    let mut solver = SoilSolver::new(system, config.cfl);
    solver.regularisation = config.regularisation;
    solver.geostatic = config.geostatic.clone();
    solver.system.set_damping(config.damping.unwrap_or(0.0));
    Ok(solver)
}

impl<const D: usize> KernelVisitor<D> for SoilBuilder<'_, D> {
    type Output = Result<Box<dyn Solver<D>>, SoilError>;

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        Ok(Box::new(soil_solver(
            self.config,
            self.setup,
            self.particles,
            kernel,
        )?))
    }
}

struct StrengthReduction<'a, const D: usize> {
    builder: SoilBuilder<'a, D>,
    search: &'a StrengthReductionConfig,
    on_trial: &'a mut dyn FnMut(&Trial),
}

impl<const D: usize> KernelVisitor<D> for StrengthReduction<'_, D> {
    type Output = Result<(FactorOfSafety, Box<dyn Solver<D>>), SoilError>;

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let SoilBuilder {
            config,
            setup,
            particles,
        } = self.builder;
        let mut solver = soil_solver(config, setup, particles, kernel)?;
        let result = solver.factor_of_safety(particles, self.search, self.on_trial)?;
        Ok((result, Box::new(solver)))
    }
}

/// The lattice spacing dx = (m/ρ₀)^{1/D} of the first particle.
fn particle_spacing<const D: usize>(particles: &Particles<D>, rest_density: Real) -> Real {
    let mass = particles.mass.first().copied().unwrap_or(rest_density);
    (mass / rest_density).powf(1.0 / D as Real)
}
