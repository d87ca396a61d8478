//! Helpers shared by the unit tests.

use geosph_core::{Domain, NeighbourList, Real, Vector};

/// All pairs with `|x_i − x_j| ≤ radius` (minimum image), each particle listing itself, in
/// ascending index order: an O(N²) reference search.
pub fn brute_force_neighbours<const D: usize>(
    domain: &Domain<D>,
    position: &[Vector<D>],
    radius: Real,
) -> NeighbourList {
    let mut list = NeighbourList::new();
    for x_i in position {
        for (j, x_j) in position.iter().enumerate() {
            if domain.displacement(x_i, x_j).norm() <= radius {
                list.indices.push(j as u32);
            }
        }
        list.offsets.push(list.indices.len() as u32);
    }
    list
}

/// A regular square lattice of `n × n` points with spacing `dx`, the first at `(dx/2, dx/2)`.
pub fn square_lattice(n: usize, dx: Real) -> Vec<Vector<2>> {
    (0..n * n)
        .map(|k| Vector::<2>::new((k % n) as Real + 0.5, (k / n) as Real + 0.5) * dx)
        .collect()
}
