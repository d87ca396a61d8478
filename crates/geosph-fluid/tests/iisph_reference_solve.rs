//! IISPH's converged pressure against a direct solve of the same linear system.
//!
//! One step of a disordered water block at rest in a tank: the relaxed Jacobi iteration of
//! IISPH (Ihmsen et al. 2014), run to convergence, must give the pressures that an LU
//! factorisation with partial pivoting (nalgebra's; the active set has about a hundred
//! unknowns) gives for the pressure system
//!
//! Δt² Σ_j m_j (a^p_i − a^p_j)·∇_i W_ij + Δt² Σ_b m_b a^p_i·∇_i W_ib = ρ₀ − ρ*_i
//!
//! on the particles where the iteration's pressure is positive (p = 0 elsewhere), and the
//! particles it left at p = 0 must not be compressed: the clamp p ≥ 0 makes the solve a
//! complementarity problem, whose solution is the linear solve on its active set.
//!
//! The matrix is assembled column by column from the solver's own operators (the pressure
//! acceleration of a unit pressure at one particle, then the density change it causes), so the
//! test checks the iteration, not the discretisation. A second test checks IISPH's BiCGSTAB
//! solve against the converged Jacobi on the same step.

use geosph_boundary::{Slip, generate};
use geosph_core::{Domain, Particles, Real, Vector};
use geosph_fluid::incompressible::{
    Bicgstab, Iisph, Incompressible, PressureIteration, PressureMethod, PressureSolveSettings,
    PressureSystem, Scratch, WallPressure,
};
use geosph_kernels::{Kernel, WendlandC2};
use geosph_sph::ViscousTerm;
use nalgebra::{DMatrix, DVector};

type System = PressureSystem<2, WendlandC2<2>>;

const RHO0: Real = 1000.0;

/// A 12 × 10 block (dx = 0.02 m) in a tank 0.24 m wide, every particle moved by up to
/// ±0.1 dx in each direction by a fixed pseudo-random sequence.
fn disordered_block(dx: Real) -> (Vec<Vector<2>>, Vector<2>) {
    let tank = Vector::<2>::new(0.24, 0.4);
    let mut positions = generate::fill_box(&Vector::zeros(), &Vector::<2>::new(0.24, 0.2), dx);
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut uniform = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as Real / (1u64 << 53) as Real - 0.5
    };
    for x in &mut positions {
        *x += Vector::<2>::new(uniform(), uniform()) * (0.2 * dx);
    }
    (positions, tank)
}

/// The density change Δt² (Σ_j m_j (a^p_i − a^p_j)·∇_i W_ij + Σ_b m_b a^p_i·∇_i W_ib) of
/// every particle caused by the pressure field `pressure`.
fn density_change(
    system: &System,
    fluid: &Particles<2>,
    dt: Real,
    pressure: &[Real],
    scratch: &mut Scratch<2>,
) -> Vec<Real> {
    for ((term, p), rho) in scratch
        .pressure_term
        .iter_mut()
        .zip(pressure)
        .zip(&fluid.density)
    {
        *term = p / (rho * rho);
    }
    system.pressure_acceleration(
        &fluid.mass,
        &scratch.pressure_term,
        &mut scratch.acceleration,
    );
    system.divergence(
        &fluid.mass,
        &scratch.acceleration,
        &system.walls.acceleration,
        &mut scratch.divergence,
    );
    scratch.divergence.iter().map(|d| dt * dt * d).collect()
}

/// The disordered block's solver, its fluid with v* = v + Δt a* (gravity and the wall head)
/// and p = 0, the step Δt, and the source ρ*_i − ρ₀ of each particle.
fn loaded_step() -> (
    Incompressible<2, WendlandC2<2>, Iisph>,
    Particles<2>,
    Real,
    Vec<Real>,
) {
    let dx = 0.02;
    let (positions, tank) = disordered_block(dx);
    let mut fluid = Particles::at_rest(positions, RHO0 * dx * dx, RHO0);
    let system = PressureSystem::new(
        WendlandC2::<2>::new(1.3 * dx),
        Domain::new(Vector::<2>::repeat(-0.2), Vector::<2>::repeat(0.6)).unwrap(),
        RHO0,
        ViscousTerm::Inviscid,
        Vector::<2>::new(0.0, -9.81),
        generate::tank(&Vector::zeros(), &tank, dx, 3, true, RHO0),
        WallPressure::Hydrostatic,
        Slip::NoSlip,
    )
    .unwrap();
    let solver = Incompressible::new(
        system,
        Iisph::default(),
        PressureSolveSettings::default(),
        dx,
        &mut fluid,
    )
    .unwrap();
    let system = &solver.system;
    let n = fluid.len();
    let dt = 0.004;
    let mut acceleration = vec![Vector::zeros(); n];
    system.non_pressure_acceleration(&fluid, &mut acceleration);
    for (v, a) in fluid.velocity.iter_mut().zip(&acceleration) {
        *v += a * dt;
    }
    let mut divergence = vec![0.0; n];
    system.divergence(
        &fluid.mass,
        &fluid.velocity,
        &system.walls.velocity,
        &mut divergence,
    );
    let source: Vec<Real> = (0..n)
        .map(|i| fluid.density[i] + dt * divergence[i] - RHO0)
        .collect();
    fluid.pressure.as_mut().unwrap().fill(0.0);
    (solver, fluid, dt, source)
}

/// Scratch arrays for `n` particles.
fn scratch(n: usize) -> Scratch<2> {
    Scratch {
        acceleration: vec![Vector::zeros(); n],
        pressure_term: vec![0.0; n],
        divergence: vec![0.0; n],
        residual: vec![0.0; n],
        ..Scratch::default()
    }
}

/// IISPH's relaxed Jacobi from p = 0, a fixed 20 000 iterations (target 0: never stops
/// early): the converged pressure.
fn converged_jacobi(
    system: &System,
    fluid: &Particles<2>,
    dt: Real,
    scratch: &mut Scratch<2>,
) -> Vec<Real> {
    let settings = PressureSolveSettings {
        target_density_error: 0.0,
        min_iterations: 20_000,
        max_iterations: 20_000,
        ..Default::default()
    };
    let mut iterated = fluid.clone();
    Iisph::default().correct_density(system, &mut iterated, dt, &settings, scratch);
    iterated.pressure.unwrap()
}

#[test]
fn converged_iisph_pressure_equals_a_direct_solve() {
    let (solver, fluid, dt, source) = loaded_step();
    let system = &solver.system;
    let n = fluid.len();
    let mut scratch = scratch(n);
    let pressure = converged_jacobi(system, &fluid, dt, &mut scratch);
    let p_max = pressure.iter().copied().fold(0.0, Real::max);
    let active: Vec<usize> = (0..n).filter(|&i| pressure[i] > 0.0).collect();
    println!(
        "{n} particles, {} with p > 0, p_max = {p_max:.1} Pa",
        active.len()
    );
    assert!(
        active.len() > n / 2 && p_max > 0.5 * RHO0 * 9.81 * 0.2,
        "the step must load the block"
    );

    // The system restricted to the active set, column k = density change of a unit p_k.
    let mut index_of = vec![usize::MAX; n];
    for (row, &i) in active.iter().enumerate() {
        index_of[i] = row;
    }
    let m = active.len();
    let mut matrix = DMatrix::<Real>::zeros(m, m);
    let mut non_zeros = 0;
    let mut unit = vec![0.0; n];
    let mut full_columns = Vec::new();
    for (column, &k) in active.iter().enumerate() {
        unit[k] = 1.0;
        let change = density_change(system, &fluid, dt, &unit, &mut scratch);
        unit[k] = 0.0;
        for (i, &value) in change.iter().enumerate() {
            if value != 0.0 && index_of[i] != usize::MAX {
                matrix[(index_of[i], column)] = value;
                non_zeros += 1;
            }
        }
        full_columns.push(change);
    }
    let rhs = DVector::<Real>::from_fn(m, |row, _| -source[active[row]]);
    let direct = matrix
        .lu()
        .solve(&rhs)
        .expect("the active-set system is regular");

    let mut largest = 0.0;
    for (row, &i) in active.iter().enumerate() {
        largest = Real::max(largest, (direct[row] - pressure[i]).abs());
    }
    println!(
        "{m} unknowns, {non_zeros} non-zeros; largest |p_Jacobi − p_LU| = {largest:.3e} Pa \
         ({:.1e} of p_max)",
        largest / p_max
    );
    assert!(
        largest < 1e-6 * p_max,
        "Jacobi and LU differ by {largest} Pa"
    );

    // Complementarity: with the direct pressures, no particle left at p = 0 is compressed.
    let mut worst: Real = 0.0;
    for i in (0..n).filter(|&i| pressure[i] == 0.0) {
        let predicted = source[i]
            + (0..m)
                .map(|row| full_columns[row][i] * direct[row])
                .sum::<Real>();
        worst = worst.max(predicted / RHO0);
    }
    println!("largest compression at p = 0: {worst:.2e}");
    assert!(worst < 1e-9, "a particle at p = 0 is compressed by {worst}");
}

/// With β = 1 the BiCGSTAB solve's source, the velocity divergence plus β (ρ − ρ₀), is the
/// density-invariance source, so converged it must give the relaxed Jacobi's converged
/// pressures (the direct solve's, above), active set included.
#[test]
fn bicgstab_with_the_whole_density_error_equals_the_converged_jacobi() {
    let (solver, fluid, dt, _) = loaded_step();
    let system = &solver.system;
    let mut scratch = scratch(fluid.len());
    let reference = converged_jacobi(system, &fluid, dt, &mut scratch);
    let mut bicgstab = Iisph {
        iteration: PressureIteration::Bicgstab(Bicgstab {
            tolerance: 1e-12,
            density_relaxation: 1.0,
            active_set_passes: 30,
        }),
        ..Iisph::default()
    };
    let mut solved = fluid.clone();
    let settings = PressureSolveSettings {
        max_iterations: 1000,
        ..Default::default()
    };
    let report = bicgstab.correct_density(system, &mut solved, dt, &settings, &mut scratch);
    let pressure = solved.pressure.unwrap();
    let p_max = reference.iter().copied().fold(0.0, Real::max);
    let largest = pressure
        .iter()
        .zip(&reference)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, Real::max);
    println!(
        "{} BiCGSTAB iterations; largest |p_BiCGSTAB − p_Jacobi| = {largest:.3e} Pa ({:.1e} of p_max)",
        report.iterations,
        largest / p_max
    );
    assert!(
        largest < 1e-6 * p_max,
        "BiCGSTAB and Jacobi differ by {largest} Pa"
    );
}
