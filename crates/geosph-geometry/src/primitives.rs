//! Closed meshes of simple solids, outward oriented: for tests, and for scenes that want a
//! sphere or a cylinder without a file.

use std::f64::consts::PI;

use geosph_core::{Real, Vector};

use crate::mesh::SurfaceMesh;

/// A UV sphere of `radius` about `centre` with `segments` meridians and `segments / 2`
/// parallels (at least 4 meridians). Its volume approaches 4πr³/3 from below.
pub fn sphere(centre: &Vector<3>, radius: Real, segments: u32) -> SurfaceMesh {
    let meridians = segments.max(4);
    let parallels = (meridians / 2).max(2);
    let mut vertices = vec![centre + Vector::<3>::z() * radius];
    for p in 1..parallels {
        let polar = PI * p as Real / parallels as Real;
        for m in 0..meridians {
            let azimuth = 2.0 * PI * m as Real / meridians as Real;
            vertices.push(
                centre
                    + Vector::<3>::new(
                        polar.sin() * azimuth.cos(),
                        polar.sin() * azimuth.sin(),
                        polar.cos(),
                    ) * radius,
            );
        }
    }
    let south = vertices.len() as u32;
    vertices.push(centre - Vector::<3>::z() * radius);
    let ring = |p: u32, m: u32| 1 + (p - 1) * meridians + m % meridians;
    let mut triangles = Vec::new();
    for m in 0..meridians {
        triangles.push([0, ring(1, m), ring(1, m + 1)]);
        for p in 1..parallels - 1 {
            let (a, b) = (ring(p, m), ring(p, m + 1));
            let (c, d) = (ring(p + 1, m), ring(p + 1, m + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
        triangles.push([south, ring(parallels - 1, m + 1), ring(parallels - 1, m)]);
    }
    SurfaceMesh::new("sphere", vertices, triangles).expect("a sphere has triangles")
}

/// A cylinder of `radius` and `height` standing on `base` (its axis along z), with
/// `segments` sides (at least 3).
pub fn cylinder(base: &Vector<3>, radius: Real, height: Real, segments: u32) -> SurfaceMesh {
    let n = segments.max(3);
    let mut vertices = vec![*base, base + Vector::<3>::z() * height];
    for level in [0.0, height] {
        for m in 0..n {
            let azimuth = 2.0 * PI * m as Real / n as Real;
            vertices.push(
                base + Vector::<3>::new(radius * azimuth.cos(), radius * azimuth.sin(), level),
            );
        }
    }
    let (bottom, top) = (|m: u32| 2 + m % n, |m: u32| 2 + n + m % n);
    let mut triangles = Vec::new();
    for m in 0..n {
        triangles.push([0, bottom(m + 1), bottom(m)]);
        triangles.push([1, top(m), top(m + 1)]);
        triangles.push([bottom(m), bottom(m + 1), top(m + 1)]);
        triangles.push([bottom(m), top(m + 1), top(m)]);
    }
    SurfaceMesh::new("cylinder", vertices, triangles).expect("a cylinder has triangles")
}

/// The box [`min`, `max`], outward oriented (12 triangles).
pub fn cuboid(min: &Vector<3>, max: &Vector<3>) -> SurfaceMesh {
    // Corner k has bit a set when it is on the max side of axis a.
    let corner = |k: u32| {
        Vector::<3>::from_fn(|axis, _| {
            if k >> axis & 1 == 1 {
                max[axis]
            } else {
                min[axis]
            }
        })
    };
    let vertices = (0..8).map(corner).collect();
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1], // z = min, seen from below
        [4, 5, 7],
        [4, 7, 6], // z = max
        [0, 1, 5],
        [0, 5, 4], // y = min
        [2, 6, 7],
        [2, 7, 3], // y = max
        [0, 4, 6],
        [0, 6, 2], // x = min
        [1, 3, 7],
        [1, 7, 5], // x = max
    ];
    SurfaceMesh::new("box", vertices, triangles).expect("a box has triangles")
}
