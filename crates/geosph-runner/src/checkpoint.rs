//! Checkpoints: the complete state of a run in one file, to continue it bitwise.
//!
//! A checkpoint holds the particles (every field that exists), the solver's warm-start
//! [`SolverState`], the loop's position (time, step, event counters, frames and CSV rows
//! written, running statistics) and the observer's samples. The file is
//!
//! `GEOSPHCP` | format version (u32) | body length (u64) | CRC-32 of the body (u32) | body,
//!
//! integers little-endian, the body in [postcard](https://docs.rs/postcard) (a compact,
//! stable serde format; reals keep their bits). It is written atomically (temporary file,
//! `sync_all`, rename), so a killed run leaves the previous checkpoint or the new one, never a
//! mixture. Reading checks the header, the length and the checksum, then the scene.
//!
//! A distributed run writes one piece per rank and a manifest that lists them (`pieces`).

use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::{Duration, Instant};

use geosph_core::{Particles, Real, SoilFields};
use geosph_scene::Scene;
use geosph_sph::{SolverState, StateArrays, StateError};
use serde::{Deserialize, Serialize};

mod pieces;
pub(crate) use pieces::{piece_file, remove_stale_pieces};

/// Name of the checkpoint file in the output folder.
pub const FILE_NAME: &str = "checkpoint.bin";

/// Version of the file layout; a checkpoint of another version is refused. Version 2 added
/// the particles that left the domain to [`Progress`], version 3 the report of the solver's
/// stage before t = 0, version 4 the wall contacts, version 5 the state of moving walls (rigid
/// bodies) in the solver's state, version 6 the pieces of a distributed run and the solver's
/// per-particle arrays apart from its others.
pub const FORMAT_VERSION: u32 = 6;

const MAGIC: &[u8; 8] = b"GEOSPHCP";
const HEADER_LEN: usize = 8 + 4 + 8 + 4;

/// When to write checkpoints: `0.5` is every 0.5 s of simulated time, `30s`, `10min` or `2h`
/// every so much wall-clock time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CheckpointEvery {
    /// Every this many seconds of simulated time.
    Simulated(Real),
    /// Every this much wall-clock time.
    Wall(Duration),
}

impl FromStr for CheckpointEvery {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let number = |digits: &str| -> Result<Real, String> {
            match digits.trim().parse::<Real>() {
                Ok(value) if value.is_finite() && value > 0.0 => Ok(value),
                _ => Err(format!(
                    "`{text}` is not a positive interval: give simulated seconds (`0.5`) or wall time (`30s`, `10min`, `2h`)"
                )),
            }
        };
        for (unit, seconds) in [("min", 60.0), ("h", 3600.0), ("s", 1.0)] {
            if let Some(digits) = text.strip_suffix(unit) {
                return Ok(Self::Wall(Duration::from_secs_f64(
                    number(digits)? * seconds,
                )));
            }
        }
        Ok(Self::Simulated(number(text)?))
    }
}

/// Where the time loop stood when the checkpoint was written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    /// Simulated time, s.
    pub time: Real,
    /// Steps taken.
    pub steps: u64,
    /// Output events reached (the next is at `outputs` × interval).
    pub outputs: u64,
    /// Sample events reached.
    pub samples: u64,
    /// VTU frames written (and listed in the `.pvd`).
    pub frames: u64,
    /// Rows of `diagnostics.csv` written, header excluded.
    pub rows: u64,
    /// Largest density error so far.
    pub max_density_error: Real,
    /// Sum of the steps' mean density errors.
    pub density_error_sum: Real,
    /// Sum of the steps' pressure iterations.
    pub iterations: u64,
    /// Sum of the steps' divergence-solve iterations.
    pub divergence_iterations: u64,
    /// Particles that left the domain and were removed from the run.
    pub escaped: u64,
    /// Their total mass, kg (kg/m in 2D).
    pub escaped_mass: Real,
    /// Simulated time at which the first of them was removed, s.
    pub first_escape: Option<Real>,
    /// Particle-steps that ended behind a wall's surface and were put back on it
    /// ([`geosph_sph::keep_out_of_walls`]).
    pub wall_contacts: u64,
    /// Simulated time of the first of them, s.
    pub first_wall_contact: Option<Real>,
    /// What the solver's stage before t = 0 reached ([`geosph_sph::Solver::initial_stage`]).
    pub stage: Option<geosph_sph::StageReport>,
}

/// The particles, every field that exists, as named arrays.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParticleState {
    /// Persistent ids, in the current (sorted) order.
    pub id: Vec<u32>,
    /// The real-valued fields.
    pub arrays: StateArrays,
}

impl ParticleState {
    /// Saves every existing field of `particles`.
    pub fn save<const D: usize>(particles: &Particles<D>) -> Self {
        let mut arrays = StateArrays::default();
        arrays.push_matrices("position", &particles.position);
        arrays.push_matrices("velocity", &particles.velocity);
        arrays.push("mass", &particles.mass);
        arrays.push("density", &particles.density);
        if let Some(pressure) = &particles.pressure {
            arrays.push("pressure", pressure);
        }
        if let Some(energy) = &particles.energy {
            arrays.push("energy", energy);
        }
        if let Some(soil) = &particles.soil {
            arrays.push_matrices("stress", &soil.stress);
            arrays.push_matrices("strain", &soil.strain);
            arrays.push("plastic_strain", &soil.plastic_strain);
            arrays.push_matrices("displacement", &soil.displacement);
        }
        if let Some(correction) = &particles.gradient_correction {
            arrays.push_matrices("gradient_correction", correction);
        }
        Self {
            id: particles.id.clone(),
            arrays,
        }
    }

    /// The particles saved, with the optional fields `like` has (the freshly built scene's
    /// particles, so a checkpoint of another setup is refused rather than half-used), of which
    /// `escaped` had left the domain before the checkpoint.
    pub fn restore<const D: usize>(
        mut self,
        like: &Particles<D>,
        escaped: u64,
    ) -> Result<Particles<D>, StateError> {
        let n = self.id.len();
        if n as u64 + escaped != like.len() as u64 {
            return Err(StateError(format!(
                "{n} particles saved and {escaped} escaped, the scene makes {}",
                like.len()
            )));
        }
        let a = &mut self.arrays;
        let pressure = match like.pressure {
            Some(_) => Some(a.take_values("pressure", n)?),
            None => None,
        };
        let energy = match like.energy {
            Some(_) => Some(a.take_values("energy", n)?),
            None => None,
        };
        let soil = match like.soil {
            Some(_) => Some(SoilFields {
                stress: a.take_matrices("stress", n)?,
                strain: a.take_matrices("strain", n)?,
                plastic_strain: a.take_values("plastic_strain", n)?,
                displacement: a.take_matrices("displacement", n)?,
            }),
            None => None,
        };
        let gradient_correction = match like.gradient_correction {
            Some(_) => Some(a.take_matrices("gradient_correction", n)?),
            None => None,
        };
        Ok(Particles {
            position: a.take_matrices("position", n)?,
            velocity: a.take_matrices("velocity", n)?,
            mass: a.take_values("mass", n)?,
            density: a.take_values("density", n)?,
            id: self.id,
            pressure,
            energy,
            soil,
            gradient_correction,
        })
    }
}

/// The complete state of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Scene name.
    pub scene: String,
    /// [`scene_hash`] of the scene, with every override applied.
    pub scene_hash: u64,
    /// 2 or 3.
    pub dimension: u32,
    /// Where the loop stood.
    pub progress: Progress,
    /// The particles.
    pub particles: ParticleState,
    /// The solver's warm-start state.
    pub solver: SolverState,
    /// The observer's accumulated state ([`crate::Observer::save_state`]).
    pub observer: Vec<Real>,
    /// A distributed run's checkpoint is a manifest (this, without particles) and one piece
    /// per rank (a checkpoint of the particles that rank owned and their solver state), whose
    /// files, relative to the manifest's folder, this lists in rank order; empty for one
    /// process's checkpoint, which holds every particle ([`Checkpoint::read`] puts the pieces
    /// together).
    pub pieces: Vec<String>,
}

/// Why a checkpoint cannot be used; one line, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file cannot be read or written.
    #[error("checkpoint `{}`: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The failure.
        source: geosph_io::Error,
    },
    /// The file is damaged, cut short or not a checkpoint of this format.
    #[error("checkpoint `{}` is unusable: {reason}", path.display())]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The checkpoint belongs to another scene (or the same scene with other settings).
    #[error("checkpoint `{}` does not belong to this run: {reason}", path.display())]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// What differs.
        reason: String,
    },
}

/// A 64-bit FNV-1a hash of the scene's full description (every setting, overrides included),
/// stable across runs and platforms; the folder relative files are read from is left out, so
/// a restart may name the scene file by another path.
pub fn scene_hash(scene: &Scene) -> u64 {
    let scene = Scene {
        folder: None,
        ..scene.clone()
    };
    format!("{scene:?}")
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325, |hash: u64, byte| {
            (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
        })
}

impl Checkpoint {
    /// Writes the checkpoint to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), CheckpointError> {
        let body = postcard::to_allocvec(self).map_err(|error| CheckpointError::Damaged {
            path: path.to_path_buf(),
            reason: format!("cannot encode: {error}"),
        })?;
        geosph_io::write_atomically(path, |w| {
            w.write_all(MAGIC)?;
            w.write_all(&FORMAT_VERSION.to_le_bytes())?;
            w.write_all(&(body.len() as u64).to_le_bytes())?;
            w.write_all(&crc32fast::hash(&body).to_le_bytes())?;
            w.write_all(&body)
        })
        .map_err(|source| CheckpointError::Io {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Reads the checkpoint at `path` and checks that it was written for `scene` in `D`
    /// dimensions; a distributed run's manifest is read with its pieces, put together as one
    /// process's checkpoint of every particle.
    pub fn read<const D: usize>(path: &Path, scene: &Scene) -> Result<Self, CheckpointError> {
        let checkpoint = Self::read_file::<D>(path, scene)?;
        match checkpoint.pieces.is_empty() {
            true => Ok(checkpoint),
            false => checkpoint.merge_pieces::<D>(path, scene),
        }
    }

    /// Reads the one file `path` (a whole checkpoint, a manifest or a piece) and checks it.
    fn read_file<const D: usize>(path: &Path, scene: &Scene) -> Result<Self, CheckpointError> {
        let damaged = |reason: String| CheckpointError::Damaged {
            path: path.to_path_buf(),
            reason,
        };
        let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
            path: path.to_path_buf(),
            source: geosph_io::Error::Io {
                path: path.to_path_buf(),
                source,
            },
        })?;
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err(damaged("not a geosph checkpoint".into()));
        }
        if bytes.len() < HEADER_LEN {
            return Err(damaged(format!(
                "truncated: {} bytes, shorter than the {HEADER_LEN}-byte header",
                bytes.len()
            )));
        }
        let word = |range: std::ops::Range<usize>| {
            bytes[range]
                .iter()
                .rev()
                .fold(0u64, |value, &byte| (value << 8) | u64::from(byte))
        };
        let version = word(8..12);
        if version != u64::from(FORMAT_VERSION) {
            return Err(damaged(format!(
                "format version {version}, this program reads version {FORMAT_VERSION}"
            )));
        }
        let (length, checksum) = (word(12..20), word(20..24));
        let body = &bytes[HEADER_LEN..];
        if body.len() as u64 != length {
            return Err(damaged(format!(
                "truncated or padded: the header announces {length} bytes of state, the file holds {}",
                body.len()
            )));
        }
        if u64::from(crc32fast::hash(body)) != checksum {
            return Err(damaged("corrupt: the checksum does not match".into()));
        }
        let checkpoint: Self = postcard::from_bytes(body)
            .map_err(|error| damaged(format!("corrupt: cannot decode: {error}")))?;
        let mismatch = |reason: String| CheckpointError::Mismatch {
            path: path.to_path_buf(),
            reason,
        };
        if checkpoint.scene != scene.name {
            return Err(mismatch(format!(
                "written for scene `{}`, this run is scene `{}`",
                checkpoint.scene, scene.name
            )));
        }
        if checkpoint.dimension as usize != D {
            return Err(mismatch(format!(
                "written in {}D, this run is {D}D",
                checkpoint.dimension
            )));
        }
        if checkpoint.scene_hash != scene_hash(scene) {
            return Err(mismatch(format!(
                "scene `{}` was run with other settings (restart with the same scene file and the same overrides, e.g. --dx, --end-time, --solver)",
                scene.name
            )));
        }
        Ok(checkpoint)
    }
}

/// When the next checkpoint is due. Checkpoints do not shorten steps (the run is the same
/// with or without them): one is written after the first step that reaches its time.
pub(crate) enum CheckpointClock {
    Never,
    Simulated { interval: Real, next: Real },
    Wall { interval: Duration, last: Instant },
}

impl CheckpointClock {
    pub(crate) fn new(every: Option<CheckpointEvery>, time: Real) -> Self {
        match every {
            None => Self::Never,
            Some(CheckpointEvery::Simulated(interval)) => Self::Simulated {
                interval,
                next: ((time / interval).floor() + 1.0) * interval,
            },
            Some(CheckpointEvery::Wall(interval)) => Self::Wall {
                interval,
                last: Instant::now(),
            },
        }
    }

    /// Whether a checkpoint is due at `time`; if so, the clock moves on to the next one.
    pub(crate) fn due(&mut self, time: Real) -> bool {
        match self {
            Self::Never => false,
            Self::Simulated { interval, next } => {
                let due = time >= *next;
                if due {
                    *next = ((time / *interval).floor() + 1.0) * *interval;
                }
                due
            }
            Self::Wall { interval, last } => {
                let due = last.elapsed() >= *interval;
                if due {
                    *last = Instant::now();
                }
                due
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_are_simulated_or_wall_time() {
        assert_eq!("0.5".parse(), Ok(CheckpointEvery::Simulated(0.5)));
        assert_eq!(
            "30s".parse(),
            Ok(CheckpointEvery::Wall(Duration::from_secs(30)))
        );
        assert_eq!(
            "10min".parse(),
            Ok(CheckpointEvery::Wall(Duration::from_secs(600)))
        );
        assert_eq!(
            "2h".parse(),
            Ok(CheckpointEvery::Wall(Duration::from_secs(7200)))
        );
        for bad in ["", "-1", "0", "ten", "5 days", "nan"] {
            assert!(bad.parse::<CheckpointEvery>().is_err(), "{bad}");
        }
    }
}
