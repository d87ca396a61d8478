//! What a rank sends to the others: its halo, and the particles that changed owner.

use geosph_core::Vector;

use crate::partition::Partition;

/// The particles one rank sends to each rank: `send[s]` holds the indices, among the
/// sending rank's particles and ascending, of those that go to rank `s` (`send[rank]` of the
/// rank itself is empty).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExchangePlan {
    /// Indices to send, per destination rank.
    pub send: Vec<Vec<u32>>,
}

impl ExchangePlan {
    fn new(ranks: usize) -> Self {
        Self {
            send: vec![Vec::new(); ranks],
        }
    }

    /// Records sent in all.
    pub fn len(&self) -> usize {
        self.send.iter().map(Vec::len).sum()
    }

    /// Whether nothing is sent.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The halo `depth` cells deep that rank `rank` sends: every one of its particles at
/// `position` whose cell is at most `depth` cells (along each axis) from a cell of another
/// rank goes to that rank (to each such rank once). With cells at least one interaction
/// radius wide, a rank that receives the halos of depth 1 of all others sees every neighbour
/// of each particle it owns; with depth 2 also every neighbour of those neighbours (what a
/// pass needs that reads a value its neighbours summed over theirs, such as a wall pressure
/// or a density gradient).
///
/// # Panics
/// If a rank has more than `u32::MAX` particles.
pub fn halo_plan<const D: usize>(
    partition: &Partition<D>,
    rank: usize,
    position: &[Vector<D>],
    depth: u32,
) -> ExchangePlan {
    let mut plan = ExchangePlan::new(partition.ranks());
    let mut ranks = Vec::new();
    for (i, x) in position.iter().enumerate() {
        partition.halo_ranks(x, rank, depth, &mut ranks);
        for &destination in &ranks {
            plan.send[destination].push(index(i));
        }
    }
    plan
}

/// The particles of rank `rank` at `position` that another rank owns now, and which of its
/// particles it keeps (`keep[i]`): each leaving particle goes to its new owner only.
///
/// # Panics
/// If a rank has more than `u32::MAX` particles.
pub fn migration_plan<const D: usize>(
    partition: &Partition<D>,
    rank: usize,
    position: &[Vector<D>],
) -> (ExchangePlan, Vec<bool>) {
    let mut plan = ExchangePlan::new(partition.ranks());
    let keep = position
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let owner = partition.owner(x);
            if owner != rank {
                plan.send[owner].push(index(i));
            }
            owner == rank
        })
        .collect();
    (plan, keep)
}

fn index(i: usize) -> u32 {
    u32::try_from(i).expect("at most u32::MAX particles per rank")
}
