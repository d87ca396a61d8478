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
        Self::from_csv_columns(text, 0, 1)
    }

    /// Columns `x` (abscissae) and `y` (ordinates), counted from 0, of a CSV text with a
    /// header line and `#` comment lines; rows whose two fields are not finite numbers are
    /// skipped.
    pub fn from_csv_columns(text: &str, x: usize, y: usize) -> Self {
        let mut curve = Self {
            x: Vec::new(),
            y: Vec::new(),
        };
        for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let value = |k: usize| {
                let v = line.split(',').nth(k)?.trim().parse::<Real>().ok()?;
                v.is_finite().then_some(v)
            };
            if let (Some(x), Some(y)) = (value(x), value(y)) {
                curve.x.push(x);
                curve.y.push(y);
            }
        }
        curve
    }

    /// The curve with its abscissae times `x` and its ordinates times `y` (e.g. from SI
    /// units to dimensionless ones).
    pub fn scaled(mut self, x: Real, y: Real) -> Self {
        self.x.iter_mut().for_each(|v| *v *= x);
        self.y.iter_mut().for_each(|v| *v *= y);
        self
    }

    /// The curve at `x0`, linearly interpolated ([`interpolate`]).
    pub fn at(&self, x0: Real) -> Option<Real> {
        interpolate(&self.x, &self.y, x0)
    }
}

/// Linear interpolation of the samples (x, y), x ascending, at `x0`; `None` outside their
/// range.
pub fn interpolate(x: &[Real], y: &[Real], x0: Real) -> Option<Real> {
    let k = x.partition_point(|&v| v < x0);
    if k == 0 {
        return (x.first() == Some(&x0)).then(|| y[0]);
    }
    if k == x.len() {
        return None;
    }
    let w = (x0 - x[k - 1]) / (x[k] - x[k - 1]);
    Some(y[k - 1] + w * (y[k] - y[k - 1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_two_columns_after_comments_and_header() {
        let curve = ReferenceCurve::from_csv("# source\nx,y\n0.5, 1\nbad,2\n1.5,3,9\n");
        assert_eq!(curve.x, [0.5, 1.5]);
        assert_eq!(curve.y, [1.0, 3.0]);
        let curve = ReferenceCurve::from_csv_columns("t,a,b\n1,2,3\n2,x,5\n3,4\n4,5,nan\n", 0, 2);
        assert_eq!(curve.x, [1.0, 2.0]);
        assert_eq!(curve.scaled(2.0, 0.5).y, [1.5, 2.5]);
    }

    #[test]
    fn interpolates_inside_and_is_none_outside() {
        let curve = ReferenceCurve {
            x: vec![0.0, 1.0, 3.0],
            y: vec![2.0, 4.0, 0.0],
        };
        assert_eq!(curve.at(0.0), Some(2.0));
        assert_eq!(curve.at(0.5), Some(3.0));
        assert_eq!(curve.at(2.0), Some(2.0));
        assert_eq!(curve.at(3.0), Some(0.0));
        assert_eq!(curve.at(-0.1), None);
        assert_eq!(curve.at(3.1), None);
    }
}
