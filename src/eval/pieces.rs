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
    let n = automaton.state(root).dim;
    if model.layout != Layout::Union
        && let Some(other) = roots.iter().find(|r| automaton.state(**r).dim != n)
    {
        return Err(ModelError::Layout(format!(
            "the roots of a {} layout must have the same dimension ({} has {}, not {n})",
            model.layout.keyword(),
            automaton.state(*other).name,
            automaton.state(*other).dim
        )));
    }
    let root_of = |i: usize| roots[i % roots.len()].index();
    let d = model.points.first().map_or(2, Vec::len);
    let len = model.points.len();
    let err = |s: String| Err(ModelError::Layout(s));
    // Default step: the control points one cell does not share with its neighbour.
    let boundary_dim =
        automaton.outgoing(root, ArrowKind::Boundary).first().map(|e| automaton.state(automaton.arrow_ends(*e).1).dim);
    let piece = |k: usize, name: String, idx: Vec<usize>| Piece {
        name,
        state: root_of(k),
        control: control(&model.points, &idx, d),
    };
    let mut out = Pieces { dim: d, pieces: Vec::new(), closed: false, connected: false, grid: None };
    match model.layout {
        Layout::Single => {
            if len < n {
                return err(format!("the root has dim {n} but the model has {len} control points"));
            }
            out.pieces.push(piece(0, "piece 0".into(), (0..n).collect()));
        }
        Layout::Union => {
            let mut at = 0;
            while at < len {
                let k = out.pieces.len();
                let m = automaton.state(roots[k % roots.len()]).dim;
                if at + m > len {
                    return err(format!(
                        "a union piece of `{}` needs {m} control points; only {} are left",
                        model.root(k),
                        len - at
                    ));
                }
                out.pieces.push(piece(k, format!("piece {k}"), (at..at + m).collect()));
                at += m;
            }
        }
        Layout::Open | Layout::Closed => {
            let step = model.step.unwrap_or(n - boundary_dim.unwrap_or(0).min(n - 1));
            let closed = model.layout == Layout::Closed;
            if closed {
                if !len.is_multiple_of(step) || len < n {
                    return err(format!(
                        "a closed layout with step {step} needs a multiple of {step} control points (at least {n}), not {len}"
                    ));
                }
                for (k, s) in (0..len).step_by(step).enumerate() {
                    out.pieces.push(piece(k, format!("piece {k}"), (s..s + n).map(|i| i % len).collect()));
                }
            } else {
                if len < n || !(len - n).is_multiple_of(step) {
                    return err(format!(
                        "an open layout of windows of {n} with step {step} needs {n} + a multiple of {step} control points, not {len}"
                    ));
                }
                for (k, s) in (0..=len - n).step_by(step).enumerate() {
                    out.pieces.push(piece(k, format!("piece {k}"), (s..s + n).collect()));
                }
            }
            out.closed = closed;
            out.connected = true;
        }
        Layout::Frames | Layout::ClosedFrames => {
            let closed = model.layout == Layout::ClosedFrames;
            if len < 2 || d != 2 {
                return err(format!("frame layouts need at least two 2D points, not {len} of dimension {d}"));
            }
            let segments = if closed { len } else { len - 1 };
            for i in 0..segments {
                let (p, q) = (&model.points[i], &model.points[(i + 1) % len]);
                let frame = [p[0] - (q[1] - p[1]), p[1] + (q[0] - p[0])];
                out.pieces.push(Piece {
                    name: format!("segment {i}"),
                    state: root_of(i),
                    control: vec![p[0], q[0], frame[0], p[1], q[1], frame[1]],
                });
            }
            out.closed = closed;
            out.connected = true;
        }
        Layout::Grid | Layout::Torus => {
            let w = (n as f64).sqrt().round() as usize;
            if w * w != n {
                return err(format!("grid layouts need a root of square dimension (w × w windows), not {n}"));
            }
            let (rows, cols) =
                model.grid.ok_or_else(|| ModelError::Layout("grid layouts need grid = [ROWS, COLS]".into()))?;
            // A boundary edge of a w × w face holds `bw` rows of w points.
            let bw = boundary_dim.map_or(w - 1, |b| (b / w).clamp(1, w - 1));
            let step = model.step.unwrap_or(w - bw);
            let torus = model.layout == Layout::Torus;
            let (pr, pc) = if torus {
                if !rows.is_multiple_of(step) || !cols.is_multiple_of(step) {
                    return err(format!(
                        "a torus with step {step} needs rows and columns that are multiples of {step}"
                    ));
                }
                (rows / step, cols / step)
            } else {
                if rows < w || cols < w || !(rows - w).is_multiple_of(step) || !(cols - w).is_multiple_of(step) {
                    return err(format!(
                        "a grid of {w}×{w} windows with step {step} does not fit {rows}×{cols} control points"
                    ));
                }
                ((rows - w) / step + 1, (cols - w) / step + 1)
            };
            for i in 0..pr {
                for j in 0..pc {
                    let idx = (0..w)
                        .flat_map(|r| (0..w).map(move |c| ((i * step + r) % rows) * cols + (j * step + c) % cols))
                        .collect();
                    let k = out.pieces.len();
                    out.pieces.push(piece(k, format!("patch {i},{j}"), idx));
                }
            }
            out.grid = Some((pr, pc, torus));
        }
    }
    Ok(out)
}
