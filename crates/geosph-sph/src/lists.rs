//! Pair lists: the one owner of who interacts with whom.
//!
//! A solver's particles interact with each other (the *inner* list) and with the fixed wall
//! particles (the *contact* list; the *wall-side* list is the same pairs seen from the walls,
//! for wall conditions that sum over the flow). The model is SPHinXsys's inner and contact
//! relations (Zhang, Rezavand & Hu 2021): every term loops over these lists, and none keeps
//! its own list, grid or skin.

use geosph_core::{Domain, NeighbourList, Particles, Permutation, Real, Vector};
use geosph_kernels::Kernel;
use geosph_neighbours::{CellGrid, SearchError};
use rayon::prelude::*;

use crate::distributed::Distribution;

mod distribute;
mod index;

/// One neighbour j of particle i inside the kernel support, as a pair term needs it.
#[derive(Clone, Copy, Debug)]
pub struct Neighbour<const D: usize> {
    /// j: the index of the neighbour in its own set (particles or walls).
    pub index: usize,
    /// r_ij = x_i − x_j (minimum image on periodic axes).
    pub r_ij: Vector<D>,
    /// |r_ij|².
    pub r2: Real,
    /// |r_ij|.
    pub r: Real,
    /// ∇_i W_ij = r_ij W'(r)/r.
    pub grad: Vector<D>,
}

/// The neighbour lists of one particle set and the fixed walls around it, with their grids,
/// Verlet skin and Z-order schedule.
///
/// With a skin (Verlet 1967) the lists are searched with the support radius plus the skin and
/// rebuilt only when some particle has moved more than half the skin since the last build, so
/// every pair within the support is always listed; the visitors
/// ([`PairLists::for_each_neighbour`] and its siblings) skip the pairs that are in the skin
/// only. Without a skin the lists are exact and [`PairLists::update`] rebuilds them every time
/// (the incompressible solvers, which store per-pair values and iterate over them many times
/// per step).
pub struct PairLists<const D: usize> {
    domain: Domain<D>,
    support_radius: Real,
    skin: Real,
    grid: CellGrid<D>,
    wall_grid: CellGrid<D>,
    inner: NeighbourList,
    contact: NeighbourList,
    wall_side: Option<NeighbourList>,
    listed_position: Vec<Vector<D>>,
    /// The wall positions of the last build, kept once the walls move
    /// ([`PairLists::walls_move`]).
    listed_wall_position: Option<Vec<Vector<D>>>,
    valid: bool,
    builds: usize,
    /// Steps between Z-order sorts of the particles (0: never; a distributed run sorts at its
    /// set-ups instead).
    pub reorder_every: usize,
    /// This rank's share of a distributed run, if it is one ([`PairLists::distribute`]).
    distribution: Option<Distribution<D>>,
    /// The cut of a distributed run's checkpoint, restored, for [`PairLists::distribute`].
    restored_partition: Option<crate::PartitionState>,
}

impl<const D: usize> PairLists<D> {
    /// Lists for particles interacting within `support_radius` on `domain`, with walls at
    /// `wall_position` (their grid is built once here) and a Verlet skin of `skin_fraction` ×
    /// the support radius (0: exact lists). With `wall_side`, the wall–particle list is kept
    /// too. Sorts every 100 steps unless [`PairLists::reorder_every`] says otherwise.
    pub fn new(
        domain: Domain<D>,
        support_radius: Real,
        skin_fraction: Real,
        wall_position: &[Vector<D>],
        wall_side: bool,
    ) -> Result<Self, SearchError> {
        let skin = skin_fraction.max(0.0) * support_radius;
        let radius = support_radius + skin;
        // A particle that leaves the domain keeps its pairs until the runner removes it
        // after the step it left in.
        // A domain of more cells than a dense index holds gets a hashed one, which
        // `use_cell_index` may change.
        let mut grid = CellGrid::fitting(domain.clone(), radius)?;
        grid.bin_outside_in_edge_cells();
        let mut wall_grid = CellGrid::with_index(domain.clone(), radius, grid.index())?;
        wall_grid.build(wall_position)?;
        Ok(Self {
            domain,
            support_radius,
            skin,
            grid,
            wall_grid,
            inner: NeighbourList::new(),
            contact: NeighbourList::new(),
            wall_side: wall_side.then(NeighbourList::new),
            listed_position: Vec::new(),
            listed_wall_position: None,
            valid: false,
            builds: 0,
            reorder_every: 100,
            distribution: None,
            restored_partition: None,
        })
    }

    /// The domain (periodic axes, minimum image).
    pub fn domain(&self) -> &Domain<D> {
        &self.domain
    }

    /// Particle–particle pairs of the last build (each particle lists itself too).
    pub fn inner(&self) -> &NeighbourList {
        &self.inner
    }

    /// Particle–wall pairs of the last build.
    pub fn contact(&self) -> &NeighbourList {
        &self.contact
    }

    /// Wall–particle pairs of the last build.
    ///
    /// # Panics
    /// If the lists were made without `wall_side`.
    pub fn wall_side(&self) -> &NeighbourList {
        self.wall_side
            .as_ref()
            .expect("the lists were made with wall_side")
    }

    /// How often the lists were built.
    pub fn builds(&self) -> usize {
        self.builds
    }

    /// Wraps positions on periodic axes back into the domain.
    pub fn wrap(&self, position: &mut [Vector<D>]) {
        if self.domain.is_periodic() {
            let domain = &self.domain;
            position.par_iter_mut().for_each(|x| domain.wrap(x));
        }
    }

    /// Sorts `particles` in Z order (after wrapping them) and returns the permutation, so a
    /// solver can reorder its own per-particle arrays. The lists must be rebuilt afterwards.
    pub fn sort(&mut self, particles: &mut Particles<D>) -> Result<Permutation, SearchError> {
        self.wrap(&mut particles.position);
        self.grid.build(&particles.position)?;
        let permutation = self.grid.z_order(&particles.position)?;
        particles.permute(&permutation);
        self.valid = false;
        Ok(permutation)
    }

    /// [`PairLists::sort`] when `step` is a multiple of [`PairLists::reorder_every`].
    pub fn sort_if_due(
        &mut self,
        step: usize,
        particles: &mut Particles<D>,
    ) -> Result<Option<Permutation>, SearchError> {
        if self.reorder_every > 0 && step % self.reorder_every == 0 {
            self.sort(particles).map(Some)
        } else {
            Ok(None)
        }
    }

    /// Wraps `position` and rebuilds the lists if they are stale (always without a skin);
    /// returns whether they were rebuilt.
    ///
    /// In a distributed run the ranks agree (collective): an error on any rank is an error on
    /// all ([`Distribution::agree`]), and so is a halo that no longer holds every neighbour.
    pub fn update(
        &mut self,
        position: &mut [Vector<D>],
        wall_position: &[Vector<D>],
    ) -> Result<bool, SearchError> {
        self.wrap(position);
        let result = self.rebuild_if_stale(position, wall_position);
        match &self.distribution {
            Some(distribution) => distribution.agree(result, position),
            None => result,
        }
    }

    /// Rebuilds the lists if they are stale; returns whether it did.
    fn rebuild_if_stale(
        &mut self,
        position: &[Vector<D>],
        wall_position: &[Vector<D>],
    ) -> Result<bool, SearchError> {
        if !self.stale(position, wall_position) {
            return Ok(false);
        }
        self.build(position, wall_position)?;
        if self.skin > 0.0 {
            self.listed_position.clear();
            self.listed_position.extend_from_slice(position);
        }
        Ok(true)
    }

    /// Forgets the lists (after particles were removed or moved by hand); the next update
    /// rebuilds them.
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Rebuilds the wall grid for walls now at `wall_position` (walls removed, e.g. a
    /// retaining wall at release) and forgets the lists.
    pub fn set_walls(&mut self, wall_position: &[Vector<D>]) -> Result<(), SearchError> {
        self.wall_grid.build(wall_position)?;
        self.valid = false;
        Ok(())
    }

    /// From now on the walls may move between updates (rigid bodies): each build rebins them,
    /// and the lists are stale once a pair may have come within the support, i.e. when with
    /// the largest displacements δ_p of a particle and δ_w of a wall particle since the build
    /// 2 δ_p > s or δ_p + δ_w > s (s the skin). Forgets the lists.
    pub fn walls_move(&mut self) {
        self.listed_wall_position.get_or_insert_with(Vec::new);
        self.valid = false;
    }

    /// The positions the lists were built at, while they are valid and have a skin (a
    /// checkpoint saves them: the lists' order decides the summation order).
    pub fn listed_positions(&self) -> Option<&[Vector<D>]> {
        (self.valid && self.skin > 0.0).then_some(self.listed_position.as_slice())
    }

    /// The wall positions the lists were built at, while they are valid, have a skin and the
    /// walls move (a checkpoint saves them with [`PairLists::listed_positions`]).
    pub fn listed_wall_positions(&self) -> Option<&[Vector<D>]> {
        self.listed_positions()
            .and(self.listed_wall_position.as_deref())
    }

    /// Builds the lists at `listed`, positions saved from [`PairLists::listed_positions`], so
    /// they are those of the saved run (a restart); with moving walls at `wall_position`
    /// as [`PairLists::listed_wall_positions`] saved them, else at the walls' positions.
    pub fn rebuild_at(
        &mut self,
        listed: Vec<Vector<D>>,
        wall_position: &[Vector<D>],
    ) -> Result<(), SearchError> {
        self.build(&listed, wall_position)?;
        self.listed_position = listed;
        Ok(())
    }

    /// Whether the lists must be rebuilt for `position`: without a skin always; with one when
    /// they are invalid or some particle moved more than half the skin since they were built
    /// (with moving walls, also when a particle and a wall particle together moved more than
    /// the skin).
    fn stale(&self, position: &[Vector<D>], wall_position: &[Vector<D>]) -> bool {
        if self.skin <= 0.0 || !self.valid || self.listed_position.len() != position.len() {
            return true;
        }
        let particle2 = largest_displacement2(&self.domain, position, &self.listed_position);
        if 4.0 * particle2 > self.skin * self.skin {
            return true;
        }
        match &self.listed_wall_position {
            Some(listed) if listed.len() != wall_position.len() => true,
            Some(listed) => {
                let wall2 = largest_displacement2(&self.domain, wall_position, listed);
                particle2.sqrt() + wall2.sqrt() > self.skin
            }
            None => false,
        }
    }

    /// Builds the grid and the lists at `position` (parallel, in cell order, identical for any
    /// number of threads).
    fn build(
        &mut self,
        position: &[Vector<D>],
        wall_position: &[Vector<D>],
    ) -> Result<(), SearchError> {
        if let Some(listed) = &mut self.listed_wall_position {
            self.wall_grid.build(wall_position)?;
            listed.clear();
            listed.extend_from_slice(wall_position);
        }
        self.grid.build(position)?;
        self.grid
            .neighbour_list(position, position, &mut self.inner);
        self.wall_grid
            .neighbour_list(wall_position, position, &mut self.contact);
        if let Some(wall_side) = &mut self.wall_side {
            self.grid.neighbour_list(position, wall_position, wall_side);
        }
        self.valid = true;
        self.builds += 1;
        Ok(())
    }

    /// The pair (i, j) of `x_i` and the neighbour `index` at `x_j`, if inside the support.
    #[inline(always)]
    fn pair<K: Kernel<D>>(
        &self,
        kernel: &K,
        x_i: &Vector<D>,
        index: usize,
        x_j: &Vector<D>,
    ) -> Option<Neighbour<D>> {
        let r_ij = self.domain.displacement(x_i, x_j);
        let r2 = r_ij.norm_squared();
        if r2 >= self.support_radius * self.support_radius {
            return None; // a pair in the Verlet skin
        }
        let r = r2.sqrt();
        Some(Neighbour {
            index,
            r_ij,
            r2,
            r,
            grad: r_ij * kernel.gradient_factor(r),
        })
    }

    /// Calls `visit` for every other particle j within the support of particle `i`.
    #[inline(always)]
    pub fn for_each_neighbour<K: Kernel<D>>(
        &self,
        kernel: &K,
        position: &[Vector<D>],
        i: usize,
        mut visit: impl FnMut(Neighbour<D>),
    ) {
        let x_i = position[i];
        for &j in self.inner.neighbours(i) {
            let j = j as usize;
            if j == i {
                continue;
            }
            if let Some(pair) = self.pair(kernel, &x_i, j, &position[j]) {
                visit(pair);
            }
        }
    }

    /// Calls `visit` for particle `i` itself (r = 0) and every other particle j within its
    /// support, in list order (kernel sums).
    #[inline(always)]
    pub fn for_each_neighbour_and_self<K: Kernel<D>>(
        &self,
        kernel: &K,
        position: &[Vector<D>],
        i: usize,
        mut visit: impl FnMut(Neighbour<D>),
    ) {
        let x_i = position[i];
        for &j in self.inner.neighbours(i) {
            let j = j as usize;
            if let Some(pair) = self.pair(kernel, &x_i, j, &position[j]) {
                visit(pair);
            }
        }
    }

    /// Calls `visit` for every wall particle within the support of particle `i` (`index` is
    /// the wall particle's).
    #[inline(always)]
    pub fn for_each_wall<K: Kernel<D>>(
        &self,
        kernel: &K,
        position: &[Vector<D>],
        wall_position: &[Vector<D>],
        i: usize,
        visit: impl FnMut(Neighbour<D>),
    ) {
        self.for_each_wall_at(kernel, &position[i], i, wall_position, visit);
    }

    /// [`PairLists::for_each_wall`] for particle `i` placed at `x_i` (a position being
    /// corrected, not yet written back).
    #[inline(always)]
    pub fn for_each_wall_at<K: Kernel<D>>(
        &self,
        kernel: &K,
        x_i: &Vector<D>,
        i: usize,
        wall_position: &[Vector<D>],
        mut visit: impl FnMut(Neighbour<D>),
    ) {
        for &w in self.contact.neighbours(i) {
            let w = w as usize;
            if let Some(pair) = self.pair(kernel, x_i, w, &wall_position[w]) {
                visit(pair);
            }
        }
    }

    /// Calls `visit` for every particle within the support of wall particle `w`, with
    /// r_ij = x_i − x_w from the particle to the wall (`index` is the particle's).
    ///
    /// # Panics
    /// If the lists were made without `wall_side`.
    #[inline(always)]
    pub fn for_each_particle_near_wall<K: Kernel<D>>(
        &self,
        kernel: &K,
        position: &[Vector<D>],
        wall_position: &[Vector<D>],
        w: usize,
        mut visit: impl FnMut(Neighbour<D>),
    ) {
        let x_w = wall_position[w];
        for &i in self.wall_side().neighbours(w) {
            let i = i as usize;
            if let Some(pair) = self.pair(kernel, &position[i], i, &x_w) {
                visit(pair);
            }
        }
    }
}

/// The largest |x − x₀|² over `position` and `listed` (minimum image).
fn largest_displacement2<const D: usize>(
    domain: &Domain<D>,
    position: &[Vector<D>],
    listed: &[Vector<D>],
) -> Real {
    position
        .par_iter()
        .zip(listed.par_iter())
        .map(|(x, x0)| domain.displacement(x, x0).norm_squared())
        .reduce(|| 0.0, Real::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geosph_kernels::WendlandC2;

    fn lattice(n: usize, dx: Real) -> Vec<Vector<2>> {
        (0..n * n)
            .map(|k| Vector::<2>::new((k % n) as Real + 0.5, (k / n) as Real + 0.5) * dx)
            .collect()
    }

    /// The visitors see exactly the pairs of an O(N²) search inside the support, with the skin
    /// and the particle itself left out, also after moves smaller than half the skin.
    #[test]
    fn visitors_see_the_pairs_inside_the_support_only() {
        let dx = 0.1;
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let support = kernel.support_radius();
        let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(2.0)).unwrap();
        let walls: Vec<Vector<2>> = (0..12)
            .map(|k| Vector::<2>::new(k as Real * dx, -0.5 * dx))
            .collect();
        let mut lists = PairLists::new(domain, support, 0.2, &walls, true).unwrap();
        let mut position = lattice(10, dx);
        assert!(lists.update(&mut position, &walls).unwrap());
        // Moves below half the skin keep the lists; the visitors still filter by distance.
        position[7] += Vector::<2>::new(0.09 * support, 0.0);
        assert!(!lists.update(&mut position, &walls).unwrap());
        for i in 0..position.len() {
            let mut seen = Vec::new();
            lists.for_each_neighbour(&kernel, &position, i, |pair| {
                approx::assert_relative_eq!(pair.r, (position[i] - position[pair.index]).norm());
                seen.push(pair.index);
            });
            seen.sort();
            let expected: Vec<usize> = (0..position.len())
                .filter(|&j| j != i && (position[i] - position[j]).norm() < support)
                .collect();
            assert_eq!(seen, expected, "particle {i}");
            let mut walls_seen = Vec::new();
            lists.for_each_wall(&kernel, &position, &walls, i, |pair| {
                walls_seen.push(pair.index)
            });
            walls_seen.sort();
            let expected: Vec<usize> = (0..walls.len())
                .filter(|&w| (position[i] - walls[w]).norm() < support)
                .collect();
            assert_eq!(walls_seen, expected, "walls of particle {i}");
        }
        let mut count = 0;
        lists.for_each_particle_near_wall(&kernel, &position, &walls, 3, |pair| {
            assert!(
                pair.r_ij[1] > 0.0,
                "r_ij points from the wall to the particle"
            );
            count += 1;
        });
        assert!(count > 0);
        // A move beyond half the skin rebuilds.
        position[7] += Vector::<2>::new(0.02 * support, 0.0);
        assert!(lists.update(&mut position, &walls).unwrap());
        assert_eq!(lists.builds(), 2);
    }

    /// Walls that move (a body): the lists hold every fluid–wall pair inside the support as
    /// long as a particle and a wall particle together moved less than the skin, and are
    /// rebuilt, with the walls rebinned, once they may have moved more.
    #[test]
    fn moving_walls_are_rebinned_and_their_pairs_kept() {
        let dx = 0.1;
        let kernel = WendlandC2::<2>::new(1.3 * dx);
        let support = kernel.support_radius();
        let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(3.0)).unwrap();
        let mut walls: Vec<Vector<2>> = (0..12)
            .map(|k| Vector::<2>::new(k as Real * dx, -0.5 * dx))
            .collect();
        let mut lists = PairLists::new(domain, support, 0.2, &walls, false).unwrap();
        lists.walls_move();
        let mut position = lattice(10, dx);
        assert!(lists.update(&mut position, &walls).unwrap());
        let check = |lists: &PairLists<2>, position: &[Vector<2>], walls: &[Vector<2>]| {
            for i in 0..position.len() {
                let mut seen = Vec::new();
                lists.for_each_wall(&kernel, position, walls, i, |pair| seen.push(pair.index));
                seen.sort();
                let expected: Vec<usize> = (0..walls.len())
                    .filter(|&w| (position[i] - walls[w]).norm() < support)
                    .collect();
                assert_eq!(seen, expected, "walls of particle {i}");
            }
        };
        // Up by 0.45 skin, particles still: kept, and every pair still listed.
        for x in &mut walls {
            x[1] += 0.45 * 0.2 * support;
        }
        assert!(!lists.update(&mut position, &walls).unwrap());
        check(&lists, &position, &walls);
        // A particle moving 0.45 skin towards them as well: together more than half the
        // skin but less than all of it, still kept.
        position[3][1] -= 0.45 * 0.2 * support;
        assert!(!lists.update(&mut position, &walls).unwrap());
        check(&lists, &position, &walls);
        // Walls a whole skin away from their build: rebuilt and rebinned.
        for x in &mut walls {
            x[1] += 0.2 * support;
        }
        assert!(lists.update(&mut position, &walls).unwrap());
        check(&lists, &position, &walls);
        assert_eq!(lists.listed_wall_positions(), Some(walls.as_slice()));
    }

    #[test]
    fn exact_lists_are_rebuilt_every_update_and_save_no_positions() {
        let dx = 0.1;
        let domain = Domain::new(Vector::<2>::repeat(-1.0), Vector::<2>::repeat(2.0)).unwrap();
        let mut lists = PairLists::new(domain, 0.26, 0.0, &[], false).unwrap();
        let mut position = lattice(4, dx);
        assert!(lists.update(&mut position, &[]).unwrap());
        assert!(lists.update(&mut position, &[]).unwrap());
        assert!(lists.listed_positions().is_none());
        assert_eq!(lists.builds(), 2);
    }
}
