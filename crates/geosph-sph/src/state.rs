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

    /// Removes and returns the array `name`, checking that it holds `count` values.
    pub fn take_values(&mut self, name: &str, count: usize) -> Result<Vec<Real>, StateError> {
        let values = self.take(name)?;
        match values.len() == count {
            true => Ok(values),
            false => Err(StateError(format!(
                "`{name}` holds {} values, not {count}",
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

impl StateArrays {
    /// The per-particle arrays of several sets of particles put together: `parts` lists each
    /// set's particle count and arrays (the same names in each, one entry of a fixed number
    /// of values per particle), and particle k of the result is particle `order[k]` of the
    /// sets one after the other.
    ///
    /// # Errors
    /// When a set lacks an array of the first, an array does not hold whole entries, or two
    /// sets' entries differ in size.
    ///
    /// # Panics
    /// If `order` names a particle beyond the sets'.
    pub fn merge(parts: &[(usize, &StateArrays)], order: &[usize]) -> Result<Self, StateError> {
        let Some((_, first)) = parts.first() else {
            return Ok(Self::default());
        };
        let mut merged = Self::default();
        for (name, _) in &first.arrays {
            let mut width = None;
            let mut values: Vec<&[Real]> = Vec::new();
            for &(count, part) in parts {
                let array = part
                    .arrays
                    .iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, v)| v.as_slice())
                    .ok_or_else(|| StateError(format!("`{name}` is missing from a part")))?;
                if let Some(w) = array.len().checked_div(count) {
                    if w == 0 || w * count != array.len() || width.is_some_and(|width| width != w) {
                        return Err(StateError(format!(
                            "`{name}` holds {} values for {count} particles",
                            array.len()
                        )));
                    }
                    width = Some(w);
                    values.extend(array.chunks_exact(w));
                }
            }
            let width = width.unwrap_or(0);
            let mut flat = Vec::with_capacity(order.len() * width);
            for &i in order {
                flat.extend_from_slice(&values[i][..width]);
            }
            merged.arrays.push((name.clone(), flat));
        }
        Ok(merged)
    }
}

/// What a solver's next step depends on besides the particles: see [`crate::Solver`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolverState {
    /// The solver's name ([`crate::Solver::name`]), checked on restore.
    pub method: String,
    /// Steps taken (sorting and re-initialisation schedules count them).
    pub steps: u64,
    /// The solver's arrays that are not per particle.
    pub arrays: StateArrays,
    /// Its arrays of one entry (of a fixed number of values) per particle, in the particles'
    /// order. One rank of a distributed run saves those of the particles it owns, and a
    /// restart puts the ranks' arrays together by particle id ([`StateArrays::merge`]).
    pub per_particle: StateArrays,
    /// The state of its moving walls ([`crate::WallMotion::save_state`]), if it has any.
    pub wall_motion: Option<Vec<u8>>,
    /// The cut of the cells between the ranks of a distributed run (`None` on one process).
    pub partition: Option<PartitionState>,
}

/// How a distributed run's cells were cut between its ranks ([`crate::Distribution`]): a
/// restart on as many ranks cuts them alike.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartitionState {
    /// The first Morton key of each rank after the first
    /// ([`geosph_partition::Partition::cuts`]).
    pub cuts: Vec<u64>,
    /// The imbalance (largest rank's work over the mean) the cut reached.
    pub imbalance: Real,
}

impl SolverState {
    /// An empty state of `method` after `steps` steps.
    pub fn new(method: &str, steps: usize) -> Self {
        Self {
            method: method.to_owned(),
            steps: steps as u64,
            arrays: StateArrays::default(),
            per_particle: StateArrays::default(),
            wall_motion: None,
            partition: None,
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

    #[test]
    fn pieces_merge_by_the_order_given() {
        // Two ranks' pieces: particles 0 and 2 on the first, none then 1 on the second.
        let piece = |velocity: &[Vector<2>], rate: &[Real]| {
            let mut arrays = StateArrays::default();
            arrays.push_matrices("velocity", velocity);
            arrays.push("rate", rate);
            arrays
        };
        let v = |x: Real| Vector::<2>::new(x, -x);
        let first = piece(&[v(0.0), v(2.0)], &[10.0, 12.0]);
        let empty = piece(&[], &[]);
        let second = piece(&[v(1.0)], &[11.0]);
        let parts = [(2, &first), (0, &empty), (1, &second)];
        let mut merged = StateArrays::merge(&parts, &[0, 2, 1]).unwrap();
        assert_eq!(
            merged.take_matrices::<2, 1>("velocity", 3).unwrap(),
            vec![v(0.0), v(1.0), v(2.0)]
        );
        assert_eq!(merged.take("rate").unwrap(), vec![10.0, 11.0, 12.0]);
        let odd = piece(&[v(1.0)], &[11.0, 13.0]);
        let error = StateArrays::merge(&[(2, &first), (1, &odd)], &[0, 2, 1]).unwrap_err();
        assert_eq!(error.0, "`rate` holds 2 values for 1 particles");
    }
}
