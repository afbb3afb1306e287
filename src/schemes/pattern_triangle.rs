//! Triangle patterns: a triangle split `n`-ary into `n²` triangles, `n(n+1)/2`
//! upward (its orientation, translated) and `n(n−1)/2` downward (turned half
//! round, which keeps the orientation of the plane), some kept and the
//! others holes: the Sierpiński gasket keeps the three corner ones of `n = 2`.
//!
//! Grid point `(a, b)` is `A + (a/n)(B − A) + (b/n)(C − A)` for the corners
//! `A, B, C` of the cell; upward cell `U(a, b)` has the corners `(a, b)`,
//! `(a+1, b)`, `(a, b+1)`, downward `D(a, b)` the corners `(a+1, b+1)`,
//! `(a, b+1)`, `(a+1, b)`. Side `k` runs from corner `k` to corner `k+1`.
//! Cells are listed row by row from the side `AB` (b = 0), left to right:
//! `U(0, b), D(0, b), U(1, b), …, U(n−1−b, b)`.

use std::collections::HashMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;

use crate::design::{DesignBuilder, Layout, Model};
use crate::space::CellKind;

/// An upward (`false`) or downward (`true`) cell at `(a, b)`.
type Cell = (bool, usize, usize);

/// The cells of an `n`-ary split in mask order.
fn cells(n: usize) -> Vec<Cell> {
    let mut out = Vec::with_capacity(n * n);
    for b in 0..n {
        for a in 0..n - b {
            out.push((false, a, b));
            if a + b + 1 < n {
                out.push((true, a, b));
            }
        }
    }
    out
}

/// The grid points of a cell's three corners.
fn corners((down, a, b): Cell) -> [(usize, usize); 3] {
    if down { [(a + 1, b + 1), (a, b + 1), (a + 1, b)] } else { [(a, b), (a + 1, b), (a, b + 1)] }
}

fn name((down, a, b): Cell) -> String {
    format!("{}{a}_{b}", if down { 'D' } else { 'U' })
}

/// The name of the cell at mask position `[i, 0]` (for the generator's shared naming).
pub(super) fn cell_name([i, _]: [usize; 2]) -> String {
    format!("#{i}")
}

/// The states, arrows and constraints of a triangle pattern.
pub(super) fn triangle(b: &mut DesignBuilder, n: usize, keep: &[bool]) {
    let kept: Vec<Cell> = cells(n).into_iter().zip(keep).filter(|(_, k)| **k).map(|(c, _)| c).collect();
    b.state("face", 3, CellKind::Face).doc("The triangle: its three corners A, B, C.");
    b.state("edge", 2, CellKind::Edge).doc("A side: its two ends.");
    b.state("vertex", 1, CellKind::Vertex).doc("A corner: one control point.");
    for &c in &kept {
        let (down, a, bb) = c;
        let what = if down { "downward" } else { "upward" };
        b.unknown(name(c), "face", "face").doc(format!("The {what} sub-triangle ({a}, {bb}) of the {n}-ary split."));
    }
    for i in 0..n {
        b.unknown(format!("E{i}"), "edge", "edge").doc(format!("Part {i} of {n} of a side."));
    }
    b.unknown("W", "vertex", "vertex").doc("Subdivision of a corner.");
    b.select("side0", "face", "edge", [0, 1]).doc("Side AB.");
    b.select("side1", "face", "edge", [1, 2]).doc("Side BC.");
    b.select("side2", "face", "edge", [2, 0]).doc("Side CA.");
    b.select("e_start", "edge", "vertex", [0]).select("e_end", "edge", "vertex", [1]);
    b.doc("The ends of a side.");
    glue(b, &kept);
    for &c in &kept {
        let (down, a, bb) = c;
        if down {
            continue;
        }
        if bb == 0 {
            b.incidence(format!("{} side0 = side0 E{a}", name(c))).explain(format!("({a}, 0) lies on side AB."));
        }
        if a + bb + 1 == n {
            b.incidence(format!("{} side1 = side1 E{bb}", name(c))).explain(format!("({a}, {bb}) lies on side BC."));
        }
        if a == 0 {
            b.incidence(format!("{} side2 = side2 E{}", name(c), n - 1 - bb))
                .explain(format!("(0, {bb}) lies on side CA."));
        }
    }
    for i in 0..n - 1 {
        b.adjacency(format!("E{i} e_end = E{} e_start", i + 1));
    }
    b.incidence("E0 e_start = e_start W").incidence(format!("E{} e_end = e_end W", n - 1));
    b.doc("The parts of a side share their ends; the first and last parts end at the subdivided corners.");
    let h = 0.866_025_403_784_438_6;
    b.model(
        Model::new("face", vec![vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 0.0], vec![0.5, h, 0.0]])
            .with_layout(Layout::Single),
    )
    .doc("An equilateral triangle.");
}

/// Neighbours glued: cells sharing a side share its two ends (sides of
/// neighbouring cells run opposite ways), and cells that meet only at a
/// grid point — no chain of side-sharing kept cells around it joins them —
/// share that corner (a pinch).
fn glue(b: &mut DesignBuilder, kept: &[Cell]) {
    let corner = |c: Cell, k: usize| format!("{} side{k} e_start", name(c));
    for (x, &c) in kept.iter().enumerate() {
        for &d in &kept[x + 1..] {
            let (pc, pd) = (corners(c), corners(d));
            let shared: Vec<(usize, usize)> =
                (0..3).flat_map(|i| (0..3).filter(move |&j| pc[i] == pd[j]).map(move |j| (i, j))).collect();
            if shared.len() == 2 {
                for &(i, j) in &shared {
                    b.adjacency(format!("{} = {}", corner(c, i), corner(d, j))).explain(format!(
                        "{} and {} share a side.",
                        name(c),
                        name(d)
                    ));
                }
            }
        }
    }
    // Around each grid point: the kept cells there, joined through the sides they share.
    let mut around: HashMap<(usize, usize), Vec<(Cell, usize)>> = HashMap::new();
    for &c in kept {
        for (k, p) in corners(c).into_iter().enumerate() {
            around.entry(p).or_default().push((c, k));
        }
    }
    let mut points: Vec<_> = around.into_iter().collect();
    points.sort();
    for (p, here) in points {
        let mut group: Vec<usize> = (0..here.len()).collect();
        let find = |g: &Vec<usize>, mut i: usize| {
            while g[i] != i {
                i = g[i];
            }
            i
        };
        for i in 0..here.len() {
            for j in i + 1..here.len() {
                let common = corners(here[i].0).iter().filter(|q| corners(here[j].0).contains(q)).count();
                if common == 2 {
                    let (ri, rj) = (find(&group, i), find(&group, j));
                    group[ri] = rj;
                }
            }
        }
        let first = find(&group, 0);
        let mut linked = vec![first];
        for i in 0..here.len() {
            let r = find(&group, i);
            if !linked.contains(&r) {
                linked.push(r);
                let ((c, k), (d, m)) = (here[first], here[i]);
                b.adjacency(format!("{} = {}", corner(c, k), corner(d, m))).explain(format!(
                    "{} and {} touch at one corner only, grid point {p:?} (a pinch).",
                    name(c),
                    name(d)
                ));
            }
        }
    }
}

/// Entry `(r, c)` of the classical member's matrix of `arrow`: the
/// sub-triangle's corner `c` in the barycentric coordinates of the cell,
/// the sides' parts the linear segment's.
pub(super) fn classical(n: usize, arrow: &str, r: usize, c: usize) -> BigRational {
    let frac = |x: usize| BigRational::new(BigInt::from(x), BigInt::from(n));
    let index = |t: &str| t.parse::<usize>().unwrap_or(0);
    if let Some(i) = arrow.strip_prefix('E') {
        // Part i of a side: its ends at (i + c)/n, weights (1 − t, t) of the side's ends.
        let t = index(i) + c;
        return if r == 0 { frac(n - t) } else { frac(t) };
    }
    let (down, rest) = match arrow.split_at(1) {
        ("U", rest) => (false, rest),
        ("D", rest) => (true, rest),
        _ => return BigRational::one(),
    };
    let (a, b) = rest.split_once('_').map_or((0, 0), |(a, b)| (index(a), index(b)));
    let (x, y) = corners((down, a, b))[c];
    match r {
        0 => frac(n - x - y),
        1 => frac(x),
        _ => frac(y),
    }
}
