//! The rigid-body world: rapier's 2D or 3D engine behind one interface on geosph's
//! `Vector<D>`, so the rest of the crate is written once for both dimensions.

use geosph_core::{Matrix, Real, Vector};
use rapier2d_f64::prelude as r2;
use rapier3d_f64::prelude as r3;

/// A fixed obstacle bodies collide with (the scene's walls, as their surfaces).
#[derive(Clone, Debug, PartialEq)]
pub enum FixedShape<const D: usize> {
    /// The box [min, max], solid.
    Box {
        /// Lower corner.
        min: Vector<D>,
        /// Upper corner.
        max: Vector<D>,
    },
    /// Line segments (2D): a polyline wall or the section of a mesh wall.
    Segments(Vec<[Vector<D>; 2]>),
    /// Triangles (3D): a mesh wall.
    Triangles(Vec<[Vector<D>; 3]>),
}

/// Mass, centre of mass and inertia of a body (2D: per unit thickness, inertia about z in the
/// (0, 0) entry).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties<const D: usize> {
    /// Mass m.
    pub mass: Real,
    /// Centre of mass.
    pub centre: Vector<D>,
    /// Inertia tensor about the centre of mass (3D); 2D: I_zz in entry (0, 0).
    pub inertia: Matrix<3>,
}

/// Where a body is and how it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion<const D: usize> {
    /// Centre of mass.
    pub centre: Vector<D>,
    /// Rotation from the body's initial orientation.
    pub rotation: Matrix<D>,
    /// Velocity of the centre of mass.
    pub velocity: Vector<D>,
    /// Angular velocity ω (2D: z component only).
    pub spin: Vector<3>,
    /// The rotation as a scaled axis (2D: the angle in z).
    pub angle: Vector<3>,
}

enum Engine {
    Plane(Box<r2::PhysicsWorld>),
    Space(Box<r3::PhysicsWorld>),
}

/// rapier's world of the scene's bodies and the fixed obstacles they can touch.
pub struct World<const D: usize> {
    engine: Engine,
    plane: Vec<r2::RigidBodyHandle>,
    space: Vec<r3::RigidBodyHandle>,
}

fn v2<const D: usize>(x: &Vector<D>) -> r2::Vector {
    r2::Vector::new(x[0], x[1])
}

fn v3<const D: usize>(x: &Vector<D>) -> r3::Vector {
    r3::Vector::new(x[0], x[1], x[2])
}

fn from_slice<const D: usize>(values: &[Real]) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| values[k])
}

impl<const D: usize> World<D> {
    /// An empty world with `gravity`, whose contact tolerances (allowed penetration,
    /// prediction distance) scale with `length`, the particle spacing: rapier's defaults are
    /// for bodies of metres. Rapier's speed cap (400 length units per second) is lifted: the
    /// flow, not the engine, sets a body's speed.
    pub fn new(gravity: &Vector<D>, length: Real) -> Self {
        let engine = if D == 2 {
            let mut world = r2::PhysicsWorld::new();
            world.gravity = v2(gravity);
            world.integration_parameters.length_unit = length;
            world.integration_parameters.normalized_max_linear_velocity = Real::MAX;
            Engine::Plane(Box::new(world))
        } else {
            let mut world = r3::PhysicsWorld::new();
            world.gravity = v3(gravity);
            world.integration_parameters.length_unit = length;
            world.integration_parameters.normalized_max_linear_velocity = Real::MAX;
            Engine::Space(Box::new(world))
        };
        Self {
            engine,
            plane: Vec::new(),
            space: Vec::new(),
        }
    }

    /// Adds a fixed obstacle (no friction of its own: a contact takes the body's, see
    /// [`World::add_body`]).
    pub fn add_fixed(&mut self, shape: &FixedShape<D>) {
        match &mut self.engine {
            Engine::Plane(world) => {
                let collider = match shape {
                    FixedShape::Box { min, max } => {
                        let half = (max - min) * 0.5;
                        r2::ColliderBuilder::cuboid(half[0], half[1])
                            .translation(v2(&((min + max) * 0.5)))
                    }
                    FixedShape::Segments(segments) => {
                        let vertices = segments.iter().flat_map(|s| [v2(&s[0]), v2(&s[1])]);
                        let indices = (0..segments.len() as u32).map(|k| [2 * k, 2 * k + 1]);
                        r2::ColliderBuilder::polyline(vertices.collect(), Some(indices.collect()))
                    }
                    FixedShape::Triangles(_) => unreachable!("triangles are 3D"),
                };
                world.colliders.insert(collider.friction(0.0));
            }
            Engine::Space(world) => {
                let collider = match shape {
                    FixedShape::Box { min, max } => {
                        let half = (max - min) * 0.5;
                        r3::ColliderBuilder::cuboid(half[0], half[1], half[2])
                            .translation(v3(&((min + max) * 0.5)))
                    }
                    FixedShape::Triangles(triangles) => {
                        let vertices = triangles.iter().flat_map(|t| t.iter().map(v3));
                        let indices =
                            (0..triangles.len() as u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]);
                        r3::ColliderBuilder::trimesh(vertices.collect(), indices.collect())
                            .expect("a wall mesh has triangles")
                    }
                    FixedShape::Segments(_) => unreachable!("segments are 2D"),
                };
                world.colliders.insert(collider.friction(0.0));
            }
        }
    }

    /// Adds a dynamic body with `mass` properties whose contact shape is the convex hull of
    /// `hull` (points in the world at the start), with Coulomb friction coefficient `friction`
    /// against every obstacle and body (rapier's `Max` rule makes the contact take it);
    /// returns its index.
    pub fn add_body(
        &mut self,
        mass: &MassProperties<D>,
        hull: &[Vector<D>],
        friction: Real,
    ) -> Result<usize, String> {
        let local: Vec<Vector<D>> = hull.iter().map(|x| x - mass.centre).collect();
        match &mut self.engine {
            Engine::Plane(world) => {
                let points: Vec<r2::Vector> = local.iter().map(v2).collect();
                let collider = r2::ColliderBuilder::convex_hull(&points)
                    .ok_or("its points span no area")?
                    .density(0.0)
                    .friction(friction)
                    .friction_combine_rule(r2::CoefficientCombineRule::Max);
                let properties =
                    r2::MassProperties::new(r2::Vector::ZERO, mass.mass, mass.inertia[(0, 0)]);
                let body = r2::RigidBodyBuilder::dynamic()
                    .translation(v2(&mass.centre))
                    .additional_mass_properties(properties)
                    .can_sleep(false);
                self.plane.push(world.insert(body, collider).0);
                Ok(self.plane.len() - 1)
            }
            Engine::Space(world) => {
                let points: Vec<r3::Vector> = local.iter().map(v3).collect();
                let collider = r3::ColliderBuilder::convex_hull(&points)
                    .ok_or("its points span no volume")?
                    .density(0.0)
                    .friction(friction)
                    .friction_combine_rule(r3::CoefficientCombineRule::Max);
                let i = &mass.inertia;
                let inertia = r3::Matrix::from_cols_array(&[
                    i[(0, 0)],
                    i[(1, 0)],
                    i[(2, 0)],
                    i[(0, 1)],
                    i[(1, 1)],
                    i[(2, 1)],
                    i[(0, 2)],
                    i[(1, 2)],
                    i[(2, 2)],
                ]);
                let properties =
                    r3::MassProperties::with_inertia_matrix(r3::Vector::ZERO, mass.mass, inertia);
                let body = r3::RigidBodyBuilder::dynamic()
                    .translation(v3(&mass.centre))
                    .additional_mass_properties(properties)
                    .can_sleep(false);
                self.space.push(world.insert(body, collider).0);
                Ok(self.space.len() - 1)
            }
        }
    }

    /// Sets the external force and torque (about the centre of mass) on body `index` for the
    /// next step; gravity is the world's own.
    pub fn set_load(&mut self, index: usize, force: &Vector<D>, torque: &Vector<3>) {
        match &mut self.engine {
            Engine::Plane(world) => {
                let body = &mut world.bodies[self.plane[index]];
                body.reset_forces(false);
                body.reset_torques(false);
                body.add_force(v2(force), false);
                body.add_torque(torque[2], false);
            }
            Engine::Space(world) => {
                let body = &mut world.bodies[self.space[index]];
                body.reset_forces(false);
                body.reset_torques(false);
                body.add_force(v3(force), false);
                body.add_torque(v3(torque), false);
            }
        }
    }

    /// Advances every body by `dt`, contacts and friction included.
    pub fn step(&mut self, dt: Real) {
        match &mut self.engine {
            Engine::Plane(world) => {
                world.integration_parameters.dt = dt;
                world.step();
            }
            Engine::Space(world) => {
                world.integration_parameters.dt = dt;
                world.step();
            }
        }
    }

    /// The engine's complete state (bodies, colliders, contacts and their warm start), for a
    /// checkpoint: a world restored from it steps on bitwise as this one.
    pub fn save_state(&self) -> Vec<u8> {
        let bytes = match &self.engine {
            Engine::Plane(world) => postcard::to_allocvec(world.as_ref()),
            Engine::Space(world) => postcard::to_allocvec(world.as_ref()),
        };
        bytes.expect("rapier's world serializes")
    }

    /// Continues from `state`, saved by [`World::save_state`] of a world built the same way.
    pub fn restore_state(&mut self, state: &[u8]) -> Result<(), String> {
        let error = |e: postcard::Error| format!("the rigid-body world does not load: {e}");
        match &mut self.engine {
            Engine::Plane(world) => **world = postcard::from_bytes(state).map_err(error)?,
            Engine::Space(world) => **world = postcard::from_bytes(state).map_err(error)?,
        }
        Ok(())
    }

    /// Where body `index` is and how it moves.
    pub fn motion(&self, index: usize) -> Motion<D> {
        match &self.engine {
            Engine::Plane(world) => {
                let body = &world.bodies[self.plane[index]];
                let (t, v, rotation) = (body.translation(), body.linvel(), body.rotation());
                let (c, s) = (rotation.cos(), rotation.sin());
                Motion {
                    centre: from_slice(&[t.x, t.y]),
                    rotation: Matrix::<D>::from_fn(|r, k| [[c, -s], [s, c]][r][k]),
                    velocity: from_slice(&[v.x, v.y]),
                    spin: Vector::<3>::new(0.0, 0.0, body.angvel()),
                    angle: Vector::<3>::new(0.0, 0.0, rotation.angle()),
                }
            }
            Engine::Space(world) => {
                let body = &world.bodies[self.space[index]];
                let (t, v, w) = (body.translation(), body.linvel(), body.angvel());
                let q = *body.rotation();
                let columns = [q * r3::Vector::X, q * r3::Vector::Y, q * r3::Vector::Z];
                let a = q.to_scaled_axis();
                Motion {
                    centre: from_slice(&[t.x, t.y, t.z]),
                    rotation: Matrix::<D>::from_fn(|r, k| columns[k][r]),
                    velocity: from_slice(&[v.x, v.y, v.z]),
                    spin: Vector::<3>::new(w.x, w.y, w.z),
                    angle: Vector::<3>::new(a.x, a.y, a.z),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square<const D: usize>() -> (MassProperties<D>, Vec<Vector<D>>) {
        let hull = (0..1 << D)
            .map(|k| Vector::<D>::from_fn(|a, _| if k >> a & 1 == 1 { 0.5 } else { -0.5 }))
            .collect();
        let inertia = Matrix::<3>::identity() * (1.0 / 6.0);
        let mass = MassProperties {
            mass: 1.0,
            centre: Vector::zeros(),
            inertia,
        };
        (mass, hull)
    }

    /// Without gravity, a force F and a torque τ about z for one step of Δt give
    /// v = F Δt/m, ω = τ Δt/I and a counter-clockwise turn about z of at most ω Δt (rapier
    /// takes the step in substeps, over which ω grows), read back in the `Motion` the same
    /// way in 2D and 3D: the rotation matrix turns x towards y by the reported angle.
    fn a_kick_turns_the_body_counter_clockwise<const D: usize>() {
        let mut world = World::<D>::new(&Vector::zeros(), 1.0);
        let (mass, hull) = unit_square::<D>();
        let index = world.add_body(&mass, &hull, 0.0).unwrap();
        let dt = 0.01;
        let force = Vector::<D>::from_fn(|k, _| if k == 0 { 2.0 } else { 0.0 });
        world.set_load(index, &force, &Vector::<3>::new(0.0, 0.0, 1.0 / 6.0));
        world.step(dt);
        let motion = world.motion(index);
        approx::assert_relative_eq!(motion.velocity[0], 2.0 * dt, max_relative = 1e-9);
        approx::assert_relative_eq!(motion.spin[2], dt, max_relative = 1e-9);
        let angle = motion.angle[2];
        assert!(
            angle > 0.0 && angle <= dt * dt * (1.0 + 1e-9),
            "angle {angle}"
        );
        // The x axis turned towards y.
        approx::assert_relative_eq!(motion.rotation[(1, 0)], angle.sin(), max_relative = 1e-6);
        approx::assert_relative_eq!(motion.rotation[(0, 1)], -angle.sin(), max_relative = 1e-6);
        approx::assert_relative_eq!(
            motion.rotation.transpose() * motion.rotation,
            Matrix::<D>::identity(),
            epsilon = 1e-12
        );
    }

    #[test]
    fn a_kick_turns_the_body_counter_clockwise_in_2d_and_3d() {
        a_kick_turns_the_body_counter_clockwise::<2>();
        a_kick_turns_the_body_counter_clockwise::<3>();
    }
}
