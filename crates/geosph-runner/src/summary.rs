//! What a run did: [`Summary`], printed by the apps at the end of a run.

use geosph_core::Real;
use geosph_scene::BlockReport;
use geosph_sph::StageReport;

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Solver name.
    pub solver: &'static str,
    /// What the particles are ([`geosph_sph::Solver::material`]): "fluid" or "soil".
    pub material: &'static str,
    /// Whether the solver iterates a pressure solve ([`geosph_sph::Solver::iterates`]).
    pub iterative: bool,
    /// 2 or 3.
    pub dimension: usize,
    /// Fluid particles.
    pub fluid_particles: usize,
    /// Wall particles.
    pub wall_particles: usize,
    /// How the scene's blocks were filled; the summary lists the meshes (filled against the
    /// mesh's own volume) and the blocks an earlier one overlapped.
    pub blocks: Vec<BlockReport>,
    /// Time steps taken.
    pub steps: usize,
    /// Simulated time reached, s.
    pub simulated_time: Real,
    /// Wall-clock time of the stepping loop (output included), s.
    pub wall_time: Real,
    /// Fluid particle-steps per wall-clock second.
    pub particle_steps_per_second: Real,
    /// Largest relative density error seen at any step.
    pub max_density_error: Real,
    /// Mean relative density error over all steps.
    pub mean_density_error: Real,
    /// Mean pressure iterations per step (1 for WCSPH).
    pub mean_iterations: Real,
    /// Mean divergence-solve iterations per step (DFSPH; 0 otherwise).
    pub mean_divergence_iterations: Real,
    /// Bytes per fluid particle held by its fields.
    pub bytes_per_particle: usize,
    /// VTU frames written.
    pub frames: usize,
    /// Particles that left the domain and were removed from the run (included in neither
    /// `fluid_particles` nor the frames).
    pub escaped: usize,
    /// Their share of the initial fluid mass.
    pub escaped_mass_fraction: Real,
    /// Simulated time at which the first of them was removed, s.
    pub first_escape: Option<Real>,
    /// Particle-steps that ended behind a wall's surface and were put back on it
    /// ([`geosph_sph::keep_out_of_walls`]); 0 where the walls held by pressure.
    pub wall_contacts: usize,
    /// Simulated time of the first of them, s.
    pub first_wall_contact: Option<Real>,
    /// The stage the solver ran before t = 0 ([`geosph_sph::Solver::initial_stage`]; the soil's
    /// geostatic stage), also after a restart from a checkpoint written after it.
    pub stage: Option<StageReport>,
    /// Each rank's share of a distributed run (empty for one process).
    pub ranks: Vec<RankLoad>,
}

/// One rank's share of a distributed run, for the summary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RankLoad {
    /// Particles the rank owns at the end.
    pub particles: usize,
    /// Particles in its halo at the end.
    pub halo: usize,
    /// Set-ups (migration and new halo) it took part in.
    pub setups: usize,
    /// Wall-clock seconds it spent in exchanges and reductions (waiting for the others
    /// included).
    pub exchange_seconds: Real,
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "scene              {} ({}D, {})",
            self.scene, self.dimension, self.solver
        )?;
        let material = self.material;
        writeln!(
            f,
            "particles          {} {material} + {} wall ({} bytes of fields per {material} particle)",
            self.fluid_particles, self.wall_particles, self.bytes_per_particle
        )?;
        let unit = if self.dimension == 2 { "m²" } else { "m³" };
        for (index, block) in self.blocks.iter().enumerate() {
            let mesh = block.name.starts_with("mesh");
            if mesh || block.overlapped > 0 {
                write!(
                    f,
                    "  block {index}          {}: {} particles",
                    block.name, block.particles
                )?;
                if block.overlapped > 0 {
                    write!(f, " (+{} sites an earlier block filled)", block.overlapped)?;
                }
                writeln!(
                    f,
                    ", lattice sites {:.4e} {unit} for its {:.4e} ({:+.2} %)",
                    block.filled,
                    block.volume,
                    100.0 * (block.filled / block.volume - 1.0)
                )?;
            }
        }
        writeln!(
            f,
            "steps              {} to t = {:.4} s (mean dt = {:.3e} s)",
            self.steps,
            self.simulated_time,
            self.simulated_time / self.steps.max(1) as Real
        )?;
        writeln!(
            f,
            "wall time          {:.2} s, {:.3} M particle-steps/s",
            self.wall_time,
            self.particle_steps_per_second * 1e-6
        )?;
        writeln!(
            f,
            "density error      mean {:.3} %, max {:.3} %",
            100.0 * self.mean_density_error,
            100.0 * self.max_density_error
        )?;
        // The explicit solvers take one pass per step; only the pressure solvers iterate.
        if self.iterative {
            writeln!(
                f,
                "iterations         {:.1} per step (divergence solve {:.1})",
                self.mean_iterations, self.mean_divergence_iterations
            )?;
        }
        if let Some(first) = self.first_escape {
            writeln!(
                f,
                "escaped            {} particles ({:.3} % of the mass), first at t = {first:.3} s",
                self.escaped,
                100.0 * self.escaped_mass_fraction
            )?;
        }
        if let Some(first) = self.first_wall_contact {
            writeln!(
                f,
                "wall contacts      {} particle-steps put back on a wall's surface, first at t = {first:.3} s \
                 (the walls' pressure alone did not stop them: docs/fluid.md, \"Walls that hold\")",
                self.wall_contacts
            )?;
        }
        for (rank, load) in self.ranks.iter().enumerate() {
            writeln!(
                f,
                "rank {rank:<13} {} particles + {} halo, {} set-ups, {:.2} s in exchanges",
                load.particles, load.halo, load.setups, load.exchange_seconds
            )?;
        }
        if let Some(stage) = &self.stage {
            write!(f, "\n{stage}")?;
        }
        Ok(())
    }
}
