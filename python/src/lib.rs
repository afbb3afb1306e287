//! The `bcifs` Python module (`bcifs._bcifs`, re-exported by the `bcifs`
//! package): designs loaded by name or path, evaluated into numpy arrays
//! and written in every format of the command line, through the library's
//! render API. Long calls release the GIL.

use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use bcifs::eval::{Depth, RandomSettings};
use bcifs::geometry::Shape;
use bcifs::mesh::{PolyMesh, Scheme};
use bcifs::render::{MeshJob, Options};

pyo3::create_exception!(
    bcifs,
    BcifsError,
    PyValueError,
    "What bcifs refuses, with the library's message: an unknown name, a malformed file, a bad parameter, a divergent system."
);

fn err(e: impl std::fmt::Display) -> PyErr {
    BcifsError::new_err(e.to_string())
}

/// `**params` as `(name, value)` pairs.
fn params(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut out = Vec::new();
    if let Some(kwargs) = kwargs {
        for (k, v) in kwargs.iter() {
            out.push((
                k.extract::<String>()?,
                v.extract::<f64>().map_err(|_| err(format!("parameter `{k}` must be a number")))?,
            ));
        }
    }
    Ok(out)
}

/// Runs `work` on a worker thread, the GIL released, while this thread
/// forwards its progress to `progress` (a callable taking `done, total`:
/// tqdm's `update` fits through a small lambda) and checks for Ctrl-C every
/// 100 ms: on KeyboardInterrupt the work is cancelled through the
/// [`bcifs::Cancel`] it was given (no file is left) and the exception raised.
fn cancellable<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(bcifs::Cancel, Option<bcifs::Progress>) -> T + Send,
) -> PyResult<T> {
    let cancel = bcifs::Cancel::new();
    let (tx, rx) = std::sync::mpsc::channel::<(u64, u64)>();
    let reporter = progress.is_some().then(|| {
        let tx = std::sync::Mutex::new(tx);
        bcifs::Progress::new(move |done, total| {
            let _ = tx.lock().map(|t| t.send((done, total)));
        })
    });
    let rx = std::sync::Mutex::new(rx);
    std::thread::scope(|scope| {
        let worker_cancel = cancel.clone();
        let handle = scope.spawn(move || work(worker_cancel, reporter));
        let mut interrupted = None;
        while !handle.is_finished() {
            let wait = std::time::Duration::from_millis(100);
            let message = py.detach(|| rx.lock().ok().and_then(|r| r.recv_timeout(wait).ok()));
            if let (Some((done, total)), Some(callback)) = (message, progress)
                && interrupted.is_none()
                && let Err(e) = callback.call1((done, total))
            {
                cancel.cancel();
                interrupted = Some(e);
            }
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.cancel();
                interrupted = Some(e);
            }
        }
        let result = py.detach(|| handle.join()).map_err(|_| err("the computation panicked"))?;
        match interrupted {
            Some(e) => Err(e),
            None => Ok(result),
        }
    })
}

/// A design: an automaton (states, arrows, constraints) with its model.
#[pyclass(module = "bcifs", frozen)]
pub struct Design {
    inner: bcifs::Design,
}

/// A mesh as numpy arrays: `vertices` (n, 3) float64, `faces` (m, k) int64
/// when every face has k corners (else a list of arrays), `edges` (e, 2)
/// int64 for curves, `normals` (n, 3) and `colours` (n, 3) uint8 when present.
#[pyclass(module = "bcifs", frozen, get_all)]
pub struct Mesh {
    vertices: Py<PyArray2<f64>>,
    faces: Py<PyAny>,
    edges: Py<PyArray2<i64>>,
    normals: Option<Py<PyArray2<f64>>>,
    colours: Option<Py<PyArray2<u8>>>,
}

/// `values` as an (n, k) array.
fn matrix<T: numpy::Element>(py: Python<'_>, values: Vec<T>, k: usize) -> Py<PyArray2<T>> {
    let n = values.len().checked_div(k).unwrap_or(0);
    Array2::from_shape_vec((n, k), values).expect("n × k values").into_pyarray(py).unbind()
}

/// Faces as one (m, k) array when they all have k corners, a list of arrays otherwise.
fn faces_of(py: Python<'_>, faces: Vec<Vec<i64>>) -> PyResult<Py<PyAny>> {
    let k = faces.first().map_or(3, Vec::len);
    if faces.iter().all(|f| f.len() == k) {
        return Ok(matrix(py, faces.concat(), k).into_any());
    }
    let list = PyList::empty(py);
    for f in faces {
        list.append(f.into_pyarray(py))?;
    }
    Ok(list.into_any().unbind())
}

impl Mesh {
    fn of_shape(py: Python<'_>, shape: &Shape) -> PyResult<Mesh> {
        let n = shape.vertex_count();
        let vertices: Vec<f64> = (0..n).flat_map(|i| shape.point(i)).collect();
        let mut faces: Vec<Vec<i64>> = shape.quads.iter().map(|q| q.iter().map(|&v| i64::from(v)).collect()).collect();
        faces.extend(shape.triangles.iter().map(|t| t.iter().map(|&v| v as i64).collect()));
        let mut edges = Vec::new();
        for (first, count, closed) in shape.polylines() {
            let segments = if closed && count > 2 { count } else { count.saturating_sub(1) };
            for k in 0..segments {
                edges.extend([(first + k) as i64, (first + (k + 1) % count) as i64]);
            }
        }
        Ok(Mesh {
            vertices: matrix(py, vertices, 3),
            faces: faces_of(py, faces)?,
            edges: matrix(py, edges, 2),
            normals: (shape.normals.len() == 3 * n && n > 0).then(|| matrix(py, shape.normals.clone(), 3)),
            colours: (shape.colours.len() == n && n > 0).then(|| matrix(py, shape.colours.concat(), 3)),
        })
    }

    fn of_polymesh(py: Python<'_>, mesh: &PolyMesh) -> PyResult<Mesh> {
        let faces = mesh.faces().map(|f| f.iter().map(|&v| v as i64).collect()).collect();
        let normals = bcifs::geometry::area_normals(&mesh.positions, mesh.faces());
        Ok(Mesh {
            vertices: matrix(py, mesh.positions.concat(), 3),
            faces: faces_of(py, faces)?,
            edges: matrix(py, Vec::new(), 2),
            normals: Some(matrix(py, normals.concat(), 3)),
            colours: None,
        })
    }
}

#[pymethods]
impl Mesh {
    /// The mesh as trimesh has it (trimesh must be installed): a `Trimesh`
    /// (faces fanned into triangles, normals and colours kept), a `Path3D`
    /// for curves, or a `PointCloud`.
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = py.import("trimesh")?;
        let faces = self.faces.bind(py);
        let mut triangles: Vec<i64> = Vec::new();
        for face in faces.try_iter()? {
            let f: Vec<i64> = face?.extract()?;
            for i in 1..f.len().saturating_sub(1) {
                triangles.extend([f[0], f[i], f[i + 1]]);
            }
        }
        let vertices = self.vertices.bind(py);
        if !triangles.is_empty() {
            let kwargs = PyDict::new(py);
            kwargs.set_item("vertices", vertices)?;
            kwargs.set_item("faces", matrix(py, triangles, 3))?;
            kwargs.set_item("vertex_normals", self.normals.as_ref().map(|n| n.bind(py)))?;
            kwargs.set_item("vertex_colors", self.colours.as_ref().map(|c| c.bind(py)))?;
            kwargs.set_item("process", false)?;
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

impl Design {
    fn options(
        &self,
        depth: Option<usize>,
        tolerance: Option<f64>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Options> {
        let mut options = Options { params: params(kwargs)?, ..Options::default() };
        options.eval.depth = match (depth, tolerance) {
            (Some(_), Some(_)) => return Err(err("give depth or tolerance, not both")),
            (_, Some(eps)) => Depth::Tolerance(eps),
            (Some(k), None) => Depth::Fixed(k),
            (None, None) => options.eval.depth,
        };
        Ok(options)
    }
}

#[pymethods]
impl Design {
    /// A design from the text of an automaton file.
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Design> {
        Ok(Design { inner: bcifs::parse_design(text, "<string>", "design").map_err(err)? })
    }

    /// The automaton file's text of this design.
    fn to_toml(&self) -> String {
        bcifs::write_design(&self.inner)
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
    /// cell is below `tolerance`), with the given parameter values, as a [`Mesh`].
    #[pyo3(signature = (depth=None, tolerance=None, **params))]
    fn mesh(
        &self,
        py: Python<'_>,
        depth: Option<usize>,
        tolerance: Option<f64>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Mesh> {
        let options = self.options(depth, tolerance, params)?;
        let design = &self.inner;
        let shape = py.detach(|| bcifs::render::evaluate_design(design, &options, &mut Vec::new())).map_err(err)?;
        Mesh::of_shape(py, &shape)
    }

    /// `samples` points of the chaos game (seed `seed`), an (n, 3) array.
    #[pyo3(signature = (samples, seed=0, **params))]
    fn points(
        &self,
        py: Python<'_>,
        samples: usize,
        seed: u64,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyArray2<f64>>> {
        let mut options = self.options(None, None, params)?;
        options.random = Some(RandomSettings::default().with_points(samples).with_seed(seed));
        let design = &self.inner;
        let shape = py.detach(|| bcifs::render::evaluate_design(design, &options, &mut Vec::new())).map_err(err)?;
        let n = shape.vertex_count();
        Ok(matrix(py, (0..n).flat_map(|i| shape.point(i)).collect(), 3))
    }

    /// The density picture of `samples` chaos-game points, an (h, w, 3)
    /// uint8 array: the pixels of `render(path.png, random=samples, ...)`.
    #[pyo3(signature = (samples, size=(800, 800), seed=0, palette=None, **params))]
    fn density<'py>(
        &self,
        py: Python<'py>,
        samples: usize,
        size: (u32, u32),
        seed: u64,
        palette: Option<&str>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let options = self.options(None, None, params)?;
        let palette = palette.map(bcifs::export::Palette::parse).transpose().map_err(err)?;
        let random = RandomSettings::default().with_points(samples).with_seed(seed);
        let raster = bcifs::export::RasterSettings::default().with_size(size.0, size.1);
        let design = &self.inner;
        let img = py
            .detach(|| -> Result<_, String> {
                let model = bcifs::render::model_of(design).map_err(|e| e.to_string())?;
                let instance = bcifs::instantiate(design, &options.params).map_err(|e| e.to_string())?;
                let game =
                    bcifs::eval::ChaosGame::new(&instance.automaton, &model, &random).map_err(|e| e.to_string())?;
                bcifs::export::density_image(&game, samples, &raster, &options.tone, palette.as_ref())
                    .map_err(|e| e.to_string())
            })
            .map_err(err)?;
        let (w, h) = img.dimensions();
        Ok(Array3::from_shape_vec((h as usize, w as usize, 3), img.into_raw()).expect("h × w × 3").into_pyarray(py))
    }

    /// Writes the design to `path`, the format chosen by its extension (every
    /// format of `bcifs render`); `samples` runs the chaos game; `progress`
    /// is called with `(done, total)` as the work goes. Returns the report as
    /// a dict (format, vertices, faces, bytes, warnings, notes). Ctrl-C stops
    /// it within a tenth of a second and leaves no file.
    #[pyo3(signature = (path, depth=None, tolerance=None, samples=None, seed=1, size=(800, 800), palette=None, progress=None, **params))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        path: std::path::PathBuf,
        depth: Option<usize>,
        tolerance: Option<f64>,
        samples: Option<usize>,
        seed: u64,
        size: (u32, u32),
        palette: Option<&str>,
        progress: Option<&Bound<'py, PyAny>>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut options = self.options(depth, tolerance, params)?.with_size(size.0, size.1);
        options.random = samples.map(|n| RandomSettings::default().with_points(n).with_seed(seed));
        options.palette = palette.map(bcifs::export::Palette::parse).transpose().map_err(err)?;
        let design = &self.inner;
        let report = cancellable(py, progress, |cancel, reporter| {
            let mut options = options.with_cancel(cancel);
            options.progress = reporter;
            bcifs::render::render(design, &options, &path)
        })?
        .map_err(err)?;
        report_dict(py, &report)
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

    /// A 400 × 400 picture, for Jupyter.
    fn _repr_png_(&self, py: Python<'_>) -> PyResult<Vec<u8>> {
        let path = std::env::temp_dir().join(format!("bcifs-repr-{}-{:p}.png", std::process::id(), self));
        let options = Options::default().with_size(400, 400);
        let design = &self.inner;
        py.detach(|| bcifs::render::render(design, &options, &path)).map_err(err)?;
        let bytes = std::fs::read(&path).map_err(err)?;
        let _ = std::fs::remove_file(&path);
        Ok(bytes)
    }

    fn __repr__(&self) -> String {
        format!("<bcifs.Design {:?}: {}>", self.inner.name(), self.inner.description())
    }
}

/// A JSON value as Python objects (through `json.loads`).
fn json_object<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (value.to_string(),))
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
    Ok(d)
}

/// A design by name (a shipped automaton or scheme preset) or path.
#[pyfunction]
fn load(name_or_path: &str) -> PyResult<Design> {
    Ok(Design { inner: bcifs::render::load(name_or_path).map_err(err)? })
}

/// A user's polygon mesh (`vertices` (n, 3), `faces` an (m, k) array or a
/// list of index sequences) subdivided `depth` times by `scheme`
/// (`doo-sabin`, `catmull-clark`, `loop`, `sqrt3`): the limit surface, or
/// the control net with `net=True`; `weights` the rule weights (`alpha`,
/// `beta`, `gamma` for Doo-Sabin, `w`, `sigma` for Loop). The same mesh as
/// `bcifs surface` on that mesh written as OBJ.
#[pyfunction]
#[pyo3(signature = (vertices, faces, scheme, depth, net=false, **weights))]
fn subdivide(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f64>,
    faces: &Bound<'_, PyAny>,
    scheme: &str,
    depth: usize,
    net: bool,
    weights: Option<&Bound<'_, PyDict>>,
) -> PyResult<Mesh> {
    let v = vertices.as_array();
    if v.ncols() != 3 {
        return Err(err(format!("vertices must be an (n, 3) array, not (n, {})", v.ncols())));
    }
    let positions: Vec<[f64; 3]> = v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let faces: Vec<Vec<usize>> = faces
        .extract::<Vec<Vec<i64>>>()?
        .into_iter()
        .map(|f| {
            f.into_iter()
                .map(|i| usize::try_from(i).map_err(|_| err(format!("a face index is negative: {i}"))))
                .collect()
        })
        .collect::<PyResult<_>>()?;
    let scheme = match scheme.replace('_', "-").as_str() {
        "doo-sabin" => Scheme::DooSabin,
        "catmull-clark" => Scheme::CatmullClark,
        "loop" => Scheme::Loop,
        "sqrt3" => Scheme::Sqrt3,
        other => return Err(err(format!("unknown scheme `{other}`: doo-sabin, catmull-clark, loop or sqrt3"))),
    };
    let mesh = PolyMesh::new(positions, faces).map_err(err)?;
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
    let out = py.detach(|| bcifs::render::subdivide_mesh(&mesh, &job, &Options::default())).map_err(err)?;
    Mesh::of_polymesh(py, &out)
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

/// The rows `rows` of a parameter sweep of the design in `toml` (a band of
/// `bcifs.sweep`'s array, bit for bit): `x` and `y` are `(name, lo, hi,
/// n)`; verdicts as int8: 1 converges, 0 undecided, -1 diverges (JSR ≥ 1),
/// -2 a subdivision matrix fails seed 004's per-matrix condition.
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
) -> PyResult<Bound<'py, PyArray2<i8>>> {
    use bcifs::analysis::{JsrSettings, ParameterPlane, Verdict, verdict_map_rows};
    if what != "verdict" {
        return Err(err(format!(
            "sweep what=`{what}`: this version sweeps the convergence verdict (what=\"verdict\")"
        )));
    }
    let design = bcifs::parse_design(toml, "<sweep>", "design").map_err(err)?;
    let plane = ParameterPlane { x: (x.0, x.1, x.2), y: (y.0, y.1, y.2), size: (x.3, y.3) };
    let settings = if thorough { JsrSettings::default() } else { JsrSettings::quick() };
    let cells = py
        .detach(|| -> Result<_, String> {
            let family = bcifs::solve(&design).map_err(|e| e.to_string())?;
            verdict_map_rows(&family, &plane, &settings, rows.0..rows.1).map_err(|e| e.to_string())
        })
        .map_err(err)?;
    let codes: Vec<i8> = cells
        .iter()
        .map(|c| match (c.verdict, c.per_matrix) {
            (Verdict::Converges, _) => 1,
            (Verdict::Undecided, _) => 0,
            (Verdict::Diverges, true) => -1,
            (Verdict::Diverges, false) => -2,
        })
        .collect();
    Ok(matrix(py, codes, plane.size.0).into_bound(py))
}

/// The module.
#[pymodule]
fn _bcifs(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("BcifsError", m.py().get_type::<BcifsError>())?;
    m.add_class::<Design>()?;
    m.add_class::<Mesh>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(subdivide, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_rows, m)?)?;
    m.add_function(wrap_pyfunction!(dimension, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
