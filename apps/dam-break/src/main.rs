//! `dam-break`: runs the 2D dam break of its embedded scene (or a given scene) and compares it
//! with Martin & Moyce (1952).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::{CheckpointEvery, RunError, RunOptions, interrupt};
use geosph_scene::{Scene, SolverSpec};

/// Dam break with SPH, compared with the experiments of Martin & Moyce (1952).
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    /// Scene file (RON); default: the embedded 2D scene, a 1 m × 2 m column in a 4 m × 4 m tank.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Output folder [default: out/dam-break, or with --restart the checkpoint's folder].
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
    /// Solver (overrides the scene; its parameters take their defaults).
    #[arg(long, value_parser = SolverSpec::NAMES)]
    solver: Option<String>,
    /// Target average compression of the incompressible solvers, e.g. 0.001 for 0.1 %
    /// (overrides the scene).
    #[arg(long)]
    target_error: Option<f64>,
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
            (None, None) => PathBuf::from("out/dam-break"),
        }
    }
}

fn load(cli: &Cli) -> Result<Scene, String> {
    let text = match &cli.scene {
        Some(path) => std::fs::read_to_string(path)
            .map_err(|error| format!("cannot read scene {}: {error}", path.display()))?,
        None => dam_break::DEFAULT_SCENE.to_owned(),
    };
    let mut scene = Scene::from_ron(&text).map_err(|error| match &cli.scene {
        Some(path) => format!("{}: {error}", path.display()),
        None => error.to_string(),
    })?;
    if let Some(dx) = cli.dx {
        scene.dx = dx;
    }
    if let Some(end_time) = cli.end_time {
        scene.end_time = end_time;
    }
    if let Some(solver) = &cli.solver
        && solver != scene.solver.name()
    {
        scene.solver = SolverSpec::from_name(solver).expect("clap checked the name");
    }
    if let Some(target) = cli.target_error {
        match &mut scene.solver {
            SolverSpec::Pcisph(config) | SolverSpec::Iisph(config) | SolverSpec::Dfsph(config) => {
                config.target_density_error = target;
            }
            SolverSpec::Wcsph(_) | SolverSpec::Soil(_) => {
                return Err(format!(
                    "--target-error applies to pcisph, iisph and dfsph, not {}",
                    scene.solver.name()
                ));
            }
        }
    }
    // Everything a user can get wrong is reported here, before any output or banner.
    scene.validate().map_err(|error| error.to_string())?;
    geosph_runner::output::check_folder(&cli.out())
        .map_err(|reason| format!("output folder `{}`: {reason}", cli.out().display()))?;
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
        "dam-break: {} ({}D, dx = {} m, to t = {} s) -> {}",
        scene.name,
        scene.dimension,
        scene.dx,
        scene.end_time,
        out.display()
    );
    match dam_break::run(&scene, &options) {
        Ok(report) => {
            println!("{}", report.summary);
            if let Some(validation) = &report.validation {
                println!("{validation}");
            }
            println!(
                "output             {} (open {}.pvd in ParaView; front.png, height.png, front.csv)",
                out.display(),
                scene.name
            );
            ExitCode::SUCCESS
        }
        Err(dam_break::Error::Run(error @ RunError::Interrupted { .. })) => {
            eprintln!("dam-break: {error}");
            ExitCode::from(interrupt::EXIT_INTERRUPTED)
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
