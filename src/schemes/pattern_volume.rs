//! Volume patterns: a hexahedron split into a `k × l × m` grid of sub-cells
//! (the Menger sponge keeps 20 of 27), and a tetrahedron split into its four
//! corner tetrahedra (the Sierpiński tetrahedron keeps all four).
//!
//! A hexahedron carries `D³` control points (index `D²·w + D·v + u`), and
//! its B-rep has one state per set of directions a cell extends along: the
//! volume (`u v w`), three faces (`u v`, `u w`, `v w`: `D²` points, the first
//! direction fastest), three edges and a vertex. A cell's boundary arrow
//! fixes one of its directions at its start or end (`uvw_w0` is the bottom
//! face, `uv_u1` a face's side at `u = 1`, `u_u0` an edge's start), its
//! selection the control points there in order. The faces, edges and the
//! vertex are subdivided whole (their grids of parts); the volume keeps the
//! mask's sub-cells. A tetrahedron carries its four corners (degree 2:
//! linear), its faces three, its edges two.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

use super::stationary::{BSpline, ExactMatrix, curve_structure, kron, transposed};
use crate::design::{DesignBuilder, Layout, Model};
use crate::space::{CellKind, Patch};

/// The directions' letters.
const AXES: [char; 3] = ['u', 'v', 'w'];

/// The letters of a set of directions (`uv`).
fn letters(axes: &[usize]) -> String {
    axes.iter().map(|&a| AXES[a]).collect()
}

/// The state of the cells extending along `axes`.
fn state(axes: &[usize]) -> String {
    match axes.len() {
        3 => "volume".into(),
        2 => format!("face_{}", letters(axes)),
        1 => format!("edge_{}", letters(axes)),
        _ => "vertex".into(),
    }
}

fn kind(axes: &[usize]) -> CellKind {
    [CellKind::Vertex, CellKind::Edge, CellKind::Face, CellKind::Volume][axes.len()]
}

/// The boundary arrow of a cell along `axes` fixing direction `a` at its start (0) or end (1).
fn boundary(axes: &[usize], a: usize, end: usize) -> String {
    format!("{}_{}{end}", letters(axes), AXES[a])
}

/// The subdivision arrow of the sub-cell `at` (one index per direction of `axes`).
fn sub(axes: &[usize], at: &[usize]) -> String {
    let index = at.iter().map(ToString::to_string).collect::<Vec<_>>().join("_");
    match axes.len() {
        3 => format!("T{index}"),
        0 => "X".into(),
        _ => format!("{}{index}", letters(axes).to_uppercase()),
    }
}

/// Every multi-index below `sizes`, the first direction fastest.
fn grid(sizes: &[usize]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for &n in sizes {
        out = (0..n).flat_map(|i| out.iter().map(move |x| [x.clone(), vec![i]].concat())).collect();
    }
    out
}

/// `axes` without direction `a`.
fn without(axes: &[usize], a: usize) -> Vec<usize> {
    axes.iter().copied().filter(|&x| x != a).collect()
}

/// How a hexahedron pattern's cells hold their control points along each
/// direction: `n` along a direction a cell extends, `k` layers across a
/// side (those a side's points depend on: 1 for Bézier grids, 3 for a cubic
/// B-spline), the end side's first layer, and the matrices when they are
/// fixed (the uniform B-spline's: parts per direction and a side's rule,
/// each `old × new`; none: unknowns the solver finds).
pub(super) struct Layers {
    n: usize,
    k: usize,
    end: usize,
    fixed: Option<([Vec<ExactMatrix>; 3], [ExactMatrix; 3])>,
}

impl Layers {
    /// Bézier grids of `d` points a direction: a side is its boundary layer, the matrices unknown.
    pub(super) fn bezier(d: usize) -> Layers {
        Layers { n: d, k: 1, end: d - 1, fixed: None }
    }

    /// The uniform B-spline of degree `d − 1` on `d` points a direction, split
    /// `split`: its curve subdivision's parts along each direction, tensored
    /// (Schaefer et al. 2005 §3.1, one dimension up).
    pub(super) fn bspline(d: usize, split: &[usize]) -> Result<Layers, String> {
        let mut parts: [Vec<ExactMatrix>; 3] = Default::default();
        // Across a side the rule of its own direction's split (a 2 × 3 × 2 split has two).
        let mut rules: [ExactMatrix; 3] = Default::default();
        let mut structure = None;
        for (a, &p) in split.iter().enumerate().take(3) {
            let blocks =
                BSpline::uniform(d - 1, d).and_then(|b| b.blocks(p)).map_err(|e| format!("B-spline parts: {e}"))?;
            let s = curve_structure(&blocks).filter(|s| s.start == 0 && s.start_rule == s.end_rule);
            let s = s.ok_or("the B-spline parts make no curve with one end rule")?;
            parts[a] = blocks.iter().map(transposed).collect();
            rules[a] = transposed(&s.start_rule);
            structure = Some(s);
        }
        let s = structure.ok_or("no direction")?;
        Ok(Layers { n: d, k: s.support, end: s.end, fixed: Some((parts, rules)) })
    }

    /// Control points of a cell along `axes`.
    fn size(&self, axes: &[usize]) -> usize {
        (0..3).map(|x| if axes.contains(&x) { self.n } else { self.k }).product()
    }

    /// The sizes of a cell along `axes`, per direction.
    fn sizes(&self, axes: &[usize]) -> Vec<usize> {
        (0..3).map(|x| if axes.contains(&x) { self.n } else { self.k }).collect()
    }

    /// The fixed matrix of the sub-cell `at` of a cell along `axes`: the
    /// parts along its directions, the side's rule across the others (w slowest).
    fn tensor(&self, axes: &[usize], at: &[usize]) -> Option<ExactMatrix> {
        let (parts, rules) = self.fixed.as_ref()?;
        let factor = |x: usize| match axes.iter().position(|&a| a == x) {
            Some(t) => &parts[x][at[t]],
            None => &rules[x],
        };
        Some(kron(factor(2), &kron(factor(1), factor(0))))
    }

    /// The coordinate of control point `i` of a direction in the default
    /// lattice: the unit interval's (a Bézier grid's points evenly spread,
    /// a B-spline's at its Greville abscissae, `i − (n − 2)/2`).
    fn coordinate(&self, i: usize) -> f64 {
        match self.fixed {
            None => i as f64 / (self.n - 1) as f64,
            Some(_) => i as f64 - (self.n as f64 - 2.0) / 2.0,
        }
    }
}

/// The control points of a cell along `axes` that lie on its side fixing
/// `a` at `end` (the `k` layers there), in the side's own order (u fastest).
fn select(axes: &[usize], a: usize, end: usize, layers: &Layers) -> Vec<usize> {
    let (from, to) = (layers.sizes(axes), layers.sizes(&without(axes, a)));
    grid(&to)
        .into_iter()
        .map(|mut at| {
            at[a] += end * layers.end;
            at.iter().zip(&from).rev().fold(0, |n, (&i, &s)| n * s + i)
        })
        .collect()
}

/// The sets of directions of the hexahedron's B-rep, the volume first.
fn cells() -> Vec<Vec<usize>> {
    vec![vec![0, 1, 2], vec![0, 1], vec![0, 2], vec![1, 2], vec![0], vec![1], vec![2], vec![]]
}

/// The states, arrows and constraints of a hexahedron pattern split
/// `split` (u, v, w) with the sub-cells `keep` (u fastest, then v, then w),
/// its control points laid out as `layers` say.
pub(super) fn hexahedron(b: &mut DesignBuilder, split: &[usize], keep: &[bool], layers: &Layers) {
    let kept: Vec<Vec<usize>> = grid(split).into_iter().zip(keep).filter(|(_, k)| **k).map(|(x, _)| x).collect();
    let (d, k) = (layers.n, layers.k);
    for axes in cells() {
        let what = match (axes.len(), k) {
            (3, _) => format!("The hexahedron: {d}×{d}×{d} control points, index {}·w + {d}·v + u.", d * d),
            (2, 1) => format!("A face along {}: {d}×{d} control points.", letters(&axes)),
            (1, 1) => format!("An edge along {}: {d} control points.", letters(&axes)),
            (0, 1) => "A corner: one control point.".into(),
            (2, _) => format!("A face along {}: {d}×{d} control points in each of {k} layers.", letters(&axes)),
            (1, _) => format!("An edge along {}: {d} control points in each of {k}×{k} rows.", letters(&axes)),
            _ => format!("A corner: the {k}×{k}×{k} control points around it."),
        };
        b.state(state(&axes), layers.size(&axes), kind(&axes));
        // A cell's own patch: a Bézier grid; a B-spline's volume (its sides hold layers, not a grid).
        match (&layers.fixed, axes.len()) {
            (None, 1..) => {
                b.patch(Patch::Bezier);
            }
            (Some(_), 3) => {
                b.patch(Patch::BSpline);
            }
            _ => {}
        }
        b.doc(what);
    }
    let arrow = |b: &mut DesignBuilder, axes: &[usize], x: &[usize]| {
        let (name, s) = (sub(axes, x), state(axes));
        match layers.tensor(axes, x) {
            Some(m) => b.matrix(name, s.clone(), s, m),
            None => b.unknown(name, s.clone(), s),
        };
    };
    for x in &kept {
        let at = x.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ");
        arrow(b, &[0, 1, 2], x);
        b.doc(format!("Sub-cell ({at}) of {}.", dims(split)));
    }
    for axes in cells().into_iter().skip(1) {
        let sizes: Vec<usize> = axes.iter().map(|&a| split[a]).collect();
        for x in grid(&sizes) {
            arrow(b, &axes, &x);
        }
        let parts = if axes.is_empty() { "its subdivision".into() } else { format!("its parts ({})", dims(&sizes)) };
        b.doc(format!("{} {}.", state(&axes), parts));
    }
    for axes in cells().into_iter().filter(|a| !a.is_empty()) {
        for &a in &axes {
            for end in 0..2 {
                b.select(
                    boundary(&axes, a, end),
                    state(&axes),
                    state(&without(&axes, a)),
                    select(&axes, a, end, layers),
                );
            }
        }
        b.doc(format!("The sides of {}: each direction fixed at its start (0) or end (1).", state(&axes)));
    }
    glue(b, split, &kept, keep);
    for axes in cells().into_iter().skip(1) {
        let sizes: Vec<usize> = axes.iter().map(|&a| split[a]).collect();
        let all = grid(&sizes);
        glue_grid(b, &axes, &sizes, &all);
    }
    // The unit cube: the classical member is the affine sponge.
    let points: Vec<Vec<f64>> =
        grid(&[d, d, d]).iter().map(|at| at.iter().map(|&i| layers.coordinate(i)).collect()).collect();
    let doc = match layers.fixed {
        None => "The unit cube.",
        Some(_) => {
            "The unit cube: the control lattice at the B-spline's Greville points (its map is then the identity)."
        }
    };
    b.model(Model::new("volume", points).with_layout(Layout::Single)).doc(doc);
}

/// `3x3x3`.
fn dims(sizes: &[usize]) -> String {
    sizes.iter().map(ToString::to_string).collect::<Vec<_>>().join("x")
}

/// The mask position of a grid position (first direction fastest).
fn index(x: &[isize], split: &[usize]) -> usize {
    x.iter().zip(split).rev().fold(0, |n, (&i, &s)| n * s + i.max(0) as usize)
}

/// The constraints among the sub-cells of a grid along `axes` (all present):
/// neighbours share a side, and the sub-cells on a side lie on its parts.
fn glue_grid(b: &mut DesignBuilder, axes: &[usize], sizes: &[usize], present: &[Vec<usize>]) {
    let has = |x: &[usize]| present.iter().any(|y| y == x);
    for x in present {
        for (t, &a) in axes.iter().enumerate() {
            let mut y = x.clone();
            y[t] += 1;
            if has(&y) {
                b.adjacency(format!(
                    "{} {} = {} {}",
                    sub(axes, x),
                    boundary(axes, a, 1),
                    sub(axes, &y),
                    boundary(axes, a, 0)
                ))
                .explain(format!("{} and {} share a side.", show(x), show(&y)));
            }
        }
    }
    for x in present {
        for (t, &a) in axes.iter().enumerate() {
            let rest: Vec<usize> = x.iter().enumerate().filter(|&(s, _)| s != t).map(|(_, &i)| i).collect();
            for end in 0..2 {
                if x[t] == end * (sizes[t] - 1) {
                    let side = boundary(axes, a, end);
                    b.incidence(format!("{} {side} = {side} {}", sub(axes, x), sub(&without(axes, a), &rest)))
                        .explain(format!("{} lies on the side {side}.", show(x)));
                }
            }
        }
    }
}

/// `(1, 0, 2)`.
fn show(x: &[usize]) -> String {
    format!("({})", x.iter().map(ToString::to_string).collect::<Vec<_>>().join(", "))
}

/// The volume's constraints: [`glue_grid`] over the kept sub-cells, and the
/// contacts that no shared face implies: two kept cells along an edge whose
/// two common neighbours are holes share that edge, two kept cells at a
/// corner whose six common neighbours are holes share that corner (pinches).
fn glue(b: &mut DesignBuilder, split: &[usize], kept: &[Vec<usize>], keep: &[bool]) {
    let axes = [0usize, 1, 2];
    glue_grid(b, &axes, split, kept);
    let present = |x: &[isize]| x.iter().zip(split).all(|(&i, &n)| i >= 0 && (i as usize) < n) && keep[index(x, split)];
    for x in kept {
        let xi: Vec<isize> = x.iter().map(|&i| i as isize).collect();
        for step in grid(&[3, 3, 3]) {
            let s: Vec<isize> = step.iter().map(|&i| i as isize - 1).collect();
            let moved: Vec<usize> = (0..3).filter(|&a| s[a] != 0).collect();
            // Each pair once: the first direction that moves goes forward.
            if moved.len() < 2 || s[moved[0]] < 0 {
                continue;
            }
            let y: Vec<isize> = (0..3).map(|a| xi[a] + s[a]).collect();
            if !present(&y) {
                continue;
            }
            // The other cells around the shared edge or corner.
            let others = grid(&vec![2; moved.len()]).into_iter().filter(|m| {
                let m_sum: usize = m.iter().sum();
                m_sum != 0 && m_sum != moved.len()
            });
            let mut touching = false;
            for m in others {
                let mut z = xi.clone();
                for (t, &a) in moved.iter().enumerate() {
                    z[a] += s[a] * m[t] as isize;
                }
                touching |= present(&z);
            }
            if touching {
                continue;
            }
            // Down from each cell through the sides facing the other.
            let path = |from_x: bool| {
                let mut here = axes.to_vec();
                let mut arrows = Vec::new();
                for &a in &moved {
                    let end = usize::from((s[a] > 0) == from_x);
                    arrows.push(boundary(&here, a, end));
                    here = without(&here, a);
                }
                arrows.join(" ")
            };
            let yu: Vec<usize> = y.iter().map(|&i| i as usize).collect();
            let (what, shared) = if moved.len() == 2 { ("along an edge", "edge") } else { ("at a corner", "corner") };
            let (px, py) = (path(true), path(false));
            b.adjacency(format!("{} {px} = {} {py}", sub(&axes, x), sub(&axes, &yu))).explain(format!(
                "{} and {} touch {what} only (a pinch): they share that {shared}.",
                show(x),
                show(&yu)
            ));
        }
    }
}

/// Entry `(r, c)` of the classical member's matrix of the hexahedron
/// pattern's subdivision arrow `arrow`: the tensor product of de
/// Casteljau's subdivision along each of its directions.
pub(super) fn classical(
    split: &[usize],
    arrow: &str,
    r: usize,
    c: usize,
    part: &dyn Fn(usize, usize) -> Vec<Vec<BigRational>>,
) -> BigRational {
    let (axes, rest): (Vec<usize>, &str) = if let Some(rest) = arrow.strip_prefix('T') {
        (vec![0, 1, 2], rest)
    } else {
        let n = arrow.chars().take_while(|ch| ch.is_ascii_uppercase()).count();
        let axes =
            arrow[..n].chars().filter_map(|ch| AXES.iter().position(|&a| a == ch.to_ascii_lowercase())).collect();
        (axes, &arrow[n..])
    };
    if axes.is_empty() {
        return BigRational::one();
    }
    let at: Vec<usize> = rest.split('_').map(|t| t.parse().unwrap_or(0)).collect();
    let mut value = BigRational::one();
    let (mut r, mut c) = (r, c);
    for (t, &a) in axes.iter().enumerate() {
        let part = part(split[a], at.get(t).copied().unwrap_or(0));
        let d = part.len();
        value *= part[r % d][c % d].clone();
        r /= d;
        c /= d;
    }
    value
}

/// The states of a simplex's corner split, by dimension.
const SIMPLEX: [&str; 4] = ["point", "segment", "triangle", "tetrahedron"];
/// Their corner subdivision arrows' letters.
const CORNER: [&str; 4] = ["X", "H", "G", "T"];

/// The boundary arrow of a `k`-simplex dropping its vertex `i`.
fn facet(k: usize, i: usize) -> String {
    format!("{}_{i}", &SIMPLEX[k][..3])
}

/// The path of boundary arrows from a `k`-simplex down to its vertex `j`
/// (dropping the others, the last first so the positions hold).
fn to_vertex(k: usize, j: usize) -> String {
    let mut left: Vec<usize> = (0..=k).collect();
    let mut arrows = Vec::new();
    while left.len() > 1 {
        let p = left.iter().rposition(|&v| v != j).expect("another vertex");
        arrows.push(facet(left.len() - 1, p));
        left.remove(p);
    }
    arrows.join(" ")
}

/// The states, arrows and constraints of a tetrahedron split into its four
/// corner tetrahedra (halfway along the edges), those of `keep` kept; its
/// faces split into their three corner triangles (the Sierpiński gasket),
/// its edges into halves.
pub(super) fn tetrahedron(b: &mut DesignBuilder, keep: &[bool]) {
    for (k, name) in SIMPLEX.iter().enumerate().rev() {
        let kinds = [CellKind::Vertex, CellKind::Edge, CellKind::Face, CellKind::Volume];
        b.state(*name, k + 1, kinds[k]);
        if k > 0 {
            b.patch(Patch::Bezier);
        }
        b.doc(format!("The {name}: its {} corner(s).", k + 1));
    }
    for k in (0..4).rev() {
        let corners: Vec<usize> = (0..=k).filter(|&i| k < 3 || keep[i]).collect();
        for &i in &corners {
            let name = if k == 0 { "X".to_string() } else { format!("{}{i}", CORNER[k]) };
            b.unknown(name, SIMPLEX[k], SIMPLEX[k]);
        }
        b.doc(match k {
            0 => "The subdivision of a corner.".to_string(),
            _ => format!("The corner {}s of a {}, halfway along its edges.", SIMPLEX[k], SIMPLEX[k]),
        });
    }
    for k in (1..4).rev() {
        for i in 0..=k {
            let others: Vec<usize> = (0..=k).filter(|&j| j != i).collect();
            b.select(facet(k, i), SIMPLEX[k], SIMPLEX[k - 1], others);
        }
        b.doc(format!("The facets of a {}: each drops one corner, the others in order.", SIMPLEX[k]));
    }
    for k in (1..4).rev() {
        let present: Vec<usize> = (0..=k).filter(|&i| k < 3 || keep[i]).collect();
        let corner = |i: usize| if k == 0 { "X".to_string() } else { format!("{}{i}", CORNER[k]) };
        for (n, &i) in present.iter().enumerate() {
            for &j in &present[n + 1..] {
                b.adjacency(format!("{} {} = {} {}", corner(i), to_vertex(k, j), corner(j), to_vertex(k, i)))
                    .explain(format!("Corners {i} and {j} touch at the middle of edge {i}{j} only (a pinch)."));
            }
        }
        for &i in &present {
            for j in (0..=k).filter(|&j| j != i) {
                // Corner i's facet without j lies on the facet without j, at i's place there.
                let place = (0..=k).filter(|&v| v != j).position(|v| v == i).expect("i is not j");
                let lower = if k == 1 { "X".to_string() } else { format!("{}{place}", CORNER[k - 1]) };
                b.incidence(format!("{} {f} = {f} {lower}", corner(i), f = facet(k, j)))
                    .explain(format!("Corner {i} lies on the facet without corner {j}."));
            }
        }
    }
    let h = 3f64.sqrt();
    let points = vec![
        vec![0.0, 0.0, 0.0],
        vec![1.0, 0.0, 0.0],
        vec![0.5, h / 2.0, 0.0],
        vec![0.5, h / 6.0, (2.0f64 / 3.0).sqrt()],
    ];
    b.model(Model::new("tetrahedron", points).with_layout(Layout::Single)).doc("The regular tetrahedron of side 1.");
}

/// Entry `(r, c)` of the classical member's matrix of a corner arrow `arrow`
/// (`T2`, `G0`, `H1`; `X` is 1): column `c` is the corner `i` itself or the
/// midpoint of the edge from `i` to `c`.
pub(super) fn corner_classical(arrow: &str, r: usize, c: usize) -> BigRational {
    let Some(i) = arrow.get(1..).and_then(|t| t.parse::<usize>().ok()) else { return BigRational::one() };
    let half = BigRational::new(BigInt::from(1), BigInt::from(2));
    match (c == i, r == i, r == c) {
        (true, true, _) => BigRational::one(),
        (true, false, _) => BigRational::zero(),
        (false, true, _) | (false, false, true) => half,
        _ => BigRational::zero(),
    }
}
