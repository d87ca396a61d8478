//! Structure-of-arrays particle storage.

use crate::permutation::Permutation;
use crate::types::{Matrix, Real, Tensor3, Vector};

/// The state of elastoplastic soil particles, created only for soil scenes.
#[derive(Debug, Default, PartialEq)]
pub struct SoilFields {
    /// Cauchy stress σ (tension positive), 3×3 also in 2D plane strain.
    pub stress: Vec<Tensor3>,
    /// Accumulated total strain ε.
    pub strain: Vec<Tensor3>,
    /// Accumulated equivalent plastic strain ε̄ᵖ.
    pub plastic_strain: Vec<Real>,
    /// Displacement u = ∫ v dt since the reference state (e.g. the release after a geostatic
    /// stage), 3 components also in 2D (u_z = 0).
    pub displacement: Vec<nalgebra::Vector3<Real>>,
}

impl Clone for SoilFields {
    fn clone(&self) -> Self {
        Self {
            stress: self.stress.clone(),
            strain: self.strain.clone(),
            plastic_strain: self.plastic_strain.clone(),
            displacement: self.displacement.clone(),
        }
    }

    /// Field by field, reusing this set's buffers (no allocation when they are large enough).
    fn clone_from(&mut self, source: &Self) {
        self.stress.clone_from(&source.stress);
        self.strain.clone_from(&source.strain);
        self.plastic_strain.clone_from(&source.plastic_strain);
        self.displacement.clone_from(&source.displacement);
    }
}

impl SoilFields {
    fn zeroed(n: usize) -> Self {
        Self {
            stress: vec![Tensor3::zeros(); n],
            strain: vec![Tensor3::zeros(); n],
            plastic_strain: vec![0.0; n],
            displacement: vec![nalgebra::Vector3::zeros(); n],
        }
    }

    fn permute(&mut self, permutation: &Permutation) {
        permutation.apply(&mut self.stress);
        permutation.apply(&mut self.strain);
        permutation.apply(&mut self.plastic_strain);
        permutation.apply(&mut self.displacement);
    }

    fn retain(&mut self, keep: &[bool]) {
        retain(&mut self.stress, keep);
        retain(&mut self.strain, keep);
        retain(&mut self.plastic_strain, keep);
        retain(&mut self.displacement, keep);
    }
}

/// Keeps the entries `k` of `values` with `keep[k]` and drops the others, keeping the order
/// of those kept; in place, without allocation.
///
/// # Panics
/// If `keep` and `values` differ in length.
pub fn retain<T>(values: &mut Vec<T>, keep: &[bool]) {
    assert_eq!(
        values.len(),
        keep.len(),
        "a mask of {} particles applied to a field of {}",
        keep.len(),
        values.len()
    );
    let mut flags = keep.iter();
    values.retain(|_| flags.next().copied().unwrap_or(false));
}

/// A set of particles in `D` dimensions, one `Vec` per field (structure of arrays).
///
/// Position, velocity, mass, density and a persistent `id` always exist. The optional groups
/// exist only when a solver or model asks for them ([`Particles::enable_pressure`],
/// [`Particles::enable_soil`], [`Particles::enable_gradient_correction`]), so a fluid scene
/// never allocates stress tensors. [`Particles::permute`] reorders every field that exists,
/// [`Particles::retain`] removes particles from every field that exists.
///
/// `clone_from` copies field by field into the existing buffers, so a copy refreshed every
/// step (the runner's last good state) allocates only once.
#[derive(Debug, Default, PartialEq)]
pub struct Particles<const D: usize> {
    /// Positions x.
    pub position: Vec<Vector<D>>,
    /// Velocities v.
    pub velocity: Vec<Vector<D>>,
    /// Masses m (constant in time).
    pub mass: Vec<Real>,
    /// Densities ρ.
    pub density: Vec<Real>,
    /// Creation index of each particle; unchanged by reordering, used to label output.
    pub id: Vec<u32>,
    /// Pressure p, for fluid solvers.
    pub pressure: Option<Vec<Real>>,
    /// Specific internal energy e in J/kg, for a gas (a fluid whose pressure depends on its
    /// energy as well as its density).
    pub energy: Option<Vec<Real>>,
    /// Stress, strain and plastic strain, for soil models.
    pub soil: Option<SoilFields>,
    /// Kernel-gradient correction matrices L_i (CSPM), when a correction is switched on.
    pub gradient_correction: Option<Vec<Matrix<D>>>,
}

impl<const D: usize> Clone for Particles<D> {
    fn clone(&self) -> Self {
        Self {
            position: self.position.clone(),
            velocity: self.velocity.clone(),
            mass: self.mass.clone(),
            density: self.density.clone(),
            id: self.id.clone(),
            pressure: self.pressure.clone(),
            energy: self.energy.clone(),
            soil: self.soil.clone(),
            gradient_correction: self.gradient_correction.clone(),
        }
    }

    /// Field by field, reusing this set's buffers (`Vec::clone_from`, `Option::clone_from`):
    /// no allocation when they are large enough, unlike the derived `*self = source.clone()`.
    fn clone_from(&mut self, source: &Self) {
        self.position.clone_from(&source.position);
        self.velocity.clone_from(&source.velocity);
        self.mass.clone_from(&source.mass);
        self.density.clone_from(&source.density);
        self.id.clone_from(&source.id);
        self.pressure.clone_from(&source.pressure);
        self.energy.clone_from(&source.energy);
        self.soil.clone_from(&source.soil);
        self.gradient_correction
            .clone_from(&source.gradient_correction);
    }
}

impl<const D: usize> Particles<D> {
    /// Particles at rest at `position`, each of mass `mass` and density `density`.
    pub fn at_rest(position: Vec<Vector<D>>, mass: Real, density: Real) -> Self {
        let n = position.len();
        Self {
            velocity: vec![Vector::zeros(); n],
            mass: vec![mass; n],
            density: vec![density; n],
            id: (0..n as u32).collect(),
            position,
            pressure: None,
            energy: None,
            soil: None,
            gradient_correction: None,
        }
    }

    /// Number of particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are no particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Creates the pressure field (zero) if it does not exist yet and returns it.
    pub fn enable_pressure(&mut self) -> &mut Vec<Real> {
        let n = self.len();
        self.pressure.get_or_insert_with(|| vec![0.0; n])
    }

    /// Creates the internal-energy field (zero) if it does not exist yet and returns it.
    pub fn enable_energy(&mut self) -> &mut Vec<Real> {
        let n = self.len();
        self.energy.get_or_insert_with(|| vec![0.0; n])
    }

    /// Creates the soil fields (zero stress and strain) if they do not exist yet.
    pub fn enable_soil(&mut self) -> &mut SoilFields {
        let n = self.len();
        self.soil.get_or_insert_with(|| SoilFields::zeroed(n))
    }

    /// Creates the gradient-correction matrices (identity) if they do not exist yet.
    pub fn enable_gradient_correction(&mut self) -> &mut Vec<Matrix<D>> {
        let n = self.len();
        self.gradient_correction
            .get_or_insert_with(|| vec![Matrix::identity(); n])
    }

    /// Reorders every existing field with `permutation`.
    ///
    /// # Panics
    /// If the permutation's length differs from the number of particles.
    pub fn permute(&mut self, permutation: &Permutation) {
        permutation.apply(&mut self.position);
        permutation.apply(&mut self.velocity);
        permutation.apply(&mut self.mass);
        permutation.apply(&mut self.density);
        permutation.apply(&mut self.id);
        if let Some(pressure) = &mut self.pressure {
            permutation.apply(pressure);
        }
        if let Some(energy) = &mut self.energy {
            permutation.apply(energy);
        }
        if let Some(soil) = &mut self.soil {
            soil.permute(permutation);
        }
        if let Some(correction) = &mut self.gradient_correction {
            permutation.apply(correction);
        }
    }

    /// Keeps the particles `k` with `keep[k]` in every existing field and drops the others
    /// (e.g. particles that left the domain), keeping the order of those kept; in place,
    /// without allocation.
    ///
    /// # Panics
    /// If `keep` and the particles differ in length.
    pub fn retain(&mut self, keep: &[bool]) {
        retain(&mut self.position, keep);
        retain(&mut self.velocity, keep);
        retain(&mut self.mass, keep);
        retain(&mut self.density, keep);
        retain(&mut self.id, keep);
        if let Some(pressure) = &mut self.pressure {
            retain(pressure, keep);
        }
        if let Some(energy) = &mut self.energy {
            retain(energy, keep);
        }
        if let Some(soil) = &mut self.soil {
            soil.retain(keep);
        }
        if let Some(correction) = &mut self.gradient_correction {
            retain(correction, keep);
        }
    }

    /// Bytes held per particle by the fields that exist (capacity, not length).
    pub fn bytes_per_particle(&self) -> usize {
        fn bytes<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let mut total = bytes(&self.position)
            + bytes(&self.velocity)
            + bytes(&self.mass)
            + bytes(&self.density)
            + bytes(&self.id);
        total += self.pressure.as_ref().map_or(0, bytes);
        total += self.energy.as_ref().map_or(0, bytes);
        total += self.gradient_correction.as_ref().map_or(0, bytes);
        if let Some(soil) = &self.soil {
            total += bytes(&soil.stress)
                + bytes(&soil.strain)
                + bytes(&soil.plastic_strain)
                + bytes(&soil.displacement);
        }
        total / self.len().max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize) -> Particles<2> {
        let position = (0..n).map(|i| Vector::<2>::new(i as Real, 0.0)).collect();
        Particles::at_rest(position, 1.0, 1000.0)
    }

    #[test]
    fn fluid_particles_carry_no_soil_fields() {
        let mut fluid = line(10);
        fluid.enable_pressure();
        assert!(fluid.soil.is_none());
        // position + velocity (2 × 16) + mass + density (2 × 8) + id (4) + pressure (8)
        assert_eq!(fluid.bytes_per_particle(), 32 + 16 + 4 + 8);
        let mut soil = line(10);
        soil.enable_soil();
        // no pressure; stress and strain (2 × 72) + plastic strain (8) + displacement (24)
        assert_eq!(soil.bytes_per_particle(), 52 + 2 * 72 + 8 + 24);
    }

    #[test]
    fn clone_from_reuses_the_buffers() {
        let mut source = line(8);
        source.enable_pressure();
        source.enable_soil();
        let mut copy = source.clone();
        let buffers = |p: &Particles<2>| {
            (
                p.position.as_ptr() as usize,
                p.pressure.as_ref().unwrap().as_ptr() as usize,
                p.soil.as_ref().unwrap().stress.as_ptr() as usize,
            )
        };
        let before = buffers(&copy);
        source.velocity[3] = Vector::<2>::new(1.0, -2.0);
        source.soil.as_mut().unwrap().stress[5][(1, 1)] = -7.0;
        copy.clone_from(&source);
        assert_eq!(copy, source);
        assert_eq!(buffers(&copy), before);
    }

    #[test]
    fn retain_drops_the_same_particles_from_every_field() {
        let mut particles = line(5);
        particles.enable_pressure();
        particles.enable_soil();
        particles.enable_gradient_correction();
        for i in 0..5 {
            particles.pressure.as_mut().unwrap()[i] = 10.0 * i as Real;
            particles.soil.as_mut().unwrap().plastic_strain[i] = i as Real;
            particles.gradient_correction.as_mut().unwrap()[i][(0, 0)] = i as Real;
        }
        particles.retain(&[true, false, true, true, false]);
        assert_eq!(particles.id, [0, 2, 3]);
        for (k, &id) in particles.id.iter().enumerate() {
            let i = id as Real;
            assert_eq!(particles.position[k][0], i);
            assert_eq!(particles.pressure.as_ref().unwrap()[k], 10.0 * i);
            assert_eq!(particles.soil.as_ref().unwrap().plastic_strain[k], i);
            assert_eq!(
                particles.gradient_correction.as_ref().unwrap()[k][(0, 0)],
                i
            );
        }
        assert_eq!(particles.velocity.len(), 3);
        assert_eq!(particles.mass.len(), 3);
        assert_eq!(particles.density.len(), 3);
        let soil = particles.soil.as_ref().unwrap();
        assert_eq!(
            (
                soil.stress.len(),
                soil.strain.len(),
                soil.displacement.len()
            ),
            (3, 3, 3)
        );
    }

    #[test]
    fn permute_keeps_fields_together() {
        let mut particles = line(6);
        particles.enable_pressure();
        particles.enable_soil();
        for i in 0..6 {
            particles.velocity[i] = Vector::<2>::new(0.0, i as Real);
            particles.pressure.as_mut().unwrap()[i] = 10.0 * i as Real;
            particles.soil.as_mut().unwrap().stress[i][(0, 1)] = -(i as Real);
        }
        let permutation = Permutation::from_order(vec![5, 3, 1, 0, 2, 4]).unwrap();
        particles.permute(&permutation);
        for k in 0..6 {
            let i = particles.id[k] as Real;
            assert_eq!(particles.position[k][0], i);
            assert_eq!(particles.velocity[k][1], i);
            assert_eq!(particles.pressure.as_ref().unwrap()[k], 10.0 * i);
            assert_eq!(particles.soil.as_ref().unwrap().stress[k][(0, 1)], -i);
        }
    }
}
