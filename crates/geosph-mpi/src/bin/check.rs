//! Checks the decomposition's exchanges on the ranks it is started on (up to 45, the cells
//! of its smallest case; more is a partition error, exit status 2):
//!
//! ```text
//! mpiexec -n 4 geosph-mpi-check            # 2D, a periodic axis, and 3D
//! mpiexec -n 3 geosph-mpi-check --two-cells # a domain of two cells: a clear error
//! ```
//!
//! Every rank makes the same particles (a jittered lattice), the partition gives each rank
//! its own, and then for several steps: the halo is exchanged and every neighbour of every
//! particle a rank owns (by brute force over all particles, gathered from every rank) must
//! be owned or received there, with its position to the bit; the particles move (across
//! rank boundaries both ways, across the periodic face, and all of the last rank's particles
//! into the first rank's corner, which leaves the last rank empty) and migrate; after which
//! every particle must be on its owner, exactly once. Prints one line per case on rank 0; a
//! failed check aborts (so `mpiexec` ends every rank) with the assertion's message.

use std::collections::HashSet;
use std::process::ExitCode;

use geosph_core::{Domain, Real, Vector};
use geosph_mpi::Ranks;
use geosph_partition::{Cells, Partition, PartitionError, halo_plan, migration_plan};

/// A particle on its rank: its global index and position.
type Particle<const D: usize> = (usize, Vector<D>);

fn main() -> ExitCode {
    let ranks = match Ranks::init() {
        Ok(ranks) => ranks,
        Err(error) => {
            eprintln!("geosph-mpi-check: {error}");
            return ExitCode::FAILURE;
        }
    };
    ranks.abort_on_panic();
    if std::env::args().any(|arg| arg == "--two-cells") {
        let domain = Domain::new(Vector::<2>::zeros(), Vector::<2>::new(0.2, 0.1)).unwrap();
        let cells = Cells::new(domain, 0.099).unwrap();
        return match Partition::balanced(cells, ranks.size(), Vec::new()) {
            Ok(_) => {
                if ranks.rank() == 0 {
                    println!("geosph-mpi-check: {} ranks on two cells: ok", ranks.size());
                }
                ExitCode::SUCCESS
            }
            Err(error) => {
                if ranks.rank() == 0 {
                    eprintln!("geosph-mpi-check: {error}");
                }
                ExitCode::from(2)
            }
        };
    }
    let plane = Domain::with_periodic(
        Vector::<2>::zeros(),
        Vector::<2>::new(2.0, 1.0),
        [true, false],
    )
    .unwrap();
    let closed = Domain::new(Vector::<2>::zeros(), Vector::<2>::new(1.0, 1.0)).unwrap();
    let box3 = Domain::with_periodic(
        Vector::<3>::zeros(),
        Vector::<3>::new(0.6, 0.4, 0.4),
        [false, true, false],
    )
    .unwrap();
    let checks = check(&ranks, "2D, periodic along x", plane, 0.02, 0.052)
        .and_then(|()| check(&ranks, "2D, closed", closed, 0.02, 0.052))
        .and_then(|()| check(&ranks, "3D, periodic along y", box3, 0.04, 0.104));
    match checks {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            if ranks.rank() == 0 {
                eprintln!("geosph-mpi-check: {error}");
            }
            ExitCode::from(2)
        }
    }
}

/// A hash of `(a, b)` in [0, 1) (splitmix64), the same on every rank.
fn unit(a: u64, b: u64) -> Real {
    let mut z = a
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(b)
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as Real / (1u64 << 53) as Real
}

/// A lattice of spacing `dx` filling `domain`, each point jittered by up to ±dx/4.
fn lattice<const D: usize>(domain: &Domain<D>, dx: Real) -> Vec<Vector<D>> {
    let extent = domain.extent();
    let counts: Vec<usize> = (0..D).map(|k| (extent[k] / dx).floor() as usize).collect();
    let total: usize = counts.iter().product();
    (0..total)
        .map(|n| {
            let mut rest = n;
            Vector::<D>::from_fn(|k, _| {
                let c = rest % counts[k];
                rest /= counts[k];
                let jitter = 0.5 * (unit(n as u64, k as u64) - 0.5);
                domain.min[k] + (c as Real + 0.5 + jitter) * dx
            })
        })
        .collect()
}

/// Every rank's particles, gathered on every rank: position by global index.
fn gather<const D: usize>(ranks: &Ranks, mine: &[Particle<D>], n: usize) -> Vec<Option<Vector<D>>> {
    let flat: Vec<Real> = mine
        .iter()
        .flat_map(|(id, x)| std::iter::once(*id as Real).chain(x.iter().copied()))
        .collect();
    let all = ranks.all_gather(&flat);
    let mut position = vec![None; n];
    for record in all.values.chunks_exact(D + 1) {
        let id = record[0] as usize;
        assert!(
            position[id].is_none(),
            "particle {id} is on more than one rank"
        );
        position[id] = Some(Vector::<D>::from_fn(|k, _| record[k + 1]));
    }
    position
}

/// Unpacks records of (id, x) received from the other ranks.
fn unpack<const D: usize>(values: &[Real]) -> impl Iterator<Item = Particle<D>> + '_ {
    values.chunks_exact(D + 1).map(|record| {
        (
            record[0] as usize,
            Vector::<D>::from_fn(|k, _| record[k + 1]),
        )
    })
}

fn pack<const D: usize>(particle: &Particle<D>, values: &mut Vec<Real>) {
    values.push(particle.0 as Real);
    values.extend(particle.1.iter());
}

/// One case; a partition error (more ranks than the case's cells) comes back, every rank
/// alike.
fn check<const D: usize>(
    ranks: &Ranks,
    name: &str,
    domain: Domain<D>,
    dx: Real,
    radius: Real,
) -> Result<(), PartitionError> {
    let (rank, size) = (ranks.rank(), ranks.size());
    let everyone = lattice(&domain, dx);
    let n = everyone.len();
    let cells = Cells::new(domain.clone(), radius)?;
    let partition = Partition::from_particles(cells, size, &everyone, None)?;
    let mut mine: Vec<Particle<D>> = everyone
        .iter()
        .enumerate()
        .filter(|(_, x)| partition.owner(x) == rank)
        .map(|(i, x)| (i, *x))
        .collect();
    let corner = domain.min + Vector::<D>::repeat(0.25 * dx);
    assert_eq!(partition.owner(&corner), 0);
    let (mut halo_records, mut migrated) = (0, 0);
    for step in 0..4u64 {
        // The halo: every neighbour of a particle of this rank is here, to the bit.
        let position: Vec<_> = mine.iter().map(|p| p.1).collect();
        let plan = halo_plan(&partition, rank, &position, 1);
        halo_records += ranks.sum(plan.len() as u64);
        let received = ranks.exchange(&plan, D + 1, |i, values| pack(&mine[i], values));
        let everywhere = gather(ranks, &mine, n);
        let mut seen: HashSet<usize> = mine.iter().map(|p| p.0).collect();
        for (id, x) in unpack::<D>(&received.values) {
            assert_eq!(
                everywhere[id],
                Some(x),
                "{name}: halo particle {id} differs"
            );
            seen.insert(id);
        }
        for (i, x_i) in &mine {
            for (j, x_j) in everywhere.iter().enumerate() {
                let x_j = x_j.expect("every particle is on some rank");
                if domain.displacement(x_i, &x_j).norm() <= radius {
                    assert!(
                        seen.contains(&j),
                        "{name}, step {step}: rank {rank} owns {i} at {x_i:?} but does not see its neighbour {j} at {x_j:?}"
                    );
                }
            }
        }
        // Move: up to 3 cells either way along each axis (wrapped or held inside); at step 1
        // the last rank's particles, and any headed for its cells, go to the first rank's
        // corner instead.
        let emptying = step == 1 && size > 1;
        for (id, x) in &mut mine {
            for k in 0..D {
                x[k] += 6.0 * radius * (unit(*id as u64, 100 + 10 * step + k as u64) - 0.5);
                if !domain.periodic[k] {
                    x[k] = x[k].clamp(domain.min[k], domain.max[k] - 1e-9);
                }
            }
            domain.wrap(x);
            if emptying && (rank == size - 1 || partition.owner(x) == size - 1) {
                *x = corner;
            }
        }
        let position: Vec<_> = mine.iter().map(|p| p.1).collect();
        let (plan, keep) = migration_plan(&partition, rank, &position);
        migrated += ranks.sum(plan.len() as u64);
        let received = ranks.exchange(&plan, D + 1, |i, values| pack(&mine[i], values));
        let mut kept: Vec<_> = mine
            .iter()
            .zip(&keep)
            .filter(|&(_, &k)| k)
            .map(|(&p, _)| p)
            .collect();
        kept.extend(unpack::<D>(&received.values));
        mine = kept;
        for (id, x) in &mine {
            assert_eq!(
                partition.owner(x),
                rank,
                "{name}: particle {id} on the wrong rank"
            );
        }
        assert_eq!(
            ranks.sum(mine.len() as u64),
            n as u64,
            "{name}: particles lost or doubled"
        );
        // `gather` panics on a particle held twice.
        gather(ranks, &mine, n);
        if emptying {
            let empty = ranks.sum(u64::from(rank == size - 1 && mine.is_empty()));
            assert_eq!(
                empty, 1,
                "{name}: the last rank is not empty after its particles left"
            );
        }
    }
    if size > 1 {
        assert!(
            migrated > 0 && halo_records > 0,
            "{name}: nothing was exchanged"
        );
    }
    if rank == 0 {
        println!(
            "geosph-mpi-check: {size} ranks, {name}: ok ({n} particles, 4 steps, {halo_records} halo records, {migrated} migrations)"
        );
    }
    Ok(())
}
