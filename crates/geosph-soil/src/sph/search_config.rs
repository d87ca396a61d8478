//! The settings of a factor-of-safety search by strength reduction (`factor_of_safety: (...)`
//! of a soil solver) and their validation.

use geosph_core::Real;
use geosph_sph::ConfigError;
use geosph_sph::config_error::positive;
use serde::{Deserialize, Serialize};

/// Settings of a strength-reduction search (`factor_of_safety: (...)` of a soil solver).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StrengthReductionConfig {
    /// The bracket (F_low, F_high): the soil must hold at F_low and fail at F_high (default
    /// (0.5, 4)).
    pub bounds: (Real, Real),
    /// The search stops when F_high − F_low ≤ tolerance × F_low (default 0.01).
    pub tolerance: Real,
    /// Most trials, bounds included (default 20).
    pub max_trials: usize,
    /// Longest trial in simulated seconds (default 1).
    pub trial_time: Real,
    /// A trial fails when a particle moves more than this fraction of the soil's height
    /// (default 0.02).
    pub failure_displacement: Real,
    /// Damping ratio ζ of the trials' relaxation, of the fundamental mode as in the geostatic
    /// stage (default 0.05). Critical damping of that mode overdamps the much slower plastic
    /// mechanisms: a slope that holds then takes longer than the trial to come to rest, and
    /// one that fails creeps too slowly to reach the failure displacement (docs/soil.md).
    pub damping_ratio: Real,
}

impl Default for StrengthReductionConfig {
    fn default() -> Self {
        Self {
            bounds: (0.5, 4.0),
            tolerance: 0.01,
            max_trials: 20,
            trial_time: 1.0,
            failure_displacement: 0.02,
            damping_ratio: 0.05,
        }
    }
}

impl StrengthReductionConfig {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let error = |field: &str, message: String| ConfigError {
            field: format!("factor_of_safety.{field}"),
            message,
        };
        let (low, high) = self.bounds;
        if !(low.is_finite() && high.is_finite() && 0.0 < low && low < high) {
            return Err(error(
                "bounds",
                format!("({low}, {high}) must satisfy 0 < F_low < F_high"),
            ));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(error(
                "tolerance",
                format!("{} is outside the allowed range (0, 1)", self.tolerance),
            ));
        }
        if self.max_trials < 3 {
            return Err(error(
                "max_trials",
                format!(
                    "{} is below 3 (the two bounds and one bisection)",
                    self.max_trials
                ),
            ));
        }
        positive("factor_of_safety.trial_time", self.trial_time)?;
        if !(self.damping_ratio > 0.0 && self.damping_ratio <= 1.0) {
            return Err(error(
                "damping_ratio",
                format!("{} is outside the allowed range (0, 1]", self.damping_ratio),
            ));
        }
        if !(self.failure_displacement > 0.0 && self.failure_displacement < 1.0) {
            return Err(error(
                "failure_displacement",
                format!(
                    "{} is outside the allowed range (0, 1)",
                    self.failure_displacement
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_read_from_ron_and_name_bad_fields() {
        let config: StrengthReductionConfig =
            ron::from_str("(bounds: (1.0, 2.0), tolerance: 0.02)").unwrap();
        assert_eq!(config.bounds, (1.0, 2.0));
        assert!(config.validate().is_ok());
        for (text, field) in [
            ("(bounds: (2.0, 1.0))", "factor_of_safety.bounds"),
            ("(tolerance: 0.0)", "factor_of_safety.tolerance"),
            ("(max_trials: 2)", "factor_of_safety.max_trials"),
            ("(trial_time: -1.0)", "factor_of_safety.trial_time"),
            ("(damping_ratio: 2.0)", "factor_of_safety.damping_ratio"),
            (
                "(failure_displacement: 1.5)",
                "factor_of_safety.failure_displacement",
            ),
        ] {
            let config: StrengthReductionConfig = ron::from_str(text).unwrap();
            assert_eq!(config.validate().unwrap_err().field, field, "{text}");
        }
    }
}
