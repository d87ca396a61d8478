//! What a sample sees of the particles: [`Share`], this rank's own particles with the
//! collectives that combine partial results over the ranks (every particle, and no
//! collective, in one process).

use geosph_core::{Particles, Real, Tensor3, Vector};
use geosph_sph::Transport;

/// This rank's share of the particles at a sample, and how a result over them becomes the
/// run's.
///
/// In one process the share is every particle and the combining methods change nothing, so
/// a sample is what it would be computed over the whole run directly (bitwise). On one rank of
/// a distributed run the share is the particles the rank owns (its halo left out, so that no
/// particle counts twice):
///
/// - [`Share::sum_each`] adds the ranks' partial sums in rank order (the same on every rank;
///   within round-off of one process, which sums in its own order),
/// - [`Share::max_each`] is exact,
/// - [`Share::gather`] concatenates short lists (the particles near a gauge line), which the
///   caller sorts,
/// - [`Share::whole`] gathers every particle, in id order, once per sample however many
///   callers ask: what an observer that was not written for ranks needs (its memory is the
///   whole run's on every rank).
///
/// Every method that combines is collective: every rank must make the same calls in the same
/// order, whatever its particles.
pub struct Share<'a, const D: usize> {
    local: &'a Particles<D>,
    owned: usize,
    ranks: Option<Ranks<'a, D>>,
}

/// The ranks behind a distributed share, and where [`Share::whole`] gathers into.
struct Ranks<'a, const D: usize> {
    transport: &'a dyn Transport,
    whole: &'a mut Particles<D>,
    gathered: bool,
}

impl<'a, const D: usize> Share<'a, D> {
    /// Every particle of a run in one process.
    pub fn whole_run(fluid: &'a Particles<D>) -> Self {
        Self {
            local: fluid,
            owned: fluid.len(),
            ranks: None,
        }
    }

    /// The first `owned` particles of `local`, one rank's share of a run over `transport`;
    /// [`Share::whole`] gathers into `whole`.
    pub(crate) fn of_rank(
        local: &'a Particles<D>,
        owned: usize,
        transport: &'a dyn Transport,
        whole: &'a mut Particles<D>,
    ) -> Self {
        Self {
            local,
            owned,
            ranks: Some(Ranks {
                transport,
                whole,
                gathered: false,
            }),
        }
    }

    /// Whether the share is one rank's of several.
    pub fn is_distributed(&self) -> bool {
        self.ranks.is_some()
    }

    /// Positions of the share's particles, m.
    pub fn position(&self) -> &[Vector<D>] {
        &self.local.position[..self.owned]
    }

    /// Velocities, m/s.
    pub fn velocity(&self) -> &[Vector<D>] {
        &self.local.velocity[..self.owned]
    }

    /// Masses, kg (2D: kg/m).
    pub fn mass(&self) -> &[Real] {
        &self.local.mass[..self.owned]
    }

    /// Densities, kg/m³.
    pub fn density(&self) -> &[Real] {
        &self.local.density[..self.owned]
    }

    /// Pressures, Pa, when the particles carry them.
    pub fn pressure(&self) -> Option<&[Real]> {
        self.local.pressure.as_deref().map(|p| &p[..self.owned])
    }

    /// Soil stresses σ (Pa, tension positive), when the particles are soil.
    pub fn stress(&self) -> Option<&[Tensor3]> {
        let soil = self.local.soil.as_ref()?;
        Some(&soil.stress[..self.owned])
    }

    /// Adds each of `values` over the ranks, in rank order, in place (nothing in one process).
    pub fn sum_each(&self, values: &mut [Real]) {
        if let Some(ranks) = &self.ranks {
            ranks.transport.sum_each(values);
        }
    }

    /// The largest of each of `values` over the ranks, in place (exact).
    pub fn max_each(&self, values: &mut [Real]) {
        if let Some(ranks) = &self.ranks {
            ranks.transport.max_each(values);
        }
    }

    /// Every rank's `values` (any number on each), concatenated in rank order: `values`
    /// itself in one process.
    pub fn gather(&self, values: &[Real]) -> Vec<Real> {
        match &self.ranks {
            Some(ranks) => ranks.transport.all_gather(values).values,
            None => values.to_vec(),
        }
    }

    /// Every particle of the run, in id order on several ranks (gathered at the first call of
    /// a sample); in one process the particles as they are.
    pub fn whole(&mut self) -> &Particles<D> {
        match &mut self.ranks {
            None => self.local,
            Some(ranks) => {
                if !ranks.gathered {
                    gather(ranks.transport, self.local, self.owned, ranks.whole);
                    ranks.gathered = true;
                }
                ranks.whole
            }
        }
    }
}

/// Gathers every rank's first `owned` particles of `local` into `whole`, in id order
/// (collective).
pub(crate) fn gather<const D: usize>(
    transport: &dyn Transport,
    local: &Particles<D>,
    owned: usize,
    whole: &mut Particles<D>,
) {
    let width = local.record_width();
    let mut mine = Vec::with_capacity(owned * width);
    for i in 0..owned {
        local.pack(i, &mut mine);
    }
    let gathered = transport.all_gather(&mine).values;
    let mut records: Vec<&[Real]> = gathered.chunks_exact(width).collect();
    // The id follows position, velocity, mass and density.
    records.sort_unstable_by(|a, b| a[2 * D + 2].total_cmp(&b[2 * D + 2]));
    whole.resize(records.len());
    for (k, record) in records.into_iter().enumerate() {
        whole.unpack(k, record);
    }
}

#[cfg(test)]
mod tests;
