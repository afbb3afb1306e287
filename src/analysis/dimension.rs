//! Fractal dimension: box counting on a point set, and the similarity
//! dimension of an automaton whose maps are similarities of modelling space
//! (Moran's equation `Σ rᵢˢ = 1` for one state; for a graph-directed system
//! the Mauldin–Williams dimension, the `s` at which the spectral radius of
//! the matrix of `Σ rₑˢ` over the arrows between each pair of states is 1).
//!
//! A subdivision arrow `e: s → t` maps the attractor of `t`, placed by a
//! reference cell `C_t` of `t`, onto the cell `C_s M_e` inside the reference
//! cell of `s`. The map is a similarity exactly when the two point sets are
//! similar (every pairwise distance scaled by the same `rₑ`): then the
//! barycentric map `C_t λ ↦ C_s M_e λ` is that similarity. Reference cells:
//! the model's first piece for the root, and for every other state the first
//! cell met from it; another choice conjugates the matrix of `rₑˢ` by a
//! diagonal one and leaves its spectral radius, hence the dimension, as is.

use nalgebra::DMatrix;
use petgraph::graph::NodeIndex;

use crate::algebra::tolerance::{DEGENERATE, SAME_POINT, SLACK};
use crate::automaton::{ArrowKind, Automaton};

/// Scales in the box-counting fit: the finest ones.
const FITTED: usize = 5;

/// A box-counting estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxCount {
    /// The slope of `ln N(ε)` against `ln(1/ε)`.
    pub dimension: f64,
    /// The coefficient of determination of that fit.
    pub r2: f64,
    /// The scales: box side `ε` (modelling units) and boxes met `N(ε)`.
    pub scales: Vec<(f64, u64)>,
}

/// The box-counting dimension of `points`, by regression over the five
/// finest box sides `E/2^k` (`E` the largest side of the bounding box) that
/// are at least `2 · resolution` (the points are assumed to sample the set
/// to within `resolution`, every part of it); coarser scales are listed but
/// left out of the fit, where boundaries still weigh. `None` when the points
/// span nothing or the resolution leaves fewer than four scales.
///
/// Memory: one box key (24 bytes) a point, besides the points.
pub fn box_dimension(points: &[[f64; 3]], resolution: f64) -> Option<BoxCount> {
    box_dimension_of(|| points.iter().copied(), resolution, &crate::progress::Cancel::new()).ok().flatten()
}

/// The memory of one sample's key in [`box_dimension_of`].
pub const BOX_KEY_BYTES: usize = 8;

/// The largest box index along an axis (21 bits).
const FIELD: u64 = (1 << 21) - 1;

/// What a box count stopped by its cancel flag returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// [`box_dimension`] of samples made twice by `samples` (once for the
/// bounding box, once for the boxes), so that they need not be held: one
/// key of [`BOX_KEY_BYTES`] a sample is. Stops between scales when `cancel` is set.
///
/// The boxes of side `E/2^k` are counted at the finest scale first; a box
/// index at the next coarser scale is the finer one halved (rounded down),
/// exactly: the sides are the extent scaled by powers of two, so the
/// quotients are too. Each scale sorts the keys left by the finer one.
/// A key packs the three indices in 21 bits each (2²¹ boxes a side: finer
/// than any resolution asked here; a finer scale is left out of the count).
///
/// # Errors
/// [`Cancelled`] when the flag was set.
pub fn box_dimension_of<I: Iterator<Item = [f64; 3]>>(
    samples: impl Fn() -> I,
    resolution: f64,
    cancel: &crate::progress::Cancel,
) -> Result<Option<BoxCount>, Cancelled> {
    let mut it = samples();
    let Some(first) = it.next() else { return Ok(None) };
    let (mut lo, mut hi) = (first, first);
    for p in it {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    if !(extent > 0.0 && extent.is_finite()) {
        return Ok(None);
    }
    // The finest scale: the last k ≤ 20 whose side is at least 2 · resolution
    // (indices up to 2^20, within a key's 21 bits).
    let finest = (2..=20).take_while(|&k| extent * 0.5f64.powi(k) >= 2.0 * resolution).last();
    let Some(finest) = finest.filter(|k| k - 2 + 1 >= 4) else { return Ok(None) };
    let eps = extent * 0.5f64.powi(finest);
    let index = |p: [f64; 3], a: usize| (((p[a] - lo[a]) / eps).floor() as u64).min(FIELD);
    let mut keys: Vec<u64> = samples().map(|p| index(p, 0) << 42 | index(p, 1) << 21 | index(p, 2)).collect();
    let mut scales = Vec::new();
    for k in (2..=finest).rev() {
        if cancel.is_cancelled() {
            return Err(Cancelled);
        }
        if k < finest {
            // Each field halved: the bit shifted out of a field's bottom into the next one's top is cleared.
            for key in &mut keys {
                *key = (*key >> 1) & !(1 << 20 | 1 << 41);
            }
        }
        keys.sort_unstable();
        keys.dedup();
        scales.push((extent * 0.5f64.powi(k), keys.len() as u64));
    }
    scales.reverse();
    let fitted = &scales[scales.len().saturating_sub(FITTED)..];
    let xy: Vec<(f64, f64)> = fitted.iter().map(|(e, n)| ((1.0 / e).ln(), (*n as f64).ln())).collect();
    let n = xy.len() as f64;
    let (mx, my) = (xy.iter().map(|p| p.0).sum::<f64>() / n, xy.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = xy.iter().map(|p| (p.1 - my).powi(2)).sum();
    let slope = sxy / sxx;
    let r2 = if syy > 0.0 { sxy * sxy / (sxx * syy) } else { 1.0 };
    Ok(Some(BoxCount { dimension: slope, r2, scales }))
}

/// The ratio of a similarity taking the points `x` onto `y` (columns of
/// `d × n` row-major arrays), or `None` when none does (to `1e-9` relative).
fn similarity_ratio(x: &[f64], y: &[f64], d: usize, n: usize) -> Option<f64> {
    let dist =
        |c: &[f64], i: usize, j: usize| (0..d).map(|a| (c[a * n + i] - c[a * n + j]).powi(2)).sum::<f64>().sqrt();
    let mut ratio: Option<f64> = None;
    let scale = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| dist(x, i, j)).fold(0.0, f64::max);
    if scale == 0.0 {
        return None;
    }
    for i in 0..n {
        for j in i + 1..n {
            let (dx, dy) = (dist(x, i, j), dist(y, i, j));
            if dx < DEGENERATE * scale {
                if dy > SAME_POINT * scale {
                    return None;
                }
                continue;
            }
            match ratio {
                None => ratio = Some(dy / dx),
                Some(r) if (dy / dx - r).abs() > SLACK * r.max(DEGENERATE) => return None,
                _ => {}
            }
        }
    }
    ratio
}

/// The similarity (Moran, or Mauldin–Williams) dimension of the attractor
/// of the cell of state `root` with control points `control` (`d` rows of
/// `dim(root)` coordinates, row-major: a model's first piece), or `None`
/// when a subdivision arrow reachable from it is not a similarity of
/// modelling space, or its cycles do not contract.
pub fn similarity_dimension(automaton: &Automaton<f64>, root: NodeIndex, control: &[f64], d: usize) -> Option<f64> {
    let n_root = automaton.state(root).dim;
    if d == 0 || control.len() != d * n_root {
        return None;
    }
    let reference = control.to_vec();
    // Reference cells, and the ratio of every reachable subdivision arrow.
    let mut cells: Vec<(NodeIndex, Vec<f64>)> = vec![(root, reference)];
    let mut edges: Vec<(usize, usize, f64)> = Vec::new();
    let mut at = 0;
    while at < cells.len() {
        let (s, c) = cells[at].clone();
        let ns = automaton.state(s).dim;
        for e in automaton.outgoing(s, ArrowKind::Subdivision) {
            let (_, t) = automaton.arrow_ends(e);
            let m = &automaton.arrow(e).matrix;
            let nt = automaton.state(t).dim;
            let cm = DMatrix::from_row_slice(d, ns, &c) * m;
            let child: Vec<f64> = (0..d).flat_map(|a| (0..nt).map(move |j| (a, j))).map(|(a, j)| cm[(a, j)]).collect();
            let ti = match cells.iter().position(|(u, _)| *u == t) {
                Some(i) => i,
                None => {
                    cells.push((t, child.clone()));
                    cells.len() - 1
                }
            };
            // A ratio may be 1 or more (the arrow that placed a reference cell): what
            // must contract are the cycles, which the bisection below requires.
            let r = similarity_ratio(&cells[ti].1, &child, d, nt)?;
            edges.push((at, ti, r));
        }
        at += 1;
    }
    if edges.is_empty() {
        return None;
    }
    let k = cells.len();
    let rho = |s: f64| {
        let mut m = DMatrix::<f64>::zeros(k, k);
        for &(u, v, r) in &edges {
            m[(u, v)] += r.powf(s);
        }
        crate::algebra::eigenvalues(&m).map_or(f64::INFINITY, |e| e.iter().map(|z| z.norm()).fold(0.0, f64::max))
    };
    // ρ(s) decreases from the number of arrows of a cycle (s = 0) to 0: bisect for ρ = 1.
    if rho(0.0) <= 1.0 {
        return Some(0.0);
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while rho(hi) > 1.0 {
        hi *= 2.0;
        if hi > 1e3 {
            return None;
        }
    }
    for _ in 0..100 {
        let mid = (lo + hi) / 2.0;
        if rho(mid) > 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((lo + hi) / 2.0)
}

/// What is known of Moran's open set condition for the attractor whose
/// similarity dimension is `s` (see [`similarity_dimension`]), and why.
#[derive(Clone, Debug, PartialEq)]
pub struct OpenSet {
    /// `Some(true)`: it holds (the Hausdorff dimension is `s`); `Some(false)`:
    /// it fails; `None`: not known. Unless it holds, `s` is only an upper
    /// bound of the Hausdorff dimension.
    pub holds: Option<bool>,
    /// The reason, in a sentence.
    pub reason: String,
}

/// Relative tolerance of the geometric tests of [`open_set_condition`].
const TOUCH: f64 = 1e-9;

/// Moran's open set condition for the attractor of `root` with control
/// points `control` (`d` rows, row-major), whose similarity dimension is `s`:
///
/// - it **fails** when two arrows from a state are the same map (the images
///   coincide), or when `s` exceeds the dimension `k` of the affine span of
///   the control points (with the condition the Hausdorff dimension is `s`,
///   and the attractor lies in that span, so `s ≤ k`): three maps of ratio
///   1/2 on a segment have `s = log 3 / log 2 > 1`;
/// - it **holds** for one state with non-negative matrices whose control
///   points span at most 3 dimensions: the polytope `P` they span (their
///   convex hull; a simplex when they are `k + 1`) holds each image
///   (an image's control points are convex combinations of `P`'s, and the
///   similarity taking the control points onto an image's takes `P` onto
///   the image's hull), and when the images meet only on their boundaries
///   (a separating hyperplane for every pair) the open set is `P`'s
///   interior: the gasket, the Cantor set, the Koch curve, the Menger
///   sponge and Cantor dust on their cube;
/// - otherwise it is not known.
pub fn open_set_condition(automaton: &Automaton<f64>, root: NodeIndex, control: &[f64], d: usize, s: f64) -> OpenSet {
    let n = automaton.state(root).dim;
    let unknown = |reason: &str| OpenSet { holds: None, reason: reason.to_string() };
    if d == 0 || control.len() != d * n {
        return unknown("the model does not fit the root state");
    }
    let point = |j: usize| (0..d).map(|a| control[a * n + j]).collect::<Vec<f64>>();
    let (basis, scale) = span(&(0..n).map(point).collect::<Vec<_>>());
    let k = basis.len();
    if let Some(same) = repeated_map(automaton, root) {
        return same;
    }
    if s > k as f64 + SLACK {
        return OpenSet {
            holds: Some(false),
            reason: format!(
                "the similarity dimension {s:.6} exceeds {k}, the dimension of the span of the control points: the images overlap"
            ),
        };
    }
    let states = reachable(automaton, root);
    if states.len() != 1 {
        return unknown("a graph-directed system: no test of the condition is known here");
    }
    if k == 0 || k > 3 {
        return unknown("the control points span more than three dimensions: no test of the condition is known here");
    }
    let arrows = automaton.outgoing(root, ArrowKind::Subdivision);
    if arrows.iter().any(|&e| automaton.arrow(e).matrix.iter().any(|x| *x < -TOUCH)) {
        return unknown("a matrix has negative entries: an image may leave the control points' hull");
    }
    // The images of the simplex, in coordinates of the span.
    let origin = point(0);
    let local = |p: &[f64]| -> Vec<f64> {
        basis.iter().map(|u| u.iter().zip(p).zip(&origin).map(|((u, p), o)| u * (p - o)).sum()).collect()
    };
    let images: Vec<Vec<Vec<f64>>> = arrows
        .iter()
        .map(|&e| {
            let m = &automaton.arrow(e).matrix;
            (0..n)
                .map(|j| {
                    let p: Vec<f64> = (0..d).map(|a| (0..n).map(|i| control[a * n + i] * m[(i, j)]).sum()).collect();
                    local(&p)
                })
                .collect()
        })
        .collect();
    for (i, a) in images.iter().enumerate() {
        for (j, b) in images.iter().enumerate().skip(i + 1) {
            if !separated(a, b, scale) {
                let name = |x: usize| automaton.arrow(arrows[x]).name.clone();
                return unknown(&format!(
                    "the images of the control points' hull by {} and {} overlap: another open set may exist",
                    name(i),
                    name(j)
                ));
            }
        }
    }
    OpenSet {
        holds: Some(true),
        reason: if n == k + 1 {
            "the images of the control simplex meet only on their boundaries (the open set is its interior)"
        } else {
            "the images of the control points' hull meet only on their boundaries (the open set is its interior)"
        }
        .to_string(),
    }
}

/// The condition failing because two arrows from a state reachable from
/// `root` are the same map (their images coincide), if two are.
fn repeated_map(automaton: &Automaton<f64>, root: NodeIndex) -> Option<OpenSet> {
    for state in reachable(automaton, root) {
        let arrows = automaton.outgoing(state, ArrowKind::Subdivision);
        for (i, &e) in arrows.iter().enumerate() {
            for &f in &arrows[i + 1..] {
                let (a, b) = (automaton.arrow(e), automaton.arrow(f));
                if automaton.arrow_ends(e).1 == automaton.arrow_ends(f).1
                    && (&a.matrix - &b.matrix).amax() <= TOUCH * a.matrix.amax().max(1.0)
                {
                    return Some(OpenSet {
                        holds: Some(false),
                        reason: format!("arrows {} and {} are the same map", a.name, b.name),
                    });
                }
            }
        }
    }
    None
}

/// The states reachable from `root` by subdivision arrows, `root` first.
fn reachable(automaton: &Automaton<f64>, root: NodeIndex) -> Vec<NodeIndex> {
    let mut out = vec![root];
    let mut at = 0;
    while at < out.len() {
        for e in automaton.outgoing(out[at], ArrowKind::Subdivision) {
            let t = automaton.arrow_ends(e).1;
            if !out.contains(&t) {
                out.push(t);
            }
        }
        at += 1;
    }
    out
}

/// An orthonormal basis of the affine span of `points` (Gram–Schmidt on
/// the differences from the first, dropping those within [`TOUCH`] of the
/// span so far), and the largest difference's length.
fn span(points: &[Vec<f64>]) -> (Vec<Vec<f64>>, f64) {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let diffs: Vec<Vec<f64>> =
        points.iter().skip(1).map(|p| p.iter().zip(&points[0]).map(|(x, o)| x - o).collect()).collect();
    let scale = diffs.iter().map(|v| dot(v, v).sqrt()).fold(0.0, f64::max);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for v in diffs {
        let mut w = v.clone();
        for u in &basis {
            let c = dot(&w, u);
            w.iter_mut().zip(u).for_each(|(x, y)| *x -= c * y);
        }
        let len = dot(&w, &w).sqrt();
        if len > TOUCH * scale.max(f64::MIN_POSITIVE) {
            basis.push(w.iter().map(|x| x / len).collect());
        }
    }
    (basis, scale)
}

/// Whether the convex hulls of two point sets in `R^k` (`k ≤ 3`; points as
/// rows) have disjoint interiors: a separating axis among the normals of
/// their facets (and, in 3D, the cross products of an edge of each), touching
/// within [`TOUCH`] of `scale` allowed. The facets' and edges' directions are
/// among the differences of the hulls' vertices, which [`hull_candidates`]
/// over-approximates: every axis tried is tested on all the points, so a
/// separation found is one.
fn separated(a: &[Vec<f64>], b: &[Vec<f64>], scale: f64) -> bool {
    let k = a[0].len();
    let mut axes: Vec<Vec<f64>> = Vec::new();
    let edges = |s: &[Vec<f64>]| -> Vec<Vec<f64>> {
        let s = hull_candidates(s);
        let mut out = Vec::new();
        for i in 0..s.len() {
            for j in i + 1..s.len() {
                out.push(s[j].iter().zip(&s[i]).map(|(x, y)| x - y).collect());
            }
        }
        out
    };
    let cross =
        |u: &[f64], v: &[f64]| vec![u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    match k {
        1 => axes.push(vec![1.0]),
        2 => {
            for e in edges(a).into_iter().chain(edges(b)) {
                axes.push(vec![-e[1], e[0]]);
            }
        }
        3 => {
            let (ea, eb) = (edges(a), edges(b));
            for set in [&ea, &eb] {
                for (i, u) in set.iter().enumerate() {
                    for v in &set[i + 1..] {
                        axes.push(cross(u, v));
                    }
                }
            }
            for u in &ea {
                for v in &eb {
                    axes.push(cross(u, v));
                }
            }
        }
        _ => return false,
    }
    axes.iter().any(|axis| {
        let len = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        if len <= TOUCH * scale * scale {
            return false;
        }
        let project = |s: &[Vec<f64>]| {
            s.iter()
                .map(|p| p.iter().zip(axis).map(|(x, y)| x * y).sum::<f64>() / len)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
        };
        let ((alo, ahi), (blo, bhi)) = (project(a), project(b));
        ahi <= blo + TOUCH * scale || bhi <= alo + TOUCH * scale
    })
}

/// Points among `points` (rows in `R^k`, `k ≤ 3`) that hold every vertex of
/// their convex hull: all of them when they are few (a simplex, a cube's
/// corners), else those extreme along 146 directions spread over the sphere
/// (or circle), which finds the corners of the control nets of higher
/// degree (a 4×4×4 net's hull is its 8 corners). A vertex missed only
/// loses candidate axes: [`separated`] may then answer "not known", never wrong.
fn hull_candidates(points: &[Vec<f64>]) -> Vec<Vec<f64>> {
    const FEW: usize = 8;
    const DIRECTIONS: usize = 146;
    if points.len() <= FEW {
        return points.to_vec();
    }
    let k = points[0].len();
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut chosen: Vec<usize> = Vec::new();
    for i in 0..DIRECTIONS {
        // A Fibonacci lattice on the sphere (the circle in 2D): no direction along an axis,
        // so a grid's faces do not tie.
        let z = 1.0 - (2 * i + 1) as f64 / DIRECTIONS as f64;
        let t = golden * i as f64 + 0.1;
        let dir: Vec<f64> = match k {
            1 => vec![if i % 2 == 0 { 1.0 } else { -1.0 }],
            2 => vec![t.cos(), t.sin()],
            _ => {
                let r = (1.0 - z * z).sqrt();
                vec![r * t.cos(), r * t.sin(), z]
            }
        };
        let dot = |p: &Vec<f64>| p.iter().zip(&dir).map(|(x, y)| x * y).sum::<f64>();
        let best = (0..points.len()).max_by(|&x, &y| dot(&points[x]).total_cmp(&dot(&points[y]))).unwrap_or(0);
        if !chosen.contains(&best) {
            chosen.push(best);
        }
    }
    chosen.into_iter().map(|i| points[i].clone()).collect()
}
