//! The integrator's per-particle state as records, so that it moves with its particles
//! between the ranks of a distributed run.

use geosph_core::{PerParticle, Permutation, Real, Vector};

use super::{Integrator, Scheme};

/// Appends the components of `v` to `record`.
fn push<const D: usize>(record: &mut Vec<Real>, v: &Vector<D>) {
    record.extend_from_slice(v.as_slice());
}

/// Resizes `values` to `n` when the scheme uses it (`used`), else leaves it empty.
fn resize_if<T: Clone>(values: &mut Vec<T>, used: bool, n: usize, zero: T) {
    if used {
        values.resize(n, zero);
    }
}

/// Between steps an integrator keeps of each particle only its cached rates (a leap-frog
/// step starts from the rates at the end of the previous one); the stage copies are scratch
/// and are resized without being sent.
impl<const D: usize> PerParticle for Integrator<D> {
    fn record_width(&self) -> usize {
        D + 1 + if self.corrected { D } else { 0 } + usize::from(self.energy)
    }

    fn pack(&self, i: usize, record: &mut Vec<Real>) {
        let rates = &self.rates;
        push(record, &rates.acceleration[i]);
        record.push(rates.density_rate[i]);
        if self.corrected {
            push(record, &rates.position_correction[i]);
        }
        if self.energy {
            record.push(rates.energy_rate[i]);
        }
    }

    fn unpack(&mut self, i: usize, record: &[Real]) {
        let rates = &mut self.rates;
        rates.acceleration[i]
            .as_mut_slice()
            .copy_from_slice(&record[..D]);
        rates.density_rate[i] = record[D];
        let mut next = D + 1;
        if self.corrected {
            rates.position_correction[i]
                .as_mut_slice()
                .copy_from_slice(&record[next..next + D]);
            next += D;
        }
        if self.energy {
            rates.energy_rate[i] = record[next];
        }
    }

    fn resize(&mut self, n: usize) {
        let zero = Vector::<D>::zeros();
        let scheme = self.scheme;
        let rates = &mut self.rates;
        rates.acceleration.resize(n, zero);
        rates.density_rate.resize(n, 0.0);
        resize_if(&mut rates.position_correction, self.corrected, n, zero);
        let energy = self.energy;
        resize_if(&mut rates.energy_rate, energy, n, 0.0);
        let rk4 = scheme == Scheme::RungeKutta4;
        let accumulated = &mut self.accumulated;
        resize_if(&mut accumulated.acceleration, rk4, n, zero);
        resize_if(&mut accumulated.density_rate, rk4, n, 0.0);
        resize_if(&mut accumulated.position_correction, rk4, n, zero);
        resize_if(&mut accumulated.energy_rate, rk4 && energy, n, 0.0);
        let leap_frog = scheme == Scheme::LeapFrog;
        resize_if(&mut self.position_rate, !leap_frog, n, zero);
        let staged = matches!(scheme, Scheme::PredictorCorrector | Scheme::RungeKutta4);
        let start = &mut self.start;
        resize_if(&mut start.position, staged, n, zero);
        let halves = scheme != Scheme::SymplecticEuler;
        resize_if(&mut start.velocity, halves, n, zero);
        resize_if(&mut start.density, halves, n, 0.0);
        resize_if(&mut start.energy, halves && energy, n, 0.0);
    }

    /// Keeps the entries `k` with `keep[k]`; unlike [`Integrator::retain`] the cached rates
    /// stay current (the particles that go are not lost, they move to another rank).
    fn retain(&mut self, keep: &[bool]) {
        let current = self.rates_current;
        Integrator::retain(self, keep);
        self.rates_current = current;
    }

    fn permute(&mut self, permutation: &Permutation) {
        Integrator::permute(self, permutation);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record holds a, dρ/dt and, only when enabled, δv and de/dt; the width stays when the
    /// rank's particles go to zero and come back (a width taken from the arrays' lengths
    /// would drop δv and de/dt there), and a record round-trips through `pack`/`unpack`.
    #[test]
    fn record_width_follows_what_the_rates_carry_through_an_empty_rank() {
        let mut integrator = Integrator::<2>::new(Scheme::LeapFrog, 3);
        assert_eq!(integrator.record_width(), 3);
        assert!(integrator.rates().position_correction.is_empty());
        integrator.enable_position_correction();
        integrator.enable_energy();
        assert_eq!(integrator.record_width(), 6);
        PerParticle::resize(&mut integrator, 0);
        PerParticle::resize(&mut integrator, 2);
        assert_eq!(integrator.record_width(), 6);
        assert_eq!(integrator.rates().position_correction.len(), 2);
        assert_eq!(integrator.rates().energy_rate.len(), 2);
        let record = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        integrator.unpack(1, &record);
        let mut packed = Vec::new();
        integrator.pack(1, &mut packed);
        assert_eq!(packed, record);
    }
}
