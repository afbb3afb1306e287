//! `bcifs.Builder`: the library's checked builder, for designs made in code.

use pyo3::prelude::*;
use pyo3::types::PyString;

use bcifs::render::{CellKind, DesignBuilder, Layout, MatrixValue as Value, Model};

use crate::{Design, err};

/// A number (exact: `0.1` is 1/10), a `fractions.Fraction`, or an expression as text.
fn value(v: &Bound<'_, PyAny>) -> PyResult<Value> {
    if let Ok(text) = v.cast::<PyString>() {
        return Ok(Value::Text(text.to_string()));
    }
    if v.hasattr("numerator")? && v.hasattr("denominator")? && !v.is_instance_of::<pyo3::types::PyFloat>() {
        let (n, d): (i64, i64) = (v.getattr("numerator")?.extract()?, v.getattr("denominator")?.extract()?);
        return Ok(if d == 1 { Value::from(n) } else { Value::Text(format!("{n}/{d}")) });
    }
    let x: f64 = v.extract().map_err(|_| err(format!("`{v}`: expected a number, a Fraction or an expression")))?;
    Ok(Value::from(x))
}

/// Builds a design in code, as an automaton file would: states, arrows
/// (unknown, known or selection matrices), constraints as path or entry
/// equations, parameters and a model, checked as a whole by `build()`,
/// which names the item at fault. Every method returns the builder::
///
///     b = bcifs.Builder("corner_cutting")
///     b.state("e", 3, "edge").state("v", 2, "vertex")
///     b.unknown("T0", "e", "e").unknown("T1", "e", "e").unknown("Tv", "v", "v")
///     b.select("b0", "e", "v", [0, 1]).select("b1", "e", "v", [1, 2])
///     b.adjacency("T0 b1 = T1 b0").incidence("T0 b0 = b0 Tv").incidence("T1 b1 = b1 Tv")
///     b.name_entry("a", "T0[1][0]", default=0.25).name_entry("b", "T0[0][1]", default=0.25)
///     b.model("e", [[0, 0], [1, 2], [3, 2], [4, 0]], layout="open")
///     design = b.build()
///
/// Paths read in arrow order (`T0 b1` is `e -T0-> e -b1-> v`); a matrix maps
/// target coordinates into source coordinates (`dim(source) × dim(target)`).
#[pyclass(module = "bcifs")]
pub struct Builder {
    inner: DesignBuilder,
}

#[pymethods]
impl Builder {
    #[new]
    fn new(name: &str) -> Builder {
        Builder { inner: DesignBuilder::new(name) }
    }

    /// The builder of an existing design (to change it and build again).
    #[staticmethod]
    fn of(design: &Design) -> Builder {
        Builder { inner: design.inner.to_builder() }
    }

    /// Free text describing the design.
    fn description<'py>(mut slf: PyRefMut<'py, Self>, text: &str) -> PyRefMut<'py, Self> {
        slf.inner.description(text);
        slf
    }

    /// A comment on the item added last (written above it in the file).
    fn doc<'py>(mut slf: PyRefMut<'py, Self>, text: &str) -> PyRefMut<'py, Self> {
        slf.inner.doc(text);
        slf
    }

    /// A state: the barycentric space of `dim` control points of a cell of
    /// `kind` (`vertex`, `edge`, `face` or `free`).
    fn state<'py>(mut slf: PyRefMut<'py, Self>, name: &str, dim: usize, kind: &str) -> PyResult<PyRefMut<'py, Self>> {
        let kind: CellKind = kind.parse().map_err(|()| {
            err(format!("state `{name}`: unknown kind `{kind}`: expected vertex, edge, face, volume or free"))
        })?;
        slf.inner.state(name, dim, kind);
        Ok(slf)
    }

    /// A subdivision arrow `source → target` whose matrix the solver finds.
    fn unknown<'py>(mut slf: PyRefMut<'py, Self>, name: &str, source: &str, target: &str) -> PyRefMut<'py, Self> {
        slf.inner.unknown(name, source, target);
        slf
    }

    /// A subdivision arrow with a known matrix: rows of numbers, Fractions
    /// or expressions (`[["1 - t", "t"], ["t", "1 - t"]]`), or a 2D array.
    fn matrix<'py>(
        mut slf: PyRefMut<'py, Self>,
        name: &str,
        source: &str,
        target: &str,
        rows: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let mut values = Vec::new();
        for row in rows.try_iter()? {
            let mut r = Vec::new();
            for v in row?.try_iter()? {
                r.push(value(&v?)?);
            }
            values.push(r);
        }
        slf.inner.matrix(name, source, target, values);
        Ok(slf)
    }

    /// A boundary arrow: the cell `target` has the control points `select`
    /// of the cell `source`.
    fn select<'py>(
        mut slf: PyRefMut<'py, Self>,
        name: &str,
        source: &str,
        target: &str,
        select: Vec<usize>,
    ) -> PyRefMut<'py, Self> {
        slf.inner.select(name, source, target, select);
        slf
    }

    /// An equation of the constraint group `group`: two paths (`"T0 b1 = T1
    /// b0"`) or two expressions in entries and parameters (`"T0[2][2] = 1/2"`).
    fn constraint<'py>(mut slf: PyRefMut<'py, Self>, group: &str, equation: &str) -> PyRefMut<'py, Self> {
        slf.inner.constraint(group, equation);
        slf
    }

    /// An adjacency equation: neighbouring sub-cells share their boundary.
    fn adjacency<'py>(mut slf: PyRefMut<'py, Self>, equation: &str) -> PyRefMut<'py, Self> {
        slf.inner.adjacency(equation);
        slf
    }

    /// An incidence equation: the boundary of a sub-cell is the subdivided boundary.
    fn incidence<'py>(mut slf: PyRefMut<'py, Self>, equation: &str) -> PyRefMut<'py, Self> {
        slf.inner.incidence(equation);
        slf
    }

    /// Names the unknown entry `entry` (`"T0[1][0]"`) as a free parameter, with a default value.
    #[pyo3(signature = (name, entry, default=None))]
    fn name_entry<'py>(
        mut slf: PyRefMut<'py, Self>,
        name: &str,
        entry: &str,
        default: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        slf.inner.name_entry(name, entry);
        if let Some(v) = default {
            slf.inner.default_value(name, value(v)?);
        }
        Ok(slf)
    }

    /// A plain parameter, used by known matrices and entry equations, with a default value.
    #[pyo3(signature = (name, default=None))]
    fn parameter<'py>(
        mut slf: PyRefMut<'py, Self>,
        name: &str,
        default: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        slf.inner.parameter(name);
        if let Some(v) = default {
            slf.inner.default_value(name, value(v)?);
        }
        Ok(slf)
    }

    /// The default value of parameter `name`.
    fn default<'py>(
        mut slf: PyRefMut<'py, Self>,
        name: &str,
        value: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let v = self::value(value)?;
        slf.inner.default_value(name, v);
        Ok(slf)
    }

    /// The projection into modelling space: control `points` (2 or 3
    /// coordinates each) cut into pieces of the state `root` by `layout`
    /// (`single`, `open`, `closed`, `grid`, `torus`, `frames`,
    /// `closed-frames`, `union`, `patches`); `roots` several roots taken in
    /// turn, `step` the window step, `grid` (rows, cols) for grid layouts,
    /// `net` the control net's faces, `patches` the pieces' points (layout
    /// `patches`), `y_up` for points in Y-up axes.
    #[pyo3(signature = (root, points, layout="single", roots=None, step=None, grid=None, net=None, patches=None, y_up=false))]
    #[allow(clippy::too_many_arguments)]
    fn model<'py>(
        mut slf: PyRefMut<'py, Self>,
        root: &str,
        points: Vec<Vec<f64>>,
        layout: &str,
        roots: Option<Vec<String>>,
        step: Option<usize>,
        grid: Option<(usize, usize)>,
        net: Option<Vec<Vec<usize>>>,
        patches: Option<Vec<Vec<usize>>>,
        y_up: bool,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let layout = Layout::ALL.into_iter().find(|l| l.keyword() == layout).ok_or_else(|| {
            let names: Vec<&str> = Layout::ALL.iter().map(|l| l.keyword()).collect();
            err(format!("unknown layout `{layout}`: expected one of {}", names.join(", ")))
        })?;
        let mut model = Model::new(root, points).with_layout(layout).with_y_up(y_up);
        if let Some(roots) = roots {
            model = model.with_roots(roots);
        }
        if let Some(step) = step {
            model = model.with_step(step);
        }
        if let Some((rows, cols)) = grid {
            model = model.with_grid(rows, cols);
        }
        if let Some(net) = net {
            model = model.with_net(net);
        }
        if let Some(patches) = patches {
            let roots = model.roots.clone();
            model = model.with_patches(roots, patches);
        }
        slf.inner.model(model);
        Ok(slf)
    }

    /// The design, checked as a whole; `BcifsError` names the item at fault.
    fn build(&self) -> PyResult<Design> {
        Ok(Design { inner: self.inner.build().map_err(err)? })
    }

    fn __repr__(&self) -> String {
        format!("<bcifs.Builder {:?}>", self.inner.name())
    }
}
