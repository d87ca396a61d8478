//! Checkpoints and interrupts of the run loop: one file in one process; in a distributed run
//! one piece per rank (the particles it owns and their solver state) and a manifest that
//! rank 0 writes once every piece is complete (`checkpoint::pieces`).

use std::sync::atomic::Ordering;

use geosph_core::{Particles, Real};
use geosph_sph::SolverState;

use crate::checkpoint::{
    self, Checkpoint, CheckpointError, ParticleState, piece_file, remove_stale_pieces,
};
use crate::error::RunError;

impl<const D: usize> super::RunLoop<'_, D> {
    /// Writes a checkpoint when one is due or the run was interrupted (the ranks of a
    /// distributed run agree on both); after an interrupt, also the current frame, and ends
    /// the run.
    pub(super) fn checkpoint_or_interrupt(
        &mut self,
        time: Real,
        steps: usize,
    ) -> Result<(), RunError> {
        let mut interrupted = self
            .options
            .interrupt
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed));
        let finished = time >= self.scene.end_time - self.tolerance;
        let mut due = !finished && self.checkpoints.due(time);
        let can_save = match &self.ranks {
            Some(view) => {
                // Rank 0's clock decides (a wall-clock interval would end at other steps on
                // other ranks).
                due &= view.is_root();
                [interrupted, due] = view.any([interrupted, due]);
                self.options.pieces_dir.is_some()
            }
            None => self.checkpoint_path.is_some() && self.output.is_some(),
        };
        if can_save && (interrupted || due) {
            if let Some(output) = &mut self.output {
                output.flush()?;
            }
            match self.ranks.is_some() {
                true => self.write_pieces()?,
                false => {
                    if let Some(path) = &self.checkpoint_path {
                        let solver = self.solver.save_state();
                        self.checkpoint(ParticleState::save(&self.fluid), solver)
                            .write(path)?;
                        // The pieces of a distributed run this one restarted from.
                        remove_stale_pieces(path, &[]);
                    }
                }
            }
        }
        if !interrupted {
            return Ok(());
        }
        self.take_whole();
        self.bar.finish_and_clear();
        let frame = match &self.output {
            Some(output) => {
                Some(output.write_snapshot("interrupted.vtu", &self.fluid, self.solver.as_ref())?)
            }
            None => None,
        };
        Err(RunError::Interrupted {
            time,
            step: steps,
            checkpoint: self.checkpoint_path.clone().filter(|_| frame.is_some()),
            frame,
        })
    }

    /// The state of the run now, with `particles` and the solver's state `solver`.
    fn checkpoint(&self, particles: ParticleState, solver: SolverState) -> Checkpoint {
        Checkpoint {
            scene: self.scene.name.clone(),
            scene_hash: checkpoint::scene_hash(self.scene),
            dimension: D as u32,
            progress: self.state.clone(),
            particles,
            solver,
            observer: self.observer.save_state(),
            pieces: Vec::new(),
        }
    }

    /// A distributed run's checkpoint (collective): each rank writes its piece, the ranks
    /// agree every piece is complete, rank 0 writes the manifest and removes the earlier
    /// pieces; the next step starts with a set-up that keeps the cut, as a restart from this
    /// checkpoint does, so that both continue alike.
    fn write_pieces(&mut self) -> Result<(), RunError> {
        let (Some(view), Some(dir)) = (&self.ranks, &self.options.pieces_dir) else {
            return Ok(());
        };
        let (rank, ranks) = (view.rank(), view.size());
        let steps = self.state.steps;
        let path = dir.join(piece_file(steps, rank));
        let mut owned = self.fluid.clone();
        owned.resize(self.owned());
        // Before any I/O that may fail on one rank: a solver's state may combine values over
        // the ranks (`Solver::save_state`).
        let solver = self.solver.save_state();
        let written = std::fs::create_dir_all(path.parent().unwrap_or(dir))
            .map_err(|source| CheckpointError::Io {
                path: path.clone(),
                source: geosph_io::Error::Io {
                    path: path.clone(),
                    source,
                },
            })
            .and_then(|()| {
                self.checkpoint(ParticleState::save(&owned), solver)
                    .write(&path)
            });
        let [failed] = view.any([written.is_err()]);
        written?;
        if failed {
            return Err(RunError::Checkpoint(CheckpointError::Damaged {
                path,
                reason: "another rank could not write its piece of this checkpoint".into(),
            }));
        }
        if let Some(manifest_path) = self.checkpoint_path.as_ref().filter(|_| view.is_root()) {
            let nothing = ParticleState::save(&Particles::<D>::default());
            let solver = SolverState::new(self.solver.name(), 0);
            let mut manifest = self.checkpoint(nothing, solver);
            manifest.pieces = (0..ranks).map(|rank| piece_file(steps, rank)).collect();
            manifest.write(manifest_path)?;
            remove_stale_pieces(manifest_path, &manifest.pieces);
        }
        if let Some(distribution) = self.solver.distribution_mut() {
            distribution.set_up_next_step();
        }
        Ok(())
    }
}
