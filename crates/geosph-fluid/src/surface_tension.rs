//! Surface tension between two phases of one fluid: the continuum surface force (CSF) of
//! Brackbill, Kothe & Zemach (1992, J. Comput. Phys. 100:335) with a colour function, its
//! curvature the divergence of the unit normals renormalised over the neighbours that have
//! one, after Adami, Hu & Adams (2010, J. Comput. Phys. 229:5011).
//!
//! Each particle has a colour c ∈ {0, 1}: 1 in the blocks the scene names (e.g. a drop), 0 in
//! the others (the fluid around it). Per rate evaluation, in two gather passes:
//!
//! 1. the colour gradient n_i = g Σ_j V_j (c_j − c_i) ∇_i W_ij, which points into the
//!    phase of colour 1 and whose integral across the interface is 1 (g the lattice gradient
//!    correction of the pressure term, so that this holds on the initial lattice);
//! 2. where the normal is reliable, |n_i| h > ε (Morris 2000, IJNMF 33:333), the
//!    curvature κ_i = −∇·n̂_i = −tr(G_i M_i⁻¹) with
//!
//!    G_i = Σ_j V_j (n̂_j − n̂_i) ⊗ ∇_i W_ij,   M_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij
//!
//!    over the neighbours j with reliable normals: M_i⁻¹ makes the gradient of a linear field
//!    exact whatever neighbours are left out (the renormalisation of Randles & Libersky 1996).
//!    Adami et al. (2010) divide by the trace of M_i instead, which is exact for an isotropic
//!    field only: the band of reliable normals is thin across the interface, and that
//!    quotient overestimates the curvature of a lattice disc by 6 % (the unit test). The
//!    acceleration is
//!
//!    a_i = σ κ_i n_i / ρ_i,
//!
//!    the force per unit volume σ κ δ_s n̂ of the CSF with the surface delta δ_s n̂ = ∇c.
//!
//! Across a circular interface of radius R (2D) the force integrates to the Laplace jump
//! p_in − p_out = σ/R (σ · 2/R in 3D). The explicit step must resolve the capillary waves of
//! the particle scale: Δt ≤ 0.25 √(ρ h³ / (2π σ)) (Brackbill et al. 1992, eq. 61).
//! `docs/surface-tension.md` has the derivation and the checks.

use std::ops::Range;

use geosph_core::{Domain, Matrix, Particles, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::CellGrid;
use geosph_sph::PairLists;
use geosph_sph::config_error::{ConfigError, in_range};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The scene's surface tension: a coefficient and the blocks of the phase of colour 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceTensionConfig {
    /// Surface tension coefficient σ in N/m (0.0728 for water against air at 20 °C).
    pub coefficient: Real,
    /// The fluid blocks (indices into `fluid.blocks`) of one phase, e.g. a drop; the other
    /// blocks are the phase around it. A particle belongs to the first block that holds its
    /// site.
    pub blocks: Vec<usize>,
    /// Threshold ε of a reliable normal, |n| h > ε (default 0.01, Morris 2000).
    #[serde(default = "default_threshold")]
    pub normal_threshold: Real,
}

fn default_threshold() -> Real {
    0.01
}

impl SurfaceTensionConfig {
    /// Checks the coefficient (finite, > 0), the threshold (in [1e-4, 0.5]) and that some
    /// block is named; `field` is the block's name in the scene. The blocks' indices are the
    /// scene's to check.
    pub fn validate(&self, field: &str) -> Result<(), ConfigError> {
        if !(self.coefficient.is_finite() && self.coefficient > 0.0) {
            return Err(ConfigError::new(
                format!("{field}.coefficient"),
                format!(
                    "must be a finite number > 0 N/m (water–air: 0.0728), got {}",
                    self.coefficient
                ),
            ));
        }
        if self.blocks.is_empty() {
            return Err(ConfigError::new(
                format!("{field}.blocks"),
                "must name the blocks of one phase (e.g. `[0]` for a drop that is block 0)",
            ));
        }
        in_range(
            &format!("{field}.normal_threshold"),
            self.normal_threshold,
            1e-4,
            0.5,
        )
    }
}

/// The CSF of one rate evaluation, with its per-particle scratch.
#[derive(Clone, Debug)]
pub struct SurfaceTension<const D: usize> {
    /// σ in N/m.
    pub coefficient: Real,
    /// ε of a reliable normal, |n| h > ε.
    pub normal_threshold: Real,
    /// The colour of each particle id (1 or 0).
    colour_of_id: Vec<Real>,
    /// c_i of every particle in the current order.
    colour: Vec<Real>,
    /// n_i = ∇c_i of every particle.
    normal: Vec<Vector<D>>,
    /// n̂_i where the normal is reliable, else zero.
    unit_normal: Vec<Vector<D>>,
}

impl<const D: usize> SurfaceTension<D> {
    /// The force of `config` for particles whose ids the fluid blocks hold in `block_ids`
    /// (block k's particles have the ids `block_ids[k]`).
    ///
    /// # Panics
    /// If `config` names a block that `block_ids` does not have (a scene checks that).
    pub fn new(config: &SurfaceTensionConfig, block_ids: &[Range<u32>]) -> Self {
        let count = block_ids.iter().map(|ids| ids.end).max().unwrap_or(0);
        let mut colour_of_id = vec![0.0; count as usize];
        for &block in &config.blocks {
            for id in block_ids[block].clone() {
                colour_of_id[id as usize] = 1.0;
            }
        }
        Self {
            coefficient: config.coefficient,
            normal_threshold: config.normal_threshold,
            colour_of_id,
            colour: Vec::new(),
            normal: Vec::new(),
            unit_normal: Vec::new(),
        }
    }

    /// The capillary limit of the explicit step for the lighter phase's density `density`
    /// and smoothing length `h`: 0.25 √(ρ h³ / (2π σ)) (Brackbill et al. 1992, eq. 61).
    pub fn time_step_limit(&self, density: Real, h: Real) -> Real {
        0.25 * (density * h.powi(3) / (2.0 * std::f64::consts::PI * self.coefficient)).sqrt()
    }

    /// The interface's length (2D) or area (3D) between the phases of `fluid`, Σ_i V_i |n_i|
    /// with V_i = m_i/ρ_i and n_i the colour gradient with the lattice gradient correction
    /// `correction`, from a search of its own (a run's budget of surface energy σ L; the
    /// particles need not have been listed yet).
    ///
    /// # Panics
    /// If `domain` cannot hold a grid of the kernel's support or a particle lies outside it.
    pub fn interface_measure<K: Kernel<D>>(
        &self,
        kernel: &K,
        domain: &Domain<D>,
        fluid: &Particles<D>,
        correction: Real,
    ) -> Real {
        let radius = kernel.support_radius();
        let mut grid = CellGrid::fitting(domain.clone(), radius).expect("the run's domain");
        grid.build(&fluid.position)
            .expect("the particles lie in the run's domain");
        let colour = |i: usize| self.colour_of_id[fluid.id[i] as usize];
        let volume = |i: usize| fluid.mass[i] / fluid.density[i];
        (0..fluid.len())
            .into_par_iter()
            .map(|i| {
                let mut sum = Vector::<D>::zeros();
                grid.for_each_neighbour(&fluid.position, &fluid.position[i], |j, r_ij, r| {
                    let j = j as usize;
                    if j != i && r < radius {
                        sum += r_ij
                            * (kernel.gradient_factor(r) * volume(j) * (colour(j) - colour(i)));
                    }
                });
                volume(i) * correction * sum.norm()
            })
            .sum()
    }

    /// Adds σ κ_i n_i / ρ_i to `acceleration` of every particle of `fluid`, with the
    /// particles' volumes `volume` = m/ρ and the lattice gradient correction `correction`.
    ///
    /// # Panics
    /// If a particle's id is not one of the scene's blocks.
    pub fn add_acceleration<K: Kernel<D>>(
        &mut self,
        kernel: &K,
        lists: &PairLists<D>,
        fluid: &Particles<D>,
        volume: &[Real],
        correction: Real,
        acceleration: &mut [Vector<D>],
    ) {
        let position = &fluid.position;
        let colour_of_id = &self.colour_of_id;
        self.colour.resize(fluid.len(), 0.0);
        self.colour
            .par_iter_mut()
            .zip(fluid.id.par_iter())
            .for_each(|(c, &id)| *c = colour_of_id[id as usize]);
        let colour = &self.colour;
        self.normal.resize(fluid.len(), Vector::zeros());
        self.unit_normal.resize(fluid.len(), Vector::zeros());
        let reliable = self.normal_threshold / kernel.smoothing_length();
        self.normal
            .par_iter_mut()
            .zip(self.unit_normal.par_iter_mut())
            .enumerate()
            .for_each(|(i, (n_i, unit_i))| {
                // Inside one phase the sum is zero: a scan of the listed colours, with no
                // kernel evaluated, finds most particles there.
                let c_i = colour[i];
                let listed = lists.inner().neighbours(i);
                if listed.iter().all(|&j| colour[j as usize] == c_i) {
                    *n_i = Vector::zeros();
                    *unit_i = Vector::zeros();
                    return;
                }
                let mut sum = Vector::<D>::zeros();
                lists.for_each_neighbour(kernel, position, i, |pair| {
                    let j = pair.index;
                    sum += pair.grad * (volume[j] * (colour[j] - c_i));
                });
                *n_i = sum * correction;
                let length = n_i.norm();
                *unit_i = if length > reliable {
                    *n_i / length
                } else {
                    Vector::zeros()
                };
            });
        let (normal, unit_normal) = (&self.normal, &self.unit_normal);
        // A unit normal is zero where the normal is unreliable.
        let is_reliable = |n: &Vector<D>| n.norm_squared() > 0.5;
        let sigma = self.coefficient;
        acceleration
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, a_i)| {
                let unit_i = unit_normal[i];
                if !is_reliable(&unit_i) {
                    return;
                }
                let mut change = Matrix::<D>::zeros();
                let mut moment = Matrix::<D>::zeros();
                lists.for_each_neighbour(kernel, position, i, |pair| {
                    let j = pair.index;
                    let unit_j = unit_normal[j];
                    if is_reliable(&unit_j) {
                        let weighted = (pair.grad * volume[j]).transpose();
                        change += (unit_j - unit_i) * weighted;
                        moment -= pair.r_ij * weighted;
                    }
                });
                if let Some(inverse) = moment.try_inverse() {
                    let curvature = -(change * inverse).trace();
                    *a_i += normal[i] * (sigma * curvature / fluid.density[i]);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_kernels::WendlandC2;

    type Disc = (Particles<2>, SurfaceTension<2>, PairLists<2>, WendlandC2<2>);

    /// A disc of radius `radius` of colour 1 in a periodic unit square of colour 0, on a
    /// lattice of spacing `dx`, with h = 2 dx.
    fn disc(dx: Real, radius: Real) -> Disc {
        let count = (1.0 / dx).round() as usize;
        let centre = Vector::<2>::repeat(0.5);
        let (mut inside, mut outside) = (Vec::new(), Vec::new());
        for a in 0..count {
            for b in 0..count {
                let x = Vector::<2>::new((a as Real + 0.5) * dx, (b as Real + 0.5) * dx);
                if (x - centre).norm() < radius {
                    inside.push(x);
                } else {
                    outside.push(x);
                }
            }
        }
        let (drop, total) = (inside.len() as u32, (inside.len() + outside.len()) as u32);
        inside.extend(outside);
        let fluid = Particles::at_rest(inside, dx * dx, 1.0);
        let config = SurfaceTensionConfig {
            coefficient: 1.0,
            blocks: vec![0],
            normal_threshold: default_threshold(),
        };
        let kernel = WendlandC2::<2>::new(2.0 * dx);
        let domain = Domain::with_periodic(Vector::zeros(), Vector::repeat(1.0), [true, true])
            .expect("a box");
        let mut lists =
            PairLists::new(domain, kernel.support_radius(), 0.0, &[], false).expect("lists");
        let mut position = fluid.position.clone();
        lists.update(&mut position, &[]).expect("a search");
        let tension = SurfaceTension::new(&config, &[0..drop, drop..total]);
        (fluid, tension, lists, kernel)
    }

    /// The force on a disc of radius R pushes inward and integrates to the Laplace jump:
    /// Σ_i V_i f_i·r̂_i = ∫ f·r̂ dA = −σ/R · 2πR = −2πσ, within 5 %; its net force is nil.
    #[test]
    fn the_force_on_a_disc_integrates_to_the_laplace_jump() {
        let (dx, radius) = (0.01, 0.25);
        let (fluid, mut tension, lists, kernel) = disc(dx, radius);
        let volume = vec![dx * dx; fluid.len()];
        let mut acceleration = vec![Vector::<2>::zeros(); fluid.len()];
        tension.add_acceleration(&kernel, &lists, &fluid, &volume, 1.0, &mut acceleration);
        let centre = Vector::<2>::repeat(0.5);
        let (mut radial, mut net) = (0.0, Vector::<2>::zeros());
        for i in 0..fluid.len() {
            let r = fluid.position[i] - centre;
            let force = acceleration[i] * (volume[i] * fluid.density[i]);
            radial += force.dot(&(r / r.norm()));
            net += force;
        }
        let expected = -2.0 * std::f64::consts::PI;
        assert!(
            (radial / expected - 1.0).abs() < 0.05,
            "∫ f·r̂ dA = {radial}, expected {expected}"
        );
        assert!(net.norm() < 1e-9 * radial.abs(), "net force {net}");
        let length = tension.interface_measure(&kernel, lists.domain(), &fluid, 1.0);
        let circumference = 2.0 * std::f64::consts::PI * radius;
        assert!(
            (length / circumference - 1.0).abs() < 0.02,
            "interface {length} m, circumference {circumference} m"
        );
    }
}
