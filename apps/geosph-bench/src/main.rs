//! `geosph-bench`: error against run time of geosph's solvers on cases with a reference, and
//! their stability under stress.
//!
//! ```sh
//! cargo run --release -p geosph-bench -- --quick            # the CI matrix, under 5 minutes
//! cargo run --release -p geosph-bench                       # the full matrix → docs/
//! cargo run --release -p geosph-bench -- --stability        # the stability map → docs/
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use geosph_bench::{Case, matrix, report, stability};

/// Accuracy against cost, and stability under stress, of geosph's solvers.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Cli {
    /// Run the small CI matrix (coarse, short runs; under 5 minutes on 2 cores).
    #[arg(long)]
    quick: bool,
    /// Run the stability map (time-step bisection and stress cases) instead of the matrix.
    #[arg(long)]
    stability: bool,
    /// Only these cases (taylor-green, poiseuille, couette, hydrostatic, dam-break, wall-pressure,
    /// collapse, k0-column, square-drop, shock-tube).
    #[arg(long = "case", value_parser = parse_case)]
    cases: Vec<Case>,
    /// Output folder: the report (`benchmarks.md` or `stability.md`), the CSV and `img/`
    /// [default: `docs`, or `target/bench-quick` with --quick].
    #[arg(long)]
    out: Option<PathBuf>,
}

fn parse_case(name: &str) -> Result<Case, String> {
    Case::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Case::ALL.iter().map(|case| case.name()).collect();
        format!("unknown case `{name}`; one of {}", names.join(", "))
    })
}

fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|line| line.starts_with("model name"))
                .and_then(|line| line.split(':').nth(1))
                .map(|model| model.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    format!("{cores} threads on {model}")
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    geosph_io::write_atomically(path, |file| file.write_all(text.as_bytes()))
        .map_err(|error| format!("{}: {error}", path.display()))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Runs what `cli` asks; `Ok(false)` when a run failed (reported, exit status 2).
fn run(cli: &Cli) -> Result<bool, String> {
    let out = cli.out.clone().unwrap_or_else(|| {
        PathBuf::from(if cli.quick {
            "target/bench-quick"
        } else {
            "docs"
        })
    });
    let images = out.join("img");
    std::fs::create_dir_all(&images)
        .map_err(|error| format!("output folder `{}`: {error}", images.display()))?;
    let command: Vec<String> = std::env::args().collect();
    let started = Instant::now();
    if cli.stability {
        let results = stability::run_all(cli.quick);
        let ok = results.iter().all(|r| r.passed);
        let header = format!(
            "# Stability map\n\nWritten by `{}` ({}, {:.0} s). Do not edit by hand: rerun.\n",
            command.join(" "),
            machine(),
            started.elapsed().as_secs_f64()
        );
        write(
            &out.join("stability.md"),
            &stability::markdown(&results, &header),
        )?;
        eprintln!("wrote {}", out.join("stability.md").display());
        return Ok(ok);
    }
    let cases = if cli.cases.is_empty() {
        Case::ALL.to_vec()
    } else {
        cli.cases.clone()
    };
    let configs = matrix::configurations(&cases, cli.quick);
    eprintln!(
        "{} configurations, {}",
        configs.len(),
        if cli.quick { "quick" } else { "full" }
    );
    let outcomes = matrix::run_all(&configs, cli.quick);
    write(&out.join("benchmarks.csv"), &report::csv(&outcomes))?;
    for &case in &cases {
        let path = images.join(format!("bench-{}.png", case.name()));
        report::plot(&path, case, &outcomes).map_err(|error| error.to_string())?;
    }
    let header = format!(
        "# Accuracy against run time\n\nWritten by `{}` on {} in {:.0} s; every figure below \
         is from that run (wall time of one run at a time, all threads). Do not edit by hand: \
         rerun. The data are in `benchmarks.csv`.\n",
        command.join(" "),
        machine(),
        started.elapsed().as_secs_f64()
    );
    write(
        &out.join("benchmarks.md"),
        &report::markdown(&outcomes, &header, "img"),
    )?;
    let failed: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.completed())
        .map(|o| {
            format!(
                "{} {}: {}",
                o.config.case.name(),
                o.config.label(),
                o.status
            )
        })
        .collect();
    eprintln!(
        "wrote {} ({} runs, {} failed)",
        out.join("benchmarks.md").display(),
        outcomes.len(),
        failed.len()
    );
    for line in &failed {
        eprintln!("failed: {line}");
    }
    Ok(failed.is_empty())
}
