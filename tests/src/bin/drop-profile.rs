//! Runs the square drop and the oscillating drop of `docs/surface-tension.md` at the spacings
//! given, prints the Laplace jump and the shape against the circle's, and the measured mode-2
//! period and decay rate against Lamb's and the viscous normal mode's, and plots the finest
//! runs: the pressure across the relaxed drop over the jump σ/R, and the oscillating drop's
//! shape moment over the viscous mode and Lamb's period:
//!
//! `cargo run --release -p geosph-tests --bin drop-profile -- docs/img 0.02 0.01`

use std::f64::consts::PI;
use std::path::Path;

use geosph_core::{Real, Vector};
use geosph_io::{PlotSpec, Series, line_plot_png};
use geosph_tests::drops::{
    DropRecord, decay_rate, elliptic_drop, lamb_frequency, period, record, relaxed, square_drop,
    viscous_rate,
};

/// The oscillating drop's radius, amplitude ε, viscosity and duration.
const ELLIPSE: (Real, Real, Real, Real) = (0.2, 0.1, 0.005, 1.5);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let folder = args.next().ok_or("usage: drop-profile FOLDER DX [DX …]")?;
    let spacings: Vec<Real> = args.map(|a| a.parse()).collect::<Result<_, _>>()?;
    let finest = spacings.iter().copied().fold(Real::INFINITY, Real::min);
    if spacings.is_empty() {
        return Err("give at least one spacing".into());
    }
    println!(
        "square drop at t = 2 s: dx, particles, R, jump, sigma/R, error, farthest drop/R, \
         nearest other phase/R, largest speed"
    );
    let mut square = None;
    for &dx in &spacings {
        let scene = square_drop(dx, 2.0, 0.05);
        let run = record(&scene);
        let r = relaxed(&run, dx, 2.0 * scene.smoothing_ratio * dx);
        println!(
            "{dx}, {}, {:.4}, {:.4}, {:.4}, {:+.2} %, {:.3}, {:.3}, {:.3e}",
            run.last.as_ref().map_or(0, |f| f.len()),
            r.radius,
            r.jump,
            r.laplace,
            100.0 * (r.jump / r.laplace - 1.0),
            r.farthest_drop,
            r.nearest_outside,
            r.max_speed
        );
        if dx == finest {
            square = Some((run, r.laplace));
        }
    }
    println!(
        "oscillating drop: dx, R, measured period, Lamb's period, error, viscous mode's period, \
         error, measured decay rate, viscous mode's, error"
    );
    let mut ellipse = None;
    for &dx in &spacings {
        let (radius, epsilon, viscosity, end) = ELLIPSE;
        let run = record(&elliptic_drop(dx, radius, epsilon, viscosity, end));
        let radius = (run.drop as Real * dx * dx / PI).sqrt();
        let lamb = 2.0 * PI / lamb_frequency(2, radius);
        let mode = viscous_rate(2, radius, viscosity);
        let viscous = 2.0 * PI / mode.im;
        let measured = period(&run.moment, 4).ok_or("fewer than two periods")?;
        let decay = decay_rate(&run.moment, 4).ok_or("fewer than two periods")?;
        println!(
            "{dx}, {radius:.4}, {measured:.4}, {lamb:.4}, {:+.2} %, {viscous:.4}, {:+.2} %, \
             {decay:.3}, {:.3}, {:+.1} %",
            100.0 * (measured / lamb - 1.0),
            100.0 * (measured / viscous - 1.0),
            -mode.re,
            100.0 * (decay / -mode.re - 1.0)
        );
        if dx == finest {
            ellipse = Some((run, lamb, mode));
        }
    }
    let (run, laplace) = square.expect("the finest square drop");
    plot_pressure(
        &Path::new(&folder).join("square-drop.png"),
        &run,
        laplace,
        finest,
    )?;
    let (run, lamb, mode) = ellipse.expect("the finest elliptic drop");
    plot_moment(
        &Path::new(&folder).join("oscillating-drop.png"),
        &run,
        (lamb, mode),
        finest,
    )?;
    Ok(())
}

/// p − p_out against the distance from the drop's centroid, with the jump σ/R at R.
fn plot_pressure(
    image: &Path,
    run: &DropRecord,
    laplace: Real,
    dx: Real,
) -> Result<(), Box<dyn std::error::Error>> {
    let fluid = run.last.as_ref().expect("a sample");
    let pressure = fluid.pressure.as_ref().expect("a pressure");
    let drop: Vec<usize> = (0..fluid.len())
        .filter(|&i| fluid.id[i] < run.drop)
        .collect();
    let centre = drop.iter().map(|&i| fluid.position[i]).sum::<Vector<2>>() / drop.len() as Real;
    let radius = (run.drop as Real * dx * dx / PI).sqrt();
    // The pressure far out: the mean beyond 1.5 R.
    let distance = |i: usize| (fluid.position[i] - centre).norm();
    let far: Vec<Real> = (0..fluid.len())
        .filter(|&i| distance(i) > 1.5 * radius)
        .map(|i| pressure[i])
        .collect();
    let outside = far.iter().sum::<Real>() / far.len() as Real;
    let r: Vec<Real> = (0..fluid.len()).map(distance).collect();
    let p: Vec<Real> = pressure.iter().map(|p| p - outside).collect();
    let step_r = [0.0, radius, radius, 2.0 * radius];
    let step_p = [laplace, laplace, 0.0, 0.0];
    let title = format!(
        "Square drop relaxed (t = 2 s, dx = {dx} m): pressure against σ/R = {laplace:.3} Pa"
    );
    line_plot_png(
        image,
        &PlotSpec {
            title: &title,
            x_label: "distance from the drop's centre (m)",
            y_label: "p − p_out (Pa)",
            lines: vec![Series {
                label: "Laplace jump σ/R at R",
                x: &step_r,
                y: &step_p,
            }],
            points: vec![Series {
                label: "SPH particles",
                x: &r,
                y: &p,
            }],
            x_range: Some((0.0, 2.0 * radius)),
            ..Default::default()
        },
    )?;
    println!("wrote {}", image.display());
    Ok(())
}

/// The shape moment Q(t)/Q(0) with the viscous mode's e^{−γt} cos ωt and Lamb's cos(2πt/T).
fn plot_moment(
    image: &Path,
    run: &DropRecord,
    (lamb, mode): (Real, nalgebra::Complex<Real>),
    dx: Real,
) -> Result<(), Box<dyn std::error::Error>> {
    let q0 = run.moment[0].1;
    let t: Vec<Real> = run.moment.iter().map(|m| m.0).collect();
    let q: Vec<Real> = run.moment.iter().map(|m| m.1 / q0).collect();
    let reference: Vec<Real> = t.iter().map(|&t| (2.0 * PI * t / lamb).cos()).collect();
    let viscous: Vec<Real> = t
        .iter()
        .map(|&t| (mode.re * t).exp() * (mode.im * t).cos())
        .collect();
    let title = format!("Oscillating drop, mode 2 (dx = {dx} m): shape moment and references");
    line_plot_png(
        image,
        &PlotSpec {
            title: &title,
            x_label: "t (s)",
            y_label: "Q(t)/Q(0), Q = Σ (x − x̄)² − (y − ȳ)²",
            lines: vec![
                Series {
                    label: "SPH",
                    x: &t,
                    y: &q,
                },
                Series {
                    label: "viscous normal mode e^(−γt) cos ωt",
                    x: &t,
                    y: &viscous,
                },
                Series {
                    label: "cos(2πt/T), T of Lamb (1932), inviscid",
                    x: &t,
                    y: &reference,
                },
            ],
            ..Default::default()
        },
    )?;
    println!("wrote {}", image.display());
    Ok(())
}
