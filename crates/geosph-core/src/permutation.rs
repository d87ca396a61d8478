//! Reordering of particles, applied in place to any per-particle field.

/// A reordering of `n` particles: after [`Permutation::apply`], slot `k` holds what slot
/// `order[k]` held before.
///
/// The cycles of the permutation are found once at construction, so applying it to a field is
/// an in-place O(n) walk without allocation, whatever the field's type. Neighbour searches
/// build one to sort particles along a space-filling curve; [`crate::Particles::permute`]
/// applies it to every field that exists.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Permutation {
    order: Vec<u32>,
    cycle_starts: Vec<u32>,
}

/// The order given to [`Permutation::from_order`] is not a permutation of `0..n`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "not a permutation: entry {position} is {value}, which is out of range or repeated (n = {len})"
)]
pub struct NotAPermutation {
    /// Position of the offending entry.
    pub position: usize,
    /// Its value.
    pub value: u32,
    /// Length of the order.
    pub len: usize,
}

impl Permutation {
    /// The identity on `n` particles.
    pub fn identity(n: usize) -> Self {
        Self {
            order: (0..n as u32).collect(),
            cycle_starts: Vec::new(),
        }
    }

    /// The permutation that moves old slot `order[k]` to new slot `k`.
    pub fn from_order(order: Vec<u32>) -> Result<Self, NotAPermutation> {
        let len = order.len();
        let mut seen = vec![false; len];
        for (position, &value) in order.iter().enumerate() {
            let slot = seen.get_mut(value as usize);
            match slot {
                Some(s) if !*s => *s = true,
                _ => {
                    return Err(NotAPermutation {
                        position,
                        value,
                        len,
                    });
                }
            }
        }
        // Every non-trivial cycle is entered once, at its smallest index.
        seen.fill(false);
        let mut cycle_starts = Vec::new();
        for start in 0..len {
            if seen[start] || order[start] as usize == start {
                continue;
            }
            cycle_starts.push(start as u32);
            let mut k = start;
            while !seen[k] {
                seen[k] = true;
                k = order[k] as usize;
            }
        }
        Ok(Self {
            order,
            cycle_starts,
        })
    }

    /// Number of particles it reorders.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Whether it reorders zero particles.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Whether it leaves every particle where it is.
    pub fn is_identity(&self) -> bool {
        self.cycle_starts.is_empty()
    }

    /// `order()[k]` is the old slot of the particle now in slot `k`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Reorders `data` in place: `data[k] ← data_old[order[k]]`.
    ///
    /// # Panics
    /// If `data.len()` differs from the permutation's length.
    pub fn apply<T: Copy>(&self, data: &mut [T]) {
        assert_eq!(
            data.len(),
            self.order.len(),
            "permutation of {} particles applied to a field of {}",
            self.order.len(),
            data.len()
        );
        for &start in &self.cycle_starts {
            let start = start as usize;
            let first = data[start];
            let mut k = start;
            loop {
                let next = self.order[k] as usize;
                if next == start {
                    data[k] = first;
                    break;
                }
                data[k] = data[next];
                k = next;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apply_matches_gather() {
        let order = vec![3, 0, 4, 1, 2, 5, 7, 6];
        let perm = Permutation::from_order(order.clone()).unwrap();
        let old: Vec<u32> = (100..108).collect();
        let mut data = old.clone();
        perm.apply(&mut data);
        let gathered: Vec<u32> = order.iter().map(|&k| old[k as usize]).collect();
        assert_eq!(data, gathered);
        assert!(!perm.is_identity());
        assert!(Permutation::identity(4).is_identity());
    }

    #[test]
    fn rejects_repeats_and_out_of_range() {
        assert_eq!(
            Permutation::from_order(vec![0, 2, 2]).unwrap_err().position,
            2
        );
        assert_eq!(Permutation::from_order(vec![0, 3]).unwrap_err().value, 3);
    }
}
