//! Rigid bodies (issue 23): a floating box settles at the draft Archimedes gives, a block
//! released on a slope slides as Coulomb friction says, and bad bodies are refused.

use std::path::{Path, PathBuf};

use geosph_core::{Particles, Real};
use geosph_runner::{Observer, RunOptions};
use geosph_scene::Scene;

use crate::geometry::{mean_columns, scratch};

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

fn run<O>(scene: &str, folder: &Path, observer: &mut O) -> PathBuf
where
    O: Observer<2> + Observer<3> + Send,
{
    let mut scene = Scene::from_ron(scene).unwrap();
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
/// the same density would roll over, as it does here). Released at a draft of 0.08 m into a
/// 1 m wide tank of water 0.4 m deep (WCSPH, dx = 0.02 m), it heaves about the equilibrium;
/// the draft, the water level beside it less the box's bottom, is averaged over the last
/// 2 s (about two heave periods).
#[test]
fn a_floating_box_settles_at_the_archimedes_draft() {
    let folder = scratch("bodies-float");
    let scene = r#"Scene(
        name: "float", dimension: 2, dx: 0.02, end_time: 4.0,
        output: (interval: 4.0, sample_interval: 0.01, vtk: false),
        fluid: (blocks: [
            Box(min: [0.0, 0.0], max: [0.3, 0.4]),
            Box(min: [0.7, 0.0], max: [1.0, 0.4]),
            Box(min: [0.3, 0.0], max: [0.7, 0.32]),
        ]),
        walls: [Tank(min: [0.0, 0.0], max: [1.0, 0.8])],
        bodies: [(name: "box", shape: Box(min: [0.3, 0.32], max: [0.7, 0.52]),
                  density: 500.0, friction: 0.0)],
        solver: Wcsph(()),
    )"#;
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
