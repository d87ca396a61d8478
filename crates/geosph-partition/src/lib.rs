//! Domain decomposition for distributed SPH (issue 26): which rank owns which particle, and
//! which particles each rank must send to the others.
//!
//! The domain is cut into cells at least one interaction radius wide (the support radius
//! plus the Verlet skin), and each rank owns a contiguous run of cells along the Z-order
//! (Morton) curve, the runs chosen so that every rank has about the same work: the
//! space-filling-curve partition of Warren & Salmon (1993, A parallel hashed oct-tree N-body
//! algorithm, Supercomputing '93), who cut the Morton key range as here. Because a cell is at least one radius wide, every neighbour of a particle lies in
//! the 3^D cells around its own, so a rank needs, besides its own particles, only the
//! particles of the other ranks' cells that touch its cells: its *halo*
//! ([`Partition::halo_ranks`], [`halo_plan`]). A particle that moves into another rank's cell
//! changes owner ([`migration_plan`]).
//!
//! Nothing here communicates: the plans say what to send where, and a [`Transport`] (MPI, in
//! `geosph-mpi`) moves the records. So the decomposition is tested in one process, every rank
//! simulated; [`ThreadRanks`] is a transport whose ranks are threads of one process, for tests
//! of code that calls the collectives (the runner's samples reduced over the ranks).

mod partition;
mod plan;
#[cfg(test)]
mod tests;
mod threads;
mod transport;

pub use partition::{Cells, Partition, PartitionError, imbalance};
pub use plan::{ExchangePlan, halo_plan, migration_plan};
pub use threads::ThreadRanks;
pub use transport::{OneRank, Received, Transport};
