//! BC-IFS topology generators: the automata of a curve (edge bounded by two
//! vertices) and of a quad patch (face bounded by four edges), written as
//! commented automaton files so that nobody writes twenty equations by hand.
//!
//! Seed: Sokolov, Gentil, Bensoudane, *Tangents to fractal curves and
//! surfaces*, §3 (curve) and §7 (Doo-Sabin-like patches).

use crate::design::{Design, DesignBuilder, Layout, Model, Origin};
use crate::family::solve;
use crate::space::CellKind;

/// Invalid sizes for a topology generator.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TopologyError {
    /// The curve sizes do not make an edge bounded by two vertices.
    #[error(
        "a curve needs points ≥ 2, 1 ≤ vertex < points and arity ≥ 2 (got points = {points}, vertex = {vertex}, arity = {arity})"
    )]
    Curve {
        /// Control points of the edge.
        points: usize,
        /// Control points of a vertex.
        vertex: usize,
        /// Number of sub-edges.
        arity: usize,
    },
    /// A curve whose unknown matrices exceed what the exact solver takes.
    #[error(
        "a curve of {points} control points and arity {arity} has {unknowns} unknown entries (arity × points² + vertex²): the exact solver takes at most {max}; use fewer control points"
    )]
    TooLarge {
        /// Control points of the edge.
        points: usize,
        /// Number of sub-edges.
        arity: usize,
        /// Unknown entries.
        unknowns: u128,
        /// The limit, [`crate::design::MAX_UNKNOWNS`].
        max: usize,
    },
    /// The generated automaton does not build or solve: a bug.
    #[error("internal error in a topology generator (please report): {0}")]
    Internal(String),
}

fn internal(e: impl std::fmt::Display) -> TopologyError {
    TopologyError::Internal(e.to_string())
}

/// The cardinal B-spline of degree `d` (support `[0, d+1]`) at `x`.
pub(crate) fn cardinal_bspline(d: usize, x: f64) -> f64 {
    let mut sum = 0.0;
    let mut binom = 1.0;
    for k in 0..=d + 1 {
        let t = x - k as f64;
        if t > 0.0 {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            sum += sign * binom * t.powi(d as i32);
        }
        binom = binom * (d + 1 - k) as f64 / (k + 1) as f64;
    }
    sum / (1..=d).map(|i| i as f64).product::<f64>()
}

/// The `p` subdivision matrices of the uniform B-spline of degree `d` on one
/// segment (`d + 1` control points), exactly: `T_l` maps the control points
/// of the sub-segment `[l/p, (l+1)/p]` into those of the segment (the
/// transposed blocks of the stationary scheme, Schaefer et al. 2005 §3.1).
/// Chaikin's (`d = 2, p = 2`) are `[[3/4, 1/4, 0], [1/4, 3/4, 3/4], [0, 0, 1/4]]` and its mirror.
///
/// ```
/// let t = bcifs::schemes::bspline_segment_parts(2, 3);
/// assert_eq!(t[0][2][2].to_string(), "1/9");
/// ```
pub fn bspline_segment_parts(d: usize, p: usize) -> Vec<super::stationary::ExactMatrix> {
    super::stationary::BSpline::uniform(d, d + 1)
        .and_then(|b| b.blocks(p))
        .map(|blocks| blocks.iter().map(super::stationary::transposed).collect())
        .unwrap_or_default()
}

/// [`bspline_segment_parts`] in floating point.
pub fn bspline_segment_matrices(d: usize, p: usize) -> Vec<nalgebra::DMatrix<f64>> {
    bspline_segment_parts(d, p)
        .iter()
        .map(|m| nalgebra::DMatrix::from_fn(m.len(), m.len(), |i, j| m[i][j].to_f64()))
        .collect()
}

fn letters(count: usize) -> Vec<String> {
    if count <= 26 {
        (0..count).map(|i| ((b'a' + i as u8) as char).to_string()).collect()
    } else {
        (1..=count).map(|i| format!("p{i}")).collect()
    }
}

/// Solves the structure (no parameters yet) and names its free entries
/// `a, b, c, ...` (column-major within each arrow, arrows in order).
fn name_free_entries(structure: &DesignBuilder) -> Result<Vec<(String, String, usize, usize)>, TopologyError> {
    free_entries(structure).map_err(internal)
}

/// The free entries of the solved structure `(name, arrow, row, column)`,
/// named `a, b, c, …` (or `p1, p2, …` past 26), column-major within each
/// arrow, arrows in order.
///
/// # Errors
/// The structure does not build or solve.
pub(super) fn free_entries(structure: &DesignBuilder) -> Result<Vec<(String, String, usize, usize)>, String> {
    let design = structure.build().map_err(|e| e.to_string())?;
    let family = solve(&design).map_err(|e| e.to_string())?;
    let order = |arrow: &str| design.automaton().arrow_id(arrow).map_or(usize::MAX, |i| i.index());
    let mut free: Vec<(String, usize, usize)> = family
        .parameters
        .iter()
        .filter_map(|p| match &p.origin {
            Origin::Entry { arrow, row, col } => Some((arrow.clone(), *row, *col)),
            Origin::Parameter => None,
        })
        .collect();
    free.sort_by_key(|(a, r, c)| (order(a), *c, *r));
    Ok(letters(free.len()).into_iter().zip(free).map(|(l, (a, r, c))| (l, a, r, c)).collect())
}

/// The design of a curve: an edge with `points` control points, vertices
/// with `vertex` control points (the first and the last `vertex` points of
/// the edge), split into `arity` sub-edges, with a closed star-shaped
/// control polygon as its model. `bcifs new curve` prints it.
///
/// Free parameters are named `a, b, ...`; when `vertex = points - 1` the
/// uniform B-spline of degree `points - 1` belongs to the family and gives
/// the defaults.
///
/// ```
/// let d = bcifs::schemes::curve(3, 2, 2).unwrap();
/// let f = bcifs::solve(&d).unwrap();
/// assert_eq!(f.parameter_names(), ["a", "b"]); // the corner-cutting family of Sokolov et al. 2010 §3
/// ```
///
/// # Errors
/// [`TopologyError::Curve`] for sizes that do not make a curve.
pub fn curve(points: usize, vertex: usize, arity: usize) -> Result<Design, TopologyError> {
    if points < 2 || vertex == 0 || vertex >= points || arity < 2 {
        return Err(TopologyError::Curve { points, vertex, arity });
    }
    let unknowns = (arity as u128) * (points as u128).pow(2) + (vertex as u128).pow(2);
    let max = crate::design::MAX_UNKNOWNS;
    if unknowns > max as u128 {
        return Err(TopologyError::TooLarge { points, arity, unknowns, max });
    }
    let mut b = Design::builder(format!("curve_{points}_{vertex}_{arity}"));
    b.description(format!("curve, {points} control points, vertex support {vertex}, {arity}-ary")).doc(format!(
        "A BC-IFS curve: an edge with {points} control points bounded by two vertices with {vertex}\n\
         control points each, subdivided into {arity} sub-edges (generated by `bcifs new curve`).\n\
         Paths read in arrow order: `T0 b1` is the right end of the first sub-edge."
    ));
    b.state("e", points, CellKind::Edge).doc(format!("The edge: barycentric space BI^{points}."));
    b.state("v", vertex, CellKind::Vertex).doc(format!("A vertex (both ends share it): BI^{vertex}."));
    for i in 0..arity {
        b.unknown(format!("T{i}"), "e", "e").doc(format!("Sub-edge {i} of {arity}, from the left."));
    }
    b.unknown("Tv", "v", "v").doc("Subdivision of the vertex.");
    b.select("b0", "e", "v", 0..vertex).doc("Left end: the vertex depends on the first control points of the edge.");
    b.select("b1", "e", "v", points - vertex..points)
        .doc("Right end: the vertex depends on the last control points of the edge.");
    for i in 0..arity - 1 {
        b.adjacency(format!("T{i} b1 = T{} b0", i + 1)).doc("Neighbouring sub-edges share their common end.");
    }
    b.incidence("T0 b0 = b0 Tv").incidence(format!("T{} b1 = b1 Tv", arity - 1));
    b.doc("The ends of the subdivided edge are the subdivided ends.");
    let named = name_free_entries(&b)?;
    let defaults = (vertex == points - 1).then(|| bspline_segment_parts(points - 1, arity));
    for (l, arrow, r, c) in &named {
        b.name_entry(l.clone(), format!("{arrow}[{r}][{c}]"));
        if let Some(ms) = &defaults {
            let i = arrow.strip_prefix('T').and_then(|i| i.parse::<usize>().ok()).unwrap_or(0);
            // Exact: 7/9, not 0.777…
            b.default_value(l, crate::algebra::Num::from(ms[i][*r][*c].clone()));
        }
    }
    if !named.is_empty() {
        b.doc(format!(
            "{} free parameters (degrees of freedom of the admissible family){}.",
            named.len(),
            if defaults.is_some() {
                format!("; defaults: the uniform B-spline of degree {}", points - 1)
            } else {
                String::new()
            }
        ));
    }
    // A closed star-shaped control polygon: 8 windows of `points` control points.
    let m = 8 * (points - vertex);
    let star: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / m as f64;
            let r = if i % 2 == 0 { 1.0 } else { 0.55 };
            vec![(r * t.cos() * 1e6).round() / 1e6, (r * t.sin() * 1e6).round() / 1e6]
        })
        .collect();
    b.model(Model::new("e", star).with_layout(Layout::Closed))
        .doc("A closed star-shaped control polygon (render with `bcifs render`).");
    b.build().map_err(internal)
}

/// Grid indices `(row, col) → row * cols + col` of a rectangle of a grid.
fn block(cols: usize, rows: std::ops::Range<usize>, columns: std::ops::Range<usize>) -> Vec<usize> {
    rows.flat_map(|r| columns.clone().map(move |c| r * cols + c)).collect()
}

/// Adjacency of the quad patch: neighbouring sub-cells share their boundary.
const QUAD_ADJACENCY: [&str; 6] = [
    "T00 right = T10 left",
    "T01 right = T11 left",
    "T00 top = T01 bottom",
    "T10 top = T11 bottom",
    "U0 u_end = U1 u_start",
    "V0 v_end = V1 v_start",
];

/// Incidence of the quad patch: the boundary of a sub-cell is the subdivided boundary.
const QUAD_INCIDENCE: [&str; 12] = [
    "T00 bottom = bottom U0",
    "T10 bottom = bottom U1",
    "T01 top = top U0",
    "T11 top = top U1",
    "T00 left = left V0",
    "T01 left = left V1",
    "T10 right = right V0",
    "T11 right = right V1",
    "U0 u_start = u_start W",
    "U1 u_end = u_end W",
    "V0 v_start = v_start W",
    "V1 v_end = v_end W",
];

/// The rotationally symmetric vertex rule: corners counter-clockwise in
/// (u, v) are (0,0)=0, (1,0)=1, (1,1)=3, (0,1)=2; column c of W (the new
/// point near corner c) weighs corner c by alpha, the next corner by beta,
/// the previous by gamma.
const QUAD_SYMMETRY: [&str; 9] = [
    "W[1][1] = W[0][0]",
    "W[3][3] = W[0][0]",
    "W[2][2] = W[0][0]",
    "W[3][1] = W[1][0]",
    "W[2][3] = W[1][0]",
    "W[0][2] = W[1][0]",
    "W[0][1] = W[2][0]",
    "W[1][3] = W[2][0]",
    "W[3][2] = W[2][0]",
];

/// The design of the Doo-Sabin-like quad patch (DESIGN §2): a face with a
/// 3×3 grid of control points split into 2×2 sub-faces, one edge state
/// along u (2 rows of 3) and one along v (3 rows of 2), and a 2×2 vertex.
/// With `symmetric`, the vertex rule is rotationally symmetric with weights
/// α (own corner), β (next), γ (previous), δ = 1 - α - β - γ (opposite):
/// 3 free parameters, `(9/16, 3/16, 3/16)` by default (the biquadratic
/// B-spline). `bcifs new quad-patch` prints it.
///
/// # Errors
/// [`TopologyError::Internal`] only (a bug).
pub fn quad_patch(symmetric: bool) -> Result<Design, TopologyError> {
    let mut b = Design::builder(if symmetric { "doo_sabin_quad" } else { "quad_patch" });
    b.description(if symmetric {
        "Doo-Sabin-like quad patch, rotationally symmetric vertex rule"
    } else {
        "quad patch, general vertex rule"
    })
    .doc(
        "The Doo-Sabin-like quad patch as a face-edge-vertex BC-IFS (generated by `bcifs new quad-patch`).\n\
         Control points are numbered row by row: index = 3*row + col on the 3×3 face grid (row = v, col = u).\n\
         Sub-face Tuv is the one at position (u, v) in {0,1}²: T00 bottom-left, T10 bottom-right,\n\
         T01 top-left, T11 top-right. Boundary cells keep the grid orientation, so a single\n\
         vertex rule W acts at all four corners of a face.",
    );
    b.state("face", 9, CellKind::Face).doc("The face: 3×3 control grid, BI^9.");
    b.state("edge_u", 6, CellKind::Edge).doc("An edge along u: 2 rows of 3 control points, BI^6 (index 3*row + col).");
    b.state("edge_v", 6, CellKind::Edge).doc("An edge along v: 3 rows of 2 control points, BI^6 (index 2*row + col).");
    b.state("vertex", 4, CellKind::Vertex).doc("A corner: 2×2 block of control points, BI^4 (index 2*row + col).");
    for (name, pos) in [("T00", "bottom-left"), ("T10", "bottom-right"), ("T01", "top-left"), ("T11", "top-right")] {
        b.unknown(name, "face", "face").doc(format!("Sub-face {pos}."));
    }
    b.unknown("U0", "edge_u", "edge_u").doc("Left half of an edge along u.");
    b.unknown("U1", "edge_u", "edge_u").doc("Right half of an edge along u.");
    b.unknown("V0", "edge_v", "edge_v").doc("Lower half of an edge along v.");
    b.unknown("V1", "edge_v", "edge_v").doc("Upper half of an edge along v.");
    b.unknown("W", "vertex", "vertex").doc("The vertex rule: new 2×2 corner block from the old one.");
    b.select("bottom", "face", "edge_u", block(3, 0..2, 0..3)).doc("Bottom edge: rows 0-1 of the face.");
    b.select("top", "face", "edge_u", block(3, 1..3, 0..3)).doc("Top edge: rows 1-2 of the face.");
    b.select("left", "face", "edge_v", block(3, 0..3, 0..2)).doc("Left edge: columns 0-1 of the face.");
    b.select("right", "face", "edge_v", block(3, 0..3, 1..3)).doc("Right edge: columns 1-2 of the face.");
    b.select("u_start", "edge_u", "vertex", block(3, 0..2, 0..2)).doc("Start of an edge along u: its columns 0-1.");
    b.select("u_end", "edge_u", "vertex", block(3, 0..2, 1..3)).doc("End of an edge along u: its columns 1-2.");
    b.select("v_start", "edge_v", "vertex", block(2, 0..2, 0..2)).doc("Start of an edge along v: its rows 0-1.");
    b.select("v_end", "edge_v", "vertex", block(2, 1..3, 0..2)).doc("End of an edge along v: its rows 1-2.");
    for e in QUAD_ADJACENCY {
        b.adjacency(e);
    }
    b.doc("Neighbouring sub-cells share their common boundary.");
    for e in QUAD_INCIDENCE {
        b.incidence(e);
    }
    b.doc("The boundary of a sub-cell is the subdivided boundary.");
    quad_parameters(&mut b, symmetric)?;
    // An open 5×5 control grid with a raised centre: 3×3 patches.
    let grid: Vec<Vec<f64>> = (0..25)
        .map(|k| {
            let (r, c) = (k / 5, k % 5);
            let z = match (r, c) {
                (2, 2) => 2.0,
                (1..=3, 1..=3) => 0.8,
                _ => 0.0,
            };
            vec![c as f64, r as f64, z]
        })
        .collect();
    b.model(Model::new("face", grid).with_layout(Layout::Grid).with_grid(5, 5))
        .doc("A 5×5 control grid (rows along v): 3×3 patches welded into one sheet.");
    b.build().map_err(internal)
}

/// The quad patch's parameters: the symmetric vertex rule's `alpha`,
/// `beta`, `gamma` (Doo-Sabin's by default), or every free entry of `W`.
fn quad_parameters(b: &mut DesignBuilder, symmetric: bool) -> Result<(), TopologyError> {
    if symmetric {
        for e in QUAD_SYMMETRY {
            b.constraint("symmetry", e);
        }
        b.doc(
            "Rotationally symmetric vertex rule: column c of W (the new point near corner c)\n\
             weighs corner c by alpha, the next corner counter-clockwise by beta, the previous by gamma.",
        );
        for (name, entry, sixteenths) in [("alpha", "W[0][0]", 9), ("beta", "W[1][0]", 3), ("gamma", "W[2][0]", 3)] {
            let exact = num_rational::BigRational::new(sixteenths.into(), 16.into());
            b.name_entry(name, entry).default_value(name, crate::algebra::Num::rational(exact));
        }
        b.doc(
            "3 free parameters; the defaults (9/16, 3/16, 3/16) give the regular Doo-Sabin rule,\n\
             i.e. the biquadratic B-spline patch.",
        );
    } else {
        let named = name_free_entries(b)?;
        for (l, a, r, c) in &named {
            b.name_entry(l.clone(), format!("{a}[{r}][{c}]"));
        }
        b.doc(format!("{} free parameters: the entries of the vertex rule W.", named.len()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cardinal_bspline_is_a_partition_of_unity() {
        for d in 0..5 {
            let x = 0.37;
            let sum: f64 = (0..=d).map(|i| cardinal_bspline(d, x + i as f64)).sum();
            assert!((sum - 1.0).abs() < 1e-12, "degree {d}: {sum}");
        }
        assert!((cardinal_bspline(2, 1.5) - 0.75).abs() < 1e-15);
    }

    #[test]
    fn chaikin_is_the_quadratic_bspline() {
        let m = bspline_segment_matrices(2, 2);
        let t0 = nalgebra::DMatrix::from_row_slice(3, 3, &[0.75, 0.25, 0.0, 0.25, 0.75, 0.75, 0.0, 0.0, 0.25]);
        assert!((&m[0] - t0).amax() < 1e-12, "{}", m[0]);
    }
}
