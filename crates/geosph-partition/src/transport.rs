//! What a distributed run needs from its transport (MPI in `geosph-mpi`): moving the records a
//! plan names, gathering, and global reductions. A trait, so that the SPH layer that drives
//! the exchanges needs no MPI library.

use geosph_core::Real;

use crate::plan::ExchangePlan;

/// Records received in one exchange.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Received {
    /// The values of all records, by source rank.
    pub values: Vec<Real>,
    /// Where each source rank's values start, and at the end their total.
    pub offsets: Vec<usize>,
}

impl Received {
    /// The values that came from rank `source`.
    pub fn from_rank(&self, source: usize) -> &[Real] {
        &self.values[self.offsets[source]..self.offsets[source + 1]]
    }
}

/// The ranks of a distributed run as its exchanges and reductions see them. Every method is
/// collective: every rank calls it, in the same order.
pub trait Transport: Send {
    /// This rank, 0 ≤ rank < size.
    fn rank(&self) -> usize;

    /// The number of ranks.
    fn size(&self) -> usize;

    /// Sends to every rank s the records of the particles `plan.send[s]`, each the `width`
    /// values that `pack(i, values)` appends for particle i, and receives what every rank
    /// sent here, by source rank in the order it was sent.
    fn exchange(
        &self,
        plan: &ExchangePlan,
        width: usize,
        pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Received;

    /// Every rank's `values`, concatenated in rank order, on every rank.
    fn all_gather(&self, values: &[Real]) -> Received;

    /// The largest `value` over the ranks (exact: the same as in one process).
    fn max(&self, value: Real) -> Real;

    /// The largest of each of `values` over the ranks, in place (one collective for several
    /// maxima).
    fn max_each(&self, values: &mut [Real]) {
        for value in values {
            *value = self.max(*value);
        }
    }

    /// Every rank's `values`, the same number on every rank, concatenated in rank order.
    fn gather_each(&self, values: &[Real]) -> Vec<Real> {
        self.all_gather(values).values
    }

    /// The sum of `value` over the ranks, added in rank order (so the same on every rank and
    /// for every run on the same ranks).
    fn sum(&self, value: Real) -> Real {
        self.gather_each(&[value]).iter().sum()
    }

    /// Each of `values` summed over the ranks, in place, added in rank order from rank 0's
    /// (one collective for several sums; the same on every rank, and on one rank `values`
    /// itself, bit for bit).
    fn sum_each(&self, values: &mut [Real]) {
        let count = values.len();
        let all = self.gather_each(values);
        for (k, value) in values.iter_mut().enumerate() {
            let mut per_rank = all[k..].iter().step_by(count.max(1));
            *value = per_rank.next().copied().unwrap_or(0.0);
            for partial in per_rank {
                *value += partial;
            }
        }
    }

    /// Returns on each rank once every rank has called it: for a rank that must not end
    /// before rank 0 has written its files (a collective reduction of nothing, which waits as
    /// [`Transport::max`] does).
    fn barrier(&self) {
        self.max(0.0);
    }

    /// Ends every rank of the run with exit status `code`: for an error some ranks met and
    /// others did not, which would leave those waiting in their next exchange.
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

/// The transport of a run on one rank: nothing to exchange.
#[derive(Clone, Copy, Debug, Default)]
pub struct OneRank;

impl Transport for OneRank {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn exchange(
        &self,
        plan: &ExchangePlan,
        _width: usize,
        _pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Received {
        assert!(plan.is_empty(), "one rank sends nothing");
        Received {
            values: Vec::new(),
            offsets: vec![0, 0],
        }
    }

    fn all_gather(&self, values: &[Real]) -> Received {
        Received {
            values: values.to_vec(),
            offsets: vec![0, values.len()],
        }
    }

    fn max(&self, value: Real) -> Real {
        value
    }
}

/// A shared transport (the program keeps it for its own gathers while a solver exchanges
/// through it).
impl<T: Transport + Sync + ?Sized> Transport for std::sync::Arc<T> {
    fn rank(&self) -> usize {
        T::rank(self)
    }

    fn size(&self) -> usize {
        T::size(self)
    }

    fn exchange(
        &self,
        plan: &ExchangePlan,
        width: usize,
        pack: &mut dyn FnMut(usize, &mut Vec<Real>),
    ) -> Received {
        T::exchange(self, plan, width, pack)
    }

    fn all_gather(&self, values: &[Real]) -> Received {
        T::all_gather(self, values)
    }

    fn max(&self, value: Real) -> Real {
        T::max(self, value)
    }

    fn max_each(&self, values: &mut [Real]) {
        T::max_each(self, values);
    }

    fn gather_each(&self, values: &[Real]) -> Vec<Real> {
        T::gather_each(self, values)
    }

    fn sum(&self, value: Real) -> Real {
        T::sum(self, value)
    }

    fn sum_each(&self, values: &mut [Real]) {
        T::sum_each(self, values);
    }

    fn barrier(&self) {
        T::barrier(self);
    }

    fn abort(&self, code: i32) -> ! {
        T::abort(self, code)
    }
}
