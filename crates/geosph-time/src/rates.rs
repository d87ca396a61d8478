//! Time derivatives of the particle state and the trait of systems that compute them.

use geosph_core::{Particles, Real, Vector};

/// The time derivatives of one particle set, written by [`ExplicitSystem::rates`].
///
/// `position_correction` is added to the velocity when positions are advanced
/// (dx/dt = v + δv), e.g. the XSPH term of Monaghan (1989); like `energy_rate` it exists only
/// when a system writes it ([`Rates::enable_position_correction`]), so that a scene without
/// XSPH or shifting neither stores nor streams it (16 B per particle in 2D).
/// `energy_rate` exists (is as long as the others) only for particles with an internal-energy
/// field ([`Rates::enable_energy`]); it is empty otherwise.
#[derive(Clone, Debug, Default)]
pub struct Rates<const D: usize> {
    /// dv/dt.
    pub acceleration: Vec<Vector<D>>,
    /// dρ/dt.
    pub density_rate: Vec<Real>,
    /// δv in dx/dt = v + δv (empty when no system writes one).
    pub position_correction: Vec<Vector<D>>,
    /// de/dt of the specific internal energy (empty without an energy field).
    pub energy_rate: Vec<Real>,
}

impl<const D: usize> Rates<D> {
    /// Zero rates for `n` particles.
    pub fn zeros(n: usize) -> Self {
        Self {
            acceleration: vec![Vector::zeros(); n],
            density_rate: vec![0.0; n],
            position_correction: Vec::new(),
            energy_rate: Vec::new(),
        }
    }

    /// Creates the position correction δv (zero), as long as the other rates.
    pub fn enable_position_correction(&mut self) {
        self.position_correction.resize(self.len(), Vector::zeros());
    }

    /// Whether the rates carry a position correction.
    pub fn has_position_correction(&self) -> bool {
        !self.position_correction.is_empty()
    }

    /// Creates the energy rate (zero), as long as the other rates.
    pub fn enable_energy(&mut self) {
        self.energy_rate.resize(self.len(), 0.0);
    }

    /// Whether the rates carry an energy rate.
    pub fn has_energy(&self) -> bool {
        !self.energy_rate.is_empty()
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.acceleration.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.acceleration.is_empty()
    }

    /// Drops the rates of the particles `k` without `keep[k]` (nothing when these rates are
    /// unused and empty).
    pub fn retain(&mut self, keep: &[bool]) {
        if self.is_empty() {
            return;
        }
        geosph_core::retain(&mut self.acceleration, keep);
        geosph_core::retain(&mut self.density_rate, keep);
        if self.has_position_correction() {
            geosph_core::retain(&mut self.position_correction, keep);
        }
        if self.has_energy() {
            geosph_core::retain(&mut self.energy_rate, keep);
        }
    }

    /// Keeps the rates of the first `n` particles (the scratch of a restart with fewer
    /// particles than were built; its values are overwritten before they are read).
    pub fn truncate(&mut self, n: usize) {
        self.acceleration.truncate(n);
        self.density_rate.truncate(n);
        self.position_correction.truncate(n);
        self.energy_rate.truncate(n);
    }

    /// Largest |dv/dt|, reduced in a fixed order.
    pub fn max_acceleration(&self) -> Real {
        self.acceleration
            .iter()
            .fold(0.0, |m: Real, a| m.max(a.norm()))
    }
}

/// A particle system advanced by an explicit [`crate::Integrator`].
///
/// The integrator owns the scheme; the system owns the physics. Per step the integrator calls
/// [`ExplicitSystem::prepare`] once (neighbour search on the positions at the start of the
/// step, or after the drift for leap-frog), then [`ExplicitSystem::rates`] once per stage
/// (before each stage but the first of a multi-stage scheme [`ExplicitSystem::begin_stage`]),
/// and [`ExplicitSystem::finish_stage`] after each state update (e.g. a plastic return map or
/// a density clamp).
pub trait ExplicitSystem<const D: usize> {
    /// The error a system reports (e.g. a particle leaving the domain).
    type Error;

    /// Brings neighbour lists and other position-dependent data up to date.
    fn prepare(&mut self, particles: &mut Particles<D>) -> Result<(), Self::Error>;

    /// Computes the time derivatives of `particles` at time `time` into `rates`.
    fn rates(&mut self, particles: &Particles<D>, time: Real, rates: &mut Rates<D>);

    /// Applies constraints after the state was updated (return mapping, clamping); default none.
    fn finish_stage(&mut self, _particles: &mut Particles<D>) {}

    /// Before the rates of a stage that no [`ExplicitSystem::prepare`] precedes (the later
    /// stages of the predictor–corrector and Runge–Kutta schemes, which keep the lists of the
    /// step's start): e.g. a distributed system refreshes its halo from the other ranks, whose
    /// particles the last stage moved. Default none.
    fn begin_stage(&mut self, _particles: &mut Particles<D>) {}
}
