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
        if rows.round() < 1.0 || (rows - rows.round()).abs() > 1e-6 * rows.max(1.0) {
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

/// The lattice cell of a point on the lattice aligned with the origin, sites at (i + ½) dx.
pub(crate) fn lattice_cell<const D: usize>(x: &Vector<D>, dx: Real) -> [i64; D] {
    std::array::from_fn(|k| (x[k] / dx - 0.5).round() as i64)
}

/// The wall sites of a surface (on the lattice aligned with the origin) folded into one
/// period along each periodic axis: a site in cell i outside the period's cells
/// i₀ … i₀ + n − 1 (n = P/dx, i₀ the first cell whose centre is at or above the period's
/// lower bound) moves to cell i₀ + (i − i₀) mod n. A site whose cell a site already inside
/// the period holds is dropped, so a surface drawn wider than the period (its edges beyond
/// the seam) gives one period of the infinite surface, and an obstacle that straddles the
/// seam keeps its part on either side. The folding is done on cell indices, so an image
/// lands exactly on a lattice site and inside the period.
pub(crate) fn fold_sites<const D: usize>(
    sites: Vec<WallSite<D>>,
    periods: &[Option<(Real, Real)>; D],
    dx: Real,
) -> Vec<WallSite<D>> {
    if periods.iter().all(Option::is_none) {
        return sites;
    }
    // Per periodic axis: the first cell of the period and the number of cells in it.
    let cells: [Option<(i64, i64)>; D] = periods.map(|period| {
        period.map(|(lower, period)| {
            let first = (lower / dx - 0.5 - 1e-9).ceil() as i64;
            (first, (period / dx).round() as i64)
        })
    });
    let fold = |cell: [i64; D]| -> [i64; D] {
        std::array::from_fn(|k| match cells[k] {
            Some((first, n)) => first + (cell[k] - first).rem_euclid(n),
            None => cell[k],
        })
    };
    let (mut folded, outside): (Vec<_>, Vec<_>) = sites.into_iter().partition(|site| {
        let cell = lattice_cell(&site.position, dx);
        fold(cell) == cell
    });
    let mut taken: std::collections::HashSet<[i64; D]> = folded
        .iter()
        .map(|site| lattice_cell(&site.position, dx))
        .collect();
    for mut site in outside {
        let cell = fold(lattice_cell(&site.position, dx));
        if taken.insert(cell) {
            for (k, &i) in cell.iter().enumerate() {
                if cells[k].is_some() {
                    site.position[k] = (i as Real + 0.5) * dx;
                }
            }
            folded.push(site);
        }
    }
    folded
}

/// The first periodic axis along which the box `[lo, hi]` reaches beyond the domain's
/// period by more than `tolerance`, if any.
pub(crate) fn beyond_period<const D: usize>(
    (lo, hi): (&[Real], &[Real]),
    periods: &[Option<(Real, Real)>; D],
    tolerance: Real,
) -> Option<usize> {
    (0..D).find(|&k| {
        periods[k].is_some_and(|(lower, period)| {
            lo[k] < lower - tolerance || hi[k] > lower + period + tolerance
        })
    })
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

    /// A period whose lower bound is negative and not a multiple of dx: every image lands on
    /// a cell centre inside the period.
    #[test]
    fn a_period_off_the_origin_folds_onto_its_own_cells() {
        let dx = 0.5;
        // The period [-0.6, 1.4): its cells have centres -0.25, 0.25, 0.75, 1.25.
        let sites: Vec<_> = (-6..8)
            .map(|i| site([(i as Real + 0.5) * dx, 0.25]))
            .collect();
        let folded = fold_sites(sites, &[Some((-0.6, 2.0)), None], dx);
        let mut x: Vec<Real> = folded.iter().map(|s| s.position[0]).collect();
        x.sort_by(Real::total_cmp);
        assert_eq!(x, vec![-0.25, 0.25, 0.75, 1.25]);
    }

    /// A 3D surface wider than the period on both periodic axes folds onto one period's cells.
    #[test]
    fn a_3d_plane_folds_along_two_axes() {
        let dx = 0.1;
        let mut sites = Vec::new();
        for i in -5..10 {
            for j in -3..12 {
                sites.push(WallSite {
                    position: Vector::<3>::new(
                        (i as Real + 0.5) * dx,
                        (j as Real + 0.5) * dx,
                        -0.05,
                    ),
                    normal: Vector::<3>::new(0.0, 0.0, 1.0),
                    depth: 0.05,
                });
            }
        }
        let periods = [Some((0.0, 0.4)), Some((-0.2, 0.6)), None];
        let folded = fold_sites(sites, &periods, dx);
        assert_eq!(folded.len(), 4 * 6);
        for site in &folded {
            assert!((0.0..0.4).contains(&site.position[0]), "{site:?}");
            assert!((-0.2..0.4).contains(&site.position[1]), "{site:?}");
        }
    }

    /// The shipped 3D slab's gate (`meshes/bui-slab-gate.obj`, drawn 0.15 m wide across a
    /// 12 mm period): its wall particles lie in the period, and every one of the six rows
    /// across y holds the same gate particles, so the gate closes the whole slab.
    #[test]
    fn the_shipped_slab_gate_closes_the_whole_period() {
        let mut scene = Scene::from_ron(include_str!(
            "../../../data/scenes/granular-collapse-3d.ron"
        ))
        .unwrap();
        scene.folder =
            Some(std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes"));
        let setup = crate::build::<3>(&scene).unwrap();
        let dx = scene.dx;
        let walls = &setup.walls.position;
        assert!(walls.iter().all(|x| (0.0..0.012).contains(&x[1])));
        let mut per_row = [0usize; 6];
        for x in walls
            .iter()
            .filter(|x| x[0] > 0.2 && x[0] < 0.2 + 3.0 * dx && x[2] > 0.0)
        {
            per_row[(x[1] / dx) as usize] += 1;
        }
        // 3 layers behind the plane, 60 rows up to z = 0.12 m, and the sites about its top edge.
        assert!(per_row[0] >= 3 * 60, "{per_row:?}");
        assert!(per_row.iter().all(|&n| n == per_row[0]), "{per_row:?}");
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
