//! The result of a run of [`crate::run`] and its printed summary.

use geosph_core::Real;
use geosph_runner::Summary;

use crate::{
    AspectRatioComparison, Column, ExperimentComparison, GRAIN_THICKNESS, Sample, TOE_THICKNESS,
};

/// The result of a run.
#[derive(Clone, Debug)]
pub struct Report {
    /// The runner's summary (with the geostatic stage's report, if the scene had one).
    pub summary: Summary,
    /// The initial column.
    pub column: Column,
    /// A 3D slab in plane strain ([`Column::plane_strain`]): the largest displacement across
    /// the runout direction during the run, max |u_y| in m (zero in exact plane strain).
    pub out_of_plane: Option<Real>,
    /// Front, wall height and kinetic energy at every sample time.
    pub samples: Vec<Sample>,
    /// The final sample.
    pub last: Sample,
    /// Largest kinetic energy of the run.
    pub peak_kinetic_energy: Real,
    /// The deposit against the experiment of Bui et al. (2008), when the scene is its set-up
    /// ([`crate::bui2008::is_experiment`]).
    pub experiment: Option<ExperimentComparison>,
    /// The deposit against the aspect-ratio laws of Nguyen et al. (2015), when the soil is the
    /// aluminium bars ([`crate::bui2008::is_aluminium_bars`]).
    pub aspect_ratio: Option<AspectRatioComparison>,
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "column             L = {:.3} m, H = {:.3} m, dx = {} m",
            self.column.length, self.column.height, self.column.spacing
        )?;
        writeln!(
            f,
            "final runout       {:.4} m from the wall (L_f/L = {:.3}; deposit toe, {} H thick), height at the wall {:.4} m (H_f/H = {:.3})",
            self.last.runout,
            self.last.runout / self.column.length,
            TOE_THICKNESS,
            self.last.height_at_wall,
            self.last.height_at_wall / self.column.height
        )?;
        writeln!(
            f,
            "farthest particles {:.4} m from the wall (the thin leading layer; grows as dx shrinks)",
            self.last.front
        )?;
        if self.aspect_ratio.is_some() {
            writeln!(
                f,
                "grain toe          {:.4} m from the wall (where the deposit is one bar, {} m, or one particle layer thick)",
                self.last.grain_toe, GRAIN_THICKNESS
            )?;
        }
        write!(
            f,
            "kinetic energy     peak {:.3e} J, final {:.3e} J (ratio {:.1e})",
            self.peak_kinetic_energy,
            self.last.kinetic_energy,
            self.last.kinetic_energy / self.peak_kinetic_energy.max(Real::MIN_POSITIVE)
        )?;
        let (peak, at) = self
            .samples
            .iter()
            .map(|s| (s.stress_noise, s.time))
            .fold((0.0, 0.0), |best, s| if s.0 > best.0 { s } else { best });
        write!(
            f,
            "\nstress noise       peak {peak:.3} at t = {at:.3} s, final {:.3} (|sigma - MLS fit|/|sigma|)",
            self.last.stress_noise
        )?;
        if let Some(u) = self.out_of_plane {
            write!(
                f,
                "\nout of plane       max |u_y| = {u:.2e} m ({:.1e} dx; 0 in plane strain)",
                u / self.column.spacing
            )?;
        }
        if let Some(experiment) = &self.experiment {
            write!(f, "\n{experiment}")?;
        }
        if let Some(comparison) = &self.aspect_ratio {
            write!(f, "\n{comparison}")?;
        }
        Ok(())
    }
}
