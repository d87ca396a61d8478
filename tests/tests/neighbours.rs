//! Cell-grid neighbour search (`geosph-neighbours`) against an O(N²) brute force, with the
//! dense index and the hashed one, which must give the same lists bitwise.
//!
//! The definition being checked: `j` is a neighbour of query point `x_q` when
//! `d = domain.displacement(x_q, x_j)` (minimum image on periodic axes) has `d·d ≤ radius²`,
//! inclusive; each list is in cell order (ascending index within a cell), and is compared with
//! the brute force after sorting. Pairs exactly at the radius are built from exactly
//! representable lattice spacings (radius/2, and the 3-4-5 triangle).

use geosph_core::{Domain, NeighbourList, Particles, Real, Vector};
use geosph_neighbours::{CellGrid, SearchError, morton_encode, rayon};
use geosph_tests::{jittered_lattice, random_points};

/// The O(N²) reference: every built particle tested against every query.
fn brute_force<const D: usize>(
    domain: &Domain<D>,
    radius: Real,
    position: &[Vector<D>],
    queries: &[Vector<D>],
) -> NeighbourList {
    let mut list = NeighbourList::new();
    for x in queries {
        for (j, y) in position.iter().enumerate() {
            if domain.displacement(x, y).norm_squared() <= radius * radius {
                list.indices.push(j as u32);
            }
        }
        list.offsets.push(list.indices.len() as u32);
    }
    list
}

/// The grid's list, checked to be in cell order, with each run then sorted by index.
fn search<const D: usize>(
    domain: &Domain<D>,
    radius: Real,
    position: &[Vector<D>],
    queries: &[Vector<D>],
) -> NeighbourList {
    let mut grid = CellGrid::new(domain.clone(), radius).unwrap();
    grid.build(position).unwrap();
    let mut list = NeighbourList::new();
    grid.neighbour_list(position, queries, &mut list);
    assert_cell_order(&grid, &list);
    let mut hashed = CellGrid::hashed(domain.clone(), radius).unwrap();
    hashed.build(position).unwrap();
    let mut hashed_list = NeighbourList::new();
    hashed.neighbour_list(position, queries, &mut hashed_list);
    assert_eq!(
        hashed_list, list,
        "hashed against dense, {domain:?}, radius {radius}"
    );
    sorted(list)
}

/// Each run lists a cell's particles together, in ascending index, and (without a periodic
/// wrap) the cells in ascending linear index.
fn assert_cell_order<const D: usize>(grid: &CellGrid<D>, list: &NeighbourList) {
    let cell = |j: u32| grid.cell_of()[j as usize];
    let periodic = grid.domain().periodic.iter().any(|&p| p);
    for i in 0..list.len() {
        for pair in list.neighbours(i).windows(2) {
            let (a, b) = (cell(pair[0]), cell(pair[1]));
            assert!(
                a != b || pair[0] < pair[1],
                "query {i}: {pair:?} in one cell"
            );
            assert!(periodic || a <= b, "query {i}: cells {a} then {b}");
        }
    }
}

/// `list` with each run sorted by ascending index.
fn sorted(mut list: NeighbourList) -> NeighbourList {
    for i in 0..list.len() {
        let range = list.offsets[i] as usize..list.offsets[i + 1] as usize;
        list.indices[range].sort_unstable();
    }
    list
}

/// Self query (with a few duplicated positions) and a cross query that includes points just
/// outside the non-periodic faces and far away, both equal to the brute force.
fn check_against_brute_force<const D: usize>(domain: Domain<D>, radius: Real, n: usize, seed: u64) {
    let mut position = random_points(domain.min, domain.max, n, seed);
    // Duplicates: exact copies of some particles, at the end and in the middle.
    for k in (0..n).step_by(7).take(20) {
        position.push(position[k]);
    }
    position.insert(n / 2, position[1]);
    let reference = brute_force(&domain, radius, &position, &position);
    let list = search(&domain, radius, &position, &position);
    assert_eq!(list, reference, "self query, {domain:?}, radius {radius}");
    for i in 0..position.len() {
        assert!(list.neighbours(i).binary_search(&(i as u32)).is_ok());
    }
    assert!(list.pair_count() > position.len(), "test set has pairs");

    let margin = Vector::<D>::from_element(radius);
    let mut queries = random_points(domain.min - margin, domain.max + margin, n / 2, seed + 1);
    queries.push(domain.max + margin * 10.0);
    queries.push(domain.min - margin * 3.0);
    queries.push(Vector::<D>::from_element(Real::NAN));
    queries.push(Vector::<D>::from_element(Real::INFINITY));
    queries.extend_from_slice(&position[..5]);
    let reference = brute_force(&domain, radius, &position, &queries);
    let list = search(&domain, radius, &position, &queries);
    assert_eq!(list, reference, "cross query, {domain:?}, radius {radius}");
}

#[test]
fn random_sets_2d_match_brute_force() {
    let (min, max) = (Vector::<2>::new(-1.0, 0.5), Vector::<2>::new(2.0, 2.75));
    for (case, periodic) in [[false, false], [true, true], [true, false], [false, true]]
        .into_iter()
        .enumerate()
    {
        let domain = Domain::with_periodic(min, max, periodic).unwrap();
        check_against_brute_force(domain.clone(), 0.17, 1500, 10 + case as u64);
        // Fewer than three cells on a periodic axis (2.25 / 0.7 → 3, 3 / 1.1 → 2, 2.25 / 1.1 → 2).
        check_against_brute_force(domain.clone(), 0.7, 300, 20 + case as u64);
        check_against_brute_force(domain, 1.1, 300, 30 + case as u64);
    }
    // A period of exactly twice the radius: one cell.
    let domain = Domain::with_periodic(min, max, [false, true]).unwrap();
    check_against_brute_force(domain, 1.125, 200, 40);
    // Non-periodic axis shorter than the radius.
    let thin = Domain::new(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(5.0, 0.1)).unwrap();
    check_against_brute_force(thin, 0.3, 500, 41);
}

#[test]
fn random_sets_3d_match_brute_force() {
    let (min, max) = (
        Vector::<3>::new(0.0, -0.5, 1.0),
        Vector::<3>::new(1.0, 1.0, 2.2),
    );
    for (case, periodic) in [
        [false, false, false],
        [true, true, true],
        [true, false, true],
        [false, true, false],
    ]
    .into_iter()
    .enumerate()
    {
        let domain = Domain::with_periodic(min, max, periodic).unwrap();
        check_against_brute_force(domain.clone(), 0.16, 2000, 50 + case as u64);
        check_against_brute_force(domain, 0.45, 400, 60 + case as u64);
    }
}

/// A lattice of spacing `s` starting at `s/2`, exactly representable.
fn exact_lattice<const D: usize>(counts: [usize; D], s: Real) -> Vec<Vector<D>> {
    jittered_lattice(Vector::<D>::zeros(), counts, s, 0.0, 0)
}

#[test]
fn pairs_exactly_at_the_radius_are_neighbours() {
    // Two points exactly one radius apart on an axis, and one an ulp further.
    let domain = Domain::new(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(2.0, 2.0)).unwrap();
    let position = vec![
        Vector::<2>::new(0.25, 0.5),
        Vector::<2>::new(0.75, 0.5),
        Vector::<2>::new(0.25, 1.0_f64.next_up()),
        Vector::<2>::new(1.25, 0.5),
    ];
    let list = search(&domain, 0.5, &position, &position);
    assert_eq!(list.neighbours(0), &[0, 1]);
    assert_eq!(list.neighbours(1), &[0, 1, 3]);
    assert_eq!(list.neighbours(2), &[2]);
    assert_eq!(list, brute_force(&domain, 0.5, &position, &position));

    // Lattice spacing radius/2 (0.25, radius 0.5): an interior particle has 13 neighbours,
    // 4 of them exactly at the radius; periodic lattices have 13 everywhere, also across the
    // wrap. Domain [0, 4)² holds 16 × 16 points.
    let position = exact_lattice([16, 16], 0.25);
    let box4 = |periodic| {
        Domain::with_periodic(Vector::<2>::zeros(), Vector::<2>::new(4.0, 4.0), periodic).unwrap()
    };
    for periodic in [[false, false], [true, true], [true, false]] {
        let domain = box4(periodic);
        let list = search(&domain, 0.5, &position, &position);
        assert_eq!(list, brute_force(&domain, 0.5, &position, &position));
        let interior = 16 * 8 + 8; // (8, 8)
        assert_eq!(list.neighbours(interior).len(), 13);
        if periodic == [true, true] {
            assert!((0..position.len()).all(|i| list.neighbours(i).len() == 13));
            // Particle 0 sees particle 14 (x = 3.625) exactly at the radius through the wrap.
            assert!(list.neighbours(0).contains(&14));
        }
    }
    // The 3-4-5 triangle: spacing 0.25, radius 1.25, offset (0.75, 1.0) is exactly at the
    // radius; an interior particle has 81 neighbours (lattice points in a disc of radius 5).
    let domain = box4([false, false]);
    let list = search(&domain, 1.25, &position, &position);
    assert_eq!(list, brute_force(&domain, 1.25, &position, &position));
    let interior = 16 * 8 + 8;
    assert_eq!(list.neighbours(interior).len(), 81);
    assert!(
        list.neighbours(interior)
            .contains(&(interior as u32 + 3 + 4 * 16))
    );

    // 3D: spacing 0.25, radius 0.5: 1 + 6 + 12 + 8 + 6 = 33 neighbours inside, 6 at the radius.
    let position = exact_lattice([12, 12, 12], 0.25);
    for periodic in [[false; 3], [true; 3], [false, true, false]] {
        let domain = Domain::with_periodic(
            Vector::<3>::zeros(),
            Vector::<3>::from_element(3.0),
            periodic,
        )
        .unwrap();
        let list = search(&domain, 0.5, &position, &position);
        assert_eq!(list, brute_force(&domain, 0.5, &position, &position));
        assert_eq!(list.neighbours(6 + 12 * 6 + 144 * 6).len(), 33);
    }
}

#[test]
fn pairs_at_the_radius_across_cell_faces_survive_rounding() {
    // With cells exactly one radius wide, (0.19999999999999998 − 0)·10 and (0.3 − 0)·10 fall
    // in cells 1 and 3 although the points are 0.1 = radius apart: the grid must still pair
    // them. Points at every cell face, an ulp either side, and one radius (± an ulp) away.
    for (min, length, radius) in [(0.0, 1.0, 0.1), (-0.7, 2.1, 0.03), (-1.0, 3.0, 0.1)] {
        for periodic in [[false, false], [true, false]] {
            let domain = Domain::with_periodic(
                Vector::<2>::new(min, 0.0),
                Vector::<2>::new(min + length, 1.0),
                periodic,
            )
            .unwrap();
            let n = (length / radius).floor() as usize;
            let mut position = Vec::new();
            for a in 0..n {
                let face = min + a as Real * (length / n as Real);
                for x in [face, face.next_down(), face.next_up()] {
                    for y in [
                        x,
                        x + radius,
                        (x + radius).next_down(),
                        x - radius,
                        (x - radius).next_up(),
                    ] {
                        if domain.contains(&Vector::<2>::new(y, 0.5)) {
                            position.push(Vector::<2>::new(y, 0.5));
                        }
                    }
                }
            }
            let list = search(&domain, radius, &position, &position);
            assert_eq!(
                list,
                brute_force(&domain, radius, &position, &position),
                "{domain:?}"
            );
        }
    }
}

#[test]
fn pairs_near_the_radius_across_cell_edges_and_corners_in_3d() {
    // In 3D the queries leave out the cells whose nearest point is beyond the radius: a pair
    // just inside the radius across a cell edge or corner must survive that test. Points at
    // every grid node (an ulp either side), each with partners one radius away (and a
    // billionth less) along the axes, the face diagonals and the body diagonals.
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let s3 = 1.0 / 3.0_f64.sqrt();
    let directions = [
        Vector::<3>::new(1.0, 0.0, 0.0),
        Vector::<3>::new(0.0, -1.0, 0.0),
        Vector::<3>::new(s2, s2, 0.0),
        Vector::<3>::new(-s2, 0.0, s2),
        Vector::<3>::new(0.0, s2, -s2),
        Vector::<3>::new(s3, s3, s3),
        Vector::<3>::new(-s3, s3, -s3),
        Vector::<3>::new(-s3, -s3, s3),
    ];
    for (min, length, radius) in [(0.0, 0.5, 0.1), (-0.7, 0.45, 0.09)] {
        for periodic in [[false; 3], [true, false, true]] {
            let domain = Domain::with_periodic(
                Vector::<3>::repeat(min),
                Vector::<3>::repeat(min + length),
                periodic,
            )
            .unwrap();
            let n = (length / (radius * (1.0 + 1e-6))).floor() as usize;
            let edge = length / n as Real;
            let mut position = Vec::new();
            for a in 0..=n {
                for b in 0..=n {
                    for c in 0..=n {
                        let node = Vector::<3>::new(a as Real, b as Real, c as Real) * edge
                            + Vector::<3>::repeat(min);
                        for x in [node, node.map(Real::next_down), node.map(Real::next_up)] {
                            let partners = directions.iter().flat_map(|direction| {
                                [1.0, 1.0 - 1e-9].map(|scale| x + direction * (radius * scale))
                            });
                            for y in std::iter::once(x).chain(partners) {
                                if domain.contains(&y) {
                                    position.push(y);
                                }
                            }
                        }
                    }
                }
            }
            let list = search(&domain, radius, &position, &position);
            assert_eq!(
                list,
                brute_force(&domain, radius, &position, &position),
                "{domain:?}"
            );
        }
    }
}

#[test]
fn cross_query_against_wall_particles() {
    // Fluid particles querying a grid built on three layers of wall particles below them.
    let domain = Domain::with_periodic(
        Vector::<2>::new(0.0, -0.1),
        Vector::<2>::new(1.0, 1.0),
        [true, false],
    )
    .unwrap();
    let dx = 0.02;
    let wall = jittered_lattice(Vector::<2>::new(0.0, -3.0 * dx), [50, 3], dx, 0.0, 0);
    let fluid = jittered_lattice(Vector::<2>::new(0.0, 0.0), [50, 20], dx, 0.2, 3);
    let radius = 2.6 * dx;
    let list = search(&domain, radius, &wall, &fluid);
    assert_eq!(list, brute_force(&domain, radius, &wall, &fluid));
    assert_eq!(list.len(), fluid.len());
    assert!(list.neighbours(0).len() > 5 && list.neighbours(999).is_empty());
}

#[test]
fn for_each_neighbour_gives_the_list_with_displacement_and_distance() {
    let domain = Domain::with_periodic(
        Vector::<3>::zeros(),
        Vector::<3>::new(1.0, 1.0, 0.5),
        [true, false, true],
    )
    .unwrap();
    let position = random_points(domain.min, domain.max, 800, 5);
    let radius = 0.15;
    let mut grid = CellGrid::new(domain.clone(), radius).unwrap();
    grid.build(&position).unwrap();
    let mut list = NeighbourList::new();
    grid.neighbour_list(&position, &position, &mut list);
    for (i, x) in position.iter().enumerate() {
        let mut seen = Vec::new();
        grid.for_each_neighbour(&position, x, |j, d, r| {
            assert_eq!(d, domain.displacement(x, &position[j as usize]));
            assert_eq!(r, d.norm());
            assert!(r <= radius);
            seen.push(j);
        });
        assert_eq!(seen, list.neighbours(i), "same order as the list");
    }
}

#[test]
fn particle_outside_the_domain_is_an_error_naming_it() {
    let domain = Domain::with_periodic(
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(1.0, 2.0),
        [true, false],
    )
    .unwrap();
    let mut grid = CellGrid::new(domain, 0.1).unwrap();
    let mut position = random_points(Vector::<2>::zeros(), Vector::<2>::new(1.0, 2.0), 50, 1);
    position[17] = Vector::<2>::new(0.5, 2.0); // on the open upper face
    position[30] = Vector::<2>::new(-0.25, 1.0);
    let err = grid.build(&position).unwrap_err();
    assert!(matches!(err, SearchError::OutsideDomain { index: 17, .. }));
    assert_eq!(
        err.to_string(),
        "particle 17 at (0.5, 2) lies outside the domain [(0, 0), (1, 2)) of the cell grid \
         (positions on periodic axes must be wrapped into the domain first)"
    );
    // The grid is left empty, not half built.
    assert_eq!(grid.particle_count(), 0);

    position[17] = Vector::<2>::new(0.5, 1.5);
    let err = grid.build(&position).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("particle 30 at (-0.25, 1) lies outside"),
        "{err}"
    );
    position[30] = Vector::<2>::new(Real::NAN, 1.0);
    let err = grid.build(&position).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("particle 30 at (NaN, 1) lies outside"),
        "{err}"
    );
    assert!(grid.z_order(&position).is_err());
    position[30] = Vector::<2>::new(0.25, 1.0);
    grid.build(&position).unwrap();
    assert_eq!(grid.particle_count(), 50);
}

/// With `bin_outside_in_edge_cells`, particles up to three cells outside the closed faces
/// (a splash leaving the domain together) are built into the edge cells, and every pair,
/// among them and with the particles inside, is found as the brute force finds it: in 2D
/// with one periodic axis and in 3D with none. Without it the same build fails.
#[test]
fn particles_outside_binned_in_edge_cells_keep_every_pair() {
    fn check<const D: usize>(domain: Domain<D>, radius: Real, seed: u64) {
        let (lo, hi) = (domain.min, domain.max);
        let mut wide_min = lo;
        let mut wide_max = hi;
        for k in 0..D {
            if !domain.periodic[k] {
                wide_min[k] -= 3.0 * radius;
                wide_max[k] += 3.0 * radius;
            }
        }
        let position = random_points(wide_min, wide_max, 2_000, seed);
        let outside = position.iter().filter(|x| !domain.contains(x)).count();
        assert!(outside > 100, "{outside} particles outside");
        let mut grid = CellGrid::new(domain.clone(), radius).unwrap();
        assert!(matches!(
            grid.build(&position),
            Err(SearchError::OutsideDomain { .. })
        ));
        grid.bin_outside_in_edge_cells();
        grid.build(&position).unwrap();
        let mut list = NeighbourList::new();
        grid.neighbour_list(&position, &position, &mut list);
        assert_eq!(
            sorted(list),
            brute_force(&domain, radius, &position, &position)
        );
    }
    let plane = Domain::with_periodic(
        Vector::<2>::zeros(),
        Vector::<2>::new(1.0, 0.6),
        [true, false],
    )
    .unwrap();
    check(plane, 0.07, 3);
    let space = Domain::new(Vector::<3>::zeros(), Vector::<3>::new(0.5, 0.4, 0.3)).unwrap();
    check(space, 0.06, 4);
}

#[test]
fn invalid_grids_are_refused() {
    let domain = Domain::with_periodic(
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(1.0, 2.0),
        [false, true],
    )
    .unwrap();
    assert_eq!(
        CellGrid::new(domain.clone(), 1.5).unwrap_err().to_string(),
        "periodic axis 1 has length 2, less than 2 × search radius 1.5: a particle would see \
         several images of another; enlarge the period or shrink the radius"
    );
    assert!(matches!(
        CellGrid::new(domain.clone(), 0.0),
        Err(SearchError::InvalidRadius { .. })
    ));
    assert!(matches!(
        CellGrid::new(domain.clone(), Real::NAN),
        Err(SearchError::InvalidRadius { .. })
    ));
    assert!(matches!(
        CellGrid::new(domain, 1e-9),
        Err(SearchError::TooManyCells { .. })
    ));
}

#[test]
fn grid_geometry_and_buffer_reuse() {
    let domain = Domain::with_periodic(
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(1.0, 0.5),
        [true, false],
    )
    .unwrap();
    let mut grid = CellGrid::new(domain.clone(), 0.1).unwrap();
    // ⌊L / (radius·(1 + 10⁻⁶))⌋: 9 × 4 cells, each at least one radius wide.
    assert_eq!(grid.cells_per_axis(), [9, 4]);
    assert_eq!(grid.cell_count(), 36);
    assert!(grid.cell_size().iter().all(|&e| e >= 0.1));
    assert_eq!(grid.radius(), 0.1);
    assert_eq!(grid.domain(), &domain);

    // Queries on an empty grid find nothing.
    let mut list = NeighbourList::new();
    grid.neighbour_list(&[], &[Vector::<2>::new(0.5, 0.25)], &mut list);
    assert_eq!(list.offsets, [0, 0]);

    let a = random_points(domain.min, domain.max, 2000, 8);
    let b = random_points(domain.min, domain.max, 2000, 9);
    grid.build(&a).unwrap();
    grid.neighbour_list(&a, &a, &mut list);
    let cell_ptr = grid.particle_index().as_ptr();
    list.indices.reserve(list.indices.len()); // room for a denser second set
    let (offsets_ptr, indices_ptr) = (list.offsets.as_ptr(), list.indices.as_ptr());
    grid.build(&b).unwrap();
    grid.neighbour_list(&b, &b, &mut list);
    assert_eq!(grid.particle_index().as_ptr(), cell_ptr);
    assert_eq!(list.offsets.as_ptr(), offsets_ptr);
    assert_eq!(list.indices.as_ptr(), indices_ptr);
    assert_cell_order(&grid, &list);
    assert_eq!(sorted(list), brute_force(&domain, 0.1, &b, &b));
    // Cells hold their particles in ascending order.
    for c in 0..grid.cell_count() {
        let run = grid.cell_particles(c);
        assert!(run.windows(2).all(|w| w[0] < w[1]));
        assert!(
            run.iter()
                .all(|&i| grid.cell_of()[i as usize] as usize == c)
        );
    }
}

#[test]
fn lists_are_bitwise_identical_for_any_thread_count() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let dx = 0.01;
                let domain = Domain::with_periodic(
                    Vector::<2>::zeros(),
                    Vector::<2>::new(2.0, 1.0),
                    [true, false],
                )
                .unwrap();
                // Random order: the parallel sort and query do real work on every thread.
                let position = random_points(domain.min, domain.max, 60_000, 77);
                let queries = jittered_lattice(Vector::<2>::zeros(), [150, 80], dx, 0.4, 78);
                let mut grid = CellGrid::new(domain, 2.6 * dx).unwrap();
                grid.build(&position).unwrap();
                let mut own = NeighbourList::new();
                grid.neighbour_list(&position, &position, &mut own);
                let mut cross = NeighbourList::new();
                grid.neighbour_list(&position, &queries, &mut cross);
                let order = grid.z_order(&position).unwrap();
                (
                    grid.cell_start().to_vec(),
                    grid.particle_index().to_vec(),
                    own,
                    cross,
                    order,
                )
            })
    };
    let one = run(1);
    assert!(one.2.pair_count() > 60_000 * 10);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}

#[test]
fn z_order_reordering_keeps_fields_and_neighbourhoods_consistent() {
    let domain = Domain::with_periodic(
        Vector::<2>::zeros(),
        Vector::<2>::new(1.0, 1.0),
        [false, true],
    )
    .unwrap();
    let radius = 0.05;
    let mut particles =
        Particles::at_rest(random_points(domain.min, domain.max, 5000, 3), 1.0, 1.0);
    particles.enable_pressure();
    particles.enable_soil();
    for i in 0..particles.len() {
        particles.pressure.as_mut().unwrap()[i] = 2.0 * i as Real;
        particles.soil.as_mut().unwrap().stress[i][(0, 1)] = -(i as Real);
        particles.soil.as_mut().unwrap().plastic_strain[i] = 0.5 * i as Real;
        particles.velocity[i] = particles.position[i] * 3.0;
    }
    let mut grid = CellGrid::new(domain.clone(), radius).unwrap();
    grid.build(&particles.position).unwrap();
    let mut before = NeighbourList::new();
    grid.neighbour_list(&particles.position, &particles.position, &mut before);
    let old_position = particles.position.clone();

    let permutation = grid.z_order(&particles.position).unwrap();
    let order = permutation.order().to_vec();
    particles.permute(&permutation);
    grid.build(&particles.position).unwrap();
    let mut after = NeighbourList::new();
    grid.neighbour_list(&particles.position, &particles.position, &mut after);

    // Fields travel together: slot k now holds old particle order[k] = id[k].
    for k in 0..particles.len() {
        let old = order[k] as usize;
        assert_eq!(particles.id[k] as usize, old);
        assert_eq!(particles.position[k], old_position[old]);
        assert_eq!(particles.velocity[k], old_position[old] * 3.0);
        assert_eq!(particles.pressure.as_ref().unwrap()[k], 2.0 * old as Real);
        let soil = particles.soil.as_ref().unwrap();
        assert_eq!(soil.stress[k][(0, 1)], -(old as Real));
        assert_eq!(soil.plastic_strain[k], 0.5 * old as Real);
    }
    // Neighbourhoods, mapped back to the old numbering, are the same sets.
    for k in 0..particles.len() {
        let mut mapped: Vec<u32> = after
            .neighbours(k)
            .iter()
            .map(|&j| order[j as usize])
            .collect();
        mapped.sort_unstable();
        let mut expected = before.neighbours(order[k] as usize).to_vec();
        expected.sort_unstable();
        assert_eq!(mapped, expected);
    }
    // Memory order now follows the Z curve of cells (ties keep the old order)...
    let code = |x: &Vector<2>| {
        let e = grid.cell_size();
        morton_encode::<2>([((x[0] / e[0]) as u32), ((x[1] / e[1]) as u32)])
    };
    for k in 1..particles.len() {
        let (a, b) = (
            code(&particles.position[k - 1]),
            code(&particles.position[k]),
        );
        assert!(a < b || (a == b && order[k - 1] < order[k]));
    }
    // ...so neighbours are much closer in memory than in the random initial order.
    let spread = |list: &NeighbourList| {
        let mut sum = 0u64;
        for i in 0..list.len() {
            sum += list
                .neighbours(i)
                .iter()
                .map(|&j| (i as i64 - j as i64).unsigned_abs())
                .sum::<u64>();
        }
        sum as Real / list.pair_count() as Real
    };
    assert!(
        spread(&after) * 5.0 < spread(&before),
        "{} vs {}",
        spread(&after),
        spread(&before)
    );
}

/// A spray of 3 000 drops in clusters over a 3D valley 10 km × 10 km × 1 km with a search
/// radius of 2.6 cm: 5.7 × 10¹⁵ cells, which no dense index holds (refused by name), while the
/// hashed one stores the few thousand occupied cells and finds every pair the brute force
/// finds; and the same with a periodic axis and with particles binned in edge cells.
#[test]
fn a_hashed_grid_searches_a_domain_too_large_for_a_dense_one() {
    let (min, max) = (
        Vector::<3>::new(0.0, 0.0, 0.0),
        Vector::<3>::new(1e4, 1e4, 1e3),
    );
    let radius = 0.026;
    let mut position = Vec::new();
    let inset = Vector::<3>::from_element(1.0);
    for (k, centre) in random_points(min + inset, max - inset, 30, 7)
        .into_iter()
        .enumerate()
    {
        let half = Vector::<3>::from_element(0.05);
        position.extend(random_points(
            centre - half,
            centre + half,
            100,
            100 + k as u64,
        ));
    }
    for periodic in [[false, false, false], [true, false, false]] {
        let domain = Domain::with_periodic(min, max, periodic).unwrap();
        let position: Vec<_> = position
            .iter()
            .map(|x| {
                let mut x = *x;
                domain.wrap(&mut x);
                x
            })
            .collect();
        assert!(matches!(
            CellGrid::new(domain.clone(), radius),
            Err(SearchError::TooManyCells { .. })
        ));
        let mut grid = CellGrid::hashed(domain.clone(), radius).unwrap();
        grid.build(&position).unwrap();
        assert!(grid.occupied_cells().unwrap() <= position.len());
        let mut list = NeighbourList::new();
        grid.neighbour_list(&position, &position, &mut list);
        assert_cell_order(&grid, &list);
        let reference = brute_force(&domain, radius, &position, &position);
        assert_eq!(sorted(list), reference, "{periodic:?}");
        assert!(
            reference.pair_count() > 2 * position.len(),
            "the drops have neighbours"
        );
    }
    // Outside a closed face, binned in the edge cells, as the dense grid does.
    let domain = Domain::new(min, max).unwrap();
    let mut grid = CellGrid::hashed(domain.clone(), radius).unwrap();
    grid.bin_outside_in_edge_cells();
    let outside: Vec<_> = position
        .iter()
        .map(|x| Vector::<3>::new(x[0], x[1], x[2] + 1e3 + 0.01))
        .chain(position.iter().copied())
        .collect();
    grid.build(&outside).unwrap();
    let mut list = NeighbourList::new();
    grid.neighbour_list(&outside, &outside, &mut list);
    let reference = brute_force(&domain, radius, &outside, &outside);
    assert_eq!(sorted(list), reference);
}

/// A scene's `domain.cells: Hashed` runs every solver family as the dense index does,
/// bitwise (a column collapsing in a tank, WCSPH, DFSPH and the soil, 0.1 s); and a drop
/// falling in a domain 3 km × 3 km (1.1 × 10¹⁰ cells at dx = 1 cm: refused by the dense index,
/// naming the cell counts) runs with the hashed one.
#[test]
fn hashed_cells_in_a_scene_run_as_the_dense_ones() {
    use geosph_runner::{RunOptions, run};
    use geosph_scene::Scene;
    use geosph_tests::FinalState;
    let scene = |cells: &str, solver: &str| {
        Scene::from_ron(&format!(
            "Scene(name: \"cells\", dimension: 2, dx: 0.05, end_time: 0.1,
                output: (interval: 0.1, sample_interval: 0.1, vtk: false),
                domain: (min: [-0.5, -0.5], max: [2.5, 2.5], cells: {cells}),
                fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.5, 1.0])]),
                walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0])],
                solver: {solver})"
        ))
        .unwrap()
    };
    for solver in ["Wcsph(())", "Dfsph(())", "Soil(())"] {
        let [dense, hashed] = ["Dense", "Hashed"].map(|cells| {
            let mut state = FinalState::default();
            run(&scene(cells, solver), &RunOptions::default(), &mut state).unwrap();
            state.plane.expect("a 2D run").1
        });
        assert_eq!(dense.position, hashed.position, "{solver}");
        assert_eq!(dense.velocity, hashed.velocity, "{solver}");
        let speed = dense.velocity.iter().map(|v| v.norm()).fold(0.0, Real::max);
        assert!(speed > 0.1, "{solver}: the column collapses ({speed} m/s)");
    }
    let drop = |cells: &str| {
        Scene::from_ron(&format!(
            "Scene(name: \"drop\", dimension: 2, dx: 0.01, end_time: 0.05,
                output: (interval: 0.05, sample_interval: 0.05, vtk: false),
                domain: (min: [-1500.0, -1500.0], max: [1500.0, 1500.0], cells: {cells}),
                fluid: (blocks: [Box(min: [0.0, 0.0], max: [0.1, 0.1])], hydrostatic: false),
                solver: Wcsph((sound_speed: Some(20.0))))"
        ))
        .unwrap()
    };
    let error = run(
        &drop("Dense"),
        &RunOptions::default(),
        &mut FinalState::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("cells"), "{error}");
    println!("dense: {error}");
    let mut state = FinalState::default();
    let summary = run(&drop("Hashed"), &RunOptions::default(), &mut state).unwrap();
    println!(
        "hashed: {} steps in {:.3} s",
        summary.steps, summary.wall_time
    );
    let (_, fluid) = state.plane.expect("a 2D run");
    // It falls freely: g t²/2 = 12 mm at 0.05 s.
    let fall = 0.05 - fluid.position.iter().map(|x| x[1]).sum::<Real>() / fluid.len() as Real;
    assert!(
        (fall - 0.5 * 9.81 * 0.05 * 0.05).abs() < 1e-3,
        "fell {fall} m"
    );
}
