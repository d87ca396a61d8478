//! Walls on the periodic axes of a scene's domain.
//!
//! Along a periodic axis the domain is a period P: a particle at x and its image at x + P are
//! the same place. A tank has no walls across such an axis, and a mesh wall that crosses the
//! seam (a gate across a periodic slab, drawn wider than the slab) is folded into one period.

use geosph_core::{Real, Vector};
use geosph_geometry::WallSite;

use crate::error::SceneError;
use crate::format::Scene;

/// The periodic axes of the scene's domain: for each axis, its lower bound and period P, or
/// `None`. A period must hold a whole number of lattice spacings, else the last row of
/// particles lies closer than dx to the first row's image across the seam: refused under
/// `field`.
pub(crate) fn periods<const D: usize>(
    scene: &Scene,
    field: &str,
) -> Result<[Option<(Real, Real)>; D], SceneError> {
    let mut periods = [None; D];
    let Some(domain) = &scene.domain else {
        return Ok(periods);
    };
    for (k, _) in domain
        .periodic
        .iter()
        .enumerate()
        .take(D)
        .filter(|(_, p)| **p)
    {
        let period = domain.max[k] - domain.min[k];
        let rows = period / scene.dx;
        if (rows - rows.round()).abs() > 1e-6 * rows.max(1.0) {
            return Err(SceneError::Field {
                field: field.into(),
                message: format!(
                    "axis {k} is periodic and its period {period} m holds {rows:.3} lattice \
                     spacings of dx = {} m: choose a dx that divides the period",
                    scene.dx
                ),
            });
        }
        periods[k] = Some((domain.min[k], period));
    }
    Ok(periods)
}

/// The periodic axes along which a tank `[min, max]` has no walls. There the tank must span
/// the domain's period exactly (shorter, it would leave a strip without floor; longer, its
/// walls would overlap their own images), and the period must hold a whole number of dx.
pub(crate) fn periodic_span<const D: usize>(
    scene: &Scene,
    field: &str,
    min: &Vector<D>,
    max: &Vector<D>,
) -> Result<[bool; D], SceneError> {
    let periods = periods::<D>(scene, field)?;
    let tolerance = 1e-9 * scene.dx;
    for (k, &(lower, period)) in periods
        .iter()
        .enumerate()
        .filter_map(|(k, p)| Some((k, p.as_ref()?)))
    {
        let upper = lower + period;
        if (min[k] - lower).abs() > tolerance || (max[k] - upper).abs() > tolerance {
            return Err(SceneError::Field {
                field: field.into(),
                message: format!(
                    "axis {k} is periodic, so the tank has no walls across it and must span the \
                     domain's period [{lower}, {upper}] exactly, not [{}, {}]",
                    min[k], max[k]
                ),
            });
        }
    }
    Ok(periods.map(|p| p.is_some()))
}

/// The wall sites of a surface folded into one period along each periodic axis: a site at x
/// outside `[lower, lower + P)` moves to its image x − nP inside. A site whose lattice cell
/// a site already inside the period holds is dropped, so a surface drawn wider than the
/// period (its edges beyond the seam) gives one period of the infinite surface, and an
/// obstacle that straddles the seam keeps its part on either side. Sites lie on the lattice
/// (x/dx − ½ whole) and P is a whole number of dx, so an image lies on the lattice too.
pub(crate) fn fold_sites<const D: usize>(
    sites: Vec<WallSite<D>>,
    periods: &[Option<(Real, Real)>; D],
    dx: Real,
) -> Vec<WallSite<D>> {
    if periods.iter().all(Option::is_none) {
        return sites;
    }
    let inside = |x: &Vector<D>| {
        (0..D).all(|k| {
            periods[k].is_none_or(|(lower, period)| x[k] >= lower && x[k] < lower + period)
        })
    };
    let key =
        |x: &Vector<D>| -> [i64; D] { std::array::from_fn(|k| (x[k] / dx - 0.5).round() as i64) };
    let (mut folded, outside): (Vec<_>, Vec<_>) =
        sites.into_iter().partition(|site| inside(&site.position));
    let mut taken: std::collections::HashSet<[i64; D]> =
        folded.iter().map(|site| key(&site.position)).collect();
    for mut site in outside {
        for (k, &(lower, period)) in periods
            .iter()
            .enumerate()
            .filter_map(|(k, p)| Some((k, p.as_ref()?)))
        {
            site.position[k] -= ((site.position[k] - lower) / period).floor() * period;
        }
        if taken.insert(key(&site.position)) {
            folded.push(site);
        }
    }
    folded
}

#[cfg(test)]
mod tests {
    use super::*;

    fn site(x: [Real; 2]) -> WallSite<2> {
        WallSite {
            position: Vector::<2>::from(x),
            normal: Vector::<2>::new(0.0, 1.0),
            depth: 0.5,
        }
    }

    /// A row of sites drawn over 1.5 periods (P = 4 dx) folds into the period's four cells,
    /// each once, keeping the sites first found inside; an axis that is not periodic is left
    /// alone.
    #[test]
    fn a_surface_wider_than_the_period_folds_into_one_period() {
        let dx = 0.5;
        let sites: Vec<_> = (-2..10)
            .map(|i| site([(i as Real + 0.5) * dx, 7.25]))
            .collect();
        let folded = fold_sites(sites, &[Some((0.0, 2.0)), None], dx);
        let mut x: Vec<Real> = folded.iter().map(|s| s.position[0]).collect();
        x.sort_by(Real::total_cmp);
        assert_eq!(x.len(), 4);
        for (i, x) in x.iter().enumerate() {
            assert!((x - (i as Real + 0.5) * dx).abs() < 1e-12, "{x}");
        }
        assert!(folded.iter().all(|s| s.position[1] == 7.25));
    }

    /// An obstacle straddling the seam keeps both of its parts.
    #[test]
    fn an_obstacle_across_the_seam_keeps_both_parts() {
        let dx = 0.5;
        let sites = vec![site([1.75, 0.25]), site([2.25, 0.25]), site([2.75, 0.25])];
        let folded = fold_sites(sites, &[Some((0.0, 2.0)), None], dx);
        let mut x: Vec<Real> = folded.iter().map(|s| s.position[0]).collect();
        x.sort_by(Real::total_cmp);
        assert_eq!(x.len(), 3);
        assert!((x[0] - 0.25).abs() < 1e-12 && (x[1] - 0.75).abs() < 1e-12);
        assert!((x[2] - 1.75).abs() < 1e-12);
    }
}
