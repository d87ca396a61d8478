//! The harness's outputs: a CSV of every run, a Markdown report with the convergence orders and
//! the Pareto front of each case, and log–log plots of error against wall time.

use std::fmt::Write as _;
use std::path::Path;

use geosph_core::Real;
use geosph_io::plot::{Axes, PlotSpec, Series, line_plot_png};

use crate::matrix::{by_series, orders};
use crate::{Case, Outcome};

/// The CSV of all runs, one row per configuration.
pub fn csv(outcomes: &[Outcome]) -> String {
    let mut text = String::from(
        "case,solver,kernel,variant,dx,dt_factor,particles,steps,wall_time_s,\
         particle_steps_per_s,value,error,status\n",
    );
    for o in outcomes {
        let c = &o.config;
        let _ = writeln!(
            text,
            "{},{},{},{},{},{},{},{},{:.4},{:.6e},{:.6e},{:.6e},\"{}\"",
            c.case.name(),
            c.solver,
            c.kernel,
            c.variant,
            c.dx,
            c.dt_factor,
            o.particles,
            o.steps,
            o.wall_time,
            o.particle_steps_per_second,
            o.value,
            o.error,
            o.status.replace('"', "'")
        );
    }
    text
}

/// Indices of the runs on the Pareto front of error against wall time (no other run is both
/// faster and more accurate), sorted by wall time.
pub fn pareto_front(outcomes: &[Outcome], runs: &[usize]) -> Vec<usize> {
    let mut sorted: Vec<usize> = runs
        .iter()
        .copied()
        .filter(|&i| outcomes[i].is_ok())
        .collect();
    sorted.sort_by(|&a, &b| {
        outcomes[a]
            .wall_time
            .total_cmp(&outcomes[b].wall_time)
            .then(outcomes[a].error.total_cmp(&outcomes[b].error))
    });
    let mut front = Vec::new();
    let mut best = Real::INFINITY;
    for i in sorted {
        if outcomes[i].error < best {
            best = outcomes[i].error;
            front.push(i);
        }
    }
    front
}

/// Writes the plot of `case` (error against wall time, one marker colour per solver and
/// kernel, the Pareto front as a line) to `path`.
pub fn plot(path: &Path, case: Case, outcomes: &[Outcome]) -> Result<(), geosph_io::Error> {
    let runs: Vec<usize> = (0..outcomes.len())
        .filter(|&i| outcomes[i].config.case == case && outcomes[i].is_ok())
        .collect();
    let mut groups: Vec<(String, Vec<Real>, Vec<Real>)> = Vec::new();
    for &i in &runs {
        let c = &outcomes[i].config;
        let label = if c.variant == "default" || c.variant == "fourtakas" {
            format!("{} {}", c.solver, c.kernel)
        } else {
            format!("{}+{} {}", c.solver, c.variant, c.kernel)
        };
        let label = if c.dt_factor == 1.0 {
            label
        } else {
            format!("{label} dt×{}", c.dt_factor)
        };
        match groups.iter_mut().find(|g| g.0 == label) {
            Some(group) => {
                group.1.push(outcomes[i].wall_time);
                group.2.push(outcomes[i].error);
            }
            None => groups.push((label, vec![outcomes[i].wall_time], vec![outcomes[i].error])),
        }
    }
    let front = pareto_front(outcomes, &runs);
    let front_time: Vec<Real> = front.iter().map(|&i| outcomes[i].wall_time).collect();
    let front_error: Vec<Real> = front.iter().map(|&i| outcomes[i].error).collect();
    let title = format!("{}: error against wall time", case.name());
    let spec = PlotSpec {
        title: &title,
        x_label: "wall time (s)",
        y_label: "error",
        lines: vec![Series {
            label: "Pareto front",
            x: &front_time,
            y: &front_error,
        }],
        points: groups
            .iter()
            .map(|(label, x, y)| Series { label, x, y })
            .collect(),
        axes: Axes::LogLog,
        ..Default::default()
    };
    line_plot_png(path, &spec)
}

/// The Markdown report: per case its error definition, the plot, the Pareto front (which
/// configuration is cheapest for which accuracy), the observed orders of convergence and every
/// run; then the failed runs.
pub fn markdown(outcomes: &[Outcome], header: &str, image_folder: &str) -> String {
    let mut text = String::from(header);
    let groups = by_series(outcomes);
    for case in Case::ALL {
        let runs: Vec<usize> = (0..outcomes.len())
            .filter(|&i| outcomes[i].config.case == case)
            .collect();
        if runs.is_empty() {
            continue;
        }
        let _ = writeln!(text, "\n## {}\n", case.name());
        let _ = writeln!(text, "Error: {}.\n", case.error_definition());
        let _ = writeln!(
            text,
            "![{} error against wall time]({image_folder}/bench-{}.png)\n",
            case.name(),
            case.name()
        );
        let front = pareto_front(outcomes, &runs);
        if let Some(&cheapest) = front.first() {
            let _ = writeln!(
                text,
                "Which configuration wins: reading the front from cheap to accurate, each line \
                 is the cheapest run that reaches its error. The cheapest run of all is {} \
                 ({:.2} s, error {:.2e}); the most accurate is {} ({:.2} s, error {:.2e}).\n",
                outcomes[cheapest].config.label(),
                outcomes[cheapest].wall_time,
                outcomes[cheapest].error,
                outcomes[*front.last().unwrap_or(&cheapest)].config.label(),
                outcomes[*front.last().unwrap_or(&cheapest)].wall_time,
                outcomes[*front.last().unwrap_or(&cheapest)].error,
            );
            text.push_str("| for error ≤ | use | wall time (s) |\n| --- | --- | --- |\n");
            for &i in &front {
                let _ = writeln!(
                    text,
                    "| {:.2e} | {} | {:.2} |",
                    outcomes[i].error,
                    outcomes[i].config.label(),
                    outcomes[i].wall_time
                );
            }
        }
        text.push_str(
            "\nObserved order of convergence, p = ln(e₁/e₂)/ln(dx₁/dx₂) between successive \
             resolutions:\n\n| solver | kernel | variant | dt× | errors, coarse to fine | p |\n\
             | --- | --- | --- | --- | --- | --- |\n",
        );
        for (series, members) in &groups {
            if series.0 != case || members.len() < 2 {
                continue;
            }
            let errors: Vec<String> = members
                .iter()
                .map(|&i| format!("{:.2e}", outcomes[i].error))
                .collect();
            let p: Vec<String> = orders(outcomes, members)
                .iter()
                .map(|p| format!("{p:.2}"))
                .collect();
            let _ = writeln!(
                text,
                "| {} | {} | {} | {} | {} | {} |",
                series.1,
                series.2,
                series.3,
                Real::from_bits(series.4),
                errors.join(", "),
                p.join(", ")
            );
        }
        text.push_str(
            "\n<details><summary>Every run</summary>\n\n| configuration | particles | steps | \
             wall time (s) | M particle-steps/s | error |\n| --- | --- | --- | --- | --- | --- |\n",
        );
        for &i in &runs {
            let o = &outcomes[i];
            let _ = writeln!(
                text,
                "| {} | {} | {} | {:.2} | {:.2} | {} |",
                o.config.label(),
                o.particles,
                o.steps,
                o.wall_time,
                o.particle_steps_per_second * 1e-6,
                if o.is_ok() {
                    format!("{:.3e}", o.error)
                } else if o.completed() {
                    "finished without an error measure".to_string()
                } else {
                    format!("failed: {}", o.status)
                }
            );
        }
        text.push_str("\n</details>\n");
    }
    text
}
