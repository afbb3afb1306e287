//! Cutting a model's control points into pieces (one root cell each).

use crate::automaton::{ArrowKind, Automaton};
use crate::design::{Layout, Model};

/// Why a model does not fit its automaton.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ModelError {
    /// The root state does not exist.
    #[error("the model's root `{0}` is not a state of the automaton")]
    NoRoot(String),
    /// The layout cannot be cut from the points.
    #[error("{0}")]
    Layout(String),
}

/// One root cell: a state and its control points.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Name (`piece 3`, `patch 1,2`).
    pub name: String,
    /// Root state index (`NodeIndex::index()`).
    pub state: usize,
    /// Control points, `d × n` row-major: coordinate `a` of point `i` at `a * n + i`.
    pub control: Vec<f64>,
}

/// The pieces of a model and how they fit together.
#[derive(Clone, Debug, PartialEq)]
pub struct Pieces {
    /// Coordinates of modelling space (2 or 3).
    pub dim: usize,
    /// Pieces in order (curve order, or patch rows of `grid.1` patches).
    pub pieces: Vec<Piece>,
    /// Curves: the last piece ends where the first starts.
    pub closed: bool,
    /// Curves: each piece starts where the previous one ends (one polyline).
    pub connected: bool,
    /// Surfaces: `(patch rows, patch columns, torus)`.
    pub grid: Option<(usize, usize, bool)>,
    /// The pieces share control points (layout `patches`): their output is welded into one.
    pub shared: bool,
}

fn control(points: &[Vec<f64>], indices: &[usize], d: usize) -> Vec<f64> {
    let n = indices.len();
    let mut c = vec![0.0; d * n];
    for (i, &p) in indices.iter().enumerate() {
        for a in 0..d {
            c[a * n + i] = points[p][a];
        }
    }
    c
}

pub use crate::geometry::MAX_COORDINATE;

/// Cuts the model into pieces.
///
/// # Errors
/// A root that does not exist, or a layout that does not fit the points.
pub fn pieces(automaton: &Automaton<f64>, model: &Model) -> Result<Pieces, ModelError> {
    let roots = model
        .roots
        .iter()
        .map(|r| automaton.state_id(r).ok_or_else(|| ModelError::NoRoot(r.clone())))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(&root) = roots.first() else {
        return Err(ModelError::Layout("a model needs at least one root state".into()));
    };
    // Distances square the coordinates: beyond 1e150 they overflow to infinity (and then NaN).
    if let Some((i, x)) = model
        .points
        .iter()
        .enumerate()
        .flat_map(|(i, p)| p.iter().map(move |x| (i, *x)))
        .find(|(_, x)| !x.is_finite() || x.abs() > MAX_COORDINATE)
    {
        return Err(ModelError::Layout(format!(
            "control point {i} has the coordinate {x:e}: coordinates must be finite and at most {MAX_COORDINATE:e} in size (distances square them); scale the model"
        )));
    }
    let n = automaton.state(root).dim;
    if !matches!(model.layout, Layout::Union | Layout::Patches)
        && let Some(other) = roots.iter().find(|r| automaton.state(**r).dim != n)
    {
        return Err(ModelError::Layout(format!(
            "the roots of a {} layout must have the same dimension ({} has {}, not {n})",
            model.layout.keyword(),
            automaton.state(*other).name,
            automaton.state(*other).dim
        )));
    }
    // Default step: the control points one cell does not share with its neighbour.
    let boundary_dim =
        automaton.outgoing(root, ArrowKind::Boundary).first().map(|e| automaton.state(automaton.arrow_ends(*e).1).dim);
    let cut = Cut {
        model,
        dims: roots.iter().map(|r| automaton.state(*r).dim).collect(),
        roots: roots.iter().map(|r| r.index()).collect(),
        n,
        d: model.points.first().map_or(2, Vec::len),
        boundary_dim,
    };
    let mut out = Pieces { dim: cut.d, pieces: Vec::new(), closed: false, connected: false, grid: None, shared: false };
    match model.layout {
        Layout::Single => {
            let len = model.points.len();
            if len < n {
                return layout_error(format!("the root has dim {n} but the model has {len} control points"));
            }
            out.pieces.push(cut.piece(0, "piece 0".into(), (0..n).collect()));
        }
        Layout::Union => out.pieces = cut.union()?,
        Layout::Patches => {
            out.shared = true;
            for (k, patch) in model.patches.iter().enumerate() {
                if let Some(&bad) = patch.iter().find(|&&p| p >= model.points.len()) {
                    return layout_error(format!("patch {k} uses control point {bad} of {}", model.points.len()));
                }
                out.pieces.push(cut.piece(k, format!("patch {k}"), patch.clone()));
            }
        }
        Layout::Open | Layout::Closed => {
            out.closed = model.layout == Layout::Closed;
            out.pieces = cut.windows(out.closed)?;
            out.connected = true;
        }
        Layout::Frames | Layout::ClosedFrames => {
            out.closed = model.layout == Layout::ClosedFrames;
            out.pieces = cut.frames(out.closed)?;
            out.connected = true;
        }
        Layout::Grid | Layout::Torus => {
            let (pieces, grid) = cut.grid(model.layout == Layout::Torus)?;
            out.pieces = pieces;
            out.grid = Some(grid);
        }
    }
    Ok(out)
}

/// Patch rows, patch columns, and whether they wrap around (a torus).
type PatchGrid = (usize, usize, bool);

fn layout_error<T>(message: String) -> Result<T, ModelError> {
    Err(ModelError::Layout(message))
}

/// What cutting a model needs: its roots (state indices and dimensions),
/// the root dimension `n`, the point dimension `d`, and the dimension of a
/// boundary cell of the root (the points neighbouring cells share).
struct Cut<'a> {
    model: &'a Model,
    roots: Vec<usize>,
    dims: Vec<usize>,
    n: usize,
    d: usize,
    boundary_dim: Option<usize>,
}

impl Cut<'_> {
    /// Piece `k` (root `k mod roots`) on the control points `idx`.
    fn piece(&self, k: usize, name: String, idx: Vec<usize>) -> Piece {
        Piece { name, state: self.roots[k % self.roots.len()], control: control(&self.model.points, &idx, self.d) }
    }

    /// Consecutive runs of `dim(root_k)` points, nothing shared.
    fn union(&self) -> Result<Vec<Piece>, ModelError> {
        let len = self.model.points.len();
        let (mut out, mut at) = (Vec::new(), 0);
        while at < len {
            let k = out.len();
            let m = self.dims[k % self.dims.len()];
            if at + m > len {
                return layout_error(format!(
                    "a union piece of `{}` needs {m} control points; only {} are left",
                    self.model.root(k),
                    len - at
                ));
            }
            out.push(self.piece(k, format!("piece {k}"), (at..at + m).collect()));
            at += m;
        }
        Ok(out)
    }

    /// Windows of `n` points sliding by the step, wrapping around when closed.
    fn windows(&self, closed: bool) -> Result<Vec<Piece>, ModelError> {
        let (n, len) = (self.n, self.model.points.len());
        let step = self.model.step.unwrap_or(n - self.boundary_dim.unwrap_or(0).min(n - 1));
        if closed {
            if !len.is_multiple_of(step) || len < n {
                return layout_error(format!(
                    "a closed layout with step {step} needs a multiple of {step} control points (at least {n}), not {len}"
                ));
            }
            return Ok((0..len)
                .step_by(step)
                .enumerate()
                .map(|(k, s)| self.piece(k, format!("piece {k}"), (s..s + n).map(|i| i % len).collect()))
                .collect());
        }
        if len < n || !(len - n).is_multiple_of(step) {
            return layout_error(format!(
                "an open layout of windows of {n} with step {step} needs {n} + a multiple of {step} control points, not {len}"
            ));
        }
        Ok((0..=len - n)
            .step_by(step)
            .enumerate()
            .map(|(k, s)| self.piece(k, format!("piece {k}"), (s..s + n).collect()))
            .collect())
    }

    /// Segments `(P_i, P_{i+1})` with their rotated frame points.
    fn frames(&self, closed: bool) -> Result<Vec<Piece>, ModelError> {
        let (points, len, d) = (&self.model.points, self.model.points.len(), self.d);
        if len < 2 || d != 2 {
            return layout_error(format!("frame layouts need at least two 2D points, not {len} of dimension {d}"));
        }
        let segments = if closed { len } else { len - 1 };
        Ok((0..segments)
            .map(|i| {
                let (p, q) = (&points[i], &points[(i + 1) % len]);
                let frame = [p[0] - (q[1] - p[1]), p[1] + (q[0] - p[0])];
                Piece {
                    name: format!("segment {i}"),
                    state: self.roots[i % self.roots.len()],
                    control: vec![p[0], q[0], frame[0], p[1], q[1], frame[1]],
                }
            })
            .collect())
    }

    /// `w × w` windows of the control grid (`n = w²`), wrapping on a torus;
    /// with the patch rows and columns.
    fn grid(&self, torus: bool) -> Result<(Vec<Piece>, PatchGrid), ModelError> {
        let n = self.n;
        let w = (n as f64).sqrt().round() as usize;
        if w * w != n || w < 2 {
            return layout_error(format!(
                "grid layouts need a root of square dimension w × w with w ≥ 2 (windows of the grid), not {n}"
            ));
        }
        let (rows, cols) =
            self.model.grid.ok_or_else(|| ModelError::Layout("grid layouts need grid = [ROWS, COLS]".into()))?;
        // A boundary edge of a w × w face holds `bw` rows of w points.
        let bw = self.boundary_dim.map_or(w - 1, |b| (b / w).clamp(1, w - 1));
        let step = self.model.step.unwrap_or(w - bw);
        let (pr, pc) = if torus {
            if !rows.is_multiple_of(step) || !cols.is_multiple_of(step) {
                return layout_error(format!(
                    "a torus with step {step} needs rows and columns that are multiples of {step}"
                ));
            }
            (rows / step, cols / step)
        } else {
            if rows < w || cols < w || !(rows - w).is_multiple_of(step) || !(cols - w).is_multiple_of(step) {
                return layout_error(format!(
                    "a grid of {w}×{w} windows with step {step} does not fit {rows}×{cols} control points"
                ));
            }
            ((rows - w) / step + 1, (cols - w) / step + 1)
        };
        let mut out = Vec::with_capacity(pr * pc);
        for i in 0..pr {
            for j in 0..pc {
                let idx = (0..w)
                    .flat_map(|r| (0..w).map(move |c| ((i * step + r) % rows) * cols + (j * step + c) % cols))
                    .collect();
                out.push(self.piece(out.len(), format!("patch {i},{j}"), idx));
            }
        }
        Ok((out, (pr, pc, torus)))
    }
}
