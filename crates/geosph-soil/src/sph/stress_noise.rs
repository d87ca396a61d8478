//! A measure of the checkerboard (hourglass) noise in the stress field: how far each particle's
//! stress stands from the linear field its neighbours describe,
//!
//! η = √( Σ_i ‖σ_i − ⟨σ_i⟩‖² / Σ_i ‖σ_i‖² ),
//!
//! with ‖·‖ the Frobenius norm and ⟨σ_i⟩ = Σ_j V_j σ_j W^MLS_ij the linear moving-least-squares
//! fit over the particle's neighbours (Dilts 1999; the kernel of the `Mls` regularisation,
//! `crate::sph::regularise`). The fit reproduces linear fields exactly, also at a free surface,
//! so a smooth stress (gravity's linear σ_v, a smooth flow) gives η ≈ 0 up to its curvature,
//! while a pattern that alternates from particle to particle with amplitude a on a field of
//! scale S gives η ≈ a/S. The measure uses its own neighbour search (Wendland C2, h = 1.3 dx),
//! so it does not depend on the solver's kernel or lists and can run on any saved state.

use geosph_core::{Domain, NeighbourList, Particles, Real, Vector};
use geosph_kernels::{Kernel, WendlandC2};
use geosph_neighbours::CellGrid;

use crate::sph::regularise::{RegularisationScratch, smooth_stress};

/// η of `soil` on a lattice of spacing `spacing` (0 for fewer than two particles or a
/// stress-free soil; `None` where the particles cannot be searched: a non-finite position).
/// Builds its own neighbour list each call (it is a measure taken at sample times, not a
/// pass of the step).
pub fn stress_noise<const D: usize>(soil: &Particles<D>, spacing: Real) -> Option<Real> {
    let Some(fields) = soil.soil.as_ref().filter(|_| soil.len() > 1) else {
        return Some(0.0);
    };
    let kernel = WendlandC2::<D>::new(1.3 * spacing);
    let radius = kernel.support_radius();
    let (mut min, mut max) = (
        Vector::<D>::repeat(Real::MAX),
        Vector::<D>::repeat(Real::MIN),
    );
    for x in &soil.position {
        min = min.inf(x);
        max = max.sup(x);
    }
    let margin = Vector::<D>::repeat(radius);
    let domain = Domain::new(min - margin, max + margin).ok()?;
    let mut grid = CellGrid::new(domain, radius).ok()?;
    grid.build(&soil.position).ok()?;
    let mut list = NeighbourList::new();
    grid.neighbour_list(&soil.position, &soil.position, &mut list);
    let mut scratch = RegularisationScratch::default();
    let smoothed = smooth_stress(&kernel, grid.domain(), &list, soil, true, &mut scratch);
    let (mut difference, mut magnitude) = (0.0, 0.0);
    for (sigma, fit) in fields.stress.iter().zip(smoothed) {
        difference += (sigma - fit).norm_squared();
        magnitude += sigma.norm_squared();
    }
    Some(if magnitude > 0.0 {
        (difference / magnitude).sqrt()
    } else {
        0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Tensor3;

    /// A 20 × 20 block of spacing dx with σ linear in x and y: η vanishes (the MLS fit is exact
    /// for linear fields, at the block's edges too). With a checkerboard of amplitude a added,
    /// each particle's fit is a weighted mean c·a of the alternating pattern with |c| < 1
    /// (the self-weight is the largest), so σ − ⟨σ⟩ = (1 − c)a lies in (0, 2a): η lies between
    /// 0 and 2a/S (S the RMS of ‖σ‖); the measure must see at least a tenth of it.
    #[test]
    fn linear_stress_is_quiet_and_a_checkerboard_is_not() {
        let dx = 0.01;
        let position: Vec<Vector<2>> = (0..400)
            .map(|k| Vector::<2>::new((k % 20) as Real + 0.5, (k / 20) as Real + 0.5) * dx)
            .collect();
        let mut soil = Particles::at_rest(position, 2000.0 * dx * dx, 2000.0);
        let linear = |x: &Vector<2>| {
            let mut sigma = Tensor3::zeros();
            sigma[(0, 0)] = -1e3 - 4e4 * x[1];
            sigma[(1, 1)] = -2e3 - 1e5 * x[1] + 2e4 * x[0];
            sigma[(0, 1)] = 5e3 * x[0];
            sigma[(1, 0)] = 5e3 * x[0];
            sigma
        };
        let stress: Vec<Tensor3> = soil.position.iter().map(linear).collect();
        soil.enable_soil().stress.copy_from_slice(&stress);
        let quiet = stress_noise(&soil, dx).unwrap();
        assert!(quiet < 1e-10, "{quiet}");

        let amplitude = 500.0;
        let fields = soil.soil.as_mut().unwrap();
        for (k, sigma) in fields.stress.iter_mut().enumerate() {
            let sign = if (k % 20 + k / 20) % 2 == 0 {
                1.0
            } else {
                -1.0
            };
            sigma[(1, 1)] += sign * amplitude;
        }
        let scale = (fields.stress.iter().map(|s| s.norm_squared()).sum::<Real>() / 400.0).sqrt();
        let noisy = stress_noise(&soil, dx).unwrap();
        let bound = amplitude / scale;
        assert!(
            noisy > 0.1 * bound && noisy < 2.0 * bound,
            "{noisy} vs {bound}"
        );
    }
}
