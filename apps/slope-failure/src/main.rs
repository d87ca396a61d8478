//! `slope-failure`: runs the granular column collapse of Bui et al. (2008) (or a given soil
//! scene) and writes the runout, the deposit profile and VTU frames.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::{CheckpointEvery, RunError, RunOptions, interrupt};
use geosph_scene::Scene;

/// Granular column collapse and slope failure with elastoplastic soil SPH.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    /// Scene file (RON); default: the embedded granular column collapse of Bui et al. (2008),
    /// a 0.2 m × 0.1 m column of aluminium bars released on one side.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Output folder [default: out/slope-failure, or with --restart the checkpoint's folder].
    #[arg(long)]
    out: Option<PathBuf>,
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
    /// Write the complete state to `checkpoint.bin` in the output folder (replacing the
    /// previous one) at this interval: a bare number is simulated seconds (`0.5`), a number
    /// with a unit is wall-clock time (`30s`, `10min`, `2h`). Ctrl-C always writes one, with
    /// the current frame as `interrupted.vtu`, and exits with status 130.
    #[arg(long, value_name = "INTERVAL")]
    checkpoint_every: Option<CheckpointEvery>,
    /// Continue the run saved in this checkpoint, into its output folder; give the same scene
    /// and overrides. The frames and the `.pvd` continue bitwise as if never stopped.
    #[arg(long, value_name = "FILE")]
    restart: Option<PathBuf>,
}

impl Cli {
    /// The output folder: `--out`, else the restart file's folder, else the default.
    fn out(&self) -> PathBuf {
        match (&self.out, &self.restart) {
            (Some(out), _) => out.clone(),
            (None, Some(restart)) => restart
                .parent()
                .filter(|dir| !dir.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), PathBuf::from),
            (None, None) => PathBuf::from("out/slope-failure"),
        }
    }
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
    let interrupt = match interrupt::on_ctrl_c() {
        Ok(flag) => flag,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    let out = cli.out();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        vtk: cli.no_vtk.then_some(false),
        threads: cli.threads,
        progress: !cli.quiet,
        checkpoint_every: cli.checkpoint_every,
        restart: cli.restart.clone(),
        interrupt: Some(interrupt),
    };
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
                "output             {} (open {}.pvd in ParaView; runout.csv, runout.png, deposit.png)",
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
            ExitCode::FAILURE
        }
    }
}
