//! Particles, walls and solver inputs of a scene.

use geosph_boundary::{WallParticles, generate};
use geosph_core::{Domain, Particles, Real, Vector};
use geosph_kernels::KernelKind;
use geosph_sph::EquationOfState;
use geosph_sph::SphSetup;

use crate::bodies::{fixed_shape_of_tank, mesh_shape};
use crate::error::SceneError;
use crate::format::{Region, Scene, WallSpec};
use crate::initial::{initial_speed, jitter, set_velocity, vector};
pub use crate::mesh_walls::LoadSurface;
use crate::mesh_walls::{load_surface, mesh_walls, unfolded};
use crate::periodic::periodic_span;
use crate::proximity::overlap;
use crate::regions::{BlockReport, Filled, fill_blocks};
use crate::validate::MAX_PARTICLES;
use geosph_bodies::{BodyDescription, FixedShape};

/// What a solver is built from: the scene turned into particles and numbers.
#[derive(Clone, Debug)]
pub struct Setup<const D: usize> {
    /// Fluid particles, at rest, with hydrostatic density when asked.
    pub fluid: Particles<D>,
    /// Wall particles.
    pub walls: WallParticles<D>,
    /// The domain every particle must stay in.
    pub domain: Domain<D>,
    /// Kernel.
    pub kernel: KernelKind,
    /// Smoothing length h = smoothing_ratio · dx.
    pub smoothing_length: Real,
    /// ρ₀ of the fluid.
    pub rest_density: Real,
    /// c₀, given or 10 × max(√(2 |g| H), largest initial speed).
    pub sound_speed: Real,
    /// Gravity.
    pub gravity: Vector<D>,
    /// Height H of the fluid (extent along the last axis).
    pub fluid_height: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// How the neighbour search indexes the cells (`domain.cells`).
    pub cell_index: geosph_sph::CellIndex,
    /// How each fluid block was filled.
    pub blocks: Vec<BlockReport>,
    /// The surfaces of the scene's load gauges (`output.loads`), in their order.
    pub loads: Vec<LoadSurface<D>>,
    /// The scene's rigid bodies; their dummy particles are the last of `walls`.
    pub bodies: Vec<BodyDescription<D>>,
    /// The fixed walls as the bodies collide with them (empty without bodies).
    pub fixed: Vec<FixedShape<D>>,
}

impl<const D: usize> Setup<D> {
    /// The fluid particles, and the rest as the inputs of a fluid solver.
    pub fn split(self) -> (Particles<D>, SphSetup<D>) {
        let solver_inputs = SphSetup {
            kernel: self.kernel,
            smoothing_length: self.smoothing_length,
            domain: self.domain,
            rest_density: self.rest_density,
            sound_speed: self.sound_speed,
            gravity: self.gravity,
            walls: self.walls,
            spacing: self.spacing,
            cell_index: self.cell_index,
            block_ids: block_ids(&self.blocks),
        };
        (self.fluid, solver_inputs)
    }
}

/// The ids of each block's particles: the particles are made in block order with ids from 0
/// ([`Particles::at_rest`]).
fn block_ids(blocks: &[BlockReport]) -> Vec<std::ops::Range<u32>> {
    let mut start = 0;
    blocks
        .iter()
        .map(|block| {
            let end = start + block.particles as u32;
            let ids = start..end;
            start = end;
            ids
        })
        .collect()
}

/// 2D wall particles as `D`-dimensional ones (used for D = 2 only, after validation).
fn to_dimension<const D: usize>(plane: WallParticles<2>) -> WallParticles<D> {
    let lift = |v: &Vector<2>| Vector::<D>::from_fn(|k, _| if k < 2 { v[k] } else { 0.0 });
    WallParticles {
        position: plane.position.iter().map(lift).collect(),
        velocity: plane.velocity.iter().map(lift).collect(),
        acceleration: plane.acceleration.iter().map(lift).collect(),
        volume: plane.volume,
        normal: plane.normal.iter().map(lift).collect(),
        depth: plane.depth,
        pressure: plane.pressure,
        density: plane.density,
        viscous_velocity: plane.viscous_velocity.iter().map(lift).collect(),
    }
}

/// Builds the particles and solver inputs of a validated `scene` in `D` dimensions.
///
/// # Panics
/// If `D` differs from `scene.dimension` (a programming error: dispatch on the dimension).
pub fn build<const D: usize>(scene: &Scene) -> Result<Setup<D>, SceneError> {
    assert_eq!(
        scene.dimension, D,
        "scene dimension and build dimension differ"
    );
    scene.validate()?;
    let dx = scene.dx;
    let up = D - 1;
    let kernel: KernelKind = scene.kernel.parse().expect("validated");
    let smoothing_length = scene.smoothing_ratio * dx;
    let gravity = match &scene.gravity {
        Some(g) => vector::<D>(g),
        None => Vector::<D>::from_fn(|k, _| if k == up { -9.81 } else { 0.0 }),
    };
    let fluid_spec = scene.fluid.as_ref().expect("validated");

    // Fluid particles and the free-surface height above each (its block's top).
    let Filled {
        mut position,
        surface,
        blocks,
    } = fill_blocks::<D>(scene)?;
    if fluid_spec.jitter > 0.0 {
        jitter(&mut position, fluid_spec.jitter * dx);
    }
    let bottom = position
        .iter()
        .map(|p| p[up])
        .fold(Real::INFINITY, Real::min)
        - 0.5 * dx;
    let top = surface.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    let fluid_height = top - bottom;

    // How the particles start is the solver configuration's decision.
    let start = scene.solver.particle_start();
    let hydrostatic = fluid_spec.hydrostatic && start.hydrostatic;
    let g = gravity.norm();
    // The expected largest speed: the collapse speed √(2 g H), the initial speed or the speed
    // of a moving wall.
    let wall_speed = scene
        .walls
        .iter()
        .map(|wall| match wall {
            WallSpec::Polyline { velocity, .. } => velocity.0.hypot(velocity.1),
            WallSpec::Tank { .. } | WallSpec::Mesh { .. } => 0.0,
        })
        .fold(0.0, Real::max);
    let largest_speed = (2.0 * g * fluid_height)
        .sqrt()
        .max(initial_speed(&fluid_spec.velocity, &position))
        .max(wall_speed);
    // A gas's reference state is (ρ₀, p₀) of the fluid, its sound speed that state's.
    let gas = crate::gas::gas_law(scene);
    let gas_pressure = fluid_spec.pressure.filter(|_| gas.is_some());
    let sound_speed = match (gas, start.sound_speed) {
        (Some(law), _) => law.sound_speed(fluid_spec.density, gas_pressure.expect("validated")),
        (None, Some(c0)) => c0,
        (None, None) if largest_speed > 0.0 => 10.0 * largest_speed,
        (None, None) => {
            return Err(SceneError::Field {
                field: "solver.sound_speed".into(),
                message: "must be given when gravity is zero, the fluid starts at rest and no \
                          wall moves (the default is 10 × max(√(2 g H), initial speed, wall \
                          speed))"
                    .into(),
            });
        }
    };
    let rest_density = fluid_spec.density;
    let background_pressure = gas_pressure.unwrap_or(start.background_pressure);
    let eos = EquationOfState {
        kind: start.equation_of_state,
        rest_density,
        sound_speed,
        background_pressure,
    };
    let mass = rest_density * dx.powi(D as i32);
    let mut fluid = Particles::at_rest(position, mass, rest_density);
    if hydrostatic {
        // The pressure is the initial guess of the incompressible solvers; WCSPH recomputes
        // it from the density.
        let mut pressure = vec![0.0; fluid.len()];
        for (i, (rho, p)) in fluid.density.iter_mut().zip(&mut pressure).enumerate() {
            let depth = (surface[i] - fluid.position[i][up]).max(0.0);
            *p = rest_density * g * depth + background_pressure;
            *rho = eos.density(*p);
        }
        fluid.pressure = Some(pressure);
    }
    if let Some(law) = gas {
        crate::gas::set_state(&mut fluid, fluid_spec, &blocks, law, dx.powi(D as i32));
    }
    set_velocity(&mut fluid, &fluid_spec.velocity, &eos);

    let mut walls = WallParticles::default();
    // The load gauges' surfaces with their index in `output.loads`.
    let mut loads = Vec::new();
    // The first wall particle of each wall, to name the wall a fluid particle overlaps.
    let mut wall_starts = Vec::with_capacity(scene.walls.len());
    // What bodies collide with; made only when there are bodies.
    let mut fixed = Vec::new();
    let with_bodies = !scene.bodies.is_empty();
    for (index, wall) in scene.walls.iter().enumerate() {
        wall_starts.push(walls.len());
        match wall {
            WallSpec::Tank {
                min,
                max,
                layers,
                open_top,
            } => {
                let (min, max) = (vector::<D>(min), vector::<D>(max));
                let open = periodic_span::<D>(scene, &format!("walls[{index}]"), &min, &max)?;
                let tank = generate::tank_open_along(
                    &min,
                    &max,
                    dx,
                    *layers,
                    *open_top,
                    open,
                    rest_density,
                );
                let margin = 1e-9 * dx;
                let beyond = |x: &Vector<D>| {
                    (0..D).find(|&k| x[k] > max[k] + margin && (k != up || !open_top))
                };
                if let Some(i) = fluid
                    .position
                    .iter()
                    .position(|x| beyond(x).is_some() || (0..D).any(|k| x[k] < min[k] - margin))
                {
                    let x = &fluid.position[i];
                    // The fluid's farthest reach past the face.
                    let reach = |k: usize| {
                        let past = fluid.position.iter().map(|x| x[k] - max[k]);
                        past.fold(Real::NEG_INFINITY, Real::max)
                    };
                    // A Box block fills whole rows of dx from its lower corner: its last row
                    // passes its upper face by less than dx/2.
                    let pokes_out = |k: usize| {
                        reach(k) >= 0.5 * dx
                            || fluid_spec.blocks.iter().any(|block| {
                                if let Region::Box { max: top, .. } = block {
                                    top[k] > max[k] + margin
                                } else {
                                    false
                                }
                            })
                    };
                    let hint = match beyond(x) {
                        Some(k) if pokes_out(k) => format!(
                            " (the fluid reaches {:.3e} m past its inner face on axis {k}: a \
                             block extends beyond the tank)",
                            reach(k)
                        ),
                        Some(k) => format!(
                            " ({:.3e} m past its inner face on axis {k}; a Box block is filled \
                             with whole rows of dx from its lower corner, so when dx = {dx} m \
                             does not divide the block's extent its last row passes the \
                             block's upper face: choose a dx that divides it)",
                            x[k] - max[k]
                        ),
                        None => String::new(),
                    };
                    return Err(SceneError::Field {
                        field: format!("walls[{index}]"),
                        message: format!(
                            "fluid particle {i} at {:?} lies in or beyond the tank's walls{hint}",
                            x.as_slice()
                        ),
                    });
                }
                walls.extend(tank);
                if with_bodies {
                    let thickness = *layers as Real * dx;
                    fixed.extend(fixed_shape_of_tank(&min, &max, thickness, *open_top));
                }
            }
            WallSpec::Polyline {
                points,
                layers,
                flow_side,
                velocity,
            } => {
                let points: Vec<Vector<2>> = points
                    .iter()
                    .map(|&(x, y)| Vector::<2>::new(x, y))
                    .collect();
                if let Some((i, behind)) = crate::proximity::behind_polyline(
                    &fluid.position,
                    &points,
                    *flow_side,
                    *layers as Real * dx,
                ) {
                    return Err(SceneError::Field {
                        field: format!("walls[{index}]"),
                        message: format!(
                            "fluid particle {i} at {:?} lies {behind:.3e} m behind the line, inside the wall's {layers} layers: the fluid overlaps the wall (flow_side: {flow_side:?})",
                            fluid.position[i].as_slice()
                        ),
                    });
                }
                let mut plane = generate::polyline(&points, dx, *layers, *flow_side, rest_density);
                plane
                    .velocity
                    .fill(Vector::<2>::new(velocity.0, velocity.1));
                walls.extend(to_dimension::<D>(plane));
                if with_bodies {
                    let lift = |x: &Vector<2>| Vector::<D>::from_fn(|k, _| x[k]);
                    fixed.push(FixedShape::Segments(
                        points
                            .windows(2)
                            .map(|s| [lift(&s[0]), lift(&s[1])])
                            .collect(),
                    ));
                }
            }
            WallSpec::Mesh {
                file,
                scale,
                offset,
                section,
                layers,
            } => {
                let (particles, surface) = mesh_walls::<D>(
                    scene,
                    &format!("walls[{index}]"),
                    (file, *scale, offset, *section),
                    *layers,
                    rest_density,
                    &walls.position,
                )?;
                walls.extend(particles);
                if scene.output.loads.iter().any(|spec| spec.wall == index) {
                    // (Bodies are refused with periodic axes: `Scene::validate`.)
                    unfolded::<D>(scene, index, &surface)?;
                }
                if with_bodies {
                    fixed.push(mesh_shape::<D>(&surface, *section, dx));
                }
                for (k, spec) in scene.output.loads.iter().enumerate() {
                    if spec.wall == index {
                        loads.push((k, load_surface::<D>(spec, &surface, *section, dx)));
                    }
                }
            }
        }
    }

    let bodies = crate::bodies::build::<D>(
        scene,
        rest_density,
        &mut walls,
        (&fluid.position, &wall_starts),
    )?;

    // Meshes count once read: the scene's estimate could not bound them.
    let particles = fluid.len() + walls.len();
    if particles as Real > MAX_PARTICLES {
        return Err(SceneError::Field {
            field: "dx".into(),
            message: format!(
                "{dx} m makes {particles} particles with the meshes, more than \
                 {MAX_PARTICLES:.0e}: increase dx or shrink the regions"
            ),
        });
    }
    if let Some((i, j, distance)) = overlap(&fluid.position, &walls.position, 0.5 * dx) {
        let field = match bodies.iter().position(|body| body.walls.contains(&j)) {
            Some(k) => format!("bodies[{k}]"),
            None => format!(
                "walls[{}]",
                wall_starts.partition_point(|&start| start <= j) - 1
            ),
        };
        return Err(SceneError::Field {
            field,
            message: format!(
                "fluid particle {i} at {:?} is {distance:.3e} m from wall particle {j} at {:?}, \
                 closer than dx/2 = {}: the fluid overlaps the wall",
                fluid.position[i].as_slice(),
                walls.position[j].as_slice(),
                0.5 * dx
            ),
        });
    }

    let domain = match &scene.domain {
        Some(spec) => {
            let mut periodic = [false; D];
            for (k, &p) in spec.periodic.iter().enumerate() {
                periodic[k] = p;
            }
            Domain::with_periodic(vector::<D>(&spec.min), vector::<D>(&spec.max), periodic)
                .map_err(|error| SceneError::Field {
                    field: "domain".into(),
                    message: error.to_string(),
                })?
        }
        None => {
            let margin = 3.0 * kernel.support_factor() * smoothing_length;
            let mut min = Vector::<D>::repeat(Real::INFINITY);
            let mut max = Vector::<D>::repeat(Real::NEG_INFINITY);
            for x in fluid.position.iter().chain(&walls.position) {
                min = min.inf(x);
                max = max.sup(x);
            }
            min.add_scalar_mut(-margin);
            max.add_scalar_mut(margin);
            // Headroom for splashes: a jet at the collapse speed √(2 g H) × 1.7 rises 3 H.
            max[up] += 3.0 * fluid_height;
            Domain::new(min, max).expect("a bounding box with margins is never empty")
        }
    };
    for x in &mut fluid.position {
        domain.wrap(x);
    }
    for (set, points) in [("fluid", &fluid.position), ("wall", &walls.position)] {
        if let Some(i) = points.iter().position(|x| !domain.contains(x)) {
            return Err(SceneError::Field {
                field: "domain".into(),
                message: format!(
                    "{set} particle {i} at {:?} lies outside [{:?}, {:?})",
                    points[i].as_slice(),
                    domain.min.as_slice(),
                    domain.max.as_slice()
                ),
            });
        }
    }

    Ok(Setup {
        fluid,
        walls,
        domain,
        kernel,
        smoothing_length,
        rest_density,
        sound_speed,
        gravity,
        fluid_height,
        spacing: dx,
        cell_index: scene
            .domain
            .as_ref()
            .map_or(Default::default(), |domain| domain.cells.index()),
        blocks,
        loads: {
            loads.sort_by_key(|(k, _)| *k);
            loads.into_iter().map(|(_, surface)| surface).collect()
        },
        bodies,
        fixed,
    })
}
