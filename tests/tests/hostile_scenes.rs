//! Hostile and careless scenes: each malformed scene of the table must stop with a one-line
//! error that contains the expected fragment (the field, the value or the allowed range),
//! without a panic and before any output is written.
//!
//! Every case goes the whole way a user's scene goes: `Scene::from_ron`, then
//! `geosph_runner::run` with an output folder (validation, the output-folder check, the
//! particle set-up, the solver). A case passes when that path fails with its fragment and the
//! output folder was not created. A few more cases point the output at a folder that cannot be
//! written.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use geosph_runner::{NoObserver, RunOptions, run};
use geosph_scene::Scene;

/// A small valid scene (≈ 50 fluid particles, two output frames) that the cases patch.
const BASE: &str = r#"// The valid scene every case starts from.
Scene(
    name: "hostile",
    dimension: 2,
    dx: 0.1,
    smoothing_ratio: 1.3,
    kernel: "wendland-c2",
    gravity: [0.0, -9.81],
    end_time: 0.01,
    output: (interval: 0.005, sample_interval: 0.005, vtk: true),
    fluid: (density: 1000.0, blocks: [Box(min: [0.0, 0.0], max: [0.5, 1.0])], hydrostatic: true),
    walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0], layers: 3, open_top: true)],
    solver: Wcsph((
        equation_of_state: Tait(gamma: 7.0),
        diffusion: Molteni(delta: 0.1),
        viscosity: Artificial(alpha: 0.02, beta: 0.0),
        xsph: 0.0,
        integrator: LeapFrog,
        cfl: 0.25,
        neighbour_skin: 0.1,
    )),
)
"#;

/// (name, scene, expected fragment of the error). The scene is either `old => new`, one
/// replacement in [`BASE`] (`old` must occur there), `old => new ;; old2 => new2` for two, or
/// a whole file when it has no `=>`.
#[rustfmt::skip]
const CASES: &[(&str, &str, &str)] = &[
    // The file itself.
    ("empty file", "", "the file is empty"),
    ("only a comment", "// TODO write the scene\n", "Expected opening `(` for struct `Scene`"),
    ("not RON at all", "name = \"x\"\ndx = 0.1\n", "line 1, column 1"),
    ("trailing text", "\n)\n => \n)\n)\n", "trailing characters"),
    ("unclosed list", "max: [0.5, 1.0]) => max: [0.5, 1.0)", "fluid.blocks[0].Box.max"),
    // Unknown or misspelt fields and variants.
    ("misspelt top-level field", "dx: 0.1, => dxx: 0.1,", "Unexpected field named `dxx`"),
    ("misspelt fluid field", "hydrostatic: true => hydrostatc: true", "fluid.hydrostatc"),
    ("misspelt solver field", "cfl: 0.25 => cfll: 0.25", "solver.Wcsph.cfll"),
    ("misspelt output field", "vtk: true => vtu: true", "output.vtu"),
    ("unknown solver", "Wcsph(( => Sph((", "Unexpected variant named `Sph`"),
    ("misspelt integrator", "LeapFrog => Leapfrog", "`Leapfrog`"),
    ("misspelt EOS parameter", "Tait(gamma: => Tait(gama:", "equation_of_state.Tait.gama"),
    ("misspelt region", "Box(min => Square(min", "Unexpected variant named `Square`"),
    ("missing required dx", "dx: 0.1, => ", "missing field named `dx`"),
    // Wrong types.
    ("dx as text", "dx: 0.1 => dx: \"fine\"", "field `dx`: Expected float, found `\"fine\"`"),
    ("dimension as real", "dimension: 2, => dimension: 2.5,", "after field `dimension`"),
    ("name as number", "name: \"hostile\" => name: 5", "field `name`: Expected string"),
    ("vtk as number", "vtk: true => vtk: 1", "field `output.vtk`: Expected boolean"),
    ("gravity as text", "gravity: [0.0, -9.81] => gravity: \"down\"", "field `gravity`"),
    ("negative layer count", "layers: 3 => layers: -3", "walls[0].Tank.layers"),
    ("coordinate as text", "max: [0.5, 1.0] => max: [0.5, \"1\"]", "fluid.blocks[0].Box.max[1]"),
    // Values out of range.
    ("dimension 4", "dimension: 2, => dimension: 4,", "`dimension`: must be 2 or 3, got 4"),
    ("dx zero", "dx: 0.1 => dx: 0.0", "`dx`: must be a finite number > 0, got 0"),
    ("dx negative", "dx: 0.1 => dx: -0.1", "`dx`: must be a finite number > 0, got -0.1"),
    ("dx not a number", "dx: 0.1 => dx: NaN", "`dx`: must be a finite number > 0, got NaN"),
    ("dx in millimetres", "dx: 0.1 => dx: 0.00001", "`dx`: 0.00001 m would make about"),
    ("density zero", "density: 1000.0 => density: 0.0", "`fluid.density`: must be a finite number > 0, got 0"),
    ("density negative", "density: 1000.0 => density: -1000.0", "`fluid.density`: must be a finite number > 0, got -1000"),
    ("h/dx too small", "smoothing_ratio: 1.3 => smoothing_ratio: 0.5", "`smoothing_ratio`: must lie in [1, 2.5], got 0.5"),
    ("h/dx too large", "smoothing_ratio: 1.3 => smoothing_ratio: 4.0", "`smoothing_ratio`: must lie in [1, 2.5], got 4"),
    ("unknown kernel", "wendland-c2 => wendland-c3", "unknown kernel `wendland-c3`; expected one of"),
    ("end time zero", "end_time: 0.01 => end_time: 0.0", "`end_time`: must be a finite number > 0, got 0"),
    ("end time infinite", "end_time: 0.01 => end_time: inf", "`end_time`: must be a finite number > 0, got inf"),
    ("CFL too large", "cfl: 0.25 => cfl: 1.5", "`solver.cfl`: must lie in (0, 1] for the explicit LeapFrog integrator, got 1.5"),
    ("CFL zero", "cfl: 0.25 => cfl: 0.0", "`solver.cfl`: must lie in (0, 1]"),
    ("Tait exponent below 1", "gamma: 7.0 => gamma: 0.5", "`solver.equation_of_state.gamma`: must lie in [1, 10], got 0.5"),
    ("negative viscosity", "alpha: 0.02 => alpha: -0.1", "`solver.viscosity.alpha`: must lie in [0, 1], got -0.1"),
    ("diffusion too strong", "delta: 0.1 => delta: 2.0", "`solver.diffusion.delta`: must lie in [0, 1], got 2"),
    ("XSPH above 1", "xsph: 0.0 => xsph: 1.5", "`solver.xsph`: must lie in [0, 1], got 1.5"),
    ("negative Verlet skin", "neighbour_skin: 0.1 => neighbour_skin: -0.1", "`solver.neighbour_skin`: must lie in [0, 1], got -0.1"),
    ("negative shifting", "xsph: 0.0, => xsph: 0.0, shifting: Some((coefficient: -1.0)),", "`solver.shifting.coefficient`: must lie in [0, 10], got -1"),
    ("surface threshold above the near-surface one", "xsph: 0.0, => xsph: 0.0, shifting: Some((surface_threshold: 0.9)),", "`solver.shifting.near_surface_threshold`: must lie in [0.9, 1], got 0.75"),
    ("misspelt shifting field", "xsph: 0.0, => xsph: 0.0, shifting: Some((coeficient: 1.0)),", "coeficient"),
    ("escaped fraction above 1", "solver: Wcsph(( => health: (max_escaped_fraction: 1.5),\n    solver: Wcsph((", "`health.max_escaped_fraction`: must lie in [0, 1], got 1.5"),
    ("negative escaped fraction", "solver: Wcsph(( => health: (max_escaped_fraction: -0.01),\n    solver: Wcsph((", "`health.max_escaped_fraction`: must lie in [0, 1], got -0.01"),
    ("misspelt health field", "solver: Wcsph(( => health: (max_escape_fraction: 0.1),\n    solver: Wcsph((", "health.max_escape_fraction"),
    ("negative sound speed", "cfl: 0.25, => cfl: 0.25, sound_speed: -1.0,", "`solver.sound_speed`: must be a finite number > 0, got -1"),
    ("gravity in 3D", "gravity: [0.0, -9.81] => gravity: [0.0, 0.0, -9.81]", "`gravity`: needs 2 coordinates"),
    ("zero gravity, no sound speed", "gravity: [0.0, -9.81] => gravity: [0.0, 0.0]", "`solver.sound_speed`: must be given when gravity is zero"),
    ("name with a path", "name: \"hostile\" => name: \"../../etc/x\"", "`name`: must be 1 to 100 letters"),
    ("empty name", "name: \"hostile\" => name: \"\"", "`name`: must be"),
    ("output interval zero", "interval: 0.005, => interval: 0.0,", "`output.interval`: must be a finite number > 0, got 0"),
    ("a billion frames", "interval: 0.005, => interval: 1e-11,", "`output.interval`: must be at least end_time / 100000"),
    ("negative sample interval", "sample_interval: 0.005 => sample_interval: -1.0", "`output.sample_interval`: must be a finite number > 0, got -1"),
    ("probe in 3D", "vtk: true), => vtk: true, probes: [(name: \"bed\", position: [0.2, 0.0, 0.1])]),", "`output.probes[0].position`: needs 2 coordinates (the scene's dimension), got 3"),
    ("probe at NaN", "vtk: true), => vtk: true, probes: [(name: \"bed\", position: [0.2, NaN])]),", "`output.probes[0].position`: coordinates must be finite, got NaN"),
    ("probe name with a comma", "vtk: true), => vtk: true, probes: [(name: \"a,b\", position: [0.2, 0.1])]),", "`output.probes[0].name`: must be 1 to 100 letters"),
    ("probe names repeated", "vtk: true), => vtk: true, probes: [(name: \"p\", position: [0.2, 0.1]), (name: \"p\", position: [0.3, 0.1])]),", "`output.probes[1].name`: must be unique, \"p\" is used twice"),
    ("probe without a position", "vtk: true), => vtk: true, probes: [(name: \"p\")]),", "position"),
    ("free surface in 2D", "vtk: true), => vtk: true, surface: Some(())),", "`output.surface`: free-surface meshes are drawn for 3D scenes"),
    ("misspelt surface field", "vtk: true), => vtk: true, surface: Some((treshold: 0.5))),", "treshold"),
    // Geometry.
    ("empty scene: no fluid", "fluid: (density: 1000.0, blocks: [Box(min: [0.0, 0.0], max: [0.5, 1.0])], hydrostatic: true), => ", "`fluid`: the scene has no fluid"),
    ("no fluid blocks", "blocks: [Box(min: [0.0, 0.0], max: [0.5, 1.0])] => blocks: []", "`fluid.blocks`: needs at least one region, got none"),
    ("inverted block", "max: [0.5, 1.0] => max: [-0.5, 1.0]", "`fluid.blocks[0].max`: must exceed min on axis 0: min = 0, max = -0.5"),
    ("3D block in 2D", "min: [0.0, 0.0], max: [0.5 => min: [0.0, 0.0, 0.0], max: [0.5", "`fluid.blocks[0].min`: needs 2 coordinates (the scene's dimension), got 3"),
    ("polygon of two points", "Box(min: [0.0, 0.0], max: [0.5, 1.0]) => Polygon(vertices: [(0.0, 0.0), (1.0, 1.0)])", "`fluid.blocks[0].vertices`: needs at least 3 vertices, got 2"),
    ("polygon with NaN", "Box(min: [0.0, 0.0], max: [0.5, 1.0]) => Polygon(vertices: [(0.0, 0.0), (1.0, NaN), (0.0, 1.0)])", "`fluid.blocks[0].vertices[1]`: coordinates must be finite, got (1, NaN)"),
    ("polygon smaller than dx", "Box(min: [0.0, 0.0], max: [0.5, 1.0]) => Polygon(vertices: [(0.01, 0.01), (0.02, 0.01), (0.01, 0.02)])", "fluid.blocks[0]`: the polygon holds no lattice site at dx = 0.1"),
    ("fluid outside the domain", "walls: [ => domain: (min: [-1.0, -1.0], max: [0.3, 3.0]), walls: [", "`domain`: fluid particle"),
    ("fluid through the tank wall", "max: [0.5, 1.0] => max: [2.5, 1.0]", "lies in or beyond the tank's walls (the fluid reaches 4.500e-1 m past its inner face on axis 0: a block extends beyond the tank)"),
    ("block past the tank by less than dx", "max: [0.5, 1.0] => max: [2.1, 1.0]", "past its inner face on axis 0: a block extends beyond the tank)"),
    ("dx not dividing a block that fills the tank", "max: [0.5, 1.0])], hydrostatic: true),\n    walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0] => max: [0.52, 1.0])], hydrostatic: true),\n    walls: [Tank(min: [0.0, 0.0], max: [0.52, 2.0]", "3.000e-2 m past its inner face on axis 0; a Box block is filled with whole rows of dx from its lower corner, so when dx = 0.1 m does not divide the block's extent"),
    ("fluid overlapping a wall", "open_top: true)] => open_top: true), Polyline(points: [(0.0, 0.55), (0.5, 0.55)])]", "`walls[1]`: fluid particle"),
    ("tank wall too thin", "layers: 3 => layers: 1", "`walls[0].layers`: must lie in [3, 10]"),
    ("tank wall too thick", "layers: 3 => layers: 40", "`walls[0].layers`: must lie in [3, 10]"),
    ("inverted tank", "max: [2.0, 2.0] => max: [2.0, -2.0]", "`walls[0].max`: must exceed min on axis 1"),
    ("tank of ten billion cells", "max: [2.0, 2.0] => max: [1.0e4, 1.0e4]", "`walls[0]`: the tank spans"),
    ("polyline of one point", "walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0], layers: 3, open_top: true)], => walls: [Polyline(points: [(0.0, 0.0)])],", "`walls[0].points`: needs at least 2 points, got 1"),
    ("polyline repeating a point", "walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0], layers: 3, open_top: true)], => walls: [Polyline(points: [(0.0, 0.0), (0.0, 0.0), (1.0, 0.0)])],", "`walls[0].points[1]`: repeats the point before it"),
    ("domain inverted", "walls: [ => domain: (min: [0.0, 0.0], max: [-1.0, 3.0]), walls: [", "`domain.max`: must exceed min on axis 0"),
    ("tank short of a periodic axis", "walls: [ => domain: (min: [-1.0, -1.0], max: [2.0, 3.0], periodic: [true, false]), walls: [", "`walls[0]`: axis 0 is periodic, so the tank has no walls across it and must span the domain's period [-1, 2] exactly, not [0, 2]"),
    ("period not a whole number of dx", "walls: [Tank(min: [0.0, 0.0], max: [2.0, 2.0] => domain: (min: [-0.05, -1.0], max: [2.0, 3.0], periodic: [true, false]), walls: [Tank(min: [-0.05, 0.0], max: [2.0, 2.0]", "its period 2.05 m holds 20.500 lattice spacings of dx = 0.1 m: choose a dx that divides the period"),
    ("periodic list too long", "walls: [ => domain: (min: [-1.0, -1.0], max: [3.0, 3.0], periodic: [true, false, true]), walls: [", "`domain.periodic`: needs 2 entries or none, got 3"),
];

/// A small valid soil scene (≈ 50 soil particles) that the soil cases patch.
const SOIL_BASE: &str = r#"Scene(
    name: "hostile-soil",
    dimension: 2,
    dx: 0.02,
    end_time: 0.002,
    output: (interval: 0.001, sample_interval: 0.001, vtk: true),
    soil: (density: 2650.0, blocks: [Box(min: [0.0, 0.0], max: [0.2, 0.1])]),
    walls: [Tank(min: [0.0, 0.0], max: [0.6, 0.3], layers: 3, open_top: true)],
    solver: Soil((
        constitutive: DruckerPrager(
            material: (youngs_modulus: 0.84e6, poisson_ratio: 0.3, friction_angle_deg: 19.8,
                       cohesion: 0.0, dilatancy_angle_deg: 0.0),
            algorithm: Bui2008,
        ),
        cfl: 0.2,
    )),
)
"#;

/// Soil cases, patches of [`SOIL_BASE`]: the material's ranges (E > 0, ν ∈ [0, 0.5),
/// φ ∈ [0°, 90°), c ≥ 0, 0 ≤ ψ ≤ φ) and the soil solver's own settings.
#[rustfmt::skip]
const SOIL_CASES: &[(&str, &str, &str)] = &[
    ("negative Young's modulus", "youngs_modulus: 0.84e6 => youngs_modulus: -0.84e6", "`solver.constitutive.youngs_modulus`: must lie in (0, inf), got -840000"),
    ("zero Young's modulus", "youngs_modulus: 0.84e6 => youngs_modulus: 0.0", "`solver.constitutive.youngs_modulus`: must lie in (0, inf), got 0"),
    ("Poisson's ratio 0.5", "poisson_ratio: 0.3 => poisson_ratio: 0.5", "`solver.constitutive.poisson_ratio`: must lie in [0, 0.5), got 0.5"),
    ("negative Poisson's ratio", "poisson_ratio: 0.3 => poisson_ratio: -0.1", "`solver.constitutive.poisson_ratio`: must lie in [0, 0.5), got -0.1"),
    ("friction angle 90°", "friction_angle_deg: 19.8 => friction_angle_deg: 90.0", "`solver.constitutive.friction_angle_deg`: must lie in [0, 90) degrees, got 90"),
    ("negative friction angle", "friction_angle_deg: 19.8 => friction_angle_deg: -5.0", "`solver.constitutive.friction_angle_deg`: must lie in [0, 90) degrees, got -5"),
    ("negative cohesion", "cohesion: 0.0 => cohesion: -100.0", "`solver.constitutive.cohesion`: must lie in [0, inf), got -100"),
    ("dilatancy above friction", "dilatancy_angle_deg: 0.0 => dilatancy_angle_deg: 30.0", "`solver.constitutive.dilatancy_angle_deg`: must lie in [0, friction_angle_deg] degrees, got 30"),
    ("soil CFL too large", "cfl: 0.2 => cfl: 1.2", "`solver.cfl`: must lie in (0, 1], got 1.2"),
    ("misspelt material field", "poisson_ratio: 0.3 => poison_ratio: 0.3", "poison_ratio"),
    ("pressure probe on soil", "vtk: true), => vtk: true, probes: [(name: \"p\", position: [0.1, 0.05])]),", "`output.probes`: pressure probes need a fluid solver"),
    ("water-level gauge with a height", "vtk: true), => vtk: true, heights: [(name: \"h\", position: [0.1, 0.05])]),", "`output.heights[0].position`: needs 1 finite coordinate(s), the horizontal ones"),
    ("water-level gauge named twice", "vtk: true), => vtk: true, heights: [(name: \"h\", position: [0.1]), (name: \"h\", position: [0.2])]),", "`output.heights[1].name`: must be unique"),
];

/// The scene text of a case: `spec` patched into `base`, or `spec` itself.
fn scene_text(base: &str, spec: &str) -> Result<String, String> {
    if !spec.contains(" => ") {
        return Ok(spec.to_owned());
    }
    let mut text = base.to_owned();
    for replacement in spec.split(" ;; ") {
        let (old, new) = replacement
            .split_once(" => ")
            .ok_or_else(|| format!("bad patch `{replacement}`"))?;
        if !text.contains(old) {
            return Err(format!("`{old}` does not occur in the base scene"));
        }
        text = text.replacen(old, new, 1);
    }
    Ok(text)
}

/// Parses and runs `text` with output to `out`; the error message, or `Ok` when the scene ran.
fn parse_and_run(text: &str, out: &Path) -> Result<(), String> {
    let scene = Scene::from_ron(text).map_err(|error| error.to_string())?;
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        threads: Some(1),
        ..Default::default()
    };
    run(&scene, &options, &mut NoObserver)
        .map(|_| ())
        .map_err(|error| error.to_string())
}

fn scratch(name: &str) -> PathBuf {
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// Checks one outcome; `None` when it is as expected, else what is wrong.
fn judge(
    outcome: std::thread::Result<Result<(), String>>,
    expected: &str,
    out: &Path,
) -> Option<String> {
    let problem = match outcome {
        Err(_) => "panicked".to_owned(),
        Ok(Ok(())) => "was accepted".to_owned(),
        Ok(Err(message)) if !message.contains(expected) => {
            format!("said `{message}`")
        }
        Ok(Err(message)) if message.contains('\n') => {
            format!("said more than one line: `{message}`")
        }
        Ok(Err(_)) if out.exists() => "left the output folder behind".to_owned(),
        Ok(Err(_)) => return None,
    };
    Some(problem)
}

#[test]
fn the_base_scene_is_valid_and_runs() {
    let folder = scratch("hostile-base");
    let out = folder.join("out");
    parse_and_run(BASE, &out).unwrap();
    assert!(out.join("hostile.pvd").exists());
    assert!(out.join("frames/hostile_000002.vtu").exists());
    let out = folder.join("soil");
    parse_and_run(SOIL_BASE, &out).unwrap();
    assert!(out.join("hostile-soil.pvd").exists());
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn malformed_scenes_fail_with_a_one_line_error_naming_the_field() {
    let folder = scratch("hostile-scenes");
    let mut failures = Vec::new();
    let cases = CASES.iter().map(|case| (BASE, case));
    let soil_cases = SOIL_CASES.iter().map(|case| (SOIL_BASE, case));
    for (index, (base, (name, spec, expected))) in cases.chain(soil_cases).enumerate() {
        let text = match scene_text(base, spec) {
            Ok(text) => text,
            Err(problem) => {
                failures.push(format!("{name}: {problem}"));
                continue;
            }
        };
        let out = folder.join(format!("case-{index}"));
        let outcome = catch_unwind(AssertUnwindSafe(|| parse_and_run(&text, &out)));
        if let Some(problem) = judge(outcome, expected, &out) {
            failures.push(format!("{name}: expected `{expected}`, but it {problem}"));
        }
    }
    let total = CASES.len() + SOIL_CASES.len();
    assert!(total >= 30);
    assert!(
        failures.is_empty(),
        "{} of {} malformed scenes misbehaved:\n{}",
        failures.len(),
        total,
        failures.join("\n")
    );
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn output_folders_that_cannot_be_written_are_refused_before_any_work() {
    let folder = scratch("hostile-output");
    let file = folder.join("a-file");
    std::fs::write(&file, "not a folder").unwrap();
    let mut failures = Vec::new();
    let mut cases = vec![
        (
            "folder inside a file",
            file.join("out"),
            "is a file, not a folder",
        ),
        (
            "folder is a file",
            file.clone(),
            "exists and is not a folder",
        ),
    ];
    // Permissions do not stop root; run this case only where they apply.
    let locked = folder.join("locked");
    std::fs::create_dir(&locked).unwrap();
    set_mode(&locked, 0o555);
    let root = std::fs::File::create(locked.join("probe")).is_ok();
    if root {
        eprintln!("running as root: the read-only folder case is skipped");
    } else {
        cases.push((
            "read-only folder",
            locked.join("out"),
            "cannot be created in",
        ));
    }
    for (name, out, expected) in cases {
        let outcome = catch_unwind(AssertUnwindSafe(|| parse_and_run(BASE, &out)));
        let created = out.is_dir();
        match outcome {
            Ok(Err(message)) if message.contains(expected) && !message.contains('\n') => {
                if created {
                    failures.push(format!("{name}: created {}", out.display()));
                }
            }
            Ok(Err(message)) => failures.push(format!("{name}: said `{message}`")),
            Ok(Ok(())) => failures.push(format!("{name}: was accepted")),
            Err(_) => failures.push(format!("{name}: panicked")),
        }
    }
    set_mode(&locked, 0o755);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    std::fs::remove_dir_all(folder).unwrap();
}

fn set_mode(path: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}
