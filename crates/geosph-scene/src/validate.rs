//! Validation of a scene before any work is done.

use geosph_core::Real;
use geosph_kernels::KernelKind;

use crate::checks::{
    boxed, column_name, fail, in_range, mesh_placement, plain_name, point, positive,
};
pub use crate::error::SceneError;
use crate::format::{FluidSpec, InitialVelocity, Region, Scene, SolverSpec, WallSpec};

/// Most particles (fluid and wall, estimated from the regions before any is made) a scene may
/// ask for: about 10 GB of particle fields and neighbour lists. A larger count almost always
/// means a dx typed in the wrong unit.
pub const MAX_PARTICLES: Real = 2.0e7;

/// Most lattice cells a tank generator may visit (its outer box, interior included).
pub const MAX_TANK_CELLS: Real = 1.0e9;

/// Most VTU frames a run may write (`end_time / output.interval`).
pub const MAX_FRAMES: Real = 1.0e5;

/// Most diagnostic samples a run may take (`end_time / output.sample_interval`).
pub const MAX_SAMPLES: Real = 1.0e7;

pub use crate::checks::MAX_NAME_LENGTH;

fn finite_pairs(field: &str, values: &[(Real, Real)]) -> Result<(), SceneError> {
    if let Some((index, &(x, y))) = values
        .iter()
        .enumerate()
        .find(|(_, (x, y))| !(x.is_finite() && y.is_finite()))
    {
        return Err(fail(
            format!("{field}[{index}]"),
            format!("coordinates must be finite, got ({x}, {y})"),
        ));
    }
    Ok(())
}

/// Lattice points of spacing `dx` in the box `[min, max]` (an upper bound, as a real so that
/// absurd sizes do not overflow).
fn lattice_points(min: &[Real], max: &[Real], dx: Real, pad: Real) -> Real {
    min.iter()
        .zip(max)
        .map(|(a, b)| ((b - a) / dx).ceil() + 2.0 * pad)
        .product()
}

impl Scene {
    /// Probe names usable as CSV columns and unique; positions in the scene's dimension; a
    /// fluid that carries pressure.
    fn validate_probes(&self, dimension: usize) -> Result<(), SceneError> {
        let probes = &self.output.probes;
        if !probes.is_empty() && matches!(self.solver, SolverSpec::Soil(_)) {
            return Err(fail(
                "output.probes",
                "pressure probes need a fluid solver (wcsph, pcisph, iisph or dfsph); \
                 soil particles carry stress, not pressure",
            ));
        }
        for (k, probe) in probes.iter().enumerate() {
            let earlier = probes[..k].iter().map(|p| p.name.as_str());
            column_name(&format!("output.probes[{k}]"), &probe.name, earlier)?;
            point(
                &format!("output.probes[{k}].position"),
                &probe.position,
                dimension,
            )?;
        }
        Ok(())
    }

    /// Water-level gauges: names as for probes; the horizontal coordinates, finite.
    fn validate_heights(&self, dimension: usize) -> Result<(), SceneError> {
        let heights = &self.output.heights;
        for (k, gauge) in heights.iter().enumerate() {
            let field = format!("output.heights[{k}]");
            let earlier = heights[..k].iter().map(|h| h.name.as_str());
            column_name(&field, &gauge.name, earlier)?;
            let horizontal = dimension - 1;
            let position = &gauge.position;
            if position.len() != horizontal || position.iter().any(|v| !v.is_finite()) {
                return Err(fail(
                    format!("{field}.position"),
                    format!(
                        "needs {horizontal} finite coordinate(s), the horizontal ones (x in 2D; \
                         x and y in 3D), got {position:?}"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Load gauges: names as for probes, each on a `Mesh` wall.
    fn validate_loads(&self, dimension: usize) -> Result<(), SceneError> {
        let loads = &self.output.loads;
        for (k, load) in loads.iter().enumerate() {
            let field = format!("output.loads[{k}]");
            let earlier = loads[..k].iter().map(|l| l.name.as_str());
            column_name(&field, &load.name, earlier)?;
            if !matches!(self.walls.get(load.wall), Some(WallSpec::Mesh { .. })) {
                return Err(fail(
                    format!("{field}.wall"),
                    format!(
                        "must be the index of a Mesh wall in `walls` (0 to {}), got {}",
                        self.walls.len().saturating_sub(1),
                        load.wall
                    ),
                ));
            }
            if let Some(about) = &load.about {
                point(&format!("{field}.about"), about, dimension)?;
            }
        }
        Ok(())
    }

    /// Checks every value against its allowed range; the first violation is returned with the
    /// field's path, the allowed range and the value.
    pub fn validate(&self) -> Result<(), SceneError> {
        let dimension = self.dimension;
        if !plain_name(&self.name) || self.name.starts_with('.') {
            return Err(fail(
                "name",
                format!(
                    "must be 1 to {MAX_NAME_LENGTH} letters, digits, '-', '_' or '.' (not first), \
                     as it names output files; got {:?}",
                    self.name
                ),
            ));
        }
        if dimension != 2 && dimension != 3 {
            return Err(fail(
                "dimension",
                format!("must be 2 or 3, got {dimension}"),
            ));
        }
        positive("dx", self.dx)?;
        in_range("smoothing_ratio", self.smoothing_ratio, 1.0, 2.5)?;
        let kernel: KernelKind = self
            .kernel
            .parse()
            .map_err(|error: geosph_kernels::UnknownKernel| fail("kernel", error.to_string()))?;
        if let Some(gravity) = &self.gravity {
            point("gravity", gravity, dimension)?;
        }
        positive("end_time", self.end_time)?;
        positive("output.interval", self.output.interval)?;
        positive("output.sample_interval", self.output.sample_interval)?;
        for (field, interval, most) in [
            ("output.interval", self.output.interval, MAX_FRAMES),
            (
                "output.sample_interval",
                self.output.sample_interval,
                MAX_SAMPLES,
            ),
        ] {
            if self.end_time / interval > most {
                return Err(fail(
                    field,
                    format!(
                        "must be at least end_time / {most:.0} = {:e} s (at most {most:.0} events), got {interval}",
                        self.end_time / most
                    ),
                ));
            }
        }
        self.validate_probes(dimension)?;
        self.validate_heights(dimension)?;
        self.validate_loads(dimension)?;
        crate::body_spec::validate(
            &self.bodies,
            dimension,
            matches!(self.solver, SolverSpec::Soil(_)),
            (self.smoothing_ratio * kernel.support_factor() - 1e-9).ceil() as usize,
        )?;
        let periodic = self
            .domain
            .as_ref()
            .is_some_and(|domain| domain.periodic.iter().any(|&p| p));
        if periodic && !self.bodies.is_empty() {
            return Err(fail(
                "bodies",
                "rigid bodies are not wrapped across periodic axes: use a domain without \
                 `periodic` axes",
            ));
        }
        if let Some(surface) = &self.output.surface {
            if dimension != 3 {
                return Err(fail(
                    "output.surface",
                    "free-surface meshes are drawn for 3D scenes; a 2D scene's particles \
                     show its free surface in ParaView as they are",
                ));
            }
            if !self.output.vtk {
                return Err(fail(
                    "output.surface",
                    "free surfaces are written with the frames: set `vtk: true` or leave the \
                     surface out",
                ));
            }
            in_range("output.surface.support", surface.support, 1.5, 6.0)?;
            in_range("output.surface.cube", surface.cube, 0.1, 2.0)?;
            in_range("output.surface.threshold", surface.threshold, 0.05, 0.95)?;
        }
        if let Some(domain) = &self.domain {
            boxed("domain", &domain.min, &domain.max, dimension)?;
            if !domain.periodic.is_empty() && domain.periodic.len() != dimension {
                return Err(fail(
                    "domain.periodic",
                    format!(
                        "needs {dimension} entries or none, got {}",
                        domain.periodic.len()
                    ),
                ));
            }
        }
        in_range(
            "health.max_escaped_fraction",
            self.health.max_escaped_fraction,
            0.0,
            1.0,
        )?;
        match &self.fluid {
            Some(fluid) => {
                self.validate_fluid(fluid)?;
                crate::gas::validate(self, fluid)?;
                crate::phases::validate(self, fluid)?;
            }
            None => return Err(fail("fluid", "the scene has no fluid: nothing to simulate")),
        }
        let support_cells = self.smoothing_ratio * kernel.support_factor();
        let needed = (support_cells - 1e-9).ceil() as usize;
        for (index, wall) in self.walls.iter().enumerate() {
            let field = format!("walls[{index}]");
            let layers = match wall {
                WallSpec::Tank {
                    min, max, layers, ..
                } => {
                    boxed(&field, min, max, dimension)?;
                    *layers
                }
                WallSpec::Polyline {
                    points,
                    layers,
                    velocity,
                    ..
                } => {
                    if dimension != 2 {
                        return Err(fail(field, "polyline walls exist only in 2D scenes"));
                    }
                    if points.len() < 2 {
                        return Err(fail(
                            format!("{field}.points"),
                            format!("needs at least 2 points, got {}", points.len()),
                        ));
                    }
                    finite_pairs(&format!("{field}.points"), points)?;
                    finite_pairs(&format!("{field}.velocity"), &[*velocity])?;
                    if let Some(k) = points.windows(2).position(|pair| pair[0] == pair[1]) {
                        return Err(fail(
                            format!("{field}.points[{}]", k + 1),
                            format!(
                                "repeats the point before it, {:?}: consecutive points must differ",
                                points[k]
                            ),
                        ));
                    }
                    *layers
                }
                WallSpec::Mesh {
                    file,
                    scale,
                    offset,
                    section,
                    layers,
                } => {
                    mesh_placement(&field, file, *scale, offset, *section, dimension)?;
                    *layers
                }
            };
            if layers < needed || layers > 10 {
                return Err(fail(
                    format!("{field}.layers"),
                    format!(
                        "must lie in [{needed}, 10] (the kernel support is {support_cells:.2} dx), got {layers}"
                    ),
                ));
            }
        }
        let particles = self.estimated_particles();
        if particles > MAX_PARTICLES {
            return Err(fail(
                "dx",
                format!(
                    "{} m would make about {particles:.3e} particles, more than {MAX_PARTICLES:.0e}: \
                     increase dx (is it in metres?) or shrink the regions",
                    self.dx
                ),
            ));
        }
        for (index, wall) in self.walls.iter().enumerate() {
            if let WallSpec::Tank {
                min, max, layers, ..
            } = wall
            {
                let cells = lattice_points(min, max, self.dx, *layers as Real);
                if cells > MAX_TANK_CELLS {
                    return Err(fail(
                        format!("walls[{index}]"),
                        format!(
                            "the tank spans {cells:.3e} lattice cells at dx = {}, more than {MAX_TANK_CELLS:.0e}: \
                             increase dx or shrink the tank",
                            self.dx
                        ),
                    ));
                }
            }
        }
        self.solver
            .validate()
            .map_err(|error| fail(format!("solver.{}", error.field), error.message))
    }

    /// An upper estimate of the particles (fluid and wall) the scene makes, from the size of
    /// its regions and dx, without making them. Meaningful for scenes whose coordinates and dx
    /// are finite and positive; may be infinite for absurd ones.
    pub fn estimated_particles(&self) -> Real {
        let dx = self.dx;
        let mut count = 0.0;
        if let Some(fluid) = &self.fluid {
            for block in &fluid.blocks {
                count += match block {
                    Region::Box { min, max } => lattice_points(min, max, dx, 0.0),
                    Region::Polygon { vertices } => {
                        let (xs, ys): (Vec<Real>, Vec<Real>) = vertices.iter().copied().unzip();
                        let extent = |v: &[Real]| {
                            let low = v.iter().copied().fold(Real::INFINITY, Real::min);
                            let high = v.iter().copied().fold(Real::NEG_INFINITY, Real::max);
                            if v.is_empty() { 0.0 } else { high - low }
                        };
                        ((extent(&xs) / dx).ceil() + 1.0) * ((extent(&ys) / dx).ceil() + 1.0)
                    }
                    // Known once the file is read; `build` bounds it then.
                    Region::Mesh { .. } => 0.0,
                };
            }
        }
        for wall in &self.walls {
            count += match wall {
                WallSpec::Tank {
                    min, max, layers, ..
                } => {
                    lattice_points(min, max, dx, *layers as Real)
                        - lattice_points(min, max, dx, 0.0)
                }
                WallSpec::Polyline { points, layers, .. } => {
                    let length: Real = points
                        .windows(2)
                        .map(|pair| (pair[1].0 - pair[0].0).hypot(pair[1].1 - pair[0].1))
                        .sum();
                    (length / dx + points.len() as Real) * *layers as Real
                }
                // Known once the file is read; `build` bounds it then.
                WallSpec::Mesh { .. } => 0.0,
            };
        }
        count
    }

    fn validate_fluid(&self, fluid: &FluidSpec) -> Result<(), SceneError> {
        positive("fluid.density", fluid.density)?;
        if fluid.blocks.is_empty() {
            return Err(fail("fluid.blocks", "needs at least one region, got none"));
        }
        for (index, block) in fluid.blocks.iter().enumerate() {
            let field = format!("fluid.blocks[{index}]");
            match block {
                Region::Box { min, max } => boxed(&field, min, max, self.dimension)?,
                Region::Polygon { vertices } => {
                    if self.dimension != 2 {
                        return Err(fail(field, "polygons exist only in 2D scenes"));
                    }
                    if vertices.len() < 3 {
                        return Err(fail(
                            format!("{field}.vertices"),
                            format!("needs at least 3 vertices, got {}", vertices.len()),
                        ));
                    }
                    finite_pairs(&format!("{field}.vertices"), vertices)?;
                }
                Region::Mesh {
                    file,
                    scale,
                    offset,
                    section,
                } => mesh_placement(&field, file, *scale, offset, *section, self.dimension)?,
            }
        }
        in_range("fluid.jitter", fluid.jitter, 0.0, 0.4)?;
        match &fluid.velocity {
            InitialVelocity::Rest => {}
            InitialVelocity::Uniform(velocity) => {
                point("fluid.velocity.Uniform", velocity, self.dimension)?
            }
            InitialVelocity::Stretch { centre, rate } => {
                point("fluid.velocity.Stretch.centre", centre, self.dimension)?;
                if !rate.is_finite() {
                    return Err(fail(
                        "fluid.velocity.Stretch.rate",
                        format!("must be finite, got {rate}"),
                    ));
                }
            }
            InitialVelocity::TaylorGreen { speed, wavelength } => {
                if self.dimension != 2 {
                    return Err(fail(
                        "fluid.velocity",
                        "the Taylor–Green vortex exists only in 2D scenes",
                    ));
                }
                positive("fluid.velocity.TaylorGreen.speed", *speed)?;
                positive("fluid.velocity.TaylorGreen.wavelength", *wavelength)?;
            }
        }
        Ok(())
    }
}
