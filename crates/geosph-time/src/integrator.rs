//! Explicit integration schemes.
//!
//! Each scheme advances position x, velocity v, density ρ and, where it exists, the specific
//! internal energy e by one step
//! Δt using the [`Rates`] of an [`ExplicitSystem`]. The position rate is v + δv with the
//! system's position correction δv (e.g. XSPH). All updates are per-particle parallel loops
//! (rayon) that write only their own slot, so results do not depend on the thread count.

use std::ops::{Add, Mul};

use geosph_core::{Particles, Real, Vector};
use rayon::iter::Either;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::rates::{ExplicitSystem, Rates};

mod records;

/// Smallest number of particles a parallel task handles: below it, waking a second thread
/// costs more than it saves.
const MIN_CHUNK: usize = 1024;

/// The explicit time-integration schemes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Scheme {
    /// Symplectic (semi-implicit) Euler: v ← v + Δt a, then x ← x + Δt (v + δv). First order,
    /// one rate evaluation per step.
    SymplecticEuler,
    /// Kick-drift-kick leap-frog (velocity Verlet): v and ρ get half kicks before and after the
    /// drift x ← x + Δt (v^{n+½} + δv). The end-of-step rates are evaluated at v, ρ predicted
    /// to t^{n+1} with the previous rates (as velocity-Verlet variants for dissipative forces
    /// do, Groot & Warren 1997), which keeps velocity- and density-dependent terms second
    /// order. One rate evaluation per step (the rates at the end of a step start the next).
    /// Default.
    #[default]
    LeapFrog,
    /// Predictor–corrector (explicit midpoint, Monaghan 1989): a half step with the rates at
    /// t^n, then the full step with the rates at t^{n+½}. Second order, two evaluations.
    PredictorCorrector,
    /// Classical fourth-order Runge–Kutta, four evaluations per step.
    RungeKutta4,
}

impl Scheme {
    /// Rate evaluations per step.
    pub fn evaluations_per_step(self) -> usize {
        match self {
            Scheme::SymplecticEuler | Scheme::LeapFrog => 1,
            Scheme::PredictorCorrector => 2,
            Scheme::RungeKutta4 => 4,
        }
    }
}

/// The state an integrator keeps from the start of a step (multi-stage schemes only).
#[derive(Clone, Debug, Default)]
struct StartState<const D: usize> {
    position: Vec<Vector<D>>,
    velocity: Vec<Vector<D>>,
    density: Vec<Real>,
    /// The internal energy, sized like `density` when the particles have an energy field.
    energy: Vec<Real>,
}

/// An explicit integrator: the [`Scheme`] plus its scratch arrays, allocated once.
#[derive(Clone, Debug)]
pub struct Integrator<const D: usize> {
    scheme: Scheme,
    rates: Rates<D>,
    /// RK4's weighted sum of stage rates; its `position_correction` holds Σ w (v + δv).
    accumulated: Rates<D>,
    position_rate: Vec<Vector<D>>,
    start: StartState<D>,
    /// Leap-frog: whether `rates` belong to the current state.
    rates_current: bool,
    /// Whether the rates carry an energy rate ([`Integrator::enable_energy`]).
    energy: bool,
    /// Whether the rates carry a position correction
    /// ([`Integrator::enable_position_correction`]).
    corrected: bool,
}

impl<const D: usize> Integrator<D> {
    /// An integrator for `n` particles.
    pub fn new(scheme: Scheme, n: usize) -> Self {
        // Only the arrays a scheme uses are allocated (leap-frog keeps v and ρ at n+½ and
        // needs neither the start position nor a position rate): 32 B per particle in 2D.
        let start = match scheme {
            Scheme::SymplecticEuler => StartState::default(),
            Scheme::LeapFrog => StartState {
                position: Vec::new(),
                velocity: vec![Vector::zeros(); n],
                density: vec![0.0; n],
                energy: Vec::new(),
            },
            Scheme::PredictorCorrector | Scheme::RungeKutta4 => StartState {
                position: vec![Vector::zeros(); n],
                velocity: vec![Vector::zeros(); n],
                density: vec![0.0; n],
                energy: Vec::new(),
            },
        };
        let accumulated = if scheme == Scheme::RungeKutta4 {
            let mut sum = Rates::zeros(n);
            sum.enable_position_correction();
            sum
        } else {
            Rates::default()
        };
        Self {
            scheme,
            rates: Rates::zeros(n),
            accumulated,
            position_rate: match scheme {
                Scheme::LeapFrog => Vec::new(),
                _ => vec![Vector::zeros(); n],
            },
            start,
            rates_current: false,
            energy: false,
            corrected: false,
        }
    }

    /// Makes the integrator carry a position correction δv in dx/dt = v + δv, which the
    /// system writes into the rates' `position_correction` (XSPH, particle shifting); without
    /// it the particles drift with v and the rates have no such array.
    pub fn enable_position_correction(&mut self) {
        self.rates.enable_position_correction();
        self.corrected = true;
    }

    /// Makes the integrator advance the particles' internal energy e with the rates'
    /// `energy_rate` as it advances the density (for particles with an energy field).
    pub fn enable_energy(&mut self) {
        self.rates.enable_energy();
        self.energy = true;
        if self.scheme == Scheme::RungeKutta4 {
            self.accumulated.enable_energy();
        }
        let start = &mut self.start;
        start.energy.resize(start.density.len(), 0.0);
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The rates of the last evaluation (for time-step limits and diagnostics).
    pub fn rates(&self) -> &Rates<D> {
        &self.rates
    }

    /// Whether the cached [`Integrator::rates`] belong to the current state (leap-frog then
    /// starts the next step with them instead of evaluating them again).
    pub fn rates_current(&self) -> bool {
        self.rates_current
    }

    /// Restores the cached rates and whether they are current, as saved from
    /// [`Integrator::rates`] and [`Integrator::rates_current`] (a restart from a checkpoint).
    /// The scratch arrays take the rates' particle count, which is smaller than the one the
    /// integrator was made for when particles had left the domain before the checkpoint.
    pub fn restore_rates(&mut self, rates: Rates<D>, current: bool) {
        let n = rates.len();
        let start = &mut self.start;
        for field in [
            &mut self.position_rate,
            &mut start.position,
            &mut start.velocity,
        ] {
            field.truncate(n);
        }
        start.density.truncate(n);
        start.energy.truncate(n);
        self.accumulated.truncate(n);
        self.rates = rates;
        self.rates_current = current;
    }

    /// Reorders the cached rates with the particles (after a Z-order sort between steps).
    pub fn permute(&mut self, permutation: &geosph_core::Permutation) {
        permutation.apply(&mut self.rates.acceleration);
        permutation.apply(&mut self.rates.density_rate);
        if self.rates.has_position_correction() {
            permutation.apply(&mut self.rates.position_correction);
        }
        if self.rates.has_energy() {
            permutation.apply(&mut self.rates.energy_rate);
        }
    }

    /// Drops the entries of the particles `k` without `keep[k]` from every per-particle array,
    /// as [`Particles::retain`] does to the particles, and forgets the cached rates (they
    /// include the forces of the removed particles).
    pub fn retain(&mut self, keep: &[bool]) {
        self.rates.retain(keep);
        self.accumulated.retain(keep);
        let start = &mut self.start;
        for field in [
            &mut self.position_rate,
            &mut start.position,
            &mut start.velocity,
        ] {
            retain_sized(field, keep);
        }
        retain_sized(&mut start.density, keep);
        retain_sized(&mut start.energy, keep);
        self.invalidate();
    }

    /// Forgets cached rates, e.g. after particles were changed outside the integrator.
    pub fn invalidate(&mut self) {
        self.rates_current = false;
    }

    /// Advances `particles` from `time` to `time + dt`.
    pub fn step<S: ExplicitSystem<D>>(
        &mut self,
        system: &mut S,
        particles: &mut Particles<D>,
        time: Real,
        dt: Real,
    ) -> Result<(), S::Error> {
        let Self {
            scheme,
            rates,
            accumulated,
            position_rate: x_rate,
            start,
            rates_current,
            ..
        } = self;
        match scheme {
            Scheme::SymplecticEuler => {
                system.prepare(particles)?;
                system.rates(particles, time, rates);
                add_scaled(&mut particles.velocity, &rates.acceleration, dt);
                add_scaled(&mut particles.density, &rates.density_rate, dt);
                if let Some(energy) = energy_of(particles, rates) {
                    add_scaled(energy, &rates.energy_rate, dt);
                }
                position_rate(x_rate, &particles.velocity, &rates.position_correction);
                add_scaled(&mut particles.position, x_rate, dt);
                system.finish_stage(particles);
            }
            Scheme::LeapFrog => {
                if !*rates_current {
                    system.prepare(particles)?;
                    system.rates(particles, time, rates);
                }
                let half = 0.5 * dt;
                let n = rates.len();
                let correction = if rates.has_position_correction() {
                    Either::Left(rates.position_correction.par_iter().copied())
                } else {
                    Either::Right(rayon::iter::repeat_n(Vector::zeros(), n))
                };
                // Kick to n+½, drift with v^{n+½}, keep the n+½ state and predict v, ρ at n+1
                // with the old rates (so that rates depending on them are evaluated at
                // second-order-accurate values): one fused pass over the particles.
                (
                    particles.position.par_iter_mut(),
                    particles.velocity.par_iter_mut(),
                    particles.density.par_iter_mut(),
                    start.velocity.par_iter_mut(),
                    start.density.par_iter_mut(),
                    rates.acceleration.par_iter(),
                    rates.density_rate.par_iter(),
                    correction,
                )
                    .into_par_iter()
                    .with_min_len(MIN_CHUNK)
                    .for_each(|(x, v, rho, v_half, rho_half, a, rho_rate, dv)| {
                        *v_half = *v + a * half;
                        *rho_half = *rho + rho_rate * half;
                        *x += (*v_half + dv) * dt;
                        *v = *v_half + a * half;
                        *rho = *rho_half + rho_rate * half;
                    });
                if let Some(energy) = energy_of(particles, rates) {
                    (
                        energy.par_iter_mut(),
                        start.energy.par_iter_mut(),
                        rates.energy_rate.par_iter(),
                    )
                        .into_par_iter()
                        .with_min_len(MIN_CHUNK)
                        .for_each(|(e, e_half, e_rate)| {
                            *e_half = *e + e_rate * half;
                            *e = *e_half + e_rate * half;
                        });
                }
                system.finish_stage(particles);
                *rates_current = false;
                system.prepare(particles)?;
                system.rates(particles, time + dt, rates);
                // Second kick from the n+½ state with the new rates.
                start.kick_from_saved(particles, rates, half);
                system.finish_stage(particles);
                *rates_current = true;
            }
            Scheme::PredictorCorrector => {
                system.prepare(particles)?;
                start.save(particles);
                system.rates(particles, time, rates);
                position_rate(x_rate, &particles.velocity, &rates.position_correction);
                start.advance(particles, x_rate, rates, 0.5 * dt);
                system.finish_stage(particles);
                system.begin_stage(particles);
                system.rates(particles, time + 0.5 * dt, rates);
                position_rate(x_rate, &particles.velocity, &rates.position_correction);
                start.advance(particles, x_rate, rates, dt);
                system.finish_stage(particles);
            }
            Scheme::RungeKutta4 => {
                system.prepare(particles)?;
                start.save(particles);
                // (time offset of the stage, offset of the next stage, weight), Δt units.
                let stages = [
                    (0.0, 0.5, 1.0),
                    (0.5, 0.5, 2.0),
                    (0.5, 1.0, 2.0),
                    (1.0, 0.0, 1.0),
                ];
                for (k, &(offset, next, weight)) in stages.iter().enumerate() {
                    if k > 0 {
                        system.begin_stage(particles);
                    }
                    system.rates(particles, time + offset * dt, rates);
                    position_rate(x_rate, &particles.velocity, &rates.position_correction);
                    let keep = if k == 0 { 0.0 } else { 1.0 };
                    accumulate(accumulated, keep, rates, x_rate, weight);
                    if next > 0.0 {
                        start.advance(particles, x_rate, rates, next * dt);
                        system.finish_stage(particles);
                    }
                }
                // The accumulated position rate sits in `position_correction`.
                start.advance(
                    particles,
                    &accumulated.position_correction,
                    accumulated,
                    dt / 6.0,
                );
                system.finish_stage(particles);
            }
        }
        Ok(())
    }
}

impl<const D: usize> StartState<D> {
    fn save(&mut self, particles: &Particles<D>) {
        self.position.copy_from_slice(&particles.position);
        self.velocity.copy_from_slice(&particles.velocity);
        self.density.copy_from_slice(&particles.density);
        if let Some(energy) = &particles.energy
            && !self.energy.is_empty()
        {
            self.energy.copy_from_slice(energy);
        }
    }

    /// v ← v_saved + Δt a, ρ ← ρ_saved + Δt ρ̇ (one fused pass).
    fn kick_from_saved(&self, particles: &mut Particles<D>, rates: &Rates<D>, dt: Real) {
        (
            particles.velocity.par_iter_mut(),
            particles.density.par_iter_mut(),
            self.velocity.par_iter(),
            self.density.par_iter(),
            rates.acceleration.par_iter(),
            rates.density_rate.par_iter(),
        )
            .into_par_iter()
            .with_min_len(MIN_CHUNK)
            .for_each(|(v, rho, v_half, rho_half, a, rho_rate)| {
                *v = v_half + a * dt;
                *rho = rho_half + rho_rate * dt;
            });
        if let Some(energy) = energy_of(particles, rates) {
            from_start(energy, &self.energy, &rates.energy_rate, dt);
        }
    }

    /// x ← x⁰ + Δt ẋ, v ← v⁰ + Δt a, ρ ← ρ⁰ + Δt ρ̇.
    fn advance(
        &self,
        particles: &mut Particles<D>,
        x_rate: &[Vector<D>],
        rates: &Rates<D>,
        dt: Real,
    ) {
        from_start(&mut particles.position, &self.position, x_rate, dt);
        from_start(
            &mut particles.velocity,
            &self.velocity,
            &rates.acceleration,
            dt,
        );
        from_start(
            &mut particles.density,
            &self.density,
            &rates.density_rate,
            dt,
        );
        if let Some(energy) = energy_of(particles, rates) {
            from_start(energy, &self.energy, &rates.energy_rate, dt);
        }
    }
}

/// [`geosph_core::retain`] on a scratch array that exists for this scheme (an unused one is
/// empty).
fn retain_sized<T>(values: &mut Vec<T>, keep: &[bool]) {
    if !values.is_empty() {
        geosph_core::retain(values, keep);
    }
}

/// RK4: sum ← keep · sum + weight · stage rates (the position rate goes to `position_correction`).
fn accumulate<const D: usize>(
    sum: &mut Rates<D>,
    keep: Real,
    rates: &Rates<D>,
    x_rate: &[Vector<D>],
    weight: Real,
) {
    blend(&mut sum.acceleration, keep, &rates.acceleration, weight);
    blend(&mut sum.density_rate, keep, &rates.density_rate, weight);
    blend(&mut sum.position_correction, keep, x_rate, weight);
    if sum.has_energy() {
        blend(&mut sum.energy_rate, keep, &rates.energy_rate, weight);
    }
}

/// The particles' internal energy when they have one and the rates carry its rate.
fn energy_of<'a, const D: usize>(
    particles: &'a mut Particles<D>,
    rates: &Rates<D>,
) -> Option<&'a mut Vec<Real>> {
    particles.energy.as_mut().filter(|_| rates.has_energy())
}

/// ẋ = v + δv (ẋ = v without a `correction`).
fn position_rate<const D: usize>(
    out: &mut [Vector<D>],
    velocity: &[Vector<D>],
    correction: &[Vector<D>],
) {
    if correction.is_empty() {
        out.copy_from_slice(velocity);
        return;
    }
    out.par_iter_mut()
        .zip(velocity)
        .zip(correction)
        .for_each(|((x_rate, v), dv)| *x_rate = v + dv);
}

/// y ← y + Δt ẏ.
fn add_scaled<T>(values: &mut [T], rates: &[T], dt: Real)
where
    T: Copy + Send + Sync + Add<Output = T> + Mul<Real, Output = T>,
{
    values
        .par_iter_mut()
        .zip(rates)
        .with_min_len(MIN_CHUNK)
        .for_each(|(y, &rate)| *y = *y + rate * dt);
}

/// y ← y⁰ + Δt ẏ.
fn from_start<T>(values: &mut [T], start: &[T], rates: &[T], dt: Real)
where
    T: Copy + Send + Sync + Add<Output = T> + Mul<Real, Output = T>,
{
    values
        .par_iter_mut()
        .zip(start)
        .zip(rates)
        .with_min_len(MIN_CHUNK)
        .for_each(|((y, &y0), &rate)| *y = y0 + rate * dt);
}

/// s ← keep · s + weight · r.
fn blend<T>(sum: &mut [T], keep: Real, rates: &[T], weight: Real)
where
    T: Copy + Send + Sync + Add<Output = T> + Mul<Real, Output = T>,
{
    sum.par_iter_mut()
        .zip(rates)
        .for_each(|(s, &rate)| *s = *s * keep + rate * weight);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A set of independent harmonic oscillators, a = −ω² x, ρ̇ = −ρ (exact: e^{−t}) and,
    /// with an energy field, ė = −2 e (exact: e^{−2t}).
    struct Oscillators {
        omega: Real,
    }

    impl ExplicitSystem<1> for Oscillators {
        type Error = ();
        fn prepare(&mut self, _: &mut Particles<1>) -> Result<(), ()> {
            Ok(())
        }
        fn rates(&mut self, particles: &Particles<1>, _time: Real, rates: &mut Rates<1>) {
            for i in 0..particles.len() {
                rates.acceleration[i] = -self.omega * self.omega * particles.position[i];
                rates.density_rate[i] = -particles.density[i];
                if let Some(energy) = &particles.energy {
                    rates.energy_rate[i] = -2.0 * energy[i];
                }
            }
        }
    }

    /// Counts the calls an integrator makes of a system, in order: `p` prepare, `r` rates,
    /// `b` begin_stage.
    #[derive(Default)]
    struct Calls(String);

    impl ExplicitSystem<1> for Calls {
        type Error = ();
        fn prepare(&mut self, _: &mut Particles<1>) -> Result<(), ()> {
            self.0.push('p');
            Ok(())
        }
        fn rates(&mut self, _: &Particles<1>, _time: Real, _: &mut Rates<1>) {
            self.0.push('r');
        }
        fn begin_stage(&mut self, _: &mut Particles<1>) {
            self.0.push('b');
        }
    }

    /// Every rate evaluation that no `prepare` precedes within the step follows a
    /// `begin_stage` (a distributed system refreshes its halo there), and no other does.
    #[test]
    fn later_stages_begin_with_begin_stage() {
        for (scheme, calls) in [
            (Scheme::SymplecticEuler, "pr"),
            (Scheme::LeapFrog, "prpr"),
            (Scheme::PredictorCorrector, "prbr"),
            (Scheme::RungeKutta4, "prbrbrbr"),
        ] {
            let mut particles = Particles::<1>::at_rest(vec![Vector::<1>::new(1.0)], 1.0, 1.0);
            let mut system = Calls::default();
            let mut integrator = Integrator::new(scheme, 1);
            integrator
                .step(&mut system, &mut particles, 0.0, 0.1)
                .unwrap();
            assert_eq!(system.0, calls, "{scheme:?}");
        }
    }

    /// Error in x, ρ and e at t = 1 for x(0) = 1, v(0) = 0, ρ(0) = e(0) = 1 with `steps`
    /// steps.
    fn error(scheme: Scheme, steps: usize) -> [Real; 3] {
        let omega = 2.0;
        let mut particles = Particles::<1>::at_rest(vec![Vector::<1>::new(1.0)], 1.0, 1.0);
        particles.enable_energy()[0] = 1.0;
        let mut system = Oscillators { omega };
        let mut integrator = Integrator::new(scheme, 1);
        integrator.enable_energy();
        let dt = 1.0 / steps as Real;
        for n in 0..steps {
            integrator
                .step(&mut system, &mut particles, n as Real * dt, dt)
                .unwrap();
        }
        let x_error = (particles.position[0][0] - omega.cos()).abs();
        let rho_error = (particles.density[0] - (-1.0_f64).exp()).abs();
        let energy_error = (particles.energy.as_ref().unwrap()[0] - (-2.0_f64).exp()).abs();
        [x_error, rho_error, energy_error]
    }

    fn observed_order(scheme: Scheme) -> [Real; 3] {
        let (coarse, fine) = (error(scheme, 40), error(scheme, 80));
        std::array::from_fn(|k| (coarse[k] / fine[k]).log2())
    }

    #[test]
    fn schemes_converge_at_their_order() {
        for (scheme, order) in [
            (Scheme::SymplecticEuler, 1.0),
            (Scheme::LeapFrog, 2.0),
            (Scheme::PredictorCorrector, 2.0),
            (Scheme::RungeKutta4, 4.0),
        ] {
            let [x_order, rho_order, energy_order] = observed_order(scheme);
            assert!(
                (x_order - order).abs() < 0.25,
                "{scheme:?}: position order {x_order}, expected {order}"
            );
            assert!(
                (rho_order - order).abs() < 0.25,
                "{scheme:?}: density order {rho_order}, expected {order}"
            );
            assert!(
                (energy_order - order).abs() < 0.25,
                "{scheme:?}: internal-energy order {energy_order}, expected {order}"
            );
        }
    }

    #[test]
    fn leap_frog_keeps_oscillator_energy_bounded() {
        let omega: Real = 2.0;
        let mut particles = Particles::<1>::at_rest(vec![Vector::<1>::new(1.0)], 1.0, 1.0);
        let mut system = Oscillators { omega };
        let mut integrator = Integrator::new(Scheme::LeapFrog, 1);
        let dt = 0.05;
        let energy = |p: &Particles<1>| {
            0.5 * p.velocity[0][0].powi(2) + 0.5 * (omega * p.position[0][0]).powi(2)
        };
        let initial = energy(&particles);
        for n in 0..20_000 {
            integrator
                .step(&mut system, &mut particles, n as Real * dt, dt)
                .unwrap();
        }
        // Symplectic: the energy error stays O((ω Δt)²), it does not drift.
        let drift = (energy(&particles) - initial).abs() / initial;
        assert!(drift < (omega * dt).powi(2), "energy drift {drift}");
    }
}
