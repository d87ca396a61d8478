//! [`RigidBodies`]: the scene's bodies as moving dummy walls, pushed by the flow's pressure and
//! moved by rapier.

use std::ops::Range;

use geosph_boundary::WallParticles;
use geosph_core::{Domain, Real, Vector};
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use geosph_neighbours::CellGrid;
use geosph_sph::surface_load::{
    FluidField, LoadPoint, PRESSURE_SUMS, pressure_load_from_sums, pressure_sums,
};
use geosph_sph::{FlowShare, MotionError, WallMotion};

use crate::world::{FixedShape, MassProperties, Motion, World};

/// A body as the scene describes it, in the world at t = 0.
#[derive(Clone, Debug)]
pub struct BodyDescription<const D: usize> {
    /// Its name, for the diagnostics' columns.
    pub name: String,
    /// Density ρ_b, kg/m³.
    pub density: Real,
    /// Coulomb friction coefficient μ of its contacts.
    pub friction: Real,
    /// Its dummy particles in the solver's walls.
    pub walls: Range<usize>,
    /// Lattice points filling it, each the centre of a cell of volume `cell_volume`: its mass
    /// properties.
    pub interior: Vec<Vector<D>>,
    /// dx^D.
    pub cell_volume: Real,
    /// Quadrature points of its surface (normals out of the body, into the flow).
    pub surface: Vec<LoadPoint<D>>,
    /// Points whose convex hull is its contact shape.
    pub hull: Vec<Vector<D>>,
}

/// What the coupling needs of the run: the kernel the pressure is extrapolated with, gravity
/// and the domain the fluid is in.
#[derive(Clone, Debug)]
pub struct Coupling<const D: usize> {
    /// The scene's kernel.
    pub kernel: KernelKind,
    /// Its smoothing length h.
    pub smoothing_length: Real,
    /// Gravity g.
    pub gravity: Vector<D>,
    /// The domain.
    pub domain: Domain<D>,
    /// The particle spacing dx (the length unit of rapier's contact tolerances).
    pub spacing: Real,
    /// The background pressure of the fluid's equation of state.
    pub background_pressure: Real,
}

/// Why the bodies cannot be built or moved.
#[derive(Debug, thiserror::Error)]
pub enum BodyError {
    /// A body's shape cannot take contacts.
    #[error("body `{name}`: {message}")]
    Shape {
        /// The body.
        name: String,
        /// What is wrong.
        message: String,
    },
}

/// One body: its wall particles and surface in its own frame, and its last motion.
struct Body<const D: usize> {
    name: String,
    index: usize,
    walls: Range<usize>,
    position: Vec<Vector<D>>,
    normal: Vec<Vector<D>>,
    surface: Vec<LoadPoint<D>>,
    motion: Motion<D>,
    /// The step's mean linear and angular acceleration.
    acceleration: Vector<D>,
    angular: Vector<3>,
    force: Vector<D>,
}

impl<const D: usize> Body<D> {
    /// Its surface's quadrature points where its motion has them.
    fn surface_now(&self) -> impl Iterator<Item = LoadPoint<D>> + '_ {
        let Motion {
            centre, rotation, ..
        } = self.motion;
        self.surface.iter().map(move |p| LoadPoint {
            position: centre + rotation * p.position,
            normal: rotation * p.normal,
            area: p.area,
        })
    }

    /// Puts its wall particles where its motion has them, with the velocity and acceleration
    /// of those points of the body.
    fn place(&self, walls: &mut WallParticles<D>) {
        let now = &self.motion;
        for (k, w) in self.walls.clone().enumerate() {
            let r = now.rotation * self.position[k];
            let spin_r = now.spin.cross(&lift(&r));
            let turning = self.angular.cross(&lift(&r)) + now.spin.cross(&spin_r);
            walls.position[w] = now.centre + r;
            walls.normal[w] = now.rotation * self.normal[k];
            walls.velocity[w] = now.velocity + lower::<D>(&spin_r);
            walls.acceleration[w] = self.acceleration + lower::<D>(&turning);
        }
    }
}

/// Rigid bodies two-way coupled with the flow.
///
/// Each body is a set of dummy wall particles (the boundary treatment of the fixed walls,
/// extended to moving walls as Adami, Hu & Adams 2012, §2.3, allow: the wall's velocity
/// enters the no-slip mirror and its acceleration the pressure extrapolation). Once per
/// step the flow's pressure is integrated over the body's surface
/// ([`geosph_sph::surface_load::pressure_load`], hydrostatic extrapolation with g − a_body;
/// in a distributed run its sums over each rank's particles added over the ranks), rapier
/// advances the body under that load,
/// gravity and its contacts (Coulomb friction), and the wall particles follow rigidly:
///
/// x_w = x_c + R r_w,  n_w = R n_w⁰,  u_w = v_c + ω × R r_w,
/// a_w = a_c + α × R r_w + ω × (ω × R r_w),
///
/// with a_c and α the step's mean linear and angular acceleration. The coupling is explicit
/// (the body moves with the load at the end of the flow's step), stable while the body is
/// not much lighter than the fluid it displaces.
pub struct RigidBodies<const D: usize> {
    world: World<D>,
    bodies: Vec<Body<D>>,
    coupling: Coupling<D>,
    grid: CellGrid<D>,
    /// The pressure extrapolation's sums at every body's surface points, in body order
    /// (reused from step to step).
    sums: Vec<Real>,
}

impl<const D: usize> RigidBodies<D> {
    /// The `bodies`, whose wall particles are in `walls` at their start, colliding with the
    /// `fixed` obstacles and with each other.
    pub fn new(
        bodies: Vec<BodyDescription<D>>,
        fixed: &[FixedShape<D>],
        walls: &WallParticles<D>,
        coupling: Coupling<D>,
    ) -> Result<Self, BodyError> {
        let mut world = World::new(&coupling.gravity, coupling.spacing);
        for shape in fixed {
            world.add_fixed(shape);
        }
        let mut built = Vec::with_capacity(bodies.len());
        for body in bodies {
            let mass = mass_properties(&body.interior, body.cell_volume, body.density);
            let index = world
                .add_body(&mass, &body.hull, body.friction)
                .map_err(|message| BodyError::Shape {
                    name: body.name.clone(),
                    message: message.to_owned(),
                })?;
            let c = mass.centre;
            built.push(Body {
                index,
                position: walls.position[body.walls.clone()]
                    .iter()
                    .map(|x| x - c)
                    .collect(),
                normal: walls.normal[body.walls.clone()].to_vec(),
                surface: body
                    .surface
                    .iter()
                    .map(|p| LoadPoint {
                        position: p.position - c,
                        ..*p
                    })
                    .collect(),
                motion: world.motion(index),
                acceleration: Vector::zeros(),
                angular: Vector::zeros(),
                force: Vector::zeros(),
                name: body.name,
                walls: body.walls,
            });
        }
        let radius = coupling.kernel.support_factor() * coupling.smoothing_length;
        // Hashed when the domain has more cells than a dense index holds, as the flow's lists.
        let mut grid = CellGrid::fitting(coupling.domain.clone(), radius)
            .expect("the run's domain holds a grid of the kernel's support");
        // A particle that left the domain in this step still pushes on a body; the runner
        // removes it after the step.
        grid.bin_outside_in_edge_cells();
        Ok(Self {
            world,
            bodies: built,
            coupling,
            grid,
            sums: Vec::new(),
        })
    }

    /// The fluid's pressure force on each body at the last step (N; 2D: N/m).
    pub fn fluid_forces(&self) -> impl Iterator<Item = Vector<D>> + '_ {
        self.bodies.iter().map(|body| body.force)
    }
}

/// m = ρ_b Σ V, the centre of the lattice points and I = Σ m_k (|r_k|² 1 − r_k r_kᵀ) plus each
/// cell's own inertia (a cube or square of side a: m_k a²/6 about any axis through it).
pub fn mass_properties<const D: usize>(
    interior: &[Vector<D>],
    cell_volume: Real,
    density: Real,
) -> MassProperties<D> {
    let cell_mass = density * cell_volume;
    let mass = cell_mass * interior.len() as Real;
    let centre = interior.iter().sum::<Vector<D>>() / interior.len().max(1) as Real;
    let side2 = cell_volume.powf(2.0 / D as Real);
    let own = cell_mass * side2 / 6.0;
    let mut inertia = geosph_core::Matrix::<3>::zeros();
    for x in interior {
        let r = Vector::<3>::from_fn(|k, _| if k < D { x[k] - centre[k] } else { 0.0 });
        inertia += (geosph_core::Matrix::<3>::identity() * r.norm_squared() - r * r.transpose())
            * cell_mass;
    }
    inertia += geosph_core::Matrix::<3>::identity() * (own * interior.len() as Real);
    if D == 2 {
        // Plane motion: I_zz only, where the world reads it.
        inertia[(0, 0)] = inertia[(2, 2)];
    }
    MassProperties {
        mass,
        centre,
        inertia,
    }
}

/// The first D components of a 3-vector.
fn lower<const D: usize>(v: &Vector<3>) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| v[k])
}

/// A D-vector as a 3-vector (z = 0 in 2D).
fn lift<const D: usize>(v: &Vector<D>) -> Vector<3> {
    Vector::<3>::from_fn(|k, _| if k < D { v[k] } else { 0.0 })
}

/// The sums of the pressure extrapolation at one body's surface ([`pressure_sums`]), with
/// whichever kernel the scene names.
struct LoadSums<'a, const D: usize> {
    field: FluidField<'a, D>,
    body: &'a Body<D>,
    sums: &'a mut Vec<Real>,
}

impl<const D: usize> KernelVisitor<D> for LoadSums<'_, D> {
    type Output = ();

    fn visit<K: Kernel<D>>(self, kernel: K) {
        pressure_sums(&kernel, &self.field, self.body.surface_now(), self.sums);
    }
}

impl<const D: usize> WallMotion<D> for RigidBodies<D> {
    fn advance(
        &mut self,
        dt: Real,
        flow: FlowShare<'_, D>,
        walls: &mut WallParticles<D>,
    ) -> Result<(), MotionError> {
        let (fluid, owned) = (flow.particles, flow.owned);
        let pressure = fluid
            .pressure
            .as_deref()
            .ok_or_else(|| MotionError::Failed("rigid bodies need the fluid's pressure".into()))?;
        let position = &fluid.position[..owned];
        // A position the grid cannot bin (one that is not finite) fails the step on every
        // rank at once: the ranks agree on it in the collective below.
        let built = self.grid.build(position);
        let Coupling {
            kernel,
            smoothing_length,
            gravity,
            background_pressure,
            ..
        } = &self.coupling;
        // Each rank sums over the particles it owns; the ranks' sums, added in rank order,
        // are those over every particle, and every rank moves the bodies alike.
        self.sums.clear();
        for body in self.bodies.iter().filter(|_| built.is_ok()) {
            let field = FluidField {
                position,
                mass: &fluid.mass[..owned],
                density: &fluid.density[..owned],
                pressure: &pressure[..owned],
                grid: &self.grid,
                gravity: gravity - body.acceleration,
                background_pressure: *background_pressure,
            };
            let sums = &mut self.sums;
            kernel.dispatch(*smoothing_length, LoadSums { field, body, sums });
        }
        if built.is_err() {
            let points = self
                .bodies
                .iter()
                .map(|body| body.surface.len())
                .sum::<usize>();
            self.sums.resize(PRESSURE_SUMS * points, 0.0);
        }
        self.sums.push(Real::from(u8::from(built.is_err())));
        flow.sum_over_ranks(&mut self.sums);
        let failed = self.sums.pop().is_some_and(|ranks| ranks > 0.0);
        built?;
        if failed {
            return Err(MotionError::Failed(
                "the bodies' load: the neighbour search failed on another rank".into(),
            ));
        }
        let mut start = 0;
        for body in &mut self.bodies {
            let end = start + PRESSURE_SUMS * body.surface.len();
            let centre = body.motion.centre;
            let sums = &self.sums[start..end];
            start = end;
            let (force, torque) =
                pressure_load_from_sums(body.surface_now(), sums, &centre, *background_pressure);
            body.force = force;
            self.world.set_load(body.index, &force, &torque);
        }
        self.world.step(dt);
        for body in &mut self.bodies {
            let now = self.world.motion(body.index);
            let finite = now
                .centre
                .iter()
                .chain(&now.velocity)
                .all(|x| x.is_finite());
            if !finite {
                return Err(MotionError::Failed(format!(
                    "body `{}` reached a non-finite position or velocity",
                    body.name
                )));
            }
            body.acceleration = (now.velocity - body.motion.velocity) / dt;
            body.angular = (now.spin - body.motion.spin) / dt;
            body.motion = now;
            body.place(walls);
            let domain = &self.coupling.domain;
            if let Some(w) = body
                .walls
                .clone()
                .find(|&w| !domain.contains(&walls.position[w]))
            {
                return Err(MotionError::Failed(format!(
                    "body `{}` left the domain: its wall particle at {:?} is outside [{:?}, \
                     {:?}); enlarge the scene's `domain` or check the walls that should hold it",
                    body.name,
                    walls.position[w].as_slice(),
                    domain.min.as_slice(),
                    domain.max.as_slice()
                )));
            }
        }
        Ok(())
    }

    fn save_state(&self) -> Vec<u8> {
        let bodies: Vec<Real> = self
            .bodies
            .iter()
            .flat_map(|body| {
                let figures = body
                    .acceleration
                    .iter()
                    .chain(&body.angular)
                    .chain(&body.force);
                figures.copied().collect::<Vec<_>>()
            })
            .collect();
        postcard::to_allocvec(&(self.world.save_state(), bodies)).expect("bodies serialize")
    }

    fn restore_state(&mut self, state: &[u8], walls: &mut WallParticles<D>) -> Result<(), String> {
        let (world, figures): (Vec<u8>, Vec<Real>) = postcard::from_bytes(state)
            .map_err(|e| format!("the bodies' state does not load: {e}"))?;
        let per_body = 2 * D + 3;
        if figures.len() != per_body * self.bodies.len() {
            return Err(format!(
                "the checkpoint holds {} bodies, the scene {}",
                figures.len() / per_body,
                self.bodies.len()
            ));
        }
        self.world.restore_state(&world)?;
        for (body, figures) in self.bodies.iter_mut().zip(figures.chunks_exact(per_body)) {
            body.acceleration = Vector::<D>::from_column_slice(&figures[..D]);
            body.angular = Vector::<3>::from_column_slice(&figures[D..D + 3]);
            body.force = Vector::<D>::from_column_slice(&figures[D + 3..]);
            body.motion = self.world.motion(body.index);
            body.place(walls);
        }
        Ok(())
    }

    fn columns(&self) -> Vec<String> {
        let axes = ["x", "y", "z"];
        let mut columns = Vec::new();
        for body in &self.bodies {
            let name = &body.name;
            columns.extend(axes[..D].iter().map(|a| format!("{name}_{a}")));
            if D == 2 {
                columns.push(format!("{name}_angle"));
            } else {
                columns.extend(axes.iter().map(|a| format!("{name}_r{a}")));
            }
            columns.extend(axes[..D].iter().map(|a| format!("{name}_v{a}")));
            columns.extend(axes[..D].iter().map(|a| format!("{name}_F{a}")));
        }
        columns
    }

    fn plotted(&self) -> Vec<String> {
        let up = ["x", "y", "z"][D - 1];
        self.bodies
            .iter()
            .map(|body| format!("{}_{up}", body.name))
            .collect()
    }

    fn sample(&self, row: &mut Vec<Real>) {
        for body in &self.bodies {
            let motion = &body.motion;
            row.extend(motion.centre.iter());
            if D == 2 {
                row.push(motion.angle[2]);
            } else {
                row.extend(motion.angle.iter());
            }
            row.extend(motion.velocity.iter());
            row.extend(body.force.iter());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells of a lattice-aligned 0.4 m × 0.2 m box at dx = 0.02 m give its exact mass,
    /// centre and polar inertia m (a² + b²)/12 (2D), and in 3D the box's principal moments
    /// m (b² + c²)/12, … .
    #[test]
    fn lattice_cells_give_a_box_its_exact_mass_properties() {
        let dx = 0.02;
        let cells = |n: [usize; 3], d: usize| -> Vec<[Real; 3]> {
            let mut points = Vec::new();
            for k in 0..n[2].max(1) {
                for j in 0..n[1] {
                    for i in 0..n[0] {
                        let c = [i, j, k].map(|m| (m as Real + 0.5) * dx);
                        points.push(if d == 2 { [c[0], c[1], 0.0] } else { c });
                    }
                }
            }
            points
        };
        let plane: Vec<Vector<2>> = cells([20, 10, 0], 2)
            .iter()
            .map(|c| Vector::<2>::new(c[0], c[1]))
            .collect();
        let m2 = mass_properties(&plane, dx * dx, 500.0);
        let mass = 500.0 * 0.4 * 0.2;
        approx::assert_relative_eq!(m2.mass, mass, max_relative = 1e-12);
        approx::assert_relative_eq!(m2.centre, Vector::<2>::new(0.2, 0.1), epsilon = 1e-12);
        let polar = mass * (0.4 * 0.4 + 0.2 * 0.2) / 12.0;
        approx::assert_relative_eq!(m2.inertia[(0, 0)], polar, max_relative = 1e-9);

        let space: Vec<Vector<3>> = cells([20, 10, 5], 3)
            .iter()
            .map(|c| Vector::<3>::new(c[0], c[1], c[2]))
            .collect();
        let m3 = mass_properties(&space, dx * dx * dx, 500.0);
        let mass = 500.0 * 0.4 * 0.2 * 0.1;
        let (a, b, c) = (0.4, 0.2, 0.1);
        let expected = [b * b + c * c, a * a + c * c, a * a + b * b].map(|s| mass * s / 12.0);
        for k in 0..3 {
            approx::assert_relative_eq!(m3.inertia[(k, k)], expected[k], max_relative = 1e-9);
        }
        approx::assert_relative_eq!(m3.inertia[(0, 1)], 0.0, epsilon = 1e-12);
    }
}
