//! Triangle subdivision schemes as IFS (Schaefer et al. 2005 §3.2–3.3): the
//! three-direction quartic box-spline (Loop's scheme on the regular
//! triangular lattice) and Kobbelt's √3 scheme.
//!
//! The seed builds these IFS from a notebook that is not available; this
//! module derives them from the subdivision rules, as the seed describes.
//! Control points sit on the triangular lattice, in axial coordinates
//! `(i, j)` at position `i·(1, 0) + j·(1/2, √3/2)`. One *round* of the
//! scheme (one Loop step, or two √3 steps: a ternary split) refines the
//! lattice by a factor `s` (2 or 3). A sub-patch is a copy of the patch on
//! the fine lattice: control point `o` goes to fine point `c + σ·o` (a
//! translation by `c`, `σ = ±1`: a half-turn for the downward triangles of
//! the ternary split). Its new control points are linear combinations of
//! the old ones (the rules applied to unit vectors, exactly, over the
//! rationals): the rows of the square block `S_i` (`T_i = S_iᵀ`).
//!
//! The control set is found, not chosen: it starts from the cell's corners
//! and grows by every control point a sub-patch's fine points depend on,
//! until it is closed. Every block is then square, and the attractor of the
//! IFS is the limit surface over the cell (the cell is the union of its
//! scaled copies, and a nested sequence of sub-patches converges to the
//! limit point of their common point).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use num_rational::BigRational;
use num_traits::Zero;

use crate::algebra::Surd;

use super::stationary::ExactMatrix;

/// A lattice point in axial coordinates.
pub type Axial = (i64, i64);

/// The six lattice directions, counter-clockwise from `(1, 0)`.
pub const DIRECTIONS: [Axial; 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];

/// Position in the plane of the lattice point `(i, j)`.
pub fn position((i, j): Axial) -> [f64; 2] {
    [i as f64 + 0.5 * j as f64, j as f64 * 3f64.sqrt() / 2.0]
}

/// The triangle schemes on the regular lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeScheme {
    /// Loop's rules at valence 6: the three-direction quartic box-spline.
    /// Vertex `5/8 v + 1/16 Σ neighbours`, edge `3/8 (a + b) + 1/8 (c + d)`.
    /// One round = one step, scale 2.
    BoxSpline,
    /// Kobbelt's √3 rules at valence 6: vertex `2/3 v + 1/18 Σ neighbours`
    /// (`α₆ = 1/3`), new point at each triangle's centroid, edges flipped.
    /// One round = two steps (a ternary split), scale 3.
    Sqrt3,
}

impl LatticeScheme {
    /// How much one round refines the lattice.
    pub fn scale(self) -> i64 {
        match self {
            LatticeScheme::BoxSpline => 2,
            LatticeScheme::Sqrt3 => 3,
        }
    }
}

/// A linear combination of coarse control points (sparse, exact).
type Comb = BTreeMap<Axial, BigRational>;

fn q(n: i64, d: i64) -> BigRational {
    BigRational::new(n.into(), d.into())
}

fn add_scaled(out: &mut Comb, c: &Comb, k: &BigRational) {
    for (p, w) in c {
        let e = out.entry(*p).or_insert_with(BigRational::zero);
        *e += w * k;
        if e.is_zero() {
            out.remove(p);
        }
    }
}

fn plus(a: Axial, b: Axial) -> Axial {
    (a.0 + b.0, a.1 + b.1)
}

/// Values on a lattice in fine coordinates, with its six directions.
struct Level {
    values: HashMap<Axial, Comb>,
    dirs: [Axial; 6],
}

impl Level {
    /// The combination of `p`'s value and its six neighbours' with weights
    /// `own` and `each`, when all seven are known.
    fn smooth(&self, p: Axial, own: &BigRational, each: &BigRational) -> Option<Comb> {
        let mut out = Comb::new();
        add_scaled(&mut out, self.values.get(&p)?, own);
        for d in self.dirs {
            add_scaled(&mut out, self.values.get(&plus(p, d))?, each);
        }
        Some(out)
    }

    /// `Σ wᵢ value(pᵢ)` when every point is known.
    fn combine(&self, terms: &[(Axial, BigRational)]) -> Option<Comb> {
        let mut out = Comb::new();
        for (p, w) in terms {
            add_scaled(&mut out, self.values.get(p)?, w);
        }
        Some(out)
    }

    /// One Loop step at valence 6 (directions even: new points at the
    /// midpoints), edge points `w (a + b) + (1/2 − w)(c + d)`, vertex points
    /// `(1 − 6β) v + β Σ neighbours`.
    fn loop_step(&self, w: &BigRational, beta: &BigRational) -> Level {
        let mut values = HashMap::new();
        let d = self.dirs;
        let own = q(1, 1) - beta * q(6, 1);
        let opposite = q(1, 2) - w;
        for &p in self.values.keys() {
            if let Some(v) = self.smooth(p, &own, beta) {
                values.insert(p, v);
            }
            for k in 0..6 {
                let (a, b, c) = (plus(p, d[k]), plus(p, d[(k + 1) % 6]), plus(p, d[(k + 5) % 6]));
                let mid = (p.0 + d[k].0 / 2, p.1 + d[k].1 / 2);
                if values.contains_key(&mid) {
                    continue;
                }
                let terms = [(p, w.clone()), (a, w.clone()), (b, opposite.clone()), (c, opposite.clone())];
                if let Some(v) = self.combine(&terms) {
                    values.insert(mid, v);
                }
            }
        }
        Level { values, dirs: d.map(|(x, y)| (x / 2, y / 2)) }
    }

    /// One √3 step at valence 6 (directions multiples of 3 in the new frame's
    /// sense: centroids `p + (dₖ + dₖ₊₁)/3` are lattice points).
    fn sqrt3_step(&self) -> Level {
        let mut values = HashMap::new();
        let d = self.dirs;
        let third = |k: usize| ((d[k].0 + d[(k + 1) % 6].0) / 3, (d[k].1 + d[(k + 1) % 6].1) / 3);
        for &p in self.values.keys() {
            if let Some(v) = self.smooth(p, &q(2, 3), &q(1, 18)) {
                values.insert(p, v);
            }
            for k in 0..6 {
                let centre = plus(p, third(k));
                if values.contains_key(&centre) {
                    continue;
                }
                let terms = [(p, q(1, 3)), (plus(p, d[k]), q(1, 3)), (plus(p, d[(k + 1) % 6]), q(1, 3))];
                if let Some(v) = self.combine(&terms) {
                    values.insert(centre, v);
                }
            }
        }
        Level { values, dirs: std::array::from_fn(third) }
    }
}

/// The fine values of one round of `scheme` (the box-spline with Loop's
/// weights `(w, β)`) on the coarse lattice points of hexagonal radius
/// `radius` (fine coordinates: coarse point `o` at `s·o`).
fn one_round(scheme: LatticeScheme, loop_weights: &(BigRational, BigRational), radius: i64) -> HashMap<Axial, Comb> {
    let s = scheme.scale();
    let mut values = HashMap::new();
    for i in -radius..=radius {
        for j in -radius..=radius {
            if hex_norm((i, j)) <= radius {
                values.insert((s * i, s * j), Comb::from([((i, j), q(1, 1))]));
            }
        }
    }
    let level = Level { values, dirs: DIRECTIONS.map(|(x, y)| (s * x, s * y)) };
    match scheme {
        LatticeScheme::BoxSpline => level.loop_step(&loop_weights.0, &loop_weights.1).values,
        LatticeScheme::Sqrt3 => level.sqrt3_step().sqrt3_step().values,
    }
}

/// Hexagonal distance of a lattice point from the origin.
pub fn hex_norm((i, j): Axial) -> i64 {
    i.abs().max(j.abs()).max((i + j).abs())
}

/// A sub-patch: control point `o` goes to fine point `centre + sign·o`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubPatch {
    /// Fine lattice point where the origin goes.
    pub centre: Axial,
    /// `1`: a translated copy; `-1`: a half-turn.
    pub sign: i64,
}

/// A triangle scheme's IFS on a lattice cell: the control points (axial
/// coordinates, sorted by row `j` then `i`) and one square block `S_i` per
/// sub-patch (rows: the sub-patch's control points in terms of the cell's).
#[derive(Clone, Debug)]
pub struct LatticeIfs {
    /// The control points.
    pub control: Vec<Axial>,
    /// The blocks, in the order of the sub-patches.
    pub blocks: Vec<ExactMatrix>,
}

/// Why a lattice IFS does not close.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the sub-patches do not close on a finite control set within radius {0}: is every sub-patch inside the cell?")]
pub struct NotClosed(pub i64);

/// The IFS of `scheme` whose sub-patches are `parts`, on the smallest
/// control set that contains `corners` and every control point the
/// sub-patches depend on.
///
/// # Errors
/// [`NotClosed`] when the control set keeps growing (sub-patches that leave
/// the cell, or a contraction that is not one).
pub fn lattice_ifs(scheme: LatticeScheme, parts: &[SubPatch], corners: &[Axial]) -> Result<LatticeIfs, NotClosed> {
    lattice_ifs_weighted(scheme, &(q(3, 8), q(1, 16)), parts, corners)
}

/// The box-spline's six-map hexagon with Loop-like weights at valence 6:
/// edge points `w (a + b) + (1/2 − w)(c + d)`, vertex points
/// `(1 − 6β) v + β Σ neighbours` (Loop: `w = 3/8`, `β = 1/16`). Its joint
/// spectral radius decides whether the regular parts of a triangle mesh
/// converge under those weights.
pub fn box_spline_hexagon(w: &BigRational, beta: &BigRational) -> LatticeIfs {
    // Start from the whole two rings: zero weights must not shrink the control set.
    let rings: Vec<Axial> =
        (-2..=2).flat_map(|i| (-2..=2).map(move |j| (i, j))).filter(|&p| hex_norm(p) <= 2).collect();
    lattice_ifs_weighted(LatticeScheme::BoxSpline, &(w.clone(), beta.clone()), &hexagon_parts(), &rings)
        .expect("the hexagon's sub-patches close on the two rings for any weights")
}

fn lattice_ifs_weighted(
    scheme: LatticeScheme,
    loop_weights: &(BigRational, BigRational),
    parts: &[SubPatch],
    corners: &[Axial],
) -> Result<LatticeIfs, NotClosed> {
    const WINDOW: i64 = 12;
    let fine = one_round(scheme, loop_weights, WINDOW);
    let image = |part: &SubPatch, o: Axial| (part.centre.0 + part.sign * o.0, part.centre.1 + part.sign * o.1);
    let mut control: BTreeSet<Axial> = corners.iter().copied().collect();
    loop {
        let mut grown = control.clone();
        for part in parts {
            for &o in &control {
                let value = fine.get(&image(part, o)).ok_or(NotClosed(WINDOW))?;
                grown.extend(value.keys().copied());
            }
        }
        if grown.iter().any(|&p| hex_norm(p) > WINDOW - 3) {
            return Err(NotClosed(WINDOW));
        }
        if grown.len() == control.len() {
            break;
        }
        control = grown;
    }
    let mut control: Vec<Axial> = control.into_iter().collect();
    control.sort_by_key(|&(i, j)| (j, i));
    let index: HashMap<Axial, usize> = control.iter().enumerate().map(|(k, &p)| (p, k)).collect();
    let blocks = parts
        .iter()
        .map(|part| {
            control
                .iter()
                .map(|&o| {
                    let mut row = vec![Surd::zero(); control.len()];
                    for (p, w) in &fine[&image(part, o)] {
                        row[index[p]] = Surd::rational(w.clone());
                    }
                    row
                })
                .collect()
        })
        .collect();
    Ok(LatticeIfs { control, blocks })
}

/// The triangles of the lattice whose corners are all in `points`, as
/// counter-clockwise index triples into `points` (the control net).
pub fn lattice_triangles(points: &[Axial]) -> Vec<Vec<usize>> {
    let index: HashMap<Axial, usize> = points.iter().enumerate().map(|(k, &p)| (p, k)).collect();
    // A triangle's base point (its lower left corner, or the one left of its
    // lowest corner for a downward triangle) may lie outside `points`.
    let bases: BTreeSet<Axial> = points.iter().flat_map(|&(i, j)| [(i, j), (i - 1, j), (i, j - 1)]).collect();
    let mut out = Vec::new();
    for p in bases {
        for corners in [[(0, 0), (1, 0), (0, 1)], [(1, 0), (1, 1), (0, 1)]] {
            let face: Option<Vec<usize>> = corners.iter().map(|&d| index.get(&plus(p, d)).copied()).collect();
            out.extend(face);
        }
    }
    out
}

/// The limit point of a lattice vertex, as barycentric weights of the
/// control points: `1/2` on the vertex and `1/12` on each of its six
/// neighbours, for both schemes. It is the left eigenvector of eigenvalue 1
/// of one step at a regular vertex: with `L = a v + b Σ n_i` (`a + 6b = 1`)
/// unchanged by Loop's step (`v' = 5/8 v + 1/16 Σ n_i`, edge points
/// `3/8 (v + n_i) + 1/8 (n_{i−1} + n_{i+1})`) or by √3's (`v' = 2/3 v +
/// 1/18 Σ n_i`, new points at the centroids), `a = 6b`.
///
/// # Errors
/// [`NotClosed`] (radius 0) when a neighbour is not a control point.
pub fn limit_stencil(control: &[Axial], vertex: Axial) -> Result<Vec<f64>, NotClosed> {
    let index = |p: Axial| control.iter().position(|&q| q == p).ok_or(NotClosed(0));
    let mut weights = vec![0.0; control.len()];
    weights[index(vertex)?] = 0.5;
    for (di, dj) in DIRECTIONS {
        weights[index((vertex.0 + di, vertex.1 + dj))?] += 1.0 / 12.0;
    }
    Ok(weights)
}

/// A start set (barycentric points) and faces over it.
pub type StartMesh = (Vec<Vec<f64>>, Vec<Vec<usize>>);

/// A cell meshed by its lattice `triangles`: the start set (the limit
/// stencil of each vertex the triangles use, [`limit_stencil`]) and the
/// triangles as indices into it.
///
/// # Errors
/// [`NotClosed`] when a vertex's neighbours are not all control points.
pub fn cell_mesh(control: &[Axial], triangles: &[[Axial; 3]]) -> Result<StartMesh, NotClosed> {
    let mut vertices: Vec<Axial> = Vec::new();
    let mut faces = Vec::new();
    for t in triangles {
        faces.push(
            t.iter()
                .map(|&v| match vertices.iter().position(|&w| w == v) {
                    Some(i) => i,
                    None => {
                        vertices.push(v);
                        vertices.len() - 1
                    }
                })
                .collect(),
        );
    }
    let start = vertices.iter().map(|&v| limit_stencil(control, v)).collect::<Result<_, _>>()?;
    Ok((start, faces))
}

/// The six sub-hexagons of the box-spline's hexagonal patch (Fig. 7): the
/// half-size copies centred at the six lattice neighbours of the centre.
pub fn hexagon_parts() -> Vec<SubPatch> {
    DIRECTIONS.iter().map(|&centre| SubPatch { centre, sign: 1 }).collect()
}

/// The four sub-parallelograms of the cell `(0,0), (1,0), (1,1), (0,1)`.
pub fn parallelogram_parts() -> Vec<SubPatch> {
    [(0, 0), (1, 0), (0, 1), (1, 1)].iter().map(|&centre| SubPatch { centre, sign: 1 }).collect()
}

/// The nine sub-triangles of the ternary split of the triangle
/// `(0,0), (1,0), (0,1)`: six upright copies, three half-turned.
pub fn ternary_triangle_parts() -> Vec<SubPatch> {
    let up = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (0, 2)].map(|centre| SubPatch { centre, sign: 1 });
    let down = [(1, 1), (2, 1), (1, 2)].map(|centre| SubPatch { centre, sign: -1 });
    up.into_iter().chain(down).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum_rows(m: &ExactMatrix) -> bool {
        m.iter().all(|row| row.iter().fold(Surd::zero(), |a, x| a.add(x)).is_one())
    }

    #[test]
    fn box_spline_hexagon_needs_the_two_rings() {
        let ifs = lattice_ifs(LatticeScheme::BoxSpline, &hexagon_parts(), &[(0, 0)]).unwrap();
        assert_eq!(ifs.control.len(), 19);
        assert!(ifs.control.iter().all(|&p| hex_norm(p) <= 2));
        assert_eq!(ifs.blocks.len(), 6);
        assert!(ifs.blocks.iter().all(sum_rows));
        assert_eq!(lattice_triangles(&ifs.control).len(), 24, "the hexagon of radius 2 has 24 triangles");
    }

    #[test]
    fn parallelogram_and_ternary_triangle_close() {
        let quad =
            lattice_ifs(LatticeScheme::BoxSpline, &parallelogram_parts(), &[(0, 0), (1, 0), (0, 1), (1, 1)]).unwrap();
        assert!(quad.blocks.iter().all(sum_rows));
        let tri = lattice_ifs(LatticeScheme::Sqrt3, &ternary_triangle_parts(), &[(0, 0), (1, 0), (0, 1)]).unwrap();
        assert!(tri.blocks.iter().all(sum_rows));
        assert_eq!(tri.blocks.len(), 9);
        assert_eq!((quad.control.len(), tri.control.len()), (14, 27));
    }

    #[test]
    fn a_patch_that_leaves_the_window_does_not_close() {
        let far = [SubPatch { centre: (40, 0), sign: 1 }];
        assert!(lattice_ifs(LatticeScheme::BoxSpline, &far, &[(0, 0)]).is_err());
    }
}
