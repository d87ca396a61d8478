//! [`ThreadRanks`]: the ranks of a distributed run as threads of one process, a [`Transport`]
//! that needs no MPI, for tests of code that runs on several ranks.

use std::sync::{Arc, Barrier, Mutex, PoisonError};

use geosph_core::Real;

use crate::plan::ExchangePlan;
use crate::transport::{Received, Transport};

/// One rank of a set of ranks that are threads of one process (from [`ThreadRanks::new`]):
/// each thread takes one and calls the collectives in the same order, as MPI ranks would.
/// The values move through shared memory; every collective waits for every rank twice (once
/// when all have posted, once when all have read), so it is meant for tests, not for speed.
pub struct ThreadRanks {
    rank: usize,
    size: usize,
    shared: Arc<Shared>,
}

/// What the ranks of one set share: a mailbox for each (source, destination) pair.
struct Shared {
    barrier: Barrier,
    /// The values rank `from` posted for rank `to`, at `from * size + to`.
    mailboxes: Mutex<Vec<Vec<Real>>>,
}

impl ThreadRanks {
    /// `size` ranks (at least one), rank k at index k, to be moved each into its thread.
    pub fn new(size: usize) -> Vec<Self> {
        assert!(size > 0, "at least one rank");
        let shared = Arc::new(Shared {
            barrier: Barrier::new(size),
            mailboxes: Mutex::new(vec![Vec::new(); size * size]),
        });
        (0..size)
            .map(|rank| Self {
                rank,
                size,
                shared: Arc::clone(&shared),
            })
            .collect()
    }

    /// Posts `outgoing[to]` for every rank `to`, then returns what every rank posted for this
    /// one, by source rank.
    fn all_to_all(&self, outgoing: Vec<Vec<Real>>) -> Received {
        let lock = || {
            self.shared
                .mailboxes
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
        };
        {
            let mut mailboxes = lock();
            for (to, values) in outgoing.into_iter().enumerate() {
                mailboxes[self.rank * self.size + to] = values;
            }
        }
        self.shared.barrier.wait();
        let mut received = Received {
            values: Vec::new(),
            offsets: vec![0],
        };
        {
            let mailboxes = lock();
            for from in 0..self.size {
                let values = &mailboxes[from * self.size + self.rank];
                received.values.extend_from_slice(values);
                received.offsets.push(received.values.len());
            }
        }
        // No rank posts the next collective's values before every rank has read these.
        self.shared.barrier.wait();
        received
    }
}

impl Transport for ThreadRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn exchange(
        &self,
        plan: &ExchangePlan,
        width: usize,
        pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Received {
        assert_eq!(
            plan.send.len(),
            self.size,
            "a plan for {} ranks",
            plan.send.len()
        );
        let outgoing = plan
            .send
            .iter()
            .map(|indices| {
                let mut values = Vec::with_capacity(indices.len() * width);
                for &i in indices {
                    pack(i as usize, &mut values);
                }
                assert_eq!(
                    values.len(),
                    indices.len() * width,
                    "pack must append {width} values per record"
                );
                values
            })
            .collect();
        self.all_to_all(outgoing)
    }

    fn all_gather(&self, values: &[Real]) -> Received {
        self.all_to_all(vec![values.to_vec(); self.size])
    }

    fn max(&self, value: Real) -> Real {
        let mut values = [value];
        self.max_each(&mut values);
        values[0]
    }

    fn max_each(&self, values: &mut [Real]) {
        let count = values.len();
        let all = self.all_gather(values).values;
        for (k, value) in values.iter_mut().enumerate() {
            let per_rank = all[k..].iter().step_by(count).copied();
            *value = per_rank.fold(Real::NEG_INFINITY, Real::max);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threads_gather_exchange_and_reduce_as_ranks() {
        let results: Vec<(Received, Received, Real, [Real; 2])> = std::thread::scope(|scope| {
            let handles: Vec<_> = ThreadRanks::new(3)
                .into_iter()
                .map(|ranks| {
                    scope.spawn(move || {
                        let rank = ranks.rank() as Real;
                        // Rank r gathers r + 1 copies of r.
                        let gathered = ranks.all_gather(&vec![rank; ranks.rank() + 1]);
                        // Rank r sends its record k (the value 10 r + k) to rank k.
                        let mut plan = ExchangePlan {
                            send: vec![Vec::new(); 3],
                        };
                        for (to, send) in plan.send.iter_mut().enumerate() {
                            send.push(to as u32);
                        }
                        let exchanged =
                            ranks.exchange(&plan, 1, &mut |k, v| v.push(10.0 * rank + k as Real));
                        let mut both = [rank, -rank];
                        ranks.max_each(&mut both);
                        (gathered, exchanged, ranks.max(rank), both)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (rank, (gathered, exchanged, max, both)) in results.into_iter().enumerate() {
            assert_eq!(gathered.values, [0.0, 1.0, 1.0, 2.0, 2.0, 2.0]);
            assert_eq!(gathered.offsets, [0, 1, 3, 6]);
            let r = rank as Real;
            assert_eq!(exchanged.values, [r, 10.0 + r, 20.0 + r]);
            assert_eq!(exchanged.from_rank(1), [10.0 + r]);
            assert_eq!((max, both), (2.0, [2.0, 0.0]));
        }
    }
}
