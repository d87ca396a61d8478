//! Application hooks called at every sample time.

use geosph_core::{Particles, Real};

use crate::share::Share;

/// Samples application-specific quantities of the fluid, written as extra columns of
/// `diagnostics.csv` and kept for the application.
pub trait Observer<const D: usize> {
    /// Names of the extra columns.
    fn columns(&self) -> Vec<&'static str>;

    /// Appends one value per column to `row` for the fluid at `time`.
    fn sample(&mut self, time: Real, fluid: &Particles<D>, row: &mut Vec<Real>);

    /// [`Observer::sample`] from this rank's [`Share`] of the particles: what the runner
    /// calls, on every rank of a distributed run (every rank keeps the observer's state, and
    /// must make the same collective calls of `share` in the same order). The default gathers
    /// every particle ([`Share::whole`]) and samples them; an observer that combines partial
    /// results over the ranks instead ([`Share::sum_each`], …) needs no rank to hold the whole
    /// run. In one process the share is every particle, as [`Observer::sample`] sees them.
    fn sample_share(&mut self, time: Real, share: &mut Share<'_, D>, row: &mut Vec<Real>) {
        self.sample(time, share.whole(), row);
    }

    /// What the observer accumulated (e.g. its samples), saved in a checkpoint; default none.
    fn save_state(&self) -> Vec<Real> {
        Vec::new()
    }

    /// Continues from a state saved by [`Observer::save_state`] (a restart); a one-line
    /// reason when it does not fit.
    fn restore_state(&mut self, _state: &[Real]) -> Result<(), String> {
        Ok(())
    }
}

/// An observer with no columns.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoObserver;

impl<const D: usize> Observer<D> for NoObserver {
    fn columns(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn sample(&mut self, _time: Real, _fluid: &Particles<D>, _row: &mut Vec<Real>) {}
}

/// Appends `records` of `N` values to an observer's saved state: their count, then the values.
pub fn push_records<const N: usize>(
    state: &mut Vec<Real>,
    records: impl ExactSizeIterator<Item = [Real; N]>,
) {
    state.push(records.len() as Real);
    for record in records {
        state.extend_from_slice(&record);
    }
}

/// Takes records of `N` values written by [`push_records`] from the front of `state`.
pub fn take_records<const N: usize>(state: &mut &[Real]) -> Result<Vec<[Real; N]>, String> {
    let short = || "the saved observer state is shorter than it says".to_owned();
    let (&count, rest) = state.split_first().ok_or_else(short)?;
    let count = count as usize;
    let values = rest.get(..count * N).ok_or_else(short)?;
    *state = &rest[count * N..];
    Ok(values
        .chunks_exact(N)
        .map(|chunk| std::array::from_fn(|k| chunk[k]))
        .collect())
}
