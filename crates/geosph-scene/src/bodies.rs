//! Rigid bodies of a scene: the dummy particles, interior and surface each is built from
//! (`geosph-bodies` moves them), and the walls they collide with.

use geosph_bodies::{BodyDescription, FixedShape};
use geosph_boundary::WallParticles;
use geosph_core::{Real, Vector};
use geosph_geometry::{Section, Solid, SurfaceMesh, SurfacePoint, WallSite, WallSurface};
use geosph_sph::surface_load::LoadPoint;

use crate::body_spec::{BodyShape, BodySpec};
use crate::checks::fail;
use crate::error::SceneError;
use crate::format::Scene;
use crate::initial::vector;
use crate::proximity::overlap;
use crate::regions::{check_size, read_mesh};

/// The closed mesh of a body's shape and the section plane a 2D scene cuts it with.
fn shape_mesh<const D: usize>(
    scene: &Scene,
    body: &BodySpec,
) -> Result<(SurfaceMesh, Real), String> {
    match &body.shape {
        BodyShape::Box { min, max } => {
            let (min, max) = (vector::<D>(min), vector::<D>(max));
            let lift = |x: &Vector<D>, y: Real| {
                if D == 2 {
                    Vector::<3>::new(x[0], y, x[1])
                } else {
                    Vector::<3>::new(x[0], x[1], x[2])
                }
            };
            let half = (max - min).max();
            let mesh = geosph_geometry::primitives::cuboid(&lift(&min, -half), &lift(&max, half));
            Ok((mesh, 0.0))
        }
        BodyShape::Mesh {
            file,
            scale,
            offset,
            section,
        } => Ok((
            read_mesh::<D>(file, *scale, offset, scene.folder.as_deref())?,
            *section,
        )),
    }
}

/// A mesh wall's surface as bodies collide with it: its triangles (3D), or in 2D the pieces
/// of its section y = `section`, dx/2 long.
pub(crate) fn mesh_shape<const D: usize>(
    surface: &WallSurface,
    section: Real,
    dx: Real,
) -> FixedShape<D> {
    let point = |x: &Vector<3>| Vector::<D>::from_fn(|k, _| x[k]);
    if D == 2 {
        let pieces = surface.section_quadrature(&Section::at_y(section), 0.5 * dx);
        FixedShape::Segments(
            pieces
                .iter()
                .map(|p| {
                    let tangent = Vector::<2>::new(-p.normal[1], p.normal[0]) * (0.5 * p.area);
                    let lift = |x: Vector<2>| Vector::<D>::from_fn(|k, _| x[k]);
                    [lift(p.position - tangent), lift(p.position + tangent)]
                })
                .collect(),
        )
    } else {
        let mesh = surface.mesh();
        FixedShape::Triangles(
            mesh.triangles
                .iter()
                .map(|t| t.map(|v| point(&mesh.vertices[v as usize])))
                .collect(),
        )
    }
}

/// The first of `points` inside `solid` (in 2D its section `plane`), by its bounding box
/// first.
fn inside<const D: usize>(solid: &Solid, plane: &Section, points: &[Vector<D>]) -> Option<usize> {
    let (lo, hi) = solid.mesh().bounds();
    let lift = |x: &Vector<D>| {
        if D == 2 {
            plane.lift(&Vector::<2>::new(x[0], x[1]))
        } else {
            Vector::<3>::new(x[0], x[1], x[2])
        }
    };
    points.iter().position(|x| {
        let x = lift(x);
        (0..3).all(|k| x[k] > lo[k] && x[k] < hi[k]) && solid.contains(&x)
    })
}

/// Builds the scene's bodies: appends each one's dummy particles (lattice sites inside it
/// within `layers` dx of its surface, normals out of it) to `walls`, and describes its
/// interior (its mass), surface (the load's quadrature, dx/2 apart) and contact hull. A body
/// with a `fluid` particle, a wall particle or an earlier body's particle inside it is refused
/// (`wall_starts`: the first particle of each of the scene's walls, to name it).
pub(crate) fn build<const D: usize>(
    scene: &Scene,
    rest_density: Real,
    walls: &mut WallParticles<D>,
    (fluid, wall_starts): (&[Vector<D>], &[usize]),
) -> Result<Vec<BodyDescription<D>>, SceneError> {
    let dx = scene.dx;
    let fixed = walls.len();
    let mut bodies: Vec<BodyDescription<D>> = Vec::with_capacity(scene.bodies.len());
    let mut solids: Vec<(Solid, Section)> = Vec::with_capacity(scene.bodies.len());
    for (k, body) in scene.bodies.iter().enumerate() {
        let field = format!("bodies[{k}]");
        let failed = |message: String| fail(&field, message);
        let (mesh, section) = shape_mesh::<D>(scene, body).map_err(failed)?;
        check_size::<D>(&mesh, dx, 0.0).map_err(failed)?;
        let solid = Solid::new(mesh.clone())
            .map_err(|error| failed(format!("{error} (a body needs a closed surface)")))?;
        let surface = WallSurface::new(mesh).map_err(|error| failed(error.to_string()))?;
        let thickness = body.layers as Real * dx;
        let plane = Section::at_y(section);
        if let Some(i) = inside(&solid, &plane, fluid) {
            return Err(failed(format!(
                "overlaps the fluid: fluid particle {i} at {:?} lies inside it",
                fluid[i].as_slice()
            )));
        }
        if let Some(w) = inside(&solid, &plane, &walls.position) {
            let other = match bodies.iter().position(|b| b.walls.contains(&w)) {
                Some(j) => format!("bodies[{j}]"),
                None => format!("walls[{}]", wall_starts.partition_point(|&s| s <= w) - 1),
            };
            return Err(failed(format!(
                "starts overlapping {other}: its wall particle at {:?} lies inside it",
                walls.position[w].as_slice()
            )));
        }
        let (sites, interior, points): (Vec<WallSite<D>>, Vec<Vector<D>>, Vec<SurfacePoint<D>>) =
            if D == 2 {
                let zero = Vector::<2>::zeros();
                (
                    surface
                        .wall_sites_in_section(&plane, &zero, dx, thickness)
                        .iter()
                        .map(WallSite::recast)
                        .collect(),
                    solid
                        .fill_section(&plane, &zero, dx)
                        .iter()
                        .map(|x| Vector::<D>::from_fn(|k, _| x[k]))
                        .collect(),
                    surface
                        .section_quadrature(&plane, 0.5 * dx)
                        .iter()
                        .map(SurfacePoint::recast)
                        .collect(),
                )
            } else {
                let zero = Vector::<3>::zeros();
                (
                    surface
                        .wall_sites(&zero, dx, thickness)
                        .iter()
                        .map(WallSite::recast)
                        .collect(),
                    solid
                        .fill(&zero, dx)
                        .iter()
                        .map(|x| Vector::<D>::from_fn(|k, _| x[k]))
                        .collect(),
                    surface
                        .quadrature(0.5 * dx)
                        .iter()
                        .map(SurfacePoint::recast)
                        .collect(),
                )
            };
        if interior.is_empty() || sites.is_empty() {
            return Err(failed(format!(
                "holds no lattice site at dx = {dx}: a body must be at least a few dx across"
            )));
        }
        let (position, normal, depth): (Vec<Vector<D>>, Vec<Vector<D>>, Vec<Real>) = sites
            .into_iter()
            .map(|site| (site.position, site.normal, site.depth))
            .collect();
        if let Some(j) = solids
            .iter()
            .position(|(other, plane)| inside(other, plane, &position).is_some())
        {
            return Err(failed(format!("starts inside bodies[{j}]")));
        }
        if let Some((i, j, distance)) = overlap(&position, &walls.position[..fixed], 0.5 * dx) {
            let wall = wall_starts.partition_point(|&start| start <= j) - 1;
            return Err(failed(format!(
                "starts overlapping walls[{wall}]: its particle at {:?} is {distance:.3e} m \
                 from the wall's at {:?}, closer than dx/2 = {}; move the body clear of the \
                 wall (resting on it is fine)",
                position[i].as_slice(),
                walls.position[j].as_slice(),
                0.5 * dx
            )));
        }
        // The contact shape: in 2D the ends of the section's pieces (its polygon), in 3D the
        // mesh's vertices.
        let hull: Vec<Vector<D>> = if D == 2 {
            points
                .iter()
                .flat_map(|p| {
                    let tangent = Vector::<D>::from_fn(|k, _| [-p.normal[1], p.normal[0]][k]);
                    [-0.5, 0.5].map(|s| p.position + tangent * (s * p.area))
                })
                .collect()
        } else {
            surface
                .mesh()
                .vertices
                .iter()
                .map(|x| Vector::<D>::from_fn(|k, _| x[k]))
                .collect()
        };
        let start = walls.len();
        walls.extend(WallParticles::fixed(
            position,
            normal,
            depth,
            dx.powi(D as i32),
            rest_density,
        ));
        solids.push((solid, plane));
        bodies.push(BodyDescription {
            name: body.name.clone(),
            density: body.density,
            friction: body.friction,
            walls: start..walls.len(),
            interior,
            cell_volume: dx.powi(D as i32),
            surface: points
                .iter()
                .map(|p| LoadPoint {
                    position: p.position,
                    normal: p.normal,
                    area: p.area,
                })
                .collect(),
            hull,
        });
    }
    Ok(bodies)
}

/// A tank's walls as bodies collide with them: boxes as thick as its particle layers, each
/// grown by that thickness along the wall (so neighbouring walls overlap at the edges and
/// leave no gap), except above an open top, where there are no wall particles either.
pub(crate) fn fixed_shape_of_tank<const D: usize>(
    min: &Vector<D>,
    max: &Vector<D>,
    thickness: Real,
    open_top: bool,
) -> Vec<FixedShape<D>> {
    let up = D - 1;
    let mut shapes = Vec::new();
    for axis in 0..D {
        for side in [-1.0, 1.0] {
            if axis == up && side > 0.0 && open_top {
                continue;
            }
            let (mut lo, mut hi) = (*min, *max);
            if side < 0.0 {
                hi[axis] = min[axis];
                lo[axis] = min[axis] - thickness;
            } else {
                lo[axis] = max[axis];
                hi[axis] = max[axis] + thickness;
            }
            for k in (0..D).filter(|&k| k != axis) {
                lo[k] -= thickness;
                if !(k == up && open_top) {
                    hi[k] += thickness;
                }
            }
            shapes.push(FixedShape::Box { min: lo, max: hi });
        }
    }
    shapes
}
