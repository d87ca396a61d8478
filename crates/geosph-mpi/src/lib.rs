//! MPI transport of geosph's domain decomposition ([`geosph_partition`], issue 26): the
//! exchanges of particle records between ranks that a halo plan or a migration plan asks
//! for, and the global reductions of a distributed run.
//!
//! The transport is MPI through rsmpi (the `mpi` crate), behind the Cargo feature `mpi` so
//! that the default build needs no MPI library: `cargo build -p geosph-mpi --features mpi`
//! needs an MPI implementation and libclang (Debian: `apt-get install mpich libmpich-dev
//! libclang-dev`). Ranks run rayon threads inside; MPI is initialised with serialised
//! threading and called by one thread at a time (the run loop's, which may be a rayon worker).
//!
//! `geosph-mpi-check` (the crate's binary, `mpiexec -n 4 geosph-mpi-check`) checks the
//! exchanges against a brute-force search on up to 45 ranks; the crate's test runs it on 1,
//! 2 and 4 ranks.

pub mod launch;
#[cfg(feature = "mpi")]
mod ranks;

#[cfg(feature = "mpi")]
pub use ranks::{MpiError, Ranks};
