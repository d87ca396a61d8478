//! The geostatic stage's stress check: each particle against the state that applies where it
//! is.
//!
//! - The **free field** (periodic or free-slip sides, or farther than the soil height H from a
//!   side wall that carries shear): the 1D state σ_v = −ρ₀ g d (d the depth below the top of
//!   the particle's column, the bins below) and σ_h/σ_v equal to the
//!   material's own oedometric ratio at that σ_v ([`OedometricRatio`]: ν/(1 − ν) while elastic,
//!   the ratio on the yield surface once the oedometric path reaches it).
//! - The **wall zone** (within H of a rough side wall), where the walls carry part of the weight
//!   by shear: the mean σ_v of each layer between two walls with friction tan δ against
//!   Janssen's (1895) arching, σ̄_v(z) = γB/(2Kμ)(1 − e^{−2Kμz/B}) (the slice equilibrium
//!   B dσ̄_v/dz = γB − 2μKσ̄_v of a layer of width B, with μ = tan δ fully mobilised and K the
//!   oedometric ratio), the least σ̄_v the walls' friction allows, while ρ₀ g z is the most.
//!
//! Only particles below the top three layers of their column are checked (columns are bins of
//! width dx across gravity).

use std::collections::HashMap;

use geosph_core::{Particles, Real, Tensor3, Vector};

use crate::constitutive::Constitutive;
use crate::element::{ElementTest, LoadingPath, run_element_test};
use crate::model::SoilModel;

/// The comparison of one zone with the 1D state.
#[derive(Clone, Debug, PartialEq)]
pub struct ZoneCheck {
    /// Particles checked.
    pub particles: usize,
    /// Largest |σ_v − σ_v,ref| / |σ_v,ref|, σ_v,ref = −ρ₀ g d with d the depth below the top
    /// of the particle's column (NaN without particles).
    pub vertical_stress_error_max: Real,
    /// Mean of the same error.
    pub vertical_stress_error_mean: Real,
    /// Mean σ_v / σ_v,ref (below 1 where walls carry weight).
    pub vertical_stress_ratio_mean: Real,
    /// Smallest, mean and largest σ_h/σ_v (σ_h the mean horizontal normal stress).
    pub lateral_ratio: (Real, Real, Real),
    /// Largest |σ_h/σ_v − K| / K with K the oedometric ratio at the particle's σ_v.
    pub lateral_ratio_error_max: Real,
}

/// The wall zone's layers against Janssen's arching.
#[derive(Clone, Debug, PartialEq)]
pub struct JanssenCheck {
    /// Layers compared (those bounded by a rough wall at both ends).
    pub layers: usize,
    /// Width B of the deepest compared layer, m.
    pub width: Real,
    /// μ = tan δ of the walls.
    pub wall_friction: Real,
    /// K, the oedometric ratio of the material.
    pub lateral_ratio: Real,
    /// Largest |σ̄_v − σ̄_v,Janssen| / (ρ₀ g z) over the layers.
    pub error_max: Real,
    /// At the deepest compared layer: σ̄_v / (ρ₀ g z) measured and Janssen's.
    pub deepest: (Real, Real),
    /// Layers whose σ̄_v lies outside [σ̄_v,Janssen, ρ₀ g z] by more than 1 % of ρ₀ g z.
    pub outside_bounds: usize,
}

/// The stress check of a geostatic state.
#[derive(Clone, Debug, PartialEq)]
pub struct StressCheck {
    /// Distance from a rough side wall beyond which a particle is free field (the soil
    /// height H), m; infinite when no wall carries shear.
    pub free_field_distance: Real,
    /// The free field against the 1D state.
    pub free_field: ZoneCheck,
    /// The wall zone against the 1D state (which does not apply there; for the record).
    pub wall_zone: ZoneCheck,
    /// The wall zone against Janssen (2D, friction walls on both sides of a layer).
    pub janssen: Option<JanssenCheck>,
}

/// σ_h/σ_v of the material on the oedometric path (ε_h = 0) as a function of σ_v, from the
/// element test of the scene's own constitutive model ([`crate::element`]).
pub struct OedometricRatio {
    /// (−σ_v, σ_h/σ_v) along the path, −σ_v increasing.
    path: Vec<(Real, Real)>,
    /// The compression the path was asked to reach, Pa.
    max_stress: Real,
}

impl OedometricRatio {
    /// The path of `model` up to the compression `max_stress` (positive, Pa).
    pub fn new(model: &SoilModel, max_stress: Real) -> Self {
        let mut axial_strain = 2.0 * max_stress / model.elastic().p_wave_modulus();
        loop {
            let test = ElementTest {
                initial_stress: Tensor3::zeros(),
                path: LoadingPath::Oedometer { axial_strain },
                steps: 2000,
            };
            let points = run_element_test(model, &test).expect("2000 steps");
            let path: Vec<(Real, Real)> = points[1..]
                .iter()
                .map(|p| (-p.stress[(1, 1)], p.stress[(0, 0)] / p.stress[(1, 1)]))
                .collect();
            if path.last().is_some_and(|&(s, _)| s >= max_stress) || axial_strain > 1.0 {
                return Self { path, max_stress };
            }
            axial_strain *= 4.0;
        }
    }

    /// The path of `model` for a column of unit weight γ and height H: up to 1.5 γH, half
    /// again the deepest 1D σ_v, for stresses the walls or the relaxation raise above it.
    pub fn for_column(model: &SoilModel, unit_weight: Real, height: Real) -> Self {
        Self::new(model, 1.5 * unit_weight * height)
    }

    /// The compression the path was asked to reach (positive, Pa).
    pub fn max_stress(&self) -> Real {
        self.max_stress
    }

    /// K at the compression `stress` (positive, Pa), interpolated along the path.
    pub fn at(&self, stress: Real) -> Real {
        let i = self.path.partition_point(|&(s, _)| s < stress);
        if i == 0 {
            return self.path[0].1;
        }
        let Some(&(s1, k1)) = self.path.get(i) else {
            return self.path[self.path.len() - 1].1;
        };
        let (s0, k0) = self.path[i - 1];
        k0 + (k1 - k0) * (stress - s0) / (s1 - s0)
    }
}

/// The particles binned into columns of width dx across gravity, with the height of each
/// column's top particle: the depth of a particle below the top of its column.
pub(crate) struct Columns<const D: usize> {
    down: Vector<D>,
    spacing: Real,
    /// The least coordinate of the particles across gravity: with gravity along a coordinate
    /// axis (every coordinate across it is then a lattice direction) the bins are centred on
    /// the particles' lattice, so that none sits on a bin's edge.
    origin: Vector<D>,
    /// Height (against gravity) of the highest particle of each column.
    top: HashMap<[i64; D], Real>,
}

impl<const D: usize> Columns<D> {
    /// The columns of the particles at `position`, `down` the unit vector along gravity.
    pub(crate) fn of(position: &[Vector<D>], down: Vector<D>, spacing: Real) -> Self {
        let origin = position
            .iter()
            .fold(Vector::<D>::repeat(Real::INFINITY), |low, x| {
                low.inf(&(x - down * x.dot(&down)))
            });
        let mut columns = Self {
            down,
            spacing,
            origin,
            top: HashMap::new(),
        };
        columns.top = columns.highest(position);
        columns
    }

    /// The height of the highest of `points` in each column (binned with these columns'
    /// origin: wall particles on the soil's lattice, or offset from it by whole spacings).
    pub(crate) fn highest(&self, points: &[Vector<D>]) -> HashMap<[i64; D], Real> {
        let mut top = HashMap::new();
        for x in points {
            let entry = top.entry(self.column(x)).or_insert(Real::NEG_INFINITY);
            *entry = Real::max(*entry, self.height_of(x));
        }
        top
    }

    /// Height of `x` against gravity.
    pub(crate) fn height_of(&self, x: &Vector<D>) -> Real {
        -x.dot(&self.down)
    }

    /// The column (bin across gravity) of `x`.
    pub(crate) fn column(&self, x: &Vector<D>) -> [i64; D] {
        let across = x - self.down * x.dot(&self.down) - self.origin;
        std::array::from_fn(|k| (across[k] / self.spacing).round() as i64)
    }

    /// Depth of a particle at `x` of the binned set below the top of its column, the top
    /// particle's own half layer included (dx/2 for the top particle).
    pub(crate) fn depth(&self, x: &Vector<D>) -> Real {
        self.top[&self.column(x)] + 0.5 * self.spacing - self.height_of(x)
    }
}

/// Where the check is made: gravity, density and lattice spacing, and the side walls.
pub struct CheckSetup<'a, const D: usize> {
    /// Unit vector along gravity.
    pub down: Vector<D>,
    /// ρ₀ g, N/m³.
    pub unit_weight: Real,
    /// dx.
    pub spacing: Real,
    /// H, the soil height.
    pub height: Real,
    /// Wall particles that carry shear (empty when the walls are free-slip during the stage).
    pub rough_walls: &'a [Vector<D>],
    /// tan δ of those walls, `None` for no-slip walls (no Janssen reference).
    pub wall_friction: Option<Real>,
}

/// One checked particle.
struct Sample {
    depth: Real,
    /// Height against gravity.
    height: Real,
    /// Position across gravity (first horizontal axis in 2D).
    across: Real,
    sigma_v: Real,
    lateral_ratio: Real,
    free: bool,
}

/// Checks the stress of `soil` against the 1D state and Janssen (see the module's doc), with
/// `oedometer` the oedometric ratio of the scene's model ([`OedometricRatio::for_column`]).
pub fn check_stress<const D: usize>(
    soil: &Particles<D>,
    oedometer: &OedometricRatio,
    setup: &CheckSetup<'_, D>,
) -> StressCheck {
    let fields = soil
        .soil
        .as_ref()
        .expect("soil particles carry soil fields");
    let (down, dx) = (setup.down, setup.spacing);
    let columns = Columns::of(&soil.position, down, dx);
    // A particle is in the free field if no rough wall particle at or above its level lies
    // within H across gravity (side walls; the floor below does not hold the soil up by
    // shear). Per column (the bins above): the highest rough wall particle of each wall
    // column, then per soil column the highest of those within H, so the cost is
    // soil columns × wall columns, not particles × wall particles.
    let wall_top = columns.highest(setup.rough_walls);
    // A particle exactly H from a wall (the middle of a column 2H long) is within H,
    // whatever the rounding of H/dx.
    let reach = setup.height / dx + 1e-9;
    let shear_top: HashMap<&[i64; D], Real> = columns
        .top
        .keys()
        .map(|soil_column| {
            let highest = wall_top
                .iter()
                .filter(|(wall_column, _)| {
                    let d2: i64 = (0..D)
                        .map(|k| (wall_column[k] - soil_column[k]).pow(2))
                        .sum();
                    (d2 as Real).sqrt() <= reach
                })
                .map(|(_, &height)| height)
                .fold(Real::NEG_INFINITY, Real::max);
            (soil_column, highest)
        })
        .collect();
    let samples: Vec<Sample> = soil
        .position
        .iter()
        .zip(&fields.stress)
        .filter_map(|(x, sigma)| {
            let depth = columns.depth(x);
            if depth <= 3.0 * dx {
                return None;
            }
            let mut sigma_v = 0.0;
            let mut trace = 0.0;
            for a in 0..D {
                trace += sigma[(a, a)];
                for b in 0..D {
                    sigma_v += down[a] * sigma[(a, b)] * down[b];
                }
            }
            let sigma_h = (trace - sigma_v) / (D - 1) as Real;
            Some(Sample {
                depth,
                height: columns.height_of(x),
                across: (x - down * x.dot(&down))[0],
                sigma_v,
                lateral_ratio: sigma_h / sigma_v,
                free: columns.height_of(x) - 0.5 * dx > shear_top[&columns.column(x)],
            })
        })
        .collect();
    // Janssen's K: the ratio at the deepest stress of the path.
    let max_stress = oedometer.max_stress();
    let zone = |free: bool| zone_check(samples.iter().filter(|s| s.free == free), setup, oedometer);
    let janssen = match (D, setup.wall_friction) {
        (2, Some(mu)) if !setup.rough_walls.is_empty() => {
            janssen_check(&samples, setup, mu, oedometer.at(max_stress))
        }
        _ => None,
    };
    StressCheck {
        free_field_distance: if setup.rough_walls.is_empty() {
            Real::INFINITY
        } else {
            setup.height
        },
        free_field: zone(true),
        wall_zone: zone(false),
        janssen,
    }
}

fn zone_check<'s, const D: usize>(
    samples: impl Iterator<Item = &'s Sample>,
    setup: &CheckSetup<'_, D>,
    oedometer: &OedometricRatio,
) -> ZoneCheck {
    let (mut n, mut error_max, mut error_sum, mut ratio_sum) = (0, 0.0, 0.0, 0.0);
    let (mut k_min, mut k_sum, mut k_max, mut k_error) =
        (Real::INFINITY, 0.0, Real::NEG_INFINITY, 0.0);
    for s in samples {
        let reference = -setup.unit_weight * s.depth;
        let error = ((s.sigma_v - reference) / reference).abs();
        error_max = Real::max(error_max, error);
        error_sum += error;
        ratio_sum += s.sigma_v / reference;
        k_min = k_min.min(s.lateral_ratio);
        k_max = k_max.max(s.lateral_ratio);
        k_sum += s.lateral_ratio;
        let k = oedometer.at(-s.sigma_v);
        k_error = Real::max(k_error, (s.lateral_ratio / k - 1.0).abs());
        n += 1;
    }
    let mean = |sum: Real| if n == 0 { Real::NAN } else { sum / n as Real };
    let extreme = |value: Real| if n == 0 { Real::NAN } else { value };
    ZoneCheck {
        particles: n,
        vertical_stress_error_max: extreme(error_max),
        vertical_stress_error_mean: mean(error_sum),
        vertical_stress_ratio_mean: mean(ratio_sum),
        lateral_ratio: (extreme(k_min), mean(k_sum), extreme(k_max)),
        lateral_ratio_error_max: extreme(k_error),
    }
}

/// The layers (bins of width dx in height) whose ends both lie within 1.5 dx of a rough wall
/// at their level, against Janssen's slice equilibrium with the layer's width.
fn janssen_check<const D: usize>(
    samples: &[Sample],
    setup: &CheckSetup<'_, D>,
    mu: Real,
    k: Real,
) -> Option<JanssenCheck> {
    let (dx, down) = (setup.spacing, setup.down);
    let mut layers: HashMap<i64, Layer> = HashMap::new();
    for s in samples {
        layers
            .entry((s.height / dx).floor() as i64)
            .or_default()
            .add(s);
    }
    let wall_beside = |across: Real, level: Real, side: Real| {
        setup.rough_walls.iter().any(|w| {
            let gap = side * ((w - down * w.dot(&down))[0] - across);
            gap > 0.0 && gap <= 1.5 * dx && (-w.dot(&down) - level).abs() <= dx
        })
    };
    let mut keys: Vec<i64> = layers.keys().copied().collect();
    keys.sort_unstable_by(|a, b| b.cmp(a));
    let gamma = setup.unit_weight;
    let mut check = JanssenCheck {
        layers: 0,
        width: Real::NAN,
        wall_friction: mu,
        lateral_ratio: k,
        error_max: 0.0,
        deepest: (Real::NAN, Real::NAN),
        outside_bounds: 0,
    };
    for layer in keys.iter().map(|key| &layers[key]) {
        let n = layer.count as Real;
        let (depth, level) = (layer.depth / n, layer.height / n);
        if !(wall_beside(layer.low, level, -1.0) && wall_beside(layer.high, level, 1.0)) {
            continue;
        }
        let width = layer.high - layer.low + dx;
        let x = 2.0 * k * mu * depth / width;
        let janssen = gamma * depth * (1.0 - (-x).exp()) / x;
        let (mean, scale) = (-layer.sigma_v / n, gamma * depth);
        check.error_max = Real::max(check.error_max, (mean - janssen).abs() / scale);
        if mean < janssen - 0.01 * scale || mean > 1.01 * scale {
            check.outside_bounds += 1;
        }
        check.layers += 1;
        check.width = width;
        check.deepest = (mean / scale, janssen / scale);
    }
    (check.layers > 0).then_some(check)
}

/// Sums over one layer of samples.
struct Layer {
    low: Real,
    high: Real,
    sigma_v: Real,
    depth: Real,
    height: Real,
    count: usize,
}

impl Default for Layer {
    fn default() -> Self {
        Self {
            low: Real::INFINITY,
            high: Real::NEG_INFINITY,
            sigma_v: 0.0,
            depth: 0.0,
            height: 0.0,
            count: 0,
        }
    }
}

impl Layer {
    fn add(&mut self, s: &Sample) {
        self.low = self.low.min(s.across);
        self.high = self.high.max(s.across);
        self.sigma_v += s.sigma_v;
        self.depth += s.depth;
        self.height += s.height;
        self.count += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ConstitutiveConfig;
    use approx::assert_relative_eq;

    /// Particles on a lattice at (k + ½) dx, jittered by 10⁻⁹ dx (the round-off of a relaxed
    /// state): every particle lands in its own lattice column and its depth is its distance
    /// below the column's top plus dx/2, whichever way the jitter goes.
    #[test]
    fn columns_follow_the_lattice_whatever_the_round_off() {
        let dx = 0.0025;
        let down = Vector::<2>::new(0.0, -1.0);
        let mut position = Vec::new();
        for i in 0..8 {
            for k in 0..5 {
                let jitter = if (i + k) % 2 == 0 { 1e-9 } else { -1e-9 } * dx;
                position.push(Vector::<2>::new(
                    (i as Real + 0.5) * dx + jitter,
                    (k as Real + 0.5) * dx - jitter,
                ));
            }
        }
        let columns = Columns::of(&position, down, dx);
        assert_eq!(columns.top.len(), 8);
        for x in &position {
            let layer = (x[1] / dx - 0.5).round();
            assert_relative_eq!(
                columns.depth(x),
                (4.0 - layer + 0.5) * dx,
                epsilon = 1e-8 * dx
            );
        }
    }

    /// Elastic: ν/(1 − ν) at every stress. Cohesionless Drucker–Prager with K₀ below the
    /// cone: the ratio on the cone, the same at every stress (no stress scale without c).
    #[test]
    fn oedometric_ratio_is_k0_while_elastic_and_constant_on_a_cohesionless_cone() {
        let elastic = ConstitutiveConfig::LinearElastic {
            youngs_modulus: 1e6,
            poisson_ratio: 0.3,
        }
        .build()
        .unwrap();
        let ratio = OedometricRatio::new(&elastic, 1e4);
        for stress in [10.0, 1e3, 9e3] {
            assert_relative_eq!(ratio.at(stress), 0.3 / 0.7, max_relative = 1e-9);
        }
        let sand: ConstitutiveConfig = ron::from_str(
            "DruckerPrager(material: (youngs_modulus: 0.84e6, poisson_ratio: 0.3, \
             friction_angle_deg: 19.8, cohesion: 0.0, dilatancy_angle_deg: 0.0), \
             algorithm: Bui2008)",
        )
        .unwrap();
        let ratio = OedometricRatio::new(&sand.build().unwrap(), 3e3);
        let (low, high) = (ratio.at(300.0), ratio.at(2.9e3));
        assert!(low > 0.3 / 0.7 + 0.1, "{low}");
        assert_relative_eq!(low, high, max_relative = 1e-3);
    }
}
