//! Neighbour search: building the cell grid (counting sort), self-query CSR lists and the
//! Z-order permutation, on jittered lattices of 10⁴, 10⁵ and 10⁶ particles in 2D and 3D; and
//! the dense index against the hashed one (`neighbours/index`: build and self query) on a
//! dense tank and a sparse spray.
//!
//! Spacing `dx`, search radius `2 × 1.3 dx` (a cubic spline of smoothing length `h = 1.3 dx`):
//! about 21 neighbours per particle in 2D and 92 in 3D. Particles are in lattice (row-major)
//! order, as a scene generator leaves them.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkGroup, BenchmarkId, Criterion, Throughput, measurement::WallTime};
use geosph_core::{Domain, NeighbourList, Real, Vector};
use geosph_neighbours::CellGrid;
use rand::{Rng, SeedableRng, rngs::StdRng};

const SIZES: [usize; 3] = [10_000, 100_000, 1_000_000];

/// A lattice of about `n` points of spacing `dx` with ±10 % jitter, its domain and radius.
fn setup<const D: usize>(n: usize) -> (Domain<D>, Vec<Vector<D>>, Real) {
    let side = (n as Real).powf(1.0 / D as Real).round() as usize;
    let dx = 0.01;
    let mut rng = StdRng::seed_from_u64(1);
    let total = side.pow(D as u32);
    let mut position = Vec::with_capacity(total);
    for linear in 0..total {
        let mut rest = linear;
        let x = Vector::<D>::from_fn(|_, _| {
            let index = rest % side;
            rest /= side;
            (index as Real + 0.5 + rng.random_range(-0.1..0.1)) * dx
        });
        position.push(x);
    }
    let domain = Domain::new(
        Vector::<D>::zeros(),
        Vector::<D>::from_element(side as Real * dx),
    )
    .unwrap();
    (domain, position, 2.0 * 1.3 * dx)
}

/// Few samples for the large sets, where one iteration takes long.
fn configure(group: &mut BenchmarkGroup<'_, WallTime>, n: usize) {
    if n >= 1_000_000 {
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(5));
    } else {
        group.sample_size(20);
        group.measurement_time(Duration::from_secs(3));
    }
}

fn build<const D: usize>(c: &mut Criterion) {
    let mut group = c.benchmark_group("neighbours/build");
    for n in SIZES {
        let (domain, position, radius) = setup::<D>(n);
        let mut grid = CellGrid::new(domain, radius).unwrap();
        configure(&mut group, n);
        group.throughput(Throughput::Elements(position.len() as u64));
        group.bench_function(BenchmarkId::new(format!("{D}d"), n), |b| {
            b.iter(|| grid.build(black_box(&position)).unwrap())
        });
    }
    group.finish();
}

fn query<const D: usize>(c: &mut Criterion) {
    let mut group = c.benchmark_group("neighbours/query");
    for n in SIZES {
        let (domain, position, radius) = setup::<D>(n);
        let mut grid = CellGrid::new(domain, radius).unwrap();
        grid.build(&position).unwrap();
        let mut list = NeighbourList::new();
        grid.neighbour_list(&position, &position, &mut list);
        configure(&mut group, n);
        group.throughput(Throughput::Elements(position.len() as u64));
        group.bench_function(BenchmarkId::new(format!("{D}d"), n), |b| {
            b.iter(|| grid.neighbour_list(black_box(&position), &position, &mut list))
        });
    }
    group.finish();
}

fn z_order<const D: usize>(c: &mut Criterion) {
    let mut group = c.benchmark_group("neighbours/z_order");
    for n in SIZES {
        let (domain, position, radius) = setup::<D>(n);
        let grid = CellGrid::new(domain, radius).unwrap();
        configure(&mut group, n);
        group.throughput(Throughput::Elements(position.len() as u64));
        group.bench_function(BenchmarkId::new(format!("{D}d"), n), |b| {
            b.iter(|| grid.z_order(black_box(&position)).unwrap())
        });
    }
    group.finish();
}

/// 10⁴ drops in 100 clusters of 10 cm (spacing about 1 cm) over a 3D box 10 m × 10 m × 2 m:
/// 1.1 × 10⁷ cells of the search radius, of which about 10⁴ are occupied.
fn spray() -> (Domain<3>, Vec<Vector<3>>, Real) {
    let mut rng = StdRng::seed_from_u64(2);
    let max = Vector::<3>::new(10.0, 10.0, 2.0);
    let mut position = Vec::with_capacity(10_000);
    for _ in 0..100 {
        let centre = Vector::<3>::from_fn(|k, _| rng.random_range(0.1..max[k] - 0.1));
        for _ in 0..100 {
            position.push(centre + Vector::<3>::from_fn(|_, _| rng.random_range(-0.05..0.05)));
        }
    }
    let domain = Domain::new(Vector::<3>::zeros(), max).unwrap();
    (domain, position, 2.0 * 1.3 * 0.01)
}

fn index(c: &mut Criterion) {
    let mut group = c.benchmark_group("neighbours/index");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    for (scene, (domain, position, radius)) in [("tank", setup::<3>(100_000)), ("spray", spray())] {
        for hashed in [false, true] {
            let mut grid = match hashed {
                false => CellGrid::new(domain.clone(), radius),
                true => CellGrid::hashed(domain.clone(), radius),
            }
            .unwrap();
            let mut list = NeighbourList::new();
            group.throughput(Throughput::Elements(position.len() as u64));
            let name = if hashed { "hashed" } else { "dense" };
            group.bench_function(BenchmarkId::new(name, scene), |b| {
                b.iter(|| {
                    grid.build(black_box(&position)).unwrap();
                    grid.neighbour_list(&position, &position, &mut list);
                })
            });
        }
    }
    group.finish();
}

criterion::criterion_group!(
    benches,
    index,
    build::<2>,
    build::<3>,
    query::<2>,
    query::<3>,
    z_order::<2>,
    z_order::<3>
);
