//! `bcifs.Mesh`: a mesh as numpy arrays, made from the library's shapes
//! and polygon meshes (moved, not copied, where the library holds them as
//! numpy wants them), and handed to trimesh.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use bcifs::render::PolyMesh;
use bcifs::render::Shape;

/// A mesh as numpy arrays: `vertices` (n, 3) float64, `faces` (m, k) int64
/// when every face has k corners (else a list of arrays), `edges` (e, 2)
/// int64 for curves, `normals` (n, 3) and `colours` (n, 3) uint8 when
/// present, and texture coordinates face-varying as libigl has them: `uv`
/// (t, 2) float64 and `uv_faces`, shaped as `faces`, indexing `uv` corner
/// for corner. From `subdivide(..., face_data=...)`: `face_sources` (m,)
/// int64, the input face each face comes from, and `face_data`, the given
/// arrays indexed by it.
#[pyclass(module = "bcifs", frozen, get_all)]
pub struct Mesh {
    vertices: Py<PyAny>,
    faces: Py<PyAny>,
    edges: Py<PyArray2<i64>>,
    normals: Option<Py<PyAny>>,
    colours: Option<Py<PyArray2<u8>>>,
    uv: Option<Py<PyArray2<f64>>>,
    uv_faces: Option<Py<PyAny>>,
    face_sources: Option<Py<PyArray1<i64>>>,
    face_data: Option<Py<PyDict>>,
}

/// `values` as an (n, k) array.
pub(crate) fn matrix<T: numpy::Element>(py: Python<'_>, values: Vec<T>, k: usize) -> Py<PyArray2<T>> {
    let n = values.len().checked_div(k).unwrap_or(0);
    Array2::from_shape_vec((n, k), values).expect("n × k values").into_pyarray(py).unbind()
}

/// Faces as [`Arrays`] hold them: `starts` (m + 1 offsets into `indices`).
pub(crate) struct Faces {
    starts: Vec<usize>,
    indices: Vec<i64>,
}

impl Faces {
    fn of(starts: &[usize], indices: impl IntoIterator<Item = usize>) -> Faces {
        Faces { starts: starts.to_vec(), indices: indices.into_iter().map(|i| i as i64).collect() }
    }

    /// One (m, k) array when every face has k corners, a list of arrays otherwise.
    fn into_py(self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let Faces { starts, indices } = self;
        let k = starts.get(1).map_or(3, |s| s - starts[0]);
        if starts.windows(2).all(|w| w[1] - w[0] == k) {
            return Ok(matrix(py, indices, k).into_any());
        }
        let list = PyList::empty(py);
        for w in starts.windows(2) {
            list.append(indices[w[0]..w[1]].to_vec().into_pyarray(py))?;
        }
        Ok(list.into_any().unbind())
    }
}

/// A [`Mesh`]'s arrays before they are numpy's: made from the library's
/// output on the worker thread, the GIL released and the work cancellable,
/// then handed over without a copy ([`Arrays::into_mesh`]).
pub(crate) struct Arrays {
    vertices: Vec<f64>,
    faces: Faces,
    edges: Vec<i64>,
    normals: Option<Vec<f64>>,
    colours: Option<Vec<u8>>,
    uv: Option<(Vec<f64>, Faces)>,
    sources: Option<Vec<i64>>,
}

impl Arrays {
    /// The arrays of an evaluated shape, moved out of it where the library
    /// already holds them as numpy wants them (3D positions, normals,
    /// colours: no copy).
    pub(crate) fn of_shape(shape: Shape) -> Arrays {
        let n = shape.vertex_count();
        let mut starts = Vec::with_capacity(shape.quads.len() + shape.triangles.len() + 1);
        starts.push(0);
        let mut indices = Vec::with_capacity(4 * shape.quads.len() + 3 * shape.triangles.len());
        for q in &shape.quads {
            indices.extend(q.iter().map(|&v| v as usize));
            starts.push(indices.len());
        }
        for t in &shape.triangles {
            indices.extend(t);
            starts.push(indices.len());
        }
        let textured = !shape.uvs.is_empty() && shape.triangles.is_empty() && shape.quad_uvs.len() == shape.quads.len();
        let uv_faces = textured.then(|| Faces::of(&starts, shape.quad_uvs.iter().flat_map(|q| q.map(|v| v as usize))));
        let mut edges = Vec::new();
        for (first, count, closed) in shape.polylines() {
            let segments = if closed && count > 2 { count } else { count.saturating_sub(1) };
            for k in 0..segments {
                edges.extend([(first + k) as i64, (first + (k + 1) % count) as i64]);
            }
        }
        let faces = Faces { starts, indices: indices.into_iter().map(|i| i as i64).collect() };
        let Shape { dim, positions, normals, colours, uvs, .. } = shape;
        let vertices =
            if dim == 3 { positions } else { positions.chunks(dim.max(1)).flat_map(|p| [p[0], p[1], 0.0]).collect() };
        Arrays {
            vertices,
            faces,
            edges,
            normals: (normals.len() == 3 * n && n > 0).then_some(normals),
            colours: (colours.len() == n && n > 0).then(|| colours.into_flattened()),
            uv: uv_faces.map(|f| (uvs, f)),
            sources: None,
        }
    }

    /// The arrays of a polygon mesh, its positions moved (no copy), with
    /// area-weighted normals and its texture when it has one, and each
    /// face's source when given (one per face of `mesh`). Faces of fewer
    /// than three corners (Doo-Sabin's digon beside a vertex of valence 2,
    /// a doubled edge) are left out, as the files leave them out.
    pub(crate) fn of_polymesh(mesh: PolyMesh, sources: Option<Vec<u32>>) -> Arrays {
        let normals = bcifs::render::area_normals(&mesh.positions, mesh.faces());
        let kept: Vec<usize> = (0..mesh.face_count()).filter(|&f| mesh.face(f).len() >= 3).collect();
        let faces_of = |m: &PolyMesh| {
            let (offsets, corners) = (m.offsets(), m.corners());
            let mut starts = vec![0];
            let mut indices = Vec::with_capacity(corners.len());
            for &f in &kept {
                indices.extend(corners[offsets[f]..offsets[f + 1]].iter().map(|&i| i as i64));
                starts.push(indices.len());
            }
            Faces { starts, indices }
        };
        let uv = mesh.texture().map(|t| (t.positions.iter().flat_map(|p| [p[0], p[1]]).collect(), faces_of(t)));
        let faces = faces_of(&mesh);
        let sources = sources.map(|s| kept.iter().map(|&f| i64::from(s[f])).collect());
        Arrays {
            vertices: mesh.positions.into_flattened(),
            faces,
            edges: Vec::new(),
            normals: Some(normals.into_flattened()),
            colours: None,
            uv,
            sources,
        }
    }

    /// The numpy arrays, the buffers moved.
    pub(crate) fn into_mesh(self, py: Python<'_>) -> PyResult<Mesh> {
        self.into_mesh_as(py, None)
    }

    /// [`Arrays::into_mesh`], the vertices and normals as `dtype` (numpy's
    /// `float32` or `float64`; `None`: float64, the buffers moved).
    pub(crate) fn into_mesh_as(self, py: Python<'_>, dtype: Option<&Bound<'_, PyAny>>) -> PyResult<Mesh> {
        let (uv, uv_faces) = match self.uv {
            Some((uv, faces)) => (Some(matrix(py, uv, 2)), Some(faces.into_py(py)?)),
            None => (None, None),
        };
        let cast = |array: Py<PyArray2<f64>>| -> PyResult<Py<PyAny>> {
            match dtype {
                None => Ok(array.into_any()),
                Some(d) => {
                    let numpy = py.import("numpy")?;
                    let kind = numpy.getattr("dtype")?.call1((d,))?;
                    let float = kind.getattr("kind")?.extract::<String>()? == "f";
                    if !float {
                        return Err(crate::err(format!(
                            "dtype={kind}: expected a float type (numpy.float32 or numpy.float64)"
                        )));
                    }
                    Ok(array.bind(py).call_method1("astype", (kind,))?.unbind())
                }
            }
        };
        let normals = self.normals.map(|v| cast(matrix(py, v, 3))).transpose()?;
        let face_sources = self.sources.map(|s| s.into_pyarray(py).unbind());
        Ok(Mesh {
            vertices: cast(matrix(py, self.vertices, 3))?,
            faces: self.faces.into_py(py)?,
            edges: matrix(py, self.edges, 2),
            normals,
            colours: self.colours.map(|v| matrix(py, v, 3)),
            uv,
            uv_faces,
            face_sources,
            face_data: None,
        })
    }
}

impl Mesh {
    /// The same mesh with `face_data` (name → an array of one row per input
    /// face) indexed by its face sources: each face's rows from the face it
    /// comes from.
    pub(crate) fn with_face_data(mut self, py: Python<'_>, data: &Bound<'_, PyDict>) -> PyResult<Mesh> {
        let Some(sources) = &self.face_sources else { return Ok(self) };
        let numpy = py.import("numpy")?;
        let out = PyDict::new(py);
        for (name, values) in data.iter() {
            let array = numpy.call_method1("asarray", (values,))?;
            out.set_item(name, array.get_item(sources.bind(py))?)?;
        }
        self.face_data = Some(out.unbind());
        Ok(self)
    }
}

#[pymethods]
impl Mesh {
    /// The mesh as trimesh has it (trimesh must be installed): a `Trimesh`
    /// (faces fanned into triangles, normals and colours kept; with UVs, a
    /// vertex split at the seams, trimesh's one UV per vertex), a `Path3D`
    /// for curves, or a `PointCloud`.
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = py.import("trimesh")?;
        let faces: Vec<Vec<i64>> = self.faces.bind(py).extract()?;
        let mut triangles: Vec<i64> = Vec::new();
        let fan = |f: &[i64], out: &mut Vec<i64>| out.extend(bcifs::render::fan(f, 0).flatten());
        faces.iter().for_each(|f| fan(f, &mut triangles));
        let vertices = self.vertices.bind(py);
        if !triangles.is_empty() {
            let kwargs = PyDict::new(py);
            kwargs.set_item("process", false)?;
            let (Some(uv), Some(uv_faces)) = (&self.uv, &self.uv_faces) else {
                kwargs.set_item("vertices", vertices)?;
                kwargs.set_item("faces", matrix(py, triangles, 3))?;
                kwargs.set_item("vertex_normals", self.normals.as_ref().map(|n| n.bind(py)))?;
                kwargs.set_item("vertex_colors", self.colours.as_ref().map(|c| c.bind(py)))?;
                return trimesh.getattr("Trimesh")?.call((), Some(&kwargs));
            };
            // trimesh holds one UV per vertex: a vertex is split where its corners' UVs differ (the seams).
            let uv_faces: Vec<Vec<i64>> = uv_faces.bind(py).extract()?;
            let (p, t): (Vec<[f64; 3]>, Vec<[f64; 2]>) = (vertices.extract()?, uv.bind(py).extract()?);
            let n: Option<Vec<[f64; 3]>> = self.normals.as_ref().map(|n| n.bind(py).extract()).transpose()?;
            let mut split = std::collections::HashMap::new();
            let (mut positions, mut uvs, mut normals, mut corners) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for (f, g) in faces.iter().zip(&uv_faces) {
                let face: Vec<i64> = f
                    .iter()
                    .zip(g)
                    .map(|(&v, &k)| {
                        *split.entry((v, k)).or_insert_with(|| {
                            positions.extend(p[v as usize]);
                            uvs.extend(t[k as usize]);
                            if let Some(n) = &n {
                                normals.extend(n[v as usize]);
                            }
                            (positions.len() / 3 - 1) as i64
                        })
                    })
                    .collect();
                fan(&face, &mut corners);
            }
            kwargs.set_item("vertices", matrix(py, positions, 3))?;
            kwargs.set_item("faces", matrix(py, corners, 3))?;
            kwargs.set_item("vertex_normals", n.is_some().then(|| matrix(py, normals, 3)))?;
            let visuals = py.import("trimesh.visual")?.getattr("TextureVisuals")?;
            let visual_kwargs = PyDict::new(py);
            visual_kwargs.set_item("uv", matrix(py, uvs, 2))?;
            kwargs.set_item("visual", visuals.call((), Some(&visual_kwargs))?)?;
            return trimesh.getattr("Trimesh")?.call((), Some(&kwargs));
        }
        let edges = self.edges.bind(py);
        if edges.len()? > 0 {
            // One `Line` entity per segment (no solver of trimesh's needed).
            let line = py.import("trimesh.path.entities")?.getattr("Line")?;
            let entities = PyList::empty(py);
            for edge in edges.try_iter()? {
                entities.append(line.call1((edge?,))?)?;
            }
            let kwargs = PyDict::new(py);
            kwargs.set_item("entities", entities)?;
            kwargs.set_item("vertices", vertices)?;
            return py.import("trimesh.path")?.getattr("Path3D")?.call((), Some(&kwargs));
        }
        let kwargs = PyDict::new(py);
        kwargs.set_item("colors", self.colours.as_ref().map(|c| c.bind(py)))?;
        trimesh.getattr("PointCloud")?.call((vertices,), Some(&kwargs))
    }

    /// The mesh as Open3D has it (Open3D must be installed): a
    /// `TriangleMesh` (faces fanned into triangles as `to_trimesh` fans
    /// them; vertex normals, colours as floats in [0, 1], and texture
    /// coordinates per triangle corner, Open3D's `triangle_uvs`), a
    /// `LineSet` for curves, or a `PointCloud` (with its colours).
    fn to_open3d<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let o3d = py.import("open3d")?;
        let (geometry, utility) = (o3d.getattr("geometry")?, o3d.getattr("utility")?);
        let numpy = py.import("numpy")?;
        // Open3D's vectors take float64 and int32 arrays.
        let as_type = |array: &Bound<'py, PyAny>, dtype: &str| -> PyResult<Bound<'py, PyAny>> {
            numpy.call_method1("ascontiguousarray", (array, numpy.getattr(dtype)?))
        };
        let vector3d =
            |array: &Bound<'py, PyAny>| utility.getattr("Vector3dVector")?.call1((as_type(array, "float64")?,));
        let vertices = vector3d(self.vertices.bind(py))?;
        let colours = |geometry: &Bound<'py, PyAny>, name: &str| -> PyResult<()> {
            if let Some(c) = &self.colours {
                let floats = c.bind(py).call_method1("__truediv__", (255.0,))?;
                geometry.setattr(name, vector3d(&floats)?)?;
            }
            Ok(())
        };
        let faces: Vec<Vec<i64>> = self.faces.bind(py).extract()?;
        let triangles: Vec<i32> =
            faces.iter().flat_map(|f| bcifs::render::fan(f, 0).flatten()).map(|i| i as i32).collect();
        if !triangles.is_empty() {
            let indices = utility.getattr("Vector3iVector")?.call1((matrix(py, triangles, 3),))?;
            let mesh = geometry.getattr("TriangleMesh")?.call1((vertices, indices))?;
            if let Some(n) = &self.normals {
                mesh.setattr("vertex_normals", vector3d(n.bind(py))?)?;
            }
            colours(&mesh, "vertex_colors")?;
            if let (Some(uv), Some(uv_faces)) = (&self.uv, &self.uv_faces) {
                let uv_faces: Vec<Vec<i64>> = uv_faces.bind(py).extract()?;
                let t: Vec<[f64; 2]> = uv.bind(py).extract()?;
                let corners = uv_faces.iter().flat_map(|f| bcifs::render::fan(f, 0).flatten());
                let per_corner: Vec<f64> = corners.flat_map(|k| t[k as usize]).collect();
                mesh.setattr("triangle_uvs", utility.getattr("Vector2dVector")?.call1((matrix(py, per_corner, 2),))?)?;
            }
            return Ok(mesh);
        }
        let edges = self.edges.bind(py);
        if edges.len()? > 0 {
            let lines = utility.getattr("Vector2iVector")?.call1((as_type(edges.as_any(), "int32")?,))?;
            return geometry.getattr("LineSet")?.call1((vertices, lines));
        }
        let cloud = geometry.getattr("PointCloud")?.call1((vertices,))?;
        if let Some(n) = &self.normals {
            cloud.setattr("normals", vector3d(n.bind(py))?)?;
        }
        colours(&cloud, "colors")?;
        Ok(cloud)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let faces = self.faces.bind(py).len().unwrap_or(0);
        format!(
            "<bcifs.Mesh: {} vertices, {} faces, {} edges>",
            self.vertices.bind(py).len().unwrap_or(0),
            faces,
            self.edges.bind(py).len().unwrap_or(0)
        )
    }
}
