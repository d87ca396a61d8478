//! Blow-up checks after every step, and the report of a blow-up.
//!
//! [`check`] runs after every step against the [`Limits`] fixed when the run starts, in this
//! order (the first failure wins, so a non-finite state is named as such rather than as the
//! density error it also causes):
//!
//! 1. the time step is finite and positive;
//! 2. every position, velocity, density (and soil stress) is finite;
//! 3. every particle is inside the domain on its non-periodic axes (the runner has removed
//!    those that left, [`crate::escape`], unless too many did);
//! 4. the density error is at most [`MAX_DENSITY_ERROR`];
//! 5. soil only: the stress magnitude ‖σ‖ is at most [`Limits::max_stress`];
//! 6. the kinetic energy is within the [`EnergyBudget`].
//!
//! Checks 2, 3, 5 and 6 share one sequential, branch-free pass over the particles ([`scan`]),
//! without allocation; it sums in index order, so a run stops at the same step with any
//! number of threads. The particle to blame is looked up only after a check has failed.
//! [`report`] writes `blowup.txt` then.

pub mod report;
pub mod scan;

use geosph_core::{Domain, Particles, Real, Vector};
use geosph_neighbours::SearchError;
use geosph_sph::SphSetup;
use geosph_sph::{Solver, SolverError, StepReport, max_speed};

pub use scan::Scan;

/// Largest relative density error |ρ/ρ₀ − 1| a weakly compressible run may reach before it is
/// declared blown up. WCSPH is designed for ≈ 1 % (Monaghan 1994); 20 % means the sound speed
/// or the time step is far off.
pub const MAX_DENSITY_ERROR: Real = 0.2;

/// The kinetic energy may reach this multiple of the energy available to it
/// ([`EnergyBudget`]); the margin covers the time integrator's energy error and the estimate
/// of the initially stored elastic energy.
pub const ENERGY_FACTOR: Real = 2.0;

/// Mach number of the kinetic-energy floor: a bulk flow slower than this fraction of the
/// sound speed is never called a blow-up, whatever the energy budget (weakly compressible SPH
/// is designed for Mach ≤ 0.1, so this floor is far below any real flow's energy scale).
pub const ENERGY_FLOOR_MACH: Real = 0.01;

/// A stress magnitude may reach this multiple of the solver's [`Solver::stress_scale`] (for
/// soil the geostatic stress of the domain's height plus the stress of an elastic impact at
/// free-fall speed).
pub const STRESS_FACTOR: Real = 10.0;

/// Exit status of the apps when a run blows up (0: success, 1: any other error, 2: a command
/// line clap refuses, 130: interrupted by Ctrl-C).
pub const EXIT_BLOW_UP: u8 = 3;

/// The quantity a check found wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// The time step is not finite or not positive.
    TimeStep,
    /// A position is not finite, or lies outside the domain.
    Position,
    /// A velocity is not finite.
    Velocity,
    /// A density is not finite.
    Density,
    /// The relative density error exceeds [`MAX_DENSITY_ERROR`].
    DensityError,
    /// A soil stress is not finite or exceeds [`Limits::max_stress`].
    Stress,
    /// The kinetic energy exceeds the [`EnergyBudget`].
    KineticEnergy,
}

impl Quantity {
    /// Its name as the report and the error message print it, e.g. "density error".
    pub fn name(self) -> &'static str {
        match self {
            Self::TimeStep => "time step",
            Self::Position => "position",
            Self::Velocity => "velocity",
            Self::Density => "density",
            Self::DensityError => "density error",
            Self::Stress => "stress",
            Self::KineticEnergy => "kinetic energy",
        }
    }

    /// The unit of [`Diagnosis::value`] and [`Diagnosis::bound`].
    pub fn unit(self) -> &'static str {
        match self {
            Self::TimeStep => "s",
            Self::Position => "m outside the domain",
            Self::Velocity => "m/s",
            Self::Density => "kg/m³",
            Self::DensityError => "(fraction of ρ₀)",
            Self::Stress => "Pa",
            Self::KineticEnergy => "J",
        }
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What went wrong in a step.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnosis {
    /// The quantity that failed.
    pub quantity: Quantity,
    /// The offending particle (index in the failed state) and its persistent id, if one is to
    /// blame.
    pub particle: Option<(usize, u32)>,
    /// The value found (a non-finite one, a distance outside the domain, the density error,
    /// ‖σ‖, the kinetic energy), in [`Quantity::unit`].
    pub value: Real,
    /// The bound it broke; `None` when the bound is "finite".
    pub bound: Option<Real>,
    /// A one-line explanation with advice.
    pub explanation: String,
}

/// The kinetic energy a run may reach: with no input but gravity (walls do not move),
///
/// KE(t) + E_el(t) = KE(0) + E_el(0) + W_g(t) − D(t),  W_g(t) = Σ m g·(x(t) − x(0)) = M g·Δx_cm,
///
/// with E_el ≥ 0 the stored elastic (compression) energy and D ≥ 0 what viscosity dissipated.
/// So KE(t) ≤ KE(0) + E_el(0) + W_g(t). A run blows up when KE(t) exceeds
/// [`ENERGY_FACTOR`] × that, plus the [`ENERGY_FLOOR_MACH`] floor ½ M (0.01 c)². E_el(0) is
/// estimated as Σ ½ m c² (ρ/ρ₀ − 1)², the energy of a linear-elastic compression. Walls with a
/// prescribed velocity (a belt, a Couette plate) can drive the flow up to their own speed
/// u_w: ½ M |u_w|²max is added to the initial energy, and rigid bodies the most potential
/// energy they can release ([`LimitInputs::add_bodies`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyBudget {
    /// KE(0) + E_el(0) at the start of the run (or of the restart), J.
    pub initial: Real,
    /// Σ m g·x at the start, J.
    pub initial_gravity_moment: Real,
    /// ½ M (ENERGY_FLOOR_MACH · c)², J.
    pub floor: Real,
}

impl EnergyBudget {
    /// Takes out of the budget the particles removed from the run (they left the domain),
    /// whose ½ m |v|² sums to `kinetic_energy` and m g·x to `gravity_moment` when they go.
    /// The balance then holds for the particles that remain: the kinetic energy carried away
    /// is no longer available to them, and the work of gravity is still measured on each of
    /// them from its own start (without this a particle falling out through the floor would
    /// take its work with it and lower the bound of the others).
    pub fn carry_away(&mut self, kinetic_energy: Real, gravity_moment: Real) {
        self.initial -= kinetic_energy;
        self.initial_gravity_moment -= gravity_moment;
    }

    /// The largest kinetic energy allowed when the particles' Σ m g·x is `gravity_moment`.
    pub fn bound(&self, gravity_moment: Real) -> Real {
        let work = gravity_moment - self.initial_gravity_moment;
        ENERGY_FACTOR * (self.initial + work).max(0.0) + self.floor
    }
}

/// The bounds of a run, fixed when it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits<const D: usize> {
    /// The domain particles must stay in (on its non-periodic axes).
    pub domain: Domain<D>,
    /// Gravity.
    pub gravity: Vector<D>,
    /// ρ₀.
    pub rest_density: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// Kernel support radius, for the neighbours listed in the report.
    pub support_radius: Real,
    /// The energy budget; `None` when gravity has a component along a periodic axis (it can
    /// then feed energy without bound).
    pub energy: Option<EnergyBudget>,
    /// Largest stress magnitude ‖σ‖ = √(σ:σ), Pa: [`STRESS_FACTOR`] × the solver's
    /// [`Solver::stress_scale`], or ×
    /// the largest initial ‖σ‖ if that is larger; `None` without soil fields or when both are
    /// zero.
    pub max_stress: Option<Real>,
}

/// What [`Limits::new`] needs besides the particles.
#[derive(Clone, Debug)]
pub struct LimitInputs<const D: usize> {
    /// The domain.
    pub domain: Domain<D>,
    /// Gravity.
    pub gravity: Vector<D>,
    /// ρ₀.
    pub rest_density: Real,
    /// Particle spacing dx.
    pub spacing: Real,
    /// Kernel support radius.
    pub support_radius: Real,
    /// The sound speed c (the elastic P-wave speed for soil; for the incompressible solvers
    /// the reference speed 10 √(2 |g| H) of their artificial viscosity).
    pub sound_speed: Real,
    /// Energy that sources other than the particles' own can give the flow, J: the rigid
    /// bodies' potential energy ([`LimitInputs::add_bodies`]).
    pub external_energy: Real,
}

impl<const D: usize> LimitInputs<D> {
    /// The inputs a scene's solver is built from (before it consumes them); the sound speed is
    /// the scene's, replaced in [`Limits::new`] by the solver's when it has one.
    pub fn of(setup: &SphSetup<D>) -> Self {
        Self {
            domain: setup.domain.clone(),
            gravity: setup.gravity,
            rest_density: setup.rest_density,
            spacing: setup.spacing,
            support_radius: setup.kernel.support_factor() * setup.smoothing_length,
            sound_speed: setup.sound_speed,
            external_energy: 0.0,
        }
    }

    /// Adds the potential energy rigid bodies of masses m_b can give the flow by sinking from
    /// the domain's top to its floor, Σ m_b g·(x_floor − x_top) with x_floor (x_top) the
    /// domain's corner farthest along (against) g: a bound that holds wherever the bodies are,
    /// at the start or at a restart.
    pub fn add_bodies(&mut self, masses: impl IntoIterator<Item = Real>) {
        let g = self.gravity;
        let corner = |down: bool| {
            Vector::<D>::from_fn(|k, _| {
                if (g[k] > 0.0) == down {
                    self.domain.max[k]
                } else {
                    self.domain.min[k]
                }
            })
        };
        let drop = g.dot(&(corner(true) - corner(false))).max(0.0);
        self.external_energy += masses.into_iter().sum::<Real>() * drop;
    }
}

impl<const D: usize> Limits<D> {
    /// The limits of a run of `solver` starting from `fluid`: c is the solver's
    /// [`Solver::sound_speed`] when positive (WCSPH, soil), else `inputs.sound_speed`.
    pub fn new(inputs: LimitInputs<D>, fluid: &Particles<D>, solver: &dyn Solver<D>) -> Self {
        let LimitInputs {
            domain,
            gravity,
            rest_density,
            spacing,
            support_radius,
            mut sound_speed,
            external_energy,
        } = inputs;
        if solver.sound_speed() > 0.0 {
            sound_speed = solver.sound_speed();
        }
        let gravity_on_periodic_axis = (0..D).any(|k| domain.periodic[k] && gravity[k] != 0.0);
        let mut limits = Self {
            domain,
            gravity,
            rest_density,
            spacing,
            support_radius,
            energy: None,
            max_stress: None,
        };
        let start = Scan::of(fluid, &limits);
        let mass: Real = fluid.mass.iter().sum();
        let stored: Real = match &fluid.energy {
            // A gas's flow draws on its internal energy, all of which it could turn into
            // motion (a blast wave between equal densities has no compression to spend).
            Some(energy) => energy
                .iter()
                .zip(&fluid.mass)
                .map(|(e, m)| m * e.max(0.0))
                .sum(),
            None => fluid
                .density
                .iter()
                .zip(&fluid.mass)
                .map(|(rho, m)| 0.5 * m * (sound_speed * (rho / rest_density - 1.0)).powi(2))
                .sum(),
        };
        if !gravity_on_periodic_axis {
            let wall_speed = max_speed(&solver.walls().velocity);
            limits.energy = Some(EnergyBudget {
                initial: start.kinetic_energy
                    + stored
                    + 0.5 * mass * wall_speed * wall_speed
                    + external_energy
                    + solver.surface_energy(fluid),
                initial_gravity_moment: start.gravity_moment,
                floor: 0.5 * mass * (ENERGY_FLOOR_MACH * sound_speed).powi(2),
            });
        }
        if fluid.soil.is_some() {
            let g = gravity.norm();
            let height = match g > 0.0 {
                true => (0..D)
                    .map(|k| limits.domain.extent()[k] * gravity[k].abs() / g)
                    .sum(),
                false => 0.0,
            };
            if let Some(scale) = solver.stress_scale(g, height) {
                let scale = scale.max(start.max_stress);
                if scale > 0.0 && scale.is_finite() {
                    limits.max_stress = Some(STRESS_FACTOR * scale);
                }
            }
        }
        limits
    }
}

/// Whether [`check`] can find trouble after a step whose particles `scan` describes: its
/// conditions, from the scan and the report alone (a distributed run tests this on the scan
/// over every rank, [`Scan::over_ranks`], and gathers the particles only when it holds).
pub fn suspect<const D: usize>(report: &StepReport, scan: &Scan<D>, limits: &Limits<D>) -> bool {
    let energy_exceeded = limits
        .energy
        .as_ref()
        .is_some_and(|budget| scan.kinetic_energy > budget.bound(scan.gravity_moment));
    let healthy = report.dt.is_finite()
        && report.dt > 0.0
        && scan.finite
        && !scan.leaves_domain(limits)
        && report.density_error_max.is_finite()
        && report.density_error_max <= MAX_DENSITY_ERROR
        && !limits
            .max_stress
            .is_some_and(|bound| scan.max_stress > bound)
        && !energy_exceeded;
    !healthy
}

/// Checks the state after a step against `limits`; `None` when healthy.
pub fn check<const D: usize>(
    report: &StepReport,
    fluid: &Particles<D>,
    solver: &dyn Solver<D>,
    limits: &Limits<D>,
) -> Option<Diagnosis> {
    if !(report.dt.is_finite() && report.dt > 0.0) {
        return Some(Diagnosis {
            quantity: Quantity::TimeStep,
            particle: None,
            value: report.dt,
            bound: None,
            explanation: format!(
                "the time step became {}: a velocity or an acceleration is not finite; {}",
                report.dt,
                solver.blow_up_advice()
            ),
        });
    }
    let particle = |i: usize| Some((i, fluid.id[i]));
    let scan = Scan::of(fluid, limits);
    if !scan.finite
        && let Some((i, quantity, value)) = Scan::first_non_finite(fluid)
    {
        return Some(Diagnosis {
            quantity,
            particle: particle(i),
            value,
            bound: None,
            explanation: format!(
                "the {quantity} is not finite ({value}); {}",
                solver.blow_up_advice()
            ),
        });
    }
    if scan.leaves_domain(limits)
        && let Some((i, distance)) = Scan::first_outside(fluid, limits)
    {
        return Some(outside_domain(
            i,
            fluid.id[i],
            distance,
            &fluid.position[i],
            &limits.domain,
        ));
    }
    if !(report.density_error_max.is_finite() && report.density_error_max <= MAX_DENSITY_ERROR) {
        let i = (0..fluid.len())
            .max_by(|&a, &b| {
                let error = |k: usize| {
                    let e = solver.density_error(fluid.density[k]);
                    if e.is_nan() { Real::INFINITY } else { e }
                };
                error(a).total_cmp(&error(b))
            })
            .unwrap_or(0);
        let error = solver.density_error(fluid.density[i]);
        return Some(Diagnosis {
            quantity: Quantity::DensityError,
            particle: particle(i),
            value: error,
            bound: Some(MAX_DENSITY_ERROR),
            explanation: format!(
                "density {:.6e} kg/m³ is {:.1} % from the rest density (bound {:.0} %): {}",
                fluid.density[i],
                100.0 * error,
                100.0 * MAX_DENSITY_ERROR,
                solver.blow_up_advice()
            ),
        });
    }
    if let Some(bound) = limits.max_stress
        && scan.max_stress > bound
    {
        let (i, value) = Scan::largest_stress(fluid);
        return Some(Diagnosis {
            quantity: Quantity::Stress,
            particle: particle(i),
            value,
            bound: Some(bound),
            explanation: format!(
                "stress magnitude {value:.3e} Pa exceeds {STRESS_FACTOR} × the largest geostatic and impact stress ({bound:.3e} Pa): the stress integration is unstable; lower `cfl` or raise the artificial viscosity"
            ),
        });
    }
    if let Some(budget) = &limits.energy {
        let bound = budget.bound(scan.gravity_moment);
        if scan.kinetic_energy > bound {
            let i = Scan::most_energetic(fluid);
            return Some(Diagnosis {
                quantity: Quantity::KineticEnergy,
                particle: particle(i),
                value: scan.kinetic_energy,
                bound: Some(bound),
                explanation: format!(
                    "kinetic energy {:.3e} J exceeds {ENERGY_FACTOR} × what gravity and the initial state can supply ({bound:.3e} J): energy is being created; {}",
                    scan.kinetic_energy,
                    solver.blow_up_advice()
                ),
            });
        }
    }
    None
}

/// The diagnosis of a step that failed because the neighbour search met a particle of
/// `fluid` it could not bin (its [`SearchError::OutsideDomain`]: a position that is not
/// finite; the pair lists bin finite positions outside the domain in their edge cells);
/// `None` for any other error.
pub fn escaped<const D: usize>(
    error: &SolverError,
    fluid: &Particles<D>,
    limits: &Limits<D>,
) -> Option<Diagnosis> {
    let SolverError::Search(SearchError::OutsideDomain {
        index,
        position,
        min,
        max,
    }) = error
    else {
        return None;
    };
    let &index = index;
    if index >= fluid.len() || position.len() != D {
        return None;
    }
    let distance = (0..D)
        .map(|k| (min[k] - position[k]).max(position[k] - max[k]))
        .fold(0.0, Real::max);
    Some(outside_domain(
        index,
        fluid.id[index],
        distance,
        &Vector::<D>::from_column_slice(position),
        &limits.domain,
    ))
}

/// The diagnosis of particle `index` (id `id`) at `position`, `distance` outside `domain` (or
/// with a non-finite coordinate).
pub fn outside_domain<const D: usize>(
    index: usize,
    id: u32,
    distance: Real,
    position: &Vector<D>,
    domain: &Domain<D>,
) -> Diagnosis {
    if let Some(&c) = position.iter().find(|c| !c.is_finite()) {
        return Diagnosis {
            quantity: Quantity::Position,
            particle: Some((index, id)),
            value: c,
            bound: None,
            explanation: format!(
                "the position is not finite ({}); lower `cfl`",
                report::point(position.as_slice())
            ),
        };
    }
    Diagnosis {
        quantity: Quantity::Position,
        particle: Some((index, id)),
        value: distance,
        bound: Some(0.0),
        explanation: format!(
            "at {} it lies {distance:.3e} m outside the domain [{}, {}): {}",
            report::point(position.as_slice()),
            report::point(domain.min.as_slice()),
            report::point(domain.max.as_slice()),
            OUTSIDE_ADVICE
        ),
    }
}

/// What a user can do about a particle outside the domain.
pub const OUTSIDE_ADVICE: &str = "if the flow may go there (a splash, an outflow), enlarge the scene's `domain`; otherwise check the walls (a leak) and the time step (lower `cfl`)";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_energy_bound_follows_the_work_of_gravity() {
        let budget = EnergyBudget {
            initial: 1.0,
            initial_gravity_moment: -100.0,
            floor: 0.5,
        };
        // No fall yet: 2 × 1 + 0.5.
        assert_eq!(budget.bound(-100.0), 2.5);
        // The centre of mass fell: gravity did 10 J of work.
        assert_eq!(budget.bound(-90.0), 2.0 * 11.0 + 0.5);
        // Risen above the start by more than the energy there was: only the floor.
        assert_eq!(budget.bound(-120.0), 0.5);
    }
}
