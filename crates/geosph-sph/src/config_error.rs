//! [`ConfigError`]: a solver setting outside its allowed range, and the checks that make one.
//! Every solver configuration validates itself with them; the scene prefixes the field with
//! `solver.`.

use geosph_core::Real;

/// A solver setting out of range: the field (relative to the solver block) and what is
/// allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{field}`: {message}")]
pub struct ConfigError {
    /// The field, e.g. `viscosity.alpha`.
    pub field: String,
    /// The allowed range and the value given.
    pub message: String,
}

impl ConfigError {
    /// The error of `field` with `message`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// `value` must be finite and in [`low`, `high`].
pub fn in_range(field: &str, value: Real, low: Real, high: Real) -> Result<(), ConfigError> {
    if value.is_finite() && value >= low && value <= high {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            format!("must lie in [{low}, {high}], got {value}"),
        ))
    }
}

/// `value` must be finite and > 0.
pub fn positive(field: &str, value: Real) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            format!("must be a finite number > 0, got {value}"),
        ))
    }
}
