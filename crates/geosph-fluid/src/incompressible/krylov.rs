//! IISPH's pressure system solved by BiCGSTAB: a projection of the velocities with a gentle
//! density correction, converged in its long modes.

use geosph_core::{Particles, Real, Vector};
use geosph_kernels::Kernel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::system::MIN_LEN;
use super::{PressureSolveSettings, PressureSystem, Scratch, SolveReport};

/// How IISPH iterates its pressure system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum PressureIteration {
    /// Relaxed Jacobi on the [`PressureSource`](super::PressureSource) of the settings
    /// (default; Ihmsen et al. 2014): cheap per step, but it stops after a few iterations, before the pressure's long
    /// modes have converged, so the pressure of still water alternates from step to step.
    #[default]
    RelaxedJacobi,
    /// BiCGSTAB on the velocity-divergence source with a density correction ([`Bicgstab`]).
    Bicgstab(Bicgstab),
}

/// Settings of the BiCGSTAB pressure solve (van der Vorst 1992, SIAM J. Sci. Stat. Comput.
/// 13:631, Algorithm "preconditioned Bi-CGSTAB", with the Jacobi preconditioner −Δt² d_i).
///
/// The source is the velocity divergence of v* plus a fraction of the density error
/// e_i = ρ_i − ρ₀,
///
/// Δt² Σ_j m_j (a^p_i − a^p_j)·∇_i W_ij + Δt² a^p_i·Σ_b m_b ∇_i W_ib
///   = −Δt Σ_j m_j (v*_i − v*_j)·∇_i W_ij − (walls) − β e_i − (1 − β) max(e_i − κ ρ₀, 0),
///
/// the velocity-divergence source of Cornelis, Bender, Gissler, Ihmsen & Teschner (2019, Vis.
/// Comput. 35:579) with β = `density_relaxation` of the density-invariance source added, so a
/// density error decays by (1 − β) per step instead of being removed in one: a converged
/// solve of the density-invariance source alone turns density errors of 10⁻⁵ in a long mode
/// into pressures of ρ₀ g H, and alternates by 20 % in still water (`docs/incompressible.md`).
/// A compression beyond κ = `max_compression` is removed whole, as in the papers: a start
/// from a jittered lattice, 25 % compressed in places, blew up in its first step without it.
///
/// The shared [`PressureSolveSettings`] mean, under this solve: `max_iterations` the most
/// BiCGSTAB iterations per active-set pass (each applies the operator twice; a pass that
/// reaches it keeps its iterate of smallest residual);
/// `target_density_error` the predicted compression beyond which a particle outside the set
/// enters it; `max_compression` κ above. `min_iterations`, and IISPH's `relaxation` and
/// `warm_start`, are not used (the start is the previous pressure whole). The report's error
/// is the mean |r_i|/ρ₀ of the solved equation's kept residual over all particles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Bicgstab {
    /// Stop when the residual's 2-norm is at most this fraction of the source's (default
    /// 0.01), the source summed over all particles, those outside the active set included:
    /// at a free surface their expansion makes the norm larger than the active rows' alone,
    /// so the tolerance is looser than on the rows solved (normalising by the active rows
    /// took 25 instead of 2.9 iterations per step in the dam break for the same still-tank
    /// steadiness).
    pub tolerance: Real,
    /// Fraction β of the density error ρ − ρ₀ removed per step (default 0.1).
    pub density_relaxation: Real,
    /// Most solves per step on an updated active set (default 2: from the previous step's
    /// pressure the set changes little; from p = 0 it takes more).
    pub active_set_passes: usize,
}

impl Default for Bicgstab {
    fn default() -> Self {
        Self {
            tolerance: 0.01,
            density_relaxation: 0.1,
            active_set_passes: 2,
        }
    }
}

/// Particles per partial sum of the dot products: the sums are the same for any thread count.
const CHUNK: usize = 256;

/// Work vectors of the BiCGSTAB solve ([`Bicgstab`]), reused every step.
#[derive(Clone, Debug, Default)]
pub struct KrylovScratch {
    /// The unknown π = p/ρ².
    unknown: Vec<Real>,
    source: Vec<Real>,
    residual: Vec<Real>,
    shadow: Vec<Real>,
    direction: Vec<Real>,
    image: Vec<Real>,
    corrected: Vec<Real>,
    corrected_image: Vec<Real>,
    preconditioned: Vec<Real>,
    /// −1/(Δt² d_i) on the active set, 0 elsewhere.
    inverse_diagonal: Vec<Real>,
    /// The iterate with the smallest residual so far, and its residual.
    best_unknown: Vec<Real>,
    best_residual: Vec<Real>,
    partial: Vec<[Real; 2]>,
}

impl KrylovScratch {
    fn resize(&mut self, n: usize) {
        for v in [
            &mut self.unknown,
            &mut self.source,
            &mut self.residual,
            &mut self.shadow,
            &mut self.direction,
            &mut self.image,
            &mut self.corrected,
            &mut self.corrected_image,
            &mut self.preconditioned,
            &mut self.inverse_diagonal,
            &mut self.best_unknown,
            &mut self.best_residual,
        ] {
            v.resize(n, 0.0);
        }
        // Zeroed: with no particles no chunk overwrites the one partial sum, which must
        // then add nothing to the ranks' sums.
        self.partial.clear();
        self.partial.resize(n.div_ceil(CHUNK).max(1), [0.0; 2]);
    }
}

/// The chunks' partial sums, added in order.
fn total(partial: &[[Real; 2]]) -> [Real; 2] {
    total_of(partial.iter().map(|sum| sum.as_slice()))
}

/// Pairs of sums added in order.
fn total_of<'a>(sums: impl Iterator<Item = &'a [Real]>) -> [Real; 2] {
    sums.fold([0.0; 2], |[a, b], sum| [a + sum[0], b + sum[1]])
}

/// The linear part of the solve's operator and its sums.
///
/// In a distributed run the rows from `owned` on are the halo's: the operator's input is
/// refreshed there before each product (its pressure acceleration reads the neighbours'),
/// the dot products and norms sum the owned rows only and are combined over the ranks in rank
/// order, so every rank takes the same α, ω and stopping decisions.
struct Operator<'a, const D: usize, K: Kernel<D>> {
    system: &'a PressureSystem<D, K>,
    mass: &'a [Real],
    dt: Real,
    owned: usize,
}

impl<const D: usize, K: Kernel<D>> Operator<'_, D, K> {
    /// Sums of this rank's chunks, combined over the ranks in rank order (unchanged on one
    /// process).
    fn over_ranks(&self, local: [Real; 2]) -> [Real; 2] {
        let lists = &self.system.lists;
        match lists.distribution() {
            None => local,
            Some(_) => total_of(lists.gather_over_ranks(&local).chunks_exact(2)),
        }
    }

    /// y_i = Δt² (Σ_j m_j (a_i − a_j)·∇_i W_ij + a_i·Σ_b m_b ∇_i W_ib) with a the pressure
    /// acceleration of π = `x` (its halo entries refreshed first), where `rows(i)` (0
    /// elsewhere); returns ⟨y, y⟩ and ⟨y, w⟩ over every rank's owned rows.
    fn apply(
        &self,
        x: &mut [Real],
        rows: impl Fn(usize) -> bool + Sync,
        acceleration: &mut [Vector<D>],
        y: &mut [Real],
        w: &[Real],
        partial: &mut [[Real; 2]],
    ) -> [Real; 2] {
        let (system, mass, dt, owned) = (self.system, self.mass, self.dt, self.owned);
        system.lists.exchange_halo_values(x);
        system.pressure_acceleration(mass, x, acceleration);
        let acceleration = &*acceleration;
        y.par_chunks_mut(CHUNK)
            .zip(partial.par_iter_mut())
            .enumerate()
            .for_each(|(k, (y, sum))| {
                *sum = [0.0; 2];
                for (l, y_i) in y.iter_mut().enumerate() {
                    let i = k * CHUNK + l;
                    *y_i = if rows(i) {
                        dt * dt * system.pressure_divergence_at(i, mass, acceleration)
                    } else {
                        0.0
                    };
                    if i < owned {
                        sum[0] += *y_i * *y_i;
                        sum[1] += *y_i * w[i];
                    }
                }
            });
        self.over_ranks(total(partial))
    }
}

impl Bicgstab {
    /// Solves for pressures p ≥ 0 (any sign with `negative_pressure`) and applies
    /// v ← v* + Δt a^p. Unknowns are π = p/ρ², started from the previous step's pressure
    /// whole, on an active set: the particles that take pressure (d_i > 0) and either had
    /// pressure or are predicted compressed. After each converged solve, particles with p < 0
    /// leave the set and particles outside it predicted compressed beyond the density target
    /// enter it, and the solve repeats, at most `active_set_passes` times.
    pub(crate) fn solve<const D: usize, K: Kernel<D>>(
        &self,
        system: &PressureSystem<D, K>,
        fluid: &mut Particles<D>,
        dt: Real,
        settings: &PressureSolveSettings,
        scratch: &mut Scratch<D>,
    ) -> SolveReport {
        let n = fluid.len();
        let work = &mut scratch.krylov;
        work.resize(n);
        let rho0 = system.rest_density;
        let Particles {
            velocity,
            mass,
            density,
            pressure,
            ..
        } = fluid;
        let pressure = pressure.as_mut().expect("pressure is enabled");
        let (mass, density) = (&*mass, &*density);
        let acceleration = &mut scratch.acceleration;
        let walls = &system.walls;
        let diagonal = system.diagonal();
        let free = settings.negative_pressure;
        let beta = self.density_relaxation;
        let tolerated = settings.max_compression * rho0;
        let owned = system.owned();
        let operator = Operator {
            system,
            mass,
            dt,
            owned,
        };

        // The source b_i and the active set with the warm start.
        {
            let velocity = &*velocity;
            (
                work.source.par_iter_mut(),
                work.inverse_diagonal.par_iter_mut(),
                work.unknown.par_iter_mut(),
            )
                .into_par_iter()
                .enumerate()
                .with_min_len(MIN_LEN)
                .for_each(|(i, (b, inverse, x))| {
                    let rate = dt * system.divergence_at(i, mass, velocity, &walls.velocity);
                    // The walls' own acceleration, the constant part of Δt² ∇·a.
                    let wall = dt
                        * dt
                        * system.add_wall_divergence(i, Vector::zeros(), &walls.acceleration, 0.0);
                    let error = density[i] - rho0;
                    let excess = (error - tolerated).max(0.0);
                    *b = -(rate + wall + beta * error + (1.0 - beta) * excess);
                    let active = diagonal[i] > 0.0 && (free || pressure[i] > 0.0 || *b < 0.0);
                    *inverse = if active {
                        -1.0 / (dt * dt * diagonal[i])
                    } else {
                        0.0
                    };
                    *x = if active {
                        pressure[i] / (density[i] * density[i])
                    } else {
                        0.0
                    };
                });
        }
        let [source_norm, _] = {
            let source = &work.source[..owned];
            work.partial
                .par_iter_mut()
                .zip(source.par_chunks(CHUNK))
                .for_each(|(sum, b)| *sum = [b.iter().map(|b| b * b).sum(), 0.0]);
            let chunks = owned.div_ceil(CHUNK);
            operator.over_ranks(total(&work.partial[..chunks]))
        };
        let target = self.tolerance * self.tolerance * source_norm;

        let mut report = SolveReport::default();
        for _ in 0..self.active_set_passes {
            report.iterations += Self::iterate(&operator, work, acceleration, target, settings);
            if free {
                break;
            }
            // p = max(p, 0) and the density it predicts everywhere; update the set.
            work.unknown.par_iter_mut().for_each(|x| *x = x.max(0.0));
            let KrylovScratch {
                unknown,
                source,
                image,
                inverse_diagonal,
                partial,
                ..
            } = work;
            operator.apply(
                unknown,
                |i| diagonal[i] > 0.0,
                acceleration,
                image,
                source,
                partial,
            );
            let compressed = settings.target_density_error * rho0;
            let mut changed = false;
            for i in 0..owned {
                let active = inverse_diagonal[i] != 0.0;
                if active && unknown[i] <= 0.0 {
                    inverse_diagonal[i] = 0.0;
                    changed = true;
                } else if !active && diagonal[i] > 0.0 && image[i] - source[i] > compressed {
                    inverse_diagonal[i] = -1.0 / (dt * dt * diagonal[i]);
                    changed = true;
                }
            }
            // Every rank goes on while any rank's set changed.
            let mut changed = [Real::from(u8::from(changed))];
            system.lists.max_over_ranks(&mut changed);
            if changed[0] == 0.0 {
                break;
            }
        }

        // Mean predicted error over ρ₀, from the kept residual.
        let residual = &work.residual[..owned];
        let mean = residual.iter().map(|r| r.abs()).sum::<Real>() / (owned.max(1) as Real);
        report.error = system.error_over_ranks((mean, 0.0)).0 / rho0;
        pressure
            .par_iter_mut()
            .zip(work.unknown.par_iter())
            .enumerate()
            .for_each(|(i, (p, x))| *p = x * density[i] * density[i]);
        system.lists.exchange_halo_values(&mut work.unknown);
        let x = &work.unknown;
        velocity
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, v)| *v += system.pressure_acceleration_at(i, mass, x) * dt);
        report
    }

    /// Preconditioned BiCGSTAB on the active rows from the current unknowns, until
    /// ‖r‖² ≤ `target` or the iteration limit; returns the iterations taken. BiCGSTAB's
    /// residual does not fall monotonically, so a solve that stops unconverged keeps the
    /// iterate of smallest residual: the last one can be far worse (in the dam break at
    /// dx = 0.0125 m, whose first step from the hydrostatic start does not converge in 100
    /// iterations, it held pressures of ±1.5 ρ₀gH and the run blew up in step 2).
    fn iterate<const D: usize, K: Kernel<D>>(
        operator: &Operator<'_, D, K>,
        work: &mut KrylovScratch,
        acceleration: &mut [Vector<D>],
        target: Real,
        settings: &PressureSolveSettings,
    ) -> usize {
        let KrylovScratch {
            unknown: x,
            source: b,
            residual: r,
            shadow,
            direction: p,
            image: v,
            corrected: s,
            corrected_image: t,
            preconditioned: z,
            inverse_diagonal: inverse,
            best_unknown,
            best_residual,
            partial,
        } = work;
        let inverse = &*inverse;
        let active = |i: usize| inverse[i] != 0.0;
        let owned = operator.owned;
        // r = b − A x on the active rows, r̂ = r.
        operator.apply(x, active, acceleration, v, b, partial);
        (r.par_iter_mut(), shadow.par_iter_mut(), p.par_iter_mut())
            .into_par_iter()
            .zip(b.par_iter().zip(v.par_iter()))
            .enumerate()
            .for_each(|(i, ((r, shadow, p), (b, v)))| {
                *r = if active(i) { b - v } else { 0.0 };
                *shadow = *r;
                *p = 0.0;
            });
        v.par_iter_mut().for_each(|v| *v = 0.0);
        let [mut r_norm, _] = operator.over_ranks([r[..owned].iter().map(|r| r * r).sum(), 0.0]);
        let mut best_norm = r_norm;
        best_unknown.copy_from_slice(x);
        best_residual.copy_from_slice(r);
        let mut rho = r_norm;
        let (mut alpha, mut omega, mut rho_previous) = (1.0, 1.0, 1.0);
        let mut iterations = 0;
        while iterations < settings.max_iterations && r_norm > target && rho != 0.0 {
            let beta = (rho / rho_previous) * (alpha / omega);
            // p = r + β (p − ω v), z = M⁻¹ p.
            (p.par_iter_mut(), z.par_iter_mut())
                .into_par_iter()
                .zip((r.par_iter(), v.par_iter(), inverse.par_iter()).into_par_iter())
                .for_each(|((p, z), (r, v, inverse))| {
                    *p = r + beta * (*p - omega * v);
                    *z = *p * inverse;
                });
            let [_, shadow_v] = operator.apply(z, active, acceleration, v, shadow, partial);
            if shadow_v == 0.0 {
                break;
            }
            alpha = rho / shadow_v;
            // x += α z, s = r − α v, z = M⁻¹ s, with ‖s‖².
            (
                x.par_chunks_mut(CHUNK),
                s.par_chunks_mut(CHUNK),
                z.par_chunks_mut(CHUNK),
            )
                .into_par_iter()
                .zip(partial.par_iter_mut())
                .enumerate()
                .for_each(|(k, ((x, s, z), sum))| {
                    *sum = [0.0; 2];
                    for (l, ((x, s), z)) in
                        x.iter_mut().zip(s.iter_mut()).zip(z.iter_mut()).enumerate()
                    {
                        let i = k * CHUNK + l;
                        *x += alpha * *z;
                        *s = r[i] - alpha * v[i];
                        *z = *s * inverse[i];
                        if i < owned {
                            sum[0] += *s * *s;
                        }
                    }
                });
            iterations += 1;
            let [s_norm, _] = operator.over_ranks(total(partial));
            if s_norm <= target {
                std::mem::swap(r, s);
                r_norm = s_norm;
                break;
            }
            let [tt, ts] = operator.apply(z, active, acceleration, t, s, partial);
            omega = if tt > 0.0 { ts / tt } else { 0.0 };
            // x += ω z, r = s − ω t, with ‖r‖² and ⟨r̂, r⟩.
            (x.par_chunks_mut(CHUNK), r.par_chunks_mut(CHUNK))
                .into_par_iter()
                .zip(partial.par_iter_mut())
                .enumerate()
                .for_each(|(k, ((x, r), sum))| {
                    *sum = [0.0; 2];
                    for (l, (x, r)) in x.iter_mut().zip(r.iter_mut()).enumerate() {
                        let i = k * CHUNK + l;
                        *x += omega * z[i];
                        *r = s[i] - omega * t[i];
                        if i < owned {
                            sum[0] += *r * *r;
                            sum[1] += *r * shadow[i];
                        }
                    }
                });
            rho_previous = rho;
            [r_norm, rho] = operator.over_ranks(total(partial));
            if r_norm < best_norm {
                best_norm = r_norm;
                best_unknown.copy_from_slice(x);
                best_residual.copy_from_slice(r);
            }
            if omega == 0.0 {
                break;
            }
        }
        if r_norm.is_nan() || r_norm > best_norm {
            x.copy_from_slice(best_unknown);
            r.copy_from_slice(best_residual);
        }
        iterations
    }
}
