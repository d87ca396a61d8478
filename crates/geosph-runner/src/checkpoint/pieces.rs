//! The checkpoint of a distributed run: one piece per rank, each a checkpoint of the particles
//! that rank owned and their solver state, and a manifest (`checkpoint.bin`) that lists them.
//! A restart on any number of ranks, or on one process, reads them all and puts them together
//! by particle id.

use std::path::Path;

use geosph_scene::Scene;
use geosph_sph::StateArrays;

use super::{Checkpoint, CheckpointError, ParticleState};

/// The folder of the pieces, beside the manifest.
pub const PIECES_FOLDER: &str = "checkpoint-pieces";

/// The file of rank `rank`'s piece of the checkpoint after `steps` steps, relative to the
/// manifest's folder: a new name at each checkpoint, so that a run killed while writing one
/// leaves the previous manifest's pieces intact.
pub(crate) fn piece_file(steps: u64, rank: usize) -> String {
    format!("{PIECES_FOLDER}/step{steps:09}-rank{rank:04}.bin")
}

impl Checkpoint {
    /// The checkpoint of every particle from this manifest (read from `path`) and its pieces:
    /// the particles and the solver's per-particle arrays in id order, the rest of the
    /// solver's state from the first piece.
    pub(super) fn merge_pieces<const D: usize>(
        self,
        path: &Path,
        scene: &Scene,
    ) -> Result<Self, CheckpointError> {
        let folder = path.parent().unwrap_or(Path::new(""));
        let mut pieces = Vec::with_capacity(self.pieces.len());
        for file in &self.pieces {
            let piece_path = folder.join(file);
            let piece = Self::read_file::<D>(&piece_path, scene)?;
            // Time and step, not the whole progress: its stage report may hold NaN (a
            // measure over no particles), which is never equal to itself.
            let (at, manifest_at) = (&piece.progress, &self.progress);
            let same_step =
                at.steps == manifest_at.steps && at.time.to_bits() == manifest_at.time.to_bits();
            if !same_step || !piece.pieces.is_empty() {
                return Err(CheckpointError::Mismatch {
                    path: piece_path,
                    reason: format!(
                        "not a piece of `{}` (written at another step)",
                        path.display()
                    ),
                });
            }
            pieces.push(piece);
        }
        let mismatch = |reason: String| CheckpointError::Mismatch {
            path: path.to_path_buf(),
            reason,
        };
        let ids: Vec<u32> = pieces
            .iter()
            .flat_map(|piece| piece.particles.id.iter().copied())
            .collect();
        let mut order: Vec<usize> = (0..ids.len()).collect();
        order.sort_unstable_by_key(|&i| ids[i]);
        if order.windows(2).any(|pair| ids[pair[0]] == ids[pair[1]]) {
            return Err(mismatch("a particle is in two pieces".into()));
        }
        let merge = |arrays: &dyn Fn(&Checkpoint) -> &StateArrays| {
            let parts: Vec<(usize, &StateArrays)> = pieces
                .iter()
                .map(|piece| (piece.particles.id.len(), arrays(piece)))
                .collect();
            StateArrays::merge(&parts, &order).map_err(|error| mismatch(error.0))
        };
        let particles = ParticleState {
            id: order.iter().map(|&i| ids[i]).collect(),
            arrays: merge(&|piece| &piece.particles.arrays)?,
        };
        let per_particle = merge(&|piece| &piece.solver.per_particle)?;
        let Some(first) = pieces.into_iter().next() else {
            return Err(mismatch("lists no piece".into()));
        };
        let mut solver = first.solver;
        solver.per_particle = per_particle;
        Ok(Self {
            particles,
            solver,
            pieces: Vec::new(),
            ..self
        })
    }
}

/// Removes the files of the pieces folder beside `manifest` that `pieces` (the manifest's
/// list) does not name: the pieces of earlier checkpoints. Best effort: a file that cannot be
/// removed stays.
pub(crate) fn remove_stale_pieces(manifest: &Path, pieces: &[String]) {
    let folder = manifest.parent().unwrap_or(Path::new(""));
    let Ok(entries) = std::fs::read_dir(folder.join(PIECES_FOLDER)) else {
        return;
    };
    for entry in entries.flatten() {
        let name = format!("{PIECES_FOLDER}/{}", entry.file_name().to_string_lossy());
        if !pieces.contains(&name) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}
