//! The granular collapse of Bui et al. (2008) in 3D, as a slab periodic across y
//! (`data/scenes/granular-collapse-3d.ron`), against its 2D plane-strain twin (the default
//! scene) and the experiment.
//!
//! Both run at dx = 5 mm to t = 0.6 s (the toe is final by then; `soil_sph`). The slab is six
//! particles wide (the least a period may hold), its gate a mesh plane folded into the period.
//!
//! Bounds:
//! - plane strain: nothing in the slab's set-up breaks its symmetry across y; round-off does,
//!   and seeds a mode across y at the thin toe (neighbouring rows moving apart, 1.5 % of dx by
//!   t = 0.6 s at this dx; docs/soil.md, "The 3D column in plane strain"). The deposit is drawn
//!   by particles to ±dx/2, so motion across y below dx/10 changes none of its measures: no
//!   grain may move across y by more than dx/10;
//! - the experiment: the bounds of the 2D test at this dx (`soil_sph::against_the_experiment`,
//!   derived there from the fine 2D run and the measured deposit);
//! - the 2D twin: the deposit toe and the height at the wall are each drawn by particles to
//!   ±dx/2, so the slab's and the 2D column's agree within dx.

use std::path::PathBuf;

use geosph_runner::RunOptions;
use geosph_scene::Scene;

use crate::soil_sph::{against_the_experiment, collapse};

#[test]
fn slab_collapse_stays_plane_and_matches_the_2d_column() {
    let dx = 0.005;
    let end_time = 0.6;
    // The shipped slab is 6 dx = 12 mm wide at its dx = 2 mm; at 5 mm it must be 30 mm.
    let text = include_str!("../../data/scenes/granular-collapse-3d.ron").replace("0.012", "0.03");
    assert_eq!(text.matches("0.03,").count(), 3, "domain, block, tank");
    let mut scene = Scene::from_ron(&text).unwrap();
    scene.folder = Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes"));
    scene.dx = dx;
    scene.end_time = end_time;
    scene.output.interval = 0.2;
    // The frames are read by VTK in `.ci/run`.
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("granular-collapse-3d");
    let _ = std::fs::remove_dir_all(&out);
    let options = RunOptions {
        out_dir: Some(out),
        ..Default::default()
    };
    let slab = slope_failure::run(&scene, &options).unwrap();
    println!("{}\n{slab}", slab.summary);
    assert_eq!(slab.summary.escaped, 0);

    let out_of_plane = slab.out_of_plane.expect("the slab counts as plane strain");
    assert!(
        out_of_plane <= 0.1 * dx,
        "a grain moved {out_of_plane:.2e} m across y"
    );

    against_the_experiment(&slab);

    let plane = collapse(dx, end_time);
    println!("2D plane strain:\n{plane}");
    let toe = |report: &slope_failure::Report| report.last.runout;
    assert!(
        (toe(&slab) - toe(&plane)).abs() <= dx,
        "deposit toe {:.4} m in the slab, {:.4} m in 2D",
        toe(&slab),
        toe(&plane)
    );
    let height = |report: &slope_failure::Report| report.last.height_at_wall;
    assert!(
        (height(&slab) - height(&plane)).abs() <= dx,
        "height at the wall {:.4} m in the slab, {:.4} m in 2D",
        height(&slab),
        height(&plane)
    );
}
