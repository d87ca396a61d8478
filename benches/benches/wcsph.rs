//! One full WCSPH step of the default dam break (neighbour update, wall extrapolation, rates,
//! leap-frog update), at about 10⁴ and 10⁵ fluid particles in 2D, on 1 and 2 threads.
//!
//! The column is 1 m × 2 m in a 4 m × 4 m tank; the fluid is first advanced 0.05 s so the
//! flow is under way. With the default Verlet skin (10 % of the support radius) the lists
//! are rebuilt only every few steps, so the figure is the amortised cost of a step.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput};
use geosph_fluid::build_wcsph;
use geosph_scene::{Scene, SolverSpec};
use geosph_sph::Solver;

/// The dam break at spacing `dx`, advanced to t = 0.05 s.
fn dam_break(dx: f64) -> (Box<dyn Solver<2>>, geosph_core::Particles<2>, f64) {
    let mut scene = Scene::from_ron(include_str!("../../data/scenes/dam-break-2d.ron")).unwrap();
    scene.dx = dx;
    let (mut fluid, solver_inputs) = geosph_scene::build::<2>(&scene).unwrap().split();
    let SolverSpec::Wcsph(config) = &scene.solver else {
        unreachable!("the dam-break scene names WCSPH")
    };
    let mut solver = build_wcsph(config, solver_inputs, &mut fluid).unwrap();
    let mut time = 0.0;
    while time < 0.05 {
        time += solver.step(&mut fluid, time, 1.0).unwrap().dt;
    }
    (solver, fluid, time)
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("wcsph/step");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(8));
    // dx = 0.014 m: 10 296 fluid particles; dx = 0.00447 m: 100 352.
    for dx in [0.014, 0.00447] {
        let (mut solver, mut fluid, mut time) = dam_break(dx);
        group.throughput(Throughput::Elements(fluid.len() as u64));
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let id = BenchmarkId::new(format!("2d/{threads}-threads"), fluid.len());
            group.bench_function(id, |b| {
                pool.install(|| {
                    b.iter(|| {
                        let report = solver.step(&mut fluid, time, 1.0).unwrap();
                        time += report.dt;
                        black_box(report)
                    })
                })
            });
        }
    }
    group.finish();
}

criterion::criterion_group!(benches, step);
