//! Predictive–corrective incompressible SPH (Solenthaler & Pajarola 2009).

use geosph_core::{Particles, Real};
use geosph_kernels::Kernel;
use rayon::prelude::*;

use super::iisph::{StopOn, relaxed_jacobi};
use super::{PressureMethod, PressureSolveSettings, PressureSystem, Scratch, SolveReport};
use geosph_sph::lattice::lattice_gradient_squares;

/// PCISPH: starting from p = 0, predict the density, correct every pressure by
///
/// p_i ← max(0, p_i + δ (ρ̃_i − ρ₀)),  δ = ρ₀² / (2 Δt² m² (|Σ_j ∇W_ij|² + Σ_j |∇W_ij|²)),
///
/// with the sums over a *prototype* particle with a filled neighbourhood on the initial
/// lattice, and iterate at least three times until the average error is below the target
/// (Solenthaler & Pajarola 2009, ACM TOG 28(3):40, eqs. 5–8 and Algorithm 1). δ is capped per
/// particle at ρ_i² / (2 Δt² d_i), the IISPH step with ω = ½, where walls make the
/// particle's diagonal d_i larger than the prototype's. Where ½ exceeds
/// [`PressureSystem::relaxation_limit`] (the quintic spline, 3D), the limit takes its place in
/// both: the paper's δ then makes the stiffest lattice mode grow.
///
/// The predicted density ρ̃ is evaluated from the predicted velocities with the continuity
/// equation, ρ̃_i = ρ_i + Δt Σ_j m_j (ṽ_i − ṽ_j)·∇_i W_ij, rather than by a kernel sum at
/// predicted positions with the old neighbour lists: the two agree to first order in Δt, and
/// the first cannot miss a pair that the prediction moved into the support. With that, PCISPH
/// is the fixed-point iteration of IISPH's system with one global step δ instead of the
/// per-particle diagonal, and takes IISPH's choice of [`PressureSource`](super::PressureSource).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pcisph {
    /// m² (|Σ_j ∇W_ij|² + Σ_j |∇W_ij|²) of the prototype particle.
    pub prototype_diagonal: Real,
}

impl Pcisph {
    /// The prototype of a particle of mass `mass` inside a square (cubic) lattice of spacing
    /// `spacing`, filled over the kernel support, where Σ_j ∇W_ij vanishes by symmetry:
    /// m² Σ_j |∇W_ij|² ([`lattice_gradient_squares`]).
    pub fn new<const D: usize, K: Kernel<D>>(kernel: &K, spacing: Real, mass: Real) -> Self {
        Self {
            prototype_diagonal: mass * mass * lattice_gradient_squares(kernel, spacing),
        }
    }
}

impl<const D: usize> PressureMethod<D> for Pcisph {
    const NAME: &'static str = "pcisph";

    fn correct_density<K: Kernel<D>>(
        &mut self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport {
        let pressure = fluid.pressure.as_mut().expect("pressure is enabled");
        pressure.par_iter_mut().for_each(|p| *p = 0.0);
        let rho0 = system.rest_density;
        // δ is the Jacobi step of relaxation ½ on the prototype's diagonal; where ½ exceeds
        // the system's relaxation limit (the quintic spline, 3D), the limit replaces it.
        let relaxation = system.relaxation_limit().min(0.5);
        let delta = relaxation * rho0 * rho0 / (dt * dt * self.prototype_diagonal);
        let settings = PressureSolveSettings {
            min_iterations: settings.min_iterations.max(3),
            ..*settings
        };
        let diagonal = system.diagonal();
        relaxed_jacobi(
            system,
            fluid,
            dt,
            &settings,
            scratch,
            StopOn::Compression,
            |i, rho_i| {
                // Never a larger step than ½ of the particle's own diagonal allows: next to a
                // wall, whose mirrored pressure doubles its share, d_i exceeds the prototype's
                // and the global δ would over-relax.
                if diagonal[i] > 0.0 {
                    delta.min(relaxation * rho_i * rho_i / (dt * dt * diagonal[i]))
                } else {
                    0.0
                }
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Vector;
    use geosph_kernels::WendlandC2;

    #[test]
    fn prototype_sums_match_a_direct_lattice_sum() {
        let (h, dx, mass) = (0.013, 0.01, 0.1);
        let kernel = WendlandC2::<2>::new(h);
        let pcisph = Pcisph::new::<2, _>(&kernel, dx, mass);
        let mut squares = 0.0;
        for a in -5..=5 {
            for b in -5..=5 {
                let r = Vector::<2>::new(a as Real * dx, b as Real * dx);
                squares += Kernel::<2>::gradient(&kernel, &r).norm_squared();
            }
        }
        // On a full symmetric lattice Σ∇W vanishes, leaving m² Σ|∇W|².
        approx::assert_relative_eq!(
            pcisph.prototype_diagonal,
            mass * mass * squares,
            max_relative = 1e-12
        );
    }
}
