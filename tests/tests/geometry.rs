//! Scene geometry from meshes and unions of regions (issue 23): a closed mesh fills its
//! volume on the lattice within 1 % at dx ≤ size/50, in 3D and as a 2D section; overlapping
//! blocks fill each lattice site once; bad meshes are refused with the file and the problem.

use std::path::{Path, PathBuf};

use geosph_core::Vector;
use geosph_geometry::{SurfaceMesh, primitives};
use geosph_scene::{Scene, WallSpec, build};

use crate::wcsph::{check_hydrostatic, hydrostatic_scene, run_hydrostatic_scene};

pub(crate) fn scratch(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// Writes `mesh` as a Wavefront OBJ file.
pub(crate) fn write_obj(mesh: &SurfaceMesh, path: &Path) {
    let mut text = String::new();
    for v in &mesh.vertices {
        text.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    for t in &mesh.triangles {
        text.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    std::fs::write(path, text).unwrap();
}

fn scene(dimension: usize, dx: f64, blocks: &str, folder: &Path) -> Scene {
    let (gravity, tank) = if dimension == 2 {
        ("[0.0, -9.81]", "Tank(min: [-1.0, -1.0], max: [1.0, 1.0])")
    } else {
        (
            "[0.0, 0.0, -9.81]",
            "Tank(min: [-1.0, -1.0, -1.0], max: [1.0, 1.0, 1.0])",
        )
    };
    let mut scene = Scene::from_ron(&format!(
        "Scene(name: \"mesh\", dimension: {dimension}, dx: {dx}, gravity: {gravity}, \
         end_time: 0.1, fluid: (blocks: [{blocks}]), walls: [{tank}], solver: Wcsph(()))"
    ))
    .unwrap();
    scene.folder = Some(folder.to_owned());
    scene
}

#[test]
fn a_sphere_mesh_fills_its_volume_within_one_percent_in_3d() {
    let folder = scratch("geometry-sphere");
    // A sphere of diameter 0.6 m in mm, placed by scale and offset.
    let sphere = primitives::sphere(&Vector::<3>::zeros(), 300.0, 64);
    write_obj(&sphere, &folder.join("sphere.obj"));
    let dx = 0.6 / 50.0;
    let scene = scene(
        3,
        dx,
        "Mesh(file: \"sphere.obj\", scale: 0.001, offset: [0.1, 0.0, -0.2])",
        &folder,
    );
    let setup = build::<3>(&scene).unwrap();
    let block = &setup.blocks[0];
    assert_eq!(block.particles, setup.fluid.len());
    assert!(block.name.ends_with("sphere.obj"), "{}", block.name);
    let error = block.filled / block.volume - 1.0;
    assert!(
        error.abs() < 0.01,
        "filled {} of {} m³",
        block.filled,
        block.volume
    );
    // Every particle inside the placed sphere.
    let centre = Vector::<3>::new(0.1, 0.0, -0.2);
    assert!(
        setup
            .fluid
            .position
            .iter()
            .all(|x| (x - centre).norm() < 0.3)
    );
}

#[test]
fn a_cylinder_mesh_section_fills_its_area_within_one_percent_in_2d() {
    let folder = scratch("geometry-cylinder");
    // A horizontal cylinder (axis along the mesh's y): its section is a disc of radius 0.25.
    let upright = primitives::cylinder(&Vector::<3>::zeros(), 0.25, 1.0, 96);
    let lying = SurfaceMesh {
        vertices: upright
            .vertices
            .iter()
            .map(|v| Vector::<3>::new(v[0], v[2] - 0.5, v[1]))
            .collect(),
        ..upright
    };
    write_obj(&lying, &folder.join("cylinder.obj"));
    let dx = 0.5 / 50.0;
    let scene = scene(2, dx, "Mesh(file: \"cylinder.obj\", section: 0.2)", &folder);
    let setup = build::<2>(&scene).unwrap();
    let block = &setup.blocks[0];
    let disc = std::f64::consts::PI * 0.25 * 0.25;
    assert!((block.volume / disc - 1.0).abs() < 0.01, "{}", block.volume);
    assert!(
        (block.filled / block.volume - 1.0).abs() < 0.01,
        "filled {} of {} m²",
        block.filled,
        block.volume
    );
}

#[test]
fn overlapping_blocks_fill_each_lattice_site_once() {
    let folder = scratch("geometry-union");
    let dx = 0.1;
    let scene = scene(
        2,
        dx,
        "Box(min: [0.0, 0.0], max: [0.5, 0.5]), Box(min: [0.2, 0.0], max: [0.7, 0.3])",
        &folder,
    );
    let setup = build::<2>(&scene).unwrap();
    // 25 sites in the first box, 15 in the second, 9 of them shared.
    assert_eq!(setup.fluid.len(), 25 + 15 - 9);
    assert_eq!(setup.blocks[1].overlapped, 9);
    let mut sites: Vec<_> = setup
        .fluid
        .position
        .iter()
        .map(|x| ((x[0] / dx).floor() as i64, (x[1] / dx).floor() as i64))
        .collect();
    sites.sort_unstable();
    sites.dedup();
    assert_eq!(sites.len(), setup.fluid.len());
}

#[test]
fn bad_meshes_are_refused_naming_the_block_the_file_and_the_problem() {
    let folder = scratch("geometry-bad");
    let mut open = primitives::sphere(&Vector::<3>::zeros(), 0.2, 16);
    open.triangles.pop();
    write_obj(&open, &folder.join("open.obj"));
    std::fs::write(folder.join("empty.obj"), "# nothing\n").unwrap();
    let small = primitives::sphere(&Vector::<3>::zeros(), 0.001, 8);
    write_obj(&small, &folder.join("small.obj"));
    let cases = [
        (
            "Mesh(file: \"missing.stl\")",
            "missing.stl`: cannot read it:",
        ),
        ("Mesh(file: \"terrain.ply\")", "unknown extension; use .stl"),
        ("Mesh(file: \"open.obj\")", "not closed: the edge from"),
        ("Mesh(file: \"empty.obj\")", "empty.obj`"),
        (
            "Mesh(file: \"small.obj\")",
            "holds no lattice site at dx = 0.05",
        ),
        ("Mesh(file: \"open.obj\", scale: 0.0)", "scale"),
    ];
    for (block, expected) in cases {
        let error = build::<3>(&scene(3, 0.05, block, &folder))
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("scene field `fluid.blocks[0]") && error.contains(expected),
            "{block}: {error}"
        );
        assert_eq!(error.lines().count(), 1, "{error}");
    }
}

/// A mesh of quads, each given by its corners and the direction its front faces.
fn quads(name: &str, faces: &[([Vector<3>; 4], Vector<3>)]) -> SurfaceMesh {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (quad, facing) in faces {
        let first = vertices.len() as u32;
        vertices.extend(quad);
        for [a, b, c] in [[0, 1, 2], [0, 2, 3]] {
            let normal = (quad[b] - quad[a]).cross(&(quad[c] - quad[a]));
            let [a, b, c] = [a, b, c].map(|k| first + k as u32);
            triangles.push(if normal.dot(facing) > 0.0 {
                [a, b, c]
            } else {
                [a, c, b]
            });
        }
    }
    SurfaceMesh::new(name, vertices, triangles).unwrap()
}

fn v(x: f64, y: f64, z: f64) -> Vector<3> {
    Vector::<3>::new(x, y, z)
}

/// The vertical quad x = `x` from z = 0 to 1 across y = ±0.5, facing `facing`.
fn side(x: f64, facing: f64) -> ([Vector<3>; 4], Vector<3>) {
    (
        [
            v(x, -0.5, 0.0),
            v(x, 0.5, 0.0),
            v(x, 0.5, 1.0),
            v(x, -0.5, 1.0),
        ],
        v(facing, 0.0, 0.0),
    )
}

/// The bed z = 0 from x = 0 to 1 across y = ±0.5, facing up.
fn bed() -> ([Vector<3>; 4], Vector<3>) {
    (
        [
            v(0.0, -0.5, 0.0),
            v(1.0, -0.5, 0.0),
            v(1.0, 0.5, 0.0),
            v(0.0, 0.5, 0.0),
        ],
        v(0.0, 0.0, 1.0),
    )
}

/// A channel of width 1 m and height 1 m along the mesh's y (−0.5 to 0.5): bed and two side
/// walls, their triangles facing the water, open at the top and at both ends.
fn channel() -> SurfaceMesh {
    quads("channel", &[bed(), side(0.0, 1.0), side(1.0, -1.0)])
}

/// Runs the still tank of `wcsph::hydrostatic_scene` with its walls laid behind `mesh`
/// (3 layers) instead of a box tank, and checks it with the box tank's bars.
fn check_tank_in_mesh(dimension: usize, dx: f64, depth: f64, end_time: f64, mesh: &SurfaceMesh) {
    let folder = scratch(&format!("geometry-{}", mesh.name));
    let file = format!("{}.obj", mesh.name);
    write_obj(mesh, &folder.join(&file));
    let mut scene = hydrostatic_scene(dimension, dx, depth, end_time);
    scene.walls = vec![WallSpec::Mesh {
        file,
        scale: 1.0,
        offset: Vec::new(),
        section: 0.0,
        layers: 3,
    }];
    scene.folder = Some(folder);
    let (average, particles) = run_hydrostatic_scene(scene, dx, depth);
    let layers = average.mean();
    match (&average.last.plane, &average.last.space) {
        (Some((_, fluid)), _) => check_hydrostatic(fluid, &layers, particles, dx, depth, 1.0),
        (_, Some((_, fluid))) => check_hydrostatic(fluid, &layers, particles, dx, depth, 0.4),
        _ => panic!("no sample was taken"),
    }
}

#[test]
fn a_still_tank_in_a_mesh_channel_holds_the_hydrostatic_pressure() {
    check_tank_in_mesh(2, 0.02, 0.6, 2.0, &channel());
}

/// An open box container [0, 0.4]² × [0, 0.8] m: its bed and four sides, facing in.
fn box_container() -> SurfaceMesh {
    let (w, h) = (0.4, 0.8);
    let wall = |x: [f64; 2], y: [f64; 2], facing: Vector<3>| {
        (
            [
                v(x[0], y[0], 0.0),
                v(x[1], y[1], 0.0),
                v(x[1], y[1], h),
                v(x[0], y[0], h),
            ],
            facing,
        )
    };
    quads(
        "container",
        &[
            (
                [
                    v(0.0, 0.0, 0.0),
                    v(w, 0.0, 0.0),
                    v(w, w, 0.0),
                    v(0.0, w, 0.0),
                ],
                v(0.0, 0.0, 1.0),
            ),
            wall([0.0, 0.0], [0.0, w], v(1.0, 0.0, 0.0)),
            wall([w, w], [0.0, w], v(-1.0, 0.0, 0.0)),
            wall([0.0, w], [0.0, 0.0], v(0.0, 1.0, 0.0)),
            wall([0.0, w], [w, w], v(0.0, -1.0, 0.0)),
        ],
    )
}

#[test]
fn a_still_tank_in_a_3d_mesh_container_holds_the_hydrostatic_pressure() {
    // The 3D still tank of `wcsph::hydrostatic_tank_3d_matches_rho_g_depth` (dx = 0.04 m,
    // 0.4 m of water, 1.2 s) with its walls laid behind a mesh instead of a box tank: the
    // same bars (no particle crosses a wall, every layer's mean pressure within the box
    // tank's tolerance of rho g (H - z)).
    check_tank_in_mesh(3, 0.04, 0.4, 1.2, &box_container());
}

/// Reads the columns `names` of `diagnostics.csv` in `folder`, averaged over the rows with
/// time ≥ `from`.
pub(crate) fn mean_columns(folder: &Path, names: &[&str], from: f64) -> Vec<f64> {
    let text = std::fs::read_to_string(folder.join("diagnostics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let index: Vec<usize> = names
        .iter()
        .map(|n| {
            header
                .iter()
                .position(|h| h == n)
                .unwrap_or_else(|| panic!("no {n}"))
        })
        .collect();
    let mut sums = vec![0.0; names.len()];
    let mut count = 0;
    for line in lines {
        let values: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        if values[0] >= from {
            for (sum, &k) in sums.iter_mut().zip(&index) {
                *sum += values[k];
            }
            count += 1;
        }
    }
    sums.iter().map(|s| s / count as f64).collect()
}

/// Writes the meshes of the load tests into `folder`: the tank (bed and left side), its
/// right side as a plate of its own, and a 0.2 m × 0.2 m block 0.1 m above the bed.
pub(crate) fn load_meshes(folder: &Path) {
    write_obj(
        &quads("tank", &[bed(), side(0.0, 1.0)]),
        &folder.join("tank.obj"),
    );
    write_obj(
        &quads("plate", &[side(1.0, -1.0)]),
        &folder.join("plate.obj"),
    );
    let block = [
        (
            [
                v(0.4, -0.5, 0.1),
                v(0.6, -0.5, 0.1),
                v(0.6, 0.5, 0.1),
                v(0.4, 0.5, 0.1),
            ],
            v(0.0, 0.0, -1.0),
        ),
        (
            [
                v(0.4, -0.5, 0.3),
                v(0.6, -0.5, 0.3),
                v(0.6, 0.5, 0.3),
                v(0.4, 0.5, 0.3),
            ],
            v(0.0, 0.0, 1.0),
        ),
        (
            [
                v(0.4, -0.5, 0.1),
                v(0.4, 0.5, 0.1),
                v(0.4, 0.5, 0.3),
                v(0.4, -0.5, 0.3),
            ],
            v(-1.0, 0.0, 0.0),
        ),
        (
            [
                v(0.6, -0.5, 0.1),
                v(0.6, 0.5, 0.1),
                v(0.6, 0.5, 0.3),
                v(0.6, -0.5, 0.3),
            ],
            v(1.0, 0.0, 0.0),
        ),
    ];
    write_obj(&quads("block", &block), &folder.join("block.obj"));
}

/// Runs a 2D WCSPH scene of 0.6 m of water with `blocks` and `walls` and the load gauges
/// `loads` to `end_time` into `folder/out`; returns the output folder.
fn run_loads(folder: &Path, end_time: f64, blocks: &str, walls: &str, loads: &str) -> PathBuf {
    let mut scene = Scene::from_ron(&format!(
        "Scene(name: \"loads\", dimension: 2, dx: 0.02, end_time: {end_time},
            output: (interval: {end_time}, sample_interval: 0.01, vtk: false, loads: [{loads}]),
            fluid: (blocks: [{blocks}]), walls: [{walls}], solver: Wcsph(()))"
    ))
    .unwrap();
    scene.folder = Some(folder.to_owned());
    let out = folder.join("out");
    let options = geosph_runner::RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    geosph_runner::run(&scene, &options, &mut geosph_runner::NoObserver).unwrap();
    out
}

// Issue 23's bar: the hydrostatic force on a face within 2 % of ρ g A h_c. Per metre of
// width: the plate of 0.6 m of water carries ρ g H²/2 = 1765.8 N along +x, the block
// ρ g V = 392.4 N up (Archimedes).
const PLATE: f64 = 1000.0 * 9.81 * 0.6 * 0.6 / 2.0;
const BUOYANCY: f64 = 1000.0 * 9.81 * 0.2 * 0.2;

#[test]
fn still_water_loads_a_wall_plate_with_rho_g_h_squared_over_two() {
    // The 2D still tank (1 m × 0.6 m, dx = 0.02 m, WCSPH, 2 s) whose right side is a plate
    // of its own; the force averaged over the second second.
    let folder = scratch("geometry-plate");
    load_meshes(&folder);
    let out = run_loads(
        &folder,
        2.0,
        "Box(min: [0.0, 0.0], max: [1.0, 0.6])",
        "Mesh(file: \"tank.obj\"), Mesh(file: \"plate.obj\")",
        "(name: \"plate\", wall: 1)",
    );
    let [x, y, energy] = mean_columns(&out, &["F_plate_x", "F_plate_y", "kinetic_energy"], 1.0)[..]
    else {
        unreachable!()
    };
    println!("plate {x:.1} N/m against {PLATE:.1}, kinetic energy {energy:.2e} J/m");
    assert!((x / PLATE - 1.0).abs() < 0.02, "plate {x} against {PLATE}");
    assert!(y.abs() < 0.02 * PLATE, "shear {y}");
    assert!(out.join("loads.png").exists());
}

#[test]
fn a_submerged_block_in_hydrostatic_water_carries_its_buoyancy() {
    // The block held 0.1 m above the bed, the water filled around it by four boxes (their
    // union); 2 s of WCSPH, the loads averaged over the second second as the plate's.
    let folder = scratch("geometry-block");
    load_meshes(&folder);
    let out = run_loads(
        &folder,
        2.0,
        "Box(min: [0.0, 0.0], max: [0.4, 0.6]), Box(min: [0.6, 0.0], max: [1.0, 0.6]),
         Box(min: [0.4, 0.0], max: [0.6, 0.1]), Box(min: [0.4, 0.3], max: [0.6, 0.6])",
        "Mesh(file: \"tank.obj\"), Mesh(file: \"plate.obj\"), Mesh(file: \"block.obj\")",
        "(name: \"plate\", wall: 1), (name: \"block\", wall: 2)",
    );
    let [plate, x, y, energy] = mean_columns(
        &out,
        &["F_plate_x", "F_block_x", "F_block_y", "kinetic_energy"],
        1.0,
    )[..] else {
        unreachable!()
    };
    println!(
        "plate {plate:.1} N/m, block {y:.1} N/m against {BUOYANCY:.1}, kinetic energy {energy:.2e} J/m"
    );
    assert!(
        (plate / PLATE - 1.0).abs() < 0.02,
        "plate {plate} against {PLATE}"
    );
    assert!(
        (y / BUOYANCY - 1.0).abs() < 0.02,
        "block {y} against {BUOYANCY}"
    );
    assert!(x.abs() < 0.02 * BUOYANCY, "block across {x}");
}

#[test]
fn the_shipped_debris_flow_scene_loads_its_barrier_once_the_water_arrives() {
    // data/scenes/debris-flow-barrier.ron (terrain from an ESRI ASCII height grid, barrier
    // from an OBJ box), coarse: dx = 0.02 m, to t = 1 s. The water starts 1.9 m up-slope of
    // the barrier, so the barrier carries nothing at first; once the flow arrives, the
    // water pushes it downstream (+x) and no particle leaves the domain.
    let mut scene =
        Scene::from_ron(include_str!("../../data/scenes/debris-flow-barrier.ron")).unwrap();
    scene.folder = Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes"));
    scene.dx = 0.02;
    scene.end_time = 1.0;
    scene.output.vtk = false;
    let out = scratch("geometry-debris-flow");
    let options = geosph_runner::RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    let summary = geosph_runner::run(&scene, &options, &mut geosph_runner::NoObserver).unwrap();
    assert_eq!(summary.escaped, 0);
    // The front cannot reach the barrier 1.9 m away within 0.3 s: faster than 6.3 m/s, more
    // than the 4.8 m/s of a fall from the water's top to the bed.
    let text = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    let column = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|name| name == "F_barrier_x")
        .unwrap();
    for line in text.lines().skip(1) {
        let values: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        if values[0] < 0.3 {
            assert_eq!(values[column], 0.0, "a load at t = {} s", values[0]);
        }
    }
    let [late] = mean_columns(&out, &["F_barrier_x"], 0.8)[..] else {
        unreachable!()
    };
    println!("barrier: mean force {late:.1} N/m over t = 0.8-1 s");
    assert!(late > 0.0, "{late}");
    assert!(out.join("loads.png").exists());
}
