//! Contour pieces (the Bézier-fractal contours paper): quadratic Bézier arcs and line segments, the
//! segments file that lists them, and their IFS in the paper's convention
//! (homogeneous row vectors, `[x' y' 1] = [x y 1] F`, eq. 2).
//!
//! ```toml
//! [[segment]]
//! points = [[-1, 0], [-1, 1], [0, 0]]   # 3 points: quadratic Bézier P0, P1, P2
//! [[segment]]
//! points = [[0, 0], [1, 0]]             # 2 points: line segment
//! ```
//!
//! Coordinates are pixels for fitted images — pixel (column c, row r) has its
//! centre at (c, r), so the picture's top-left corner is at (−0.5, −0.5), x to
//! the right, y down — or any units when written by hand.

use std::fmt::Write as _;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use crate::format::{FormatError, ReadError, Source};
use crate::schemes::{RowMap, segment_ifs};

/// A piece of a contour: a line segment (2 points) or a quadratic Bézier
/// arc (3 points: `P0`, `P1`, `P2`).
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// The control points.
    pub points: Vec<[f64; 2]>,
}

impl Segment {
    /// Whether it is a quadratic Bézier arc.
    pub fn is_arc(&self) -> bool {
        self.points.len() == 3
    }

    /// The first point.
    pub fn start(&self) -> [f64; 2] {
        self.points[0]
    }

    /// The last point.
    pub fn end(&self) -> [f64; 2] {
        self.points[self.points.len() - 1]
    }

    /// The point at parameter `u ∈ [0, 1]`.
    pub fn at(&self, u: f64) -> [f64; 2] {
        let p = &self.points;
        if self.is_arc() {
            let (a, b, c) = ((1.0 - u) * (1.0 - u), 2.0 * u * (1.0 - u), u * u);
            [0, 1].map(|k| a * p[0][k] + b * p[1][k] + c * p[2][k])
        } else {
            [0, 1].map(|k| (1.0 - u) * p[0][k] + u * p[1][k])
        }
    }

    /// The same piece run the other way.
    pub fn reversed(&self) -> Segment {
        Segment { points: self.points.iter().rev().copied().collect() }
    }

    /// Its two maps with their names: `L`, `M` for an arc (eq. 10), `F1`,
    /// `F2` for a line segment (eqs. 12–14 with the direction corrected).
    ///
    /// # Errors
    /// An arc with collinear control points: eq. 10's `P` is singular, the
    /// maps of the plane do not exist (the barycentric automaton still works).
    pub fn maps(&self) -> Result<[(&'static str, RowMap); 2], String> {
        if self.is_arc() {
            let [l, m] = arc_ifs(self.points[0], self.points[1], self.points[2]).ok_or_else(|| {
                "its control points are collinear: P of eq. 10 is singular, so the arc has no maps of the plane \
                 (the automaton's barycentric form draws it)"
                    .to_string()
            })?;
            Ok([("L", l), ("M", m)])
        } else {
            let [f1, f2] = segment_ifs(self.points[0], self.points[1]);
            Ok([("F1", f1), ("F2", f2)])
        }
    }
}

/// The de Casteljau halves at `u = 1/2` (eq. 9): new control points as
/// rows of combinations of the old ones.
pub const CASTELJAU_LEFT: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.25, 0.5, 0.25]];
/// The right half.
pub const CASTELJAU_RIGHT: [[f64; 3]; 3] = [[0.25, 0.5, 0.25], [0.0, 0.5, 0.5], [0.0, 0.0, 1.0]];

fn mul(a: &RowMap, b: &RowMap) -> RowMap {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// `Lp = P⁻¹ L P`, `Mp = P⁻¹ M P` (eq. 10) for the arc `p0, p1, p2`, with
/// `P` the rows `[xᵢ yᵢ 1]`; `None` when the points are collinear.
///
/// ```
/// // the Bézier-fractal contours paper §5, the heart's first arc (-1, 0), (-1, 1), (0, 0): the printed L1.
/// let [l, _] = bcifs::contour::arc_ifs([-1.0, 0.0], [-1.0, 1.0], [0.0, 0.0]).unwrap();
/// assert_eq!(l, [[0.25, 0.5, 0.0], [0.0, 0.5, 0.0], [-0.75, 0.5, 1.0]]);
/// ```
pub fn arc_ifs(p0: [f64; 2], p1: [f64; 2], p2: [f64; 2]) -> Option<[RowMap; 2]> {
    let p: RowMap = [[p0[0], p0[1], 1.0], [p1[0], p1[1], 1.0], [p2[0], p2[1], 1.0]];
    let det = p[0][0] * (p[1][1] - p[2][1]) - p[0][1] * (p[1][0] - p[2][0]) + (p[1][0] * p[2][1] - p[2][0] * p[1][1]);
    let scale = [p0, p1, p2].iter().flat_map(|q| q.iter()).fold(1.0f64, |m, x| m.max(x.abs()));
    if det.abs() <= crate::algebra::tolerance::DEGENERATE * scale * scale {
        return None;
    }
    // The adjugate over the determinant.
    let cof = |r: usize, c: usize| {
        let (r0, r1) = ([1, 0, 0][r], [2, 2, 1][r]);
        let (c0, c1) = ([1, 0, 0][c], [2, 2, 1][c]);
        let sign = if (r + c).is_multiple_of(2) { 1.0 } else { -1.0 };
        sign * (p[r0][c0] * p[r1][c1] - p[r0][c1] * p[r1][c0])
    };
    let inv: RowMap = std::array::from_fn(|i| std::array::from_fn(|j| cof(j, i) / det));
    Some([mul(&mul(&inv, &CASTELJAU_LEFT), &p), mul(&mul(&inv, &CASTELJAU_RIGHT), &p)])
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SegmentsFile {
    #[serde(default)]
    segment: Vec<Spanned<SegmentSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SegmentSpec {
    points: Spanned<Vec<Spanned<Vec<f64>>>>,
}

/// Reads a segments file's text (`file` names it in errors).
///
/// # Errors
/// `file:line:column` and what was expected: not TOML, a segment without 2
/// or 3 points, a point without 2 finite coordinates, two equal consecutive
/// points of a line segment, no segment at all.
pub fn parse_segments(text: &str, file: &str) -> Result<Vec<Segment>, FormatError> {
    let src = Source { file, text };
    let spec: SegmentsFile = toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        src.error(offset, e.message().to_string())
    })?;
    if spec.segment.is_empty() {
        return Err(src.error(0, "expected at least one [[segment]] with points = [[x, y], ...]"));
    }
    let mut out = Vec::with_capacity(spec.segment.len());
    for s in &spec.segment {
        let pts = &s.get_ref().points;
        if !(2..=3).contains(&pts.get_ref().len()) {
            return Err(src.at(
                &pts.span(),
                format!(
                    "expected 2 points (a line segment) or 3 (a quadratic Bézier arc), not {}",
                    pts.get_ref().len()
                ),
            ));
        }
        let mut points = Vec::with_capacity(3);
        for p in pts.get_ref() {
            match p.get_ref()[..] {
                [x, y] if x.is_finite() && y.is_finite() => points.push([x, y]),
                _ => return Err(src.at(&p.span(), "expected a point [x, y] of two finite numbers")),
            }
        }
        if points.len() == 2 && points[0] == points[1] {
            return Err(src.at(&pts.span(), "a line segment needs two different points"));
        }
        out.push(Segment { points });
    }
    Ok(out)
}

/// Reads a segments file.
///
/// # Errors
/// An unreadable file (named, with the system's reason: no line or column
/// to point at), or as [`parse_segments`].
pub fn read_segments(path: &Path) -> Result<Vec<Segment>, ReadError> {
    let file = path.display().to_string();
    let text = crate::input::read_text(path, crate::input::TEXT_FILE_LIMIT)
        .map_err(|error| ReadError::Io { path: file.clone(), error })?;
    Ok(parse_segments(&text, &file)?)
}

/// The segments file of `segments` (shortest round-trip numbers).
pub fn write_segments(segments: &[Segment]) -> String {
    let mut out = String::new();
    for s in segments {
        let pts: Vec<String> = s.points.iter().map(|p| format!("[{:?}, {:?}]", p[0] + 0.0, p[1] + 0.0)).collect();
        let kind = if s.is_arc() { "quadratic Bézier" } else { "line segment" };
        let _ = writeln!(out, "[[segment]]  # {kind}\npoints = [{}]", pts.join(", "));
    }
    out
}

/// The images of the polygon `start` under every word of length `depth` of
/// each piece's two maps (Figs. 5–6 of the Bézier-fractal contours paper: iterations from a start
/// set), piece by piece; pieces without maps of the plane (collinear arcs)
/// are left out.
pub fn iterate_polygon(segments: &[Segment], start: &[[f64; 2]], depth: usize) -> Vec<Vec<[f64; 2]>> {
    let apply = |p: [f64; 2], f: &RowMap| [0, 1].map(|j| p[0] * f[0][j] + p[1] * f[1][j] + f[2][j]);
    let mut out = Vec::new();
    for s in segments {
        let Ok([(_, a), (_, b)]) = s.maps() else { continue };
        let mut level = vec![start.to_vec()];
        for _ in 0..depth.min(16) {
            level =
                level.iter().flat_map(|poly| [a, b].map(|f| poly.iter().map(|&p| apply(p, &f)).collect())).collect();
        }
        out.extend(level);
    }
    out
}

/// The chaos game of each piece (Fig. 7 of the Bézier-fractal contours paper): `per_map` points per
/// map, each the image of the last by a map drawn with probability `∝ |det|`
/// (the Bézier-fractal contours paper §2.2), from the piece's start point; a fixed seed.
pub fn chaos_points(segments: &[Segment], per_map: usize, seed: u64) -> Vec<[f64; 2]> {
    let apply = |p: [f64; 2], f: &RowMap| [0, 1].map(|j| p[0] * f[0][j] + p[1] * f[1][j] + f[2][j]);
    let det = |f: &RowMap| (f[0][0] * f[1][1] - f[0][1] * f[1][0]).abs();
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
    let mut out = Vec::new();
    for s in segments {
        let Ok([(_, a), (_, b)]) = s.maps() else { continue };
        let pa = if det(&a) + det(&b) > 0.0 { det(&a) / (det(&a) + det(&b)) } else { 0.5 };
        let mut p = s.start();
        for _ in 0..2 * per_map {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            p = apply(p, if u < pa { &a } else { &b });
            out.push(p);
        }
    }
    out
}
