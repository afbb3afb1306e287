//! The leaf points of an evaluation with their derivatives along directions
//! of the parameters: what a fit's Gauss–Newton steps need. A leaf point is
//! `C · M_{i1} ⋯ M_{ik} · s`, a polynomial in the matrices' entries; its
//! derivative is carried down the tree in forward mode,
//! `d(C·M) = dC·M + C·dM`, so the products' derivatives are exact.

use petgraph::stable_graph::EdgeIndex;

use super::prepared::{Evaluator, mul_into};

/// The derivatives the walk is given, per direction `j`: each arrow's matrix
/// (row-major, as the plan holds it; `None`: constant) and each state's leaf
/// samples ([`Evaluator::leaf_samples`]' order; `None`: constant).
pub struct Directions<'a> {
    /// Number of directions.
    pub count: usize,
    /// `matrix(arrow, j)`: the derivative of the arrow's matrix along direction `j`.
    pub matrix: &'a dyn Fn(EdgeIndex, usize) -> Option<&'a [f64]>,
    /// `samples(state, j)`: the derivative of the state's leaf samples along direction `j`.
    pub samples: &'a dyn Fn(usize, usize) -> Option<&'a [Vec<f64>]>,
}

/// Leaf points and their derivatives ([`Evaluator::tangents`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tangents {
    /// Coordinates per point.
    pub dim: usize,
    /// Directions.
    pub directions: usize,
    /// The points, `dim` coordinates each.
    pub points: Vec<f64>,
    /// Coordinate `a` of the derivative of point `p` along direction `j` at `(p · directions + j) · dim + a`.
    pub derivatives: Vec<f64>,
}

impl Tangents {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len() / self.dim.max(1)
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The derivative of point `p` along direction `j`.
    pub fn derivative(&self, p: usize, j: usize) -> &[f64] {
        let at = (p * self.directions + j) * self.dim;
        &self.derivatives[at..at + self.dim]
    }
}

impl Evaluator {
    /// The barycentric points a leaf cell of state `state` emits: its
    /// samples, then its end (an edge's) when it has one.
    pub fn leaf_samples(&self, state: usize) -> Vec<Vec<f64>> {
        let s = self.plan.state(state);
        s.samples.iter().cloned().chain(s.end.clone()).collect()
    }

    /// The dimension of what the evaluation draws: 1 for curves, 2 for
    /// surfaces and for solids (their boundary), 0 for points.
    pub fn cell_dimension(&self) -> usize {
        use crate::space::CellKind;
        let of = |state: usize| match self.plan.state(state).kind {
            CellKind::Edge => 1,
            CellKind::Face | CellKind::Volume => 2,
            CellKind::Vertex | CellKind::Free => 0,
        };
        self.pieces.pieces.iter().map(|p| of(p.state)).max().unwrap_or(0)
    }

    /// The number of states (the indices [`Evaluator::leaf_samples`] takes).
    pub fn state_count(&self) -> usize {
        self.plan.states.len()
    }

    /// Every leaf point of every piece at depth `depth` (each leaf's samples
    /// and end: the points the evaluation emits, some twice), with their
    /// derivatives along `directions`. Cost: `directions + 1` times the
    /// products of the evaluation, on one thread.
    pub fn tangents(&self, depth: usize, directions: &Directions<'_>) -> Tangents {
        let d = self.pieces.dim;
        let mut out = Tangents { dim: d, directions: directions.count, ..Tangents::default() };
        for piece in &self.pieces.pieces {
            let n = self.plan.state(piece.state).dim;
            let dc = vec![0.0; directions.count * d * n];
            self.walk_tangents(piece.state, &piece.control, &dc, depth, directions, &mut out);
        }
        out
    }

    fn walk_tangents(&self, state: usize, c: &[f64], dc: &[f64], r: usize, dirs: &Directions<'_>, out: &mut Tangents) {
        let (d, s) = (self.pieces.dim, self.plan.state(state));
        let n = s.dim;
        if r == 0 || s.children.is_empty() {
            let samples = self.leaf_samples(state);
            for (k, lambda) in samples.iter().enumerate() {
                out.points.extend((0..d).map(|a| dot(&c[a * n..(a + 1) * n], lambda)));
                for j in 0..dirs.count {
                    let dcj = &dc[j * d * n..(j + 1) * d * n];
                    let dl = (dirs.samples)(state, j).map(|ds| &ds[k]);
                    out.derivatives.extend((0..d).map(|a| {
                        let row = a * n..(a + 1) * n;
                        dot(&dcj[row.clone()], lambda) + dl.map_or(0.0, |dl| dot(&c[row], dl))
                    }));
                }
            }
            return;
        }
        for (e, t, m) in &s.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, n, m, nt, &mut child);
            let mut dchild = vec![0.0; dirs.count * d * nt];
            let mut term = vec![0.0; d * nt];
            for j in 0..dirs.count {
                let slot = &mut dchild[j * d * nt..(j + 1) * d * nt];
                mul_into(&dc[j * d * n..(j + 1) * d * n], d, n, m, nt, slot);
                if let Some(dm) = (dirs.matrix)(*e, j) {
                    mul_into(c, d, n, dm, nt, &mut term);
                    slot.iter_mut().zip(&term).for_each(|(x, y)| *x += y);
                }
            }
            self.walk_tangents(*t, &child, &dchild, r - 1, dirs, out);
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
