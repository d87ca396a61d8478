//! The factor of safety by strength reduction: c and tan φ divided by a trial factor F until
//! the soil no longer comes to rest (Dawson, Roth & Drescher 1999, Géotechnique 49:835;
//! Griffiths & Lane 1999, Géotechnique 49:387; with SPH, Bui, Fukagawa, Sako & Wells 2011,
//! Géotechnique 61:565).
//!
//! Every trial starts from the same state, the soil at rest after the geostatic stage and its
//! release, and relaxes with the stage's damping μ = 2ζω₁ (dynamic relaxation) under the
//! reduced strength
//!
//! c_F = c / F,  tan φ_F = tan φ / F,  ψ_F = min(ψ, φ_F)
//!
//! (associated flow stays associated). The trial **fails** as soon as a particle has moved
//! more than `failure_displacement` × H from that state (H the soil's height along gravity) —
//! a slip that the damping could only slow down — or if the soil is still not at rest at
//! `trial_time`; it **holds** when the kinetic energy falls below the stage's tolerance (after
//! at least one period 4H/c). A bisection on F between a holding and a failing bound stops when
//! the bracket is narrower than `tolerance` × its lower end; the factor of safety is the
//! bracket's midpoint.

use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;

use crate::drucker_prager::DruckerPragerBui2008;
use crate::material::SoilMaterial;
use crate::model::SoilModel;
use crate::sph::config::{ConfigError, SoilError, StrengthReductionConfig};
use crate::sph::geostatic::GeostaticReport;
use crate::sph::relaxation::{RelaxationScale, relax};
use crate::sph::solver::SoilSolver;

/// One trial of the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trial {
    /// The trial factor F.
    pub factor: Real,
    /// How it ended.
    pub outcome: TrialOutcome,
    /// Simulated time of the trial, s.
    pub time: Real,
    /// Steps of the trial.
    pub steps: usize,
    /// Largest particle displacement from the starting state, m.
    pub max_displacement: Real,
    /// Final E_k / (½ M (gH/c)²), the stage's measure of rest.
    pub kinetic_energy_ratio: Real,
}

/// How a trial ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrialOutcome {
    /// The soil came to rest: the slope holds at this F.
    Holds,
    /// A particle moved beyond the failure displacement: the slope fails.
    Slips,
    /// Neither within the trial time: counted as failing.
    NotAtRest,
}

impl Trial {
    /// Whether the slope held at this F.
    pub fn holds(&self) -> bool {
        self.outcome == TrialOutcome::Holds
    }
}

/// The result of a search.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorOfSafety {
    /// The geostatic stage every trial starts from.
    pub stage: GeostaticReport,
    /// The factor of safety: the midpoint of the final bracket.
    pub factor: Real,
    /// The largest factor at which the soil held and the smallest at which it failed.
    pub bracket: (Real, Real),
    /// Every trial, in the order run.
    pub trials: Vec<Trial>,
}

impl std::fmt::Display for FactorOfSafety {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (low, high) = self.bracket;
        writeln!(f, "{}", self.stage)?;
        writeln!(
            f,
            "factor of safety   F = {:.4} (holds at {low:.4}, fails at {high:.4}; {} trials)",
            self.factor,
            self.trials.len()
        )?;
        for trial in &self.trials {
            writeln!(f, "  {trial}")?;
        }
        Ok(())
    }
}

impl std::fmt::Display for Trial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "F = {:.4}: {:11} after {:.3} s ({} steps), largest displacement {:.2e} m, E_k ratio {:.1e}",
            self.factor,
            match self.outcome {
                TrialOutcome::Holds => "holds",
                TrialOutcome::Slips => "slips",
                TrialOutcome::NotAtRest => "not at rest",
            },
            self.time,
            self.steps,
            self.max_displacement,
            self.kinetic_energy_ratio
        )
    }
}

/// The strength of `material` reduced by `factor`.
pub fn reduced_strength(material: &SoilMaterial, factor: Real) -> SoilMaterial {
    let friction = (material.friction_angle_deg.to_radians().tan() / factor)
        .atan()
        .to_degrees();
    SoilMaterial {
        cohesion: material.cohesion / factor,
        friction_angle_deg: friction,
        dilatancy_angle_deg: material.dilatancy_angle_deg.min(friction),
        ..*material
    }
}

impl<const D: usize, K: Kernel<D>> SoilSolver<D, K> {
    /// Runs the geostatic stage (which the solver must have) and then the strength-reduction
    /// search `config` on `soil`, calling `on_trial` after each trial (for progress); on
    /// return `soil` holds the state of the smallest failing trial factor.
    ///
    /// The trials run without the mean-stress diffusion (`stress_diffusion`), as the search
    /// was validated; the solver gets it back on return.
    pub fn factor_of_safety(
        &mut self,
        soil: &mut Particles<D>,
        config: &StrengthReductionConfig,
        on_trial: &mut dyn FnMut(&Trial),
    ) -> Result<FactorOfSafety, SoilError> {
        self.without_mean_stress_diffusion(|solver| solver.search(soil, config, on_trial))
    }

    fn search(
        &mut self,
        soil: &mut Particles<D>,
        config: &StrengthReductionConfig,
        on_trial: &mut dyn FnMut(&Trial),
    ) -> Result<FactorOfSafety, SoilError> {
        config.validate()?;
        let SoilModel::DruckerPrager(model) = self.system.model else {
            return Err(config_error(
                "constitutive",
                "a factor of safety needs a Drucker–Prager soil (a linear elastic soil never fails)",
            ));
        };
        let stage = self.geostatic.take().ok_or_else(|| {
            config_error(
                "geostatic",
                "a factor-of-safety search starts from the soil at rest: add a geostatic stage",
            )
        })?;
        let stage_report = self.run_geostatic_stage(soil, &stage)?;
        if !stage_report.converged {
            return Err(config_error(
                "geostatic.max_time",
                &format!(
                    "the geostatic stage was not at rest after {:.3} s (E_k ratio {:.1e} above {:.1e}), \
                     so no trial can start from equilibrium: raise max_time",
                    stage_report.time,
                    stage_report.kinetic_energy_ratio,
                    stage.kinetic_energy_tolerance
                ),
            ));
        }
        let start = soil.clone();
        let scale = RelaxationScale::of(self, soil, config.damping_ratio);
        let tolerance = stage.kinetic_energy_tolerance;
        let mut trials = Vec::new();
        // The state of the smallest failing factor so far: the slip to look at.
        let mut failing = None;
        let mut run = |solver: &mut Self, soil: &mut Particles<D>, factor: Real| {
            soil.clone_from(&start);
            let material = reduced_strength(model.material(), factor);
            solver.system.model = SoilModel::DruckerPrager(
                DruckerPragerBui2008::new(material, model.algorithm())
                    .expect("a reduced strength stays in range")
                    .with_matching(model.matching()),
            );
            let trial = run_trial(solver, soil, factor, (&scale, tolerance), config)?;
            on_trial(&trial);
            trials.push(trial);
            if !trial.holds() {
                match &mut failing {
                    Some(state) => Particles::clone_from(state, soil),
                    None => failing = Some(soil.clone()),
                }
            }
            Ok::<_, SoilError>(trial)
        };
        let (mut low, mut high) = config.bounds;
        if run(self, soil, high)?.holds() {
            return Err(config_error(
                "factor_of_safety.bounds",
                &format!("the soil still holds at F_high = {high}: raise the upper bound"),
            ));
        }
        let first = run(self, soil, low)?;
        if !first.holds() {
            let message = if first.outcome == TrialOutcome::Slips {
                format!(
                    "the soil fails already at F_low = {low} (a particle moved {:.3} m): lower the \
                     lower bound",
                    first.max_displacement
                )
            } else {
                format!(
                    "at F_low = {low} the soil did not come to rest within trial_time = {} s \
                     (E_k ratio {:.1e} above {tolerance:.1e}, largest displacement {:.2e} m): \
                     raise trial_time or damping_ratio, or lower the lower bound",
                    config.trial_time, first.kinetic_energy_ratio, first.max_displacement
                )
            };
            return Err(config_error("factor_of_safety.bounds", &message));
        }
        let mut count = 2;
        while high - low > config.tolerance * low {
            if count >= config.max_trials {
                return Err(config_error(
                    "factor_of_safety.max_trials",
                    &format!(
                        "the bisection did not converge in {} trials: F is in [{low:.4}, {high:.4}]",
                        config.max_trials
                    ),
                ));
            }
            let middle = 0.5 * (low + high);
            count += 1;
            if run(self, soil, middle)?.holds() {
                low = middle;
            } else {
                high = middle;
            }
        }
        if let Some(state) = failing {
            *soil = state;
        }
        self.system.model = SoilModel::DruckerPrager(model);
        self.system.update_lists(soil)?;
        Ok(FactorOfSafety {
            stage: stage_report,
            factor: 0.5 * (low + high),
            bracket: (low, high),
            trials,
        })
    }
}

fn config_error(field: &str, message: &str) -> SoilError {
    ConfigError::new(field, message).into()
}

/// One trial: damped steps from the state in `soil` ([`relax`]) until the soil is at rest, a
/// particle has moved more than the failure displacement, or the trial time is up.
fn run_trial<const D: usize, K: Kernel<D>>(
    solver: &mut SoilSolver<D, K>,
    soil: &mut Particles<D>,
    factor: Real,
    (scale, tolerance): (&RelaxationScale, Real),
    config: &StrengthReductionConfig,
) -> Result<Trial, SoilError> {
    let limit = config.failure_displacement * scale.height;
    let mut max_displacement = 0.0;
    let relaxation = relax(solver, soil, scale, config.trial_time, tolerance, |soil| {
        max_displacement = largest_displacement(soil);
        max_displacement > limit
    })
    .map_err(|failure| {
        config_error(
            "factor_of_safety",
            &format!("the trial at F = {factor} failed numerically {failure}"),
        )
    })?;
    let outcome = if relaxation.at_rest {
        TrialOutcome::Holds
    } else if max_displacement > limit {
        TrialOutcome::Slips
    } else {
        TrialOutcome::NotAtRest
    };
    Ok(Trial {
        factor,
        outcome,
        time: relaxation.time,
        steps: relaxation.steps,
        max_displacement,
        kinetic_energy_ratio: relaxation.kinetic_energy_ratio,
    })
}

/// The largest |u| of the soil's displacement field (zero at the start of every trial).
fn largest_displacement<const D: usize>(soil: &Particles<D>) -> Real {
    soil.soil.as_ref().map_or(0.0, |fields| {
        fields
            .displacement
            .iter()
            .map(|u| u.norm())
            .fold(0.0, Real::max)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reduction_divides_cohesion_and_friction_and_keeps_flow_associated() {
        let material = SoilMaterial {
            youngs_modulus: 1e6,
            poisson_ratio: 0.3,
            friction_angle_deg: 30.0,
            cohesion: 10.0,
            dilatancy_angle_deg: 30.0,
        };
        let reduced = reduced_strength(&material, 2.0);
        assert!((reduced.cohesion - 5.0).abs() < 1e-12);
        let tan = reduced.friction_angle_deg.to_radians().tan();
        assert!((tan - 30f64.to_radians().tan() / 2.0).abs() < 1e-12);
        assert_eq!(reduced.dilatancy_angle_deg, reduced.friction_angle_deg);
        let non_associated = SoilMaterial {
            dilatancy_angle_deg: 5.0,
            ..material
        };
        assert_eq!(
            reduced_strength(&non_associated, 2.0).dilatancy_angle_deg,
            5.0
        );
    }
}
