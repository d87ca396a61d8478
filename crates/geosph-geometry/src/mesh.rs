//! Triangle surface meshes: reading STL and OBJ files, and the topology checks a closed
//! volume needs.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use geosph_core::{Real, Vector};

/// What is wrong with a mesh file or a mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read or parsed.
    #[error("mesh `{path}`: cannot read it: {reason}")]
    Read {
        /// The file as named.
        path: PathBuf,
        /// The reader's reason.
        reason: String,
    },
    /// The file's extension is not one this crate reads.
    #[error(
        "mesh `{path}`: unknown extension; use .stl (ASCII or binary), .obj or .asc (ESRI ASCII height grid)"
    )]
    Extension {
        /// The file as named.
        path: PathBuf,
    },
    /// The mesh has no triangle of non-zero area.
    #[error("mesh `{name}`: no triangle of non-zero area")]
    Empty {
        /// The mesh's name (its file).
        name: String,
    },
    /// A closed volume was asked of a mesh that is not one.
    #[error("mesh `{name}`: {problem}")]
    Topology {
        /// The mesh's name (its file).
        name: String,
        /// What is wrong, with the vertices and triangles involved.
        problem: String,
    },
}

/// A triangle surface mesh: vertices and triangles as index triples, counter-clockwise seen
/// from outside for a closed, outward-oriented surface.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMesh {
    /// A name for messages (the file it came from).
    pub name: String,
    /// Vertex positions in m.
    pub vertices: Vec<Vector<3>>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl SurfaceMesh {
    /// A mesh of `vertices` and `triangles`, with triangles of zero area (repeated vertices)
    /// removed; an error if none is left or an index is out of range.
    pub fn new(
        name: impl Into<String>,
        vertices: Vec<Vector<3>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, MeshError> {
        let name = name.into();
        if let Some((t, _)) = triangles
            .iter()
            .enumerate()
            .find(|(_, tri)| tri.iter().any(|&v| v as usize >= vertices.len()))
        {
            return Err(MeshError::Topology {
                name,
                problem: format!(
                    "triangle {t} names a vertex beyond the {} vertices",
                    vertices.len()
                ),
            });
        }
        let mut mesh = Self {
            name,
            vertices,
            triangles,
        };
        mesh.triangles.retain(|&[a, b, c]| {
            let [a, b, c] = [a, b, c].map(|v| mesh.vertices[v as usize]);
            (b - a).cross(&(c - a)).norm_squared() > 0.0
        });
        if mesh.triangles.is_empty() {
            return Err(MeshError::Empty { name: mesh.name });
        }
        Ok(mesh)
    }

    /// Reads an STL (ASCII or binary; vertices merged by position) or a Wavefront OBJ file
    /// (every object's faces, triangulated), or a terrain from an ESRI ASCII height grid
    /// (`.asc`: the cell centres at their elevation, two triangles per square of four
    /// centres with data, facing up).
    pub fn read(path: &Path) -> Result<Self, MeshError> {
        let read_error = |reason: String| MeshError::Read {
            path: path.to_owned(),
            reason,
        };
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let (vertices, triangles) = match extension.as_deref() {
            Some("stl") => {
                let mut file = std::fs::File::open(path).map_err(|e| read_error(e.to_string()))?;
                let stl = stl_io::read_stl(&mut file).map_err(|e| read_error(e.to_string()))?;
                let vertices = stl
                    .vertices
                    .iter()
                    .map(|v| Vector::<3>::new(v[0].into(), v[1].into(), v[2].into()))
                    .collect();
                let triangles = stl
                    .faces
                    .iter()
                    .map(|f| f.vertices.map(|v| v as u32))
                    .collect();
                (vertices, triangles)
            }
            Some("obj") => {
                let options = tobj::LoadOptions {
                    triangulate: true,
                    single_index: true,
                    ..Default::default()
                };
                let (models, _) =
                    tobj::load_obj(path, &options).map_err(|e| read_error(e.to_string()))?;
                let mut vertices = Vec::new();
                let mut triangles = Vec::new();
                for model in models {
                    let offset = vertices.len() as u32;
                    vertices.extend(
                        model
                            .mesh
                            .positions
                            .chunks_exact(3)
                            .map(|p| Vector::<3>::new(p[0], p[1], p[2])),
                    );
                    triangles.extend(
                        model
                            .mesh
                            .indices
                            .chunks_exact(3)
                            .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
                    );
                }
                (vertices, triangles)
            }
            Some("asc") => crate::height_grid::read(path).map_err(read_error)?,
            _ => {
                return Err(MeshError::Extension {
                    path: path.to_owned(),
                });
            }
        };
        Self::new(path.display().to_string(), vertices, triangles)
    }

    /// The corners of the mesh's bounding box.
    pub fn bounds(&self) -> (Vector<3>, Vector<3>) {
        self.vertices.iter().fold(
            (
                Vector::<3>::repeat(Real::INFINITY),
                Vector::<3>::repeat(Real::NEG_INFINITY),
            ),
            |(lo, hi), v| (lo.inf(v), hi.sup(v)),
        )
    }

    /// The enclosed volume by the divergence theorem, V = Σ_t a·(b × c)/6 over the triangles
    /// (a, b, c): positive for outward-oriented triangles. Meaningful for a closed mesh.
    pub fn signed_volume(&self) -> Real {
        self.triangles
            .iter()
            .map(|&[a, b, c]| {
                let [a, b, c] = [a, b, c].map(|v| self.vertices[v as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    /// Checks that the mesh bounds a volume: every edge shared by exactly two triangles that
    /// run along it in opposite directions (a closed, manifold, consistently oriented
    /// surface). Vertices at the same position count as one.
    pub fn check_closed(&self) -> Result<(), MeshError> {
        self.check_edges(true)
    }

    /// Checks that the mesh is a consistently oriented manifold surface, open or closed: no
    /// two triangles run along an edge in the same direction (which a flipped triangle or a
    /// third triangle on an edge makes).
    pub fn check_oriented(&self) -> Result<(), MeshError> {
        self.check_edges(false)
    }

    /// [`Self::check_closed`] if `closed`, else [`Self::check_oriented`].
    fn check_edges(&self, closed: bool) -> Result<(), MeshError> {
        let canonical = self.merged_vertices();
        // Directed edge (from, to) → the triangles that run along it.
        let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (t, triangle) in self.triangles.iter().enumerate() {
            let [a, b, c] = triangle.map(|v| canonical[v as usize]);
            for edge in [(a, b), (b, c), (c, a)] {
                edges.entry(edge).or_default().push(t);
            }
        }
        let problem = |problem: String| MeshError::Topology {
            name: self.name.clone(),
            problem,
        };
        let mut sorted: Vec<_> = edges.iter().collect();
        sorted.sort_unstable_by_key(|(edge, _)| **edge);
        for (&(from, to), triangles) in sorted {
            let twins = edges.get(&(to, from)).map_or(0, Vec::len);
            let point = |v: u32| format!("{:?}", self.vertices[v as usize].as_slice());
            if triangles.len() > 1 {
                return Err(problem(format!(
                    "triangles {triangles:?} run along the edge from {} to {} in the same \
                     direction: the surface is non-manifold there or not consistently oriented",
                    point(from),
                    point(to)
                )));
            }
            if closed && twins == 0 {
                return Err(problem(format!(
                    "not closed: the edge from {} to {} of triangle {} has no neighbour \
                     (a closed volume needs every edge shared by two triangles)",
                    point(from),
                    point(to),
                    triangles[0]
                )));
            }
        }
        Ok(())
    }

    /// The closed mesh with outward-facing triangles: checked by [`Self::check_closed`],
    /// flipped if its volume is negative.
    pub fn into_outward(mut self) -> Result<Self, MeshError> {
        self.check_closed()?;
        if self.signed_volume() < 0.0 {
            for triangle in &mut self.triangles {
                triangle.swap(1, 2);
            }
        }
        Ok(self)
    }

    /// For each vertex, the first vertex at the same position.
    fn merged_vertices(&self) -> Vec<u32> {
        let mut first: HashMap<[u64; 3], u32> = HashMap::new();
        self.vertices
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let key = [v[0], v[1], v[2]].map(|x| (x + 0.0).to_bits());
                *first.entry(key).or_insert(i as u32)
            })
            .collect()
    }

    /// The mesh with every vertex x moved to `scale` · x + `offset`.
    pub fn transformed(mut self, scale: Real, offset: &Vector<3>) -> Self {
        for v in &mut self.vertices {
            *v = *v * scale + offset;
        }
        self
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The unit cube [0, 1]³, outward oriented.
    pub(crate) fn cube() -> SurfaceMesh {
        let vertices = (0..8)
            .map(|i| Vector::<3>::new((i & 1) as Real, ((i >> 1) & 1) as Real, (i >> 2) as Real))
            .collect();
        let triangles = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        SurfaceMesh::new("cube", vertices, triangles).unwrap()
    }

    #[test]
    fn the_unit_cube_is_closed_with_volume_one() {
        let cube = cube();
        cube.check_closed().unwrap();
        assert_relative_eq!(cube.signed_volume(), 1.0, epsilon = 1e-14);
    }

    #[test]
    fn an_inward_cube_is_turned_outward() {
        let mut cube = cube();
        for t in &mut cube.triangles {
            t.swap(0, 1);
        }
        assert_relative_eq!(cube.signed_volume(), -1.0, epsilon = 1e-14);
        let outward = cube.into_outward().unwrap();
        assert_relative_eq!(outward.signed_volume(), 1.0, epsilon = 1e-14);
    }

    #[test]
    fn an_open_or_misoriented_mesh_is_named_with_the_edge() {
        let mut open = cube();
        open.triangles.pop();
        let message = open.check_closed().unwrap_err().to_string();
        assert!(
            message.starts_with("mesh `cube`: not closed: the edge from"),
            "{message}"
        );

        let mut flipped = cube();
        flipped.triangles[0].swap(1, 2);
        let message = flipped.check_closed().unwrap_err().to_string();
        assert!(message.contains("in the same direction"), "{message}");
    }

    #[test]
    fn degenerate_triangles_are_dropped_and_an_empty_mesh_refused() {
        let vertices = vec![
            Vector::<3>::zeros(),
            Vector::<3>::x(),
            Vector::<3>::x() * 2.0,
        ];
        let error = SurfaceMesh::new("line", vertices, vec![[0, 1, 2], [0, 0, 1]]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "mesh `line`: no triangle of non-zero area"
        );
        let error = SurfaceMesh::new("bad", vec![Vector::<3>::zeros()], vec![[0, 1, 2]]);
        assert!(
            error
                .unwrap_err()
                .to_string()
                .contains("beyond the 1 vertices")
        );
    }

    #[test]
    fn unknown_extensions_and_missing_files_are_named() {
        let error = SurfaceMesh::read(Path::new("terrain.ply")).unwrap_err();
        assert_eq!(
            error.to_string(),
            "mesh `terrain.ply`: unknown extension; use .stl (ASCII or binary), .obj or .asc (ESRI ASCII height grid)"
        );
        let error = SurfaceMesh::read(Path::new("no/such/file.stl")).unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with("mesh `no/such/file.stl`: cannot read it:")
        );
    }

    #[test]
    fn stl_and_obj_files_read_back_as_the_closed_cube() {
        let cube = cube();
        let folder = std::env::temp_dir().join(format!("geosph-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        // Binary STL (triangle soup: the reader merges the corners).
        let stl = folder.join("cube.stl");
        let facets: Vec<stl_io::Triangle> = cube
            .triangles
            .iter()
            .map(|t| stl_io::Triangle {
                normal: stl_io::Normal::new([0.0; 3]),
                vertices: t.map(|v| {
                    let x = cube.vertices[v as usize];
                    stl_io::Vertex::new([x[0] as f32, x[1] as f32, x[2] as f32])
                }),
            })
            .collect();
        stl_io::write_stl(&mut std::fs::File::create(&stl).unwrap(), facets.iter()).unwrap();
        // OBJ with quads (triangulated on reading).
        let obj = folder.join("cube.obj");
        let mut text = String::new();
        for x in &cube.vertices {
            text.push_str(&format!("v {} {} {}\n", x[0], x[1], x[2]));
        }
        for quad in [
            [1, 3, 4, 2],
            [5, 6, 8, 7],
            [1, 2, 6, 5],
            [3, 7, 8, 4],
            [1, 5, 7, 3],
            [2, 4, 8, 6],
        ] {
            text.push_str(&format!(
                "f {} {} {} {}\n",
                quad[0], quad[1], quad[2], quad[3]
            ));
        }
        std::fs::write(&obj, text).unwrap();
        for path in [stl, obj] {
            let mesh = SurfaceMesh::read(&path).unwrap();
            assert_eq!(mesh.triangles.len(), 12, "{}", path.display());
            mesh.check_closed().unwrap();
            assert_relative_eq!(mesh.signed_volume(), 1.0, epsilon = 1e-6);
        }
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
