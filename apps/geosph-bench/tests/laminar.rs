//! Start-up of plane Poiseuille and Couette flow (Morris, Fox & Zhu 1997) with WCSPH and DFSPH
//! and the laminar viscosity, against the series solutions: the layer-averaged velocity profile
//! must lie within 1 % of the steady speed scale at 0.0225, 0.045, 0.1125, 0.225 and 0.9 s
//! (steady state), with 20 particles across the channel.

use geosph_bench::{Case, Config};

fn profile_error(case: Case, solver: &'static str) -> f64 {
    let config = Config {
        case,
        solver,
        kernel: "wendland-c2",
        variant: "default",
        dx: 5e-5,
        dt_factor: 1.0,
    };
    let measured = case.run(&config, false).expect("the channel flow runs");
    eprintln!(
        "{} {solver}: largest profile error {:.4}",
        case.name(),
        measured.error
    );
    measured.error
}

#[test]
fn poiseuille_start_up_follows_the_series() {
    for solver in ["wcsph", "dfsph"] {
        let error = profile_error(Case::Poiseuille, solver);
        assert!(error <= 0.01, "{solver}: profile error {error} exceeds 1 %");
    }
}

#[test]
fn couette_start_up_follows_the_series() {
    for solver in ["wcsph", "dfsph"] {
        let error = profile_error(Case::Couette, solver);
        assert!(error <= 0.01, "{solver}: profile error {error} exceeds 1 %");
    }
}
