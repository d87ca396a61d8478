//! The experimental curves of Martin & Moyce (1952) and Lobovsky et al. (2014), embedded from
//! `data/validation/`.

pub use geosph_io::ReferenceCurve;

/// Surge front Z = x/a against T = t √(2g/a) (Martin & Moyce 1952, Part IV, n² = 2).
pub fn martin_moyce_front() -> ReferenceCurve {
    ReferenceCurve::from_csv(include_str!(
        "../../../data/validation/martin-moyce-1952-surge-front.csv"
    ))
}

/// Column height H = h/(2a) against τ = t √(g/a) (Martin & Moyce 1952, Part IV, n² = 2).
pub fn martin_moyce_column_height() -> ReferenceCurve {
    ReferenceCurve::from_csv(include_str!(
        "../../../data/validation/martin-moyce-1952-column-height.csv"
    ))
}

/// Wall pressure p/(ρ g H) against t √(g/H) of Lobovsky, Botia-Vera, Castellana, Mas-Soler &
/// Souto-Iglesias (2014, J. Fluids Struct. 48:407, H = 0.3 m) at sensor 1 (3 mm above the
/// bed), 3 (30 mm) and 4 (80 mm) on the downstream wall, in that order.
pub fn lobovsky_wall_pressure() -> [ReferenceCurve; 3] {
    [
        ReferenceCurve::from_csv(include_str!(
            "../../../data/validation/lobovsky-2014-sensor1-z3mm.csv"
        )),
        ReferenceCurve::from_csv(include_str!(
            "../../../data/validation/lobovsky-2014-sensor3-z30mm.csv"
        )),
        ReferenceCurve::from_csv(include_str!(
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
