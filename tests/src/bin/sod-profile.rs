//! Runs Sod's shock tube at the spacings given, prints the L1 errors against the exact
//! solution and the energy drift, and plots the finest run's ρ, u and p along the tube over
//! the exact profiles (the figure of `docs/gas.md`):
//!
//! `cargo run --release -p geosph-tests --bin sod-profile -- docs/img/sod-shock-tube.png 0.01 0.005 0.0025`

use geosph_core::Real;
use geosph_io::{PlotSpec, Series, line_plot_png};
use geosph_tests::shock_tube::{END_TIME, compare, exact};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let image = args
        .next()
        .ok_or("usage: sod-profile IMAGE.png DX [DX …]")?;
    let spacings: Vec<Real> = args.map(|a| a.parse()).collect::<Result<_, _>>()?;
    let finest = spacings.iter().copied().fold(Real::INFINITY, Real::min);
    if spacings.is_empty() {
        return Err("give at least one spacing".into());
    }
    println!("dx, L1 density, L1 velocity, L1 pressure, energy drift, particles");
    let mut last = None;
    for &dx in &spacings {
        let comparison = compare(dx);
        let [rho, u, p] = comparison.l1;
        println!(
            "{dx}, {rho:.4e}, {u:.4e}, {p:.4e}, {:.2e}, {}",
            comparison.energy_drift,
            comparison.fluid.len()
        );
        if dx == finest {
            last = Some(comparison.fluid);
        }
    }
    let fluid = last.expect("the finest run");
    // One row of particles along the tube, x ∈ [0, 1].
    let mut row: Vec<usize> = (0..fluid.len())
        .filter(|&i| fluid.position[i][1] < finest && (0.0..=1.0).contains(&fluid.position[i][0]))
        .collect();
    row.sort_by(|&a, &b| fluid.position[a][0].total_cmp(&fluid.position[b][0]));
    let x: Vec<Real> = row.iter().map(|&i| fluid.position[i][0]).collect();
    let pressure = fluid.pressure.as_ref().expect("a gas's pressure");
    let density: Vec<Real> = row.iter().map(|&i| fluid.density[i]).collect();
    let velocity: Vec<Real> = row.iter().map(|&i| fluid.velocity[i][0]).collect();
    let p: Vec<Real> = row.iter().map(|&i| pressure[i]).collect();
    let solution = exact();
    let grid: Vec<Real> = (0..=1000).map(|k| k as Real / 1000.0).collect();
    let sample = |x: Real| solution.sample((x - 0.5) / END_TIME);
    let exact_density: Vec<Real> = grid.iter().map(|&x| sample(x).density).collect();
    let exact_velocity: Vec<Real> = grid.iter().map(|&x| sample(x).velocity).collect();
    let exact_pressure: Vec<Real> = grid.iter().map(|&x| sample(x).pressure).collect();
    let title = format!(
        "Sod shock tube at t = {END_TIME} s, dx = {finest} m: particles and exact solution"
    );
    line_plot_png(
        &image,
        &PlotSpec {
            title: &title,
            x_label: "x (m)",
            y_label: "ρ (kg/m³), u (m/s), p (Pa)",
            lines: vec![
                Series {
                    label: "exact ρ",
                    x: &grid,
                    y: &exact_density,
                },
                Series {
                    label: "exact u",
                    x: &grid,
                    y: &exact_velocity,
                },
                Series {
                    label: "exact p",
                    x: &grid,
                    y: &exact_pressure,
                },
            ],
            points: vec![
                Series {
                    label: "SPH ρ",
                    x: &x,
                    y: &density,
                },
                Series {
                    label: "SPH u",
                    x: &x,
                    y: &velocity,
                },
                Series {
                    label: "SPH p",
                    x: &x,
                    y: &p,
                },
            ],
            ..Default::default()
        },
    )?;
    println!("wrote {image}");
    Ok(())
}
