//! The errors a pressure solve stops on: means over the particles in index order and the
//! largest entry of a particle that can take pressure.

use geosph_core::Real;

/// Mean of the positive entries of `values`, summed in index order, and the largest entry
/// of a particle with a non-zero `diagonal` (one that can take pressure; 0 if none).
pub(crate) fn mean_and_max_positive(values: &[Real], diagonal: &[Real]) -> (Real, Real) {
    mean_error_and_max(values, diagonal, |_, value| value.max(0.0), |r| r)
}

/// Mean of |`values`|, summed in index order, and the largest |entry| of a particle with a
/// non-zero `diagonal`: the error of a solve whose pressures may be negative.
pub(crate) fn mean_and_max_absolute(values: &[Real], diagonal: &[Real]) -> (Real, Real) {
    mean_error_and_max(values, diagonal, |_, r| r.abs(), Real::abs)
}

/// [`mean_and_max_absolute`] when `negative_pressure`, else [`mean_and_max_positive`].
pub(crate) fn residual_error(
    values: &[Real],
    diagonal: &[Real],
    negative_pressure: bool,
) -> (Real, Real) {
    if negative_pressure {
        mean_and_max_absolute(values, diagonal)
    } else {
        mean_and_max_positive(values, diagonal)
    }
}

/// The complementarity error of a pressure solve with p ≥ 0: the mean over all particles of
/// |r_i| where p_i > 0 and max(r_i, 0) where p_i = 0, r = `residual` = ρ̃ − ρ₀, summed in
/// index order; and the largest r_i of a particle with a non-zero `diagonal` (0 if none).
///
/// The exact solution satisfies p_i ≥ 0, ρ̃_i ≤ ρ₀ and p_i (ρ̃_i − ρ₀) = 0 (a linear
/// complementarity problem): a particle under pressure must be at ρ₀, not below it. Counting
/// only compression lets a solve stop with pressures that hold particles apart, expanded
/// below ρ₀; in still water that left the level of the pressure free by several per cent
/// (`docs/incompressible.md`, "Still water").
pub(crate) fn complementarity_error(
    residual: &[Real],
    pressure: &[Real],
    diagonal: &[Real],
) -> (Real, Real) {
    let error = |i: usize, r: Real| {
        if pressure[i] > 0.0 {
            r.abs()
        } else {
            r.max(0.0)
        }
    };
    mean_error_and_max(residual, diagonal, error, |r| r)
}

/// The mean of `error(i, r_i)` over `residual`, summed in index order, and the largest
/// `peak(r_i)` of a particle with a non-zero `diagonal` (0 if none).
fn mean_error_and_max(
    residual: &[Real],
    diagonal: &[Real],
    error: impl Fn(usize, Real) -> Real,
    peak: impl Fn(Real) -> Real,
) -> (Real, Real) {
    let (sum, max) = residual.iter().zip(diagonal).enumerate().fold(
        (0.0, 0.0),
        |(sum, max): (Real, Real), (i, (&r, &d))| {
            let max = if d > 0.0 { max.max(peak(r)) } else { max };
            (sum + error(i, r), max)
        },
    );
    (sum / residual.len().max(1) as Real, max)
}
