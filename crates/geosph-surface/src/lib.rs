//! Free surfaces of SPH particle sets, for viewing: a closed triangle mesh around the
//! particles, the level set of their kernel-smoothed density.
//!
//! The density field ρ(x) = Σ_j m_j W(x − x_j), with each particle standing for the volume
//! dx^D of the lattice it started on, is sampled on a background grid of cubes and its level
//! set ρ = c ρ₀ (c the `threshold`, 0.6 by default) triangulated by marching cubes (Lorensen
//! & Cline 1987), the method of Akinci, Ihmsen, Akinci, Solenthaler & Teschner (2012,
//! "Parallel surface reconstruction for particle-based fluids", Comput. Graph. Forum
//! 31:1797–1809) as `splashsurf_lib` implements it: subdomains reconstructed in turn (on one
//! thread, so that the surface is the same bit for bit for any number of threads) and
//! stitched into one closed mesh. Anisotropic kernels (Yu & Turk 2013) are not applied, so
//! thin sheets and jets look thicker than they are by about one kernel radius.
//!
//! # Example
//!
//! The surface of a cube of 20³ particles is closed and encloses about its volume:
//!
//! ```
//! use geosph_core::Vector;
//! use geosph_surface::{SurfaceParameters, reconstruct};
//!
//! let dx = 0.01;
//! let particles: Vec<Vector<3>> = (0..8000)
//!     .map(|k| Vector::<3>::new((k % 20) as f64, (k / 20 % 20) as f64, (k / 400) as f64))
//!     .map(|index| (index + Vector::<3>::repeat(0.5)) * dx)
//!     .collect();
//! let surface = reconstruct(&particles, &SurfaceParameters::new(dx))?;
//! surface.check_closed()?;
//! assert!((surface.signed_volume() / 0.2f64.powi(3) - 1.0).abs() < 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

use geosph_core::{Real, Vector};
use geosph_geometry::SurfaceMesh;
use splashsurf_lib::nalgebra::Vector3;

/// How the surface is drawn, in units of the particle spacing dx.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceParameters {
    /// The particle spacing dx in m; each particle stands for the volume dx³.
    pub dx: Real,
    /// The compact support radius of the smoothing kernel, in dx (default 2.5: a particle's
    /// own kernel reach).
    pub support: Real,
    /// The edge of the marching cubes, in dx (default 0.5).
    pub cube: Real,
    /// The level set drawn, as a fraction of the rest density (default 0.6).
    pub threshold: Real,
}

impl SurfaceParameters {
    /// The defaults for particles of spacing `dx`.
    pub fn new(dx: Real) -> Self {
        Self {
            dx,
            support: 2.5,
            cube: 0.5,
            threshold: 0.6,
        }
    }
}

/// Why a surface could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    /// The reconstruction failed (e.g. a grid too large for its index type).
    #[error("free-surface reconstruction: {0}")]
    Reconstruction(String),
}

/// The closed surface around `positions`: triangles counter-clockwise seen from outside (an
/// outward-oriented mesh, so [`SurfaceMesh::signed_volume`] is the enclosed volume). Empty
/// when there are no particles.
pub fn reconstruct(
    positions: &[Vector<3>],
    parameters: &SurfaceParameters,
) -> Result<SurfaceMesh, SurfaceError> {
    let empty = || SurfaceMesh {
        name: "free surface".into(),
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    if positions.is_empty() {
        return Ok(empty());
    }
    let dx = parameters.dx;
    // The radius of the sphere of volume dx³.
    let particle_radius = dx * (3.0 / (4.0 * std::f64::consts::PI)).cbrt();
    let mut settings = splashsurf_lib::Parameters::new(
        particle_radius,
        parameters.support * dx,
        parameters.cube * dx,
    );
    settings.iso_surface_threshold = parameters.threshold;
    // splashsurf's parallel subdomains differ in the last bit with the thread count; one
    // thread keeps every output file the same for any number of threads.
    settings.enable_multi_threading = false;
    let points: Vec<Vector3<Real>> = positions
        .iter()
        .map(|x| Vector3::new(x[0], x[1], x[2]))
        .collect();
    let reconstruction = splashsurf_lib::reconstruct_surface::<i64, Real>(&points, &settings)
        .map_err(|error| SurfaceError::Reconstruction(format!("{error:#}")))?;
    let mesh = reconstruction.mesh;
    // As marching cubes made it: dropping its degenerate triangles would open the surface.
    Ok(SurfaceMesh {
        name: "free surface".into(),
        vertices: mesh
            .vertices
            .iter()
            .map(|v| Vector::<3>::new(v.x, v.y, v.z))
            .collect(),
        triangles: mesh.triangles.iter().map(|t| t.map(|v| v as u32)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The particles of a lattice of spacing `dx` whose sites lie in the ball of `radius`.
    fn ball(radius: Real, dx: Real) -> Vec<Vector<3>> {
        let n = (radius / dx).ceil() as i64;
        let mut positions = Vec::new();
        for i in -n..n {
            for j in -n..n {
                for k in -n..n {
                    let x = Vector::<3>::new(i as Real, j as Real, k as Real).add_scalar(0.5) * dx;
                    if x.norm() < radius {
                        positions.push(x);
                    }
                }
            }
        }
        positions
    }

    #[test]
    fn a_ball_of_particles_gets_a_closed_outward_surface_at_its_radius() {
        // A ball of radius 0.1 m at dx = 5 mm (about 33 500 particles).
        let (radius, dx) = (0.1, 0.005);
        let positions = ball(radius, dx);
        let surface = reconstruct(&positions, &SurfaceParameters::new(dx)).unwrap();
        surface.check_closed().unwrap();
        let volume = surface.signed_volume();
        let exact = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
        let radii: Vec<Real> = surface.vertices.iter().map(|v| v.norm()).collect();
        let (lo, hi) = radii
            .iter()
            .fold((Real::INFINITY, 0.0 as Real), |(lo, hi), &r| {
                (lo.min(r), hi.max(r))
            });
        println!(
            "{} particles, {} triangles, volume {:.4e} against {exact:.4e}, radius {lo:.4}…{hi:.4}",
            positions.len(),
            surface.triangles.len(),
            volume
        );
        // The surface lies within half a particle spacing of the ball's sphere (the
        // particles' own resolution), so the volume within 3 × dx/2 / R = 7.5 %.
        assert!(
            lo > radius - dx / 2.0 && hi < radius + dx / 2.0,
            "{lo} {hi}"
        );
        assert!((volume / exact - 1.0).abs() < 1.5 * dx / radius);
    }

    #[test]
    fn no_particles_give_an_empty_surface() {
        let surface = reconstruct(&[], &SurfaceParameters::new(0.01)).unwrap();
        assert!(surface.vertices.is_empty() && surface.triangles.is_empty());
    }
}
