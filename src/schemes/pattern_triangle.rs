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
use crate::space::{CellKind, Patch};

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

/// The indices of side `k` of a triangle's net of `d` points a side, from corner `k` to corner `k + 1`.
fn side(d: usize, k: usize) -> Vec<usize> {
    let net = super::blossom::triangle_net(d);
    let index = |p: (usize, usize)| net.iter().position(|&q| q == p).unwrap_or(0);
    let m = d - 1;
    (0..=m)
        .map(|t| match k {
            0 => index((t, 0)),
            1 => index((m - t, t)),
            _ => index((0, m - t)),
        })
        .collect()
}

/// The states, arrows and constraints of a triangle pattern of `d` control points a side.
pub(super) fn triangle(b: &mut DesignBuilder, n: usize, keep: &[bool], d: usize) {
    let kept: Vec<Cell> = cells(n).into_iter().zip(keep).filter(|(_, k)| **k).map(|(c, _)| c).collect();
    if d == 2 {
        b.state("face", 3, CellKind::Face).patch(Patch::Bezier).doc("The triangle: its three corners A, B, C.");
        b.state("edge", 2, CellKind::Edge).patch(Patch::Bezier).doc("A side: its two ends.");
    } else {
        b.state("face", d * (d + 1) / 2, CellKind::Face).patch(Patch::Bezier).doc(format!(
            "The Bézier triangle of degree {}: its {} control points (a, b), weight of B to the power a and of C to b,\n\
             row by row from side AB.",
            d - 1,
            d * (d + 1) / 2
        ));
        b.state("edge", d, CellKind::Edge).patch(Patch::Bezier).doc(format!("A side: {d} control points."));
    }
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
    for (k, what) in ["Side AB.", "Side BC.", "Side CA."].into_iter().enumerate() {
        b.select(format!("side{k}"), "face", "edge", side(d, k)).doc(what);
    }
    b.select("e_start", "edge", "vertex", [0]).select("e_end", "edge", "vertex", [d - 1]);
    b.doc("The ends of a side.");
    // An upward and a downward neighbour run along the side they share in opposite directions.
    let reversed = kept.iter().any(|c| c.0 && kept.iter().any(|u| !u.0 && shared_side(*c, *u)));
    if reversed {
        b.select("flip", "edge", "edge", (0..d).rev().collect::<Vec<_>>())
            .doc("A side read from its end: neighbours run along a side they share in opposite directions.");
    }
    glue(b, &kept, d);
    on_the_sides(b, &kept, n);
    for i in 0..n - 1 {
        b.adjacency(format!("E{i} e_end = E{} e_start", i + 1));
    }
    b.incidence("E0 e_start = e_start W").incidence(format!("E{} e_end = e_end W", n - 1));
    b.doc("The parts of a side share their ends; the first and last parts end at the subdivided corners.");
    if reversed {
        for i in 0..n.div_ceil(2) {
            b.adjacency(format!("flip E{i} = E{} flip", n - 1 - i)).explain(format!(
                "Part {i} of a side read backwards is part {} of it: a side two cells share in opposite directions is split at the same points seen from either.",
                n - 1 - i
            ));
        }
    }
    let h = 0.866_025_403_784_438_6;
    let m = (d - 1) as f64;
    let points: Vec<Vec<f64>> = super::blossom::triangle_net(d)
        .into_iter()
        .map(|(a, bb)| {
            let (u, v) = (a as f64 / m, bb as f64 / m);
            let corner = [(0, 0), (d - 1, 0), (0, d - 1)].contains(&(a, bb));
            vec![u + v / 2.0, v * h, if corner { 0.0 } else { 0.5 }]
        })
        .collect();
    b.model(Model::new("face", points).with_layout(Layout::Single)).doc(if d == 2 {
        "An equilateral triangle."
    } else {
        "An equilateral triangle, its control points off the corners raised: a curved patch."
    });
}

/// The incidences of the kept cells on the outer sides: an upward cell on a
/// side lies on its part of it, a downward one touching a side at a corner
/// only has that corner at the side's split point.
fn on_the_sides(b: &mut DesignBuilder, kept: &[Cell], n: usize) {
    for &c in kept {
        let (down, a, bb) = c;
        if down {
            for (k, (x, y)) in corners(c).into_iter().enumerate() {
                let on = match () {
                    () if y == 0 => Some((0, x)),
                    () if x + y == n => Some((1, y)),
                    () if x == 0 => Some((2, n - y)),
                    () => None,
                };
                if let Some((side, at)) = on {
                    b.incidence(format!("{} side{k} e_start = side{side} E{} e_end", name(c), at - 1)).explain(
                        format!(
                            "The downward ({a}, {bb}) touches side {} at its split point {at} of {n}.",
                            ["AB", "BC", "CA"][side]
                        ),
                    );
                }
            }
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
}

/// Whether two cells share a side (two corners).
fn shared_side(c: Cell, d: Cell) -> bool {
    corners(c).iter().filter(|p| corners(d).contains(p)).count() == 2
}

/// Neighbours glued: cells sharing a side share its two ends (sides of
/// neighbouring cells run opposite ways), and cells that meet only at a
/// grid point — no chain of side-sharing kept cells around it joins them —
/// share that corner (a pinch).
fn glue(b: &mut DesignBuilder, kept: &[Cell], degree: usize) {
    let corner = |c: Cell, k: usize| format!("{} side{k} e_start", name(c));
    // The side of a triangle joining two of its corners.
    let side_of = |i: usize, j: usize| if (i + 1) % 3 == j { i } else { j };
    for (x, &c) in kept.iter().enumerate() {
        for &d in &kept[x + 1..] {
            let (pc, pd) = (corners(c), corners(d));
            let shared: Vec<(usize, usize)> =
                (0..3).flat_map(|i| (0..3).filter(move |&j| pc[i] == pd[j]).map(move |j| (i, j))).collect();
            let why = format!("{} and {} share a side.", name(c), name(d));
            if shared.len() == 2 && degree > 2 {
                // The whole side (its inner control points too), read backwards when the two run opposite ways.
                let (k, l) = (side_of(shared[0].0, shared[1].0), side_of(shared[0].1, shared[1].1));
                let flip = if pc[k] == pd[l] { "" } else { " flip" };
                b.adjacency(format!("{} side{k} = {} side{l}{flip}", name(c), name(d))).explain(why);
            } else if shared.len() == 2 {
                for &(i, j) in &shared {
                    b.adjacency(format!("{} = {}", corner(c, i), corner(d, j))).explain(why.clone());
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
/// Bézier triangle of `d` points a side (for `d = 2` its corners, the
/// linear triangle) subdivided at the `n`-ary grid, exactly (its blossom at
/// the sub-triangle's corners); the sides' parts the Bézier curve's.
pub(super) fn classical(n: usize, d: usize, arrow: &str, r: usize, c: usize) -> BigRational {
    let frac = |x: usize| BigRational::new(BigInt::from(x), BigInt::from(n));
    let index = |t: &str| t.parse::<usize>().unwrap_or(0);
    if let Some(i) = arrow.strip_prefix('E') {
        return super::blossom::bezier_part(d, index(i), n)[r][c].clone();
    }
    let (down, rest) = match arrow.split_at(1) {
        ("U", rest) => (false, rest),
        ("D", rest) => (true, rest),
        _ => return BigRational::one(),
    };
    let (a, b) = rest.split_once('_').map_or((0, 0), |(a, b)| (index(a), index(b)));
    let at = corners((down, a, b)).map(|(x, y)| [frac(n - x - y), frac(x), frac(y)]);
    super::blossom::bezier_triangle_part(d, &at)[r][c].clone()
}
