//! The ranks of a run and what they exchange.

use geosph_core::Real;
use geosph_partition::{ExchangePlan, Received, Transport};
use mpi::Count;
use mpi::Threading;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition as Blocks, PartitionMut as BlocksMut};
use mpi::environment::Universe;
use mpi::request::{Request, Scope, scope};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// Why MPI could not be started.
#[derive(Debug, thiserror::Error)]
pub enum MpiError {
    /// MPI was already initialised in this process.
    #[error("MPI is already initialised in this process")]
    AlreadyInitialised,
    /// The MPI library does not let rayon's threads run beside MPI calls.
    #[error(
        "the MPI library gives thread support {0:?}; geosph needs at least Serialized (MPI called by one thread at a time, not always the main one, while rayon threads compute)"
    )]
    Threading(Threading),
}

/// The ranks of a run (MPI's world communicator), initialised with serialised threading and
/// finalised when dropped. A program started without `mpiexec` is one rank (MPI's singleton
/// start).
pub struct Ranks {
    world: SimpleCommunicator,
    _universe: Universe,
}

impl Ranks {
    /// Initialises MPI; once per process.
    pub fn init() -> Result<Self, MpiError> {
        let (universe, threading) = mpi::initialize_with_threading(Threading::Serialized)
            .ok_or(MpiError::AlreadyInitialised)?;
        if threading < Threading::Serialized {
            return Err(MpiError::Threading(threading));
        }
        Ok(Self {
            world: universe.world(),
            _universe: universe,
        })
    }

    /// Makes a panic on this rank abort the process after printing its message, so that
    /// `mpiexec` ends the whole job instead of leaving the other ranks waiting in a
    /// collective that this rank will never join.
    pub fn abort_on_panic(&self) {
        let report = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            report(info);
            std::process::abort();
        }));
    }

    /// Ends every rank of the job with `code` (MPI_Abort): for an error on some ranks only,
    /// which would otherwise leave the others waiting in their next collective.
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }

    /// This process's rank.
    pub fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    /// Ranks in all.
    pub fn size(&self) -> usize {
        self.world.size() as usize
    }

    /// Sends to every rank s the records of the particles `plan.send[s]`, each the `width`
    /// values that `pack(i, values)` appends for particle i, and receives what every rank sent
    /// here: one all-to-all of the counts and one of the values (MPI_Alltoall,
    /// MPI_Alltoallv). Collective: every rank calls it with the same `width`.
    ///
    /// # Panics
    /// If `pack` appends other than `width` values, or a rank sends or receives more than
    /// `i32::MAX` values (MPI's counts); a panic on one rank leaves the others waiting in
    /// the collective, so a program should abort on panic ([`Ranks::abort_on_panic`]).
    pub fn exchange(
        &self,
        plan: &ExchangePlan,
        width: usize,
        mut pack: impl FnMut(usize, &mut Vec<Real>),
    ) -> Received {
        let size = self.size();
        assert_eq!(
            plan.send.len(),
            size,
            "a plan for {} ranks",
            plan.send.len()
        );
        let mut values = Vec::with_capacity(plan.len() * width);
        let mut send_counts = vec![0 as Count; size];
        for (count, indices) in send_counts.iter_mut().zip(&plan.send) {
            let start = values.len();
            for &i in indices {
                pack(i as usize, &mut values);
            }
            assert_eq!(
                values.len(),
                start + indices.len() * width,
                "pack must append {width} values per record"
            );
            *count = to_count(values.len() - start);
        }
        let mut receive_counts = vec![0 as Count; size];
        scope(|scope| {
            let request = self.world.immediate_all_to_all_into(
                scope,
                &send_counts[..],
                &mut receive_counts[..],
            );
            wait(request);
        });
        let send_offsets = offsets(&send_counts);
        let receive_offsets = offsets(&receive_counts);
        let (send_displacements, receive_displacements) = (
            displacements(&send_offsets),
            displacements(&receive_offsets),
        );
        let mut received = vec![0.0; receive_offsets[size]];
        {
            let blocks = Blocks::new(&values[..], &send_counts[..], &send_displacements[..]);
            let mut into = BlocksMut::new(
                &mut received[..],
                &receive_counts[..],
                &receive_displacements[..],
            );
            scope(|scope| {
                let request = self
                    .world
                    .immediate_all_to_all_varcount_into(scope, &blocks, &mut into);
                wait(request);
            });
        }
        Received {
            values: received,
            offsets: receive_offsets,
        }
    }

    /// Every rank's `values`, concatenated in rank order, on every rank (MPI_Allgatherv).
    pub fn all_gather(&self, values: &[Real]) -> Received {
        let size = self.size();
        let mut counts = vec![0 as Count; size];
        let count = to_count(values.len());
        scope(|scope| {
            wait(
                self.world
                    .immediate_all_gather_into(scope, &count, &mut counts[..]),
            );
        });
        let offsets = offsets(&counts);
        let displacements = displacements(&offsets);
        let mut gathered = vec![0.0; offsets[size]];
        {
            let mut into = BlocksMut::new(&mut gathered[..], &counts[..], &displacements[..]);
            scope(|scope| {
                let request = self
                    .world
                    .immediate_all_gather_varcount_into(scope, values, &mut into);
                wait(request);
            });
        }
        Received {
            values: gathered,
            offsets,
        }
    }

    /// The least `value` over the ranks (MPI_Allreduce with MPI_MIN): the same on every rank.
    pub fn min(&self, value: Real) -> Real {
        let mut least = 0.0;
        scope(|scope| {
            let op = SystemOperation::min();
            wait(
                self.world
                    .immediate_all_reduce_into(scope, &value, &mut least, op),
            );
        });
        least
    }

    /// The largest `value` over the ranks.
    pub fn max(&self, value: Real) -> Real {
        let mut largest = 0.0;
        scope(|scope| {
            let op = SystemOperation::max();
            wait(
                self.world
                    .immediate_all_reduce_into(scope, &value, &mut largest, op),
            );
        });
        largest
    }

    /// The largest of each of `values` over the ranks, in place (one MPI_Allreduce).
    pub fn max_each(&self, values: &mut [Real]) {
        let local = values.to_vec();
        scope(|scope| {
            let op = SystemOperation::max();
            wait(
                self.world
                    .immediate_all_reduce_into(scope, &local[..], values, op),
            );
        });
    }

    /// Every rank's `values`, all of the same length, concatenated in rank order (one
    /// MPI_Allgather; different lengths are an error of the caller that MPI need not detect).
    pub fn gather_each(&self, values: &[Real]) -> Vec<Real> {
        let mut gathered = vec![0.0; values.len() * self.size()];
        scope(|scope| {
            wait(
                self.world
                    .immediate_all_gather_into(scope, values, &mut gathered[..]),
            );
        });
        gathered
    }

    /// The sum of `count` over the ranks.
    pub fn sum(&self, count: u64) -> u64 {
        let mut sum = 0;
        scope(|scope| {
            let op = SystemOperation::sum();
            wait(
                self.world
                    .immediate_all_reduce_into(scope, &count, &mut sum, op),
            );
        });
        sum
    }
}

impl Transport for Ranks {
    fn rank(&self) -> usize {
        Ranks::rank(self)
    }

    fn size(&self) -> usize {
        Ranks::size(self)
    }

    fn exchange(
        &self,
        plan: &ExchangePlan,
        width: usize,
        pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Received {
        Ranks::exchange(self, plan, width, pack)
    }

    fn all_gather(&self, values: &[Real]) -> Received {
        Ranks::all_gather(self, values)
    }

    fn max(&self, value: Real) -> Real {
        Ranks::max(self, value)
    }

    fn max_each(&self, values: &mut [Real]) {
        Ranks::max_each(self, values);
    }

    fn gather_each(&self, values: &[Real]) -> Vec<Real> {
        Ranks::gather_each(self, values)
    }

    fn abort(&self, code: i32) -> ! {
        Ranks::abort(self, code)
    }
}

/// Waits for `request`: by testing it for up to 20 µs (a collective between ranks that each
/// have a core completes in that time), then yielding the core between tests, and after a
/// millisecond sleeping 20 µs between them. MPI's blocking wait spins instead, and with more
/// ranks than cores (two cores here, four ranks in the tests) a spinning rank takes the core
/// from the rank it waits for: a step of a few milliseconds took a hundred.
fn wait<'a, D: ?Sized, S: Scope<'a>>(mut request: Request<'a, D, S>) {
    let start = std::time::Instant::now();
    loop {
        match request.test() {
            Ok(_) => return,
            Err(pending) => request = pending,
        }
        let waited = start.elapsed().as_micros();
        if waited > 1000 {
            std::thread::sleep(std::time::Duration::from_micros(20));
        } else if waited > 20 {
            std::thread::yield_now();
        }
    }
}

fn to_count(n: usize) -> Count {
    Count::try_from(n).expect("at most i32::MAX values per rank in one exchange")
}

/// Prefix sums of `counts`, with the total at the end.
fn offsets(counts: &[Count]) -> Vec<usize> {
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut total = 0;
    offsets.push(0);
    for &count in counts {
        total += count as usize;
        offsets.push(total);
    }
    offsets
}

/// The displacements MPI takes: the offsets of each rank's block, without the total.
fn displacements(offsets: &[usize]) -> Vec<Count> {
    offsets[..offsets.len() - 1]
        .iter()
        .map(|&offset| to_count(offset))
        .collect()
}
