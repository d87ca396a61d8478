//! Kernel evaluation: `W(r)` plus `∇_i W(r_ij)` for every kernel in 2D and 3D, over 10⁴
//! random displacement vectors whose lengths are uniform on `[0, support)`, as a neighbour
//! loop sees them. Throughput is in pairs.

use std::hint::black_box;

use criterion::{BenchmarkGroup, Criterion, Throughput, measurement::WallTime};
use geosph_core::{Real, Vector};
use geosph_kernels::{Kernel, KernelKind, KernelVisitor};
use rand::{Rng, SeedableRng, rngs::StdRng};

const PAIRS: usize = 10_000;

/// `PAIRS` displacement vectors with random direction and length uniform on `[0, support)`.
fn displacements<const D: usize>(support: Real) -> Vec<Vector<D>> {
    let mut rng = StdRng::seed_from_u64(7);
    (0..PAIRS)
        .map(|_| {
            let direction = loop {
                let v = Vector::<D>::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let norm = v.norm();
                if norm > 1e-3 && norm <= 1.0 {
                    break v / norm;
                }
            };
            direction * rng.random_range(0.0..support)
        })
        .collect()
}

/// Benchmarks one kernel inside `group`.
struct ValueAndGradient<'g, 'c> {
    group: &'g mut BenchmarkGroup<'c, WallTime>,
}

impl<const D: usize> KernelVisitor<D> for ValueAndGradient<'_, '_> {
    type Output = ();

    fn visit<K: Kernel<D>>(self, kernel: K) {
        let r_ij = displacements::<D>(kernel.support_radius());
        self.group.bench_function(format!("{}/{D}d", K::NAME), |b| {
            b.iter(|| {
                let mut sum_w = 0.0;
                let mut sum_grad = Vector::<D>::zeros();
                for r in black_box(&r_ij) {
                    sum_w += kernel.value(r.norm());
                    sum_grad += kernel.gradient(r);
                }
                black_box((sum_w, sum_grad))
            })
        });
    }
}

fn value_and_gradient(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernels/value+gradient");
    group.throughput(Throughput::Elements(PAIRS as u64));
    for kind in KernelKind::ALL {
        kind.dispatch::<2, _>(0.01, ValueAndGradient { group: &mut group });
        kind.dispatch::<3, _>(0.01, ValueAndGradient { group: &mut group });
    }
    group.finish();
}

criterion::criterion_group!(benches, value_and_gradient);
