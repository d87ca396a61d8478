//! `slope-failure`: runs the granular column collapse of Bui et al. (2008) (or a given soil
//! scene) and writes the runout, the deposit profile and VTU frames.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::RunOptions;
use geosph_scene::Scene;

/// Granular column collapse and slope failure with elastoplastic soil SPH.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    /// Scene file (RON); default: the embedded granular column collapse of Bui et al. (2008),
    /// a 0.2 m × 0.1 m column of aluminium bars released on one side.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "out/slope-failure")]
    out: PathBuf,
    /// Particle spacing in m (overrides the scene).
    #[arg(long)]
    dx: Option<f64>,
    /// Simulated end time in s (overrides the scene).
    #[arg(long)]
    end_time: Option<f64>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
    /// Do not write VTU frames.
    #[arg(long)]
    no_vtk: bool,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

fn load(cli: &Cli) -> Result<Scene, String> {
    let text = match &cli.scene {
        Some(path) => std::fs::read_to_string(path)
            .map_err(|error| format!("cannot read scene {}: {error}", path.display()))?,
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
    let options = RunOptions {
        out_dir: Some(cli.out.clone()),
        vtk: cli.no_vtk.then_some(false),
        threads: cli.threads,
        progress: !cli.quiet,
    };
    eprintln!(
        "slope-failure: {} ({}D, dx = {} m, to t = {} s) -> {}",
        scene.name,
        scene.dimension,
        scene.dx,
        scene.end_time,
        cli.out.display()
    );
    match slope_failure::run(&scene, &options) {
        Ok(report) => {
            println!("{}", report.summary);
            println!("{report}");
            println!(
                "output             {} (open {}.pvd in ParaView; runout.csv, runout.png, deposit.png)",
                cli.out.display(),
                scene.name
            );
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
