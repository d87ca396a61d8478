//! Particle frames as VTK XML UnstructuredGrid files (`.vtu`) for ParaView.
//!
//! Format: the VTK XML file format, type `UnstructuredGrid` (VTK User's Guide, "VTK File
//! Formats", <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>), encoded by
//! [`vtkio`]: one `VTK_VERTEX` cell per particle, little-endian binary arrays, base64 inline,
//! LZ4-compressed (`compressor="vtkLZ4DataCompressor"`, read by VTK ≥ 8 and ParaView ≥ 5.4).
//!
//! Array layout, chosen for what ParaView displays without filters:
//! - positions (`Points`) and [`FieldData::Vector`] fields are `Float64` with 3 components; in
//!   2D the z component is 0, so the frame lies in the plane z = 0;
//! - [`FieldData::Tensor`] fields are `Float64` with 9 components in row-major order
//!   (`xx, xy, xz, yx, …, zz`), which ParaView labels and treats as a 3×3 tensor;
//! - [`FieldData::Scalar`] fields are `Float64`, [`FieldData::Integer`] fields `UInt32`;
//! - the first scalar, vector and tensor field are marked as the active `Scalars`, `Vectors`
//!   and `Tensors` of the point data.
//!
//! vtkio owns the arrays it encodes, so each frame copies every field once into a flat buffer
//! (which also pads 2D vectors to 3 components); nothing else is copied per particle.
//!
//! Several particle sets (fluid, soil, wall particles) go into one file with
//! [`write_vtu_sets`]: the sets are concatenated in order and a `UInt32` point array `kind`
//! gives each point's set index, so one ParaView `Threshold` on `kind` separates them. A field
//! that some sets lack is filled on their points with NaN (scalar, vector, tensor fields: ParaView
//! draws NaN in its "NaN colour" and leaves it out of colour-map ranges) or with 0 (integer
//! fields). The same name must carry the same field type in every set.

use geosph_core::{Real, Tensor3, Vector};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};
use vtkio::xml::Compressor;

use crate::{Error, write_atomically};

/// Name of the point array holding the particle-set index in [`write_vtu_sets`].
pub const KIND_FIELD: &str = "kind";

/// LZ4 level given to vtkio; any non-zero value switches compression on (LZ4 has no levels
/// in vtkio's block encoder).
const COMPRESSION_LEVEL: u32 = 1;

/// The per-particle values of one field, borrowed from the particle storage.
#[derive(Clone, Copy, Debug)]
pub enum FieldData<'a, const D: usize> {
    /// One real number per particle (density, pressure, plastic strain), written as `Float64`.
    Scalar(&'a [Real]),
    /// One `D`-vector per particle (velocity, acceleration), written as 3 `Float64` components
    /// (z = 0 in 2D).
    Vector(&'a [Vector<D>]),
    /// One 3×3 tensor per particle (stress, strain), written as 9 `Float64` components, row-major.
    Tensor(&'a [Tensor3]),
    /// One unsigned integer per particle (particle `id`, material index), written as `UInt32`.
    Integer(&'a [u32]),
}

impl<const D: usize> FieldData<'_, D> {
    /// Number of particles the field has values for.
    pub fn len(&self) -> usize {
        match self {
            Self::Scalar(values) => values.len(),
            Self::Vector(values) => values.len(),
            Self::Tensor(values) => values.len(),
            Self::Integer(values) => values.len(),
        }
    }

    /// Whether the field has no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of components per point in the written array (1, 3 or 9).
    pub fn components(&self) -> usize {
        match self {
            Self::Scalar(_) | Self::Integer(_) => 1,
            Self::Vector(_) => 3,
            Self::Tensor(_) => 9,
        }
    }

    /// The VTK array type the field is written as.
    pub(crate) fn vtk_type(&self) -> &'static str {
        match self {
            Self::Integer(_) => "UInt32",
            _ => "Float64",
        }
    }

    /// Whether `self` and `other` are the same field type (and so can share one array).
    fn same_type(&self, other: &Self) -> bool {
        std::mem::discriminant(self) == std::mem::discriminant(other)
    }
}

/// One named point array of a frame.
#[derive(Clone, Copy, Debug)]
pub struct Field<'a, const D: usize> {
    /// Array name shown in ParaView (e.g. `"pressure"`).
    pub name: &'a str,
    /// The values, one per particle.
    pub data: FieldData<'a, D>,
}

impl<'a, const D: usize> Field<'a, D> {
    /// A scalar field `name`.
    pub fn scalar(name: &'a str, values: &'a [Real]) -> Self {
        Self {
            name,
            data: FieldData::Scalar(values),
        }
    }

    /// A vector field `name`.
    pub fn vector(name: &'a str, values: &'a [Vector<D>]) -> Self {
        Self {
            name,
            data: FieldData::Vector(values),
        }
    }

    /// A 3×3 tensor field `name`.
    pub fn tensor(name: &'a str, values: &'a [Tensor3]) -> Self {
        Self {
            name,
            data: FieldData::Tensor(values),
        }
    }

    /// An unsigned integer field `name`.
    pub fn integer(name: &'a str, values: &'a [u32]) -> Self {
        Self {
            name,
            data: FieldData::Integer(values),
        }
    }
}

/// One set of particles at one instant: positions and point fields, all borrowed.
#[derive(Clone, Debug)]
pub struct Frame<'a, const D: usize> {
    /// Particle positions; their number is the number of points.
    pub position: &'a [Vector<D>],
    /// Point fields, each with one value per position.
    pub fields: Vec<Field<'a, D>>,
}

impl<'a, const D: usize> Frame<'a, D> {
    /// A frame of `position` without fields yet.
    pub fn new(position: &'a [Vector<D>]) -> Self {
        Self {
            position,
            fields: Vec::new(),
        }
    }

    /// Adds `field` (builder style).
    pub fn with(mut self, field: Field<'a, D>) -> Self {
        self.fields.push(field);
        self
    }

    fn field(&self, name: &str) -> Option<&Field<'a, D>> {
        self.fields.iter().find(|field| field.name == name)
    }
}

/// Writes one particle set as a `.vtu` file at `path`, atomically.
///
/// # Errors
/// [`Error::FieldLength`] naming the field whose length differs from the number of positions,
/// [`Error::FieldName`] for a repeated name, [`Error::Io`] (with `path`) when encoding or
/// writing fails; `path` is then left as it was.
pub fn write_vtu<const D: usize>(
    path: impl AsRef<std::path::Path>,
    frame: &Frame<'_, D>,
) -> Result<(), Error> {
    write(path.as_ref(), std::slice::from_ref(frame), false)
}

/// Writes several particle sets into one `.vtu` file at `path`, atomically.
///
/// The sets are concatenated in the order given; the point array [`KIND_FIELD`] (`kind`) holds
/// each point's index into `sets`. Fields are the union over all sets, in order of first
/// appearance; on the points of a set without a field, real-valued fields are NaN and integer
/// fields 0.
///
/// # Errors
/// As [`write_vtu`]; also [`Error::FieldName`] when a field is called `kind` or when one name
/// has different field types in different sets.
pub fn write_vtu_sets<const D: usize>(
    path: impl AsRef<std::path::Path>,
    sets: &[Frame<'_, D>],
) -> Result<(), Error> {
    write(path.as_ref(), sets, true)
}

fn write<const D: usize>(
    path: &std::path::Path,
    sets: &[Frame<'_, D>],
    with_kind: bool,
) -> Result<(), Error> {
    const { assert!(D == 2 || D == 3, "VTU output is for 2D and 3D particles") };
    let fields = union_of_fields(sets, with_kind)?;
    let points: usize = sets.iter().map(|set| set.position.len()).sum();

    let mut position = Vec::with_capacity(3 * points);
    for set in sets {
        for x in set.position {
            push_padded(&mut position, x);
        }
    }

    let mut arrays = Vec::with_capacity(fields.len() + 1);
    for (name, data) in fields {
        arrays.push(point_array(name, data, sets, points));
    }
    if with_kind {
        let mut kind = Vec::with_capacity(points);
        for (index, set) in sets.iter().enumerate() {
            let index = u32::try_from(index).expect("fewer than 2³² particle sets");
            kind.extend(std::iter::repeat_n(index, set.position.len()));
        }
        arrays.push(Attribute::DataArray(DataArray {
            name: KIND_FIELD.into(),
            elem: ElementType::Generic(1),
            data: IOBuffer::U32(kind),
        }));
    }

    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(position),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity: (0..points as u64).collect(),
                offsets: (1..=points as u64).collect(),
            },
            types: vec![CellType::Vertex; points],
        },
        data: Attributes {
            point: arrays,
            cell: Vec::new(),
        },
    };
    let empty = (points == 0).then_some(r#"NumberOfPoints="0" NumberOfCells="0""#);
    write_xml(path, DataSet::inline(piece), empty)
}

/// Writes `data` as a compressed VTK XML file at `path`, atomically. For a piece without
/// points, `empty_counts` are the zero counts (`NumberOfPoints="0" …`) that VTK needs on its
/// `<Piece>` and vtkio leaves out; such a file is small, so its text is patched in memory.
pub(crate) fn write_xml(
    path: &std::path::Path,
    data: DataSet,
    empty_counts: Option<&str>,
) -> Result<(), Error> {
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        data,
        file_path: None,
    };
    let invalid = |e: vtkio::xml::Error| std::io::Error::other(e.to_string());
    let file = vtk
        .try_into_xml_format(Compressor::LZ4, COMPRESSION_LEVEL)
        .map_err(|e| Error::io(path, invalid(e)))?;
    match empty_counts {
        None => write_atomically(path, |w| file.write(w).map_err(invalid)),
        Some(counts) => {
            let mut text = Vec::new();
            file.write(&mut text)
                .map_err(|e| Error::io(path, invalid(e)))?;
            let text =
                String::from_utf8_lossy(&text).replacen("<Piece>", &format!("<Piece {counts}>"), 1);
            write_atomically(path, |w| w.write_all(text.as_bytes()))
        }
    }
}

/// Checks every set's field lengths and names, and returns the union of fields by name: the
/// first occurrence of each name, in order of appearance.
pub(crate) fn union_of_fields<'s, 'a, const D: usize>(
    sets: &'s [Frame<'a, D>],
    with_kind: bool,
) -> Result<Vec<(&'a str, &'s FieldData<'a, D>)>, Error> {
    let mut union: Vec<(&'a str, &'s FieldData<'a, D>)> = Vec::new();
    for set in sets {
        for (index, field) in set.fields.iter().enumerate() {
            let reject = |reason| {
                Err(Error::FieldName {
                    name: field.name.into(),
                    reason,
                })
            };
            if field.data.len() != set.position.len() {
                return Err(Error::FieldLength {
                    name: field.name.into(),
                    len: field.data.len(),
                    points: set.position.len(),
                });
            }
            if with_kind && field.name == KIND_FIELD {
                return reject("the name `kind` is reserved for the particle-set index");
            }
            if set.fields[..index].iter().any(|f| f.name == field.name) {
                return reject("appears twice in one particle set");
            }
            match union.iter().find(|(name, _)| *name == field.name) {
                Some((_, data)) if !data.same_type(&field.data) => {
                    return reject("has different types in different particle sets");
                }
                Some(_) => {}
                None => union.push((field.name, &field.data)),
            }
        }
    }
    Ok(union)
}

/// The point array `name` over all sets, filled where a set lacks the field.
fn point_array<const D: usize>(
    name: &str,
    data: &FieldData<'_, D>,
    sets: &[Frame<'_, D>],
    points: usize,
) -> Attribute {
    let mut real = Vec::new();
    let mut integer = Vec::new();
    match data {
        FieldData::Integer(_) => integer.reserve(points),
        _ => real.reserve(points * data.components()),
    }
    for set in sets {
        let n = set.position.len();
        match set.field(name).map(|field| field.data) {
            Some(FieldData::Scalar(values)) => real.extend_from_slice(values),
            Some(FieldData::Vector(values)) => {
                values.iter().for_each(|v| push_padded(&mut real, v))
            }
            Some(FieldData::Tensor(values)) => {
                for t in values {
                    for row in 0..3 {
                        real.extend(t.row(row).iter());
                    }
                }
            }
            Some(FieldData::Integer(values)) => integer.extend_from_slice(values),
            None => match data {
                FieldData::Integer(_) => integer.extend(std::iter::repeat_n(0, n)),
                _ => real.extend(std::iter::repeat_n(Real::NAN, n * data.components())),
            },
        }
    }
    // vtkio marks the first `Scalars`, `Vectors` and `Tensors` array as the active one.
    let (elem, data) = match data {
        FieldData::Scalar(_) => (
            ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            },
            IOBuffer::F64(real),
        ),
        FieldData::Vector(_) => (ElementType::Vectors, IOBuffer::F64(real)),
        FieldData::Tensor(_) => (ElementType::Tensors, IOBuffer::F64(real)),
        FieldData::Integer(_) => (ElementType::Generic(1), IOBuffer::U32(integer)),
    };
    Attribute::DataArray(DataArray {
        name: name.into(),
        elem,
        data,
    })
}

/// Appends the 3 components of `x`, with zeros after the first `D`.
fn push_padded<const D: usize>(buffer: &mut Vec<Real>, x: &Vector<D>) {
    buffer.extend_from_slice(x.as_slice());
    buffer.extend(std::iter::repeat_n(0.0, 3 - D));
}

#[cfg(test)]
mod tests;
