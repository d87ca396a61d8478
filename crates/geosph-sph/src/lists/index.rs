//! The cell index of the pair lists' grids: dense or hashed (a scene's `domain.cells`).

use geosph_core::Vector;
use geosph_neighbours::{CellGrid, CellIndex, SearchError};

use super::PairLists;

impl<const D: usize> PairLists<D> {
    /// Indexes the cells of the particles' and the walls' grids with `index` (nothing to do
    /// when they already do; the lists start with a dense index, or a hashed one when the
    /// domain has more cells than a dense one holds, which a dense `index` then refuses; the
    /// lists are
    /// made anew at the next update, and are those of the other index, bitwise); the walls
    /// at `wall_position` are binned again. For the sparse or unbounded domains a dense
    /// index cannot hold ([`CellGrid::hashed`]).
    pub fn use_cell_index(
        &mut self,
        index: CellIndex,
        wall_position: &[Vector<D>],
    ) -> Result<(), SearchError> {
        if index == self.grid.index() {
            return Ok(());
        }
        let radius = self.grid.radius();
        let mut grid = CellGrid::with_index(self.domain.clone(), radius, index)?;
        grid.bin_outside_in_edge_cells();
        let mut wall_grid = CellGrid::with_index(self.domain.clone(), radius, index)?;
        wall_grid.build(wall_position)?;
        (self.grid, self.wall_grid) = (grid, wall_grid);
        self.valid = false;
        Ok(())
    }
}
