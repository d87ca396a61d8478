//! `dam-break`: runs the 2D dam break of its embedded scene (or a given scene) and compares it
//! with Martin & Moyce (1952).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use geosph_runner::RunError;
use geosph_runner::cli::{self, RunArgs};
use geosph_scene::{Scene, SolverSpec};

/// Dam break with SPH, compared with the experiments of Martin & Moyce (1952).
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    /// Scene file (RON); default: the embedded 2D scene, a 1 m × 2 m column in a 4 m × 4 m tank.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Particle spacing in m (overrides the scene).
    #[arg(long)]
    dx: Option<f64>,
    /// Simulated end time in s (overrides the scene).
    #[arg(long)]
    end_time: Option<f64>,
    /// Solver (overrides the scene; its parameters take their defaults).
    #[arg(long, value_parser = SolverSpec::NAMES)]
    solver: Option<String>,
    /// Target average compression of the incompressible solvers, e.g. 0.001 for 0.1 %
    /// (overrides the scene).
    #[arg(long)]
    target_error: Option<f64>,
    /// Output, threads, progress, checkpoints and restart.
    #[command(flatten)]
    run: RunArgs,
}

impl Cli {
    /// The output folder: `--out`, else the restart file's folder, else `out/dam-break`.
    fn out(&self) -> PathBuf {
        self.run.out("out/dam-break")
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
    // Under `mpiexec` rank 0 alone writes the output.
    if geosph_runner::cli::launch_root() {
        geosph_runner::output::check_folder(&cli.out())
            .map_err(|reason| format!("output folder `{}`: {reason}", cli.out().display()))?;
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
    let root = options.out_dir.is_some();
    if root {
        eprintln!(
            "dam-break: {} ({}D, dx = {} m, to t = {} s) -> {}",
            scene.name,
            scene.dimension,
            scene.dx,
            scene.end_time,
            out.display()
        );
    }
    match dam_break::run(&scene, &options) {
        // The other ranks of a distributed run report nothing: rank 0 prints the summary.
        Ok(_) if !root => ExitCode::SUCCESS,
        Ok(report) => {
            println!("{}", report.summary);
            if let Some(validation) = &report.validation {
                println!("{validation}");
            }
            if let Some(wall_pressure) = &report.wall_pressure {
                println!("{wall_pressure}");
            }
            let vtk = options.vtk.unwrap_or(scene.output.vtk);
            let mut files = geosph_runner::scene_outputs(&scene, vtk);
            if !report.samples.is_empty() {
                files.push("front.png, height.png, front.csv".to_owned());
            }
            if report.wall_pressure.is_some() {
                files.push("wall-pressure.png".to_owned());
            }
            files.push("diagnostics.csv".to_owned());
            println!(
                "output             {} (open {}.pvd in ParaView; {})",
                out.display(),
                scene.name,
                files.join(", ")
            );
            ExitCode::SUCCESS
        }
        // Every rank stops at the same step on an interrupt or a blow-up: the others wait
        // until rank 0 has written its files and message.
        Err(dam_break::Error::Run(error)) if !root && cli::ends_together(&error) => {
            cli::end_together(&options, error.exit_code())
        }
        Err(dam_break::Error::Run(error @ RunError::Interrupted { .. })) => {
            eprintln!("dam-break: {error}");
            cli::end_together(&options, error.exit_code())
        }
        Err(error) => {
            eprintln!("error: {error}");
            match error {
                // 3 for a blow-up (the report is in the output folder), 1 otherwise.
                dam_break::Error::Run(error) if cli::ends_together(&error) => {
                    cli::end_together(&options, error.exit_code())
                }
                dam_break::Error::Run(error) => cli::end_ranks(&options, error.exit_code()),
                _ => cli::end_ranks(&options, 1),
            }
        }
    }
}
