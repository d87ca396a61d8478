//! `slope-failure`: runs the granular column collapse of Bui et al. (2008) (or a given soil
//! scene) and writes the runout, the deposit profile and VTU frames, or a given fluid scene
//! (a flow down a slope onto barriers: frames, diagnostics, loads); or searches a slope's
//! factor of safety (`--factor-of-safety`, then its run at F = 1 with `--run-out`); or runs
//! columns of the same bars at four aspect ratios against experiments (`--aspect-ratios`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::RunError;
use geosph_runner::cli::{self, RunArgs};
use geosph_scene::{Region, Scene, SolverSpec};

/// Granular column collapse and slope failure with elastoplastic soil SPH.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    /// Scene file (RON); default: the embedded granular column collapse of Bui et al. (2008),
    /// a 0.2 m × 0.1 m column of aluminium bars released on one side.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Particle spacing in m (overrides the scene).
    #[arg(long)]
    dx: Option<f64>,
    /// Simulated end time in s (overrides the scene).
    #[arg(long)]
    end_time: Option<f64>,
    /// Instead of the run, search the factor of safety by strength reduction (c and tan φ
    /// divided by F until the soil no longer comes to rest), with the scene's
    /// `factor_of_safety` settings or the defaults; writes factor-of-safety.csv,
    /// slip-surface.png and failing-state.vtu. Without --scene: the slope of Griffiths &
    /// Lane (1999), data/scenes/homogeneous-slope.ron.
    #[arg(long, conflicts_with = "aspect_ratios")]
    factor_of_safety: bool,
    /// With --factor-of-safety: afterwards, run the scene at its own strength (F = 1) to its
    /// end time (--end-time) into <out>/run-out: VTU frames of the post-failure run-out when
    /// the factor of safety is below 1, of the slope at rest otherwise.
    #[arg(long, requires = "factor_of_safety")]
    run_out: bool,
    /// Instead of one run, columns of the default scene's aluminium bars at aspect ratios 0.5,
    /// 1, 2 and 4 in turn (generated from the default scene, each into <out>/bar-column-a<a>),
    /// against the experiments of Nguyen et al. (2015) and Bui et al. (2008); writes
    /// aspect-ratios.csv and aspect-ratios.png. Takes --dx.
    #[arg(long, conflicts_with_all = ["scene", "end_time"])]
    aspect_ratios: bool,
    /// Output, threads, progress, checkpoints and restart.
    #[command(flatten)]
    run: RunArgs,
}

impl Cli {
    /// The output folder: `--out`, else the restart file's folder, else `out/slope-failure`.
    fn out(&self) -> PathBuf {
        self.run.out("out/slope-failure")
    }
}

fn load(cli: &Cli) -> Result<Scene, String> {
    let text = match &cli.scene {
        Some(path) => std::fs::read_to_string(path)
            .map_err(|error| format!("cannot read scene {}: {error}", path.display()))?,
        None if cli.factor_of_safety => slope_failure::SLOPE_SCENE.to_owned(),
        None => slope_failure::DEFAULT_SCENE.to_owned(),
    };
    let mut scene = Scene::from_ron(&text).map_err(|error| error.to_string())?;
    scene.folder = cli
        .scene
        .as_deref()
        .and_then(std::path::Path::parent)
        .map(std::path::Path::to_path_buf);
    if let Some(dx) = cli.dx {
        scene.dx = dx;
    }
    if let Some(end_time) = cli.end_time {
        scene.end_time = end_time;
    }
    Ok(scene)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let out = cli.out();
    let options = match cli.run.options(out.clone()) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    // Under `mpiexec` every rank runs the scene; rank 0 alone writes and reports.
    let root = options.out_dir.is_some();
    let series = match (cli.aspect_ratios, cli.factor_of_safety) {
        (true, _) => Some("--aspect-ratios (a series of runs)"),
        (_, true) => Some("--factor-of-safety (a search of trial runs)"),
        _ => None,
    };
    // Every rank decides alike, before any exchange: each exits, none ends the job (which
    // could stop rank 0 before it prints).
    if let Some(Err(message)) = series.map(|what| cli::refuse_ranks(&options, what)) {
        if root {
            eprintln!("error: {message}");
        }
        return ExitCode::FAILURE;
    }
    if cli.aspect_ratios {
        return aspect_ratios(cli.dx, &options, &out);
    }
    let scene = match load(&cli) {
        Ok(scene) => scene,
        Err(message) => {
            if root {
                eprintln!("error: {message}");
            }
            return ExitCode::FAILURE;
        }
    };
    if cli.factor_of_safety {
        if let Err(code) = one_run_only(&options, "--factor-of-safety runs trials") {
            return code;
        }
        if cli.end_time.is_some() && !cli.run_out {
            eprintln!(
                "slope-failure: --end-time is ignored by --factor-of-safety (each trial lasts at most `factor_of_safety.trial_time`)"
            );
        }
        let Some(factor) = factor_of_safety(&scene, &options, &out) else {
            return ExitCode::FAILURE;
        };
        if !cli.run_out {
            return ExitCode::SUCCESS;
        }
        let mut options = options;
        options.out_dir = Some(out.join("run-out"));
        let fate = if factor < 1.0 {
            "below 1: the slope fails at its own strength"
        } else {
            "at least 1: the frames show the slope at rest"
        };
        eprintln!(
            "slope-failure: the run-out of {} at F = 1 (its own strength; factor of safety {factor:.3}, {fate}), to t = {} s -> {}",
            scene.name,
            scene.end_time,
            out.join("run-out").display()
        );
        return run_frames(&scene, &options);
    }
    let say = |message: &str| {
        if root {
            eprintln!("slope-failure: {message}");
        }
    };
    say(&format!(
        "{} ({}D, dx = {} m, to t = {} s) -> {}",
        scene.name,
        scene.dimension,
        scene.dx,
        scene.end_time,
        out.display()
    ));
    if !matches!(scene.solver, SolverSpec::Soil(_)) {
        say(
            "a fluid scene (a flow down a slope, loads on barriers): VTU frames, diagnostics and the load and probe plots",
        );
        return run_frames(&scene, &options);
    }
    let column = scene
        .fluid
        .as_ref()
        .is_none_or(|soil| matches!(soil.blocks.first(), Some(Region::Box { .. })));
    if !column && scene.dimension == 3 {
        say(
            "the first soil block is not a box: the deposit is measured about the soil's vertical axis, as an axisymmetric column's",
        );
        return match slope_failure::axisymmetric::run(&scene, &options) {
            Ok(_) if !root => ExitCode::SUCCESS,
            Ok(report) => {
                println!("{}", report.summary);
                println!("{report}");
                println!(
                    "output             {} (open {}.pvd in ParaView; radial_runout, radial_farthest, height_at_axis in diagnostics.csv)",
                    out.display(),
                    scene.name
                );
                ExitCode::SUCCESS
            }
            Err(error) => failure(error, None, &options),
        };
    }
    if !column {
        say(
            "the first soil block is not a box, so no column to measure: VTU frames and diagnostics only",
        );
        return run_frames(&scene, &options);
    }
    match slope_failure::run(&scene, &options) {
        Ok(_) if !root => ExitCode::SUCCESS,
        Ok(report) => {
            println!("{}", report.summary);
            println!("{report}");
            println!(
                "output             {} (open {}.pvd in ParaView; runout.csv, runout.png, deposit.csv, deposit.png)",
                out.display(),
                scene.name
            );
            ExitCode::SUCCESS
        }
        Err(error) => failure(error, None, &options),
    }
}

/// Refuses `--restart` and `--checkpoint-every` for a mode that is not one run.
fn one_run_only(options: &geosph_runner::RunOptions, mode: &str) -> Result<(), ExitCode> {
    if options.restart.is_some() || options.checkpoint_every.is_some() {
        eprintln!("error: {mode}, not one run: it takes no --restart or --checkpoint-every");
        return Err(ExitCode::FAILURE);
    }
    Ok(())
}

/// Prints `error` and returns the exit status: 3 for a blow-up (its report is in the output
/// folder), the interrupt status after Ctrl-C (with `rerun`, what to do instead of a restart),
/// 1 otherwise. In a distributed run rank 0 prints; an error that ended every rank at the same
/// step ends each once rank 0 has printed ([`cli::end_together`]), another ends the job
/// ([`cli::end_ranks`]).
fn failure(
    error: slope_failure::Error,
    rerun: Option<&str>,
    options: &geosph_runner::RunOptions,
) -> ExitCode {
    let root = options.out_dir.is_some();
    match error {
        slope_failure::Error::Run(error) if !root && cli::ends_together(&error) => {
            cli::end_together(options, error.exit_code())
        }
        slope_failure::Error::Run(error @ RunError::Interrupted { .. }) => {
            match rerun {
                Some(rerun) => eprintln!("slope-failure: interrupted; {rerun}"),
                None => eprintln!("slope-failure: {error}"),
            }
            cli::end_together(options, error.exit_code())
        }
        slope_failure::Error::Run(error) => {
            eprintln!("error: {error}");
            if cli::ends_together(&error) {
                cli::end_together(options, error.exit_code())
            } else {
                cli::end_ranks(options, error.exit_code())
            }
        }
        error => {
            eprintln!("error: {error}");
            cli::end_ranks(options, 1)
        }
    }
}

/// The search and its report; the factor of safety, or `None` after printing the error.
fn factor_of_safety(
    scene: &Scene,
    options: &geosph_runner::RunOptions,
    out: &std::path::Path,
) -> Option<f64> {
    eprintln!(
        "slope-failure: factor of safety of {} ({}D, dx = {} m) -> {}",
        scene.name,
        scene.dimension,
        scene.dx,
        out.display()
    );
    let mut progress = |trial: &geosph_soil::sph::Trial| eprintln!("  {trial}");
    match slope_failure::factor_of_safety::search(scene, options, &mut progress) {
        Ok(result) => {
            print!("{result}");
            println!(
                "output             {} (factor-of-safety.csv, slip-surface.png, failing-state.vtu)",
                out.display()
            );
            Some(result.factor)
        }
        Err(error) => {
            eprintln!("error: {error}");
            None
        }
    }
}

/// The aspect-ratio series ([`slope_failure::aspect_ratios`]).
fn aspect_ratios(
    dx: Option<f64>,
    options: &geosph_runner::RunOptions,
    out: &std::path::Path,
) -> ExitCode {
    if let Err(code) = one_run_only(options, "--aspect-ratios runs a series") {
        return code;
    }
    let mut started = |scene: &Scene| {
        eprintln!(
            "slope-failure: {} (dx = {} m, to t = {} s)",
            scene.name, scene.dx, scene.end_time
        );
    };
    match slope_failure::aspect_ratios::run(dx, options, &mut started) {
        Ok(reports) => {
            for report in &reports {
                if let Some(experiment) = &report.experiment {
                    println!("{experiment}");
                }
                if let Some(comparison) = &report.aspect_ratio {
                    println!("{comparison}");
                }
            }
            println!(
                "output             {} (aspect-ratios.csv, aspect-ratios.png; one folder per column)",
                out.display()
            );
            ExitCode::SUCCESS
        }
        Err(error) => failure(
            error,
            Some("a series cannot be restarted: run --aspect-ratios again into a new folder"),
            options,
        ),
    }
}

/// Runs `scene` through the runner with no runout measures: VTU frames, diagnostics and the
/// summary (a slope, or the run-out after a factor-of-safety search).
fn run_frames(scene: &Scene, options: &geosph_runner::RunOptions) -> ExitCode {
    match geosph_runner::run(scene, options, &mut geosph_runner::NoObserver) {
        Ok(_) if options.out_dir.is_none() => ExitCode::SUCCESS,
        Ok(summary) => {
            println!("{summary}");
            if let Some(dir) = &options.out_dir {
                let fields = if matches!(scene.solver, SolverSpec::Soil(_)) {
                    "displacement, plastic strain, stress"
                } else {
                    "velocity, pressure"
                };
                let vtk = options.vtk.unwrap_or(scene.output.vtk);
                let mut files = vec![fields.to_owned()];
                files.extend(geosph_runner::scene_outputs(scene, vtk));
                println!(
                    "output             {} (open {}.pvd in ParaView: {}; diagnostics.csv)",
                    dir.display(),
                    scene.name,
                    files.join("; ")
                );
            }
            ExitCode::SUCCESS
        }
        Err(error) => failure(error.into(), None, options),
    }
}
