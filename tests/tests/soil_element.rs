//! Element tests of the soil constitutive core (`geosph-soil`), without SPH.
//!
//! One material point is driven along oedometric, simple-shear, triaxial and rigid-rotation
//! paths through the same `Constitutive::update` the SPH solver calls, and the stress path is
//! checked against closed forms:
//! - Hooke's law in plane strain (oedometer: σ_h/σ_v = ν/(1 − ν), σ_v = E(1 − ν)/((1 + ν)(1 − 2ν)) ε);
//! - the Drucker–Prager cone matched to Mohr–Coulomb in plane strain (Bui et al. 2008, Int. J.
//!   Numer. Anal. Meth. Geomech. 32:1537): α_φ = tan φ/√(9 + 12 tan²φ), k_c = 3c/√(9 + 12 tan²φ),
//!   failure in simple shear at √J₂ = k_c − α_φ I₁, in drained triaxial compression at
//!   q = √3 k_c + 3√3 α_φ p;
//! - associated/dilatant flow under constrained simple shear: dτ/dγ = 9KGα_φα_ψ/(G + 9Kα_φα_ψ);
//! - the Jaumann rate: a rigid rotation rotates σ (σ(t) = R σ₀ Rᵀ);
//! - the apex: with c = 0 no tension is carried (σ → 0).
//!
//! Both return algorithms (Bui 2008 tangent + tension cracking + stress scaling, and the
//! closest-point return) are run on every plastic path.

use approx::assert_relative_eq;
use geosph_core::{Real, Tensor3};
use geosph_soil::kinematics::rotation_about_z;
use geosph_soil::{
    Constitutive, DruckerPragerBui2008, ElementTest, LinearElastic, LoadingPath, PathPoint,
    Response, ReturnAlgorithm, SoilMaterial, run_element_test,
};

const E: Real = 20e6;
const NU: Real = 0.3;
const P0: Real = 100e3;
const ALGORITHMS: [ReturnAlgorithm; 2] =
    [ReturnAlgorithm::Bui2008, ReturnAlgorithm::ConsistentReturn];

fn soil(
    friction_deg: Real,
    cohesion: Real,
    dilatancy_deg: Real,
    algorithm: ReturnAlgorithm,
) -> DruckerPragerBui2008 {
    let material = SoilMaterial::new(E, NU, friction_deg, cohesion, dilatancy_deg).unwrap();
    DruckerPragerBui2008::new(material, algorithm).unwrap()
}

fn isotropic(p: Real) -> Tensor3 {
    Tensor3::identity() * -p
}

fn scientific(values: &[Real]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.3e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn max_yield_value(path: &[PathPoint]) -> Real {
    path.iter()
        .map(|point| point.yield_value.unwrap())
        .fold(Real::NEG_INFINITY, Real::max)
}

#[test]
fn plane_strain_match_constants() {
    let at = |phi: Real| soil(phi, 1.0, 0.0, ReturnAlgorithm::Bui2008);
    assert_relative_eq!(at(30.0).constants().alpha_phi, 0.16013, epsilon = 1e-5);
    assert_relative_eq!(at(30.0).constants().k_c, 0.83205, epsilon = 1e-5);
    assert_relative_eq!(at(19.8).constants().alpha_phi, 0.11081, epsilon = 1e-5);
}

#[test]
fn oedometer_follows_hookes_law_in_plane_strain() {
    let strain = 1e-3;
    let test = ElementTest {
        initial_stress: Tensor3::zeros(),
        path: LoadingPath::Oedometer {
            axial_strain: strain,
        },
        steps: 20,
    };
    let elastic = LinearElastic::new(E, NU).unwrap();
    // A Drucker–Prager soil with a large cohesion stays elastic on this path.
    let strong = ALGORITHMS.map(|algorithm| soil(30.0, 1e9, 0.0, algorithm));
    let models: [&dyn Constitutive; 3] = [&elastic, &strong[0], &strong[1]];
    let vertical = -E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU)) * strain;
    for model in models {
        let path = run_element_test(model, &test).unwrap();
        let last = path.last().unwrap();
        assert_relative_eq!(last.stress[(1, 1)], vertical, max_relative = 1e-12);
        let k0 = last.stress[(0, 0)] / last.stress[(1, 1)];
        assert_relative_eq!(k0, NU / (1.0 - NU), max_relative = 1e-12);
        assert_relative_eq!(
            last.stress[(2, 2)],
            last.stress[(0, 0)],
            max_relative = 1e-12
        );
        assert!(path.iter().all(|point| point.response == Response::Elastic));
    }
}

#[test]
fn simple_shear_yields_at_the_drucker_prager_strength_and_flows() {
    let (cohesion, gamma) = (5e3, 0.02);
    for algorithm in ALGORITHMS {
        let model = soil(30.0, cohesion, 0.0, algorithm);
        let dp = *model.constants();
        let g = model.elastic().shear_modulus;
        // √J₂ = |τ| and I₁ = −3p₀ (no volume change in simple shear): τ_y = k_c + 3α_φ p₀.
        let tau_yield = dp.k_c + 3.0 * dp.alpha_phi * P0;
        let test = ElementTest {
            initial_stress: isotropic(P0),
            path: LoadingPath::SimpleShear {
                shear_strain: gamma,
                spin: false,
            },
            steps: 400,
        };
        let path = run_element_test(&model, &test).unwrap();
        for point in &path {
            let gamma_i = 2.0 * point.strain[(0, 1)];
            let expected = (g * gamma_i).min(tau_yield);
            assert_relative_eq!(point.stress[(0, 1)], expected, max_relative = 1e-10);
            assert_relative_eq!(point.p, P0, max_relative = 1e-12);
        }
        let f_max = max_yield_value(&path);
        assert!(
            f_max <= 1e-9 * tau_yield,
            "{algorithm:?}: f_max = {f_max:e}"
        );
        let last = path.last().unwrap();
        // Δεᵖ is pure shear: ε̄ᵖ = γᵖ/√3 with γᵖ = γ − τ_y/G.
        let plastic = (gamma - tau_yield / g) / 3.0_f64.sqrt();
        assert_relative_eq!(last.plastic_strain, plastic, max_relative = 1e-9);
        eprintln!(
            "simple shear {algorithm:?}: τ_y = {tau_yield:.3} Pa, final τ = {:.3} Pa, \
             max f = {f_max:.2e} Pa, ε̄ᵖ = {:.6e} (closed form {plastic:.6e})",
            last.stress[(0, 1)],
            last.plastic_strain
        );
    }
}

#[test]
fn simple_shear_with_jaumann_spin_never_exceeds_the_yield_surface() {
    for algorithm in ALGORITHMS {
        let model = soil(30.0, 5e3, 0.0, algorithm);
        let tau_yield = model.constants().k_c + 3.0 * model.constants().alpha_phi * P0;
        let test = ElementTest {
            initial_stress: isotropic(P0),
            path: LoadingPath::SimpleShear {
                shear_strain: 0.5,
                spin: true,
            },
            steps: 2000,
        };
        let path = run_element_test(&model, &test).unwrap();
        let f_max = max_yield_value(&path);
        assert!(
            f_max <= 1e-9 * tau_yield,
            "{algorithm:?}: f_max = {f_max:e}"
        );
        // The spin rotates the stress: normal stresses differ once τ ≠ 0.
        let last = path.last().unwrap();
        assert!((last.stress[(0, 0)] - last.stress[(1, 1)]).abs() > 1.0);
        eprintln!(
            "simple shear with spin {algorithm:?}: max f = {f_max:.2e} Pa, final (p, q) = ({:.1}, {:.1}) Pa",
            last.p, last.q
        );
    }
}

#[test]
fn dilatant_simple_shear_hardens_at_the_closed_form_rate() {
    // Constrained simple shear with ψ > 0: plastic dilation is cancelled by elastic
    // compression, so p rises and τ with it. On the cone with s pure shear:
    // Δλ = G Δγ/(G + 9Kα_φα_ψ), Δp = 3Kα_ψ Δλ, Δτ = 3α_φ Δp.
    for dilatancy in [10.0, 30.0] {
        for algorithm in ALGORITHMS {
            let model = soil(30.0, 5e3, dilatancy, algorithm);
            let dp = *model.constants();
            let (k, g) = (model.elastic().bulk_modulus, model.elastic().shear_modulus);
            let test = ElementTest {
                initial_stress: isotropic(P0),
                path: LoadingPath::SimpleShear {
                    shear_strain: 0.02,
                    spin: false,
                },
                steps: 400,
            };
            let path = run_element_test(&model, &test).unwrap();
            let tau_yield = dp.k_c + 3.0 * dp.alpha_phi * P0;
            let gamma_yield = tau_yield / g;
            let rate = g / (g + 9.0 * k * dp.alpha_phi * dp.alpha_psi);
            let last = path.last().unwrap();
            let gamma_plastic = 2.0 * last.strain[(0, 1)] - gamma_yield;
            let p_expected = P0 + 3.0 * k * dp.alpha_psi * rate * gamma_plastic;
            let tau_expected = dp.k_c + 3.0 * dp.alpha_phi * p_expected;
            // The closest-point return is exact for any step on this path. Bui's step that
            // crosses the surface scales the deviator at constant I₁, so the dilation of the
            // overshoot (at most one increment Δγ) is lost: |Δp| ≤ 3Kα_ψ G/(G + 9Kα_φα_ψ) Δγ.
            let tolerance = match algorithm {
                ReturnAlgorithm::ConsistentReturn => 1e-9 * p_expected,
                ReturnAlgorithm::Bui2008 => 3.0 * k * dp.alpha_psi * rate * 0.02 / 400.0,
            };
            assert_relative_eq!(last.p, p_expected, epsilon = tolerance);
            // On the surface throughout, so τ follows p.
            assert_relative_eq!(
                last.stress[(0, 1)],
                dp.k_c + 3.0 * dp.alpha_phi * last.p,
                max_relative = 1e-10
            );
            assert!(max_yield_value(&path) <= 1e-9 * tau_expected);
            eprintln!(
                "dilatant simple shear ψ = {dilatancy}° {algorithm:?}: p = {:.2} Pa \
                 (closed form {p_expected:.2}, bound {tolerance:.2e}), τ = {:.2} Pa \
                 (closed form {tau_expected:.2})",
                last.p,
                last.stress[(0, 1)]
            );
        }
    }
}

#[test]
fn triaxial_compression_fails_at_the_plane_strain_matched_ratio() {
    for cohesion in [0.0, 5e3] {
        for algorithm in ALGORITHMS {
            let model = soil(30.0, cohesion, 0.0, algorithm);
            let dp = *model.constants();
            let test = ElementTest {
                initial_stress: isotropic(P0),
                path: LoadingPath::TriaxialCompression { axial_strain: 0.02 },
                steps: 200,
            };
            let path = run_element_test(&model, &test).unwrap();
            // Drained path dq/dp = 3 from (p₀, 0) meets q = √3 k_c + 3√3 α_φ p at
            // q_f = (√3 k_c + 3√3 α_φ p₀)/(1 − √3 α_φ), p_f = p₀ + q_f/3.
            let sqrt3 = 3.0_f64.sqrt();
            let q_f =
                (sqrt3 * dp.k_c + 3.0 * sqrt3 * dp.alpha_phi * P0) / (1.0 - sqrt3 * dp.alpha_phi);
            let p_f = P0 + q_f / 3.0;
            let last = path.last().unwrap();
            assert_eq!(last.response, Response::Cone);
            assert_relative_eq!(last.q, q_f, max_relative = 1e-9);
            assert_relative_eq!(last.p, p_f, max_relative = 1e-9);
            assert_relative_eq!(last.stress[(0, 0)], -P0, max_relative = 1e-10);
            for point in &path {
                assert_relative_eq!(point.q, 3.0 * (point.p - P0), epsilon = 1e-6 * P0);
            }
            if cohesion == 0.0 {
                assert_relative_eq!(
                    last.q / last.p,
                    3.0 * sqrt3 * dp.alpha_phi,
                    max_relative = 1e-9
                );
                assert_relative_eq!(last.q / last.p, 0.83205, epsilon = 1e-5);
            }
            assert!(max_yield_value(&path) <= 1e-9 * q_f);
            eprintln!(
                "triaxial c = {cohesion} {algorithm:?}: q_f = {:.2} Pa (closed form {q_f:.2}), \
                 p_f = {:.2} Pa, q/p = {:.5}, ε̄ᵖ = {:.4e}",
                last.q,
                last.p,
                last.q / last.p,
                last.plastic_strain
            );
        }
    }
}

/// A path with rotating principal axes and volumetric change (plane strain), from p₀.
fn rotating_path(steps: usize) -> ElementTest {
    ElementTest {
        initial_stress: isotropic(P0),
        path: LoadingPath::VelocityGradient {
            velocity_gradient: Tensor3::new(0.004, 0.02, 0.0, -0.005, -0.01, 0.0, 0.0, 0.0, 0.0),
            duration: 1.0,
        },
        steps,
    }
}

#[test]
fn return_algorithms_agree_on_radial_returns_and_converge_together_otherwise() {
    // ψ = 0 simple shear: every return is radial at constant I₁, where the stress scaling of
    // Bui (2008) is the closest-point return: the paths agree to round-off (1e-12 of p₀).
    let shear = ElementTest {
        initial_stress: isotropic(P0),
        path: LoadingPath::SimpleShear {
            shear_strain: 0.02,
            spin: false,
        },
        steps: 400,
    };
    let [bui, consistent] =
        ALGORITHMS.map(|a| run_element_test(&soil(30.0, 5e3, 0.0, a), &shear).unwrap());
    for (a, b) in bui.iter().zip(&consistent) {
        assert_relative_eq!(a.stress, b.stress, epsilon = 1e-12 * P0);
    }

    // A non-radial path with spin (rotating principal axes, volume change): from a point on
    // the cone Bui's tangent step + scaling and the closest-point return differ by O(Δε²) per
    // step, so the paths differ by O(Δε) — halving the step halves the difference.
    for dilatancy in [0.0, 10.0] {
        let (mut differences, mut bounds) = (Vec::new(), Vec::new());
        for steps in [100, 200, 400, 800, 1600] {
            let [a, b] = ALGORITHMS.map(|algorithm| {
                let model = soil(30.0, 5e3, dilatancy, algorithm);
                *run_element_test(&model, &rotating_path(steps))
                    .unwrap()
                    .last()
                    .unwrap()
            });
            assert_eq!(a.response, Response::Cone);
            differences.push((a.stress - b.stress).norm() / a.stress.norm());
            // The paths part by at most what one step can change: the elastic trial increment
            // C : Δε = 2G Δe + K tr(Δε) 1 of a step, relative to the stress reached.
            let elastic = SoilMaterial::new(E, NU, 30.0, 5e3, dilatancy)
                .unwrap()
                .elastic();
            let LoadingPath::VelocityGradient {
                velocity_gradient,
                duration,
            } = rotating_path(steps).path
            else {
                unreachable!()
            };
            let strain = (velocity_gradient + velocity_gradient.transpose()) * (0.5 * duration);
            let increment = strain / steps as Real;
            let volumetric = increment.trace();
            let deviatoric = increment - Tensor3::identity() * (volumetric / 3.0);
            let trial = deviatoric * (2.0 * elastic.shear_modulus)
                + Tensor3::identity() * (elastic.bulk_modulus * volumetric);
            bounds.push(trial.norm() / a.stress.norm());
        }
        eprintln!(
            "rotating path ψ = {dilatancy}°, relative difference Bui2008 vs consistent, N = 100..1600: {}",
            scientific(&differences)
        );
        if dilatancy == 0.0 {
            for pair in differences.windows(2) {
                let ratio = pair[0] / pair[1];
                assert!(
                    (1.8..2.2).contains(&ratio),
                    "ratio {ratio}: {}",
                    scientific(&differences)
                );
            }
        }
        // With ψ > 0 the step that first crosses the cone dominates: Bui's scaling drops the
        // dilation of the overshoot, a fraction of one increment that depends on where yield
        // falls in the step, so the difference is not monotone in N; for any ψ it stays below
        // one step's elastic increment.
        for ((difference, bound), steps) in differences
            .iter()
            .zip(&bounds)
            .zip([100, 200, 400, 800, 1600])
        {
            assert!(
                difference <= bound,
                "N = {steps}: {difference:e} above one step's increment {bound:e}"
            );
        }
    }
}

#[test]
fn tension_without_cohesion_ends_at_zero_stress() {
    // Plane-strain isotropic extension from p₀: elastic unloading to the apex, then no tension.
    let extension = ElementTest {
        initial_stress: isotropic(P0),
        path: LoadingPath::VelocityGradient {
            velocity_gradient: Tensor3::from_diagonal(&nalgebra::Vector3::new(0.01, 0.01, 0.0)),
            duration: 1.0,
        },
        steps: 100,
    };
    for algorithm in ALGORITHMS {
        let path = run_element_test(&soil(30.0, 0.0, 0.0, algorithm), &extension).unwrap();
        let last = path.last().unwrap();
        assert_eq!(last.response, Response::Apex);
        assert!(
            last.stress.norm() <= 1e-9 * P0,
            "{algorithm:?}: {}",
            last.stress
        );
        assert!(path.iter().all(|point| point.stress.trace() <= 1e-9 * P0));

        let cohesive = soil(30.0, 5e3, 0.0, algorithm);
        let apex = cohesive.constants().k_c / (3.0 * cohesive.constants().alpha_phi);
        let last = *run_element_test(&cohesive, &extension)
            .unwrap()
            .last()
            .unwrap();
        assert_eq!(last.response, Response::Apex);
        assert_relative_eq!(last.stress, Tensor3::identity() * apex, epsilon = 1e-9 * P0);
    }
}

#[test]
fn rigid_rotation_rotates_the_stress_with_first_order_error() {
    // v = Ω e_z × x: L = [[0, −Ω], [Ω, 0]], ε̇ = 0; after a quarter turn σ = R σ₀ Rᵀ.
    let omega = 1.0;
    let quarter = std::f64::consts::FRAC_PI_2 / omega;
    let sigma0 = Tensor3::new(-150e3, 30e3, 0.0, 30e3, -60e3, 0.0, 0.0, 0.0, -90e3);
    let r = rotation_about_z(omega * quarter);
    let exact = r * sigma0 * r.transpose();
    // Forward Euler on the Jaumann term maps z = (σ_xx − σ_yy)/2 + i σ_xy to (1 + 2iΔθ) z per
    // step (Δθ = ΩΔt) and leaves I₁ and σ_zz unchanged; the exact map is e^{2iΔθ}. The error
    // after N steps is √2 |(1 + 2iΔθ)^N − e^{iπ}| |z₀| / ‖σ₀‖ = O(1/N) (amplitude growth
    // (1 + 4Δθ²)^{N/2}), and J₂ grows by |z₀|² ((1 + 4Δθ²)^N − 1).
    let z0 = ((sigma0[(0, 0)] - sigma0[(1, 1)]) / 2.0).hypot(sigma0[(0, 1)]);
    let j2 = |s: &Tensor3| geosph_soil::invariants::second_deviatoric_invariant(s);
    let model = LinearElastic::new(E, NU).unwrap();
    let mut errors = Vec::new();
    for steps in [50, 100, 200, 400] {
        let test = ElementTest {
            initial_stress: sigma0,
            path: LoadingPath::VelocityGradient {
                velocity_gradient: Tensor3::new(0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0),
                duration: quarter,
            },
            steps,
        };
        let last = run_element_test(&model, &test).unwrap().pop().unwrap();
        let n = steps as Real;
        let dtheta = omega * quarter / n;
        let (modulus, phase) = (
            (1.0 + 4.0 * dtheta * dtheta).powf(n / 2.0),
            n * (2.0 * dtheta).atan(),
        );
        let discrete =
            2.0_f64.sqrt() * z0 * (modulus * phase.cos() + 1.0).hypot(modulus * phase.sin())
                / sigma0.norm();
        let error = (last.stress - exact).norm() / sigma0.norm();
        assert_relative_eq!(error, discrete, max_relative = 1e-8);
        assert!(error <= 2.5 / n, "N = {steps}: error {error}");
        let j2_growth = z0 * z0 * ((1.0 + 4.0 * dtheta * dtheta).powf(n) - 1.0);
        assert_relative_eq!(
            j2(&last.stress) - j2(&sigma0),
            j2_growth,
            max_relative = 1e-8
        );
        assert_relative_eq!(last.stress.trace(), sigma0.trace(), max_relative = 1e-13);
        assert_eq!(last.stress[(2, 2)], sigma0[(2, 2)]);
        assert_eq!(last.strain, Tensor3::zeros());
        errors.push((error, (j2(&last.stress) - j2(&sigma0)) / j2(&sigma0)));
    }
    let (error, drift): (Vec<Real>, Vec<Real>) = errors.iter().copied().unzip();
    eprintln!(
        "rigid rotation, forward Euler, N = 50..400: error {}, relative J₂ drift {}",
        scientific(&error),
        scientific(&drift)
    );
    for pair in error.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!((1.8..2.2).contains(&ratio), "ratio {ratio}");
    }

    // The same rate integrated with Heun's method (as an SPH integrator of dσ/dt would) is
    // second order: the error falls by 4 per halving.
    let spin = Tensor3::new(0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0);
    let zero = Tensor3::zeros();
    let heun = |steps: usize| {
        let dt = quarter / steps as Real;
        let mut s = sigma0;
        for _ in 0..steps {
            let k1 = model.stress_rate(&s, &zero, &spin);
            let k2 = model.stress_rate(&(s + k1 * dt), &zero, &spin);
            s += (k1 + k2) * (0.5 * dt);
        }
        (s - exact).norm() / sigma0.norm()
    };
    let (e1, e2) = (heun(100), heun(200));
    eprintln!("rigid rotation, Heun: N = 100 → {e1:.3e}, N = 200 → {e2:.3e}");
    assert!((3.6..4.4).contains(&(e1 / e2)), "ratio {}", e1 / e2);
}
