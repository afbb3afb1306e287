//! The subdivision rules, written once over any [`Mix`] of points: the
//! mesh code mixes positions (`[f64; 3]` with `f64` weights, in the order
//! of CGAL's and OpenSubdiv's arithmetic, so their meshes are matched), the
//! automaton generator mixes exact symbolic points (a control point's
//! number → an affine form in the rule's weights, `schemes::mesh`). What
//! differs between the two is only the weights' values: numbers here, free
//! parameters there with these numbers as their defaults.
//!
//! ```
//! use bcifs::mesh::rules::{self, CcEdge, Mix};
//! // Catmull-Clark's edge point of the classic rule: (a + b + f + g)/4.
//! let [a, b, f, g] = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, -1.0, 0.0]];
//! assert_eq!(rules::cc_edge(&a, &b, &f, &g, &CcEdge::CLASSIC), [1.0, 0.0, 0.0]);
//! ```

/// What a rule combines: points that can be scaled and summed. The weight
/// type is the rule's number: `f64`, or an exact affine form.
pub trait Mix: Sized {
    /// A weight.
    type Weight: Weight;
    /// The point with every weight 0 (the origin of positions).
    fn zero() -> Self;
    /// `self += w · p`.
    fn add(&mut self, p: &Self, w: &Self::Weight);
    /// `self += p / n` (a share of a mean, divided as CGAL divides).
    fn add_share(&mut self, p: &Self, n: usize);
}

/// A rule's number: its constants are ratios.
pub trait Weight: Clone {
    /// `p / q`.
    fn ratio(p: i64, q: i64) -> Self;
}

impl Weight for f64 {
    fn ratio(p: i64, q: i64) -> f64 {
        p as f64 / q as f64
    }
}

impl Mix for [f64; 3] {
    type Weight = f64;
    fn zero() -> [f64; 3] {
        [0.0; 3]
    }
    #[inline]
    fn add(&mut self, p: &[f64; 3], w: &f64) {
        self[0] += w * p[0];
        self[1] += w * p[1];
        self[2] += w * p[2];
    }
    #[inline]
    fn add_share(&mut self, p: &[f64; 3], n: usize) {
        (0..3).for_each(|a| self[a] += p[a] / n as f64);
    }
}

/// `Σ w_k p_k`, in order.
pub fn combine<M: Mix>(terms: &[(&M, &M::Weight)]) -> M {
    let mut out = M::zero();
    for (p, w) in terms {
        out.add(p, w);
    }
    out
}

/// The centroid of a face's corners: `Σ p / n` (Catmull-Clark's face
/// point, √3's new point).
pub fn centroid<'a, M: Mix + 'a>(corners: impl ExactSizeIterator<Item = &'a M>) -> M {
    let n = corners.len();
    let mut c = M::zero();
    corners.for_each(|p| c.add_share(p, n));
    c
}

/// Doo-Sabin's point of corner `i` of an `n`-gon whose corner `j` is
/// `corner(j)`: `Σ_k α_k p_{i+k}` (`alpha`: the `n` weights, `α_0` on the
/// corner itself; [`crate::mesh::doo_sabin_weights`] are the classic ones).
pub fn doo_sabin_corner<M: Mix>(i: usize, corner: impl Fn(usize) -> M, alpha: &[M::Weight]) -> M {
    let n = alpha.len();
    let mut p = M::zero();
    for (k, a) in alpha.iter().enumerate() {
        p.add(&corner((i + k) % n), a);
    }
    p
}

/// The weights of Catmull-Clark's edge point: on each end and on each
/// adjacent face point.
#[derive(Clone, Debug, PartialEq)]
pub struct CcEdge<W> {
    /// On each end of the edge (classic `1/4`).
    pub ends: W,
    /// On each adjacent face's point (classic `1/4`).
    pub faces: W,
}

impl CcEdge<f64> {
    /// `(a + b + f + g)/4`.
    pub const CLASSIC: CcEdge<f64> = CcEdge { ends: 0.25, faces: 0.25 };
}

/// Catmull-Clark's point of the interior edge `[a, b]` between the faces
/// whose points are `f` and `g`: `ends · (a + b) + faces · (f + g)`.
pub fn cc_edge<M: Mix>(a: &M, b: &M, f: &M, g: &M, w: &CcEdge<M::Weight>) -> M {
    combine(&[(a, &w.ends), (b, &w.ends), (f, &w.faces), (g, &w.faces)])
}

/// The weights of Catmull-Clark's vertex point at valence `n`: on the sum
/// of the face points around, on the sum of the edge midpoints around, and
/// on the vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct CcVertex<W> {
    /// On `Σ f_j` (classic `1/n²`).
    pub faces: W,
    /// On `Σ (v + n_j)/2` (classic `2/n²`).
    pub edges: W,
    /// On `v` (classic `(n − 3)/n`).
    pub keep: W,
}

impl CcVertex<f64> {
    /// `(Q + 2R + (n − 3)v)/n`, with CGAL's arithmetic.
    pub fn classic(n: usize) -> CcVertex<f64> {
        let n = n as f64;
        CcVertex { faces: 1.0 / n / n, edges: 2.0 / n / n, keep: (n - 3.0) / n }
    }
}

/// Catmull-Clark's point of the interior vertex `v` whose neighbours and
/// face points around are `ring` (pairs: the head of an outgoing edge, the
/// point of the face after it), its weights at the valence given by `weights(n)`.
pub fn cc_vertex<M: Mix>(
    v: &M,
    ring: impl Iterator<Item = (M, M)>,
    weights: impl FnOnce(usize) -> CcVertex<M::Weight>,
) -> M {
    let (one, half) = (M::Weight::ratio(1, 1), M::Weight::ratio(1, 2));
    let (mut q, mut r, mut n) = (M::zero(), M::zero(), 0usize);
    for (neighbour, face) in ring {
        q.add(&face, &one);
        r.add(v, &half);
        r.add(&neighbour, &half);
        n += 1;
    }
    let w = weights(n);
    combine(&[(&q, &w.faces), (&r, &w.edges), (v, &w.keep)])
}

/// The cubic B-spline point `(u + 6v + w)/8` of a border vertex `v`
/// between its border neighbours `u` and `w` (Catmull-Clark's and Loop's
/// border rule).
pub fn border_curve<M: Mix>(u: &M, v: &M, w: &M) -> M {
    let (side, middle) = (M::Weight::ratio(1, 8), M::Weight::ratio(6, 8));
    combine(&[(u, &side), (v, &middle), (w, &side)])
}

/// The midpoint of a border edge `[a, b]`.
pub fn midpoint<M: Mix>(a: &M, b: &M) -> M {
    let half = M::Weight::ratio(1, 2);
    combine(&[(a, &half), (b, &half)])
}

/// The weights of Loop's vertex point at some valence: on the vertex and
/// on the sum of its neighbours.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopVertex<W> {
    /// On `v` (`1 − nβ`).
    pub keep: W,
    /// On `Σ n_j` (`β`).
    pub each: W,
}

/// Loop's point of the interior vertex `v` whose neighbours sum to `ring`: `keep · v + each · ring`.
pub fn loop_vertex<M: Mix>(v: &M, ring: &M, w: &LoopVertex<M::Weight>) -> M {
    combine(&[(v, &w.keep), (ring, &w.each)])
}

/// The sum of points (a ring's, for [`loop_vertex`]).
pub fn sum<M: Mix>(points: impl Iterator<Item = M>) -> M {
    let one = M::Weight::ratio(1, 1);
    let mut s = M::zero();
    points.for_each(|p| s.add(&p, &one));
    s
}

/// The weights of Loop's edge point: on each end, on each opposite vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopEdge<W> {
    /// On each end (classic `3/8`).
    pub end: W,
    /// On each opposite vertex (classic `1/8`).
    pub opposite: W,
}

/// Loop's point of the interior edge `[a, b]` whose triangles' third
/// corners are `c` and `d`.
pub fn loop_edge<M: Mix>(a: &M, b: &M, c: &M, d: &M, w: &LoopEdge<M::Weight>) -> M {
    combine(&[(a, &w.end), (b, &w.end), (c, &w.opposite), (d, &w.opposite)])
}

/// √3's point of the interior vertex `v` of valence `n` with the
/// neighbours `ring`: `(1 − a) v + Σ (a/n) n_j` (`keep = 1 − a`, `each = a/n`;
/// [`crate::mesh::sqrt3_alpha`] is `a`).
pub fn sqrt3_vertex<M: Mix>(v: &M, ring: impl Iterator<Item = M>, keep: &M::Weight, each: &M::Weight) -> M {
    let mut q = M::zero();
    q.add(v, keep);
    ring.for_each(|p| q.add(&p, each));
    q
}
