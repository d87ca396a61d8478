//! `slope-failure`: runs the granular column collapse of Bui et al. (2008) (or a given soil
//! scene) and writes the runout, the deposit profile and VTU frames.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::cli::RunArgs;
use geosph_runner::{RunError, interrupt};
use geosph_scene::Scene;

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
    #[arg(long)]
    factor_of_safety: bool,
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
    let scene = match load(&cli) {
        Ok(scene) => scene,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    let out = cli.out();
    let options = match cli.run.options(out.clone()) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    if cli.factor_of_safety {
        if options.restart.is_some() || options.checkpoint_every.is_some() {
            eprintln!(
                "error: --factor-of-safety runs trials, not one run: it takes no --restart or --checkpoint-every"
            );
            return ExitCode::FAILURE;
        }
        if cli.end_time.is_some() {
            eprintln!(
                "slope-failure: --end-time is ignored by --factor-of-safety (each trial lasts at most `factor_of_safety.trial_time`)"
            );
        }
        return factor_of_safety(&scene, &options, &out);
    }
    eprintln!(
        "slope-failure: {} ({}D, dx = {} m, to t = {} s) -> {}",
        scene.name,
        scene.dimension,
        scene.dx,
        scene.end_time,
        out.display()
    );
    match slope_failure::run(&scene, &options) {
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
        Err(slope_failure::Error::Run(error @ RunError::Interrupted { .. })) => {
            eprintln!("slope-failure: {error}");
            ExitCode::from(interrupt::EXIT_INTERRUPTED)
        }
        Err(error) => {
            eprintln!("error: {error}");
            match error {
                // 3 for a blow-up (the report is in the output folder), 1 otherwise.
                slope_failure::Error::Run(error) => ExitCode::from(error.exit_code()),
                _ => ExitCode::FAILURE,
            }
        }
    }
}

fn factor_of_safety(
    scene: &Scene,
    options: &geosph_runner::RunOptions,
    out: &std::path::Path,
) -> ExitCode {
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
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
