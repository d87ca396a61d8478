//! Application hooks called at every sample time.

use geosph_core::{Particles, Real};

/// Samples application-specific quantities of the fluid, written as extra columns of
/// `diagnostics.csv` and kept for the application.
pub trait Observer<const D: usize> {
    /// Names of the extra columns.
    fn columns(&self) -> Vec<&'static str>;

    /// Appends one value per column to `row` for the fluid at `time`.
    fn sample(&mut self, time: Real, fluid: &Particles<D>, row: &mut Vec<Real>);
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
