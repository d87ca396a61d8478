//! Measured reference curves embedded from `data/validation/` (the apps compare with them).

use geosph_core::Real;

/// A reference curve: points (x, y) in the order of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceCurve {
    /// Abscissae.
    pub x: Vec<Real>,
    /// Ordinates.
    pub y: Vec<Real>,
}

impl ReferenceCurve {
    /// The first two columns of a CSV text with a header line and `#` comment lines; rows
    /// whose first two fields are not numbers are skipped.
    pub fn from_csv(text: &str) -> Self {
        let mut curve = Self {
            x: Vec::new(),
            y: Vec::new(),
        };
        for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let mut values = line.split(',').map(|v| v.trim().parse::<Real>());
            if let (Some(Ok(x)), Some(Ok(y))) = (values.next(), values.next()) {
                curve.x.push(x);
                curve.y.push(y);
            }
        }
        curve
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_two_columns_after_comments_and_header() {
        let curve = ReferenceCurve::from_csv("# source\nx,y\n0.5, 1\nbad,2\n1.5,3,9\n");
        assert_eq!(curve.x, [0.5, 1.5]);
        assert_eq!(curve.y, [1.0, 3.0]);
    }
}
