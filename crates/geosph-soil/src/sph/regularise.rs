//! Stress regularisation (Nguyen et al. 2017, Eng. Geol. 225:65): every N steps the stress
//! of each particle is replaced by its kernel average over the soil neighbours,
//!
//! ⟨σ_i⟩ = Σ_j V_j σ_j W̃_ij,
//!
//! with W̃ the Shepard kernel W_ij / Σ_k V_k W_ik (zeroth order, a convex combination: a stress
//! field inside the convex Drucker–Prager cone stays inside) or the linear MLS kernel
//! (β₀ + β·r_ij) W_ij of Dilts (1999) as Nguyen et al. (2017) use it (first order; its weights
//! may be negative, so a few states can end slightly outside the cone until the next update).

use geosph_core::{Domain, NeighbourList, Particles, Real, Tensor3};
use geosph_kernels::mls::mls_coefficients;
use geosph_kernels::shepard::shepard_sums;
use geosph_kernels::{Kernel, MlsCoefficients};
use rayon::prelude::*;

use crate::sph::system::SoilSystem;

/// Work arrays of the regularisation, kept between calls so no step allocates.
#[derive(Clone, Debug, Default)]
pub struct RegularisationScratch<const D: usize> {
    volume: Vec<Real>,
    sums: Vec<Real>,
    coefficients: Vec<MlsCoefficients<D>>,
    stress: Vec<Tensor3>,
}

/// Replaces σ_i by ⟨σ_i⟩ (MLS kernel if `mls`, else Shepard) over the soil neighbour list of
/// the last step.
pub fn regularise_stress<const D: usize, K: Kernel<D>>(
    system: &SoilSystem<D, K>,
    soil: &mut Particles<D>,
    mls: bool,
    scratch: &mut RegularisationScratch<D>,
) {
    let (domain, list) = (system.lists.domain(), system.lists.inner());
    let smoothed = smooth_stress(&system.kernel, domain, list, soil, mls, scratch);
    soil.soil
        .as_mut()
        .expect("soil particles carry soil fields")
        .stress
        .copy_from_slice(smoothed);
}

/// ⟨σ_i⟩ of every particle of `soil` over `list` (its own neighbours, self-pair included) with
/// the MLS kernel if `mls`, else Shepard; the result lives in `scratch`.
pub(crate) fn smooth_stress<'s, const D: usize, K: Kernel<D>>(
    kernel: &K,
    domain: &Domain<D>,
    list: &NeighbourList,
    soil: &Particles<D>,
    mls: bool,
    scratch: &'s mut RegularisationScratch<D>,
) -> &'s [Tensor3] {
    let n = soil.len();
    scratch.volume.clear();
    scratch
        .volume
        .extend(soil.mass.iter().zip(&soil.density).map(|(m, rho)| m / rho));
    scratch.coefficients.resize(n, MlsCoefficients::default());
    if mls {
        mls_coefficients(
            kernel,
            domain,
            &soil.position,
            &scratch.volume,
            list,
            &mut scratch.coefficients,
        );
    } else {
        scratch.sums.resize(n, 0.0);
        shepard_sums(
            kernel,
            domain,
            &soil.position,
            &scratch.volume,
            list,
            &mut scratch.sums,
        );
        scratch
            .coefficients
            .par_iter_mut()
            .zip(scratch.sums.par_iter())
            .for_each(|(c, &sum)| *c = MlsCoefficients::shepard(sum));
    }
    let fields = soil
        .soil
        .as_ref()
        .expect("soil particles carry soil fields");
    scratch.stress.resize(n, Tensor3::zeros());
    let (position, volume, coefficients, stress) = (
        &soil.position,
        &scratch.volume,
        &scratch.coefficients,
        &fields.stress,
    );
    scratch
        .stress
        .par_iter_mut()
        .enumerate()
        .for_each(|(i, smoothed)| {
            let mut sum = Tensor3::zeros();
            for &j in list.neighbours(i) {
                let j = j as usize;
                let r_ij = domain.displacement(&position[i], &position[j]);
                let w = coefficients[i].corrected(&r_ij, kernel.value(r_ij.norm()));
                sum += stress[j] * (volume[j] * w);
            }
            *smoothed = sum;
        });
    &scratch.stress
}
