//! A surface that walls are laid behind (terrain, channel, barrier, obstacle): the lattice
//! sites within a given thickness on its far side from the flow, with the normal and depth
//! a dummy-particle wall needs.

use geosph_core::{Real, Vector};
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::TriMesh;

use crate::lattice;
use crate::mesh::{MeshError, SurfaceMesh};
use crate::solid::{Section, oriented_trimesh, to_parry};

/// A wall site: its position, the unit normal from it towards the flow (to the nearest
/// point of the surface) and its depth behind the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallSite<const D: usize> {
    /// Position in m.
    pub position: Vector<D>,
    /// Unit normal pointing to the surface and the flow beyond it.
    pub normal: Vector<D>,
    /// Distance to the surface in m.
    pub depth: Real,
}

/// A point of a surface quadrature: where, the unit normal of its face towards the flow, and
/// the area (length in 2D) it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint<const D: usize> {
    /// Position in m.
    pub position: Vector<D>,
    /// Unit normal of the face, pointing into the flow.
    pub normal: Vector<D>,
    /// Area in m² (2D: length in m).
    pub area: Real,
}

/// The first E components of `x` (zeros beyond N): a point of a concrete dimension as one
/// of a generic dimension D that equals it.
fn recast<const N: usize, const E: usize>(x: &Vector<N>) -> Vector<E> {
    Vector::<E>::from_fn(|k, _| if k < N { x[k] } else { 0.0 })
}

impl<const N: usize> WallSite<N> {
    /// The site as one of dimension E (for code generic in the dimension, E = N).
    pub fn recast<const E: usize>(&self) -> WallSite<E> {
        WallSite {
            position: recast(&self.position),
            normal: recast(&self.normal),
            depth: self.depth,
        }
    }
}

impl<const N: usize> SurfacePoint<N> {
    /// The point as one of dimension E (for code generic in the dimension, E = N).
    pub fn recast<const E: usize>(&self) -> SurfacePoint<E> {
        SurfacePoint {
            position: recast(&self.position),
            normal: recast(&self.normal),
            area: self.area,
        }
    }
}

/// A triangle mesh whose triangles face the flow (counter-clockwise seen from the flow):
/// a terrain with its normals up, an obstacle with outward normals, a container with inward
/// ones. Open or closed.
///
/// Which side a point is on is decided by the angle-weighted pseudo-normal of the nearest
/// feature (Bærentzen & Aanæs 2005), so the sites behind convex and concave edges and corners
/// are classified like those behind faces: convex corners are filled, concave ones not
/// doubled.
#[derive(Clone)]
pub struct WallSurface {
    mesh: SurfaceMesh,
    shape: TriMesh,
}

impl std::fmt::Debug for WallSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WallSurface")
            .field("name", &self.mesh.name)
            .field("triangles", &self.mesh.triangles.len())
            .finish()
    }
}

impl WallSurface {
    /// The surface of `mesh` as it is oriented: an error naming the first edge along which two
    /// triangles run in the same direction (a flipped triangle or a non-manifold edge).
    pub fn new(mesh: SurfaceMesh) -> Result<Self, MeshError> {
        mesh.check_oriented()?;
        let shape = oriented_trimesh(&mesh)?;
        Ok(Self { mesh, shape })
    }

    /// The mesh.
    pub fn mesh(&self) -> &SurfaceMesh {
        &self.mesh
    }

    /// The depth of `x` behind the surface and the unit normal from it to its nearest
    /// surface point, if `x` lies behind the surface; `None` in front of it.
    pub fn behind(&self, x: &Vector<3>) -> Option<(Real, Vector<3>)> {
        let (projection, (triangle, _)) = self
            .shape
            .project_local_point_and_get_location(to_parry(x), false);
        if !projection.is_inside {
            return None;
        }
        let nearest = Vector::<3>::new(projection.point.x, projection.point.y, projection.point.z);
        let offset = nearest - x;
        let depth = offset.norm();
        let normal = if depth > 1e-12 * (1.0 + x.norm()) {
            offset / depth
        } else {
            // On the surface: the face's normal.
            let [a, b, c] =
                self.mesh.triangles[triangle as usize].map(|v| self.mesh.vertices[v as usize]);
            (b - a).cross(&(c - a)).normalize()
        };
        Some((depth, normal))
    }

    /// The midpoint rule on the surface: each triangle split into n² congruent triangles,
    /// n = ⌈longest edge / `size`⌉, each standing for its area at its centroid. Exact for
    /// the integral of a field linear on each triangle.
    pub fn quadrature(&self, size: Real) -> Vec<SurfacePoint<3>> {
        let mut points = Vec::new();
        for triangle in &self.mesh.triangles {
            let [a, b, c] = triangle.map(|v| self.mesh.vertices[v as usize]);
            let face = (b - a).cross(&(c - a));
            let longest = [(b - a).norm(), (c - b).norm(), (a - c).norm()]
                .into_iter()
                .fold(0.0, Real::max);
            let n = (longest / size).ceil().max(1.0) as usize;
            let area = face.norm() / 2.0 / (n * n) as Real;
            let normal = face.normalize();
            let (u, v) = ((b - a) / n as Real, (c - a) / n as Real);
            for i in 0..n {
                for j in 0..n - i {
                    let corner = a + u * i as Real + v * j as Real;
                    // The upright sub-triangle at (i, j), and the inverted one beside it.
                    points.push(SurfacePoint {
                        position: corner + (u + v) / 3.0,
                        normal,
                        area,
                    });
                    if i + j + 1 < n {
                        points.push(SurfacePoint {
                            position: corner + (u + v) * (2.0 / 3.0),
                            normal,
                            area,
                        });
                    }
                }
            }
        }
        points
    }

    /// The midpoint rule on the surface's section by a plane: each cut segment split into
    /// ⌈length / `size`⌉ equal pieces, each standing for its length at its midpoint, with the
    /// in-plane unit normal of its face.
    pub fn section_quadrature(&self, section: &Section, size: Real) -> Vec<SurfacePoint<2>> {
        let mut points = Vec::new();
        for cut in section.cuts(&self.mesh) {
            let Some(normal) = cut.facing.try_normalize(1e-12) else {
                continue;
            };
            let length = (cut.end - cut.start).norm();
            let n = (length / size).ceil().max(1.0) as usize;
            for k in 0..n {
                let s = (k as Real + 0.5) / n as Real;
                points.push(SurfacePoint {
                    position: cut.start + (cut.end - cut.start) * s,
                    normal,
                    area: length / n as Real,
                });
            }
        }
        points
    }

    /// The lattice sites `origin + (k + ½) dx` behind the surface by less than `thickness`
    /// (e.g. layers × dx).
    pub fn wall_sites(&self, origin: &Vector<3>, dx: Real, thickness: Real) -> Vec<WallSite<3>> {
        let (lo, hi) = self.mesh.bounds();
        lattice::sites(lo.into(), hi.into(), (*origin).into(), dx, thickness)
            .filter_map(|x| {
                let position = Vector::<3>::from(x);
                let (depth, normal) = self.behind(&position)?;
                (depth < thickness).then_some(WallSite {
                    position,
                    normal,
                    depth,
                })
            })
            .collect()
    }

    /// The 2D lattice sites `origin + (k + ½) dx` of the section plane behind the surface
    /// by less than `thickness`. The depth and normal are the surface's in 3D, the normal
    /// projected on the plane: exact for a mesh extruded across the plane (a prism along the
    /// plane's normal), as a 2D geometry drawn in a 3D tool is.
    pub fn wall_sites_in_section(
        &self,
        section: &Section,
        origin: &Vector<2>,
        dx: Real,
        thickness: Real,
    ) -> Vec<WallSite<2>> {
        let (lo, hi) = section.bounds(&self.mesh);
        lattice::sites(lo.into(), hi.into(), (*origin).into(), dx, thickness)
            .filter_map(|x| {
                let position = Vector::<2>::from(x);
                let (depth, normal) = self.behind(&section.lift(&position))?;
                let normal = section
                    .project(&(section.point + normal))
                    .try_normalize(1e-12)?;
                (depth < thickness).then_some(WallSite {
                    position,
                    normal,
                    depth,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::cube;
    use approx::assert_relative_eq;

    #[test]
    fn an_obstacle_cube_has_its_walls_inside_and_a_container_outside() {
        // Outward normals: an obstacle; the walls lie inside it.
        let obstacle = WallSurface::new(cube()).unwrap();
        let sites = obstacle.wall_sites(&Vector::<3>::zeros(), 0.1, 0.3);
        // Sites (k + ½)/10 inside the unit cube within 0.3 of a face: all but the inner 4³.
        assert_eq!(sites.len(), 1000 - 64);
        for site in &sites {
            let x = site.position;
            assert!((0..3).all(|k| x[k] > 0.0 && x[k] < 1.0));
            let surface = x + site.normal * site.depth;
            assert!((0..3).any(|k| surface[k].abs() < 1e-12 || (surface[k] - 1.0).abs() < 1e-12));
        }
        // Inward normals: a container; the walls lie outside, corners and edges filled.
        let mut inward = cube();
        for t in &mut inward.triangles {
            t.swap(1, 2);
        }
        let container = WallSurface::new(inward).unwrap();
        let sites = container.wall_sites(&Vector::<3>::zeros(), 0.1, 0.3);
        // The 16³ block of sites around the cube, less the cube's 10³, less the sites
        // further than 0.3 from it (the far corners and edges of the block).
        let expected = (-3..13_i32)
            .flat_map(|i| (-3..13_i32).flat_map(move |j| (-3..13_i32).map(move |l| [i, j, l])))
            .filter(|index| {
                let x = index.map(|i| (i as Real + 0.5) * 0.1);
                let d = x
                    .map(|c| (c.clamp(0.0, 1.0) - c).powi(2))
                    .iter()
                    .sum::<Real>()
                    .sqrt();
                d > 0.0 && d < 0.3
            })
            .count();
        assert_eq!(sites.len(), expected);
        let corner = sites
            .iter()
            .find(|s| (s.position - Vector::<3>::repeat(-0.05)).norm() < 1e-12)
            .unwrap();
        assert_relative_eq!(
            corner.normal,
            Vector::<3>::repeat(1.0 / 3.0_f64.sqrt()),
            epsilon = 1e-12
        );
        assert_relative_eq!(corner.depth, 0.05 * 3.0_f64.sqrt(), epsilon = 1e-12);
    }

    #[test]
    fn a_section_of_a_container_gives_the_2d_tank_walls() {
        let mut inward = cube();
        for t in &mut inward.triangles {
            t.swap(1, 2);
        }
        let container = WallSurface::new(inward).unwrap();
        let sites =
            container.wall_sites_in_section(&Section::at_y(0.5), &Vector::<2>::zeros(), 0.1, 0.3);
        // The 16² square of sites around the unit square, less its 10², less the site at
        // (0.25, 0.25) from each corner, 0.354 away.
        assert_eq!(sites.len(), 16 * 16 - 100 - 4);
        for site in &sites {
            assert_relative_eq!(site.normal.norm(), 1.0, epsilon = 1e-12);
        }
    }

    #[test]
    fn quadratures_integrate_area_and_a_linear_pressure_exactly() {
        let cube = WallSurface::new(cube()).unwrap();
        let points = cube.quadrature(0.3);
        let area: Real = points.iter().map(|p| p.area).sum();
        assert_relative_eq!(area, 6.0, epsilon = 1e-12);
        // p = 1 − z on the closed cube: −∮ p n dA = (0, 0, 1), the "buoyancy" of the unit
        // volume in a unit pressure gradient.
        let force: Vector<3> = points
            .iter()
            .map(|p| -p.normal * (1.0 - p.position[2]) * p.area)
            .sum();
        assert_relative_eq!(force, Vector::<3>::z(), epsilon = 1e-12);
        let section = cube.section_quadrature(&Section::at_y(0.5), 0.3);
        let length: Real = section.iter().map(|p| p.area).sum();
        assert_relative_eq!(length, 4.0, epsilon = 1e-12);
        let force: Vector<2> = section
            .iter()
            .map(|p| -p.normal * (1.0 - p.position[1]) * p.area)
            .sum();
        assert_relative_eq!(force, Vector::<2>::y(), epsilon = 1e-12);
    }
}
