//! The automaton of a whole contour (the Bézier-fractal contours paper §§4–6): its pieces chained
//! into one curve, arcs as Bézier edge states (the de Casteljau halves `L`,
//! `M` as column-stochastic barycentric matrices, so collinear control
//! points need no inverse), line segments as two-point edge states, each
//! with its end vertex; the model places every piece with its own control
//! points (layout `union`), in chain order.

use super::segments::{CASTELJAU_LEFT, CASTELJAU_RIGHT, Segment};
use crate::algebra::Surd;
use crate::design::{Design, Layout, Model};
use crate::space::CellKind;

/// Why a contour has no automaton.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContourError {
    /// No segment.
    #[error("a contour needs at least one segment")]
    Empty,
    /// Pieces that do not chain into one curve.
    #[error(
        "the segments do not join into one curve: segment {segment} ({x}, {y}) touches no other segment's end \
         (segments must share end points exactly, in any order and direction)"
    )]
    Disjoint {
        /// The segment left over (from 0, in file order).
        segment: usize,
        /// Its start.
        x: f64,
        /// Its start.
        y: f64,
    },
    /// A bug in the generator.
    #[error("internal error: {0}")]
    Build(String),
}

/// The pieces in chain order (each possibly reversed), and whether the
/// chain closes: the first piece, then repeatedly a piece that starts or
/// ends where the chain ends (or, when none does, where it starts).
///
/// # Errors
/// [`ContourError::Disjoint`] for a piece that touches neither end.
pub fn chain(segments: &[Segment]) -> Result<(Vec<Segment>, bool), ContourError> {
    let Some(first) = segments.first() else { return Err(ContourError::Empty) };
    let scale = segments.iter().flat_map(|s| s.points.iter().flatten()).fold(1.0f64, |m, x| m.max(x.abs()));
    let same = |a: [f64; 2], b: [f64; 2]| {
        (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) <= crate::algebra::tolerance::SAME_POINT * scale
    };
    let mut used = vec![false; segments.len()];
    used[0] = true;
    let mut out = std::collections::VecDeque::from([first.clone()]);
    for _ in 1..segments.len() {
        let (head, tail) = (out[0].start(), out[out.len() - 1].end());
        let next = (0..segments.len()).filter(|&k| !used[k]).find_map(|k| {
            let s = &segments[k];
            if same(s.start(), tail) {
                Some((k, s.clone(), true))
            } else if same(s.end(), tail) {
                Some((k, s.reversed(), true))
            } else if same(s.end(), head) {
                Some((k, s.clone(), false))
            } else if same(s.start(), head) {
                Some((k, s.reversed(), false))
            } else {
                None
            }
        });
        let Some((k, s, at_tail)) = next else {
            let k = used.iter().position(|u| !u).unwrap_or(0);
            let [x, y] = segments[k].start();
            return Err(ContourError::Disjoint { segment: k, x, y });
        };
        used[k] = true;
        if at_tail { out.push_back(s) } else { out.push_front(s) }
    }
    let closed = same(out[0].start(), out[out.len() - 1].end());
    Ok((out.into(), closed))
}

fn transposed(m: &[[f64; 3]; 3], n: usize) -> Vec<Vec<Surd>> {
    // The de Casteljau weights are dyadic: exact as fractions of 4.
    (0..n).map(|i| (0..n).map(|j| Surd::frac((m[j][i] * 4.0).round() as i64, 4)).collect()).collect()
}

/// The automaton of the contour `segments`, named `name`, with its model.
///
/// # Errors
/// No segment, or pieces that do not chain into one curve.
///
/// ```
/// let heart = bcifs::contour::parse_segments(
///     "[[segment]]\npoints = [[-1, 0], [-1, 1], [0, 0]]\n[[segment]]\npoints = [[0, 0], [1, 1], [1, 0]]\n\
///      [[segment]]\npoints = [[-1, 0], [-1, -1], [0, -2]]\n[[segment]]\npoints = [[0, -2], [1, -1], [1, 0]]\n",
///     "heart.toml",
/// )
/// .unwrap();
/// let design = bcifs::contour::contour_design("heart", &heart).unwrap();
/// assert_eq!(design.model().unwrap().roots.len(), 4);
/// ```
pub fn contour_design(name: &str, segments: &[Segment]) -> Result<Design, ContourError> {
    let (pieces, closed) = chain(segments)?;
    let mut b = Design::builder(name);
    let arcs = pieces.iter().filter(|s| s.is_arc()).count();
    b.description(format!(
        "{} contour of {arcs} quadratic Bézier arcs and {} line segments (the Bézier-fractal contours paper)",
        if closed { "closed" } else { "open" },
        pieces.len() - arcs
    ));
    b.doc("Each piece is the attractor of its two maps; consecutive pieces share their end points.");
    let line_halves = [[[1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.0; 3]], [[0.5, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0; 3]]];
    for (state, n, halves, what) in [
        ("arc", 3, [CASTELJAU_LEFT, CASTELJAU_RIGHT], "A quadratic Bézier arc: P0, P1, P2."),
        ("line", 2, line_halves, "A line segment: its two end points."),
    ] {
        if !pieces.iter().any(|s| s.points.len() == n) {
            continue;
        }
        let (v, t0, t1, rule) =
            (format!("{state}_end"), format!("{state}_L"), format!("{state}_M"), format!("{state}_W"));
        b.state(state, n, CellKind::Edge).doc(what);
        b.state(&v, 1, CellKind::Vertex).doc("An end point.");
        b.matrix(&t0, state, state, transposed(&halves[0], n)).doc("The left half (de Casteljau at 1/2), transposed.");
        b.matrix(&t1, state, state, transposed(&halves[1], n)).doc("The right half, transposed.");
        b.matrix(&rule, &v, &v, [[Surd::one()]]).doc("An end point stays.");
        b.select(format!("{state}_start"), state, &v, [0]).doc("The start.");
        b.select(format!("{state}_stop"), state, &v, [n - 1]).doc("The end.");
        b.adjacency(format!("{t0} {state}_stop = {t1} {state}_start")).doc("The halves meet.");
        b.incidence(format!("{t0} {state}_start = {state}_start {rule}"));
        b.incidence(format!("{t1} {state}_stop = {state}_stop {rule}"));
    }
    let roots = pieces.iter().map(|s| if s.is_arc() { "arc" } else { "line" }.to_string()).collect();
    let points = pieces.iter().flat_map(|s| s.points.iter().map(|p| p.to_vec())).collect();
    let model = Model::new("", points).with_roots(roots).with_layout(Layout::Union);
    b.model(model).doc("The pieces in chain order, each with its own control points.");
    b.build().map_err(|e| ContourError::Build(e.to_string()))
}
