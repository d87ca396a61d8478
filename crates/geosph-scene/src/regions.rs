//! The fluid's regions filled on the lattice as one union: boxes, polygons and the volumes
//! of closed meshes, each lattice site filled once.

use std::path::Path;

use geosph_boundary::generate;
use geosph_core::{Real, Vector};
use geosph_geometry::{Section, Solid, SurfaceMesh};

use crate::error::SceneError;
use crate::format::{Region, Scene};
use crate::initial::vector;
use crate::validate::MAX_PARTICLES;

/// Reads the mesh `file` (relative to `folder`) and places it: x ↦ `scale` · x + `offset`,
/// the offset of a 2D scene being (x, z) of the mesh.
pub(crate) fn read_mesh<const D: usize>(
    file: &str,
    scale: Real,
    offset: &[Real],
    folder: Option<&Path>,
) -> Result<SurfaceMesh, String> {
    let path = folder.map_or_else(|| Path::new(file).to_owned(), |f| f.join(file));
    let offset = match offset {
        [] => Vector::<3>::zeros(),
        [x, z] if D == 2 => Vector::<3>::new(*x, 0.0, *z),
        [x, y, z] => Vector::<3>::new(*x, *y, *z),
        _ => unreachable!("validated"),
    };
    Ok(SurfaceMesh::read(&path)
        .map_err(|error| error.to_string())?
        .transformed(scale, &offset))
}

/// An error if the lattice sites of `mesh`'s bounding box, grown by `margin` on every side,
/// are more than a scene may hold (in 2D those of the x–z plane).
pub(crate) fn check_size<const D: usize>(
    mesh: &SurfaceMesh,
    dx: Real,
    margin: Real,
) -> Result<(), String> {
    let (lo, hi) = mesh.bounds();
    let axes = if D == 2 {
        [0, 2].as_slice()
    } else {
        [0, 1, 2].as_slice()
    };
    let sites: Real = axes
        .iter()
        .map(|&k| ((hi[k] - lo[k] + 2.0 * margin) / dx).ceil() + 1.0)
        .product();
    if sites > MAX_PARTICLES {
        return Err(format!(
            "the mesh `{}` spans {sites:.3e} lattice sites at dx = {dx}, more than \
             {MAX_PARTICLES:.0e}: increase dx, or check `scale` (a mesh in mm?)",
            mesh.name
        ));
    }
    Ok(())
}

/// How one fluid block was filled, for the run's summary.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockReport {
    /// What the block is, e.g. `mesh data/meshes/sphere.stl` or `box`.
    pub name: String,
    /// Its particles (the sites an earlier block had filled not counted).
    pub particles: usize,
    /// Lattice sites inside it that an earlier block had already filled.
    pub overlapped: usize,
    /// The volume of the lattice sites inside it, (particles + overlapped) · dx^D (area in
    /// 2D): what to compare with `volume`.
    pub filled: Real,
    /// The region's own volume (area in 2D): the mesh's by the divergence theorem, the box's
    /// or polygon's exactly.
    pub volume: Real,
}

/// A region with its mesh read and checked.
enum Shape<const D: usize> {
    Box(Vector<D>, Vector<D>),
    Polygon(Vec<Vector<2>>),
    Solid(Box<Solid>),
    /// A solid's section by the plane of a 2D scene.
    Section(Box<Solid>, Section),
}

impl<const D: usize> Shape<D> {
    fn new(
        region: &Region,
        folder: Option<&Path>,
        dx: Real,
        field: &str,
    ) -> Result<Self, SceneError> {
        Ok(match region {
            Region::Box { min, max } => Self::Box(vector::<D>(min), vector::<D>(max)),
            Region::Polygon { vertices } => Self::Polygon(
                vertices
                    .iter()
                    .map(|&(x, y)| Vector::<2>::new(x, y))
                    .collect(),
            ),
            Region::Mesh {
                file,
                scale,
                offset,
                section,
            } => {
                let fail = |message: String| SceneError::Field {
                    field: field.to_owned(),
                    message,
                };
                let mesh = read_mesh::<D>(file, *scale, offset, folder).map_err(fail)?;
                let solid = Box::new(Solid::new(mesh).map_err(|error| {
                    fail(format!(
                        "{error} (a fluid volume needs a closed surface; walls may be open)"
                    ))
                })?);
                check_size::<D>(solid.mesh(), dx, 0.0).map_err(fail)?;
                if D == 2 {
                    Self::Section(solid, Section::at_y(*section))
                } else {
                    Self::Solid(solid)
                }
            }
        })
    }

    fn name(&self) -> String {
        match self {
            Self::Box(..) => "box".into(),
            Self::Polygon(_) => "polygon".into(),
            Self::Solid(solid) => format!("mesh {}", solid.mesh().name),
            Self::Section(solid, section) => format!(
                "mesh {} (section y = {})",
                solid.mesh().name,
                section.point[1]
            ),
        }
    }

    fn volume(&self) -> Real {
        match self {
            Self::Box(min, max) => (max - min).product(),
            Self::Polygon(vertices) => {
                let n = vertices.len();
                (0..n)
                    .map(|a| {
                        let (p, q) = (vertices[a], vertices[(a + 1) % n]);
                        p[0] * q[1] - q[0] * p[1]
                    })
                    .sum::<Real>()
                    .abs()
                    / 2.0
            }
            Self::Solid(solid) => solid.volume(),
            Self::Section(solid, section) => solid.section_area(section),
        }
    }

    /// Lattice sites of spacing dx in the region: from the box's corner for a box (as
    /// before meshes), aligned with the origin otherwise.
    fn fill(&self, dx: Real) -> Vec<Vector<D>> {
        let lift = |p: Vector<2>| Vector::<D>::from_fn(|k, _| p[k]);
        match self {
            Self::Box(min, max) => generate::fill_box(min, max, dx),
            Self::Polygon(vertices) => generate::fill_polygon(vertices, &Vector::<2>::zeros(), dx)
                .into_iter()
                .map(lift)
                .collect(),
            Self::Solid(solid) => solid
                .fill(&Vector::<3>::zeros(), dx)
                .into_iter()
                .map(|p| Vector::<D>::from_fn(|k, _| p[k]))
                .collect(),
            Self::Section(solid, section) => solid
                .fill_section(section, &Vector::<2>::zeros(), dx)
                .into_iter()
                .map(lift)
                .collect(),
        }
    }

    /// Whether the region holds `x`; a box as the cells its fill covers, [min, min + n dx)
    /// with n = ⌈(max − min)/dx⌉ per axis (its last row of sites may lie beyond `max`).
    fn contains(&self, x: &Vector<D>, dx: Real) -> bool {
        let plane = || Vector::<2>::new(x[0], x[1]);
        match self {
            Self::Box(min, max) => (0..D).all(|k| {
                let end = min[k] + generate::cell_count(max[k] - min[k], dx) as Real * dx;
                x[k] >= min[k] && x[k] < end
            }),
            Self::Polygon(vertices) => generate::polygon_contains(vertices, &plane()),
            Self::Solid(solid) => solid.contains(&Vector::<3>::from_fn(|k, _| x[k])),
            Self::Section(solid, section) => solid.contains(&section.lift(&plane())),
        }
    }
}

/// The fluid's blocks filled: one particle per lattice site of their union.
pub(crate) struct Filled<const D: usize> {
    /// The particles' positions.
    pub position: Vec<Vector<D>>,
    /// The free surface above each particle for the hydrostatic start: the top of its
    /// lattice column (the highest particle within dx/2 horizontally, + dx/2), so stacked
    /// or side-by-side blocks start from the pressure of the whole column.
    pub surface: Vec<Real>,
    /// How each block was filled.
    pub blocks: Vec<BlockReport>,
}

/// The lattice sites of the fluid's blocks. A site inside an earlier block is not filled
/// again, so overlapping blocks form their union.
pub(crate) fn fill_blocks<const D: usize>(scene: &Scene) -> Result<Filled<D>, SceneError> {
    let dx = scene.dx;
    let blocks = &scene.fluid.as_ref().expect("validated").blocks;
    let mut shapes: Vec<Shape<D>> = Vec::with_capacity(blocks.len());
    let mut position = Vec::new();
    let mut reports = Vec::with_capacity(blocks.len());
    for (index, block) in blocks.iter().enumerate() {
        let field = format!("fluid.blocks[{index}]");
        let shape = Shape::<D>::new(block, scene.folder.as_deref(), dx, &field)?;
        let sites = shape.fill(dx);
        let total = sites.len();
        let points: Vec<Vector<D>> = sites
            .into_iter()
            .filter(|x| !shapes.iter().any(|earlier| earlier.contains(x, dx)))
            .collect();
        if total == 0 {
            return Err(SceneError::Field {
                field,
                message: format!(
                    "the {} holds no lattice site at dx = {dx}: make it larger than dx{}",
                    shape.name(),
                    if matches!(shape, Shape::Section(..)) {
                        " or move the section plane into the mesh"
                    } else {
                        ""
                    }
                ),
            });
        }
        reports.push(BlockReport {
            name: shape.name(),
            particles: points.len(),
            overlapped: total - points.len(),
            filled: total as Real * dx.powi(D as i32),
            volume: shape.volume(),
        });
        position.extend(points);
        shapes.push(shape);
    }
    let surface = column_tops(&position, dx);
    Ok(Filled {
        position,
        surface,
        blocks: reports,
    })
}

/// For each particle, the highest particle's height + dx/2 among those within dx/2 of it
/// horizontally (its lattice column; the last axis is up).
fn column_tops<const D: usize>(position: &[Vector<D>], dx: Real) -> Vec<Real> {
    use std::collections::HashMap;
    let up = D - 1;
    let column = |x: &Vector<D>| -> [i64; 2] {
        std::array::from_fn(|k| {
            if k < up {
                (x[k] / dx).round() as i64
            } else {
                0
            }
        })
    };
    let mut tops: HashMap<[i64; 2], Real> = HashMap::new();
    for x in position {
        let top = tops.entry(column(x)).or_insert(Real::NEG_INFINITY);
        *top = top.max(x[up]);
    }
    position
        .iter()
        .map(|x| tops[&column(x)] + 0.5 * dx)
        .collect()
}
