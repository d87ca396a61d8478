//! [`build_soil`]: the soil solver a scene's [`SoilConfig`] describes.

use geosph_core::{Particles, Real};
use geosph_kernels::{Kernel, KernelVisitor};
use geosph_sph::{ArtificialMonaghan1992, Solver, SphSetup};

use crate::constitutive::Constitutive;
use crate::sph::config::{ConfigError, SoilConfig, SoilError};
use crate::sph::solver::SoilSolver;
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

struct SoilBuilder<'a, const D: usize> {
    config: &'a SoilConfig,
    setup: SphSetup<D>,
    particles: &'a mut Particles<D>,
}

impl<const D: usize> KernelVisitor<D> for SoilBuilder<'_, D> {
    type Output = Result<Box<dyn Solver<D>>, SoilError>;

    fn visit<K: Kernel<D>>(self, kernel: K) -> Self::Output {
        let config = self.config;
        let model = config.constitutive.build().map_err(ConfigError::from)?;
        let wave_speed = (model.elastic().p_wave_modulus() / self.setup.rest_density).sqrt();
        let viscosity = config
            .artificial_viscosity
            .map(|av| ArtificialMonaghan1992 {
                alpha: av.alpha,
                beta: av.beta,
                smoothing_length: kernel.smoothing_length(),
                sound_speed: wave_speed,
            });
        let spacing = particle_spacing::<D>(self.particles, self.setup.rest_density);
        let artificial_stress = config.artificial_stress.map(|stress| {
            ArtificialStressGray2001::new(&kernel, stress.epsilon, stress.exponent, spacing)
        });
        self.particles.enable_soil();
        let mut system = SoilSystem::new(
            kernel,
            self.setup,
            model,
            viscosity,
            artificial_stress,
            config.walls,
            spacing,
            config.neighbour_skin,
        )?;
        system.set_velocity_gradient_correction(config.velocity_gradient_correction);
        system.lists.reorder_every = config.reorder_every;
        let mut solver = SoilSolver::new(system, config.cfl);
        solver.regularisation = config.regularisation;
        solver.geostatic = config.geostatic.clone();
        solver.system.set_damping(config.damping.unwrap_or(0.0));
        Ok(Box::new(solver))
    }
}

/// The lattice spacing dx = (m/ρ₀)^{1/D} of the first particle.
fn particle_spacing<const D: usize>(particles: &Particles<D>, rest_density: Real) -> Real {
    let mass = particles.mass.first().copied().unwrap_or(rest_density);
    (mass / rest_density).powf(1.0 / D as Real)
}
