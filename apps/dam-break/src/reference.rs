//! The experimental curves of Martin & Moyce (1952), Lobovsky et al. (2014) and Kleefsman et
//! al. (2005), embedded from `data/validation/`.

use geosph_core::Real;
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
        include_str!("../../../data/validation/lobovsky-2014-sensor1-z3mm.csv"),
        include_str!("../../../data/validation/lobovsky-2014-sensor3-z30mm.csv"),
        include_str!("../../../data/validation/lobovsky-2014-sensor4-z80mm.csv"),
    ]
    .map(ReferenceCurve::from_csv)
}

/// Pressure p/(ρ g H) against t √(g/H) on the box obstacle of Kleefsman, Fekken, Veldman,
/// Iwanowski & Buchner (2005, J. Comput. Phys. 206:363, SPHERIC test 2, H = 0.55 m) at P1
/// (0.021 m above the floor on the box's front face) and P3 (0.101 m), in that order: the
/// measured record (`data/validation/kleefsman-2005-record-p1-p3.csv`, sampled every 1 ms)
/// scaled with ρ = 1000 kg/m³ and g = 9.81 m/s².
pub fn kleefsman_obstacle_pressure() -> [ReferenceCurve; 2] {
    let depth: Real = 0.55;
    let time_scale = (9.81 / depth).sqrt();
    let pressure_scale = 1.0 / (1000.0 * 9.81 * depth);
    [1, 2].map(|column| {
        ReferenceCurve::from_csv_columns(KLEEFSMAN_2005_RECORD, 0, column)
            .scaled(time_scale, pressure_scale)
    })
}

/// The SPHERIC test 2 record of Kleefsman et al. (2005): t (s), then the pressure (Pa) at P1
/// and P3, to t = 2 s.
const KLEEFSMAN_2005_RECORD: &str =
    include_str!("../../../data/validation/kleefsman-2005-record-p1-p3.csv");

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
        let lengths = kleefsman_obstacle_pressure().map(|curve| curve.x.len());
        assert_eq!(lengths, [2000, 2000]);
    }
}
