//! Criterion benchmarks of geosph, one group per module.
//!
//! Run all with `cargo bench -p geosph-benches`, or a subset with a filter, e.g.
//! `cargo bench -p geosph-benches -- neighbours/build`.

mod kernels;
mod neighbours;
mod wcsph;

criterion::criterion_main!(kernels::benches, neighbours::benches, wcsph::benches);
