//! Particle generators: lattice-filled boxes and polygons, and wall particles of tanks.
//!
//! All generators place particles at the centres of a lattice of spacing dx aligned with the
//! lower corner of the region, so a fluid block and the tank around it share one lattice and
//! the first wall layer sits dx/2 behind the wall surface.

use geosph_core::{Real, Vector};
use serde::{Deserialize, Serialize};

use crate::walls::WallParticles;

/// The side of a 2D polyline the flow is on, looking along the polyline from its first point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FlowSide {
    /// The flow is to the left (a counter-clockwise container outline).
    #[default]
    Left,
    /// The flow is to the right.
    Right,
}

/// Number of lattice cells of size `dx` across `length`, tolerant of round-off
/// (a length of 1.0 with dx = 0.1 gives 10, not 11): [`fill_box`] fills this many per axis.
pub fn cell_count(length: Real, dx: Real) -> usize {
    let cells = length / dx;
    let rounded = cells.round();
    if (cells - rounded).abs() < 1e-6 * cells.max(1.0) {
        rounded.max(0.0) as usize
    } else {
        cells.ceil().max(0.0) as usize
    }
}

/// Visits the integer lattice `lower..upper` (per axis, exclusive) in x-fastest order.
fn for_each_cell<const D: usize>(
    lower: [i64; D],
    upper: [i64; D],
    mut visit: impl FnMut([i64; D]),
) {
    if (0..D).any(|k| upper[k] <= lower[k]) {
        return;
    }
    let mut index = lower;
    loop {
        visit(index);
        let mut k = 0;
        loop {
            index[k] += 1;
            if index[k] < upper[k] {
                break;
            }
            index[k] = lower[k];
            k += 1;
            if k == D {
                return;
            }
        }
    }
}

/// Lattice points `min + (i + ½) dx` filling the box `[min, max)`.
pub fn fill_box<const D: usize>(min: &Vector<D>, max: &Vector<D>, dx: Real) -> Vec<Vector<D>> {
    let mut upper = [0_i64; D];
    for k in 0..D {
        upper[k] = cell_count(max[k] - min[k], dx) as i64;
    }
    let mut points = Vec::new();
    for_each_cell([0; D], upper, |index| {
        points.push(Vector::<D>::from_fn(|k, _| {
            min[k] + (index[k] as Real + 0.5) * dx
        }));
    });
    points
}

/// Whether `x` lies inside the polygon `vertices` (even–odd rule).
pub fn polygon_contains(vertices: &[Vector<2>], x: &Vector<2>) -> bool {
    let mut inside = false;
    let n = vertices.len();
    for a in 0..n {
        let (p, q) = (vertices[a], vertices[(a + 1) % n]);
        if (p[1] > x[1]) != (q[1] > x[1]) {
            let crossing = p[0] + (x[1] - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
            if x[0] < crossing {
                inside = !inside;
            }
        }
    }
    inside
}

/// Lattice points of spacing dx (aligned with `origin`) inside a 2D polygon.
pub fn fill_polygon(vertices: &[Vector<2>], origin: &Vector<2>, dx: Real) -> Vec<Vector<2>> {
    let mut lower = [i64::MAX; 2];
    let mut upper = [i64::MIN; 2];
    for v in vertices {
        for k in 0..2 {
            lower[k] = lower[k].min(((v[k] - origin[k]) / dx).floor() as i64);
            upper[k] = upper[k].max(((v[k] - origin[k]) / dx).ceil() as i64);
        }
    }
    let mut points = Vec::new();
    for_each_cell(lower, upper, |index| {
        let x = Vector::<2>::new(
            origin[0] + (index[0] as Real + 0.5) * dx,
            origin[1] + (index[1] as Real + 0.5) * dx,
        );
        if polygon_contains(vertices, &x) {
            points.push(x);
        }
    });
    points
}

/// Dummy particles of a tank whose inner (fluid) space is the box `[min, max)`: `layers`
/// layers of lattice points of spacing dx outside the box, on every face but the top (the
/// last axis' upper face) when `open_top`.
///
/// Each particle's normal points from it to the nearest point of the box and its depth is the
/// distance to that point (corner particles point diagonally). The volume is dx^D and the
/// density starts at `rest_density`.
pub fn tank<const D: usize>(
    min: &Vector<D>,
    max: &Vector<D>,
    dx: Real,
    layers: usize,
    open_top: bool,
    rest_density: Real,
) -> WallParticles<D> {
    tank_open_along(min, max, dx, layers, open_top, [false; D], rest_density)
}

/// A [`tank`] without walls across the faces of the `open` axes: the tank of a slab that is
/// periodic along those axes, whose flow wraps around instead of meeting a wall. Along an open
/// axis the layers span `[min, max)` only, so a quasi-2D slab of width w costs the walls of its
/// floor and end faces, w/dx lattice rows across, and none of the side walls of a closed box.
pub fn tank_open_along<const D: usize>(
    min: &Vector<D>,
    max: &Vector<D>,
    dx: Real,
    layers: usize,
    open_top: bool,
    open: [bool; D],
    rest_density: Real,
) -> WallParticles<D> {
    let layers = layers as i64;
    let mut lower = [0_i64; D];
    let mut upper = [0_i64; D];
    let mut inner = [0_i64; D];
    for k in 0..D {
        inner[k] = cell_count(max[k] - min[k], dx) as i64;
        let thickness = if open[k] { 0 } else { layers };
        lower[k] = -thickness;
        upper[k] = inner[k] + thickness;
    }
    if open_top {
        upper[D - 1] = inner[D - 1];
    }
    let mut position = Vec::new();
    let mut normal = Vec::new();
    let mut depth = Vec::new();
    for_each_cell(lower, upper, |index| {
        if (0..D).all(|k| index[k] >= 0 && index[k] < inner[k]) {
            return;
        }
        let x = Vector::<D>::from_fn(|k, _| min[k] + (index[k] as Real + 0.5) * dx);
        let nearest = Vector::<D>::from_fn(|k, _| x[k].clamp(min[k], max[k]));
        let offset = nearest - x;
        let distance = offset.norm();
        position.push(x);
        normal.push(offset / distance);
        depth.push(distance);
    });
    WallParticles::fixed(position, normal, depth, dx.powi(D as i32), rest_density)
}

/// One segment of a 2D polyline wall with its frame.
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    /// The segment's first point.
    pub start: Vector<2>,
    /// Its length (positive).
    pub length: Real,
    /// The unit vector from its first point to its last.
    pub tangent: Vector<2>,
    /// The unit normal pointing into the flow.
    pub into_flow: Vector<2>,
}

/// The segments of the polyline `points` of positive length, with the flow on `flow`'s side.
pub fn segments(points: &[Vector<2>], flow: FlowSide) -> impl Iterator<Item = Segment> + '_ {
    points.windows(2).filter_map(move |pair| {
        let (start, end) = (pair[0], pair[1]);
        let length = (end - start).norm();
        (length > 0.0).then(|| {
            let tangent = (end - start) / length;
            let left = Vector::<2>::new(-tangent[1], tangent[0]);
            let into_flow = match flow {
                FlowSide::Left => left,
                FlowSide::Right => -left,
            };
            Segment {
                start,
                length,
                tangent,
                into_flow,
            }
        })
    })
}

/// Dummy particles of a 2D wall along the polyline `points`: on each segment of length L,
/// ⌈L/dx⌉ particles evenly spaced along it (spacing ≤ dx), `layers` rows deep on the side away
/// from the flow, row k at depth (k + ½) dx behind the line. Normals point into the flow.
///
/// Only the segments are filled: at a convex corner (seen from the walls) the layers of the two
/// segments leave a wedge without particles; close such corners with a [`tank`] or a short
/// extra segment.
pub fn polyline(
    points: &[Vector<2>],
    dx: Real,
    layers: usize,
    flow: FlowSide,
    rest_density: Real,
) -> WallParticles<2> {
    let mut position = Vec::new();
    let mut normal = Vec::new();
    let mut depth = Vec::new();
    for Segment {
        start,
        length,
        tangent,
        into_flow,
    } in segments(points, flow)
    {
        let count = cell_count(length, dx);
        let spacing = length / count.max(1) as Real;
        for along in 0..count {
            for layer in 0..layers {
                let behind = (layer as Real + 0.5) * dx;
                position
                    .push(start + tangent * ((along as Real + 0.5) * spacing) - into_flow * behind);
                normal.push(into_flow);
                depth.push(behind);
            }
        }
    }
    WallParticles::fixed(position, normal, depth, dx * dx, rest_density)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn box_fill_counts_and_centres() {
        let points = fill_box(
            &Vector::<2>::new(0.0, 0.0),
            &Vector::<2>::new(1.0, 2.0),
            0.1,
        );
        assert_eq!(points.len(), 10 * 20);
        assert_relative_eq!(points[0][0], 0.05);
        assert_relative_eq!(points[199][1], 1.95, epsilon = 1e-12);
    }

    #[test]
    fn tank_layers_surround_the_box() {
        let dx = 0.1;
        let walls = tank(
            &Vector::<2>::new(0.0, 0.0),
            &Vector::<2>::new(1.0, 1.0),
            dx,
            3,
            true,
            1000.0,
        );
        // bottom: (10 + 6) × 3, two sides: 3 × 10 each
        assert_eq!(walls.len(), 16 * 3 + 2 * 30);
        for i in 0..walls.len() {
            let x = walls.position[i];
            assert!(x[0] < 0.0 || x[0] > 1.0 || x[1] < 0.0, "{x:?} is inside");
            assert!(walls.depth[i] >= 0.5 * dx - 1e-12);
            assert_relative_eq!(walls.normal[i].norm(), 1.0, epsilon = 1e-12);
        }
        let closed = tank(
            &Vector::<3>::zeros(),
            &Vector::<3>::repeat(1.0),
            dx,
            2,
            false,
            1000.0,
        );
        assert_eq!(closed.len(), 14 * 14 * 14 - 10 * 10 * 10);
        // A slab periodic along y: floor and end walls, each 10 rows across, no side walls.
        let slab = tank_open_along(
            &Vector::<3>::zeros(),
            &Vector::<3>::repeat(1.0),
            dx,
            3,
            true,
            [false, true, false],
            1000.0,
        );
        assert_eq!(slab.len(), (16 * 13 - 10 * 10) * 10);
        assert!(slab.position.iter().all(|x| x[1] > 0.0 && x[1] < 1.0));
        assert!(slab.normal.iter().all(|n| n[1] == 0.0));
    }

    #[test]
    fn polyline_layers_lie_behind_the_line() {
        let dx = 0.1;
        // A slope from (0, 0) to (2, 1), flow above it (to the left going up the slope).
        let slope = [Vector::<2>::new(0.0, 0.0), Vector::<2>::new(2.0, 1.0)];
        let walls = polyline(&slope, dx, 3, FlowSide::Left, 1000.0);
        // √5 m at spacing ≤ dx: 23 particles along the slope.
        let count = (5.0_f64.sqrt() / dx).ceil() as usize;
        assert_eq!(walls.len(), count * 3);
        for i in 0..walls.len() {
            let x = walls.position[i];
            // Below the line y = x/2, at the recorded depth along the normal.
            let signed = (x[1] - 0.5 * x[0]) / (1.0_f64 + 0.25).sqrt();
            assert_relative_eq!(signed, -walls.depth[i], epsilon = 1e-12);
            assert!(walls.normal[i][1] > 0.0);
        }
    }

    #[test]
    fn polygon_fill_matches_area() {
        let triangle = [
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(2.0, 0.0),
            Vector::<2>::new(0.0, 1.0),
        ];
        let dx = 0.01;
        let points = fill_polygon(&triangle, &Vector::<2>::zeros(), dx);
        let area = points.len() as Real * dx * dx;
        assert_relative_eq!(area, 1.0, max_relative = 0.02);
    }
}
