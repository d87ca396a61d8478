//! The run that `tests/tests/output_integrity.rs` kills or starves of disk: the default dam
//! break run into a folder, on one thread.
//!
//! `integrity-child OUT long|small`: `long` writes a frame every few steps for 10 s of
//! simulated time (it is killed long before the end); `small` (≈ 250 particles) keeps every
//! frame far below a 64 KiB file-size limit while `diagnostics.csv`, a row per step, passes it
//! after a few hundred steps. Exits with 3 and the error on standard error when the run fails.

use std::path::PathBuf;
use std::process::ExitCode;

use geosph_runner::{NoObserver, RunOptions, run};
use geosph_scene::Scene;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, kind] = args.as_slice() else {
        eprintln!("usage: integrity-child OUT long|small");
        return ExitCode::from(2);
    };
    let mut scene = Scene::from_ron(dam_break::DEFAULT_SCENE).expect("the default scene parses");
    scene.end_time = 10.0;
    match kind.as_str() {
        "small" => {
            scene.dx = 0.1;
            scene.output.interval = 0.01;
            scene.output.sample_interval = 1e-4;
        }
        "long" => {
            // A frame every few steps, so that kills often land in the middle of writing one.
            scene.dx = 0.04;
            scene.output.interval = 0.002;
            scene.output.sample_interval = 0.001;
        }
        _ => {
            eprintln!("error: the scene kind is `long` or `small`, not `{kind}`");
            return ExitCode::from(2);
        }
    }
    let options = RunOptions {
        out_dir: Some(PathBuf::from(out)),
        threads: Some(1),
        ..Default::default()
    };
    match run(&scene, &options, &mut NoObserver) {
        Ok(_) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(3)
        }
    }
}
