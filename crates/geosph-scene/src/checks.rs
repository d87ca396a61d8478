//! Range checks shared by the scene's validation, each failing with the field's path.

use geosph_core::Real;

use crate::error::SceneError;

/// Longest scene name (it becomes part of output file names).
pub const MAX_NAME_LENGTH: usize = 100;

pub(crate) fn fail(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Field {
        field: field.into(),
        message: message.into(),
    }
}

pub(crate) fn positive(field: &str, value: Real) -> Result<(), SceneError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(fail(
            field,
            format!("must be a finite number > 0, got {value}"),
        ))
    }
}

pub(crate) fn in_range(field: &str, value: Real, low: Real, high: Real) -> Result<(), SceneError> {
    if value.is_finite() && value >= low && value <= high {
        Ok(())
    } else {
        Err(fail(
            field,
            format!("must lie in [{low}, {high}], got {value}"),
        ))
    }
}

/// The name of a gauge that names CSV columns: plain ([`plain_name`]) and unlike every name in
/// `earlier`, the gauges before it in its list (`field` is the gauge's, e.g.
/// `output.probes[2]`).
pub(crate) fn column_name<'a>(
    field: &str,
    name: &str,
    mut earlier: impl Iterator<Item = &'a str>,
) -> Result<(), SceneError> {
    if !plain_name(name) {
        return Err(fail(
            format!("{field}.name"),
            format!(
                "must be 1 to {MAX_NAME_LENGTH} letters, digits, '-', '_' or '.', as it names \
                 CSV columns; got {name:?}"
            ),
        ));
    }
    if earlier.any(|other| other == name) {
        return Err(fail(
            format!("{field}.name"),
            format!("must be unique, {name:?} is used twice"),
        ));
    }
    Ok(())
}

/// 1 to [`MAX_NAME_LENGTH`] ASCII letters, digits, '-', '_' or '.': safe in a file name and
/// in a CSV header.
pub(crate) fn plain_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= MAX_NAME_LENGTH
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
}

pub(crate) fn point(field: &str, values: &[Real], dimension: usize) -> Result<(), SceneError> {
    if values.len() != dimension {
        return Err(fail(
            field,
            format!(
                "needs {dimension} coordinates (the scene's dimension), got {}",
                values.len()
            ),
        ));
    }
    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
        return Err(fail(
            field,
            format!("coordinates must be finite, got {bad}"),
        ));
    }
    Ok(())
}

/// The file and placement of a mesh region or wall.
pub(crate) fn mesh_placement(
    field: &str,
    file: &str,
    scale: Real,
    offset: &[Real],
    section: Real,
    dimension: usize,
) -> Result<(), SceneError> {
    if file.trim().is_empty() {
        return Err(fail(format!("{field}.file"), "names no file"));
    }
    positive(&format!("{field}.scale"), scale)?;
    if !offset.is_empty() {
        point(&format!("{field}.offset"), offset, dimension)?;
    }
    if !section.is_finite() || (dimension == 3 && section != 0.0) {
        return Err(fail(
            format!("{field}.section"),
            format!("is the section plane of a 2D scene: finite there, unset in 3D; got {section}"),
        ));
    }
    Ok(())
}

pub(crate) fn boxed(
    field: &str,
    min: &[Real],
    max: &[Real],
    dimension: usize,
) -> Result<(), SceneError> {
    point(&format!("{field}.min"), min, dimension)?;
    point(&format!("{field}.max"), max, dimension)?;
    for k in 0..dimension {
        if min[k] >= max[k] {
            return Err(fail(
                format!("{field}.max"),
                format!(
                    "must exceed min on axis {k}: min = {}, max = {}",
                    min[k], max[k]
                ),
            ));
        }
    }
    Ok(())
}
