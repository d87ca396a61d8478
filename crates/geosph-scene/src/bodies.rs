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

/// Builds the scene's bodies: appends each one's dummy particles (lattice sites inside it
/// within `layers` dx of its surface, normals out of it) to `walls`, and describes its
/// interior (its mass), surface (the load's quadrature, dx/2 apart) and contact hull.
pub(crate) fn build<const D: usize>(
    scene: &Scene,
    rest_density: Real,
    walls: &mut WallParticles<D>,
) -> Result<Vec<BodyDescription<D>>, SceneError> {
    let dx = scene.dx;
    let mut bodies = Vec::with_capacity(scene.bodies.len());
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
        let (position, normal, depth) = sites
            .into_iter()
            .map(|site| (site.position, site.normal, site.depth))
            .collect();
        walls.extend(WallParticles::fixed(
            position,
            normal,
            depth,
            dx.powi(D as i32),
            rest_density,
        ));
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

/// The scene's fixed wall surfaces as bodies collide with them: a tank's walls as boxes as
/// thick as its particle layers, a polyline's segments, a mesh wall's triangles (3D) or the
/// pieces of its section (2D).
pub(crate) fn fixed_shape_of_tank<const D: usize>(
    min: &Vector<D>,
    max: &Vector<D>,
    thickness: Real,
    open_top: bool,
) -> Vec<FixedShape<D>> {
    let up = D - 1;
    let mut shapes = Vec::new();
    for axis in 0..D {
        if axis == up && open_top {
            // The floor only.
            let mut top = *max;
            top[up] = min[up];
            let mut bottom = *min;
            bottom[up] -= thickness;
            shapes.push(slab(&bottom, &top, up, thickness));
            continue;
        }
        for side in [-1.0, 1.0] {
            let (mut lo, mut hi) = (*min, *max);
            if side < 0.0 {
                hi[axis] = min[axis];
                lo[axis] = min[axis] - thickness;
            } else {
                lo[axis] = max[axis];
                hi[axis] = max[axis] + thickness;
            }
            shapes.push(slab(&lo, &hi, axis, thickness));
        }
    }
    shapes
}

/// The box [lo, hi] grown by `thickness` on every axis but `axis` (so that the slabs of a
/// tank overlap at its edges and leave no gap a body could slip through).
fn slab<const D: usize>(
    lo: &Vector<D>,
    hi: &Vector<D>,
    axis: usize,
    thickness: Real,
) -> FixedShape<D> {
    let grow = Vector::<D>::from_fn(|k, _| if k == axis { 0.0 } else { thickness });
    FixedShape::Box {
        min: lo - grow,
        max: hi + grow,
    }
}
