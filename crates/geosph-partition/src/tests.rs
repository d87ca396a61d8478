//! Every rank simulated in one process: ownership, halos and migration against a brute-force
//! search.

use geosph_core::{Domain, Real, Vector};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use crate::{Cells, Partition, PartitionError, halo_plan, imbalance, migration_plan};

fn test_domain<const D: usize>(periodic: [bool; D]) -> Domain<D> {
    let mut max = Vector::<D>::repeat(1.0);
    max[0] = 2.0;
    Domain::with_periodic(Vector::zeros(), max, periodic).unwrap()
}

fn random<const D: usize>(domain: &Domain<D>, n: usize, seed: u64) -> Vec<Vector<D>> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| Vector::<D>::from_fn(|k, _| rng.random_range(domain.min[k]..domain.max[k])))
        .collect()
}

/// Each rank's particles (indices into the global set), by owner.
fn owned<const D: usize>(partition: &Partition<D>, position: &[Vector<D>]) -> Vec<Vec<usize>> {
    let mut owned = vec![Vec::new(); partition.ranks()];
    for (i, x) in position.iter().enumerate() {
        owned[partition.owner(x)].push(i);
    }
    owned
}

/// For every rank r, every particle within `depth` × `radius` of a particle r owns (minimum
/// image on periodic axes) is owned by r or in the halo `depth` cells deep the other ranks
/// send to r.
fn check_halos<const D: usize>(
    partition: &Partition<D>,
    position: &[Vector<D>],
    radius: Real,
    depth: u32,
) {
    let domain = partition.cells().domain().clone();
    let owned = owned(partition, position);
    let ranks = partition.ranks();
    let mut seen = vec![vec![false; position.len()]; ranks];
    for (s, mine) in owned.iter().enumerate() {
        let local: Vec<_> = mine.iter().map(|&i| position[i]).collect();
        let plan = halo_plan(partition, s, &local, depth);
        assert!(plan.send[s].is_empty(), "rank {s} sends a halo to itself");
        for (r, indices) in plan.send.iter().enumerate() {
            for &k in indices {
                seen[r][mine[k as usize]] = true;
            }
        }
        for &i in mine {
            seen[s][i] = true;
        }
    }
    for (r, mine) in owned.iter().enumerate() {
        for &i in mine {
            for (j, x_j) in position.iter().enumerate() {
                if domain.displacement(&position[i], x_j).norm() <= Real::from(depth) * radius {
                    assert!(
                        seen[r][j],
                        "rank {r} owns particle {i} at {:?} but does not see its neighbour {j} at {:?} (owner {})",
                        position[i],
                        x_j,
                        partition.owner(x_j)
                    );
                }
            }
        }
    }
}

#[test]
fn every_neighbour_of_an_owned_particle_is_owned_or_in_the_halo() {
    let radius = 0.13;
    for (periodic, seed) in [([false, false], 1), ([true, false], 2), ([true, true], 3)] {
        let domain = test_domain::<2>(periodic);
        let position = random(&domain, 1500, seed);
        for ranks in [1, 2, 3, 4, 7] {
            let cells = Cells::new(domain.clone(), radius).unwrap();
            let partition = Partition::from_particles(cells, ranks, &position, None).unwrap();
            check_halos(&partition, &position, radius, 1);
            check_halos(&partition, &position, radius, 2);
        }
    }
    for (periodic, seed) in [([false, false, false], 4), ([true, false, true], 5)] {
        let domain = test_domain::<3>(periodic);
        let position = random(&domain, 2000, seed);
        for ranks in [2, 5] {
            let cells = Cells::new(domain.clone(), 0.21).unwrap();
            let partition = Partition::from_particles(cells, ranks, &position, None).unwrap();
            check_halos(&partition, &position, 0.21, 1);
        }
    }
}

/// A periodic axis of only three cells split over three ranks: the halo across the periodic
/// face is sent too.
#[test]
fn a_periodic_axis_split_across_ranks_sends_its_halo_across_the_face() {
    let domain = Domain::with_periodic(
        Vector::<2>::zeros(),
        Vector::<2>::new(0.9, 0.3),
        [true, false],
    )
    .unwrap();
    let position = random(&domain, 400, 6);
    let cells = Cells::new(domain, 0.29).unwrap();
    assert_eq!(cells.counts(), [3, 1]);
    let partition = Partition::from_particles(cells, 3, &position, None).unwrap();
    let owned = owned(&partition, &position);
    assert!(owned.iter().all(|mine| !mine.is_empty()));
    check_halos(&partition, &position, 0.29, 1);
}

/// On a uniform lattice each rank's work is its share within one cell's work.
#[test]
fn balanced_ranks_differ_from_their_share_by_at_most_one_cell() {
    let domain = test_domain::<2>([false, false]);
    let dx = 0.01;
    let position: Vec<_> = (0..200)
        .flat_map(|i| {
            (0..100).map(move |j| Vector::<2>::new((i as Real + 0.5) * dx, (j as Real + 0.5) * dx))
        })
        .collect();
    let cells = Cells::new(domain, 0.026).unwrap();
    let cell_work: Vec<_> = position.iter().map(|x| (cells.key(x), 1.0)).collect();
    let largest_cell = {
        let mut keys: Vec<_> = cell_work.iter().map(|&(key, _)| key).collect();
        keys.sort_unstable();
        keys.chunk_by(|a, b| a == b)
            .map(<[u64]>::len)
            .max()
            .unwrap() as Real
    };
    for ranks in [2, 3, 4, 16] {
        let partition = Partition::balanced(cells.clone(), ranks, cell_work.clone()).unwrap();
        let work = partition.work_per_rank(&cell_work);
        let share = position.len() as Real / ranks as Real;
        for (r, &w) in work.iter().enumerate() {
            assert!(
                (w - share).abs() <= largest_cell,
                "{ranks} ranks: rank {r} has {w} particles, share {share}, largest cell {largest_cell}"
            );
        }
        assert!(imbalance(&work) <= 1.0 + largest_cell / share);
    }
}

/// Particles clustered in one cell of a large domain: one rank owns that cell, the other
/// three own no particle, and the halos still hold.
#[test]
fn ranks_without_particles_stay_empty() {
    let domain = test_domain::<2>([false, false]);
    // All in one cell of 0.02 m.
    let position: Vec<_> = random(&domain, 300, 7)
        .into_iter()
        .map(|x| x * 0.005)
        .collect();
    let cells = Cells::new(domain, 0.02).unwrap();
    let partition = Partition::from_particles(cells, 4, &position, None).unwrap();
    let owned = owned(&partition, &position);
    assert_eq!(owned.iter().map(Vec::len).sum::<usize>(), position.len());
    assert_eq!(owned.iter().filter(|mine| mine.is_empty()).count(), 3);
    check_halos(&partition, &position, 0.02, 1);
    // No work at all: rank 0 owns everything.
    let cells = Cells::new(test_domain::<2>([false, false]), 0.02).unwrap();
    let partition = Partition::balanced(cells, 4, Vec::new()).unwrap();
    assert_eq!(partition.owner(&Vector::<2>::new(1.9, 0.9)), 0);
}

/// Particles moved in both directions across rank boundaries (and across a periodic face)
/// end, after one migration, on their new owner, each exactly once; a rank that every
/// particle leaves ends empty.
#[test]
fn migration_moves_each_particle_to_its_new_owner_once() {
    let domain = test_domain::<2>([true, false]);
    let position = random(&domain, 2000, 8);
    let cells = Cells::new(domain.clone(), 0.1).unwrap();
    let partition = Partition::from_particles(cells, 4, &position, None).unwrap();
    let mut ranks: Vec<Vec<(usize, Vector<2>)>> = owned(&partition, &position)
        .into_iter()
        .map(|mine| mine.into_iter().map(|i| (i, position[i])).collect())
        .collect();
    // Move every particle by up to half a metre along x (wrapping) and a little along y;
    // rank 3's particles, and any that would enter its cells, go to rank 0's first cell.
    let mut rng = StdRng::seed_from_u64(9);
    let target = Vector::<2>::new(0.01, 0.01);
    assert_eq!(partition.owner(&target), 0);
    for (r, particles) in ranks.iter_mut().enumerate() {
        for (_, x) in particles.iter_mut() {
            if r == 3 {
                *x = target;
            } else {
                x[0] += rng.random_range(-0.5..0.5);
                x[1] = (x[1] + rng.random_range(-0.05..0.05)).clamp(0.0, 0.999);
                domain.wrap(x);
                if partition.owner(x) == 3 {
                    *x = target;
                }
            }
        }
    }
    let mut arrived: Vec<Vec<(usize, Vector<2>)>> = vec![Vec::new(); 4];
    let mut moved = 0;
    for (r, particles) in ranks.iter().enumerate() {
        let local: Vec<_> = particles.iter().map(|&(_, x)| x).collect();
        let (plan, keep) = migration_plan(&partition, r, &local);
        assert!(plan.send[r].is_empty());
        moved += plan.len();
        for (s, indices) in plan.send.iter().enumerate() {
            arrived[s].extend(indices.iter().map(|&k| particles[k as usize]));
        }
        arrived[r].extend(
            particles
                .iter()
                .zip(&keep)
                .filter(|&(_, &kept)| kept)
                .map(|(&particle, _)| particle),
        );
    }
    assert!(moved > 500, "only {moved} particles changed rank");
    let mut count = vec![0; position.len()];
    for (r, particles) in arrived.iter().enumerate() {
        for &(i, x) in particles {
            count[i] += 1;
            assert_eq!(
                partition.owner(&x),
                r,
                "particle {i} at {x:?} is on rank {r}"
            );
        }
    }
    assert!(count.iter().all(|&c| c == 1));
    assert!(arrived[3].is_empty());
}

#[test]
fn bad_input_names_what_is_wrong() {
    let domain = test_domain::<2>([false, false]);
    let error =
        Partition::balanced(Cells::new(domain.clone(), 0.49).unwrap(), 9, Vec::new()).unwrap_err();
    assert_eq!(
        error,
        PartitionError::TooManyRanks {
            ranks: 9,
            cells: 8,
            counts: vec![4, 2]
        }
    );
    assert!(error.to_string().contains("at most 8 ranks"), "{error}");
    assert_eq!(
        Cells::new(domain.clone(), 0.0).unwrap_err(),
        PartitionError::Radius(0.0)
    );
    assert_eq!(
        Partition::balanced(Cells::new(domain.clone(), 0.5).unwrap(), 0, Vec::new()).unwrap_err(),
        PartitionError::NoRank
    );
    assert_eq!(
        Partition::balanced(Cells::new(domain, 0.5).unwrap(), 2, vec![(0, -1.0)]).unwrap_err(),
        PartitionError::Work(-1.0)
    );
}

/// Pairs exactly one radius apart across cell faces, with the positions an ulp either side of
/// the faces: with cells exactly one radius wide, rounding put x = 0.19999999999999998 in
/// cell 1 and x = 0.3 (0.1 m away) in cell 3; the cells are a margin wider than the radius so
/// that every such pair is in adjacent cells, whichever ranks own them.
#[test]
fn pairs_one_radius_apart_across_cell_faces_are_in_the_halo() {
    let ulp = |x: Real, up: bool| {
        if x == 0.0 {
            x
        } else {
            Real::from_bits(if up { x.to_bits() + 1 } else { x.to_bits() - 1 })
        }
    };
    let mut position = Vec::new();
    for k in 0..10 {
        let face = 0.1 * k as Real;
        for x in [ulp(face, false), face, ulp(face, true)] {
            for y in [0.35, 0.45, ulp(0.45, false), 0.55] {
                position.push(Vector::<2>::new(x, y));
            }
        }
    }
    let domain = Domain::new(Vector::<2>::zeros(), Vector::<2>::new(1.0, 1.0)).unwrap();
    for ranks in [2, 3, 5, 8] {
        let cells = Cells::new(domain.clone(), 0.1).unwrap();
        let partition = Partition::from_particles(cells, ranks, &position, None).unwrap();
        check_halos(&partition, &position, 0.1, 1);
    }
}
