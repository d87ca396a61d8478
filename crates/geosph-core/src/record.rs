//! Particles as flat records of numbers, to be sent between the ranks of a distributed run:
//! every field that exists, in a fixed order, as `Real`s.

use crate::particles::Particles;
use crate::permutation::Permutation;
use crate::types::{Matrix, Real, Tensor3, Vector};

/// Appends the components of `values` to `record`.
fn push(record: &mut Vec<Real>, values: &[Real]) {
    record.extend_from_slice(values);
}

/// Reads the next `out.len()` values of `record` from `at` into `out`.
fn take(record: &[Real], at: &mut usize, out: &mut [Real]) {
    out.copy_from_slice(&record[*at..*at + out.len()]);
    *at += out.len();
}

/// Per-particle state that travels with its particles when they change rank and is reordered
/// with them: the particles' own fields, and what a solver keeps of each particle between
/// steps (an integrator's cached rates).
pub trait PerParticle {
    /// Values in the record of one particle.
    fn record_width(&self) -> usize;
    /// Appends the record of particle `i`.
    fn pack(&self, i: usize, record: &mut Vec<Real>);
    /// Writes a record packed by [`PerParticle::pack`] into particle `i`.
    fn unpack(&mut self, i: usize, record: &[Real]);
    /// Makes the state `n` particles long (new entries zero).
    fn resize(&mut self, n: usize);
    /// Keeps the particles `k` with `keep[k]`, in order.
    fn retain(&mut self, keep: &[bool]);
    /// Reorders the particles.
    fn permute(&mut self, permutation: &Permutation);
}

impl<const D: usize> PerParticle for Particles<D> {
    fn record_width(&self) -> usize {
        Particles::record_width(self)
    }

    fn pack(&self, i: usize, record: &mut Vec<Real>) {
        Particles::pack(self, i, record);
    }

    fn unpack(&mut self, i: usize, record: &[Real]) {
        Particles::unpack(self, i, record);
    }

    fn resize(&mut self, n: usize) {
        Particles::resize(self, n);
    }

    fn retain(&mut self, keep: &[bool]) {
        Particles::retain(self, keep);
    }

    fn permute(&mut self, permutation: &Permutation) {
        Particles::permute(self, permutation);
    }
}

/// One vector per particle (a solver's accelerations of the last step).
impl<const D: usize> PerParticle for Vec<Vector<D>> {
    fn record_width(&self) -> usize {
        D
    }

    fn pack(&self, i: usize, record: &mut Vec<Real>) {
        push(record, self[i].as_slice());
    }

    fn unpack(&mut self, i: usize, record: &[Real]) {
        self[i].as_mut_slice().copy_from_slice(&record[..D]);
    }

    fn resize(&mut self, n: usize) {
        Vec::resize(self, n, Vector::zeros());
    }

    fn retain(&mut self, keep: &[bool]) {
        crate::particles::retain(self, keep);
    }

    fn permute(&mut self, permutation: &Permutation) {
        permutation.apply(self);
    }
}

impl<const D: usize> Particles<D> {
    /// Values in the record of one particle: position, velocity, mass, density, id and every
    /// optional field that exists ([`Particles::pack`]).
    pub fn record_width(&self) -> usize {
        let mut width = 2 * D + 3;
        width += usize::from(self.pressure.is_some());
        width += usize::from(self.energy.is_some());
        width += self.soil.as_ref().map_or(0, |_| 9 + 9 + 1 + 3);
        width += self.gradient_correction.as_ref().map_or(0, |_| D * D);
        width
    }

    /// Appends the record of particle `i` ([`Particles::record_width`] values; the id is exact
    /// as a `Real`).
    pub fn pack(&self, i: usize, record: &mut Vec<Real>) {
        push(record, self.position[i].as_slice());
        push(record, self.velocity[i].as_slice());
        push(
            record,
            &[self.mass[i], self.density[i], Real::from(self.id[i])],
        );
        if let Some(pressure) = &self.pressure {
            record.push(pressure[i]);
        }
        if let Some(energy) = &self.energy {
            record.push(energy[i]);
        }
        if let Some(soil) = &self.soil {
            push(record, soil.stress[i].as_slice());
            push(record, soil.strain[i].as_slice());
            record.push(soil.plastic_strain[i]);
            push(record, soil.displacement[i].as_slice());
        }
        if let Some(correction) = &self.gradient_correction {
            push(record, correction[i].as_slice());
        }
    }

    /// Writes the record `record`, packed by [`Particles::pack`] from particles with the same
    /// fields, into particle `i`.
    ///
    /// # Panics
    /// If the record is shorter than [`Particles::record_width`].
    pub fn unpack(&mut self, i: usize, record: &[Real]) {
        let at = &mut 0;
        take(record, at, self.position[i].as_mut_slice());
        take(record, at, self.velocity[i].as_mut_slice());
        let mut scalars = [0.0; 3];
        take(record, at, &mut scalars);
        let [mass, density, id] = scalars;
        (self.mass[i], self.density[i], self.id[i]) = (mass, density, id as u32);
        if let Some(pressure) = &mut self.pressure {
            take(record, at, std::slice::from_mut(&mut pressure[i]));
        }
        if let Some(energy) = &mut self.energy {
            take(record, at, std::slice::from_mut(&mut energy[i]));
        }
        if let Some(soil) = &mut self.soil {
            take(record, at, soil.stress[i].as_mut_slice());
            take(record, at, soil.strain[i].as_mut_slice());
            take(
                record,
                at,
                std::slice::from_mut(&mut soil.plastic_strain[i]),
            );
            take(record, at, soil.displacement[i].as_mut_slice());
        }
        if let Some(correction) = &mut self.gradient_correction {
            take(record, at, correction[i].as_mut_slice());
        }
    }

    /// Makes every existing field `n` long: drops the particles from `n` on, or appends
    /// particles at the origin with zero fields (to be overwritten by [`Particles::unpack`]).
    pub fn resize(&mut self, n: usize) {
        self.position.resize(n, Vector::zeros());
        self.velocity.resize(n, Vector::zeros());
        self.mass.resize(n, 0.0);
        self.density.resize(n, 0.0);
        self.id.resize(n, 0);
        if let Some(pressure) = &mut self.pressure {
            pressure.resize(n, 0.0);
        }
        if let Some(energy) = &mut self.energy {
            energy.resize(n, 0.0);
        }
        if let Some(soil) = &mut self.soil {
            soil.stress.resize(n, Tensor3::zeros());
            soil.strain.resize(n, Tensor3::zeros());
            soil.plastic_strain.resize(n, 0.0);
            soil.displacement.resize(n, nalgebra::Vector3::zeros());
        }
        if let Some(correction) = &mut self.gradient_correction {
            correction.resize(n, Matrix::zeros());
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{Particles, Vector};

    /// A record carries every field that exists, bit for bit.
    #[test]
    fn records_round_trip_every_field() {
        let position = vec![Vector::<2>::new(0.1, 0.2), Vector::<2>::new(0.3, 0.4)];
        let mut particles = Particles::at_rest(position, 0.5, 1000.0);
        particles.enable_pressure()[1] = 123.0;
        particles.enable_soil().stress[1][(0, 1)] = -7.0;
        particles.enable_gradient_correction()[1][(1, 0)] = 0.25;
        particles.velocity[1] = Vector::<2>::new(1.0 / 3.0, -2.0);
        particles.id[1] = 4_000_000_000;
        let mut record = Vec::new();
        particles.pack(1, &mut record);
        assert_eq!(record.len(), particles.record_width());
        let mut copy = particles.clone();
        copy.resize(3);
        copy.unpack(2, &record);
        let mut again = Vec::new();
        copy.pack(2, &mut again);
        assert_eq!(again, record);
        copy.resize(2);
        assert_eq!(copy, particles);
        copy.unpack(0, &record);
        assert_eq!(copy.soil.as_ref().unwrap().stress[0][(0, 1)], -7.0);
        assert_eq!(copy.id, vec![4_000_000_000, 4_000_000_000]);
    }
}
