//! Kernel corrections on disordered particles with a free surface.
//!
//! On a lattice jittered by ±0.25 dx and cut by a tilted plane (so many particles have a
//! truncated support), Shepard's normalisation must reproduce constants, the CSPM-corrected
//! gradient (Bonet & Lok 1999) the gradient of linear fields, and first-order MLS (Dilts
//! 1999) linear fields, all to round-off, at interior and surface particles alike, while the
//! uncorrected SPH sums fail visibly at the surface. A refinement study of the gradient of
//! `sin x cos y` measures the convergence order with and without CSPM.

use approx::assert_relative_eq;
use geosph_core::{Domain, Matrix, NeighbourList, Real, Vector};
use geosph_kernels::cspm::gradient_correction;
use geosph_kernels::mls::mls_coefficients;
use geosph_kernels::shepard::shepard_sums;
use geosph_kernels::{CubicSpline, Kernel, KernelKind, KernelVisitor, MlsCoefficients, WendlandC2};
use geosph_tests::jittered_lattice;

/// Neighbours within `radius` (inclusive), each particle listing itself, ascending: a sweep
/// along x over a sorted copy, exact like the O(N²) search it is checked against below.
fn brute_force_neighbours<const D: usize>(position: &[Vector<D>], radius: Real) -> NeighbourList {
    let mut order: Vec<usize> = (0..position.len()).collect();
    order.sort_by(|&a, &b| position[a][0].total_cmp(&position[b][0]));
    let sorted_x: Vec<Real> = order.iter().map(|&k| position[k][0]).collect();
    let mut list = NeighbourList::new();
    let mut found = Vec::new();
    for x_i in position {
        let first = sorted_x.partition_point(|&x| x < x_i[0] - radius);
        let last = sorted_x.partition_point(|&x| x <= x_i[0] + radius);
        found.clear();
        found.extend(
            order[first..last]
                .iter()
                .filter(|&&j| (x_i - position[j]).norm() <= radius)
                .map(|&j| j as u32),
        );
        found.sort_unstable();
        list.indices.extend_from_slice(&found);
        list.offsets.push(list.indices.len() as u32);
    }
    list
}

#[test]
fn sweep_search_equals_all_pairs_search() {
    let position = jittered_lattice(Vector::<2>::zeros(), [15, 11], 0.1, 0.25, 3);
    let radius = 0.26;
    let sweep = brute_force_neighbours(&position, radius);
    let mut all_pairs = NeighbourList::new();
    for x_i in &position {
        for (j, x_j) in position.iter().enumerate() {
            if (x_i - x_j).norm() <= radius {
                all_pairs.indices.push(j as u32);
            }
        }
        all_pairs.offsets.push(all_pairs.indices.len() as u32);
    }
    assert_eq!(sweep, all_pairs);
}

/// Particles of a jittered lattice in the unit box below a tilted plane `n · x < c`, with
/// `V = dx^D` and a flag for the particles within `radius` of any face of the cut box.
struct Body<const D: usize> {
    domain: Domain<D>,
    position: Vec<Vector<D>>,
    volume: Vec<Real>,
    surface: Vec<bool>,
    neighbours: NeighbourList,
}

impl<const D: usize> Body<D> {
    fn cut_lattice(
        cells: usize,
        jitter: Real,
        normal: Vector<D>,
        offset: Real,
        radius: Real,
        seed: u64,
    ) -> Self {
        let dx = 1.0 / cells as Real;
        let normal = normal.normalize();
        let position: Vec<Vector<D>> =
            jittered_lattice(Vector::<D>::zeros(), [cells; D], dx, jitter, seed)
                .into_iter()
                .filter(|x| normal.dot(x) < offset)
                .collect();
        let surface = position
            .iter()
            .map(|x| {
                let to_box = (0..D)
                    .map(|k| x[k].min(1.0 - x[k]))
                    .fold(Real::INFINITY, Real::min);
                to_box.min(offset - normal.dot(x)) < radius
            })
            .collect();
        let neighbours = brute_force_neighbours(&position, radius);
        Self {
            domain: Domain::new(Vector::<D>::repeat(-1.0), Vector::<D>::repeat(2.0)).unwrap(),
            volume: vec![dx.powi(D as i32); position.len()],
            position,
            surface,
            neighbours,
        }
    }
}

/// 30 × 30 jittered lattice below the plane `n̂ · x = 0.75`, `n ∝ (0.3, 1)`.
fn cut_square(radius: Real) -> Body<2> {
    Body::cut_lattice(30, 0.25, Vector::<2>::new(0.3, 1.0), 0.75, radius, 11)
}

/// 12³ jittered lattice below a plane tilted against all three axes.
fn cut_cube(radius: Real) -> Body<3> {
    Body::cut_lattice(12, 0.25, Vector::<3>::new(1.0, 0.5, 2.0), 0.6, radius, 12)
}

/// `Σ_j V_j (f_j − f_i) L_i ∇_i W_ij`, with `L_i = I` when `correction` is `None`.
fn gradient_estimate<K: Kernel<D>, const D: usize>(
    kernel: &K,
    body: &Body<D>,
    field: &[Real],
    correction: Option<&[Matrix<D>]>,
) -> Vec<Vector<D>> {
    (0..body.position.len())
        .map(|i| {
            let sum: Vector<D> = body
                .neighbours
                .neighbours(i)
                .iter()
                .map(|&j| {
                    let j = j as usize;
                    let r_ij = body.position[i] - body.position[j];
                    body.volume[j] * (field[j] - field[i]) * kernel.gradient(&r_ij)
                })
                .sum();
            correction.map_or(sum, |l| l[i] * sum)
        })
        .collect()
}

/// The largest relative error `|a − b| / |b|` over the particles selected by `keep`.
fn max_relative_error<T, F: Fn(&T, &T) -> Real>(
    approximate: &[T],
    exact: &[T],
    keep: impl Fn(usize) -> bool,
    relative_error: F,
) -> Real {
    approximate
        .iter()
        .zip(exact)
        .enumerate()
        .filter(|(i, _)| keep(*i))
        .map(|(_, (a, e))| relative_error(a, e))
        .fold(0.0, Real::max)
}

fn vector_error<const D: usize>(a: &Vector<D>, e: &Vector<D>) -> Real {
    (a - e).norm() / e.norm()
}

fn scalar_error(a: &Real, e: &Real) -> Real {
    (a - e).abs() / e.abs()
}

/// Shepard, CSPM and MLS on one body with one kernel.
struct ConsistencyChecks<'a, const D: usize> {
    body: &'a Body<D>,
    gradient: Vector<D>,
}

impl<const D: usize> KernelVisitor<D> for ConsistencyChecks<'_, D> {
    type Output = ();

    fn visit<K: Kernel<D>>(self, kernel: K) {
        let body = self.body;
        let name = K::NAME;
        let n = body.position.len();
        let surface = |i: usize| body.surface[i];
        assert!(
            body.surface.iter().filter(|&&s| s).count() > n / 5,
            "too few surface particles"
        );
        let linear: Vec<Real> = body
            .position
            .iter()
            .map(|x| 2.0 + self.gradient.dot(x))
            .collect();
        let sph_sum = |i: usize, coefficient: &dyn Fn(usize, &Vector<D>, Real) -> Real| -> Real {
            body.neighbours
                .neighbours(i)
                .iter()
                .map(|&j| {
                    let j = j as usize;
                    let r_ij = body.position[i] - body.position[j];
                    body.volume[j] * linear[j] * coefficient(i, &r_ij, kernel.value(r_ij.norm()))
                })
                .sum()
        };

        // Shepard: a constant is reproduced exactly; the plain sum Σ V_j W_ij is not 1.
        let mut shepard = vec![0.0; n];
        shepard_sums(
            &kernel,
            &body.domain,
            &body.position,
            &body.volume,
            &body.neighbours,
            &mut shepard,
        );
        let constant = 3.7;
        let normalised: Vec<Real> = shepard.iter().map(|&s| constant * s / s).collect();
        let plain: Vec<Real> = shepard.iter().map(|&s| constant * s).collect();
        let exact = vec![constant; n];
        for i in 0..n {
            let interpolated: Real = body
                .neighbours
                .neighbours(i)
                .iter()
                .map(|&j| {
                    let j = j as usize;
                    body.volume[j]
                        * constant
                        * kernel.value((body.position[i] - body.position[j]).norm())
                        / shepard[i]
                })
                .sum();
            assert_relative_eq!(interpolated, constant, max_relative = 1e-12);
        }
        assert!(max_relative_error(&normalised, &exact, |_| true, scalar_error) < 1e-14);
        let plain_error = max_relative_error(&plain, &exact, surface, scalar_error);
        assert!(
            plain_error > 1e-2,
            "{name} {D}D: uncorrected constant error {plain_error}"
        );

        // CSPM: the gradient of a linear field is exact everywhere.
        let mut correction = vec![Matrix::<D>::zeros(); n];
        let report = gradient_correction(
            &kernel,
            &body.domain,
            &body.position,
            &body.volume,
            &body.neighbours,
            &mut correction,
        );
        assert!(report.all_corrected(), "{name} {D}D: {report}");
        let exact = vec![self.gradient; n];
        let corrected = gradient_estimate(&kernel, body, &linear, Some(&correction));
        let error = max_relative_error(&corrected, &exact, |_| true, vector_error);
        assert!(error < 1e-10, "{name} {D}D: CSPM gradient error {error}");
        let uncorrected = gradient_estimate(&kernel, body, &linear, None);
        let error = max_relative_error(&uncorrected, &exact, surface, vector_error);
        assert!(
            error > 1e-2,
            "{name} {D}D: uncorrected gradient error {error}"
        );

        // MLS: a linear field is interpolated exactly everywhere.
        let mut coefficients = vec![MlsCoefficients::<D>::default(); n];
        let report = mls_coefficients(
            &kernel,
            &body.domain,
            &body.position,
            &body.volume,
            &body.neighbours,
            &mut coefficients,
        );
        assert!(report.all_corrected(), "{name} {D}D: {report}");
        let mls: Vec<Real> = (0..n)
            .map(|i| sph_sum(i, &|i, r_ij, w| coefficients[i].corrected(r_ij, w)))
            .collect();
        let error = max_relative_error(&mls, &linear, |_| true, scalar_error);
        assert!(
            error < 1e-10,
            "{name} {D}D: MLS interpolation error {error}"
        );
        let plain: Vec<Real> = (0..n).map(|i| sph_sum(i, &|_, _, w| w)).collect();
        let error = max_relative_error(&plain, &linear, surface, scalar_error);
        assert!(
            error > 1e-2,
            "{name} {D}D: uncorrected interpolation error {error}"
        );
    }
}

#[test]
fn corrections_are_exact_for_linear_fields_at_a_free_surface_2d() {
    for kind in KernelKind::ALL {
        let h = 1.3 / 30.0;
        let body = cut_square(kind.support_factor() * h);
        let gradient = Vector::<2>::new(0.5, -1.5);
        kind.dispatch::<2, _>(
            h,
            ConsistencyChecks {
                body: &body,
                gradient,
            },
        );
    }
}

#[test]
fn corrections_are_exact_for_linear_fields_at_a_free_surface_3d() {
    for kind in KernelKind::ALL {
        let h = 1.3 / 12.0;
        let body = cut_cube(kind.support_factor() * h);
        let gradient = Vector::<3>::new(0.5, -1.5, 0.8);
        kind.dispatch::<3, _>(
            h,
            ConsistencyChecks {
                body: &body,
                gradient,
            },
        );
    }
}

/// Note 001 writes `L_i = Σ_j V_j r_ij ⊗ ∇_i W_ij` and `∇̃W = L_i⁻ᵀ ∇W` with
/// `∇f_i = Σ_j V_j f_j ∇̃_i W_ij`. With `r_ij = x_i − x_j` that matrix is `−B_i ≈ −I`: the
/// gradient comes out with the wrong sign; and the non-difference form is not exact at a
/// surface even with the right matrix.
#[test]
fn note_001_cspm_flips_the_sign_and_misses_the_surface() {
    let h = 1.3 / 30.0;
    let kernel = WendlandC2::<2>::new(h);
    let body = cut_square(kernel.support_radius());
    let n = body.position.len();
    let gradient = Vector::<2>::new(0.5, -1.5);
    let linear: Vec<Real> = body
        .position
        .iter()
        .map(|x| 2.0 + gradient.dot(x))
        .collect();
    let mut correction = vec![Matrix::<2>::zeros(); n];
    gradient_correction(
        &kernel,
        &body.domain,
        &body.position,
        &body.volume,
        &body.neighbours,
        &mut correction,
    );
    let mut note_sign = Vec::with_capacity(n);
    let mut non_difference = Vec::with_capacity(n);
    for i in 0..n {
        let mut note_matrix = Matrix::<2>::zeros();
        let mut sum = Vector::<2>::zeros();
        for &j in body.neighbours.neighbours(i) {
            let j = j as usize;
            let r_ij = body.position[i] - body.position[j];
            let grad_w = kernel.gradient(&r_ij);
            note_matrix += body.volume[j] * r_ij * grad_w.transpose();
            sum += body.volume[j] * linear[j] * grad_w;
        }
        let note_inverse_transpose = note_matrix.try_inverse().unwrap().transpose();
        note_sign.push(note_inverse_transpose * sum);
        non_difference.push(correction[i] * sum);
    }
    let exact = vec![gradient; n];
    let interior = |i: usize| !body.surface[i];
    // The interior estimate is −g up to the disorder error: relative error ≈ 2.
    let sign_error = max_relative_error(&note_sign, &exact, interior, vector_error);
    assert!(sign_error > 1.5, "{sign_error}");
    let reversed: Vec<Vector<2>> = note_sign.iter().map(|g| -g).collect();
    // …and it is exactly the negative of the correct non-difference estimate.
    for i in 0..n {
        assert_relative_eq!(reversed[i], non_difference[i], max_relative = 1e-9);
    }
    let surface_error =
        max_relative_error(&non_difference, &exact, |i| body.surface[i], vector_error);
    assert!(surface_error > 0.1, "{surface_error}");
}

/// Error norms of one gradient estimate: RMS over full-support particles, max over all.
#[derive(Clone, Copy, Debug)]
struct GradientErrors {
    interior_rms: Real,
    all_max: Real,
}

/// Gradient of `f = sin x cos y` on `[0, 1]²` (all four edges free) with `cells²` particles,
/// cubic spline with `h = 1.3 dx`: errors without and with CSPM.
fn sine_gradient_errors(cells: usize, jitter: Real) -> (Real, GradientErrors, GradientErrors) {
    let dx = 1.0 / cells as Real;
    let h = 1.3 * dx;
    let kernel = CubicSpline::<2>::new(h);
    // The unit square uncut (the plane y = 2 lies outside it).
    let body = Body::<2>::cut_lattice(
        cells,
        jitter,
        Vector::<2>::new(0.0, 1.0),
        2.0,
        kernel.support_radius(),
        5 + cells as u64,
    );
    let field: Vec<Real> = body
        .position
        .iter()
        .map(|x| x[0].sin() * x[1].cos())
        .collect();
    let exact: Vec<Vector<2>> = body
        .position
        .iter()
        .map(|x| Vector::<2>::new(x[0].cos() * x[1].cos(), -x[0].sin() * x[1].sin()))
        .collect();
    let mut correction = vec![Matrix::<2>::zeros(); body.position.len()];
    let report = gradient_correction(
        &kernel,
        &body.domain,
        &body.position,
        &body.volume,
        &body.neighbours,
        &mut correction,
    );
    assert!(report.all_corrected(), "{report}");
    let norms = |estimate: &[Vector<2>]| {
        let mut sum = 0.0;
        let mut count = 0;
        let mut all_max: Real = 0.0;
        for i in 0..estimate.len() {
            let error = (estimate[i] - exact[i]).norm();
            all_max = all_max.max(error);
            if !body.surface[i] {
                sum += error * error;
                count += 1;
            }
        }
        GradientErrors {
            interior_rms: (sum / count as Real).sqrt(),
            all_max,
        }
    };
    let plain = norms(&gradient_estimate(&kernel, &body, &field, None));
    let corrected = norms(&gradient_estimate(
        &kernel,
        &body,
        &field,
        Some(&correction),
    ));
    (dx, plain, corrected)
}

/// Least-squares slope of `log error` against `log dx`.
fn fitted_order(dx: &[Real], error: &[Real]) -> Real {
    let x: Vec<Real> = dx.iter().map(|d| d.ln()).collect();
    let y: Vec<Real> = error.iter().map(|e| e.ln()).collect();
    let n = x.len() as Real;
    let (mx, my) = (x.iter().sum::<Real>() / n, y.iter().sum::<Real>() / n);
    let covariance: Real = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let variance: Real = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    covariance / variance
}

/// Convergence of the SPH gradient of `sin x cos y` under refinement at fixed `h/dx = 1.3`.
///
/// Expected orders (the bounds allow 0.2–0.3 for the randomness of the jitter):
/// - CSPM is exact for linear fields, so its error is the quadratic Taylor term,
///   `O(h |∇²f|)` on disordered particles (order 1) and at surfaces; on a regular lattice the
///   interior quadratic term cancels by symmetry (order 2).
/// - Uncorrected SPH at fixed `h/dx` does not converge: its discretisation error
///   `(B_i − I) ∇f` depends on `dx/h` and the disorder, not on `h` (Quinlan et al. 2006),
///   and at a free surface `B_i − I = O(1)`.
///
/// Run with `--nocapture` to print the table reproduced in `docs/theory.md`.
#[test]
fn gradient_convergence_with_and_without_cspm() {
    let resolutions = [20, 40, 80, 160];
    for (label, jitter) in [("jittered ±0.25 dx", 0.25), ("regular", 0.0)] {
        println!(
            "\n{label}: cubic spline, h = 1.3 dx, f = sin x cos y on [0,1]², error |∇f_h − ∇f|"
        );
        println!(
            "| 1/dx | SPH interior RMS | CSPM interior RMS | SPH max (all) | CSPM max (all) |"
        );
        println!("|---:|---:|---:|---:|---:|");
        let mut dx = Vec::new();
        let (mut plain, mut corrected) = (Vec::new(), Vec::new());
        for cells in resolutions {
            let (spacing, p, c) = sine_gradient_errors(cells, jitter);
            println!(
                "| {cells} | {:.3e} | {:.3e} | {:.3e} | {:.3e} |",
                p.interior_rms, c.interior_rms, p.all_max, c.all_max
            );
            dx.push(spacing);
            plain.push(p);
            corrected.push(c);
        }
        let order = |errors: &[GradientErrors], pick: fn(&GradientErrors) -> Real| {
            fitted_order(&dx, &errors.iter().map(pick).collect::<Vec<_>>())
        };
        let interior = |e: &GradientErrors| e.interior_rms;
        let all = |e: &GradientErrors| e.all_max;
        let orders = [
            order(&plain, interior),
            order(&corrected, interior),
            order(&plain, all),
            order(&corrected, all),
        ];
        println!(
            "| fitted order | {:.2} | {:.2} | {:.2} | {:.2} |",
            orders[0], orders[1], orders[2], orders[3]
        );
        let (interior_bound, all_bound) = if jitter > 0.0 { (0.8, 0.7) } else { (1.8, 0.8) };
        assert!(
            orders[1] >= interior_bound,
            "{label}: CSPM interior order {}",
            orders[1]
        );
        assert!(
            orders[3] >= all_bound,
            "{label}: CSPM order with surface {}",
            orders[3]
        );
        assert!(
            orders[2] < 0.3,
            "{label}: uncorrected SPH at the surface converges? {}",
            orders[2]
        );
    }
}
