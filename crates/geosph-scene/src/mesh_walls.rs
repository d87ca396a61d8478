//! Mesh walls: the dummy particles behind a surface mesh, folded into the period of a
//! periodic domain, and the quadrature of the load gauges that integrate over the mesh.

use geosph_boundary::WallParticles;
use geosph_core::{Real, Vector};
use geosph_geometry::{Section, SurfacePoint, WallSite, WallSurface};

use crate::error::SceneError;
use crate::format::{LoadSpec, Scene};
use crate::initial::vector;
use crate::periodic::{beyond_period, fold_sites, lattice_cell, periods};
use crate::regions::{check_size, read_mesh};

/// The surface a load gauge integrates the fluid's pressure, or the soil's stress, over.
#[derive(Clone, Debug)]
pub struct LoadSurface<const D: usize> {
    /// The gauge's name.
    pub name: String,
    /// Quadrature points on the wall's surface, dx/2 apart, normals into the flow.
    pub points: Vec<SurfacePoint<D>>,
    /// The point moments are taken about.
    pub about: Vector<D>,
}

/// The dummy particles behind the mesh wall `field`
/// ([`WallSpec::Mesh`](crate::format::WallSpec::Mesh)), placed by its file, scale, offset
/// and section; sites an `earlier` wall holds are not filled again.
pub(crate) fn mesh_walls<const D: usize>(
    scene: &Scene,
    field: &str,
    (file, scale, offset, section): (&str, Real, &[Real], Real),
    layers: usize,
    rest_density: Real,
    earlier: &[Vector<D>],
) -> Result<(WallParticles<D>, WallSurface), SceneError> {
    let fail = |message: String| SceneError::Field {
        field: field.to_owned(),
        message,
    };
    let dx = scene.dx;
    let thickness = layers as Real * dx;
    let mesh = read_mesh::<D>(file, scale, offset, scene.folder.as_deref()).map_err(fail)?;
    check_size::<D>(&mesh, dx, thickness).map_err(fail)?;
    let surface = WallSurface::new(mesh).map_err(|error| fail(error.to_string()))?;
    let sites: Vec<WallSite<D>> = if D == 2 {
        let section = Section::at_y(section);
        let sites = surface.wall_sites_in_section(&section, &Vector::<2>::zeros(), dx, thickness);
        sites.iter().map(WallSite::recast).collect()
    } else {
        let sites = surface.wall_sites(&Vector::<3>::zeros(), dx, thickness);
        sites.iter().map(WallSite::recast).collect()
    };
    // Across a periodic axis, one period of the surface (e.g. a gate across a slab).
    let sites = fold_sites(sites, &periods::<D>(scene, field)?, dx);
    // A site an earlier wall holds (where a barrier mesh meets a terrain mesh) is not
    // filled twice.
    let key = |x: &Vector<D>| lattice_cell(x, dx);
    let taken: std::collections::HashSet<[i64; D]> = earlier
        .iter()
        .filter(|x| (0..D).all(|k| ((x[k] / dx - 0.5) - (x[k] / dx - 0.5).round()).abs() < 1e-6))
        .map(key)
        .collect();
    let (position, normal, depth): (Vec<Vector<D>>, Vec<Vector<D>>, Vec<Real>) = sites
        .into_iter()
        .filter(|site| !taken.contains(&key(&site.position)))
        .map(|site| (site.position, site.normal, site.depth))
        .collect();
    if position.is_empty() {
        return Err(fail(format!(
            "the mesh `{}` has no lattice site behind it at dx = {dx}{}",
            surface.mesh().name,
            if D == 2 {
                ": move the section plane into the mesh"
            } else {
                ""
            }
        )));
    }
    let particles = WallParticles::fixed(position, normal, depth, dx.powi(D as i32), rest_density);
    Ok((particles, surface))
}

/// Refuses a mesh wall that reaches beyond a period of the domain when a load gauge
/// integrates over it: the gauge uses the mesh as drawn, which [`fold_sites`] folds only for
/// the wall's particles.
pub(crate) fn unfolded<const D: usize>(
    scene: &Scene,
    index: usize,
    surface: &WallSurface,
) -> Result<(), SceneError> {
    let field = format!("walls[{index}]");
    let (lo, hi) = surface.mesh().bounds();
    let plane = |x: Vector<3>| {
        if D == 2 {
            vec![x[0], x[2]]
        } else {
            x.as_slice().to_vec()
        }
    };
    let (lo, hi) = (plane(lo), plane(hi));
    let periods = periods::<D>(scene, &field)?;
    match beyond_period::<D>((&lo, &hi), &periods, 1e-9 * scene.dx) {
        Some(k) => Err(SceneError::Field {
            field,
            message: format!(
                "the mesh reaches beyond the domain's period on axis {k}: its wall particles \
                 are folded into the period but a load gauge would integrate over the mesh \
                 as drawn; draw it within one period"
            ),
        }),
        None => Ok(()),
    }
}

/// The quadrature of a load gauge on `surface`, points dx/2 apart.
pub(crate) fn load_surface<const D: usize>(
    spec: &LoadSpec,
    surface: &WallSurface,
    section: Real,
    dx: Real,
) -> LoadSurface<D> {
    let points: Vec<SurfacePoint<D>> = if D == 2 {
        let points = surface.section_quadrature(&Section::at_y(section), 0.5 * dx);
        points.iter().map(SurfacePoint::recast).collect()
    } else {
        let points = surface.quadrature(0.5 * dx);
        points.iter().map(SurfacePoint::recast).collect()
    };
    let area: Real = points.iter().map(|p| p.area).sum();
    let about = match &spec.about {
        Some(about) => vector::<D>(about),
        None => {
            points
                .iter()
                .map(|p| p.position * p.area)
                .sum::<Vector<D>>()
                / area
        }
    };
    LoadSurface {
        name: spec.name.clone(),
        points,
        about,
    }
}
