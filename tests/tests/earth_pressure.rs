//! Soil on a structure: the load gauges integrate the soil's stress on mesh walls.
//!
//! An elastic soil layer H = 0.3 m deep and L = 1 m long (ρ = 2650 kg/m³, E = 0.84 MPa,
//! ν = 0.3, plane strain, dx = 0.01 m) rests in the tank of the geometry tests (its bed and
//! left side), its right side a retaining wall (a plate mesh), each with a load gauge. The
//! walls are rollers (free slip, during the geostatic stage and after it), so the soil at rest
//! has no lateral strain: σ_v = −ρ g (H − z) and σ_h = K₀ σ_v with K₀ = ν/(1 − ν) (the
//! elastic layer of `docs/soil.md`, "Geostatic stage (`GeostaticConfig`)"). The retaining
//! wall then carries the earth pressure at rest K₀ ρ g H²/2 per metre (501.4 N/m) and the bed
//! the weight ρ g H L (7799 N/m), neither any shear. The bar is the one of the hydrostatic
//! force on a plate, 2 % (issue 23); the loads are averaged over the 0.05 s after the stage.

use geosph_runner::{NoObserver, RunOptions, run};
use geosph_scene::Scene;

use crate::geometry::{load_meshes, mean_columns, scratch};

#[test]
fn soil_at_rest_loads_a_retaining_wall_with_the_earth_pressure_at_rest() {
    let folder = scratch("earth-pressure");
    load_meshes(&folder);
    let mut scene = Scene::from_ron(
        "Scene(name: \"earth-pressure\", dimension: 2, dx: 0.01, end_time: 0.05,
            output: (interval: 0.05, sample_interval: 0.005, vtk: false,
                     loads: [(name: \"tank\", wall: 0), (name: \"wall\", wall: 1)]),
            soil: (density: 2650.0, blocks: [Box(min: [0.0, 0.0], max: [1.0, 0.3])]),
            walls: [Mesh(file: \"tank.obj\"), Mesh(file: \"plate.obj\")],
            solver: Soil((
                constitutive: LinearElastic(youngs_modulus: 0.84e6, poisson_ratio: 0.3),
                walls: (slip: FreeSlip),
                geostatic: (free_slip_walls: true),
            )))",
    )
    .unwrap();
    scene.folder = Some(folder.clone());
    let out = folder.join("out");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    run(&scene, &options, &mut NoObserver).unwrap();
    let names = ["F_wall_x", "F_wall_y", "F_tank_y"];
    let [x, shear, bed] = mean_columns(&out, &names, 0.0)[..] else {
        unreachable!()
    };
    let (rho_g, depth) = (2650.0 * 9.81, 0.3);
    let at_rest = 0.3 / (1.0 - 0.3) * rho_g * depth * depth / 2.0;
    let weight = rho_g * depth * 1.0;
    println!(
        "wall {x:.1} N/m against {at_rest:.1}, shear {shear:.1}; bed {bed:.1} against {weight:.1}"
    );
    assert!(
        (x / at_rest - 1.0).abs() < 0.02,
        "wall {x} against {at_rest}"
    );
    assert!(shear.abs() < 0.02 * at_rest, "shear {shear}");
    assert!(
        (-bed / weight - 1.0).abs() < 0.02,
        "bed {bed} against {weight}"
    );
}
