//! The last line of defence of dummy-particle walls: no particle ends a step behind a wall's
//! surface.

use geosph_boundary::WallParticles;
use geosph_core::{Real, Vector};
use geosph_kernels::Kernel;
use rayon::prelude::*;

use crate::PairLists;

/// Moves every particle that ended a step behind a wall's surface back onto it and removes
/// the part of its velocity that points into the wall; returns how many it moved.
///
/// Dummy particles stop the flow by pressure alone (Adami, Hu & Adams 2012), and a pressure
/// needs compression to build up: a spray particle that reaches a wall below the rest density
/// (the pressure solvers carry no suction at a free surface), or one drawn in by a slightly
/// negative pressure next to the wall (WCSPH), can drift through the surface. The surface near
/// particle i is that of its nearest wall particle w, the plane through x_w + d_w n_w with the
/// inward normal n_w and the depth d_w of [`WallParticles`]. With r = x_i − x_w, the particle
/// is behind it when
///
/// φ_i = r·n_w − d_w < 0  and  |r − (r·n_w) n_w| < a_w,  a_w = max(d_w, √(D−1) Δx_w / 2),
///
/// with Δx_w = V_w^{1/D} the wall particle's spacing: behind the surface point and within the
/// footprint a_w of the wall particle's normal line. The footprint keeps the test true to a
/// convex corner (an obstacle's): a wall particle on the corner's diagonal is as near to two
/// faces and carries the normal of one, whose plane runs on past the corner; the fluid beside
/// the corner is farther than d_w from its axis (the corner of a lattice-aligned right angle
/// exactly; in 3D a band √2 Δx/2 − d_w thick beside the edge stays in the test). Its least
/// value, half the diagonal of a lattice cell's face, covers every point of a flat wall behind
/// its first layer, whose nearest wall particle is at most that far aside.
///
/// Then x_i ← x_i − φ_i n_w and v_i ← v_i − min((v_i − u_w)·n_w, 0) n_w (an inelastic
/// contact, as the collision handling of particle fluids: Ihmsen et al. 2014, Eurographics
/// STAR). A run whose walls hold by pressure never reaches it: the runner reports the
/// count, so that a run where it acts is known (`docs/fluid.md`, "Walls that hold").
///
/// Reads the wall lists of `lists`, valid for positions within the Verlet skin of their
/// build (any position after one step). Each particle is corrected from its own neighbours,
/// so the result does not depend on the thread count.
pub fn keep_out_of_walls<const D: usize, K: Kernel<D>>(
    lists: &PairLists<D>,
    kernel: &K,
    walls: &WallParticles<D>,
    position: &mut [Vector<D>],
    velocity: &mut [Vector<D>],
) -> usize {
    if walls.is_empty() {
        return 0;
    }
    position
        .par_iter_mut()
        .zip(velocity.par_iter_mut())
        .enumerate()
        .with_min_len(256)
        .map(|(i, (x, v))| {
            let mut nearest: Option<(Real, usize, Real)> = None;
            lists.for_each_wall_at(kernel, x, i, &walls.position, |pair| {
                if nearest.is_none_or(|(r2, _, _)| pair.r2 < r2) {
                    let along = pair.r_ij.dot(&walls.normal[pair.index]);
                    nearest = Some((pair.r2, pair.index, along));
                }
            });
            let Some((r2, w, along)) = nearest else {
                return 0;
            };
            let depth = walls.depth[w];
            let behind = along - depth;
            if behind >= 0.0 {
                return 0;
            }
            // The footprint: d_w, and at least the half-diagonal of a lattice cell's face.
            let spacing = walls.volume[w].powf(1.0 / D as Real);
            let footprint = depth.max(0.5 * spacing * ((D - 1) as Real).sqrt());
            if r2 - along * along >= footprint * footprint {
                return 0;
            }
            let normal = walls.normal[w];
            *x -= normal * behind;
            let into = (*v - walls.velocity[w]).dot(&normal);
            if into < 0.0 {
                *v -= normal * into;
            }
            1
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_boundary::generate::tank;
    use geosph_core::Domain;
    use geosph_kernels::WendlandC2;

    #[test]
    fn a_particle_behind_a_tank_face_is_put_back_on_it_and_stopped() {
        let dx = 0.1;
        let walls = tank(
            &Vector::<2>::new(0.0, 0.0),
            &Vector::<2>::new(1.0, 1.0),
            dx,
            3,
            false,
            1000.0,
        );
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let domain = Domain::new(Vector::<2>::repeat(-0.5), Vector::<2>::repeat(1.5)).unwrap();
        // Behind the left face, on it, and well inside the tank.
        let mut position = vec![
            Vector::<2>::new(-0.02, 0.5),
            Vector::<2>::new(0.0, 0.3),
            Vector::<2>::new(0.5, 0.5),
        ];
        let mut velocity = vec![
            Vector::<2>::new(-3.0, 1.0),
            Vector::<2>::new(-1.0, 0.0),
            Vector::<2>::new(-1.0, 0.0),
        ];
        let mut lists =
            PairLists::new(domain, kernel.support_radius(), 0.1, &walls.position, false).unwrap();
        lists.update(&mut position, &walls.position).unwrap();
        let moved = keep_out_of_walls(&lists, &kernel, &walls, &mut position, &mut velocity);
        assert_eq!(moved, 1);
        approx::assert_abs_diff_eq!(position[0], Vector::<2>::new(0.0, 0.5), epsilon = 1e-15);
        // The normal velocity into the wall is removed, the tangential one kept.
        approx::assert_abs_diff_eq!(velocity[0], Vector::<2>::new(0.0, 1.0), epsilon = 1e-15);
        assert_eq!(velocity[1], Vector::<2>::new(-1.0, 0.0));
        assert_eq!(position[2], Vector::<2>::new(0.5, 0.5));
    }

    #[test]
    fn fluid_beside_an_obstacle_corner_stays_and_fluid_inside_it_is_put_back() {
        // An obstacle [0, 0.5)², three layers of wall particles inside it, each with the
        // normal to its nearest face; on the diagonal the tie goes to the x faces, so the
        // corner particle (0.45, 0.45) carries n = +x and the plane x = 0.5 runs on above
        // the top face y = 0.5.
        let (dx, side) = (0.1, 0.5);
        let mut position = Vec::new();
        let mut normal = Vec::new();
        let mut depth = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                let x = Vector::<2>::new((i as Real + 0.5) * dx, (j as Real + 0.5) * dx);
                let faces = [
                    (x[0], Vector::<2>::new(-1.0, 0.0)),
                    (side - x[0], Vector::<2>::new(1.0, 0.0)),
                    (x[1], Vector::<2>::new(0.0, -1.0)),
                    (side - x[1], Vector::<2>::new(0.0, 1.0)),
                ];
                let (d, n) =
                    faces.into_iter().fold(
                        faces[0],
                        |best, face| if face.0 < best.0 { face } else { best },
                    );
                if d < 3.0 * dx {
                    position.push(x);
                    normal.push(n);
                    depth.push(d);
                }
            }
        }
        let walls = WallParticles::fixed(position, normal, depth, dx * dx, 1000.0);
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let domain = Domain::new(Vector::<2>::repeat(-0.5), Vector::<2>::repeat(1.0)).unwrap();
        // Above the top face beside the corner (a nearest-plane test would move it to
        // x = 0.5), and inside the obstacle behind the right face near the corner.
        let mut position = vec![Vector::<2>::new(0.45, 0.52), Vector::<2>::new(0.48, 0.46)];
        let mut velocity = vec![Vector::<2>::new(0.0, -1.0), Vector::<2>::new(-1.0, 0.0)];
        let mut lists =
            PairLists::new(domain, kernel.support_radius(), 0.1, &walls.position, false).unwrap();
        lists.update(&mut position, &walls.position).unwrap();
        let moved = keep_out_of_walls(&lists, &kernel, &walls, &mut position, &mut velocity);
        assert_eq!(moved, 1);
        assert_eq!(position[0], Vector::<2>::new(0.45, 0.52));
        approx::assert_abs_diff_eq!(position[1], Vector::<2>::new(0.5, 0.46), epsilon = 1e-15);
        assert_eq!(velocity[1], Vector::<2>::new(0.0, 0.0));
    }

    #[test]
    fn a_particle_behind_a_3d_bed_between_its_wall_particles_is_put_back() {
        // Behind the bed z = 0 of a 3D tank, as far aside of its nearest wall particle
        // (0.45, 0.45, -0.05) as a point of the bed can be: (0.4, 0.4) dx.
        let dx = 0.1;
        let walls = tank(
            &Vector::<3>::zeros(),
            &Vector::<3>::repeat(1.0),
            dx,
            3,
            false,
            1000.0,
        );
        let kernel = WendlandC2::<3>::new(1.3 * dx);
        let domain = Domain::new(Vector::<3>::repeat(-0.5), Vector::<3>::repeat(1.5)).unwrap();
        let mut position = vec![Vector::<3>::new(0.49, 0.49, -0.01)];
        let mut velocity = vec![Vector::<3>::new(0.0, 0.0, -1.0)];
        let mut lists =
            PairLists::new(domain, kernel.support_radius(), 0.1, &walls.position, false).unwrap();
        lists.update(&mut position, &walls.position).unwrap();
        let moved = keep_out_of_walls(&lists, &kernel, &walls, &mut position, &mut velocity);
        assert_eq!(moved, 1);
        approx::assert_abs_diff_eq!(
            position[0],
            Vector::<3>::new(0.49, 0.49, 0.0),
            epsilon = 1e-15
        );
    }
}
