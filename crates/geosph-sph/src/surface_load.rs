//! The force and moment of the fluid's pressure, or of the soil's stress, on a surface: the
//! load gauges on fixed walls and the fluid force on rigid bodies.

use geosph_core::{Real, Tensor3, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::CellGrid;

/// One quadrature point of a loaded surface: position, unit normal into the flow, area (in 2D
/// a length, per unit thickness).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadPoint<const D: usize> {
    /// Position x_q.
    pub position: Vector<D>,
    /// Unit normal n_q, pointing into the flow.
    pub normal: Vector<D>,
    /// Area A_q.
    pub area: Real,
}

/// The fluid around a surface: particles with their pressure, binned in a grid of cells at
/// least one kernel support wide (built by the caller at the particles' current positions).
#[derive(Clone, Copy)]
pub struct FluidField<'a, const D: usize> {
    /// The fluid particles' positions x_j.
    pub position: &'a [Vector<D>],
    /// Their masses m_j.
    pub mass: &'a [Real],
    /// Their densities ρ_j.
    pub density: &'a [Real],
    /// Their pressure p_j.
    pub pressure: &'a [Real],
    /// `position` binned.
    pub grid: &'a CellGrid<D>,
    /// Gravity g, for the hydrostatic part of the extrapolation.
    pub gravity: Vector<D>,
    /// The equation of state's background pressure p_b, which acts on every side of a
    /// surface alike and is taken off.
    pub background_pressure: Real,
}

/// F = −Σ_q p(x_q) n_q A_q and M = Σ_q (x_q − x_c) × (−p(x_q) n_q A_q) about `about` = x_c,
/// over the quadrature `points`, with the pressure at the surface extrapolated from the fluid
/// as Adami, Hu & Adams (2012, eq. 27) extrapolate it to their wall particles,
/// hydrostatically:
///
/// p(x_q) = Σ_j V_j W_qj (p_j + ρ_j g·(x_q − x_j)) / Σ_j V_j W_qj − p_b,  V_j = m_j/ρ_j,
///
/// (p_b the background pressure, which a partly wetted surface would otherwise feel on its wet
/// side only) clamped at p ≥ 0 as the walls' pressure is (above a free surface it would read a tension),
/// 0 where no fluid is within the kernel's support (a dry surface). The extrapolation makes a
/// hydrostatic field exact on faces of any orientation: a plain Shepard average over the fluid
/// on one side of a face would read the pressure about a particle spacing into the fluid.
///
/// The moment is a 3-vector; in 2D only its z component is not zero.
pub fn pressure_load<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &FluidField<'_, D>,
    points: impl IntoIterator<Item = LoadPoint<D>>,
    about: &Vector<D>,
) -> (Vector<D>, Vector<3>) {
    integrate(points, about, |point| {
        let sums = pressure_point_sums(kernel, field, point);
        pressure_traction(point, sums, field.background_pressure)
    })
}

/// The sums of [`pressure_load`]'s extrapolation at each of `points`, appended to `sums`
/// ([`PRESSURE_SUMS`] per point): Σ_j V_j W_qj (p_j + ρ_j g·(x_q − x_j)) and Σ_j V_j W_qj over
/// the particles of `field.grid`. Sums over parts of the particles (one rank's each) add up
/// to the sums over all of them; [`pressure_load_from_sums`] then gives the load.
pub fn pressure_sums<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &FluidField<'_, D>,
    points: impl IntoIterator<Item = LoadPoint<D>>,
    sums: &mut Vec<Real>,
) {
    for point in points {
        sums.extend_from_slice(&pressure_point_sums(kernel, field, &point));
    }
}

/// Values per point of [`pressure_sums`].
pub const PRESSURE_SUMS: usize = 2;

/// [`pressure_load`] from the sums of [`pressure_sums`] over every particle, for the same
/// `points`, with the background pressure `background_pressure`.
pub fn pressure_load_from_sums<const D: usize>(
    points: impl IntoIterator<Item = LoadPoint<D>>,
    sums: &[Real],
    about: &Vector<D>,
    background_pressure: Real,
) -> (Vector<D>, Vector<3>) {
    let mut at = sums.chunks_exact(PRESSURE_SUMS);
    integrate(points, about, |point| {
        let sums = at.next().expect("sums for every point");
        pressure_traction(point, [sums[0], sums[1]], background_pressure)
    })
}

/// [`pressure_sums`] at one point.
fn pressure_point_sums<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &FluidField<'_, D>,
    point: &LoadPoint<D>,
) -> [Real; PRESSURE_SUMS] {
    let FluidField {
        position,
        mass,
        density,
        ..
    } = field;
    let (mut weighted, mut weights) = (0.0, 0.0);
    field
        .grid
        .for_each_neighbour(position, &point.position, |j, x_qj, r| {
            let j = j as usize;
            let w = mass[j] / density[j] * kernel.value(r);
            let hydrostatic = density[j] * field.gravity.dot(&x_qj);
            weighted += w * (field.pressure[j] + hydrostatic);
            weights += w;
        });
    [weighted, weights]
}

/// The traction at `point` from its [`pressure_sums`]; `None` where it is dry.
fn pressure_traction<const D: usize>(
    point: &LoadPoint<D>,
    [weighted, weights]: [Real; PRESSURE_SUMS],
    background_pressure: Real,
) -> Option<Vector<D>> {
    (weights > 0.0).then(|| {
        let pressure = weighted / weights - background_pressure;
        point.normal * -pressure.max(0.0)
    })
}

/// The soil around a surface: particles with their Cauchy stress, binned in a grid of cells
/// at least one kernel support wide (built by the caller at the particles' current positions).
#[derive(Clone, Copy)]
pub struct SoilField<'a, const D: usize> {
    /// The soil particles' positions x_j.
    pub position: &'a [Vector<D>],
    /// Their masses m_j.
    pub mass: &'a [Real],
    /// Their densities ρ_j.
    pub density: &'a [Real],
    /// Their Cauchy stress σ_j (tension positive; 3 × 3 also in 2D plane strain).
    pub stress: &'a [Tensor3],
    /// `position` binned.
    pub grid: &'a CellGrid<D>,
    /// Gravity g, for the weight of the soil between a particle and the surface.
    pub gravity: Vector<D>,
}

/// F = Σ_q σ(x_q) n_q A_q and M = Σ_q (x_q − x_c) × (σ(x_q) n_q A_q) about `about` = x_c: the
/// traction of the soil on the surface, with the soil's stress (tension positive; its D × D
/// block) extrapolated to the surface as the soil's walls extrapolate it to their dummy
/// particles (`docs/soil.md`, "Walls"), the weight of the soil between adding to the vertical
/// stress,
///
/// σ(x_q) = Σ_j V_j W_qj (σ_j + ρ_j (g·(x_j − x_q)) ĝĝᵀ) / Σ_j V_j W_qj,  V_j = m_j/ρ_j,
///
/// and nothing where the normal traction n·σn would pull (soil does not stick to a wall) or no
/// soil is within the kernel's support. Only the vertical stress is extrapolated (the rest of
/// its gradient is not known from equilibrium alone), so for σ = −p I this is
/// [`pressure_load`] on faces normal to g only: on a vertical face the horizontal stress is the
/// plain Shepard average over the soil on one side (unbiased along a face over which it
/// varies with depth only, but near the soil's top, points up to 2h above it read the top
/// particles' stress), and on a tilted face the vertical part alone is corrected.
pub fn stress_load<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &SoilField<'_, D>,
    points: impl IntoIterator<Item = LoadPoint<D>>,
    about: &Vector<D>,
) -> (Vector<D>, Vector<3>) {
    let gravity = field.gravity;
    integrate(points, about, |point| {
        stress_traction(point, &stress_point_sums(kernel, field, point), &gravity)
    })
}

/// Values per point of [`stress_sums`].
pub const STRESS_SUMS: usize = 11;

/// The sums of [`stress_load`]'s extrapolation at each of `points`, appended to `sums`
/// ([`STRESS_SUMS`] per point): the nine components of Σ_j V_j W_qj σ_j, the head
/// −Σ_j V_j W_qj ρ_j g·(x_q − x_j) and Σ_j V_j W_qj, over the particles of `field.grid`. Sums
/// over parts of the particles add up to the sums over all of them;
/// [`stress_load_from_sums`] then gives the load.
pub fn stress_sums<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &SoilField<'_, D>,
    points: impl IntoIterator<Item = LoadPoint<D>>,
    sums: &mut Vec<Real>,
) {
    for point in points {
        sums.extend_from_slice(&stress_point_sums(kernel, field, &point));
    }
}

/// [`stress_load`] from the sums of [`stress_sums`] over every particle, for the same
/// `points`, with gravity `gravity`.
pub fn stress_load_from_sums<const D: usize>(
    points: impl IntoIterator<Item = LoadPoint<D>>,
    sums: &[Real],
    about: &Vector<D>,
    gravity: &Vector<D>,
) -> (Vector<D>, Vector<3>) {
    let mut at = sums.chunks_exact(STRESS_SUMS);
    integrate(points, about, |point| {
        let point_sums: &[Real; STRESS_SUMS] = at
            .next()
            .and_then(|chunk| chunk.try_into().ok())
            .expect("sums for every point");
        stress_traction(point, point_sums, gravity)
    })
}

/// [`stress_sums`] at one point.
fn stress_point_sums<const D: usize, K: Kernel<D>>(
    kernel: &K,
    field: &SoilField<'_, D>,
    point: &LoadPoint<D>,
) -> [Real; STRESS_SUMS] {
    let SoilField {
        position,
        mass,
        density,
        ..
    } = field;
    let (mut weighted, mut weights) = (Tensor3::zeros(), 0.0);
    let mut head = 0.0;
    field
        .grid
        .for_each_neighbour(position, &point.position, |j, x_qj, r| {
            let j = j as usize;
            let w = mass[j] / density[j] * kernel.value(r);
            weighted += field.stress[j] * w;
            head -= w * density[j] * field.gravity.dot(&x_qj);
            weights += w;
        });
    let mut sums = [0.0; STRESS_SUMS];
    sums[..9].copy_from_slice(weighted.as_slice());
    sums[9] = head;
    sums[10] = weights;
    sums
}

/// The traction at `point` from its [`stress_sums`]; `None` where no soil is near or the
/// normal traction would pull.
fn stress_traction<const D: usize>(
    point: &LoadPoint<D>,
    sums: &[Real; STRESS_SUMS],
    gravity: &Vector<D>,
) -> Option<Vector<D>> {
    let weights = sums[10];
    if weights <= 0.0 {
        return None;
    }
    let g = gravity.norm();
    let down = Vector::<3>::from_fn(|k, _| {
        if k < D && g > 0.0 {
            gravity[k] / g
        } else {
            0.0
        }
    });
    let vertical = down * down.transpose();
    let weighted = Tensor3::from_column_slice(&sums[..9]);
    let stress = (weighted + vertical * sums[9]) / weights;
    let traction =
        Vector::<D>::from_fn(|a, _| (0..D).map(|b| stress[(a, b)] * point.normal[b]).sum());
    (traction.dot(&point.normal) <= 0.0).then_some(traction)
}

/// Σ_q t_q A_q and Σ_q (x_q − x_c) × t_q A_q over `points`, with `traction` the force per area
/// at a point (`None`: unloaded).
fn integrate<const D: usize>(
    points: impl IntoIterator<Item = LoadPoint<D>>,
    about: &Vector<D>,
    mut traction: impl FnMut(&LoadPoint<D>) -> Option<Vector<D>>,
) -> (Vector<D>, Vector<3>) {
    let mut force = Vector::<D>::zeros();
    let mut moment = Vector::<3>::zeros();
    for point in points {
        let Some(t) = traction(&point) else {
            continue;
        };
        let load = t * point.area;
        force += load;
        moment += cross(&(point.position - about), &load);
    }
    (force, moment)
}

/// a × b of two D-vectors taken as 3-vectors (z = 0 in 2D).
pub fn cross<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> Vector<3> {
    let lift = |v: &Vector<D>| Vector::<3>::from_fn(|k, _| if k < D { v[k] } else { 0.0 });
    lift(a).cross(&lift(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_core::Domain;
    use geosph_core::Particles;
    use geosph_kernels::WendlandC2;

    /// Water at rest below z = 1 (hydrostatic pressure) loads the bottom face of a 2D
    /// lattice column with ρ g H per unit area, and a tilted unit plate inside it with the
    /// pressure at its centre.
    #[test]
    fn a_hydrostatic_field_loads_faces_of_any_orientation_exactly() {
        let (dx, rho, g) = (0.05, 1000.0, 9.81);
        let n = 20;
        let position: Vec<Vector<2>> = (0..n * n)
            .map(|k| Vector::<2>::new((k % n) as Real + 0.5, (k / n) as Real + 0.5) * dx)
            .collect();
        let pressure: Vec<Real> = position.iter().map(|x| rho * g * (1.0 - x[1])).collect();
        let fluid = Particles::at_rest(position, rho * dx * dx, rho);
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(2.0)).unwrap();
        let mut grid = CellGrid::new(domain, kernel.support_radius()).unwrap();
        grid.build(&fluid.position).unwrap();
        let field = FluidField {
            position: &fluid.position,
            mass: &fluid.mass,
            density: &fluid.density,
            pressure: &pressure,
            grid: &grid,
            gravity: Vector::<2>::new(0.0, -g),
            background_pressure: 0.0,
        };
        // A plate of unit length through (0.5, 0.5) at 30°, facing up-left, in pieces of dx/2.
        let tangent = Vector::<2>::new(30f64.to_radians().cos(), 30f64.to_radians().sin());
        let normal = Vector::<2>::new(-tangent[1], tangent[0]);
        let centre = Vector::<2>::new(0.5, 0.5);
        let pieces = 40;
        let points = (0..pieces).map(|k| LoadPoint {
            position: centre + tangent * ((k as Real + 0.5) / pieces as Real - 0.5) * 0.4,
            normal,
            area: 0.4 / pieces as Real,
        });
        let (force, moment) = pressure_load(&kernel, &field, points, &centre);
        let expected = -normal * (rho * g * 0.5 * 0.4);
        approx::assert_relative_eq!(force, expected, max_relative = 1e-9);
        // The pressure varies linearly along the plate: a moment about its centre of
        // ρ g sin30° ∫ s² ds (the upper end is pushed less), which the midpoint rule of
        // pieces Δs sums as L³/12 − L Δs²/12.
        let (length, piece): (Real, Real) = (0.4, 0.4 / pieces as Real);
        let expected_moment =
            rho * g * 0.5 * (length.powi(3) / 12.0 - length * piece * piece / 12.0);
        approx::assert_relative_eq!(moment[2], expected_moment, max_relative = 1e-6);
    }
}
