//! One full WCSPH step (neighbour update, wall extrapolation, rates, leap-frog update) on 1
//! and 2 threads:
//! - 2D: the default dam break (a 1 m × 2 m column in a 4 m × 4 m tank) at about 10⁴ and 10⁵
//!   fluid particles;
//! - 3D: SPHERIC test 2 (Kleefsman et al. 2005; `data/scenes/kleefsman-obstacle.ron`, a
//!   closed tank with a box obstacle) at about 10⁴ and 10⁵ fluid particles (its walls
//!   included in the step, not in the throughput).
//!
//! The fluid is first advanced 0.05 s so the flow is under way. With the default Verlet skin
//! (10 % of the support radius) the lists are rebuilt only every few steps, so the figure is
//! the amortised cost of a step.
//!
//! `wcsph/size` steps the same two scenes on the default pool from 10⁴ to 10⁶ fluid
//! particles, from rest (advancing a million particles 0.05 s would take most of an hour):
//! the time per particle-step across sizes, at the state every size shares.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput};
use geosph_fluid::build_wcsph;
use geosph_scene::{Scene, SolverSpec};
use geosph_sph::Solver;

/// The WCSPH scene `text` (its meshes in `data/scenes/`) at spacing `dx`, advanced to
/// t = `until` (at least one step, which builds the lists).
fn advanced<const D: usize>(text: &str, dx: f64, until: f64) -> State<D> {
    let mut scene = Scene::from_ron(text).unwrap();
    scene.folder = Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes"));
    scene.dx = dx;
    let (mut fluid, solver_inputs) = geosph_scene::build::<D>(&scene).unwrap().split();
    let SolverSpec::Wcsph(config) = &scene.solver else {
        unreachable!("the benchmark's scenes name WCSPH")
    };
    let mut solver = build_wcsph(config, solver_inputs, &mut fluid).unwrap();
    let mut time = solver.step(&mut fluid, 0.0, 1.0).unwrap().dt;
    while time < until {
        time += solver.step(&mut fluid, time, 1.0).unwrap().dt;
    }
    (solver, fluid, time)
}

/// A solver, its particles and the time they are at.
type State<const D: usize> = (Box<dyn Solver<D>>, geosph_core::Particles<D>, f64);

/// Steps of the solver of `state` as benchmark `id`, on `pool` (`None`: the default pool).
fn bench_steps<const D: usize>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: BenchmarkId,
    (solver, fluid, time): &mut State<D>,
    pool: Option<&rayon::ThreadPool>,
) {
    let mut steps = |b: &mut criterion::Bencher<'_>| {
        b.iter(|| {
            let report = solver.step(fluid, *time, 1.0).unwrap();
            *time += report.dt;
            black_box(report)
        })
    };
    group.bench_function(id, |b| match pool {
        Some(pool) => pool.install(|| steps(b)),
        None => steps(b),
    });
}

/// Steps of `state`'s solver on 1 and 2 threads, with the fluid particle count as throughput.
fn bench_threads<const D: usize>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    mut state: State<D>,
) {
    group.throughput(Throughput::Elements(state.1.len() as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let id = BenchmarkId::new(format!("{D}d/{threads}-threads"), state.1.len());
        bench_steps(group, id, &mut state, Some(&pool));
    }
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("wcsph/step");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(8));
    // dx = 0.014 m: 10 296 fluid particles; dx = 0.00447 m: 100 352.
    let dam_break = include_str!("../../data/scenes/dam-break-2d.ron");
    for dx in [0.014, 0.00447] {
        bench_threads::<2>(&mut group, advanced::<2>(dam_break, dx, 0.05));
    }
    // dx = 0.04 m: 10 850 fluid particles (25 051 wall); dx = 0.02 m: 86 800 (94 616 wall).
    let kleefsman = include_str!("../../data/scenes/kleefsman-obstacle.ron");
    for dx in [0.04, 0.02] {
        bench_threads::<3>(&mut group, advanced::<3>(kleefsman, dx, 0.05));
    }
    group.finish();
}

/// Steps of `state`'s solver on the default pool, with the fluid particle count as
/// throughput.
fn bench_size<const D: usize>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    mut state: State<D>,
) {
    group.throughput(Throughput::Elements(state.1.len() as u64));
    let id = BenchmarkId::new(format!("{D}d"), state.1.len());
    bench_steps(group, id, &mut state, None);
}

fn size(c: &mut Criterion) {
    let mut group = c.benchmark_group("wcsph/size");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    // The dam break's 2 m² column: 2/dx² fluid particles, 10⁴, 10⁵ and 10⁶.
    let dam_break = include_str!("../../data/scenes/dam-break-2d.ron");
    for dx in [0.01414, 0.004472, 0.001414] {
        bench_size::<2>(&mut group, advanced::<2>(dam_break, dx, 0.0));
    }
    // SPHERIC test 2 (86 800 fluid particles at dx = 0.02 m): about 10⁴, 10⁵ and 10⁶ (dx
    // divides the tank's width of 1 m, which the column spans).
    let kleefsman = include_str!("../../data/scenes/kleefsman-obstacle.ron");
    for dx in [0.04, 0.02, 1.0 / 110.0] {
        bench_size::<3>(&mut group, advanced::<3>(kleefsman, dx, 0.0));
    }
    group.finish();
}

criterion::criterion_group!(benches, step, size);
