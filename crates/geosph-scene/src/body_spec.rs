//! The rigid bodies of a scene file and their checks.

use geosph_core::Real;
use serde::{Deserialize, Serialize};

use crate::checks::{MAX_NAME_LENGTH, boxed, fail, in_range, mesh_placement, plain_name};
use crate::error::SceneError;

/// A rigid body: dummy wall particles that move with it, pushed by the fluid's pressure and
/// held by gravity and its contacts with the walls and the other bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Its name, for the diagnostics' columns (`<name>_x`, …).
    pub name: String,
    /// Its shape, closed.
    pub shape: BodyShape,
    /// Density ρ_b in kg/m³ (its mass is ρ_b times its volume; 2D: per metre).
    pub density: Real,
    /// Coulomb friction coefficient of its contacts with walls and bodies (default 0.5).
    #[serde(default = "default_friction")]
    pub friction: Real,
    /// Thickness of its dummy particles in lattice spacings (default 3; at least support
    /// radius / dx).
    #[serde(default = "default_layers")]
    pub layers: usize,
}

fn default_friction() -> Real {
    0.5
}

fn default_layers() -> usize {
    3
}

/// The shape of a body at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum BodyShape {
    /// The box [min, max].
    Box {
        /// Lower corner.
        min: Vec<Real>,
        /// Upper corner.
        max: Vec<Real>,
    },
    /// A closed surface mesh (`.stl`, `.obj`), placed as a mesh region is; in 2D its section
    /// y = `section`.
    Mesh {
        /// The mesh file, relative to the scene file's folder.
        file: String,
        /// Scale factor (default 1).
        #[serde(default = "default_scale")]
        scale: Real,
        /// Offset after scaling, one number per scene dimension (default zero).
        #[serde(default)]
        offset: Vec<Real>,
        /// 2D scenes: the mesh's y of the section plane (default 0).
        #[serde(default)]
        section: Real,
    },
}

fn default_scale() -> Real {
    1.0
}

/// Checks a scene's `bodies` (of a soil scene when `soil`; `needed` layers span the kernel's
/// support).
pub(crate) fn validate(
    bodies: &[BodySpec],
    dimension: usize,
    soil: bool,
    needed: usize,
) -> Result<(), SceneError> {
    if !bodies.is_empty() && soil {
        return Err(fail(
            "bodies",
            "rigid bodies are moved by the fluid's pressure and need a fluid solver (wcsph, \
             pcisph, iisph or dfsph)",
        ));
    }
    for (k, body) in bodies.iter().enumerate() {
        let field = format!("bodies[{k}]");
        if !plain_name(&body.name) {
            return Err(fail(
                format!("{field}.name"),
                format!(
                    "must be 1 to {MAX_NAME_LENGTH} letters, digits, '-', '_' or '.', as it \
                     names CSV columns; got {:?}",
                    body.name
                ),
            ));
        }
        if bodies[..k].iter().any(|other| other.name == body.name) {
            return Err(fail(
                format!("{field}.name"),
                format!("must be unique, {:?} is used twice", body.name),
            ));
        }
        in_range(&format!("{field}.density"), body.density, 1.0, 1e5)?;
        in_range(&format!("{field}.friction"), body.friction, 0.0, 10.0)?;
        if !(needed..=10).contains(&body.layers) {
            return Err(fail(
                format!("{field}.layers"),
                format!(
                    "must lie in [{needed}, 10] (the kernel support in dx), got {}",
                    body.layers
                ),
            ));
        }
        match &body.shape {
            BodyShape::Box { min, max } => boxed(&format!("{field}.shape"), min, max, dimension)?,
            BodyShape::Mesh {
                file,
                scale,
                offset,
                section,
            } => mesh_placement(
                &format!("{field}.shape"),
                file,
                *scale,
                offset,
                *section,
                dimension,
            )?,
        }
    }
    Ok(())
}
