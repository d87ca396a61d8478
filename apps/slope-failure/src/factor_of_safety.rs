//! `slope-failure --factor-of-safety`: the strength-reduction search
//! ([`geosph_soil::factor_of_safety`]) on a 2D soil scene, with its outputs:
//! `factor-of-safety.csv` (every trial), `slip-surface.png` (the particles of the smallest
//! failing trial, those that flowed most drawn apart) and `failing-state.vtu` (that state and
//! the walls, for ParaView, with the fields of the run's frames: velocity, stress, p, q,
//! equivalent plastic strain, displacement).

use std::path::Path;

use geosph_core::Real;
use geosph_io::{PlotSpec, Series, line_plot_png, write_csv_atomically};
use geosph_runner::RunOptions;
use geosph_scene::{Scene, SolverSpec};
use geosph_soil::sph::Trial;
use geosph_soil::{FactorOfSafety, StrengthReductionConfig};
use geosph_sph::Solver;

use crate::Error;

/// A particle whose equivalent plastic strain exceeds this fraction of the largest one is
/// drawn as part of the slip surface in `slip-surface.png`.
pub const SLIP_FRACTION: Real = 0.1;

/// The search settings of `scene`: its solver's `factor_of_safety`, else the defaults.
pub fn settings(scene: &Scene) -> Result<StrengthReductionConfig, Error> {
    match &scene.solver {
        SolverSpec::Soil(config) => Ok(config.factor_of_safety.clone().unwrap_or_default()),
        _ => Err(Error::Scene(
            "a factor of safety needs a soil scene (its solver is not `Soil`)".into(),
        )),
    }
}

/// Runs the search on `scene` (2D) with the threads of `options`, calling `on_trial` after each
/// trial, and, with an output folder, writes its outputs there.
pub fn search(
    scene: &Scene,
    options: &RunOptions,
    on_trial: &mut (dyn FnMut(&Trial) + Send),
) -> Result<FactorOfSafety, Error> {
    let search = settings(scene)?;
    let SolverSpec::Soil(config) = &scene.solver else {
        unreachable!("settings() accepts soil scenes only")
    };
    if scene.dimension != 2 {
        return Err(Error::Scene(
            "the factor-of-safety search runs on 2D (plane-strain) scenes".into(),
        ));
    }
    if let Some(dir) = &options.out_dir {
        geosph_runner::output::check_folder(dir)
            .map_err(|reason| Error::Scene(format!("output folder {}: {reason}", dir.display())))?;
    }
    let work = move || -> Result<_, Error> {
        // `build` validates the scene.
        let (mut soil, inputs) = geosph_scene::build::<2>(scene)
            .map_err(|error| Error::Scene(error.to_string()))?
            .split();
        let (result, solver) =
            geosph_soil::factor_of_safety(config, &search, inputs, &mut soil, on_trial)
                .map_err(|error| Error::Scene(error.to_string()))?;
        if let Some(dir) = &options.out_dir {
            std::fs::create_dir_all(dir).map_err(|error| {
                Error::Scene(format!("output folder {}: {error}", dir.display()))
            })?;
            write_outputs(dir, &result, &soil, solver.as_ref())?;
        }
        Ok(result)
    };
    options
        .install(work)
        .map_err(|error| Error::Scene(format!("threads: {error}")))?
}

fn write_outputs(
    dir: &Path,
    result: &FactorOfSafety,
    soil: &geosph_core::Particles<2>,
    solver: &dyn Solver<2>,
) -> Result<(), Error> {
    write_csv_atomically(
        dir.join("factor-of-safety.csv"),
        &[
            "factor",
            "holds",
            "time",
            "steps",
            "max_displacement",
            "kinetic_energy_ratio",
        ],
        result.trials.iter().map(|trial| {
            [
                trial.factor,
                Real::from(u8::from(trial.holds())),
                trial.time,
                trial.steps as Real,
                trial.max_displacement,
                trial.kinetic_energy_ratio,
            ]
        }),
    )?;
    let fields = soil
        .soil
        .as_ref()
        .expect("a soil solver gives its particles soil fields");
    geosph_runner::output::write_particles(&dir.join("failing-state.vtu"), soil, solver)?;
    let largest = fields.plastic_strain.iter().copied().fold(0.0, Real::max);
    let threshold = SLIP_FRACTION * largest;
    let (mut still, mut slipped) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
    for (x, &plastic) in soil.position.iter().zip(&fields.plastic_strain) {
        let set = if plastic > threshold && plastic > 0.0 {
            &mut slipped
        } else {
            &mut still
        };
        set.0.push(x[0]);
        set.1.push(x[1]);
    }
    let title = format!(
        "Smallest failing trial, F = {:.3} (factor of safety {:.3})",
        result.bracket.1, result.factor
    );
    let label = format!("equivalent plastic strain > {threshold:.1e} (a tenth of the largest)");
    line_plot_png(
        dir.join("slip-surface.png"),
        &PlotSpec {
            title: &title,
            x_label: "x (m)",
            y_label: "y (m)",
            points: vec![
                Series {
                    label: "soil",
                    x: &still.0,
                    y: &still.1,
                },
                Series {
                    label: &label,
                    x: &slipped.0,
                    y: &slipped.1,
                },
            ],
            ..Default::default()
        },
    )?;
    Ok(())
}
