//! Rigid bodies (issue 23): a floating box settles at the draft Archimedes gives, a block
//! released on a slope slides as Coulomb friction says, and bad bodies are refused.

use std::path::{Path, PathBuf};

use geosph_core::{Particles, Real, Vector};
use geosph_geometry::primitives;
use geosph_runner::{Observer, RunOptions};
use geosph_scene::Scene;

use crate::geometry::{mean_columns, scratch, write_obj};

/// The free-surface height of the water between x = `from` and `to`, for the draft of a
/// floating body: in each particle column of width dx the highest particle plus dx/2, averaged
/// over the columns (the highest particle of the whole band would read the jitter of the
/// surface's particles, upwards only).
struct WaterLevel {
    from: Real,
    to: Real,
    dx: Real,
}

impl<const D: usize> Observer<D> for WaterLevel {
    fn columns(&self) -> Vec<&'static str> {
        vec!["level"]
    }

    fn sample(&mut self, _time: Real, fluid: &Particles<D>, row: &mut Vec<Real>) {
        let columns = ((self.to - self.from) / self.dx).round() as usize;
        let mut top = vec![Real::NEG_INFINITY; columns];
        for x in &fluid.position {
            let k = ((x[0] - self.from) / self.dx).floor();
            if k >= 0.0 && (k as usize) < columns {
                top[k as usize] = top[k as usize].max(x[D - 1]);
            }
        }
        row.push(top.iter().sum::<Real>() / columns as Real + 0.5 * self.dx);
    }
}

/// The floating box of [`a_floating_box_settles_at_the_archimedes_draft`]
/// (`data/scenes/tests/floating-box.ron`) run to `end_time` with frames every `interval`.
pub(crate) fn float_scene(end_time: Real, interval: Real) -> Scene {
    let mut scene =
        Scene::from_ron(include_str!("../../data/scenes/tests/floating-box.ron")).unwrap();
    scene.end_time = end_time;
    scene.output.interval = interval;
    scene.output.vtk = interval < end_time;
    scene
}

fn run<O>(mut scene: Scene, folder: &Path, observer: &mut O) -> PathBuf
where
    O: Observer<2> + Observer<3> + Send,
{
    scene.folder = Some(folder.to_owned());
    let out = folder.join("out");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        ..Default::default()
    };
    geosph_runner::run(&scene, &options, observer).unwrap();
    out
}

/// Issue 23's bar: a floating box reaches the equilibrium draft within 2 %. A 0.4 m × 0.2 m
/// box of density 500 kg/m³ floats with a draft of ρ_b/ρ_w × 0.2 m = 0.1 m (Archimedes), and
/// upright (metacentric height KB + BM − KG = 0.05 + B²/(12 d) − 0.1 = +0.083 m; a square of
/// the same density would roll over, as it does when run by hand: `docs/geometry.md`). Released at a draft of 0.08 m into a
/// 1 m wide tank of water 0.4 m deep (WCSPH, dx = 0.02 m), it heaves about the equilibrium;
/// the draft, the water level beside it less the box's bottom, is averaged over the last
/// 2 s (about two heave periods).
#[test]
fn a_floating_box_settles_at_the_archimedes_draft() {
    let folder = scratch("bodies-float");
    let scene = float_scene(4.0, 4.0);
    let mut level = WaterLevel {
        from: 0.04,
        to: 0.24,
        dx: 0.02,
    };
    let out = run(scene, &folder, &mut level);
    let [height, centre, angle, force] =
        mean_columns(&out, &["level", "box_y", "box_angle", "box_Fy"], 2.0)[..]
    else {
        unreachable!()
    };
    let draft = height - (centre - 0.1);
    let weight = 500.0 * 0.4 * 0.2 * 9.81;
    println!(
        "draft {draft:.4} m against 0.1 (level {height:.4}, centre {centre:.4}), mean angle \
         {angle:.2e} rad, fluid force {force:.1} N/m against the weight {weight:.1}"
    );
    assert!(
        (draft / 0.1 - 1.0).abs() < 0.02,
        "draft {draft} against 0.1"
    );
    assert!(angle.abs() < 0.01, "the box rolled: {angle} rad");
    // The mean fluid force carries the weight (the heave is about it).
    assert!(
        (force / weight - 1.0).abs() < 0.02,
        "force {force} against {weight}"
    );
}

/// The two blocks of [`a_block_on_a_slope_slides_as_coulomb_friction_says`] on their slope,
/// meshes written into `folder`, run to `end_time` with frames every `interval`.
pub(crate) fn slope_scene(folder: &Path, end_time: Real, interval: Real) -> String {
    let dx = 0.02;
    block_on_slope(folder, "sliding", 0.6, dx);
    block_on_slope(folder, "sticking", 0.2, dx);
    let foot = TOP / SLOPE.tan();
    format!(
        r#"Scene(
        name: "slope", dimension: 2, dx: {dx}, end_time: {end_time},
        output: (interval: {interval}, sample_interval: 0.01, vtk: {vtk}),
        fluid: (blocks: [Box(min: [2.0, 0.0], max: [2.5, 0.2])]),
        walls: [Tank(min: [0.0, 0.0], max: [2.5, 1.5]),
                Polyline(points: [(0.0, {TOP}), ({foot}, 0.0)])],
        bodies: [
            (name: "sliding", shape: Mesh(file: "sliding.obj"), density: 2000.0, friction: 0.2),
            (name: "sticking", shape: Mesh(file: "sticking.obj"), density: 2000.0, friction: 0.7),
        ],
        solver: Wcsph(()),
    )"#,
        vtk = interval < end_time
    )
}

/// A 0.2 m × 0.1 m block lying on the 30° slope `a` m down from its top, 0.25 dx above it,
/// as an OBJ box in `folder/<name>.obj`.
fn block_on_slope(folder: &Path, name: &str, along: Real, dx: Real) {
    let (sin, cos) = (SLOPE.sin(), SLOPE.cos());
    let base = Vector::<2>::new(along * cos, TOP - along * sin);
    let normal = Vector::<2>::new(sin, cos);
    let centre = base + normal * (0.25 * dx);
    let mut mesh = primitives::cuboid(
        &Vector::<3>::new(-0.1, -0.2, 0.0),
        &Vector::<3>::new(0.1, 0.2, 0.1),
    );
    for v in &mut mesh.vertices {
        let (a, c) = (v[0], v[2]);
        *v = Vector::<3>::new(
            centre[0] + a * cos + c * sin,
            v[1],
            centre[1] - a * sin + c * cos,
        );
    }
    write_obj(&mesh, &folder.join(format!("{name}.obj")));
}

/// The slope's angle and the height of its top at x = 0.
const SLOPE: Real = std::f64::consts::PI / 6.0;
const TOP: Real = 1.0;

/// Issue 23's bar: a body released on a slope with Coulomb friction follows the analytic
/// sliding motion within 2 %. Two blocks lie on a 30° polyline slope (dx = 0.02 m, a pool
/// of water at its foot so the scene has a fluid): one with μ = 0.2 < tan 30° slides with
/// a = g (sin θ − μ cos θ) = 3.206 m/s², one with μ = 0.7 > tan 30° stays where it is.
/// The sliding block's acceleration along the slope between t = 0.1 s and 0.4 s (after it
/// settled onto the slope from 0.25 dx above it) and its travel over that time are compared
/// with the closed form.
#[test]
fn a_block_on_a_slope_slides_as_coulomb_friction_says() {
    let folder = scratch("bodies-slope");
    let dx = 0.02;
    let scene = Scene::from_ron(&slope_scene(&folder, 0.4, 0.4)).unwrap();
    let out = run(scene, &folder, &mut geosph_runner::NoObserver);
    let down = Vector::<2>::new(SLOPE.cos(), -SLOPE.sin());
    let state = |name: &str, time: Real| {
        let [x, y, vx, vy] = columns_at(&out, name, time);
        (
            Vector::<2>::new(x, y).dot(&down),
            Vector::<2>::new(vx, vy).dot(&down),
        )
    };
    let g = 9.81;
    let expected = g * (SLOPE.sin() - 0.2 * SLOPE.cos());
    let (s1, v1) = state("sliding", 0.1);
    let (s2, v2) = state("sliding", 0.4);
    let acceleration = (v2 - v1) / 0.3;
    let travel = s2 - s1;
    let expected_travel = v1 * 0.3 + 0.5 * expected * 0.09;
    println!(
        "sliding block: a = {acceleration:.4} m/s² against {expected:.4}, travel {travel:.4} m \
         against {expected_travel:.4}"
    );
    assert!(
        (acceleration / expected - 1.0).abs() < 0.02,
        "acceleration {acceleration} against {expected}"
    );
    assert!(
        (travel / expected_travel - 1.0).abs() < 0.02,
        "travel {travel} against {expected_travel}"
    );
    let (start, _) = state("sticking", 0.0);
    let (end, speed) = state("sticking", 0.4);
    println!(
        "sticking block: moved {:.2e} m, speed {speed:.2e} m/s",
        end - start
    );
    // It falls straight down onto the slope, 0.25 dx/cos θ, which is 0.25 dx tan θ along it,
    // and then holds.
    let fall = 0.25 * dx * SLOPE.tan();
    assert!((end - start).abs() < 1.02 * fall, "moved {}", end - start);
    assert!(speed.abs() < 1e-3, "speed {speed}");
}

/// A body's x, y, vx, vy in the `diagnostics.csv` row at `time`.
fn columns_at(out: &Path, name: &str, time: Real) -> [Real; 4] {
    let text = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |c: &str| {
        let c = format!("{name}_{c}");
        header.iter().position(|h| *h == c).unwrap()
    };
    let row: Vec<Real> = lines
        .map(|line| {
            line.split(',')
                .map(|x| x.parse().unwrap())
                .collect::<Vec<Real>>()
        })
        .find(|row| (row[0] - time).abs() < 1e-9)
        .unwrap();
    ["x", "y", "vx", "vy"].map(|c| row[column(c)])
}

/// Bad bodies are refused before any work, naming the body and the problem.
#[test]
fn bad_bodies_are_refused_naming_the_body() {
    let folder = scratch("bodies-bad");
    let scene = |bodies: &str, solver: &str| {
        // The fluid's lattice starts at its box's corner, half a spacing off the bodies'.
        let mut scene = Scene::from_ron(&format!(
            r#"Scene(name: "bad", dimension: 2, dx: 0.02, end_time: 0.1,
                fluid: (blocks: [Box(min: [0.01, 0.01], max: [0.41, 0.21])]),
                walls: [Tank(min: [0.0, 0.0], max: [1.0, 1.0])],
                bodies: [{bodies}], solver: {solver})"#
        ))
        .unwrap();
        scene.folder = Some(folder.clone());
        scene
    };
    let refused = |bodies: &str, solver: &str| {
        let scene = scene(bodies, solver);
        match geosph_scene::build::<2>(&scene) {
            Ok(_) => panic!("accepted: {bodies}"),
            Err(error) => error.to_string(),
        }
    };
    let wcsph = "Wcsph(())";
    let square = |name: &str, lo: (f64, f64), extra: &str| {
        format!(
            r#"(name: "{name}", shape: Box(min: [{}, {}], max: [{}, {}]), {extra})"#,
            lo.0,
            lo.1,
            lo.0 + 0.2,
            lo.1 + 0.2
        )
    };
    let dense = "density: 500.0";
    // (bodies, solver, what the message must name)
    let cases = [
        (
            square("b", (0.6, -0.02), dense),
            wcsph,
            vec!["bodies[0]", "overlapping walls[0]"],
        ),
        (
            square("b", (0.3, 0.1), dense),
            wcsph,
            vec!["bodies[0]", "overlaps"],
        ),
        (
            square("b", (0.6, 0.1), dense)
                + ", "
                + r#"(name: "c", shape: Box(min: [0.65, 0.15], max: [0.75, 0.25]), density: 500.0)"#,
            wcsph,
            vec!["bodies[1]", "bodies[0]"],
        ),
        (
            square("b", (0.6, 0.1), "density: 500.0, layers: 2"),
            wcsph,
            vec!["bodies[0].layers"],
        ),
        (
            r#"(name: "b", shape: Mesh(file: "missing.obj"), density: 500.0)"#.to_owned(),
            wcsph,
            vec!["bodies[0]", "missing.obj"],
        ),
        (
            square("b", (0.6, 0.1), "density: -1.0"),
            wcsph,
            vec!["bodies[0].density"],
        ),
        (
            square("b", (0.6, 0.1), dense) + ", " + &square("b", (0.6, 0.5), dense),
            wcsph,
            vec!["bodies[1].name"],
        ),
        (
            square("b", (0.6, 0.1), dense),
            "Soil(())",
            vec!["bodies", "fluid solver"],
        ),
    ];
    for (bodies, solver, names) in cases {
        let message = refused(&bodies, solver);
        for name in names {
            assert!(
                message.contains(name),
                "{bodies}: {message} should name {name}"
            );
        }
    }
}

/// The same in 3D, coarse (dx = 0.04 m, WCSPH, 2 s): a 0.4 × 0.4 × 0.2 m box of 500 kg/m³
/// released at draft 0.08 m in a 0.8 m square tank of water 0.32 m deep heaves about its
/// equilibrium, where the fluid's mean force over t = 1–2 s (about one heave period) carries
/// its weight ρ_b g V = 157.0 N within 2 %, and it stays upright.
#[test]
fn a_floating_box_in_3d_carries_its_weight_on_the_water() {
    let folder = scratch("bodies-float-3d");
    let scene = r#"Scene(
        name: "float3", dimension: 3, dx: 0.04, end_time: 2.0,
        output: (interval: 2.0, sample_interval: 0.01, vtk: false),
        fluid: (blocks: [
            Box(min: [0.0, 0.0, 0.0], max: [0.8, 0.8, 0.24]),
            Box(min: [0.0, 0.0, 0.24], max: [0.2, 0.8, 0.32]),
            Box(min: [0.6, 0.0, 0.24], max: [0.8, 0.8, 0.32]),
            Box(min: [0.2, 0.0, 0.24], max: [0.6, 0.2, 0.32]),
            Box(min: [0.2, 0.6, 0.24], max: [0.6, 0.8, 0.32]),
        ]),
        walls: [Tank(min: [0.0, 0.0, 0.0], max: [0.8, 0.8, 0.8])],
        bodies: [(name: "box", shape: Box(min: [0.2, 0.2, 0.24], max: [0.6, 0.6, 0.44]),
                  density: 500.0, friction: 0.0)],
        solver: Wcsph(()),
    )"#;
    let scene = Scene::from_ron(scene).unwrap();
    let out = run(scene, &folder, &mut geosph_runner::NoObserver);
    let [force, rx, ry] = mean_columns(&out, &["box_Fz", "box_rx", "box_ry"], 1.0)[..] else {
        unreachable!()
    };
    let weight = 500.0 * 0.4 * 0.4 * 0.2 * 9.81;
    println!(
        "3D box: fluid force {force:.1} N against its weight {weight:.1}, tilt ({rx:.1e}, {ry:.1e}) rad"
    );
    assert!(
        (force / weight - 1.0).abs() < 0.02,
        "force {force} against {weight}"
    );
    assert!(rx.abs() < 0.02 && ry.abs() < 0.02, "tilted ({rx}, {ry})");
}
