//! The factor of safety by strength reduction (`geosph_soil::factor_of_safety`) against closed
//! forms: the infinite slope and the vertical cut (docs/soil.md, "Factor of safety").

use geosph_core::Real;
use geosph_scene::{Scene, SolverSpec};
use geosph_soil::{FactorOfSafety, SoilError, StrengthReductionConfig, factor_of_safety};

/// A layer `depth` deep on a rough floor, periodic along the slope, with gravity tilted by
/// `slope_deg` (the slope's frame): an infinite slope.
fn infinite_slope(slope_deg: Real, friction_deg: Real, cohesion: Real, depth: Real) -> Scene {
    let (sin, cos) = slope_deg.to_radians().sin_cos();
    Scene::from_ron(&format!(
        "Scene(
            name: \"infinite-slope\",
            dimension: 2,
            dx: 0.005,
            smoothing_ratio: 1.3,
            gravity: [{gx}, {gy}],
            end_time: 1.0,
            domain: (min: [0.0, -0.05], max: [0.05, {top}], periodic: [true, false]),
            soil: (density: 2650.0, blocks: [Box(min: [0.0, 0.0], max: [0.05, {depth}])]),
            walls: [Polyline(points: [(0.0, 0.0), (0.05, 0.0)], layers: 4)],
            solver: Soil((
                constitutive: DruckerPrager(
                    material: (youngs_modulus: 0.84e6, poisson_ratio: 0.3,
                               friction_angle_deg: {friction_deg}, cohesion: {cohesion},
                               dilatancy_angle_deg: {friction_deg}),
                    algorithm: Bui2008,
                ),
                geostatic: (max_time: 1.0),
            )),
        )",
        gx = 9.81 * sin,
        gy = -9.81 * cos,
        top = depth + 0.1,
    ))
    .unwrap()
}

fn search(scene: &Scene, config: &StrengthReductionConfig) -> Result<FactorOfSafety, SoilError> {
    let SolverSpec::Soil(soil) = &scene.solver else {
        unreachable!("a soil scene")
    };
    let (mut particles, inputs) = geosph_scene::build::<2>(scene).unwrap().split();
    factor_of_safety(soil, config, inputs, &mut particles, &mut |_| {}).map(|(result, _)| result)
}

/// Infinite slope, β = 20°, φ = 30°, c = 0, associated flow (for which the plane-strain
/// Drucker–Prager match is Mohr–Coulomb's): F = tan φ / tan β = 1.586 (Taylor 1948; the
/// closed form of the issue), within 3 % at dx = 5 mm (20 layers).
#[test]
fn infinite_slope_factor_of_safety_matches_the_closed_form() {
    let (beta, phi): (Real, Real) = (20.0, 30.0);
    let exact = phi.to_radians().tan() / beta.to_radians().tan();
    let scene = infinite_slope(beta, phi, 0.0, 0.1);
    let config = StrengthReductionConfig {
        bounds: (1.0, 2.5),
        ..Default::default()
    };
    let result = search(&scene, &config).unwrap();
    eprintln!("closed form {exact:.4}\n{result}");
    assert!(
        (result.factor / exact - 1.0).abs() <= 0.03,
        "F = {:.4}, closed form {exact:.4}",
        result.factor
    );
}

/// A vertical cut H = 0.1 m high, φ = 0 (Tresca in plane strain), c = 2 kPa: the critical
/// height satisfies 2 ≤ γH_c/c ≤ 3.83 (lower bound of Drucker & Prager 1952, upper bound of
/// Chen 1975, Limit Analysis and Soil Plasticity), so F = γH_c/(γH) lies between
/// 2c/(γH) = 1.54 and 3.83c/(γH) = 2.95: the cut stands with c/F for F below the lower end
/// and fails above the upper one. The cut is the shipped cohesive slope's, released from its
/// retaining wall.
#[test]
fn vertical_cut_factor_of_safety_lies_between_the_limit_analysis_bounds() {
    let mut scene = Scene::from_ron(slope_failure::SCENES[2].1).unwrap();
    scene.dx = 0.005;
    let cohesion = 2000.0;
    if let SolverSpec::Soil(config) = &mut scene.solver
        && let geosph_soil::ConstitutiveConfig::DruckerPrager { material, .. } =
            &mut config.constitutive
    {
        material.cohesion = cohesion;
        material.friction_angle_deg = 0.0;
        material.dilatancy_angle_deg = 0.0;
    }
    let unit_weight = 2650.0 * 9.81;
    let height = 0.1;
    let (lower, upper) = (
        2.0 * cohesion / (unit_weight * height),
        3.83 * cohesion / (unit_weight * height),
    );
    let config = StrengthReductionConfig {
        bounds: (1.0, 4.0),
        tolerance: 0.02,
        ..Default::default()
    };
    let result = search(&scene, &config).unwrap();
    eprintln!("bounds {lower:.3} .. {upper:.3}\n{result}");
    assert!(
        lower <= result.bracket.0 && result.bracket.1 <= upper,
        "F in [{:.3}, {:.3}], limit analysis {lower:.3} .. {upper:.3}",
        result.bracket.0,
        result.bracket.1
    );
}

/// Bad input: the search names what is wrong.
#[test]
fn factor_of_safety_search_explains_bad_input() {
    let message = |result: Result<FactorOfSafety, SoilError>| result.unwrap_err().to_string();
    // A fluid scene.
    let fluid = Scene::from_ron(dam_break::DEFAULT_SCENE).unwrap();
    let error = slope_failure::factor_of_safety::settings(&fluid).unwrap_err();
    assert!(error.to_string().contains("soil scene"), "{error}");
    // A level layer has no free face and never fails.
    let level = infinite_slope(0.0, 30.0, 0.0, 0.05);
    let quick = StrengthReductionConfig {
        bounds: (1.0, 3.0),
        trial_time: 0.2,
        ..Default::default()
    };
    let error = message(search(&level, &quick));
    assert!(
        error.contains("factor_of_safety.bounds") && error.contains("still holds at F_high = 3"),
        "{error}"
    );
    // Bounds that do not bracket: the 20° slope with φ = 30° (F = 1.59) fails at F = 2 and 3.
    let slope = infinite_slope(20.0, 30.0, 0.0, 0.05);
    let above = StrengthReductionConfig {
        bounds: (2.0, 3.0),
        ..quick.clone()
    };
    let error = message(search(&slope, &above));
    assert!(
        error.contains("fails already at F_low = 2 (a particle moved"),
        "{error}"
    );
    // A bisection that cannot reach its tolerance within its budget.
    let tight = StrengthReductionConfig {
        bounds: (1.0, 3.0),
        tolerance: 1e-4,
        max_trials: 4,
        ..quick.clone()
    };
    let error = message(search(&slope, &tight));
    assert!(
        error.contains("did not converge in 4 trials") && error.contains("F is in ["),
        "{error}"
    );
    // Out-of-range settings, named.
    let reversed = StrengthReductionConfig {
        bounds: (3.0, 1.0),
        ..Default::default()
    };
    let error = message(search(&slope, &reversed));
    assert!(
        error.contains("factor_of_safety.bounds") && error.contains("0 < F_low < F_high"),
        "{error}"
    );
}
