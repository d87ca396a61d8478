//! A closed mesh as a solid: which points lie inside it, its lattice fill in 3D, and its
//! section by a vertical plane for 2D scenes.

use geosph_core::{Real, Vector};
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

use crate::lattice;
use crate::mesh::{MeshError, SurfaceMesh};

/// The volume a closed, outward-oriented [`SurfaceMesh`] bounds.
///
/// The inside test is parry's projection onto the mesh with the angle-weighted
/// pseudo-normals of Bærentzen & Aanæs (2005, IEEE TVCG 11:243): a point is inside when it
/// lies behind the pseudo-normal of the nearest feature, which is exact for a closed mesh
/// whatever the feature (face, edge or vertex).
#[derive(Clone)]
pub struct Solid {
    mesh: SurfaceMesh,
    shape: TriMesh,
    volume: Real,
}

impl std::fmt::Debug for Solid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solid")
            .field("name", &self.mesh.name)
            .field("triangles", &self.mesh.triangles.len())
            .field("volume", &self.volume)
            .finish()
    }
}

pub(crate) fn to_parry(x: &Vector<3>) -> ParryVector {
    ParryVector::new(x[0], x[1], x[2])
}

/// parry's mesh of `mesh` with the pseudo-normals of its side tests, duplicate vertices
/// merged as [`SurfaceMesh::check_closed`] merges them (the pseudo-normals are per vertex
/// index, so an unmerged seam would read as an open edge).
pub(crate) fn oriented_trimesh(mesh: &SurfaceMesh) -> Result<TriMesh, MeshError> {
    let vertices = mesh.vertices.iter().map(to_parry).collect();
    let flags = TriMeshFlags::ORIENTED | TriMeshFlags::MERGE_DUPLICATE_VERTICES;
    TriMesh::with_flags(vertices, mesh.triangles.clone(), flags).map_err(|error| {
        MeshError::Topology {
            name: mesh.name.clone(),
            problem: error.to_string(),
        }
    })
}

impl Solid {
    /// The solid bounded by `mesh`: an error naming the mesh and the first bad edge if it is
    /// not closed, manifold and consistently oriented; inward-facing meshes are turned.
    pub fn new(mesh: SurfaceMesh) -> Result<Self, MeshError> {
        let mesh = mesh.into_outward()?;
        let shape = oriented_trimesh(&mesh)?;
        let volume = mesh.signed_volume();
        Ok(Self {
            mesh,
            shape,
            volume,
        })
    }

    /// The mesh it is bounded by (outward oriented).
    pub fn mesh(&self) -> &SurfaceMesh {
        &self.mesh
    }

    /// The enclosed volume in m³ (divergence theorem over the triangles).
    pub fn volume(&self) -> Real {
        self.volume
    }

    /// Whether `x` lies inside (points on the surface count as inside up to round-off).
    pub fn contains(&self, x: &Vector<3>) -> bool {
        self.shape.contains_local_point(to_parry(x))
    }

    /// The lattice sites `origin + (k + ½) dx` (k integer per axis) inside the solid.
    pub fn fill(&self, origin: &Vector<3>, dx: Real) -> Vec<Vector<3>> {
        let (lo, hi) = self.mesh.bounds();
        lattice::sites(lo.into(), hi.into(), (*origin).into(), dx, 0.0)
            .map(Vector::<3>::from)
            .filter(|x| self.contains(x))
            .collect()
    }

    /// The 2D lattice sites `origin + (k + ½) dx` inside the section of the solid by the
    /// vertical plane `section` (2D point (x, y) = mesh point `section.lift`).
    pub fn fill_section(&self, section: &Section, origin: &Vector<2>, dx: Real) -> Vec<Vector<2>> {
        let (lo, hi) = section.bounds(&self.mesh);
        lattice::sites(lo.into(), hi.into(), (*origin).into(), dx, 0.0)
            .map(Vector::<2>::from)
            .filter(|x| self.contains(&section.lift(x)))
            .collect()
    }

    /// The area of the solid's section in m² (the polygon its triangles cut from the
    /// plane, by the shoelace formula over the cut segments).
    pub fn section_area(&self, section: &Section) -> Real {
        section
            .cuts(&self.mesh)
            .iter()
            .map(|cut| {
                let (p, q) = (cut.start, cut.end);
                // Oriented with the solid on its left (outward normal on its right), a cut
                // adds its share of the shoelace sum.
                let left = Vector::<2>::new(p[1] - q[1], q[0] - p[0]);
                let sign = if left.dot(&cut.facing) < 0.0 {
                    1.0
                } else {
                    -1.0
                };
                sign * (p[0] * q[1] - q[0] * p[1]) / 2.0
            })
            .sum()
    }
}

/// The segment a plane cuts from one triangle of a mesh, in the plane's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cut {
    pub start: Vector<2>,
    pub end: Vector<2>,
    /// The in-plane part of the triangle's (unnormalised) front-face normal.
    pub facing: Vector<2>,
}

/// A vertical plane of a 3D mesh that a 2D scene takes as its x–y plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// The mesh point that is the 2D origin.
    pub point: Vector<3>,
    /// The mesh direction of the 2D x axis (unit).
    pub along: Vector<3>,
    /// The mesh direction of the 2D y axis, up (unit, normal to `along`).
    pub up: Vector<3>,
}

impl Section {
    /// The plane y = `y` of a mesh whose z axis points up: 2D (x, y) is mesh (x, `y`, z).
    pub fn at_y(y: Real) -> Self {
        Self {
            point: Vector::<3>::new(0.0, y, 0.0),
            along: Vector::<3>::x(),
            up: Vector::<3>::z(),
        }
    }

    /// The mesh point of the 2D point `x`.
    pub fn lift(&self, x: &Vector<2>) -> Vector<3> {
        self.point + self.along * x[0] + self.up * x[1]
    }

    /// The 2D coordinates of the mesh point `x` (its projection on the plane).
    pub fn project(&self, x: &Vector<3>) -> Vector<2> {
        let r = x - self.point;
        Vector::<2>::new(r.dot(&self.along), r.dot(&self.up))
    }

    /// The segments the plane cuts from the triangles of `mesh` (triangles it only touches
    /// at a vertex or along a shared edge give none or a repeated one).
    pub(crate) fn cuts(&self, mesh: &SurfaceMesh) -> Vec<Cut> {
        let normal = self.along.cross(&self.up);
        let mut cuts = Vec::new();
        for &[a, b, c] in &mesh.triangles {
            let corners = [a, b, c].map(|v| mesh.vertices[v as usize]);
            let height = corners.map(|x| (x - self.point).dot(&normal));
            let mut ends = Vec::with_capacity(2);
            for e in 0..3 {
                let (p, q) = (e, (e + 1) % 3);
                if (height[p] > 0.0) != (height[q] > 0.0) {
                    let s = height[p] / (height[p] - height[q]);
                    ends.push(corners[p] + (corners[q] - corners[p]) * s);
                }
            }
            if let [p, q] = ends[..] {
                let face = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
                cuts.push(Cut {
                    start: self.project(&p),
                    end: self.project(&q),
                    facing: Vector::<2>::new(face.dot(&self.along), face.dot(&self.up)),
                });
            }
        }
        cuts
    }

    /// The 2D bounding box of the mesh's vertices projected on the plane.
    pub(crate) fn bounds(&self, mesh: &SurfaceMesh) -> (Vector<2>, Vector<2>) {
        mesh.vertices.iter().map(|v| self.project(v)).fold(
            (
                Vector::<2>::repeat(Real::INFINITY),
                Vector::<2>::repeat(Real::NEG_INFINITY),
            ),
            |(lo, hi), v| (lo.inf(&v), hi.sup(&v)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::cube;
    use crate::primitives;
    use approx::assert_relative_eq;

    #[test]
    fn the_cube_holds_its_inside_and_fills_its_lattice_exactly() {
        let cube = Solid::new(cube()).unwrap();
        assert!(cube.contains(&Vector::<3>::repeat(0.5)));
        assert!(!cube.contains(&Vector::<3>::new(1.2, 0.5, 0.5)));
        assert!(!cube.contains(&Vector::<3>::new(0.5, -0.01, 0.5)));
        // Sites at (k + ½)/10 from the origin: 10³ of them inside.
        assert_eq!(cube.fill(&Vector::<3>::zeros(), 0.1).len(), 1000);
    }

    #[test]
    fn a_section_of_the_cube_is_its_square() {
        let cube = Solid::new(cube()).unwrap();
        let section = Section::at_y(0.5);
        assert_relative_eq!(cube.section_area(&section), 1.0, epsilon = 1e-12);
        assert_eq!(
            cube.fill_section(&section, &Vector::<2>::zeros(), 0.1)
                .len(),
            100
        );
    }

    #[test]
    fn sphere_and_cylinder_fills_match_the_mesh_volume_within_one_percent() {
        // dx = size/50: the bar of the filling tests (issue 23).
        let sphere = Solid::new(primitives::sphere(
            &Vector::<3>::new(0.3, 0.2, 0.1),
            0.5,
            64,
        ))
        .unwrap();
        let dx = 1.0 / 50.0;
        let filled = sphere.fill(&Vector::<3>::zeros(), dx).len() as Real * dx.powi(3);
        assert!(
            (filled / sphere.volume() - 1.0).abs() < 0.01,
            "{filled} {}",
            sphere.volume()
        );
        // The mesh is within 0.5 % of the true sphere at 64 segments.
        assert_relative_eq!(sphere.volume(), 4.0 / 3.0 * PI_R3, max_relative = 0.01);

        // The cylinder's size is its diameter, 0.5.
        let cylinder =
            Solid::new(primitives::cylinder(&Vector::<3>::zeros(), 0.25, 1.0, 64)).unwrap();
        let dx = 0.5 / 50.0;
        let filled = cylinder.fill(&Vector::<3>::zeros(), dx).len() as Real * dx.powi(3);
        assert!((filled / cylinder.volume() - 1.0).abs() < 0.01, "{filled}");
        // Its section through the axis is the 0.5 × 1 rectangle (the polygon's width is
        // the chord across the axis, 0.5 at 64 even segments).
        let section = Section::at_y(0.0);
        assert_relative_eq!(cylinder.section_area(&section), 0.5, max_relative = 1e-12);
        let filled = cylinder
            .fill_section(&section, &Vector::<2>::zeros(), dx)
            .len() as Real
            * dx.powi(2);
        assert!((filled / 0.5 - 1.0).abs() < 0.01, "{filled}");
        // A section off the axis: the chord of the circle.
        let section = Section::at_y(0.1);
        let chord = 2.0 * (0.25_f64.powi(2) - 0.01).sqrt();
        assert_relative_eq!(cylinder.section_area(&section), chord, max_relative = 0.01);
    }

    const PI_R3: Real = std::f64::consts::PI * 0.125;
}
