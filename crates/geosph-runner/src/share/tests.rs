//! The samples of a run split over thread ranks ([`ThreadRanks`]) against one process's.

use geosph_core::{Domain, Particles, Real, Tensor3, Vector};
use geosph_geometry::SurfacePoint;
use geosph_kernels::KernelKind;
use geosph_partition::{OneRank, ThreadRanks, Transport};
use geosph_scene::{HeightSpec, LoadSurface, ProbeSpec};

use super::Share;
use crate::{HeightGauges, PressureProbes, WallLoads};

#[test]
fn one_process_and_one_rank_leave_partial_results_as_they_are() {
    let fluid = Particles::at_rest(vec![Vector::<2>::new(0.5, 0.25)], 2.0, 1000.0);
    let share = Share::whole_run(&fluid);
    let mut values = [0.1 + 0.2, -0.0];
    share.sum_each(&mut values);
    assert_eq!(
        values.map(Real::to_bits),
        [0.1 + 0.2, -0.0].map(Real::to_bits)
    );
    assert_eq!(share.gather(&[3.0]), [3.0]);

    // A distributed share on one rank adds nothing to its own partial sums either (no
    // 0.0 + x, which would turn −0 into +0).
    let mut whole = Particles::default();
    let mut share = Share::of_rank(&fluid, 1, &OneRank, &mut whole);
    share.sum_each(&mut values);
    assert_eq!(
        values.map(Real::to_bits),
        [0.1 + 0.2, -0.0].map(Real::to_bits)
    );
    let mut extremes = [1.0, 2.0];
    share.max_each(&mut extremes);
    assert_eq!(extremes, [1.0, 2.0]);
    assert_eq!(share.whole().position, fluid.position);
    assert_eq!(share.position().len(), 1);
}

const DX: Real = 0.05;

/// A 2D layer of 24 × 10 particles spacing `DX`, with a hydrostatic pressure and (`soil`) a
/// geostatic stress, and a few particles moving.
fn layer(soil: bool) -> Particles<2> {
    let (rho, g) = (1000.0, 9.81);
    let position = (0..240)
        .map(|k| Vector::<2>::new((k % 24) as Real + 0.5, (k / 24) as Real + 0.5) * DX)
        .collect();
    let mut fluid = Particles::at_rest(position, rho * DX * DX, rho);
    let depth: Vec<Real> = fluid.position.iter().map(|x| 0.5 - x[1]).collect();
    for (k, v) in fluid.velocity.iter_mut().enumerate() {
        *v = Vector::<2>::new((k % 7) as Real * 0.1, -((k % 5) as Real) * 0.2);
    }
    let pressure = fluid.enable_pressure();
    for (p, d) in pressure.iter_mut().zip(&depth) {
        *p = rho * g * d;
    }
    if soil {
        let stress = &mut fluid.enable_soil().stress;
        for (sigma, d) in stress.iter_mut().zip(&depth) {
            *sigma =
                Tensor3::from_diagonal(&nalgebra::Vector3::new(-0.5, -1.0, -0.5)) * (rho * g * *d);
        }
    }
    fluid
}

/// The rows the probes, levels and loads write for `fluid` on one rank of `transport`
/// owning the first `owned` particles of `fluid` (`None`: every particle in one process).
fn row(fluid: &Particles<2>, owned: Option<(usize, &dyn Transport)>) -> Vec<Real> {
    let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(3.0)).unwrap();
    let (kernel, h) = (KernelKind::WendlandC2, 1.3 * DX);
    let probes = [(0.3, 0.2), (0.61, 0.07), (2.0, 2.0)].map(|(x, y)| ProbeSpec {
        name: format!("{x}"),
        position: vec![x, y],
    });
    let heights = [0.3, 0.62, 2.0].map(|x| HeightSpec {
        name: format!("{x}"),
        position: vec![x],
    });
    // The bed under the layer, facing up, in pieces of DX/2 across the cut between the ranks.
    let points = (0..48)
        .map(|k| SurfacePoint {
            position: Vector::<2>::new((k as Real + 0.5) * DX / 2.0, 0.0),
            normal: Vector::<2>::new(0.0, 1.0),
            area: DX / 2.0,
        })
        .collect();
    let bed = LoadSurface {
        name: "bed".into(),
        points,
        about: Vector::<2>::zeros(),
    };
    let gravity = Vector::<2>::new(0.0, -9.81);
    let mut loads = WallLoads::new(vec![bed], kernel, h, (gravity, 0.0), &domain);
    let mut probes = PressureProbes::<2>::new(&probes, kernel, h);
    let mut heights = HeightGauges::<2>::new(&heights, DX);
    let mut whole = Particles::default();
    let share = match owned {
        Some((owned, transport)) => Share::of_rank(fluid, owned, transport, &mut whole),
        None => Share::whole_run(fluid),
    };
    let mut row = Vec::new();
    probes.sample(&share, &mut row);
    heights.sample(&share, &mut row);
    loads.sample(&share, &mut row);
    let mut energy = [share
        .mass()
        .iter()
        .zip(share.velocity())
        .map(|(m, v)| m * v.norm_squared())
        .sum()];
    share.sum_each(&mut energy);
    row.extend(energy);
    row
}

/// The particles of `fluid` split between 3 ranks by x (each rank's owned ones first, then a
/// halo of the particles within 2 DX of its part, which must not count), sampled on thread
/// ranks: every rank's row is one process's within round-off.
fn split_samples_match_one_process(soil: bool) {
    let fluid = layer(soil);
    let alone = row(&fluid, None);
    let cuts = [0.0, 0.4, 0.75, Real::INFINITY];
    let rows: Vec<Vec<Real>> = std::thread::scope(|scope| {
        let handles: Vec<_> = ThreadRanks::new(3)
            .into_iter()
            .map(|ranks| {
                let fluid = &fluid;
                scope.spawn(move || {
                    let (low, high) = (cuts[ranks.rank()], cuts[ranks.rank() + 1]);
                    let x = |i: usize| fluid.position[i][0];
                    let mut order: Vec<usize> = (0..fluid.len())
                        .filter(|&i| x(i) >= low && x(i) < high)
                        .collect();
                    let owned = order.len();
                    order.extend((0..fluid.len()).filter(|&i| {
                        (x(i) < low && x(i) >= low - 2.0 * DX)
                            || (x(i) >= high && x(i) < high + 2.0 * DX)
                    }));
                    let mut local = fluid.clone();
                    let mut record = Vec::new();
                    local.resize(order.len());
                    for (k, &i) in order.iter().enumerate() {
                        record.clear();
                        fluid.pack(i, &mut record);
                        local.unpack(k, &record);
                    }
                    row(&local, Some((owned, &ranks)))
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(alone.iter().all(|v| v.is_finite() || v.is_nan()));
    // Some probe, level and load reads the layer (the last probe and level are dry: NaN).
    assert!(
        alone[0] > 0.0 && alone[3] > 0.0 && alone[7] < 0.0,
        "{alone:?}"
    );
    for (rank, got) in rows.iter().enumerate() {
        assert_eq!(got.len(), alone.len());
        for (k, (a, b)) in alone.iter().zip(got).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * a.abs() || (a.is_nan() && b.is_nan()),
                "soil {soil}, rank {rank}, value {k}: {a} against {b}"
            );
        }
    }
}

#[test]
fn fluid_samples_split_over_ranks_are_one_process_samples() {
    split_samples_match_one_process(false);
}

#[test]
fn soil_samples_split_over_ranks_are_one_process_samples() {
    split_samples_match_one_process(true);
}
