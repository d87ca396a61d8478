//! Calibration of SPH sums on the initial particle lattice: the kernel sum, the gradient of a
//! linear field, and the spectrum of the pressure system there. Solvers use them to start a
//! lattice at rest and to make the pressure gradient of still water exact.

use geosph_core::{Real, Vector};
use geosph_kernels::Kernel;

/// Calls `visit(x)` for every point x = k·dx (k ∈ ℤ^D) of the lattice of `spacing` dx with
/// |x| < `radius`, the origin included.
pub fn for_each_lattice_offset<const D: usize>(
    radius: Real,
    spacing: Real,
    mut visit: impl FnMut(Vector<D>),
) {
    let reach = (radius / spacing).ceil() as i64;
    let mut index = [-reach; D];
    loop {
        let x = Vector::<D>::from_fn(|k, _| index[k] as Real * spacing);
        if x.norm() < radius {
            visit(x);
        }
        // The next point of the box [−reach, reach]^D, axis 0 fastest.
        let mut axis = 0;
        loop {
            if axis == D {
                return;
            }
            index[axis] += 1;
            if index[axis] <= reach {
                break;
            }
            index[axis] = -reach;
            axis += 1;
        }
    }
}

/// The kernel sum Σ_k W(|k dx|) of a particle inside a filled lattice of spacing dx.
///
/// It differs from 1/dx^D by the kernel's discretisation error (+1.0 % for Wendland C2 with
/// h = 1.3 dx in 2D, see the unit test), so a fluid of particles of mass ρ₀ dx^D on the
/// lattice has a summation density off ρ₀ by as much. The incompressible solvers, whose
/// density *is* the kernel sum, would start by pushing the lattice apart; they use the mass
/// ρ₀ / Σ_k W instead (and the wall volume 1 / Σ_k W), for which the lattice is at rest.
pub fn lattice_kernel_sum<const D: usize, K: Kernel<D>>(kernel: &K, spacing: Real) -> Real {
    let mut sum = 0.0;
    for_each_lattice_offset::<D>(kernel.support_radius(), spacing, |x| {
        sum += kernel.value(x.norm());
    });
    sum
}

/// The factor f of Σ_j V (x_j − x_i) ⊗ ∇_i W_ij = f I for a particle inside a filled lattice
/// of spacing dx whose particles have volume `volume`: 1 / Σ_k W(|k dx|) for the
/// incompressible solvers, dx^D for WCSPH.
///
/// f = 1 would make the SPH gradient of a linear field exact; for Wendland C2 at h = 1.3 dx
/// in 2D f = 0.964 with V = 1/Σ_k W and 0.974 with V = dx² (see the unit test), so a pressure
/// force −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij holding still water up needs a pressure
/// gradient 3.7 % (2.7 %) steeper than ρ₀ g. Every solver multiplies its pressure-gradient
/// terms by 1/f (`gradient_correction`): a constant, so the pair forces stay antisymmetric
/// and momentum is conserved, unlike a per-particle renormalisation (Randles & Libersky
/// 1996), which is exact for any particle order but is not.
pub fn lattice_gradient_factor<const D: usize, K: Kernel<D>>(
    kernel: &K,
    spacing: Real,
    volume: Real,
) -> Real {
    let mut sum = 0.0;
    for_each_lattice_offset::<D>(kernel.support_radius(), spacing, |x| {
        // x = x_j − x_i, so ∇_i W_ij = ∇W(−x).
        sum += x.dot(&kernel.gradient(&-x));
    });
    volume * sum / D as Real
}

/// The factor f_ν of the laminar viscous term (Morris, Fox & Zhu 1997) on a filled lattice of
/// spacing dx whose particles have volume `volume`: for the velocity u = ½ x₀² e₀, whose
/// Laplacian is e₀, the term gives ν f_ν e₀ instead of ν e₀, with
///
/// f_ν = V Σ_k (−x_k·∇W(x_k)) x_k,0² / (|x_k|² + 0.01 h²).
///
/// On an isotropic continuum f_ν would be 1 without the 0.01 h² regularisation, which alone
/// lowers it to about 0.985 at any h/dx; on the lattice the discretisation error of the
/// kernel sums comes on top: 0.963 for Wendland C2 at h = 1.3 dx in 2D with V = dx² (0.985 at
/// h ≥ 1.5 dx, unit test), so an uncorrected Poiseuille flow between plates runs 3.9 % fast
/// (measured 4.0 % at 40 particles across, `docs/fluid.md`).
/// The laminar term is divided by it
/// ([`ViscousTerm::calibrated`](crate::viscosity::ViscousTerm::calibrated)).
pub fn lattice_laplacian_factor<const D: usize, K: Kernel<D>>(
    kernel: &K,
    spacing: Real,
    volume: Real,
) -> Real {
    let eta2 = 0.01 * kernel.smoothing_length().powi(2);
    let mut sum = 0.0;
    for_each_lattice_offset::<D>(kernel.support_radius(), spacing, |x| {
        let radial = x.dot(&kernel.gradient(&x));
        sum -= radial * x[0] * x[0] / (x.norm_squared() + eta2);
    });
    volume * sum
}

/// Σ_k |∇W(x_k)|² over a filled lattice of spacing dx: m² times it is the diagonal d of a
/// particle of mass m inside the lattice (its G·S vanishes there), the scale of
/// the incompressible solvers' diagonal floor.
pub fn lattice_gradient_squares<const D: usize, K: Kernel<D>>(kernel: &K, spacing: Real) -> Real {
    let mut squares = 0.0;
    for_each_lattice_offset::<D>(kernel.support_radius(), spacing, |x| {
        squares += kernel.gradient(&x).norm_squared();
    });
    squares
}

/// The largest eigenvalue λ_max of D⁻¹A for the pressure system A of a filled lattice of
/// spacing dx, D its diagonal: the bound on the relaxation of a Jacobi iteration on it, which
/// converges only for ω λ_max < 2.
///
/// On the lattice A is a convolution, so its eigenvectors are the Fourier modes p_j = e^{ik·x_j}
/// and, with the symmetric pressure force −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij and the
/// continuity divergence, its eigenvalue over the diagonal is
///
/// λ(k) = |Σ_j sin(k·x_j) ∇W(x_j)|² / Σ_j |∇W(x_j)|²,
///
/// maximised here over k in the quarter [0, π/dx]^D of the Brillouin zone (λ is even in each
/// component of k on a lattice symmetric under reflections), on a grid of 25 points per axis
/// in 2D and 13 in 3D. For Wendland C2 at h = 1.3 dx in 2D λ_max = 2.60, so Ihmsen et al.'s
/// ω = 0.5 is 65 % of the limit; for the quintic spline at the same h it is 4.11, and ω = 0.5
/// diverges (see the unit test).
pub fn lattice_jacobi_bound<const D: usize, K: Kernel<D>>(kernel: &K, spacing: Real) -> Real {
    let mut offsets = Vec::new();
    for_each_lattice_offset::<D>(kernel.support_radius(), spacing, |x| {
        offsets.push((x, kernel.gradient(&-x)));
    });
    let squares = lattice_gradient_squares(kernel, spacing);
    let points = if D <= 2 { 25 } else { 13 };
    let step = std::f64::consts::PI / (spacing * (points - 1) as Real);
    let mut largest: Real = 0.0;
    let mut index = [0usize; D];
    loop {
        let k = Vector::<D>::from_fn(|axis, _| index[axis] as Real * step);
        let sum = offsets
            .iter()
            .fold(Vector::<D>::zeros(), |sum, (x, gradient)| {
                sum + gradient * k.dot(x).sin()
            });
        largest = largest.max(sum.norm_squared() / squares);
        // The next grid point, axis 0 fastest.
        let mut axis = 0;
        loop {
            if axis == D {
                return largest;
            }
            index[axis] += 1;
            if index[axis] < points {
                break;
            }
            index[axis] = 0;
            axis += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_kernels::{CubicSpline, QuinticSpline, WendlandC2};

    #[test]
    fn lattice_sums_are_close_to_one_over_the_cell_volume() {
        let dx: Real = 0.01;
        for (name, sum) in [
            (
                "wendland-c2 2D",
                lattice_kernel_sum::<2, _>(&WendlandC2::<2>::new(1.3 * dx), dx) * dx * dx,
            ),
            (
                "cubic 2D",
                lattice_kernel_sum::<2, _>(&CubicSpline::<2>::new(1.3 * dx), dx) * dx * dx,
            ),
            (
                "wendland-c2 3D",
                lattice_kernel_sum::<3, _>(&WendlandC2::<3>::new(1.3 * dx), dx) * dx.powi(3),
            ),
        ] {
            println!("{name}: Σ W dx^D = {sum}");
            assert!((sum - 1.0).abs() < 0.05, "{name}: {sum}");
        }
    }

    /// The viscous factor against the Laplacian of u = ½ x² applied by Morris' term on the
    /// lattice directly (a different loop over the same sum), and against the continuum: the
    /// lattice sum is a quadrature of f_c = π ∫₀^R (−W'(r)) r⁴ / (r² + 0.01 h²) dr (the angular
    /// integral of x² is π r²), which it must approach as h/dx grows: within 0.2 % from
    /// h = 2 dx (about 50 lattice points in the support), 5 % below; without the
    /// regularisation f_c = 1 by the kernel's normalisation.
    #[test]
    fn lattice_laplacian_factor_is_the_laplacian_of_a_quadratic_field() {
        let dx: Real = 0.01;
        for ratio in [1.3, 1.5, 2.0, 3.0] {
            let h = ratio * dx;
            let kernel = WendlandC2::<2>::new(h);
            let factor = lattice_laplacian_factor::<2, _>(&kernel, dx, dx * dx);
            // a_i = 2ν Σ_j V (x_ij·∇_i W_ij)/(r² + 0.01h²) (u_i − u_j), u = ½ x², x_i = 0.
            let reach = (kernel.support_radius() / dx).ceil() as i64;
            let mut laplacian = 0.0;
            for a in -reach..=reach {
                for b in -reach..=reach {
                    let x_j = Vector::<2>::new(a as Real * dx, b as Real * dx);
                    let x_ij = -x_j;
                    let grad = kernel.gradient(&x_ij);
                    let (u_i, u_j) = (0.0, 0.5 * x_j[0] * x_j[0]);
                    if x_j.norm() > 0.0 {
                        laplacian += 2.0 * dx * dx * x_ij.dot(&grad)
                            / (x_ij.norm_squared() + 0.01 * h * h)
                            * (u_i - u_j);
                    }
                }
            }
            // Midpoint rule on the radial integral, W'(r) = r × gradient_factor(r).
            let continuum = |eta2: Real| {
                let (support, steps) = (kernel.support_radius(), 20_000);
                let dr = support / steps as Real;
                (0..steps)
                    .map(|k| {
                        let r = (k as Real + 0.5) * dr;
                        let slope = r * Kernel::<2>::gradient_factor(&kernel, r);
                        -slope * r.powi(4) / (r * r + eta2) * dr
                    })
                    .sum::<Real>()
                    * std::f64::consts::PI
            };
            let regularised = continuum(0.01 * h * h);
            println!("h = {ratio} dx: f_ν = {factor:.4}, continuum {regularised:.4}");
            approx::assert_relative_eq!(factor, laplacian, max_relative = 1e-12);
            approx::assert_relative_eq!(continuum(0.0), 1.0, max_relative = 1e-6);
            let tolerance = if ratio >= 2.0 { 0.002 } else { 0.05 };
            assert!(
                (factor - regularised).abs() < tolerance,
                "{factor} vs {regularised}"
            );
        }
    }

    /// The factor against a direct sum of the x-gradient of f(x) = x over a lattice, which
    /// must tend to 1 as h/dx grows (0.9638 at 1.3, 0.9923 at 1.5, 0.9980 at 2.0 in 2D with
    /// V = 1/Σ_k W, computed independently).
    #[test]
    fn lattice_gradient_factor_is_the_gradient_of_a_linear_field() {
        let dx: Real = 0.01;
        for (ratio, expected) in [(1.3, 0.9638), (1.5, 0.9923), (2.0, 0.9980)] {
            let kernel = WendlandC2::<2>::new(ratio * dx);
            let volume = 1.0 / lattice_kernel_sum::<2, _>(&kernel, dx);
            let mut gradient = Vector::<2>::zeros();
            for_each_lattice_offset::<2>(kernel.support_radius(), dx, |x| {
                gradient += kernel.gradient(&-x) * (volume * x[0]);
            });
            let factor = lattice_gradient_factor::<2, _>(&kernel, dx, volume);
            assert!((gradient[0] - factor).abs() < 1e-12 && gradient[1].abs() < 1e-12);
            assert!((factor - expected).abs() < 5e-4, "h = {ratio} dx: {factor}");
            // With WCSPH's volume dx²: 0.9739 at h = 1.3 dx (the same sum, volume dx²).
            let wcsph = lattice_gradient_factor::<2, _>(&kernel, dx, dx * dx);
            assert!((wcsph / factor - volume.recip() * dx * dx).abs() < 1e-12);
        }
    }

    /// λ_max against an independent computation (NumPy, 121 × 121 wave vectors over the whole
    /// zone): 2.602 Wendland C2 and 2.880 cubic spline at h = 1.3 dx, 5.676 Wendland C2 at
    /// h = 2 dx, 4.114 quintic spline at h = 1.3 dx (2D).
    #[test]
    fn lattice_jacobi_bound_matches_the_fourier_symbol() {
        let dx: Real = 0.01;
        for (name, bound, expected) in [
            (
                "wendland-c2 1.3",
                lattice_jacobi_bound::<2, _>(&WendlandC2::<2>::new(1.3 * dx), dx),
                2.602,
            ),
            (
                "cubic 1.3",
                lattice_jacobi_bound::<2, _>(&CubicSpline::<2>::new(1.3 * dx), dx),
                2.880,
            ),
            (
                "wendland-c2 2.0",
                lattice_jacobi_bound::<2, _>(&WendlandC2::<2>::new(2.0 * dx), dx),
                5.676,
            ),
            (
                "quintic 1.3",
                lattice_jacobi_bound::<2, _>(&QuinticSpline::<2>::new(1.3 * dx), dx),
                4.114,
            ),
        ] {
            println!("{name}: λ_max = {bound:.4}");
            assert!(
                (bound - expected).abs() < 0.01 * expected,
                "{name}: {bound}"
            );
        }
        let bound_3d = lattice_jacobi_bound::<3, _>(&WendlandC2::<3>::new(1.3 * dx), dx);
        println!("wendland-c2 1.3 3D: λ_max = {bound_3d:.4}");
        assert!(bound_3d > 1.0 && bound_3d < 10.0);
    }
}
