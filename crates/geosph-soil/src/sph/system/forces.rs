//! The passes of a step that push the soil: the stress the wall particles show it, and the
//! momentum equation (stress, artificial viscosity and stress, walls, friction, damping).

use geosph_core::{Matrix, Particles, Real, Tensor3, Vector};
use geosph_kernels::Kernel;
use geosph_sph::ArtificialMonaghan1992;
use rayon::prelude::*;

use super::{MIN_CHUNK, SoilSystem};
use crate::invariants::mean_pressure;
use crate::sph::config::WallStress;
use crate::sph::terms::block;
use crate::sph::walls::{coulomb_friction, dummy_velocity, gravity_extrapolation, mirror_shear};

impl<const D: usize, K: Kernel<D>> SoilSystem<D, K> {
    /// σ_w of every dummy particle from the soil around it ([`WallStress`]).
    pub(super) fn update_walls(&mut self, soil: &Particles<D>) {
        let fields = soil
            .soil
            .as_ref()
            .expect("soil particles carry soil fields");
        let (kernel, lists, gravity) = (self.kernel, &self.lists, self.gravity);
        let extrapolate = self.wall_config.stress == WallStress::Extrapolated;
        let rho_w = self.rest_density;
        let correction = self.gradient_correction;
        let mirror = self.wall_config.slip.slips();
        let diffusion = self.diffusion;
        let walls = &mut self.walls;
        let (wall_position, wall_normal) = (&walls.position, &walls.normal);
        (
            self.wall_stress.par_iter_mut(),
            self.wall_term.par_iter_mut(),
            walls.pressure.par_iter_mut(),
            self.wall_centre.par_iter_mut(),
        )
            .into_par_iter()
            .enumerate()
            .with_min_len(MIN_CHUNK)
            .for_each(|(w, (stress, term, pressure, centre))| {
                let mut sum = Tensor3::zeros();
                let mut weight = 0.0;
                let mut level = 0.0;
                lists.for_each_particle_near_wall(
                    &kernel,
                    &soil.position,
                    wall_position,
                    w,
                    |pair| {
                        let kernel_value = kernel.value(pair.r);
                        let mut sigma = fields.stress[pair.index];
                        if extrapolate {
                            sigma += gravity_extrapolation(
                                soil.density[pair.index],
                                &gravity,
                                &pair.r_ij,
                            );
                        }
                        sum += sigma * kernel_value;
                        weight += kernel_value;
                        if let Some(diffusion) = &diffusion {
                            level += diffusion.level(&soil.position[pair.index]) * kernel_value;
                        }
                    },
                );
                *stress = if weight > 0.0 {
                    sum / weight
                } else {
                    Tensor3::zeros()
                };
                if weight > 0.0 {
                    *centre = level / weight;
                }
                if mirror {
                    *stress = mirror_shear(stress, &wall_normal[w]);
                }
                *term = block::<D>(stress) * (correction / (rho_w * rho_w));
                *pressure = mean_pressure(stress);
            });
    }

    /// dv_i/dt of every soil particle with σ^{n+1}.
    pub(super) fn momentum(&mut self, soil: &Particles<D>, dt: Real) {
        let Self {
            kernel,
            lists,
            gravity,
            walls,
            wall_config,
            rest_density,
            viscosity,
            artificial_stress,
            repulsive,
            damping_rate,
            wall_term,
            stress_term,
            tensile_term,
            acceleration,
            ..
        } = self;
        let (kernel, lists, gravity, walls) = (*kernel, &*lists, *gravity, &*walls);
        let (viscosity, artificial_stress, repulsive) =
            (*viscosity, *artificial_stress, *repulsive);
        let h = kernel.smoothing_length();
        let eta2 = 0.01 * h * h;
        let (rest_density, damping_rate) = (*rest_density, *damping_rate);
        let free_slip = wall_config.slip.slips();
        let beta_max = wall_config.beta_max;
        let wall_viscosity = viscosity.filter(|_| wall_config.viscous);
        let friction = wall_config.slip.friction_coefficient();
        // −Π_ij 1 of an approaching pair with relative velocity v_ij and density ρ̄ (Bui et al.
        // 2008, eq. 32), μ_ij = h v_ij·r_ij/(r² + 0.01h²), with one division per pair.
        let add_viscosity = |term: &mut Matrix<D>,
                             viscosity: &ArtificialMonaghan1992,
                             v_ij: Vector<D>,
                             pair_r_ij: &Vector<D>,
                             r2: Real,
                             rho: Real| {
            let approach = v_ij.dot(pair_r_ij);
            if approach < 0.0 {
                let pi = viscosity.pi_of_approach(h * approach, r2 + eta2, rho);
                for k in 0..D {
                    term[(k, k)] -= pi;
                }
            }
        };
        let Particles {
            position,
            velocity,
            mass,
            density,
            ..
        } = soil;
        acceleration
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_CHUNK)
            .for_each(|(i, acceleration)| {
                let (v_i, rho_i) = (velocity[i], density[i]);
                let (term_i, tensile_i) = (stress_term[i], tensile_term[i]);
                let mut a_i = Vector::<D>::zeros();
                lists.for_each_neighbour(&kernel, position, i, |pair| {
                    let j = pair.index;
                    let mut term = term_i + stress_term[j];
                    if let Some(viscosity) = &viscosity {
                        let rho = 0.5 * (rho_i + density[j]);
                        let v_ij = v_i - velocity[j];
                        add_viscosity(&mut term, viscosity, v_ij, &pair.r_ij, pair.r2, rho);
                    }
                    if let Some(artificial_stress) = &artificial_stress {
                        let f = artificial_stress.pair_factor(kernel.value(pair.r));
                        term += (tensile_i + tensile_term[j]) * f;
                    }
                    a_i += term * pair.grad * mass[j];
                });
                let mut a_wall = Vector::<D>::zeros();
                let mut wall_normal = Vector::<D>::zeros();
                lists.for_each_wall(&kernel, position, &walls.position, i, |pair| {
                    let w = pair.index;
                    let mut term = term_i + wall_term[w];
                    if let Some(viscosity) = &wall_viscosity {
                        let v_w = dummy_velocity(
                            &position[i],
                            &v_i,
                            &(position[i] - pair.r_ij),
                            &walls.normal[w],
                            walls.depth[w],
                            &walls.velocity[w],
                            beta_max,
                            free_slip,
                        );
                        add_viscosity(&mut term, viscosity, v_i - v_w, &pair.r_ij, pair.r2, rho_i);
                    }
                    if let Some(artificial_stress) = &artificial_stress {
                        term += tensile_i * artificial_stress.pair_factor(kernel.value(pair.r));
                    }
                    a_wall += term * pair.grad * (rest_density * walls.volume[w]);
                    if let Some(repulsive) = &repulsive {
                        a_wall += repulsive.acceleration(&pair.r_ij);
                    }
                    if friction.is_some() {
                        wall_normal += walls.normal[w] * kernel.value(pair.r);
                    }
                });
                a_i += gravity + a_wall;
                if let Some(tan_delta) = friction {
                    a_i += coulomb_friction(&wall_normal, &a_wall, &v_i, &a_i, tan_delta, dt);
                }
                *acceleration = a_i - v_i * damping_rate;
            });
    }
}
