//! One exact subdivision step of a neighbourhood: the schemes' rules over
//! rationals, with the weights as parameters (affine forms in them).

use std::collections::{BTreeMap, HashMap};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::local::{Half, Local, Role, Side};
use crate::algebra::{Affine, Num};
use crate::design::Value;
use crate::mesh::rules::{self, CcEdge, CcVertex, LoopEdge, LoopVertex, Mix, Weight};
use crate::mesh::{LoopWeights, QuadWeights, Scheme};

/// An affine form in the weights (`c + Σ k_p · weight_p`, exact): the
/// solver's [`Affine`], its variables the weights' parameter numbers.
pub(super) type Lin = Affine;

/// The constant `c`.
pub(super) fn konst(c: BigRational) -> Lin {
    Affine::constant(Num::rational(c))
}

/// The weight numbered `p`.
pub(super) fn param(p: usize) -> Lin {
    Affine::var(p)
}

/// `l += k · o`.
pub(super) fn add_lin(l: &mut Lin, o: &Lin, k: &BigRational) {
    *l = l.add_scaled(o, &Num::rational(k.clone()));
}

/// The constant term of a form whose coefficients are rational (every form here).
fn constant_of(l: &Lin) -> BigRational {
    l.constant_term().as_rational().unwrap_or_else(BigRational::zero)
}

/// A form as a matrix entry of the automaton file: a number, or `c + k*name + …`.
pub(super) fn value(l: &Lin, names: &[String]) -> Value {
    if l.terms().is_empty() {
        return Value::Num(l.constant_term().clone());
    }
    let mut text = String::new();
    let mut push = |q: &BigRational, name: Option<&str>| {
        let neg = q.is_negative();
        let a = q.abs();
        text.push_str(match (text.is_empty(), neg) {
            (true, false) => "",
            (true, true) => "-",
            (false, false) => " + ",
            (false, true) => " - ",
        });
        match name {
            Some(n) if a.is_one() => text.push_str(n),
            Some(n) => text.push_str(&format!("{a}*{n}")),
            None => text.push_str(&a.to_string()),
        }
    };
    let c = constant_of(l);
    if !c.is_zero() {
        push(&c, None);
    }
    for (p, q) in l.terms() {
        push(&q.as_rational().expect("rational weights"), Some(&names[*p]));
    }
    Value::Text(text)
}

pub(super) fn rat(p: i64, q: i64) -> BigRational {
    BigRational::new(BigInt::from(p), BigInt::from(q))
}

/// A new point: old control point → weight.
pub(super) type Sym = BTreeMap<usize, Lin>;

pub(super) fn add_point(s: &mut Sym, v: usize, w: &Lin) {
    let e = s.entry(v).or_insert_with(Affine::zero);
    add_lin(e, w, &BigRational::one());
    if e.is_zero() {
        s.remove(&v);
    }
}

pub(super) fn add_sym(s: &mut Sym, o: &Sym, k: &BigRational) {
    for (v, w) in o {
        let e = s.entry(*v).or_insert_with(Affine::zero);
        add_lin(e, w, k);
        if e.is_zero() {
            s.remove(v);
        }
    }
}

impl Weight for Lin {
    fn ratio(p: i64, q: i64) -> Lin {
        konst(rat(p, q))
    }
}

/// Symbolic points mix as the mesh code's positions do, through the same
/// rules ([`crate::mesh::rules`]): a weight times a point whose weights
/// are constants (a rule never multiplies two of its parameters).
impl Mix for Sym {
    type Weight = Lin;
    fn zero() -> Sym {
        Sym::new()
    }
    fn add(&mut self, p: &Sym, w: &Lin) {
        for (v, c) in p {
            debug_assert!(c.terms().is_empty() || w.terms().is_empty(), "a product of two weights");
            let product = if c.terms().is_empty() { w.scale(c.constant_term()) } else { c.scale(w.constant_term()) };
            add_point(self, *v, &product);
        }
    }
    fn add_share(&mut self, p: &Sym, n: usize) {
        self.add(p, &konst(rat(1, n as i64)));
    }
}

/// The weights of a scheme as named parameters of the automaton, with defaults.
pub(super) struct Weights {
    pub(super) scheme: Scheme,
    pub(super) names: Vec<String>,
    pub(super) defaults: Vec<Value>,
    pub(super) quad: QuadWeights,
    pub(super) triangle: LoopWeights,
}

impl Weights {
    pub(super) fn param(&mut self, name: String, default: impl Into<Value>) -> usize {
        if let Some(i) = self.names.iter().position(|n| *n == name) {
            return i;
        }
        self.names.push(name);
        self.defaults.push(default.into());
        self.names.len() - 1
    }

    /// Doo-Sabin's weights of an `n`-gon's corner: `α_k` on corner `i + k`.
    /// Quads: `alpha`, `beta`, `gamma` and the rest on the opposite corner;
    /// other `n`: `a{n}_{k}` with the rest on corner `⌊n/2⌋`.
    pub(super) fn doo_sabin(&mut self, n: usize) -> Vec<Lin> {
        let classic = crate::mesh::doo_sabin_weights(n);
        let rest = n / 2;
        let mut out: Vec<Lin> = (0..n)
            .map(|k| {
                if k == rest {
                    return Affine::zero();
                }
                let (name, default) = match (n, k) {
                    (4, 0) => ("alpha".to_string(), self.quad.alpha),
                    (4, 1) => ("beta".to_string(), self.quad.beta),
                    (4, 3) => ("gamma".to_string(), self.quad.gamma),
                    _ => (format!("a{n}_{k}"), classic[k]),
                };
                param(self.param(name, default))
            })
            .collect();
        let mut last = konst(BigRational::one());
        for (k, w) in out.iter().enumerate() {
            if k != rest {
                add_lin(&mut last, w, &-BigRational::one());
            }
        }
        out[rest] = last;
        out
    }

    /// Catmull-Clark's vertex rule at valence `n`: the shares of the
    /// neighbours' average (`ring{n}`) and of the face points' average
    /// (`faces{n}`), both `1/n` in the classic rule `(Q + 2R + (n − 3)v)/n`.
    pub(super) fn catmull_clark_vertex(&mut self, n: usize) -> (Lin, Lin) {
        let ring = self.param(format!("ring{n}"), format!("1/{n}"));
        let faces = self.param(format!("faces{n}"), format!("1/{n}"));
        (param(ring), param(faces))
    }

    /// Loop's ring weight `β` at valence `n` (each neighbour; the vertex keeps `1 − nβ`).
    pub(super) fn loop_ring(&mut self, n: usize) -> Lin {
        let default = self.triangle.ring(n) / n as f64;
        param(self.param(format!("beta{n}"), default))
    }
}

/// One exact step of a local mesh, and where each old element went.
pub(super) struct Step {
    pub(super) mesh: Local,
    /// The new points over the old control points (`None`: its stencil leaves the neighbourhood).
    pub(super) points: Vec<Option<Sym>>,
    /// Catmull-Clark, Loop: the child face of face `f` at corner `i`; Doo-Sabin: the face of `f`.
    pub(super) child: Vec<Vec<usize>>,
    /// Loop: the middle triangle of each face.
    pub(super) middle: Vec<usize>,
    /// Doo-Sabin: the edge face of a half-edge, and the corner of its copy of this half-edge's start.
    pub(super) edge_face: HashMap<Half, (usize, usize)>,
    /// √3: the mesh after the first of the two steps an arrow makes.
    pub(super) halfway: Option<Local>,
}

pub(super) fn step(m: &Local, w: &mut Weights) -> Step {
    match w.scheme {
        Scheme::DooSabin => doo_sabin_step(m, w),
        Scheme::Sqrt3 => sqrt3_step(m),
        _ => primal_step(m, w),
    }
}

/// A weight within this of a small fraction is that fraction (a float's
/// own rounding of it is below this).
const FRACTION: f64 = 1e-15;

/// An exact rational for a weight: small fractions where the weight is
/// one, the float's shortest decimal otherwise.
pub(super) fn exact_weight(x: f64) -> BigRational {
    for q in 1..=36i64 {
        let p = (x * q as f64).round();
        if (p / q as f64 - x).abs() < FRACTION {
            return rat(p as i64, q);
        }
    }
    Num::from_f64(x).as_rational().unwrap_or_default()
}

/// One √3 step of a closed neighbourhood: vertex points `(1 − a) v + a/n Σ`
/// (`a = (4 − 2cos(2π/n))/9`), a centroid per face numbered after the
/// vertices, and every edge flipped into `[c_g, b, c_f]`, `[c_f, a, c_g]`.
pub(super) fn sqrt3_once(m: &Local) -> (Local, Vec<Option<Sym>>) {
    let nv = m.vertices;
    let mut points: Vec<Option<Sym>> = (0..nv)
        .map(|v| {
            if !m.closed_at(v) {
                return None;
            }
            let n = m.around[v].len();
            let a = exact_weight(crate::mesh::sqrt3_alpha(n));
            let (keep, each) = (konst(BigRational::one() - &a), konst(a / BigInt::from(n)));
            Some(rules::sqrt3_vertex(&unit(v), m.around[v].iter().map(|&h| unit(m.head(h))), &keep, &each))
        })
        .collect();
    for face in &m.faces {
        let corners: Vec<Sym> = face.iter().map(|&v| unit(v)).collect();
        points.push(Some(rules::centroid(corners.iter())));
    }
    let mut faces = Vec::new();
    for (f, face) in m.faces.iter().enumerate() {
        for i in 0..face.len() {
            let Some(t) = m.twin_of((f, i)).filter(|&t| (f, i) < t && m.sides[f][i] == Side::Inner) else { continue };
            let (a, b, cf, cg) = (m.at((f, i)), m.head((f, i)), nv + f, nv + t.0);
            faces.push(vec![cg, b, cf]);
            faces.push(vec![cf, a, cg]);
        }
    }
    let count = points.len();
    (Local::with_open_sides(faces, count, Side::Cut), points)
}

/// Two √3 steps (an arrow): a triangle's nine children lie in it (a ternary split).
pub(super) fn sqrt3_step(m: &Local) -> Step {
    let (halfway, first) = sqrt3_once(m);
    let (mesh, second) = sqrt3_once(&halfway);
    let points = second
        .iter()
        .map(|s| {
            let mut out = Sym::new();
            for (j, w) in s.as_ref()? {
                add_sym(&mut out, first[*j].as_ref()?, &constant_of(w));
            }
            Some(out)
        })
        .collect();
    Step { mesh, points, child: Vec::new(), middle: Vec::new(), edge_face: HashMap::new(), halfway: Some(halfway) }
}

/// √3's children, found by their vertices: the corners `a_i` of a face
/// `f`, its centroid `c_f` halfway, and the centroids `c_Q`, `c_P` (second
/// step) of the two triangles `Q_i = [c_f, a_i, c_g]`, `P_i = [c_g, a_{i+1}, c_f]`
/// its edge `i` became halfway (`c_Q_i`, `c_P_i` are the thirds of that
/// edge). A face has nine children (one at each corner, six around `c_f`),
/// an edge three (`a → c_Q → c_P → b`), a vertex one (`a → c_Q`).
pub(super) fn sqrt3_children(role: Role, m: &Local, s: &Step, h: Half) -> Vec<Half> {
    const MISSING: Half = (usize::MAX, 0);
    let Some(mid) = &s.halfway else { return Vec::new() };
    let (nv, n1) = (m.vertices, mid.vertices);
    let at = |x: usize, y: usize| s.mesh.twin.get(&(x, y)).copied().unwrap_or(MISSING);
    let face_of = |x: usize, y: usize| mid.twin.get(&(x, y)).map_or(usize::MAX, |h| n1 + h.0);
    let (f, i) = h;
    let corner = |c: usize| m.faces[f][c % 3];
    let cf = nv + f;
    let q = |c: usize| face_of(cf, corner(c));
    let p = |c: usize| face_of(corner(c + 1), cf);
    match role {
        // Anchored as the ternary split's copies keep the parent's orientation: three
        // translated corner triangles, three translated and three half-turned around c_f.
        Role::Face => vec![
            at(corner(i), q(i)),
            at(p(i), corner(i + 1)),
            at(q(i + 2), p(i + 1)),
            at(q(i), p(i)),
            at(p(i + 2), cf),
            at(cf, q(i + 1)),
            at(cf, p(i + 2)),
            at(q(i + 1), cf),
            at(p(i + 1), q(i + 2)),
        ],
        Role::Edge => vec![at(corner(i), q(i)), at(q(i), p(i)), at(p(i), corner(i + 1))],
        Role::Vertex => vec![at(corner(i), q(i))],
    }
}

/// The point of control point `v` alone.
fn unit(v: usize) -> Sym {
    Sym::from([(v, konst(BigRational::one()))])
}

/// Catmull-Clark's face points: the faces' centroids.
fn face_points(m: &Local) -> Vec<Sym> {
    m.faces
        .iter()
        .map(|f| {
            let corners: Vec<Sym> = f.iter().map(|&v| unit(v)).collect();
            rules::centroid(corners.iter())
        })
        .collect()
}

/// The vertex point of `v` (Catmull-Clark or Loop), `None` where its
/// stencil leaves the neighbourhood.
fn vertex_point(m: &Local, w: &mut Weights, face_point: &[Sym], v: usize) -> Option<Sym> {
    let out = &m.around[v];
    let side = |h: Half| m.sides[h.0][h.1];
    let border: Vec<Half> = out.iter().copied().filter(|&h| side(h) == Side::Border).collect();
    if out.is_empty() || out.iter().any(|&h| side(h) == Side::Cut || side(m.prev(h)) == Side::Cut) {
        return None;
    }
    if let Some(&b) = border.first() {
        // (u + 6v + w)/8 with the border neighbours: the head of the outgoing
        // border half-edge and the tail of the incoming one.
        let incoming = out.iter().map(|&h| m.prev(h)).find(|&g| side(g) == Side::Border);
        return incoming.map(|g| rules::border_curve(&unit(m.head(b)), &unit(v), &unit(m.at(g))));
    }
    let n = out.len();
    let one = konst(BigRational::one());
    if w.scheme == Scheme::Loop {
        let beta = w.loop_ring(n);
        let mut keep = one;
        add_lin(&mut keep, &beta, &rat(-(n as i64), 1));
        let ring = rules::sum(out.iter().map(|&h| unit(m.head(h))));
        return Some(rules::loop_vertex(&unit(v), &ring, &LoopVertex { keep, each: beta }));
    }
    // (1 − r − f) v + r · (mean neighbour) + f · (mean face point), which is
    // f/n · Σ f_j + 2r/n · Σ (v + n_j)/2 + (1 − 2r − f) v; r = f = 1/n is (Q + 2R + (n − 3)v)/n.
    let (r, f) = w.catmull_clark_vertex(n);
    let mut keep = one;
    add_lin(&mut keep, &r, &rat(-2, 1));
    add_lin(&mut keep, &f, &-BigRational::one());
    let weights = CcVertex {
        faces: f.scale(&Num::rational(rat(1, n as i64))),
        edges: r.scale(&Num::rational(rat(2, n as i64))),
        keep,
    };
    let ring = out.iter().map(|&h| (unit(m.head(h)), face_point[h.0].clone()));
    Some(rules::cc_vertex(&unit(v), ring, |_| weights))
}

/// The edge point of the half-edge `h` (Catmull-Clark or Loop), `None`
/// where its stencil leaves the neighbourhood.
fn edge_point(m: &Local, w: &mut Weights, face_point: &[Sym], h: Half) -> Option<Sym> {
    let (a, b) = (m.at(h), m.head(h));
    match (m.sides[h.0][h.1], m.twin_of(h)) {
        (Side::Inner, Some(t)) => {
            let (ua, ub) = (unit(a), unit(b));
            if w.scheme == Scheme::Loop {
                let end = param(w.param("w".into(), w.triangle.w));
                let mut opposite = konst(rat(1, 2));
                add_lin(&mut opposite, &end, &-BigRational::one());
                let (c, d) = (unit(m.at(m.prev(h))), unit(m.at(m.prev(t))));
                Some(rules::loop_edge(&ua, &ub, &c, &d, &LoopEdge { end, opposite }))
            } else {
                // (1 − c)/2 (a + b) + c/2 (f + g): c = 1/2 is (a + b + f + g)/4.
                let c = param(w.param("edge_faces".into(), "1/2"));
                let mut ends = konst(rat(1, 2));
                add_lin(&mut ends, &c, &rat(-1, 2));
                let faces = c.scale(&Num::rational(rat(1, 2)));
                Some(rules::cc_edge(&ua, &ub, &face_point[h.0], &face_point[t.0], &CcEdge { ends, faces }))
            }
        }
        (Side::Border, _) => Some(rules::midpoint(&unit(a), &unit(b))),
        _ => None,
    }
}

/// Catmull-Clark and Loop: vertex points, edge points, (face points), children per corner.
pub(super) fn primal_step(m: &Local, w: &mut Weights) -> Step {
    let loop_ = w.scheme == Scheme::Loop;
    let face_point = face_points(m);
    let mut points: Vec<Option<Sym>> = (0..m.vertices).map(|v| vertex_point(m, w, &face_point, v)).collect();
    // Edge points, one per edge, numbered after the vertices.
    let mut edge_of: HashMap<(usize, usize), usize> = HashMap::new();
    for (f, face) in m.faces.iter().enumerate() {
        for i in 0..face.len() {
            let (a, b) = (m.at((f, i)), m.head((f, i)));
            if let std::collections::hash_map::Entry::Vacant(e) = edge_of.entry((a.min(b), a.max(b))) {
                e.insert(points.len());
                points.push(edge_point(m, w, &face_point, (f, i)));
            }
        }
    }
    let edge = |h: Half| {
        let (a, b) = (m.at(h), m.head(h));
        edge_of[&(a.min(b), a.max(b))]
    };
    let (mut faces, mut sides, mut child, mut middle) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (f, face) in m.faces.iter().enumerate() {
        let d = face.len();
        let fp = (!loop_).then(|| {
            points.push(Some(face_point[f].clone()));
            points.len() - 1
        });
        let mut here = Vec::with_capacity(d);
        for (i, &corner) in face.iter().enumerate() {
            let (h, g) = ((f, i), m.prev((f, i)));
            here.push(faces.len());
            let (outer_h, outer_g) = (m.sides[f][i], m.sides[g.0][g.1]);
            match fp {
                Some(c) => {
                    faces.push(vec![corner, edge(h), c, edge(g)]);
                    sides.push(vec![outer_h, Side::Inner, Side::Inner, outer_g]);
                }
                None => {
                    faces.push(vec![corner, edge(h), edge(g)]);
                    sides.push(vec![outer_h, Side::Inner, outer_g]);
                }
            }
        }
        if loop_ {
            middle.push(faces.len());
            faces.push((0..d).map(|i| edge((f, i))).collect());
            sides.push(vec![Side::Inner; d]);
        }
        child.push(here);
    }
    let count = points.len();
    Step { mesh: Local::new(faces, sides, count), points, child, middle, edge_face: HashMap::new(), halfway: None }
}

/// Doo-Sabin: a point per corner, faces for the faces, the inner edges and the closed vertices.
pub(super) fn doo_sabin_step(m: &Local, w: &mut Weights) -> Step {
    let mut points = Vec::new();
    let mut corner = Vec::new();
    for face in &m.faces {
        let d = face.len();
        let alpha = w.doo_sabin(d);
        corner.push(points.len());
        for i in 0..d {
            points.push(Some(rules::doo_sabin_corner(i, |j| unit(face[j]), &alpha)));
        }
    }
    let new = |(f, i): Half| corner[f] + i;
    let closed = |v: usize| m.closed_at(v);
    let mut faces: Vec<Vec<usize>> = Vec::new();
    let mut sides: Vec<Vec<Side>> = Vec::new();
    let mut child = Vec::new();
    for (f, face) in m.faces.iter().enumerate() {
        child.push(vec![faces.len()]);
        faces.push((0..face.len()).map(|i| new((f, i))).collect());
        sides.push(m.sides[f].clone());
    }
    // Across a side of an edge face or a vertex face: the vertex face of `v` if it has one.
    let vertex_side = |v: usize| {
        if closed(v) {
            Side::Inner
        } else if m.around[v].iter().any(|h| m.sides[h.0][h.1] == Side::Cut) || m.around[v].is_empty() {
            Side::Cut
        } else {
            let cut_in = m.around[v].iter().any(|&h| {
                let g = m.prev(h);
                m.sides[g.0][g.1] == Side::Cut
            });
            if cut_in { Side::Cut } else { Side::Border }
        }
    };
    let mut edge_face = HashMap::new();
    for (f, face) in m.faces.iter().enumerate() {
        for i in 0..face.len() {
            let h = (f, i);
            let Some(t) = m.twin_of(h).filter(|_| m.sides[f][i] == Side::Inner) else { continue };
            if edge_face.contains_key(&h) {
                continue;
            }
            // [b_f, a_f, a_g, b_g] for h = a → b in f, its twin b → a in g.
            let (bf, af, ag, bg) = (new(m.next(h)), new(h), new(m.next(t)), new(t));
            edge_face.insert(h, (faces.len(), 1));
            edge_face.insert(t, (faces.len(), 3));
            faces.push(vec![bf, af, ag, bg]);
            sides.push(vec![Side::Inner, vertex_side(m.at(h)), Side::Inner, vertex_side(m.at(t))]);
        }
    }
    for v in 0..m.vertices {
        if closed(v) {
            let fan = m.fan(m.around[v][0]);
            faces.push(fan.iter().map(|&h| new(h)).collect());
            sides.push(vec![Side::Inner; fan.len()]);
        }
    }
    let count = points.len();
    Step { mesh: Local::new(faces, sides, count), points, child, middle: Vec::new(), edge_face, halfway: None }
}
