//! The reusable buffers of the neighbour queries ([`crate::CellGrid::neighbour_list`]).

use std::sync::Mutex;

/// Scratch buffers for [`CellGrid::neighbour_list`], one per chunk of a wave of queries, kept
/// between calls so that steady-state queries do not allocate. Taken out of the mutex for the
/// duration of a call (a concurrent call on the same grid simply allocates its own).
#[derive(Debug, Default)]
pub(crate) struct QueryScratch(Mutex<Vec<ChunkBuffer>>);

/// One chunk's neighbour indices: the first `len` entries of `slots`. The slots are only
/// ever grown, never cleared, so that appending a run of candidates needs no zeroing (a
/// `memset` per run cost about 2 % of a DFSPH dam break).
#[derive(Debug, Default)]
pub(crate) struct ChunkBuffer {
    pub(crate) slots: Vec<u32>,
    pub(crate) len: usize,
}

impl ChunkBuffer {
    /// The indices written so far.
    pub(crate) fn filled(&self) -> &[u32] {
        &self.slots[..self.len]
    }
}

impl Clone for QueryScratch {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl QueryScratch {
    pub(crate) fn take(&self) -> Vec<ChunkBuffer> {
        self.0
            .lock()
            .map(|mut buffers| std::mem::take(&mut *buffers))
            .unwrap_or_default()
    }

    pub(crate) fn put_back(&self, buffers: Vec<ChunkBuffer>) {
        if let Ok(mut slot) = self.0.lock() {
            *slot = buffers;
        }
    }
}
