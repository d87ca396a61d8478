//! The scene file format (RON, read with serde).

use geosph_core::Real;
use geosph_fluid::{IncompressibleConfig, IncompressibleMethod, WcsphConfig};
use serde::{Deserialize, Serialize};

/// A simulation scene. Coordinates are lists of `dimension` numbers, in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A short name, used in output file names.
    pub name: String,
    /// 2 (plane) or 3.
    pub dimension: usize,
    /// Particle spacing dx in m.
    pub dx: Real,
    /// h/dx (default 1.3).
    #[serde(default = "default_smoothing_ratio")]
    pub smoothing_ratio: Real,
    /// Kernel name (default "wendland-c2"): cubic-spline, quintic-spline, wendland-c2,
    /// wendland-c4, wendland-c6, gaussian.
    #[serde(default = "default_kernel")]
    pub kernel: String,
    /// Gravity in m/s² (default (0, −9.81) or (0, 0, −9.81): the last axis points up).
    #[serde(default)]
    pub gravity: Option<Vec<Real>>,
    /// Simulated end time in s.
    pub end_time: Real,
    /// Output settings.
    #[serde(default)]
    pub output: OutputSpec,
    /// Domain box; default: the bounding box of all particles, enlarged by 3 support radii
    /// and, upwards, by three fluid heights.
    #[serde(default)]
    pub domain: Option<DomainSpec>,
    /// The fluid, if any; soil scenes may call this block `soil` (its density and blocks are
    /// the soil's, `hydrostatic` is ignored).
    #[serde(default, alias = "soil")]
    pub fluid: Option<FluidSpec>,
    /// Walls.
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    /// Rigid bodies moved by the fluid (default none).
    #[serde(default)]
    pub bodies: Vec<crate::body_spec::BodySpec>,
    /// The solver and its parameters.
    pub solver: SolverSpec,
    /// Limits of the blow-up checks.
    #[serde(default)]
    pub health: HealthSpec,
    /// The folder that relative file names (meshes) are read from, e.g. the scene file's
    /// folder (the apps set it so); `None`: the working folder. Not part of the file.
    #[serde(skip)]
    pub folder: Option<std::path::PathBuf>,
}

/// Limits of the runner's blow-up checks that a scene may change.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HealthSpec {
    /// Largest fraction of the particles, in [0, 1], that may leave the domain (they are
    /// removed from the run, counted and reported) before the run is stopped as a blow-up
    /// (default 0.01; 0 stops the run at the first particle that leaves).
    pub max_escaped_fraction: Real,
}

impl Default for HealthSpec {
    fn default() -> Self {
        Self {
            max_escaped_fraction: 0.01,
        }
    }
}

fn default_smoothing_ratio() -> Real {
    1.3
}

fn default_kernel() -> String {
    "wendland-c2".to_owned()
}

/// When and what to write.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// Simulated time between VTU frames in s (default 0.05).
    pub interval: Real,
    /// Simulated time between diagnostic samples in s (default 0.005).
    pub sample_interval: Real,
    /// Write VTU frames (default true).
    pub vtk: bool,
    /// Pressure probes, sampled with the diagnostics (default none): one column
    /// `p_<name>` (Pa) each in `diagnostics.csv`.
    pub probes: Vec<ProbeSpec>,
    /// Water-level gauges, sampled with the diagnostics (default none): one column
    /// `h_<name>` (m) each in `diagnostics.csv`, the height coordinate of the free surface
    /// at the gauge's horizontal position (an elevation, not a depth).
    pub heights: Vec<HeightSpec>,
    /// Loads of the fluid or soil on mesh walls, sampled with the diagnostics (default none): the
    /// columns `F_<name>_x`, `F_<name>_y` (`_z`) in N (2D: N per m of width) and the moment
    /// `M_<name>` (3D: `M_<name>_x`, `_y`, `_z`) in N m (2D: N m per m) each.
    pub loads: Vec<LoadSpec>,
    /// Free-surface meshes written with every frame (3D only; default none):
    /// `frames/<name>-surface_NNNNNN.vtp`, listed in `<name>-surface.pvd`.
    pub surface: Option<SurfaceSpec>,
}

/// How the free surface of the particles is drawn for viewing: the level set
/// ρ = `threshold` ρ₀ of their density smoothed over `support`, by marching cubes of edge
/// `cube` (`geosph_surface`, after Akinci et al. 2012). Lengths in units of dx.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SurfaceSpec {
    /// Compact support radius of the smoothing kernel in dx, 1.5 to 6 (default 2.5).
    pub support: Real,
    /// Edge of the marching cubes in dx, 0.1 to 2 (default 0.5).
    pub cube: Real,
    /// The level drawn as a fraction of the rest density, 0.05 to 0.95 (default 0.6).
    pub threshold: Real,
}

impl Default for SurfaceSpec {
    fn default() -> Self {
        Self {
            support: 2.5,
            cube: 0.5,
            threshold: 0.6,
        }
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            interval: 0.05,
            sample_interval: 0.005,
            vtk: true,
            probes: Vec::new(),
            heights: Vec::new(),
            loads: Vec::new(),
            surface: None,
        }
    }
}

/// A pressure probe: the fluid's pressure interpolated at a fixed point, as a pressure gauge
/// of an experiment reads it (Shepard-normalised kernel interpolation over the fluid
/// particles within the kernel's support; empty, NaN, when there are none).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Column name (letters, digits, '-', '_' or '.'), written as `p_<name>`.
    pub name: String,
    /// Where, in m (one coordinate per dimension).
    pub position: Vec<Real>,
}

/// A water-level gauge, as the wave gauges of an experiment read the free surface: the top of
/// the particles along a vertical line (the last axis: y in 2D, z in 3D), the same coordinate
/// the scene's positions use (`geosph_runner::HeightGauges`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightSpec {
    /// Column name (letters, digits, '-', '_' or '.'), written as `h_<name>`.
    pub name: String,
    /// Where, in m: the horizontal coordinates (x in 2D; x and y in 3D).
    pub position: Vec<Real>,
}

/// A load gauge: the force and moment the fluid's pressure exerts on a mesh wall,
/// F = −∮ p n dA and M = ∮ (x − x_c) × (−p n) dA over the wall's surface (n its normal into
/// the flow), p interpolated from the fluid at points dx/2 apart on the surface; for soil
/// F = ∮ σ n dA with the soil's stress σ (`geosph_sph::surface_load::stress_load`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Column name (letters, digits, '-', '_' or '.').
    pub name: String,
    /// The index in `walls` of a `Mesh` wall.
    pub wall: usize,
    /// The point x_c the moment is taken about (default: the surface's centroid).
    #[serde(default)]
    pub about: Option<Vec<Real>>,
}

/// An explicit domain box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSpec {
    /// Lower corner.
    pub min: Vec<Real>,
    /// Upper corner.
    pub max: Vec<Real>,
    /// Periodic axes (default none).
    #[serde(default)]
    pub periodic: Vec<bool>,
    /// How the neighbour search indexes the domain's cells: `Dense` (default: one entry per
    /// cell, the fastest when the particles fill the domain) or `Hashed` (the occupied cells
    /// only: for very large or sparse domains, e.g. a spray in a valley; the same results).
    #[serde(default)]
    pub cells: CellIndexSpec,
}

/// The scene's name of a [`geosph_sph::CellIndex`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CellIndexSpec {
    /// [`geosph_sph::CellIndex::Dense`].
    #[default]
    Dense,
    /// [`geosph_sph::CellIndex::Hashed`].
    Hashed,
}

impl CellIndexSpec {
    /// The search's index.
    pub fn index(self) -> geosph_sph::CellIndex {
        match self {
            Self::Dense => geosph_sph::CellIndex::Dense,
            Self::Hashed => geosph_sph::CellIndex::Hashed,
        }
    }
}

/// A region of space filled with particles on the lattice of spacing dx.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Region {
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: Vec<Real>,
        /// Upper corner.
        max: Vec<Real>,
    },
    /// A 2D polygon (counter-clockwise or clockwise), filled on the lattice aligned with the
    /// origin.
    Polygon {
        /// Vertices (x, y).
        vertices: Vec<(Real, Real)>,
    },
    /// The volume inside a closed surface mesh (`.stl` or `.obj`), filled on the lattice
    /// aligned with the origin. The mesh's z axis points up; a mesh point x becomes
    /// `scale` · x + `offset`. In a 2D scene the region is the mesh's section by the plane
    /// y = `section` (after scaling and offset): 2D (x, y) is mesh (x, `section`, z).
    Mesh {
        /// The mesh file, relative to the scene file's folder (or the working folder for a
        /// scene given as text).
        file: String,
        /// Scale factor of the mesh's coordinates (default 1; e.g. 0.001 for a mesh in mm).
        #[serde(default = "default_scale")]
        scale: Real,
        /// Offset added after scaling, one number per scene dimension (default zero).
        #[serde(default)]
        offset: Vec<Real>,
        /// 2D scenes: the mesh's y of the section plane (default 0).
        #[serde(default)]
        section: Real,
    },
}

fn default_scale() -> Real {
    1.0
}

/// The fluid of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSpec {
    /// Rest density ρ₀ in kg/m³ (default 1000).
    #[serde(default = "default_water_density")]
    pub density: Real,
    /// The regions the fluid fills.
    pub blocks: Vec<Region>,
    /// Start from the hydrostatic pressure of each block's own column (default true);
    /// otherwise from ρ = ρ₀.
    #[serde(default = "default_true")]
    pub hydrostatic: bool,
    /// Initial velocity field (default `Rest`).
    #[serde(default)]
    pub velocity: InitialVelocity,
    /// Random displacement of every particle from its lattice site, uniform in
    /// [−jitter, jitter]·dx per axis, in [0, 0.4] (default 0). Deterministic: the same scene
    /// always gives the same particles. For testing how a solver copes with disorder.
    #[serde(default)]
    pub jitter: Real,
    /// A gas only (an equation of state with internal energy): its initial pressure in Pa,
    /// which with `density` sets each particle's internal energy; the reference state
    /// (ρ₀, p₀) of the gas.
    #[serde(default)]
    pub pressure: Option<Real>,
    /// A gas only: blocks that start in another state than (`density`, `pressure`), e.g. the
    /// two sides of a shock tube. Their particles keep the lattice spacing, so a denser
    /// state has heavier particles (m = ρ dx^D).
    #[serde(default)]
    pub states: Vec<BlockState>,
}

/// The initial state of the gas in one block of the fluid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockState {
    /// The block, an index into `fluid.blocks` (its sites that an earlier block already
    /// holds belong to that one).
    pub block: usize,
    /// Density in kg/m³.
    pub density: Real,
    /// Pressure in Pa.
    pub pressure: Real,
}

/// The velocity the particles start with.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum InitialVelocity {
    /// At rest.
    #[default]
    Rest,
    /// The same velocity everywhere, one component per dimension (e.g. an impact).
    Uniform(Vec<Real>),
    /// Uniform expansion about `centre`: v = rate · (x − centre), in 1/s; a block pulled
    /// apart in every direction (tension).
    Stretch {
        /// Centre of the expansion.
        centre: Vec<Real>,
        /// Expansion rate in 1/s (negative: compression).
        rate: Real,
    },
    /// The 2D Taylor–Green vortex of wavelength L and speed U (Taylor & Green 1937):
    /// u = −U cos(2πx/L) sin(2πy/L), v = U sin(2πx/L) cos(2πy/L), with its pressure
    /// p = −ρ₀U²/4 (cos(4πx/L) + cos(4πy/L)) (lowest in the vortex centres). In a periodic box of side L without gravity it
    /// decays as e^(−8π²νt/L²) (kinetic energy e^(−16π²νt/L²)).
    TaylorGreen {
        /// Velocity amplitude U in m/s.
        speed: Real,
        /// Wavelength L in m (the side of the periodic box).
        wavelength: Real,
    },
}

fn default_water_density() -> Real {
    1000.0
}

fn default_true() -> bool {
    true
}

/// A wall made of dummy particles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum WallSpec {
    /// A tank whose inner space is the box `[min, max]`. It has no walls across a periodic
    /// axis of the domain (a slab periodic across y has a floor and two end walls); there it
    /// must span the domain's period, a whole number of dx.
    Tank {
        /// Lower inner corner.
        min: Vec<Real>,
        /// Upper inner corner.
        max: Vec<Real>,
        /// Layers of dummy particles (default 3; at least support radius / dx).
        #[serde(default = "default_layers")]
        layers: usize,
        /// No lid (default true).
        #[serde(default = "default_true")]
        open_top: bool,
    },
    /// A 2D wall along a polyline, e.g. a slope or a ramp.
    Polyline {
        /// Vertices (x, y), at least two.
        points: Vec<(Real, Real)>,
        /// Layers of dummy particles (default 3).
        #[serde(default = "default_layers")]
        layers: usize,
        /// The side of the line the flow is on, looking from the first point (default Left).
        #[serde(default)]
        flow_side: geosph_boundary::generate::FlowSide,
        /// Prescribed velocity (u, v) of the wall's surface in m/s (default at rest): the
        /// particles stay in place and the flow sees a moving belt, e.g. the plate of a
        /// Couette flow. It should lie along the wall.
        #[serde(default)]
        velocity: (Real, Real),
    },
    /// Dummy particles behind a surface mesh (`.stl` or `.obj`, open or closed) whose
    /// triangles face the flow: a terrain with normals up, an obstacle with outward normals,
    /// a container with inward ones. The lattice sites (aligned with the origin) behind the
    /// surface by less than `layers` dx, convex and concave corners included. Placement as
    /// in [`Region::Mesh`]; in 2D the walls of the section plane y = `section`. Along a
    /// periodic axis of the domain the sites are folded into one period (a plane drawn wider
    /// than a periodic slab is a wall across all of it).
    Mesh {
        /// The mesh file, relative to the scene file's folder (or the working folder for a
        /// scene given as text).
        file: String,
        /// Scale factor of the mesh's coordinates (default 1).
        #[serde(default = "default_scale")]
        scale: Real,
        /// Offset added after scaling, one number per scene dimension (default zero).
        #[serde(default)]
        offset: Vec<Real>,
        /// 2D scenes: the mesh's y of the section plane (default 0).
        #[serde(default)]
        section: Real,
        /// Thickness in lattice spacings (default 3; at least support radius / dx).
        #[serde(default = "default_layers")]
        layers: usize,
    },
}

fn default_layers() -> usize {
    3
}

/// The solver of a scene, by name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SolverSpec {
    /// Weakly compressible SPH.
    Wcsph(#[serde(default)] WcsphConfig),
    /// Elastoplastic soil SPH (`geosph-soil`).
    Soil(#[serde(default)] geosph_soil::SoilConfig),
    /// Predictive–corrective incompressible SPH (Solenthaler & Pajarola 2009).
    Pcisph(#[serde(default)] IncompressibleConfig),
    /// Implicit incompressible SPH (Ihmsen et al. 2014).
    Iisph(#[serde(default)] IncompressibleConfig),
    /// Divergence-free SPH (Bender & Koschier 2017).
    Dfsph(#[serde(default)] IncompressibleConfig),
}

impl SolverSpec {
    /// The solver's name as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            SolverSpec::Wcsph(_) => "wcsph",
            SolverSpec::Soil(_) => "soil",
            SolverSpec::Pcisph(_) => "pcisph",
            SolverSpec::Iisph(_) => "iisph",
            SolverSpec::Dfsph(_) => "dfsph",
        }
    }

    /// How the solver's particles start, as its configuration decides.
    pub fn particle_start(&self) -> geosph_sph::ParticleStart {
        match self {
            SolverSpec::Wcsph(config) => config.particle_start(),
            SolverSpec::Soil(config) => config.particle_start(),
            SolverSpec::Pcisph(config) | SolverSpec::Iisph(config) | SolverSpec::Dfsph(config) => {
                config.particle_start()
            }
        }
    }

    /// Checks the solver's configuration (fields relative to the solver block).
    pub fn validate(&self) -> Result<(), geosph_sph::ConfigError> {
        match self {
            SolverSpec::Wcsph(config) => config.validate(),
            SolverSpec::Soil(config) => config.validate(),
            SolverSpec::Pcisph(config) => config.validate_for(IncompressibleMethod::Pcisph),
            SolverSpec::Iisph(config) => config.validate_for(IncompressibleMethod::Iisph),
            SolverSpec::Dfsph(config) => config.validate_for(IncompressibleMethod::Dfsph),
        }
    }

    /// The names [`SolverSpec::from_name`] accepts.
    pub const NAMES: [&'static str; 4] = ["wcsph", "pcisph", "iisph", "dfsph"];

    /// The solver `name` with its default parameters, or `None` for an unknown name.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "wcsph" => SolverSpec::Wcsph(Default::default()),
            "pcisph" => SolverSpec::Pcisph(Default::default()),
            "iisph" => SolverSpec::Iisph(Default::default()),
            "dfsph" => SolverSpec::Dfsph(Default::default()),
            _ => return None,
        })
    }
}

impl Scene {
    /// Writes the scene as pretty RON.
    pub fn to_ron(&self) -> String {
        ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .to_string_pretty(self, ron::ser::PrettyConfig::default())
            .expect("a scene always serialises")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_scenes_parse_and_validate() {
        for text in [
            include_str!("../../../data/scenes/dam-break-2d.ron"),
            include_str!("../../../data/scenes/dam-break-3d.ron"),
            include_str!("../../../data/scenes/axisymmetric-collapse.ron"),
            include_str!("../../../data/scenes/granular-collapse-3d.ron"),
        ] {
            let scene = Scene::from_ron(text).unwrap();
            scene.validate().unwrap();
            let again = Scene::from_ron(&scene.to_ron()).unwrap();
            assert_eq!(again, scene);
        }
    }

    #[test]
    fn polyline_walls_build_behind_the_line() {
        let scene = Scene::from_ron(
            "Scene(name: \"ramp\", dimension: 2, dx: 0.05, end_time: 1.0,
                fluid: (blocks: [Box(min: [0.0, 0.5], max: [0.5, 1.0])]),
                walls: [Polyline(points: [(0.0, 0.0), (2.0, 0.0)])],
                solver: Wcsph(()))",
        )
        .unwrap();
        let setup = crate::build::<2>(&scene).unwrap();
        // 2 m / 0.05 m = 40 particles along, 3 layers below y = 0.
        assert_eq!(setup.walls.len(), 40 * 3);
        assert!(setup.walls.position.iter().all(|x| x[1] < 0.0));
    }

    #[test]
    fn misspelt_field_names_line_and_column() {
        let text = "Scene(\n  name: \"x\",\n  dimension: 2,\n  dxx: 0.1,\n)";
        let message = Scene::from_ron(text).unwrap_err().to_string();
        assert!(
            message.contains("line 4, column 3") && message.contains("dxx"),
            "{message}"
        );
    }
}
