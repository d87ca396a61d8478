//! A surface that walls are laid behind (terrain, channel, barrier, obstacle): the lattice
//! sites within a given thickness on its far side from the flow, with the normal and depth
//! a dummy-particle wall needs.

use geosph_core::{Real, Vector};
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

use crate::mesh::{MeshError, SurfaceMesh};
use crate::solid::{Section, to_parry};

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
    /// The surface of `mesh` as it is oriented.
    pub fn new(mesh: SurfaceMesh) -> Result<Self, MeshError> {
        let vertices = mesh.vertices.iter().map(to_parry).collect();
        let flags = TriMeshFlags::ORIENTED | TriMeshFlags::MERGE_DUPLICATE_VERTICES;
        let shape =
            TriMesh::with_flags(vertices, mesh.triangles.clone(), flags).map_err(|error| {
                MeshError::Topology {
                    name: mesh.name.clone(),
                    problem: error.to_string(),
                }
            })?;
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

    /// The lattice sites `origin + (k + ½) dx` behind the surface by less than `thickness`
    /// (e.g. layers × dx).
    pub fn wall_sites(&self, origin: &Vector<3>, dx: Real, thickness: Real) -> Vec<WallSite<3>> {
        let (lo, hi) = self.mesh.bounds();
        let range = |k: usize| {
            let first = ((lo[k] - thickness - origin[k]) / dx - 0.5).floor() as i64;
            let last = ((hi[k] + thickness - origin[k]) / dx - 0.5).ceil() as i64;
            first..=last
        };
        let site = |k: usize, i: i64| origin[k] + (i as Real + 0.5) * dx;
        let mut sites = Vec::new();
        for i in range(0) {
            for j in range(1) {
                for l in range(2) {
                    let position = Vector::<3>::new(site(0, i), site(1, j), site(2, l));
                    if let Some((depth, normal)) = self.behind(&position)
                        && depth < thickness
                    {
                        sites.push(WallSite {
                            position,
                            normal,
                            depth,
                        });
                    }
                }
            }
        }
        sites
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
        let range = |k: usize| {
            let first = ((lo[k] - thickness - origin[k]) / dx - 0.5).floor() as i64;
            let last = ((hi[k] + thickness - origin[k]) / dx - 0.5).ceil() as i64;
            first..=last
        };
        let mut sites = Vec::new();
        for i in range(0) {
            for j in range(1) {
                let position = Vector::<2>::new(
                    origin[0] + (i as Real + 0.5) * dx,
                    origin[1] + (j as Real + 0.5) * dx,
                );
                if let Some((depth, normal)) = self.behind(&section.lift(&position))
                    && depth < thickness
                {
                    let normal = section.project(&(section.point + normal));
                    if let Some(normal) = normal.try_normalize(1e-12) {
                        sites.push(WallSite {
                            position,
                            normal,
                            depth,
                        });
                    }
                }
            }
        }
        sites
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
}
