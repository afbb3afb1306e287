//! The `bcifs` Python module (`bcifs._bcifs`, re-exported by the `bcifs`
//! package): designs loaded by name or path, evaluated into numpy arrays
//! and written in every format of the command line, through the library's
//! render API. Long calls release the GIL.

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use bcifs::render::{MeshJob, Options};
use bcifs::render::{PolyMesh, Scheme};
use cancel::{cancellable, cancellable_writing};

mod builder;
mod cancel;
mod fit;
mod mesh;
mod options;
use builder::Builder;
use mesh::{Arrays, Mesh, matrix};

pyo3::create_exception!(
    bcifs,
    BcifsError,
    PyValueError,
    "What bcifs refuses, with the library's message: an unknown name, a malformed file, a bad parameter, a divergent system."
);

pub(crate) fn err(e: impl std::fmt::Display) -> PyErr {
    BcifsError::new_err(e.to_string())
}

/// `**params` as `(name, value)` pairs.
fn params(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut out = Vec::new();
    if let Some(kwargs) = kwargs {
        for (k, v) in kwargs.iter() {
            let name = k.extract::<String>()?;
            let value = param_value(&name, &v)?;
            out.push((name, value));
        }
    }
    Ok(out)
}

/// A parameter's value: a number, or an exact one as `analyze_curve` takes
/// them (`"1/4"`, `Fraction(1, 4)`, `"sqrt(3)/6"`), as a float.
pub(crate) fn param_value(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    if let Ok(x) = v.extract::<f64>() {
        return Ok(x);
    }
    exact_value(v).map(|n| n.to_f64()).map_err(|e| err(format!("parameter `{name}`: {e}")))
}

/// A design: an automaton (states, arrows, constraints) with its model.
#[pyclass(module = "bcifs", frozen)]
pub struct Design {
    pub(crate) inner: bcifs::render::Design,
}

impl Design {
    /// Options from explicit keywords (`None`: unset) and `**params`, through the library's keys.
    fn options(
        py: Python<'_>,
        keywords: &[(&str, Option<&Bound<'_, PyAny>>)],
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Options> {
        let all = PyDict::new(py);
        for (k, v) in keywords {
            if let Some(v) = v {
                all.set_item(k, v)?;
            }
        }
        let mut options = options::options(Some(&all))?;
        options.params = self::params(params)?;
        Ok(options)
    }
}

#[pymethods]
impl Design {
    /// A design from the text of an automaton file.
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Design> {
        Ok(Design { inner: bcifs::render::parse_design(text, "<string>", "design").map_err(err)? })
    }

    /// The automaton file's text of this design.
    fn to_toml(&self) -> String {
        bcifs::render::write_design(&self.inner)
    }

    /// The design's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name().to_string()
    }

    /// The parameters the design declares (names of its families' free values).
    #[getter]
    fn parameters(&self) -> Vec<String> {
        self.inner.declared().to_vec()
    }

    /// The attractor evaluated `depth` subdivisions down (or until every
    /// cell is below `tolerance`), with the given parameter values, as a
    /// [`Mesh`]; `uv` gives surfaces texture coordinates (as `render
    /// --uv`), `force` evaluates a system whose bounds prove divergence,
    /// `thickness` makes a surface (a lace) a closed shell (as `render --thickness`);
    /// `dtype=numpy.float32` gives float32 vertices and normals (as Open3D and
    /// trimesh users keep them); `colour` (`"state"`, `"level"`, `"map"`) with
    /// `palette` colours the vertices as the files have them (`colours`, uint8).
    #[pyo3(signature = (depth=None, tolerance=None, uv=None, force=None, thickness=None, dtype=None, colour=None, palette=None, **params))]
    #[allow(clippy::too_many_arguments)]
    fn mesh(
        &self,
        py: Python<'_>,
        depth: Option<&Bound<'_, PyAny>>,
        tolerance: Option<&Bound<'_, PyAny>>,
        uv: Option<&Bound<'_, PyAny>>,
        force: Option<&Bound<'_, PyAny>>,
        thickness: Option<&Bound<'_, PyAny>>,
        dtype: Option<&Bound<'_, PyAny>>,
        colour: Option<&Bound<'_, PyAny>>,
        palette: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Mesh> {
        let keywords = [
            ("depth", depth),
            ("tolerance", tolerance),
            ("uv", uv),
            ("force", force),
            ("thickness", thickness),
            ("colour", colour),
            ("palette", palette),
        ];
        let options = Design::options(py, &keywords, params)?;
        let design = self.inner.clone();
        let arrays = cancellable(py, None, move |cancel, _| {
            let shape = bcifs::render::evaluate_design(&design, &options.with_cancel(cancel), &mut Vec::new())?;
            Ok::<_, bcifs::render::RenderError>(Arrays::of_shape(shape))
        })?
        .map_err(err)?;
        arrays.into_mesh_as(py, dtype)
    }

    /// The print report of the mesh `render` writes (as `render --json`):
    /// `volume`, `area`, `bbox`, `components`, `closed`, `oriented`, `euler`,
    /// `genus`, `triangles`, `vertices`, `manifold`, `scale` (mm per model
    /// unit) and `warnings` (what a slicer will not like, with its place);
    /// `thickness` measures a lace's shell; `print_size` (the longest side,
    /// mm) or `print_scale` (mm per unit) give the figures in millimetres,
    /// `nozzle` (mm) the walls and holes warned of.
    #[pyo3(signature = (depth=None, tolerance=None, thickness=None, print_size=None, print_scale=None, nozzle=None, **params))]
    #[allow(clippy::too_many_arguments)] // pyo3 keyword parameters are spelled out
    fn print_report<'py>(
        &self,
        py: Python<'py>,
        depth: Option<&Bound<'py, PyAny>>,
        tolerance: Option<&Bound<'py, PyAny>>,
        thickness: Option<&Bound<'py, PyAny>>,
        print_size: Option<&Bound<'py, PyAny>>,
        print_scale: Option<&Bound<'py, PyAny>>,
        nozzle: Option<&Bound<'py, PyAny>>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let keywords = [
            ("depth", depth),
            ("tolerance", tolerance),
            ("thickness", thickness),
            ("print_size", print_size),
            ("print_scale", print_scale),
            ("nozzle", nozzle),
        ];
        let options = Design::options(py, &keywords, params)?;
        let design = self.inner.clone();
        let report =
            cancellable(py, None, move |cancel, _| bcifs::render::print_report(&design, &options.with_cancel(cancel)))?
                .map_err(err)?;
        json_object(py, &report)
    }

    /// `samples` points of the chaos game (from `seed`: by default the
    /// command line's), an (n, 3) array.
    #[pyo3(signature = (samples, seed=None, **params))]
    fn points(
        &self,
        py: Python<'_>,
        samples: &Bound<'_, PyAny>,
        seed: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyArray2<f64>>> {
        let options = Design::options(py, &[("samples", Some(samples)), ("seed", seed)], params)?;
        let design = self.inner.clone();
        let points = cancellable(py, None, move |cancel, _| {
            let shape = bcifs::render::evaluate_design(&design, &options.with_cancel(cancel.clone()), &mut Vec::new())?;
            // In 3D, a chunk at a time: an interrupt stops the copy too.
            let mut points = Vec::with_capacity(3 * shape.vertex_count());
            let n = shape.vertex_count();
            for from in (0..n).step_by(1 << 20) {
                if cancel.is_cancelled() {
                    return Err(bcifs::render::RenderError::Cancelled);
                }
                points.extend((from..n.min(from + (1 << 20))).flat_map(|i| shape.point(i)));
            }
            Ok(points)
        })?
        .map_err(err)?;
        Ok(matrix(py, points, 3))
    }

    /// The density picture of `samples` chaos-game points, an (h, w, 3)
    /// uint8 array: the pixels of `render(path.png, samples=samples, ...)`.
    #[pyo3(signature = (samples, size=None, seed=None, palette=None, **params))]
    fn density<'py>(
        &self,
        py: Python<'py>,
        samples: &Bound<'py, PyAny>,
        size: Option<&Bound<'py, PyAny>>,
        seed: Option<&Bound<'py, PyAny>>,
        palette: Option<&Bound<'py, PyAny>>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let keywords = [("samples", Some(samples)), ("size", size), ("seed", seed), ("palette", palette)];
        let options = Design::options(py, &keywords, params)?;
        let design = self.inner.clone();
        let img =
            cancellable(py, None, move |cancel, _| bcifs::render::density(&design, &options.with_cancel(cancel)))?
                .map_err(err)?;
        let (w, h) = img.dimensions();
        Ok(Array3::from_shape_vec((h as usize, w as usize, 3), img.into_raw()).expect("h × w × 3").into_pyarray(py))
    }

    /// Writes the design to `path`, the format chosen by its extension (every
    /// format of `bcifs render`), with the options of `bcifs render` as
    /// keywords (`bcifs.option_keys()` lists them: the library's one
    /// description of the command line's flags): `depth` or `tolerance`;
    /// `samples` runs the chaos game (`seed`, `probs` {arrow: p}, `drop`
    /// [arrows]); `size` (w, h), `view` (yaw, pitch), `palette`,
    /// `brightness`, `gamma`… of pictures (or `tone` {brightness, …});
    /// `up`, `ascii`, `precision` of files; `threads`, `memory_mib`,
    /// `max_output_gib`. The other keywords are the design's parameters (or
    /// `params` {name: value}, for a parameter named as an option).
    /// `progress` is called with `(done, total)` as the
    /// work goes. Returns the report as a dict (format, vertices, faces,
    /// bytes, warnings, notes). Ctrl-C stops it within a tenth of a second
    /// and leaves no file.
    #[pyo3(signature = (path, progress=None, **options))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        path: std::path::PathBuf,
        progress: Option<&Bound<'py, PyAny>>,
        options: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let options = options::options(options)?;
        let design = self.inner.clone();
        let report = cancellable_writing(py, progress, move |cancel, reporter| {
            let mut options = options.with_cancel(cancel);
            options.progress = reporter;
            bcifs::render::render(&design, &options, &path)
        })?
        .map_err(err)?;
        report_dict(py, &report)
    }

    /// The free parameters with their defaults and the interval around
    /// each where the bounds prove convergence (the others at their
    /// defaults): `[{"name", "default", "range": (lo, hi)}]`, a slider's range.
    fn ranges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let design = self.inner.clone();
        let ranges = cancellable(py, None, move |_, _| bcifs::render::parameter_ranges(&design))?.map_err(err)?;
        let list = PyList::empty(py);
        for r in ranges {
            let d = PyDict::new(py);
            d.set_item("name", r.name)?;
            d.set_item("default", r.default)?;
            d.set_item("range", r.range)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The solved family: the object `bcifs solve --json` prints (a dict:
    /// `consistent`, `dof`, `parameters`, exact `matrices`, or `conflicts`).
    fn solve<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let design = &self.inner;
        let report = py.detach(|| bcifs::render::solve_report(design)).map_err(err)?;
        json_object(py, &report)
    }

    /// The check at the given parameter values: the object `bcifs check
    /// --json` prints (constraints' residuals, spectra, JSR bounds, verdict).
    #[pyo3(signature = (**params))]
    fn check<'py>(&self, py: Python<'py>, params: Option<&Bound<'py, PyDict>>) -> PyResult<Bound<'py, PyAny>> {
        let values = self::params(params)?;
        let design = &self.inner;
        let report = py.detach(|| bcifs::render::check_report(design, &values)).map_err(err)?;
        json_object(py, &report)
    }

    /// A 400 × 400 picture, for Jupyter: the PNG `render` writes, made in memory.
    fn _repr_png_(&self, py: Python<'_>) -> PyResult<Vec<u8>> {
        let options = Options::default().with_size(400, 400);
        let design = &self.inner;
        let (_, png) = py
            .detach(|| bcifs::render::picture_png(design, &options, bcifs::render::Compression::Small))
            .map_err(err)?;
        Ok(png)
    }

    fn __repr__(&self) -> String {
        format!("<bcifs.Design {:?}: {}>", self.inner.name(), self.inner.description())
    }
}

/// A report as the dict `json.loads` makes of the JSON the CLI prints.
pub(crate) fn json_object<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

fn report_dict<'py>(py: Python<'py>, report: &bcifs::render::Report) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("format", report.format.map(|f| f.extension()))?;
    d.set_item("vertices", report.vertices)?;
    d.set_item("faces", report.faces)?;
    d.set_item("bytes", report.bytes)?;
    d.set_item("depth", report.depth)?;
    d.set_item("warnings", report.warnings.clone())?;
    d.set_item("notes", report.notes.clone())?;
    // A print file's print report (STL, 3MF), in millimetres.
    if let Some(print) = &report.print {
        d.set_item("print", json_object(py, print)?)?;
    }
    Ok(d)
}

/// Index lists (an (m, k) array or a list of sequences) as `usize`s, refusing negative ones.
fn index_lists(faces: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<usize>>> {
    faces
        .extract::<Vec<Vec<i64>>>()?
        .into_iter()
        .map(|f| {
            f.into_iter()
                .map(|i| usize::try_from(i).map_err(|_| err(format!("a face index is negative: {i}"))))
                .collect()
        })
        .collect()
}

/// A design by name (a shipped automaton or scheme preset) or path; a
/// polygon mesh file (OBJ, OFF) with `scheme` (`doo-sabin`,
/// `catmull-clark`, `loop`, `sqrt3`): the automaton it generates, as
/// `bcifs surface FILE --scheme S --print` writes it.
#[pyfunction]
#[pyo3(signature = (name_or_path, scheme=None))]
fn load(name_or_path: std::path::PathBuf, scheme: Option<&str>) -> PyResult<Design> {
    // A name or a path: `str` and `os.PathLike` both (pathlib's paths as `render` takes them).
    let name_or_path = name_or_path.to_string_lossy();
    let scheme = scheme.map(scheme_of).transpose()?;
    Ok(Design { inner: bcifs::render::load_with_scheme(&name_or_path, scheme).map_err(err)? })
}

/// A subdivision scheme by name (`_` for `-` accepted).
fn scheme_of(name: &str) -> PyResult<Scheme> {
    Scheme::from_name(&name.replace('_', "-"))
        .ok_or_else(|| err(format!("unknown scheme `{name}`: doo-sabin, catmull-clark, loop or sqrt3")))
}

/// A user's polygon mesh (`vertices` (n, 3), any array-like of numbers:
/// float32, lists; `faces` an (m, k) array or a list of index sequences;
/// `triangulate=True` splits each face into a fan of triangles first, for
/// Loop and √3 on quads) subdivided `depth` times by `scheme`
/// (`doo-sabin`, `catmull-clark`, `loop`, `sqrt3`): the limit surface, or
/// the control net with `net=True`; `weights` the rule weights (`alpha`,
/// `beta`, `gamma` for Doo-Sabin, `w`, `sigma` for Loop). The same mesh as
/// `bcifs surface` on that mesh written as OBJ. Texture coordinates `uv`
/// (t, 2) with `uv_faces` (shaped as `faces`, indexing `uv`) follow
/// Catmull-Clark and Loop with linear seams, as in the files: the result's
/// `uv` and `uv_faces`. Per-face data follows the scheme: `face_data`
/// (name → an array with one row per input face: a material index, a
/// group, a colour) comes back in the result's `face_data`, each face's rows
/// from the face it comes from (`face_sources`; Doo-Sabin's and √3's faces
/// of edges and vertices, which span several faces, from the lowest).
#[pyfunction]
#[pyo3(signature = (vertices, faces, scheme, depth, net=false, uv=None, uv_faces=None, triangulate=false, face_data=None, **weights))]
#[allow(clippy::too_many_arguments)]
fn subdivide(
    py: Python<'_>,
    vertices: numpy::PyArrayLike2<'_, f64, numpy::AllowTypeChange>,
    faces: &Bound<'_, PyAny>,
    scheme: &str,
    depth: usize,
    net: bool,
    uv: Option<numpy::PyArrayLike2<'_, f64, numpy::AllowTypeChange>>,
    uv_faces: Option<&Bound<'_, PyAny>>,
    triangulate: bool,
    face_data: Option<&Bound<'_, PyDict>>,
    weights: Option<&Bound<'_, PyDict>>,
) -> PyResult<Mesh> {
    let v = vertices.as_array();
    if v.ncols() != 3 {
        return Err(err(format!("vertices must be an (n, 3) array, not (n, {})", v.ncols())));
    }
    let positions: Vec<[f64; 3]> = v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let faces = index_lists(faces)?;
    let scheme = scheme_of(scheme)?;
    let mut mesh = PolyMesh::new(positions, faces).map_err(err)?;
    match (uv, uv_faces) {
        (Some(uv), Some(uv_faces)) => {
            let t = uv.as_array();
            if t.ncols() != 2 {
                return Err(err(format!("uv must be a (t, 2) array, not (t, {})", t.ncols())));
            }
            let uvs: Vec<[f64; 2]> = t.rows().into_iter().map(|r| [r[0], r[1]]).collect();
            let corners: Vec<usize> = index_lists(uv_faces)?.concat();
            mesh = mesh.with_texture(uvs, corners).map_err(|e| err(format!("uv_faces: {e}")))?;
        }
        (None, None) => {}
        _ => return Err(err("give uv and uv_faces together")),
    }
    if let Some(data) = face_data {
        check_face_data(data, mesh.face_count())?;
    }
    // Per triangle of the split, the face it splits (the fan of a face of k corners: k − 2 triangles).
    let split: Option<Vec<u32>> = triangulate.then(|| {
        (0..mesh.face_count() as u32)
            .flat_map(|f| std::iter::repeat_n(f, mesh.face(f as usize).len().saturating_sub(2)))
            .collect()
    });
    // Loop and √3 on a quad mesh: each face a fan of triangles first (as `bcifs surface --triangulate`).
    if triangulate {
        mesh = mesh.triangulated();
    }
    let weights = bcifs::render::rule_weights(scheme, &params(weights)?).map_err(err)?;
    if let Some(why) = bcifs::render::check_weights(&mesh, weights).map_err(err)? {
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &std::ffi::CString::new(why).unwrap_or_default(),
            1,
        )?;
    }
    let job = MeshJob { weights, net, ..MeshJob::new(scheme, depth) };
    let want_sources = face_data.is_some();
    let arrays = cancellable(py, None, move |cancel, _| {
        let options = Options::default().with_cancel(cancel);
        let out = bcifs::render::subdivide_mesh(&mesh, &job, &options)?;
        let sources = want_sources.then(|| {
            let sources = bcifs::render::face_sources(&mesh, &job);
            match &split {
                Some(split) => sources.into_iter().map(|t| split[t as usize]).collect(),
                None => sources,
            }
        });
        Ok::<_, bcifs::render::RenderError>(Arrays::of_polymesh(out, sources))
    })?
    .map_err(err)?;
    let mesh = arrays.into_mesh(py)?;
    match face_data {
        Some(data) => mesh.with_face_data(py, data),
        None => Ok(mesh),
    }
}

/// Every array of `face_data` has one row per input face (`faces` of them).
fn check_face_data(data: &Bound<'_, PyDict>, faces: usize) -> PyResult<()> {
    for (name, values) in data.iter() {
        let rows =
            values.len().map_err(|_| err(format!("face_data[{name}]: expected an array with a row per face")))?;
        if rows != faces {
            return Err(err(format!("face_data[{name}] has {rows} rows for {faces} faces: one row per face")));
        }
    }
    Ok(())
}

/// The dimensions of a design's attractor at the given parameter values:
/// the object `bcifs analyze dimension --json` prints (box-counting
/// dimension and its fit, similarity dimension, open set condition).
#[pyfunction]
#[pyo3(signature = (design, **params))]
fn dimension<'py>(
    py: Python<'py>,
    design: &Design,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let values = self::params(params)?;
    let inner = &design.inner;
    let report = py.detach(|| bcifs::render::dimension_report(inner, &values)).map_err(err)?;
    json_object(py, &report.to_json())
}

/// The topology of a design's depth-`depth` cells: the object `bcifs analyze
/// topology --json` prints (`cells`, `components`, `euler`, `betti` [b0, b1,
/// b2], `pinches`).
#[pyfunction]
#[pyo3(signature = (design, depth=3, **params))]
fn topology<'py>(
    py: Python<'py>,
    design: &Design,
    depth: usize,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    report_at(py, design, params, |d, v| bcifs::render::topology_report(d, v, depth))
}

/// Porosity per depth (1 to `depth`: 5 by default, 4 for a solid) and the
/// gliding-box lacunarity curve at `depth`: the object `bcifs analyze lacunarity --json` prints
/// (`porosity`, `lacunarity` as `[r, Λ(r)]` pairs).
#[pyfunction]
#[pyo3(signature = (design, depth=None, **params))]
fn lacunarity<'py>(
    py: Python<'py>,
    design: &Design,
    depth: Option<usize>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    report_at(py, design, params, |d, v| {
        bcifs::render::lacunarity_report(d, v, depth.unwrap_or_else(|| bcifs::render::lacunarity_depth(d)))
    })
}

/// A report on `design` at the parameters `params`, the GIL released, as the dict of its JSON.
fn report_at<'py, R: serde::Serialize + Send>(
    py: Python<'py>,
    design: &Design,
    params: Option<&Bound<'py, PyDict>>,
    report: impl FnOnce(&bcifs::render::Design, &[(String, f64)]) -> Result<R, bcifs::render::ReportError> + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let values = self::params(params)?;
    let inner = &design.inner;
    let r = py.detach(|| report(inner, &values)).map_err(err)?;
    json_object(py, &r)
}

/// The automaton of a subdivision pattern (as `bcifs new pattern`): `cell`
/// (`"segment"`, `"quad"`, `"triangle"`, `"hexahedron"`, `"tetrahedron"`),
/// `split` (`3`, `"3x3"`, `(3, 3, 3)`; 2 for a tetrahedron), `keep`
/// (`"111101111"` or a sequence of 0/1 or booleans, u fastest, then v, then
/// w; all kept when `None`), `degree` (control points per direction, 2 to 4),
/// `at` (where the default member splits each direction: `"2/5,3/5"`, or a
/// sequence of numbers, `str`s or `Fraction`s; uniform when `None`),
/// `basis` (`"bezier"`: the family of unknown matrices; `"bspline"`: a
/// hexahedron's uniform B-spline, fixed matrices, `degree=4` the tricubic volume).
#[pyfunction]
#[pyo3(signature = (cell, split, keep=None, degree=2, name="pattern", at=None, basis="bezier"))]
#[allow(clippy::too_many_arguments)]
fn pattern(
    cell: &str,
    split: &Bound<'_, PyAny>,
    keep: Option<&Bound<'_, PyAny>>,
    degree: usize,
    name: &str,
    at: Option<&Bound<'_, PyAny>>,
    basis: &str,
) -> PyResult<Design> {
    use bcifs::render::{Pattern, PatternCell};
    let cell = PatternCell::named(cell).ok_or_else(|| {
        err(format!("cell=`{cell}`: expected \"segment\", \"quad\", \"triangle\", \"hexahedron\" or \"tetrahedron\""))
    })?;
    let split: String = match split.extract::<String>() {
        Ok(text) => text,
        Err(_) => match split.extract::<usize>() {
            Ok(k) => k.to_string(),
            Err(_) => split
                .extract::<Vec<usize>>()
                .map_err(|_| err("split=: expected 3, \"3x3\" or (3, 3)"))?
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("x"),
        },
    };
    let keep: Option<String> = match keep {
        None => None,
        Some(k) => Some(match k.extract::<String>() {
            Ok(text) => text,
            Err(_) => k
                .extract::<Vec<bool>>()
                .or_else(|_| k.extract::<Vec<u8>>().map(|v| v.into_iter().map(|x| x != 0).collect()))
                .map_err(|_| err("keep=: expected \"111101111\" or a sequence of 0s and 1s"))?
                .into_iter()
                .map(|b| if b { '1' } else { '0' })
                .collect(),
        }),
    };
    let basis = bcifs::render::Basis::named(basis)
        .ok_or_else(|| err(format!("basis=`{basis}`: expected \"bezier\" or \"bspline\"")))?;
    let mut pattern = Pattern::parse_in(cell, &split, keep.as_deref(), degree, basis).map_err(err)?;
    if let Some(at) = at {
        let text = match at.extract::<String>() {
            Ok(text) => text,
            Err(_) => at
                .try_iter()?
                .map(|v| -> PyResult<String> { Ok(exact_value(&v?).map_err(|e| err(format!("at: {e}")))?.to_string()) })
                .collect::<PyResult<Vec<_>>>()?
                .join(","),
        };
        pattern = pattern.with_at(&text).map_err(err)?;
    }
    Ok(Design { inner: pattern.design(name).map_err(err)? })
}

/// The lacunar polygon of a polyhedron's circle packing (as `bcifs new
/// polyhedron`): `polyhedron` is a name (`"tetrahedron"`, `"cube"`,
/// `"octahedron"`, `"dodecahedron"`, `"icosahedron"`, `"prism"`,
/// `"pyramid"`), an OBJ or OFF file (`str` or path), or the faces as
/// sequences of vertex numbers (oriented alike); `face` the face whose gap
/// is the polygon; `name` the design's (default: the polyhedron's, `_lace` added).
#[pyfunction]
#[pyo3(signature = (polyhedron, face=0, name=None))]
fn polyhedral_lace(polyhedron: &Bound<'_, PyAny>, face: usize, name: Option<&str>) -> PyResult<Design> {
    use bcifs::render::Polyhedron;
    let p = if let Ok(text) = polyhedron.extract::<std::path::PathBuf>() {
        Polyhedron::named_or_read(&text.to_string_lossy()).map_err(err)?
    } else {
        let faces: Vec<Vec<usize>> = polyhedron.extract().map_err(|_| {
            err("polyhedron=: expected a name (\"cube\"), an OBJ or OFF file, or faces as sequences of vertex numbers")
        })?;
        Polyhedron::from_faces(faces).map_err(err)?
    };
    let name = name.map_or_else(|| format!("{}_lace", p.name()), str::to_string);
    Ok(Design { inner: bcifs::render::polyhedral_lace(&p, face, &name).map_err(err)? })
}

/// A parameter value read exactly: a `str` (`"1/20"`, `"sqrt(2)/4"`), a
/// `Fraction`, an int, or a float read as its shortest decimal (`0.05` is 1/20).
/// An exact value: a float as written, a fraction, or the text of an exact
/// number; the error is the message alone (the caller names the parameter).
fn exact_value(v: &Bound<'_, PyAny>) -> Result<bcifs::render::Num, String> {
    let text = if v.is_instance_of::<pyo3::types::PyFloat>() {
        let x: f64 = v.extract().map_err(|e: PyErr| e.to_string())?;
        return Ok(bcifs::render::Num::from_f64(x));
    } else if v.hasattr("numerator").unwrap_or(false) && v.hasattr("denominator").unwrap_or(false) {
        let part = |n: &str| v.getattr(n).map(|x| x.to_string()).unwrap_or_default();
        format!("{}/{}", part("numerator"), part("denominator"))
    } else if v.is_instance_of::<pyo3::types::PyString>() {
        v.to_string()
    } else {
        return Err(format!("expected a number or an exact one such as \"1/4\", not a {}", type_name(v)));
    };
    text.parse::<bcifs::render::Num>().map_err(|e| e.to_string())
}

/// The Python type name of `v` (`list`, `NoneType`).
fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "value".into())
}

/// A curve family's differential behaviour at the given parameter values
/// (Sokolov et al. 2010 §4): the object `bcifs analyze curve --json` prints
/// (convergence, eigenvalues, half-tangents, junction angle, region of
/// Fig. 8, and the exact answers when the halves are rational 3 × 3).
/// Values are read exactly: `a="1/20"`, `a=Fraction(1, 20)` and `a=0.05`
/// are the same point.
#[pyfunction]
#[pyo3(signature = (design, **params))]
fn analyze_curve<'py>(
    py: Python<'py>,
    design: &Design,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut values = Vec::new();
    if let Some(params) = params {
        for (k, v) in params.iter() {
            values.push((k.extract::<String>()?, exact_value(&v).map_err(|e| err(format!("parameter `{k}`: {e}")))?));
        }
    }
    let inner = &design.inner;
    let analysis = py.detach(|| bcifs::render::curve_analysis(inner, &values)).map_err(err)?;
    json_object(py, &analysis.to_json())
}

/// The rows `rows` of a parameter sweep of the design in `toml` (a band of
/// `bcifs.sweep`'s array, bit for bit): `x` and `y` are `(name, lo, hi,
/// n)`; `what` is `verdict` (int8: 1 converges, 0 undecided, -1 diverges,
/// -2 a matrix fails the per-matrix condition), `region` (int8, an index
/// into `bcifs.REGIONS`), `angle` or `dimension` (float64, NaN where none).
#[pyfunction]
#[pyo3(signature = (toml, x, y, rows, what="verdict", thorough=false))]
fn sweep_rows<'py>(
    py: Python<'py>,
    toml: &str,
    x: (String, f64, f64, usize),
    y: (String, f64, f64, usize),
    rows: (usize, usize),
    what: &str,
    thorough: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use bcifs::render::{SweepKind, SweepValues};
    let kind: SweepKind = what.parse().map_err(err)?;
    let design = bcifs::render::parse_design(toml, "<sweep>", "design").map_err(err)?;
    let plane = bcifs::render::ParameterPlane { x: (x.0, x.1, x.2), y: (y.0, y.1, y.2), size: (x.3, y.3) };
    let width = plane.size.0;
    let values = cancellable(py, None, move |cancel, _| {
        bcifs::render::sweep_cancellable(&design, &plane, kind, thorough, rows.0..rows.1, &cancel)
    })?
    .map_err(err)?;
    Ok(match values {
        SweepValues::Codes(c) => matrix(py, c, width).into_bound(py).into_any(),
        SweepValues::Values(v) => matrix(py, v, width).into_bound(py).into_any(),
    })
}

/// The colours of a map's values (`what` as for `sweep`): an `(rows, columns, 3)` uint8 array of
/// sRGB bytes, the palette `bcifs analyze map` and the explorer draw with.
#[pyfunction]
#[pyo3(signature = (values, what="verdict"))]
fn map_colours<'py>(py: Python<'py>, values: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyAny>> {
    let kind: bcifs::render::SweepKind = what.parse().map_err(err)?;
    let numpy = py.import("numpy")?;
    let values = numpy.call_method1("asarray", (values, "float64"))?;
    let ndim: usize = values.getattr("ndim")?.extract()?;
    if ndim != 2 {
        return Err(BcifsError::new_err(format!("values: a 2-D array (rows, columns) of a sweep; got {ndim}-D")));
    }
    let array: PyReadonlyArray2<f64> = values.extract()?;
    let view = array.as_array();
    let (rows, columns) = view.dim();
    let mut out = Array3::<u8>::zeros((rows, columns, 3));
    for ((r, c), &v) in view.indexed_iter() {
        let rgb = bcifs::render::sweep_colour(kind, v);
        for (k, &byte) in rgb.iter().enumerate() {
            out[(r, c, k)] = byte;
        }
    }
    Ok(out.into_pyarray(py).into_any())
}

/// The module.
#[pymodule]
fn _bcifs(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("BcifsError", m.py().get_type::<BcifsError>())?;
    // The package's version (maturin takes it from this crate's).
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<Design>()?;
    m.add_class::<Mesh>()?;
    m.add_class::<Builder>()?;
    m.add_function(wrap_pyfunction!(analyze_curve, m)?)?;
    m.add("REGIONS", bcifs::render::REGIONS.to_vec())?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(options::option_keys, m)?)?;
    m.add_function(wrap_pyfunction!(options::profile, m)?)?;
    m.add_function(wrap_pyfunction!(subdivide, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_starts, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_rows, m)?)?;
    m.add_function(wrap_pyfunction!(dimension, m)?)?;
    m.add_function(wrap_pyfunction!(topology, m)?)?;
    m.add_function(wrap_pyfunction!(pattern, m)?)?;
    m.add_function(wrap_pyfunction!(polyhedral_lace, m)?)?;
    m.add_function(wrap_pyfunction!(lacunarity, m)?)?;
    m.add_function(wrap_pyfunction!(map_colours, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
