//! Terrain from a height grid in the ESRI ASCII raster format (`.asc`), triangulated.
//!
//! The format (ESRI, "ESRI ASCII raster format", ArcGIS documentation): a header of
//! `ncols`, `nrows`, `xllcorner` or `xllcenter`, `yllcorner` or `yllcenter`, `cellsize` and an
//! optional `NODATA_value` (default −9999), then `nrows` rows of `ncols` elevations, the first
//! row the northernmost (largest y). Each value is the elevation at its cell's centre;
//! `xllcorner` gives the lower-left corner of the lower-left cell, `xllcenter` its centre.

use std::path::Path;

use geosph_core::{Real, Vector};

/// The most cells a grid may have (a header that asks for more is refused before anything
/// is allocated).
const MAX_CELLS: usize = 10_000_000;

/// The vertices (cell centres at their elevation) and triangles (each square of four centres
/// split into two, counter-clockwise seen from above; a triangle with a missing value at one
/// of its centres is left out) of the grid in `text`; an error naming the header line or the
/// value that is wrong.
pub(crate) fn triangulate(text: &str) -> Result<(Vec<Vector<3>>, Vec<[u32; 3]>), String> {
    let mut lines = text.lines().enumerate().peekable();
    let mut header = std::collections::HashMap::new();
    while let Some((number, line)) = lines.peek() {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else {
            lines.next();
            continue;
        };
        if key.parse::<Real>().is_ok() {
            break;
        }
        let key = key.to_ascii_lowercase();
        let value = words
            .next()
            .and_then(|v| v.parse::<Real>().ok())
            .ok_or_else(|| format!("line {}: `{key}` needs a number", number + 1))?;
        header.insert(key, value);
        lines.next();
    }
    let get = |keys: &[&str]| {
        keys.iter()
            .find_map(|&k| header.get(k).map(|&v| (k.to_owned(), v)))
    };
    let count = |key: &str| match get(&[key]) {
        Some((_, v)) if v >= 2.0 && v.fract() == 0.0 && v <= 1e5 => Ok(v as usize),
        Some((_, v)) => Err(format!(
            "`{key}` must be a whole number from 2 to 100000, got {v}"
        )),
        None => Err(format!("the header has no `{key}`")),
    };
    let (ncols, nrows) = (count("ncols")?, count("nrows")?);
    if ncols * nrows > MAX_CELLS {
        return Err(format!(
            "{nrows} rows of {ncols} values: more than {MAX_CELLS} cells (cellsize in the wrong unit?)"
        ));
    }
    let corner = |axis: &str| match get(&[&format!("{axis}llcorner"), &format!("{axis}llcenter")]) {
        Some(_)
            if header.contains_key(&format!("{axis}llcorner"))
                && header.contains_key(&format!("{axis}llcenter")) =>
        {
            Err(format!(
                "the header gives both `{axis}llcorner` and `{axis}llcenter`"
            ))
        }
        Some((key, v)) if v.is_finite() => Ok((v, key.ends_with("corner"))),
        Some((key, v)) => Err(format!("`{key}` must be finite, got {v}")),
        None => Err(format!(
            "the header has no `{axis}llcorner` or `{axis}llcenter`"
        )),
    };
    let ((x0, x_corner), (y0, y_corner)) = (corner("x")?, corner("y")?);
    let cell = match get(&["cellsize"]) {
        Some((_, v)) if v > 0.0 && v.is_finite() => v,
        Some((_, v)) => return Err(format!("`cellsize` must be a finite number > 0, got {v}")),
        None => return Err("the header has no `cellsize`".into()),
    };
    let no_data = get(&["nodata_value"]).map_or(Some(-9999.0), |(_, v)| Some(v));
    let mut elevation = Vec::with_capacity(ncols * nrows);
    for (number, line) in lines {
        for word in line.split_whitespace() {
            let z: Real = word
                .parse()
                .ok()
                .filter(|z: &Real| z.is_finite())
                .ok_or_else(|| format!("line {}: `{word}` is not an elevation", number + 1))?;
            elevation.push((Some(z) != no_data).then_some(z));
        }
    }
    if elevation.len() != ncols * nrows {
        return Err(format!(
            "{nrows} rows of {ncols} values = {} elevations expected, {} found",
            ncols * nrows,
            elevation.len()
        ));
    }
    // Cell centres: column j east, row i from the north.
    let centre = |i: usize, j: usize| {
        let x = x0 + (j as Real + if x_corner { 0.5 } else { 0.0 }) * cell;
        let y = y0 + ((nrows - 1 - i) as Real + if y_corner { 0.5 } else { 0.0 }) * cell;
        (x, y)
    };
    let mut index = vec![u32::MAX; ncols * nrows];
    let mut vertices = Vec::new();
    let mut vertex = |k: usize, vertices: &mut Vec<Vector<3>>| {
        if index[k] == u32::MAX {
            let (x, y) = centre(k / ncols, k % ncols);
            index[k] = vertices.len() as u32;
            vertices.push(Vector::<3>::new(x, y, elevation[k].unwrap_or(0.0)));
        }
        index[k]
    };
    let mut triangles = Vec::new();
    for i in 0..nrows - 1 {
        for j in 0..ncols - 1 {
            let (nw, ne) = (i * ncols + j, i * ncols + j + 1);
            let (sw, se) = (nw + ncols, ne + ncols);
            for triangle in [[sw, se, ne], [sw, ne, nw]] {
                if triangle.iter().all(|&k| elevation[k].is_some()) {
                    triangles.push(triangle.map(|k| vertex(k, &mut vertices)));
                }
            }
        }
    }
    Ok((vertices, triangles))
}

/// Reads the grid at `path` (see [`triangulate`]).
pub(crate) fn read(path: &Path) -> Result<(Vec<Vector<3>>, Vec<[u32; 3]>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    triangulate(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLOPE: &str = "ncols 3\nnrows 2\nxllcorner 10.0\nyllcorner 20.0\ncellsize 2.0\n\
                         NODATA_value -9999\n4.0 5.0 6.0\n2.0 3.0 -9999\n";

    #[test]
    fn a_grid_becomes_cell_centres_and_upward_triangles_without_its_missing_values() {
        let (vertices, triangles) = triangulate(SLOPE).unwrap();
        // Two squares of centres; the east one lacks its south-east corner: 3 triangles.
        assert_eq!(triangles.len(), 3);
        assert_eq!(vertices.len(), 5);
        // The first row is the north one: (11, 23) at 4 m; the south-west centre (11, 21) at 2 m.
        assert!(vertices.contains(&Vector::<3>::new(11.0, 23.0, 4.0)));
        assert!(vertices.contains(&Vector::<3>::new(11.0, 21.0, 2.0)));
        for [a, b, c] in &triangles {
            let [a, b, c] = [a, b, c].map(|&v| vertices[v as usize]);
            assert!((b - a).cross(&(c - a))[2] > 0.0, "a triangle faces down");
        }
    }

    #[test]
    fn cell_centre_origins_give_the_same_terrain_and_nodata_defaults_to_minus_9999() {
        let centred = SLOPE
            .replace("xllcorner 10.0", "xllcenter 11.0")
            .replace("yllcorner 20.0", "yllcenter 21.0")
            .replace("NODATA_value -9999\n", "");
        assert_eq!(triangulate(&centred).unwrap(), triangulate(SLOPE).unwrap());
    }

    #[test]
    fn bad_grids_are_refused_naming_the_problem() {
        let cases = [
            (SLOPE.replace("ncols 3\n", ""), "the header has no `ncols`"),
            (
                SLOPE.replace("cellsize 2.0", "cellsize -1"),
                "`cellsize` must be",
            ),
            (
                SLOPE.replace("3.0 -9999", "3.0"),
                "6 elevations expected, 5 found",
            ),
            (
                SLOPE.replace("5.0", "five"),
                "line 7: `five` is not an elevation",
            ),
            (
                SLOPE.replace("nrows 2", "nrows x"),
                "line 2: `nrows` needs a number",
            ),
            (
                SLOPE.replace("nrows 2", "nrows 100000\nncols 100000"),
                "more than 10000000 cells",
            ),
            (
                SLOPE.replace("cellsize", "xllcenter 11.0\ncellsize"),
                "both `xllcorner` and `xllcenter`",
            ),
        ];
        for (text, expected) in cases {
            let error = triangulate(&text).unwrap_err();
            assert!(error.contains(expected), "{error}");
        }
    }
}
