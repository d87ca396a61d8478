//! The element-test driver: one material point driven along a strain path through the same
//! constitutive code the SPH solver calls, reporting the stress path (p, q).
//!
//! Axes: x and z are horizontal, y is vertical (the 2D convention of geosph). All strains are
//! tension positive; the compressive paths take positive magnitudes and document the sign.

use std::io::{self, Write};

use geosph_core::{Real, Tensor3};

use crate::constitutive::{Constitutive, Response};
use crate::invariants::{deviatoric_stress, mean_pressure};

/// A loading path, applied in equal increments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LoadingPath {
    /// A constant velocity gradient L (3×3, L_αβ = ∂v_α/∂x_β) applied for `duration`: each
    /// step gets Δε = ½(L + Lᵀ) Δt and Δω = ½(L − Lᵀ) Δt.
    VelocityGradient {
        /// L.
        velocity_gradient: Tensor3,
        /// Total time.
        duration: Real,
    },
    /// Plane-strain simple shear v_x = γ̇ y to the engineering shear strain γ = 2ε_xy; with
    /// `spin` the Jaumann rotation ω_xy = γ̇/2 acts, without it the path is pure strain
    /// (ε_xy only), for which the closed forms hold.
    SimpleShear {
        /// Final γ.
        shear_strain: Real,
        /// Whether the spin increment is passed to the model.
        spin: bool,
    },
    /// Oedometric (1D, K₀) compression: ε_yy goes from 0 to −`axial_strain`, ε_xx = ε_zz = 0.
    Oedometer {
        /// Final vertical compressive strain (positive).
        axial_strain: Real,
    },
    /// Drained axisymmetric triaxial compression: ε_yy goes from 0 to −`axial_strain` while
    /// the lateral strains ε_xx = ε_zz are solved each step so that the lateral stress
    /// (σ_xx + σ_zz)/2 keeps its initial value (secant iteration to 1e-12 of the stress scale).
    TriaxialCompression {
        /// Final axial compressive strain (positive).
        axial_strain: Real,
    },
}

/// An element test: the initial stress, the path and the number of equal increments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementTest {
    /// σ₀ (tension positive), e.g. `-p0 * Tensor3::identity()` for an isotropic confinement.
    pub initial_stress: Tensor3,
    /// The path.
    pub path: LoadingPath,
    /// Number of increments (≥ 1).
    pub steps: usize,
}

/// One point of the stress path (the initial state is step 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// Increment index, 0 for the initial state.
    pub step: usize,
    /// Accumulated total strain Σ Δε.
    pub strain: Tensor3,
    /// σ after this step.
    pub stress: Tensor3,
    /// p = −I₁/3.
    pub p: Real,
    /// q = √(3 J₂).
    pub q: Real,
    /// f(σ) if the model has a yield function.
    pub yield_value: Option<Real>,
    /// Accumulated equivalent plastic strain ε̄ᵖ.
    pub plastic_strain: Real,
    /// Where the step ended ([`Response::Elastic`] for step 0).
    pub response: Response,
}

/// Why an element test could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ElementTestError {
    /// `steps` was 0.
    #[error("element test: steps must be at least 1")]
    NoSteps,
    /// The lateral-stress iteration of a triaxial step did not converge.
    #[error(
        "element test: triaxial step {step}: lateral stress residual {residual:e} after {iterations} iterations"
    )]
    NotConverged {
        /// The increment index.
        step: usize,
        /// The last residual |σ_lateral − target|.
        residual: Real,
        /// Iterations done.
        iterations: usize,
    },
}

fn point<M: Constitutive + ?Sized>(
    model: &M,
    step: usize,
    strain: Tensor3,
    stress: Tensor3,
    plastic_strain: Real,
    response: Response,
) -> PathPoint {
    PathPoint {
        step,
        strain,
        stress,
        p: mean_pressure(&stress),
        q: deviatoric_stress(&stress),
        yield_value: model.yield_function(&stress),
        plastic_strain,
        response,
    }
}

/// Drives `model` along `test.path` from `test.initial_stress` and returns the `steps + 1`
/// points of the path (initial state first).
pub fn run_element_test<M: Constitutive + ?Sized>(
    model: &M,
    test: &ElementTest,
) -> Result<Vec<PathPoint>, ElementTestError> {
    if test.steps == 0 {
        return Err(ElementTestError::NoSteps);
    }
    let n = test.steps as Real;
    let mut stress = test.initial_stress;
    let mut strain = Tensor3::zeros();
    let mut plastic_strain = 0.0;
    let mut path = Vec::with_capacity(test.steps + 1);
    path.push(point(model, 0, strain, stress, 0.0, Response::Elastic));

    // Strain-controlled paths as a constant (Δε, Δω) per step.
    let fixed = |l: Tensor3, duration: Real, with_spin: bool| {
        let dt = duration / n;
        let d = (l + l.transpose()) * (0.5 * dt);
        let w = if with_spin {
            (l - l.transpose()) * (0.5 * dt)
        } else {
            Tensor3::zeros()
        };
        (d, w)
    };
    let increments = match test.path {
        LoadingPath::VelocityGradient {
            velocity_gradient,
            duration,
        } => Some(fixed(velocity_gradient, duration, true)),
        LoadingPath::SimpleShear { shear_strain, spin } => {
            let mut l = Tensor3::zeros();
            l[(0, 1)] = shear_strain;
            Some(fixed(l, 1.0, spin))
        }
        LoadingPath::Oedometer { axial_strain } => {
            let mut l = Tensor3::zeros();
            l[(1, 1)] = -axial_strain;
            Some(fixed(l, 1.0, false))
        }
        LoadingPath::TriaxialCompression { .. } => None,
    };

    for step in 1..=test.steps {
        let (strain_increment, update) = match (increments, test.path) {
            (Some((d, w)), _) => (d, model.update(&stress, &d, &w)),
            (None, LoadingPath::TriaxialCompression { axial_strain }) => {
                let target = 0.5 * (test.initial_stress[(0, 0)] + test.initial_stress[(2, 2)]);
                triaxial_step(model, &stress, -axial_strain / n, target, step)?
            }
            (None, _) => unreachable!("only the triaxial path is mixed-controlled"),
        };
        stress = update.stress;
        strain += strain_increment;
        plastic_strain += update.equivalent_plastic_strain_increment;
        path.push(point(
            model,
            step,
            strain,
            stress,
            plastic_strain,
            update.response,
        ));
    }
    Ok(path)
}

/// One drained triaxial increment: Δε_yy given, Δε_xx = Δε_zz = x with the mean lateral stress
/// of σ_{n+1} equal to `target`, by secant iteration started from the elastic x = −ν Δε_yy.
fn triaxial_step<M: Constitutive + ?Sized>(
    model: &M,
    stress: &Tensor3,
    axial_increment: Real,
    target: Real,
    step: usize,
) -> Result<(Tensor3, crate::constitutive::StressUpdate), ElementTestError> {
    const MAX_ITERATIONS: usize = 100;
    let elastic = model.elastic();
    // ∂σ_lateral/∂x for the elastic law when both lateral strains move together.
    let stiffness = 2.0 * (elastic.lame_lambda + elastic.shear_modulus);
    let scale = stress.norm() + elastic.p_wave_modulus() * axial_increment.abs();
    let tolerance = 1e-12 * scale.max(Real::MIN_POSITIVE);
    let zero = Tensor3::zeros();
    let evaluate = |x: Real| {
        let d = Tensor3::from_diagonal(&nalgebra::Vector3::new(x, axial_increment, x));
        let update = model.update(stress, &d, &zero);
        let residual = 0.5 * (update.stress[(0, 0)] + update.stress[(2, 2)]) - target;
        (d, update, residual)
    };
    let mut x_previous = -elastic.poisson_ratio * axial_increment;
    let (mut d, mut update, mut r_previous) = evaluate(x_previous);
    if r_previous.abs() <= tolerance {
        return Ok((d, update));
    }
    let mut x = x_previous - r_previous / stiffness;
    for _ in 0..MAX_ITERATIONS {
        let residual;
        (d, update, residual) = evaluate(x);
        if residual.abs() <= tolerance {
            return Ok((d, update));
        }
        let secant = (residual - r_previous) / (x - x_previous);
        let slope = if secant.is_finite() && secant.abs() > 1e-6 * stiffness {
            secant
        } else {
            stiffness
        };
        (x_previous, r_previous) = (x, residual);
        x -= residual / slope;
    }
    Err(ElementTestError::NotConverged {
        step,
        residual: r_previous.abs(),
        iterations: MAX_ITERATIONS,
    })
}

/// Writes a stress path as CSV with the header
/// `step,eps_xx,eps_yy,eps_zz,eps_xy,sigma_xx,sigma_yy,sigma_zz,sigma_xy,p,q,yield_function,plastic_strain,response`
/// (`yield_function` empty for a model without one; `response` is `elastic`, `cone` or
/// `apex`).
pub fn write_csv<W: Write>(path: &[PathPoint], mut out: W) -> io::Result<()> {
    writeln!(
        out,
        "step,eps_xx,eps_yy,eps_zz,eps_xy,sigma_xx,sigma_yy,sigma_zz,sigma_xy,p,q,\
         yield_function,plastic_strain,response"
    )?;
    for point in path {
        let (e, s) = (&point.strain, &point.stress);
        let f = point
            .yield_value
            .map(|f| format!("{f:e}"))
            .unwrap_or_default();
        let response = match point.response {
            Response::Elastic => "elastic",
            Response::Cone => "cone",
            Response::Apex => "apex",
        };
        writeln!(
            out,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{}",
            point.step,
            e[(0, 0)],
            e[(1, 1)],
            e[(2, 2)],
            e[(0, 1)],
            s[(0, 0)],
            s[(1, 1)],
            s[(2, 2)],
            s[(0, 1)],
            point.p,
            point.q,
            f,
            point.plastic_strain,
            response
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elastic::LinearElastic;
    use approx::assert_relative_eq;

    #[test]
    fn elastic_triaxial_path_has_slope_three_and_youngs_modulus() {
        let (e, nu, p0) = (10e6, 0.25, 50e3);
        let model = LinearElastic::new(e, nu).unwrap();
        let test = ElementTest {
            initial_stress: Tensor3::identity() * -p0,
            path: LoadingPath::TriaxialCompression { axial_strain: 1e-3 },
            steps: 10,
        };
        let path = run_element_test(&model, &test).unwrap();
        let last = path.last().unwrap();
        // Δσ_a = E ε_a, lateral stress unchanged, lateral strain ν ε_a.
        assert_relative_eq!(last.stress[(1, 1)], -p0 - e * 1e-3, max_relative = 1e-10);
        assert_relative_eq!(last.stress[(0, 0)], -p0, max_relative = 1e-10);
        assert_relative_eq!(last.strain[(0, 0)], nu * 1e-3, max_relative = 1e-10);
        assert_relative_eq!(last.q / (last.p - p0), 3.0, max_relative = 1e-10);
    }

    #[test]
    fn csv_has_a_header_and_one_row_per_point() {
        let model = LinearElastic::new(1e6, 0.3).unwrap();
        let test = ElementTest {
            initial_stress: Tensor3::zeros(),
            path: LoadingPath::Oedometer { axial_strain: 1e-3 },
            steps: 4,
        };
        let path = run_element_test(&model, &test).unwrap();
        let mut bytes = Vec::new();
        write_csv(&path, &mut bytes).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        let lines: Vec<_> = text.lines().collect();
        assert_eq!(lines.len(), 6);
        assert!(lines[0].starts_with("step,eps_xx"));
        assert_eq!(lines[0].split(',').count(), lines[5].split(',').count());
        assert!(lines[5].ends_with(",elastic"));
    }

    #[test]
    fn zero_steps_is_an_error() {
        let model = LinearElastic::new(1e6, 0.3).unwrap();
        let test = ElementTest {
            initial_stress: Tensor3::zeros(),
            path: LoadingPath::Oedometer { axial_strain: 1e-3 },
            steps: 0,
        };
        assert_eq!(
            run_element_test(&model, &test),
            Err(ElementTestError::NoSteps)
        );
    }
}
