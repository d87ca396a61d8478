//! The run loop on one rank of a distributed run ([`RunOptions::transport`]): the solver steps
//! this rank's particles (its own, then its halo). The samples are reduced over the ranks
//! from each rank's [`Share`] (an observer not written for ranks gathers every particle
//! there); the health check scans each rank's own particles every step and combines the
//! scans; the frames are written in pieces (`frames.rs`). What needs *every* particle (a free
//! surface, the summary, a blow-up's or an interrupt's files) gathers them from the ranks, in
//! id order, at the moment it is needed.

use std::path::PathBuf;
use std::sync::Arc;

use geosph_core::{Particles, Real};
use geosph_scene::Scene;
use geosph_sph::{Solver, SolverError, Transport};

use crate::health::Scan;
use crate::options::RunOptions;
use crate::share::Share;
use crate::summary::RankLoad;

/// This rank's view of a distributed run.
pub(super) struct RankView<const D: usize> {
    transport: Arc<dyn Transport + Sync>,
    /// Every particle of the run, in id order, as of the last [`RankView::gather`].
    pub(super) whole: Particles<D>,
}

/// Makes `solver` one rank's share of the run when `options` has a transport of more than
/// one rank (after the solver's stage before t = 0, which every rank runs in full, or the
/// restart, which every rank reads in full); `None` otherwise.
pub(super) fn distribute<const D: usize>(
    options: &RunOptions,
    solver: &mut dyn Solver<D>,
    fluid: &mut Particles<D>,
) -> Result<Option<RankView<D>>, SolverError> {
    let Some(transport) = options
        .transport
        .as_ref()
        .map(|ranks| &ranks.0)
        .filter(|t| t.size() > 1)
    else {
        return Ok(None);
    };
    solver.distribute(fluid, Box::new(Arc::clone(transport)))?;
    Ok(Some(RankView {
        transport: Arc::clone(transport),
        whole: fluid.clone(),
    }))
}

impl<const D: usize> RankView<D> {
    /// Whether this is rank 0, the one that writes the output and reports.
    pub(super) fn is_root(&self) -> bool {
        self.transport.rank() == 0
    }

    /// This rank.
    pub(super) fn rank(&self) -> usize {
        self.transport.rank()
    }

    /// Ranks in all.
    pub(super) fn size(&self) -> usize {
        self.transport.size()
    }

    /// The folder every rank writes its pieces of the frames into, when VTK output is on.
    pub(super) fn frames_folder(&self, options: &RunOptions, scene: &Scene) -> Option<PathBuf> {
        let vtk = options.vtk.unwrap_or(scene.output.vtk);
        let dir = options.pieces_dir.as_ref().filter(|_| vtk)?;
        Some(dir.join("frames"))
    }

    /// Gathers every rank's owned particles of `local` (the first `owned`) into
    /// [`RankView::whole`], in id order (collective).
    pub(super) fn gather(&mut self, local: &Particles<D>, owned: usize) {
        crate::share::gather(&*self.transport, local, owned, &mut self.whole);
    }

    /// This rank's share of `local`, its first `owned` particles, for a sample.
    pub(super) fn share<'a>(&'a mut self, local: &'a Particles<D>, owned: usize) -> Share<'a, D> {
        Share::of_rank(local, owned, &*self.transport, &mut self.whole)
    }

    /// For each flag, whether some rank raised it (collective).
    pub(super) fn any<const N: usize>(&self, flags: [bool; N]) -> [bool; N] {
        let mut values = flags.map(|flag| Real::from(u8::from(flag)));
        self.transport.max_each(&mut values);
        values.map(|value| value > 0.0)
    }

    /// Every rank's particles, halo and exchange time (collective).
    pub(super) fn loads(&self, solver: &dyn Solver<D>) -> Vec<RankLoad> {
        let Some(distribution) = solver.distribution() else {
            return Vec::new();
        };
        let counts = distribution.counts();
        let mine = [
            distribution.owned() as Real,
            counts.halo as Real,
            counts.setups as Real,
            counts.seconds,
        ];
        self.transport
            .gather_each(&mine)
            .chunks_exact(4)
            .map(|load| RankLoad {
                particles: load[0] as usize,
                halo: load[1] as usize,
                setups: load[2] as usize,
                exchange_seconds: load[3],
            })
            .collect()
    }
}

impl<const D: usize> super::RunLoop<'_, D> {
    /// The particles this rank owns: the first of its set (all of them in one process).
    pub(super) fn owned(&self) -> usize {
        self.solver
            .distribution()
            .map_or(self.fluid.len(), |distribution| distribution.owned())
    }

    /// Gathers every particle into the rank view (collective; nothing in one process).
    pub(super) fn gather(&mut self) {
        let owned = self.owned();
        if let Some(view) = &mut self.ranks {
            view.gather(&self.fluid, owned);
        }
    }

    /// Makes the particles of the loop every particle of the run (collective; nothing in one
    /// process): what a run that ends (finished, interrupted, blown up) reports and writes.
    pub(super) fn take_whole(&mut self) {
        self.gather();
        if let Some(view) = &self.ranks {
            self.fluid.clone_from(&view.whole);
        }
    }

    /// The owned particles of a distributed run once the first step has shared them out
    /// (`None` before, when every rank holds every particle, and in one process).
    pub(super) fn owned_after_split(&self) -> Option<usize> {
        self.solver
            .distribution()
            .filter(|distribution| distribution.counts().setups > 0)
            .map(|distribution| distribution.owned())
    }

    /// The particles that left the domain in the step that ended at `time`, removed from
    /// every rank together ([`Escapes::after_step_on_rank`](crate::escape::Escapes), one
    /// collective a step; nothing before the first step has shared the particles out). When
    /// too many have left, the failed and last good states of every particle (the last good
    /// one's owned particles were the first `last_good_owned`) become the loop's, for the
    /// report, as after a failed health check.
    pub(super) fn escapes_on_ranks(
        &mut self,
        time: Real,
        last_good_owned: Option<usize>,
    ) -> Result<crate::escape::Removal, SolverError> {
        let owned = self.owned_after_split();
        let (Some(view), Some(owned)) = (&mut self.ranks, owned) else {
            return Ok(crate::escape::Removal::Nothing);
        };
        let transport = Arc::clone(&view.transport);
        let removal = self.escapes.after_step_on_rank(
            &mut self.fluid,
            owned,
            self.solver.as_mut(),
            &mut self.limits,
            &mut self.state,
            time,
            &*transport,
            &mut |local| {
                view.gather(local, owned);
                view.whole.clone()
            },
        )?;
        if let (crate::escape::Removal::TooMany(_), Some(owned)) = (&removal, last_good_owned) {
            view.gather(&self.last_good, owned);
            self.last_good.clone_from(&view.whole);
        }
        Ok(removal)
    }

    /// The health check after a step (`health::check`). In a distributed run each rank scans
    /// its own particles and the scans are combined over the ranks (one collective a step),
    /// so the energy budget, a sum over every particle, is checked at every step as in one
    /// process; only when the combined scan is [`health::suspect`](crate::health::suspect)
    /// is every particle gathered and checked as one process would, with the same outcome on
    /// every rank. On trouble the failed and last good states of every particle (the last
    /// good one's owned particles were the first `last_good_owned`; `None`: it held every
    /// particle) become the loop's, for the report.
    pub(super) fn health(
        &mut self,
        report: &geosph_sph::StepReport,
        last_good_owned: Option<usize>,
    ) -> Option<crate::health::Diagnosis> {
        let owned = self.owned();
        let (solver, limits) = (self.solver.as_ref(), &self.limits);
        let Some(view) = &mut self.ranks else {
            return crate::health::check(report, &self.fluid, solver, limits);
        };
        let scan = Scan::of_first(&self.fluid, owned, limits).over_ranks(&*view.transport);
        if !crate::health::suspect(report, &scan, limits) {
            return None;
        }
        view.gather(&self.fluid, owned);
        let diagnosis = crate::health::check(report, &view.whole, solver, limits);
        if diagnosis.is_some() {
            self.fluid.clone_from(&view.whole);
            if let Some(owned) = last_good_owned {
                view.gather(&self.last_good, owned);
                self.last_good.clone_from(&view.whole);
            }
        }
        diagnosis
    }
}
