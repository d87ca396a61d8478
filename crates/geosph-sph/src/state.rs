//! The warm-start state of a solver, saved in a checkpoint and restored on a restart.
//!
//! A solver saves exactly what its next step depends on beyond the particles (step count,
//! cached rates, the positions its neighbour lists were built at, warm-start pressures), as
//! named arrays of `f64` bits, so a restarted run continues bitwise like the uninterrupted one.

use geosph_core::Real;
use nalgebra::SMatrix;
use serde::{Deserialize, Serialize};

/// Named arrays of reals; matrices and vectors are stored column-major, one after another.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StateArrays {
    arrays: Vec<(String, Vec<Real>)>,
}

/// A saved state does not fit the solver or particles it is restored into.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("saved state: {0}")]
pub struct StateError(pub String);

impl StateArrays {
    /// Adds the array `name`.
    pub fn push(&mut self, name: &str, values: &[Real]) {
        self.arrays.push((name.to_owned(), values.to_vec()));
    }

    /// Adds the array `name` of `R`×`C` matrices (vectors when `C` = 1).
    pub fn push_matrices<const R: usize, const C: usize>(
        &mut self,
        name: &str,
        values: &[SMatrix<Real, R, C>],
    ) {
        let flat = values.iter().flat_map(|m| m.iter().copied()).collect();
        self.arrays.push((name.to_owned(), flat));
    }

    /// Whether the array `name` exists.
    pub fn contains(&self, name: &str) -> bool {
        self.arrays.iter().any(|(n, _)| n == name)
    }

    /// Removes and returns the array `name`.
    pub fn take(&mut self, name: &str) -> Result<Vec<Real>, StateError> {
        let index = self
            .arrays
            .iter()
            .position(|(n, _)| n == name)
            .ok_or_else(|| StateError(format!("`{name}` is missing")))?;
        Ok(self.arrays.swap_remove(index).1)
    }

    /// Removes and returns the one value saved as `name`.
    pub fn take_value(&mut self, name: &str) -> Result<Real, StateError> {
        match self.take(name)?.as_slice() {
            [value] => Ok(*value),
            values => Err(StateError(format!(
                "`{name}` holds {} values, not 1",
                values.len()
            ))),
        }
    }

    /// Removes and returns the array `name` of `R`×`C` matrices, checking that it holds
    /// `count` of them.
    pub fn take_matrices<const R: usize, const C: usize>(
        &mut self,
        name: &str,
        count: usize,
    ) -> Result<Vec<SMatrix<Real, R, C>>, StateError> {
        let flat = self.take(name)?;
        if flat.len() != count * R * C {
            return Err(StateError(format!(
                "`{name}` holds {} values, not {count} × {R}×{C}",
                flat.len()
            )));
        }
        Ok(flat
            .chunks_exact(R * C)
            .map(SMatrix::<Real, R, C>::from_column_slice)
            .collect())
    }
}

/// What a solver's next step depends on besides the particles: see [`crate::Solver`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolverState {
    /// The solver's name ([`crate::Solver::name`]), checked on restore.
    pub method: String,
    /// Steps taken (sorting and re-initialisation schedules count them).
    pub steps: u64,
    /// The solver's arrays.
    pub arrays: StateArrays,
    /// The state of its moving walls ([`crate::WallMotion::save_state`]), if it has any.
    pub wall_motion: Option<Vec<u8>>,
}

impl SolverState {
    /// An empty state of `method` after `steps` steps.
    pub fn new(method: &str, steps: usize) -> Self {
        Self {
            method: method.to_owned(),
            steps: steps as u64,
            arrays: StateArrays::default(),
            wall_motion: None,
        }
    }

    /// Checks the state was saved by `method` and returns its step count.
    pub fn steps_of(&self, method: &str) -> Result<usize, StateError> {
        if self.method != method {
            return Err(StateError(format!(
                "saved by the {} solver, not {method}",
                self.method
            )));
        }
        Ok(self.steps as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::{Tensor3, Vector};

    #[test]
    fn arrays_round_trip_and_report_mismatches() {
        let mut arrays = StateArrays::default();
        let vectors = vec![Vector::<2>::new(1.0, -2.0), Vector::<2>::new(0.1, 3.5)];
        let tensors = vec![Tensor3::from_fn(|r, c| (3 * r + c) as Real)];
        arrays.push_matrices("velocity", &vectors);
        arrays.push_matrices("stress", &tensors);
        arrays.push("max_acceleration", &[9.81]);
        assert_eq!(arrays.take_matrices::<3, 3>("stress", 1).unwrap(), tensors);
        assert!(arrays.take_matrices::<2, 1>("velocity", 3).is_err());
        assert!(arrays.take("velocity").is_err(), "taken once");
        assert_eq!(arrays.take_value("max_acceleration").unwrap(), 9.81);
        assert_eq!(
            SolverState::new("wcsph", 3)
                .steps_of("dfsph")
                .unwrap_err()
                .0,
            "saved by the wcsph solver, not dfsph"
        );
    }
}
