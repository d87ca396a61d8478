//! Fuzz target: any bytes as a scene file must give a scene or an error, never a panic, an
//! abort or an unbounded allocation. Valid scenes are also built (particles, walls, domain).
#![no_main]

use geosph_scene::{Scene, build};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = Scene::from_ron(text) else {
        return;
    };
    if scene.validate().is_err() {
        return;
    }
    // Valid but large scenes are legitimate; building them only costs the fuzzer time.
    if scene.estimated_particles() > 2.0e4 {
        return;
    }
    let _ = match scene.dimension {
        2 => build::<2>(&scene).map(|setup| setup.fluid.len()),
        _ => build::<3>(&scene).map(|setup| setup.fluid.len()),
    };
});
