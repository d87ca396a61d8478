//! The experimental curves of Martin & Moyce (1952) and Lobovsky et al. (2014), embedded from
//! `data/validation/`.

use geosph_core::Real;

/// A reference curve: points (x, y).
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceCurve {
    /// Abscissae.
    pub x: Vec<Real>,
    /// Ordinates.
    pub y: Vec<Real>,
}

/// Reads a two-column CSV with `#` comments and a header line.
fn parse(text: &str) -> ReferenceCurve {
    let mut curve = ReferenceCurve {
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

/// Surge front Z = x/a against T = t √(2g/a) (Martin & Moyce 1952, Part IV, n² = 2).
pub fn martin_moyce_front() -> ReferenceCurve {
    parse(include_str!(
        "../../../data/validation/martin-moyce-1952-surge-front.csv"
    ))
}

/// Column height H = h/(2a) against τ = t √(g/a) (Martin & Moyce 1952, Part IV, n² = 2).
pub fn martin_moyce_column_height() -> ReferenceCurve {
    parse(include_str!(
        "../../../data/validation/martin-moyce-1952-column-height.csv"
    ))
}

/// Wall pressure p/(ρ g H) against t √(g/H) of Lobovsky, Botia-Vera, Castellana, Mas-Soler &
/// Souto-Iglesias (2014, J. Fluids Struct. 48:407, H = 0.3 m) at sensor 1 (3 mm above the
/// bed), 3 (30 mm) and 4 (80 mm) on the downstream wall, in that order.
pub fn lobovsky_wall_pressure() -> [ReferenceCurve; 3] {
    [
        parse(include_str!(
            "../../../data/validation/lobovsky-2014-sensor1-z3mm.csv"
        )),
        parse(include_str!(
            "../../../data/validation/lobovsky-2014-sensor3-z30mm.csv"
        )),
        parse(include_str!(
            "../../../data/validation/lobovsky-2014-sensor4-z80mm.csv"
        )),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_tables_are_complete() {
        let front = martin_moyce_front();
        assert_eq!(front.x.len(), 15);
        assert_eq!((front.x[0], front.y[14]), (0.41, 4.11));
        let height = martin_moyce_column_height();
        assert_eq!(height.x.len(), 17);
        assert_eq!((height.x[16], height.y[0]), (7.40, 0.94));
        let lengths = lobovsky_wall_pressure().map(|curve| curve.x.len());
        assert_eq!(lengths, [61, 119, 58]);
    }
}
