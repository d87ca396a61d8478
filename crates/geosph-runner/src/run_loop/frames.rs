//! The frames of a run: one `.vtu` per frame in one process; in a distributed run, one piece
//! per rank (its own particles and the walls in its cells) and a `.pvtu` that lists them,
//! which ParaView opens as one data set. No rank gathers the particles for a frame (except
//! for the free surface, which rank 0 draws from every particle).

use geosph_core::Real;
use geosph_io::{Error, write_vtu_sets};

use crate::error::RunError;
use crate::output::{piece_file, with_frame_sets};

impl<const D: usize> super::RunLoop<'_, D> {
    /// Writes the frame at `time` (collective in a distributed run): in one process, the
    /// particles and walls as one `.vtu`; on several ranks, this rank's piece, and once every
    /// rank has written its own, rank 0 the `.pvtu`. Nothing when VTK output is off.
    pub(super) fn write_frame(&mut self, time: Real) -> Result<(), RunError> {
        let split = self.owned_after_split();
        let Some(view) = &mut self.ranks else {
            if let Some(output) = &mut self.output {
                output.write_frame(time, &self.fluid, self.solver.as_ref())?;
                self.state.frames = output.frames() as u64;
            }
            return Ok(());
        };
        let Some(folder) = view.frames_folder(self.options, self.scene) else {
            return Ok(());
        };
        let surfaces = self.scene.output.surface.is_some();
        if let Some(owned) = split.filter(|_| surfaces) {
            view.gather(&self.fluid, owned);
        }
        let view = &*view;
        // Every particle, for the free surface: gathered, or before the first step shares
        // them out, this rank's own set.
        let whole = match split {
            Some(_) => &view.whole,
            None => &self.fluid,
        };
        let whole = surfaces.then_some(whole);
        let (rank, ranks) = (view.rank(), view.size());
        let frame = self.state.frames as usize;
        let file = folder.join(piece_file(&self.scene.name, frame, rank));
        // The particles and walls this rank writes: its own and those in its cells once the
        // first step has shared them out; before (every rank holds every particle), an equal
        // share of each by index.
        let solver = self.solver.as_ref();
        let walls = &solver.walls().position;
        let distribution = solver.distribution().filter(|_| split.is_some());
        let share = |n: usize| n * rank / ranks..n * (rank + 1) / ranks;
        let particles = match split {
            Some(owned) => 0..owned,
            None => share(self.fluid.len()),
        };
        let wall_share = share(walls.len());
        let wall = |i: usize| match distribution {
            Some(distribution) => distribution.owner(&walls[i]) == Some(rank),
            None => wall_share.contains(&i),
        };
        let output = &mut self.output;
        with_frame_sets(&self.fluid, particles, solver, &wall, |sets| {
            // A failure here is agreed below, so that no rank leaves the others waiting.
            let written = std::fs::create_dir_all(&folder)
                .map_err(|source| Error::Io {
                    path: folder.clone(),
                    source,
                })
                .and_then(|()| write_vtu_sets(&file, sets));
            let [failed] = view.any([written.is_err()]);
            written?;
            if failed {
                return Err(Error::Io {
                    path: file.clone(),
                    source: std::io::Error::other(
                        "another rank could not write its piece of this frame",
                    ),
                });
            }
            match output {
                Some(output) => output.add_pieces(time, sets, ranks, whole),
                None => Ok(()),
            }
        })?;
        self.state.frames += 1;
        Ok(())
    }
}
