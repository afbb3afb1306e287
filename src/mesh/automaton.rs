//! A polygon mesh as a BC-IFS automaton: one state per kind of
//! neighbourhood that occurs, exact subdivision matrices, and the incidence
//! and adjacency constraints between neighbouring sub-cells.
//!
//! A *cell* is a patch of the limit surface (a face state), a curve where
//! two patches meet (an edge state) or a point where curves meet (a vertex
//! state). Its control points are the mesh vertices its limit depends on:
//!
//! | scheme | face (patch) | edge | vertex |
//! |---|---|---|---|
//! | Catmull-Clark, Loop | a mesh face, with every face that shares a vertex with it | a mesh edge, with the faces around its two ends | a mesh vertex, with its faces |
//! | Doo-Sabin | an interior mesh vertex, with its faces (corners: their centroids) | a mesh edge: its two faces | a mesh face (its centroid) |
//!
//! A cell is *anchored* at a half-edge (a face and a corner), and its
//! control points are numbered by a breadth-first walk of its neighbourhood
//! from the anchor: two cells with the same walk (same faces, same sides on
//! the border) are the same state, and the walk, not the mesh's numbering,
//! says which control point is which. One exact subdivision step of a
//! state's neighbourhood (the scheme's rules over rationals, with the
//! weights as parameters) gives the new points as affine combinations of
//! the old ones; the children's neighbourhoods are found in the subdivided
//! one, anchored at the child half-edges, and their walks give the columns
//! of the subdivision matrices. New states are processed until none
//! appears: for the classic schemes a face next to an extraordinary vertex
//! subdivides into one such face and regular ones, so the automaton has a
//! few states per valence (and per n-gon for Doo-Sabin).
//!
//! The constraints are found the same way: a child's side that lies on a
//! side of its parent gives an incidence equation (`T_c b_k = b_j U_t`), a
//! side two children share gives an adjacency equation (`T_c b_k = T_d b_l
//! P`), where `P` renumbers the shared cell from one anchor to the other (a
//! selection arrow between edge or vertex states). They hold identically in
//! the weights: `bcifs solve` keeps every weight free, and `bcifs check`
//! finds residuals of zero.
//!
//! The weights are the rotationally symmetric rules on each scheme's
//! stencils: Doo-Sabin `alpha, beta, gamma` on quads and `a{n}_{k}` (corner
//! `i + k`'s share) on other n-gons; Loop `w` and `beta{n}` per valence;
//! Catmull-Clark `edge_faces` and, per valence, `ring{n}` and `faces{n}`.
//!
//! The model is the user's mesh itself: its vertices are the control
//! points, and the `patches` layout lists each patch's root state and
//! control points (pieces that share points are welded).
//!
//! √3 rotates the triangles, so a triangle is nested in its parent only
//! after two steps: an arrow of the √3 automaton is two steps (a ternary
//! split into nine), its cells reach one ring further (the faces around
//! the faces around a cell's vertices: 27 points for the regular patch),
//! and its weights are the classic `(4 − 2cos(2π/n))/9` (exact where they
//! are rational, the float's decimal otherwise): two steps would multiply
//! weights, and the constraints would no longer be linear in them. Closed
//! meshes only: its border rule changes from one step to the next.

use std::collections::{BTreeMap, HashMap, VecDeque};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::polymesh::{MeshError, PolyMesh, Scheme};
use super::subdivide::{LoopWeights, QuadWeights, RuleWeights};
use crate::algebra::{Num, Surd};
use crate::automaton::ArrowKind;
use crate::design::{Design, DesignBuilder, Matrix, Model, Value};
use crate::space::CellKind;

/// What a cell is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Role {
    Face,
    Edge,
    Vertex,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::Face => "face",
            Role::Edge => "edge",
            Role::Vertex => "vertex",
        }
    }
    fn kind(self) -> CellKind {
        match self {
            Role::Face => CellKind::Face,
            Role::Edge => CellKind::Edge,
            Role::Vertex => CellKind::Vertex,
        }
    }
    /// The role of its sides.
    fn side(self) -> Role {
        match self {
            Role::Face => Role::Edge,
            _ => Role::Vertex,
        }
    }
}

/// What is across a side of a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Side {
    /// Another face of the same (local) mesh.
    Inner,
    /// Nothing: the border of the surface.
    Border,
    /// A face outside the neighbourhood.
    Cut,
}

/// A half-edge: face `.0`, from its corner `.1` to the next.
type Half = (usize, usize);

/// A mesh with its half-edges (the input, a neighbourhood, or a subdivided one).
#[derive(Clone, Debug)]
struct Local {
    faces: Vec<Vec<usize>>,
    sides: Vec<Vec<Side>>,
    vertices: usize,
    twin: HashMap<(usize, usize), Half>,
    around: Vec<Vec<Half>>,
}

impl Local {
    fn new(faces: Vec<Vec<usize>>, sides: Vec<Vec<Side>>, vertices: usize) -> Local {
        let mut twin = HashMap::new();
        let mut around = vec![Vec::new(); vertices];
        for (f, face) in faces.iter().enumerate() {
            for (i, &v) in face.iter().enumerate() {
                twin.insert((v, face[(i + 1) % face.len()]), (f, i));
                around[v].push((f, i));
            }
        }
        Local { faces, sides, vertices, twin, around }
    }

    /// A mesh whose sides without a face across are all `open`: the
    /// border of a whole mesh, or the cut edge of a neighbourhood.
    fn with_open_sides(faces: Vec<Vec<usize>>, vertices: usize, open: Side) -> Local {
        let mut local = Local::new(faces, Vec::new(), vertices);
        local.sides = (0..local.faces.len())
            .map(|f| {
                (0..local.faces[f].len())
                    .map(|i| if local.twin_of((f, i)).is_some() { Side::Inner } else { open })
                    .collect()
            })
            .collect();
        local
    }

    fn of_mesh(mesh: &PolyMesh) -> Local {
        Local::with_open_sides(mesh.faces().map(<[usize]>::to_vec).collect(), mesh.positions.len(), Side::Border)
    }

    fn deg(&self, f: usize) -> usize {
        self.faces[f].len()
    }
    fn at(&self, (f, i): Half) -> usize {
        self.faces[f][i % self.deg(f)]
    }
    fn head(&self, (f, i): Half) -> usize {
        self.faces[f][(i + 1) % self.deg(f)]
    }
    fn next(&self, (f, i): Half) -> Half {
        (f, (i + 1) % self.deg(f))
    }
    fn prev(&self, (f, i): Half) -> Half {
        (f, (i + self.deg(f) - 1) % self.deg(f))
    }
    fn twin_of(&self, h: Half) -> Option<Half> {
        self.twin.get(&(self.head(h), self.at(h))).copied()
    }
    /// The next half-edge out of the same vertex, counter-clockwise.
    fn rotate(&self, h: Half) -> Option<Half> {
        self.twin_of(self.prev(h))
    }
    /// Whether every side at vertex `v` has a face across it.
    fn closed_at(&self, v: usize) -> bool {
        !self.around[v].is_empty()
            && self.around[v].iter().all(|&h| self.sides[h.0][h.1] == Side::Inner && self.twin_of(h).is_some())
    }
    /// The half-edges out of `v` counter-clockwise from `h` (a closed fan).
    fn fan(&self, h: Half) -> Vec<Half> {
        let mut out = vec![h];
        let mut at = h;
        while let Some(r) = self.rotate(at) {
            if r == h || out.len() > self.around[self.at(h)].len() {
                break;
            }
            out.push(r);
            at = r;
        }
        out
    }
    /// The side of half-edge `h` as seen from a neighbourhood of faces `set`.
    fn side_in(&self, h: Half, set: &[usize]) -> Side {
        match self.twin_of(h) {
            Some((g, _)) if set.binary_search(&g).is_ok() => Side::Inner,
            Some(_) => Side::Cut,
            None => self.sides[h.0][h.1],
        }
    }
}

/// A cell's neighbourhood walked from its anchor: the canonical local mesh,
/// the mesh vertices in the order of its control points, and its key.
struct Walk {
    local: Local,
    order: Vec<usize>,
    key: Vec<u32>,
}

/// The faces a cell's limit depends on (sorted).
fn neighbourhood(scheme: Scheme, role: Role, m: &Local, h: Half) -> Vec<usize> {
    let faces_at = |v: usize| m.around[v].iter().map(|&(f, _)| f);
    // √3's stencils reach further in two steps: the faces around the faces' vertices.
    let widen = |faces: Vec<usize>| -> Vec<usize> {
        faces.iter().flat_map(|&f| m.faces[f].iter().flat_map(|&v| faces_at(v))).collect()
    };
    let mut set: Vec<usize> = match (scheme, role) {
        (Scheme::Sqrt3, Role::Face) => widen(m.faces[h.0].iter().flat_map(|&v| faces_at(v)).collect()),
        (Scheme::Sqrt3, Role::Edge) => widen(faces_at(m.at(h)).chain(faces_at(m.head(h))).collect()),
        (Scheme::Sqrt3, Role::Vertex) => widen(faces_at(m.at(h)).collect()),
        (Scheme::DooSabin, Role::Face) => faces_at(m.at(h)).collect(),
        (Scheme::DooSabin, Role::Edge) => std::iter::once(h.0).chain(m.twin_of(h).map(|t| t.0)).collect(),
        (Scheme::DooSabin, Role::Vertex) => vec![h.0],
        (_, Role::Face) => m.faces[h.0].iter().flat_map(|&v| faces_at(v)).collect(),
        (_, Role::Edge) => faces_at(m.at(h)).chain(faces_at(m.head(h))).collect(),
        (_, Role::Vertex) => faces_at(m.at(h)).collect(),
    };
    set.sort_unstable();
    set.dedup();
    set
}

/// Walks the faces `set` of `m` breadth first from half-edge `h`: faces
/// are entered at the half-edge they share with the face they are reached
/// from, vertices numbered as they are met.
fn walk(m: &Local, set: &[usize], h: Half) -> Option<Walk> {
    let mut number: HashMap<usize, usize> = HashMap::new();
    let mut order = Vec::new();
    let (mut faces, mut sides, mut key) = (Vec::new(), Vec::new(), Vec::new());
    let mut seen = vec![h.0];
    let mut queue = VecDeque::from([h]);
    while let Some((f, s)) = queue.pop_front() {
        let d = m.deg(f);
        let (mut face, mut side) = (Vec::with_capacity(d), Vec::with_capacity(d));
        key.push(d as u32);
        for k in 0..d {
            let c = (f, (s + k) % d);
            let v = m.at(c);
            let id = *number.entry(v).or_insert_with(|| {
                order.push(v);
                order.len() - 1
            });
            face.push(id);
            key.push(id as u32);
            let sd = m.side_in(c, set);
            if sd == Side::Inner {
                let t = m.twin_of(c)?;
                if !seen.contains(&t.0) {
                    seen.push(t.0);
                    queue.push_back(t);
                }
            }
            key.push(sd as u32);
            side.push(sd);
        }
        faces.push(face);
        sides.push(side);
    }
    // A neighbourhood that is not one piece: a vertex where two fans touch.
    if seen.len() != set.len() {
        return None;
    }
    let n = order.len();
    Some(Walk { local: Local::new(faces, sides, n), order, key })
}

/// Where the children of a cell are, and its sides, as half-edges.
fn sides_of(scheme: Scheme, role: Role, m: &Local, h: Half) -> Vec<Half> {
    match (scheme, role) {
        (_, Role::Vertex) => Vec::new(),
        (Scheme::DooSabin, Role::Face) => m.fan(h).into_iter().map(|g| m.prev(g)).collect(),
        (Scheme::DooSabin, Role::Edge) => vec![h, m.twin_of(h).unwrap_or(h)],
        (_, Role::Face) => (0..m.deg(h.0)).map(|k| (h.0, (h.1 + k) % m.deg(h.0))).collect(),
        (_, Role::Edge) => vec![h, m.next(h)],
    }
}

/// An affine form in the weights: `c + Σ k_p · weight_p`, exact.
#[derive(Clone, Debug, Default, PartialEq)]
struct Lin {
    c: BigRational,
    terms: BTreeMap<usize, BigRational>,
}

impl Lin {
    fn konst(c: BigRational) -> Lin {
        Lin { c, terms: BTreeMap::new() }
    }
    fn param(p: usize) -> Lin {
        Lin { c: BigRational::zero(), terms: BTreeMap::from([(p, BigRational::one())]) }
    }
    fn add_scaled(&mut self, o: &Lin, k: &BigRational) {
        self.c += &o.c * k;
        for (p, q) in &o.terms {
            let e = self.terms.entry(*p).or_insert_with(BigRational::zero);
            *e += q * k;
            if e.is_zero() {
                self.terms.remove(p);
            }
        }
    }
    fn is_zero(&self) -> bool {
        self.c.is_zero() && self.terms.is_empty()
    }
    fn value(&self, names: &[String]) -> Value {
        if self.terms.is_empty() {
            return Value::Num(Num::Exact(Surd::rational(self.c.clone())));
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
        if !self.c.is_zero() {
            push(&self.c, None);
        }
        for (p, q) in &self.terms {
            push(q, Some(&names[*p]));
        }
        Value::Text(text)
    }
}

fn rat(p: i64, q: i64) -> BigRational {
    BigRational::new(BigInt::from(p), BigInt::from(q))
}

/// A new point: old control point → weight.
type Sym = BTreeMap<usize, Lin>;

fn add_point(s: &mut Sym, v: usize, w: &Lin) {
    let e = s.entry(v).or_default();
    e.add_scaled(w, &BigRational::one());
    if e.is_zero() {
        s.remove(&v);
    }
}

fn add_sym(s: &mut Sym, o: &Sym, k: &BigRational) {
    for (v, w) in o {
        let e = s.entry(*v).or_default();
        e.add_scaled(w, k);
        if e.is_zero() {
            s.remove(v);
        }
    }
}

/// `s += k · w · o` for a point `o` of constant weights.
fn add_scaled_points(s: &mut Sym, o: &Sym, w: &Lin, k: &BigRational) {
    for (v, c) in o {
        let mut share = Lin::default();
        share.add_scaled(w, &(&c.c * k));
        add_point(s, *v, &share);
    }
}

/// The weights of a scheme as named parameters of the automaton, with defaults.
struct Weights {
    scheme: Scheme,
    names: Vec<String>,
    defaults: Vec<Value>,
    quad: QuadWeights,
    triangle: LoopWeights,
}

impl Weights {
    fn param(&mut self, name: String, default: impl Into<Value>) -> usize {
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
    fn doo_sabin(&mut self, n: usize) -> Vec<Lin> {
        let classic = |k: usize| {
            let nf = n as f64;
            if k == 0 {
                0.25 + 1.25 / nf
            } else {
                (3.0 + 2.0 * (2.0 * std::f64::consts::PI * k as f64 / nf).cos()) / (4.0 * nf)
            }
        };
        let rest = n / 2;
        let mut out: Vec<Lin> = (0..n)
            .map(|k| {
                if k == rest {
                    return Lin::default();
                }
                let (name, default) = match (n, k) {
                    (4, 0) => ("alpha".to_string(), self.quad.alpha),
                    (4, 1) => ("beta".to_string(), self.quad.beta),
                    (4, 3) => ("gamma".to_string(), self.quad.gamma),
                    _ => (format!("a{n}_{k}"), classic(k)),
                };
                Lin::param(self.param(name, default))
            })
            .collect();
        let mut last = Lin::konst(BigRational::one());
        for (k, w) in out.iter().enumerate() {
            if k != rest {
                last.add_scaled(w, &-BigRational::one());
            }
        }
        out[rest] = last;
        out
    }

    /// Catmull-Clark's vertex rule at valence `n`: the shares of the
    /// neighbours' average (`ring{n}`) and of the face points' average
    /// (`faces{n}`), both `1/n` in the classic rule `(Q + 2R + (n − 3)v)/n`.
    fn catmull_clark_vertex(&mut self, n: usize) -> (Lin, Lin) {
        let ring = self.param(format!("ring{n}"), format!("1/{n}"));
        let faces = self.param(format!("faces{n}"), format!("1/{n}"));
        (Lin::param(ring), Lin::param(faces))
    }

    /// Loop's ring weight `β` at valence `n` (each neighbour; the vertex keeps `1 − nβ`).
    fn loop_ring(&mut self, n: usize) -> Lin {
        let default = self.triangle.ring(n) / n as f64;
        Lin::param(self.param(format!("beta{n}"), default))
    }
}

/// One exact step of a local mesh, and where each old element went.
struct Step {
    mesh: Local,
    /// The new points over the old control points (`None`: its stencil leaves the neighbourhood).
    points: Vec<Option<Sym>>,
    /// Catmull-Clark, Loop: the child face of face `f` at corner `i`; Doo-Sabin: the face of `f`.
    child: Vec<Vec<usize>>,
    /// Loop: the middle triangle of each face.
    middle: Vec<usize>,
    /// Doo-Sabin: the edge face of a half-edge, and the corner of its copy of this half-edge's start.
    edge_face: HashMap<Half, (usize, usize)>,
    /// √3: the mesh after the first of the two steps an arrow makes.
    halfway: Option<Local>,
}

fn step(m: &Local, w: &mut Weights) -> Step {
    match w.scheme {
        Scheme::DooSabin => doo_sabin_step(m, w),
        Scheme::Sqrt3 => sqrt3_step(m),
        _ => primal_step(m, w),
    }
}

/// An exact rational for a weight: small fractions where the weight is
/// one, the float's shortest decimal otherwise.
fn exact_weight(x: f64) -> BigRational {
    for q in 1..=36i64 {
        let p = (x * q as f64).round();
        if (p / q as f64 - x).abs() < 1e-15 {
            return rat(p as i64, q);
        }
    }
    Num::from_f64(x).as_rational().cloned().unwrap_or_default()
}

/// One √3 step of a closed neighbourhood: vertex points `(1 − a) v + a/n Σ`
/// (`a = (4 − 2cos(2π/n))/9`), a centroid per face numbered after the
/// vertices, and every edge flipped into `[c_g, b, c_f]`, `[c_f, a, c_g]`.
fn sqrt3_once(m: &Local) -> (Local, Vec<Option<Sym>>) {
    let nv = m.vertices;
    let mut points: Vec<Option<Sym>> = (0..nv)
        .map(|v| {
            if !m.closed_at(v) {
                return None;
            }
            let n = m.around[v].len();
            let a = exact_weight(super::triangles::sqrt3_alpha(n));
            let mut s = Sym::new();
            add_point(&mut s, v, &Lin::konst(BigRational::one() - &a));
            let each = Lin::konst(a / BigInt::from(n));
            m.around[v].iter().for_each(|&h| add_point(&mut s, m.head(h), &each));
            Some(s)
        })
        .collect();
    for face in &m.faces {
        let mut s = Sym::new();
        face.iter().for_each(|&v| add_point(&mut s, v, &Lin::konst(rat(1, face.len() as i64))));
        points.push(Some(s));
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
fn sqrt3_step(m: &Local) -> Step {
    let (halfway, first) = sqrt3_once(m);
    let (mesh, second) = sqrt3_once(&halfway);
    let points = second
        .iter()
        .map(|s| {
            let mut out = Sym::new();
            for (j, w) in s.as_ref()? {
                add_sym(&mut out, first[*j].as_ref()?, &w.c);
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
fn sqrt3_children(role: Role, m: &Local, s: &Step, h: Half) -> Vec<Half> {
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

/// Catmull-Clark and Loop: vertex points, edge points, (face points), children per corner.
fn primal_step(m: &Local, w: &mut Weights) -> Step {
    let loop_ = w.scheme == Scheme::Loop;
    let one = Lin::konst(BigRational::one());
    let unit = |v: usize| Sym::from([(v, one.clone())]);
    let nv = m.vertices;
    let mut points: Vec<Option<Sym>> = Vec::new();
    // Face points (Catmull-Clark): centroids.
    let face_point: Vec<Sym> = m
        .faces
        .iter()
        .map(|f| {
            let mut s = Sym::new();
            f.iter().for_each(|&v| add_sym(&mut s, &unit(v), &rat(1, f.len() as i64)));
            s
        })
        .collect();
    // Vertex points.
    for v in 0..nv {
        let out = &m.around[v];
        let border: Vec<Half> = out.iter().copied().filter(|h| m.sides[h.0][h.1] == Side::Border).collect();
        let cut =
            out.iter().any(|h| m.sides[h.0][h.1] == Side::Cut || m.sides[m.prev(*h).0][m.prev(*h).1] == Side::Cut);
        let p = if out.is_empty() || cut {
            None
        } else if let Some(&b) = border.first() {
            // (u + 6v + w)/8 with the border neighbours: the head of the outgoing
            // border half-edge and the tail of the incoming one.
            let incoming = out.iter().map(|&h| m.prev(h)).find(|g| m.sides[g.0][g.1] == Side::Border);
            incoming.map(|g| {
                let mut s = Sym::new();
                add_sym(&mut s, &unit(m.head(b)), &rat(1, 8));
                add_sym(&mut s, &unit(m.at(g)), &rat(1, 8));
                add_sym(&mut s, &unit(v), &rat(6, 8));
                s
            })
        } else {
            let n = out.len();
            let mut s = Sym::new();
            if loop_ {
                let beta = w.loop_ring(n);
                let mut keep = one.clone();
                keep.add_scaled(&beta, &rat(-(n as i64), 1));
                add_point(&mut s, v, &keep);
                out.iter().for_each(|&h| add_point(&mut s, m.head(h), &beta));
            } else {
                // (1 − r − f) v + r · (mean neighbour) + f · (mean face point);
                // r = f = 1/n is (Q + 2R + (n − 3)v)/n.
                let (r, f) = w.catmull_clark_vertex(n);
                let mut keep = one.clone();
                keep.add_scaled(&r, &-BigRational::one());
                keep.add_scaled(&f, &-BigRational::one());
                add_point(&mut s, v, &keep);
                let each = rat(1, n as i64);
                for &h in out {
                    let mut share = Lin::default();
                    share.add_scaled(&r, &each);
                    add_point(&mut s, m.head(h), &share);
                    add_scaled_points(&mut s, &face_point[h.0], &f, &each);
                }
            }
            Some(s)
        };
        points.push(p);
    }
    // Edge points, one per edge, numbered after the vertices.
    let mut edge_of: HashMap<(usize, usize), usize> = HashMap::new();
    for (f, face) in m.faces.iter().enumerate() {
        for i in 0..face.len() {
            let h = (f, i);
            let (a, b) = (m.at(h), m.head(h));
            if edge_of.contains_key(&(a.min(b), a.max(b))) {
                continue;
            }
            let p = match (m.sides[f][i], m.twin_of(h)) {
                (Side::Inner, Some(t)) => {
                    let mut s = Sym::new();
                    if loop_ {
                        let end = Lin::param(w.param("w".into(), w.triangle.w));
                        let mut opposite = Lin::konst(rat(1, 2));
                        opposite.add_scaled(&end, &-BigRational::one());
                        add_point(&mut s, a, &end);
                        add_point(&mut s, b, &end);
                        add_point(&mut s, m.at(m.prev(h)), &opposite);
                        add_point(&mut s, m.at(m.prev(t)), &opposite);
                    } else {
                        // (1 − c)/2 (a + b) + c/2 (f + g): c = 1/2 is (a + b + f + g)/4.
                        let c = Lin::param(w.param("edge_faces".into(), "1/2"));
                        let mut end = Lin::konst(rat(1, 2));
                        end.add_scaled(&c, &rat(-1, 2));
                        add_point(&mut s, a, &end);
                        add_point(&mut s, b, &end);
                        add_scaled_points(&mut s, &face_point[f], &c, &rat(1, 2));
                        add_scaled_points(&mut s, &face_point[t.0], &c, &rat(1, 2));
                    }
                    Some(s)
                }
                (Side::Border, _) => {
                    let mut s = Sym::new();
                    add_sym(&mut s, &unit(a), &rat(1, 2));
                    add_sym(&mut s, &unit(b), &rat(1, 2));
                    Some(s)
                }
                _ => None,
            };
            edge_of.insert((a.min(b), a.max(b)), points.len());
            points.push(p);
        }
    }
    let edge = |h: Half| {
        let (a, b) = (m.at(h), m.head(h));
        edge_of[&(a.min(b), a.max(b))]
    };
    let (mut faces, mut sides, mut child, mut middle) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (f, face) in m.faces.iter().enumerate() {
        let d = face.len();
        let fp = if loop_ {
            None
        } else {
            points.push(Some(face_point[f].clone()));
            Some(points.len() - 1)
        };
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
fn doo_sabin_step(m: &Local, w: &mut Weights) -> Step {
    let mut points = Vec::new();
    let mut corner = Vec::new();
    for face in &m.faces {
        let d = face.len();
        let alpha = w.doo_sabin(d);
        corner.push(points.len());
        for i in 0..d {
            let mut s = Sym::new();
            for (k, a) in alpha.iter().enumerate() {
                add_point(&mut s, face[(i + k) % d], a);
            }
            points.push(Some(s));
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

/// The children of a cell anchored at `h`, anchored in the subdivided mesh.
fn children_of(scheme: Scheme, role: Role, m: &Local, s: &Step, h: Half) -> Vec<Half> {
    let (f, i) = h;
    match (scheme, role) {
        (Scheme::Sqrt3, _) => sqrt3_children(role, m, s, h),
        (Scheme::DooSabin, Role::Face) => m
            .fan(h)
            .into_iter()
            .enumerate()
            .map(|(k, (g, j))| {
                // The k-th face around turned back by k quarter turns: the child keeps the parent's orientation.
                let fan = s.mesh.fan((s.child[g][0], j));
                fan[(4 - k % 4) % 4 % fan.len()]
            })
            .collect(),
        (Scheme::DooSabin, Role::Edge) => {
            let (e, c) = s.edge_face.get(&h).copied().unwrap_or((usize::MAX, 0));
            // a_f → b_f in the face's face; then the edge face's side shared with the twin's face.
            vec![(s.child[f][0], i), (e, (c + 1) % 4)]
        }
        (Scheme::DooSabin, Role::Vertex) => vec![(s.child[f][0], i)],
        (_, Role::Face) => {
            // Translated copies: the child at corner i + k is anchored at its corner
            // that the translation takes the parent's anchor to; Loop's middle
            // triangle is a half-turned copy.
            let d = m.deg(f);
            let mut out: Vec<Half> = (0..d)
                .map(|k| {
                    let child = s.child[f][(i + k) % d];
                    let n = s.mesh.deg(child);
                    (child, (n - k % n) % n)
                })
                .collect();
            if scheme == Scheme::Loop {
                out.push((s.middle[f], (i + 1) % 3));
            }
            out
        }
        (_, Role::Edge) => {
            let last = s.mesh.deg(s.child[f][(i + 1) % m.deg(f)]) - 1;
            vec![(s.child[f][i], 0), (s.child[f][(i + 1) % m.deg(f)], last)]
        }
        (_, Role::Vertex) => vec![(s.child[f][i], 0)],
    }
}

/// Which cell an anchored half-edge stands for (two anchors of one cell give the same).
fn cell(scheme: Scheme, role: Role, m: &Local, h: Half) -> (usize, usize) {
    let (a, b) = (m.at(h), m.head(h));
    match (scheme, role) {
        (Scheme::DooSabin, Role::Vertex) => (h.0, usize::MAX),
        (_, Role::Vertex) => (a, usize::MAX),
        _ => (a.min(b), a.max(b)),
    }
}

/// A state of the generated automaton.
struct Kind {
    role: Role,
    local: Local,
    /// A line for the file: what the neighbourhood is.
    about: String,
}

/// The generated automaton, before it is a design.
struct Generator {
    scheme: Scheme,
    weights: Weights,
    kinds: Vec<Kind>,
    index: HashMap<(Role, Vec<u32>), usize>,
    names: Vec<String>,
    /// Subdivision arrows `(name, from, to, rows)`.
    arrows: Vec<(String, usize, usize, Vec<Vec<Lin>>)>,
    /// Boundary (and renumbering) arrows `(name, from, to, select)`.
    selects: Vec<(String, usize, usize, Vec<usize>)>,
    renumber: HashMap<(usize, usize, Vec<usize>), String>,
    incidence: Vec<String>,
    adjacency: Vec<String>,
}

impl Generator {
    fn intern(&mut self, role: Role, w: Walk) -> usize {
        if let Some(&k) = self.index.get(&(role, w.key.clone())) {
            return k;
        }
        let k = self.kinds.len();
        let count = self.kinds.iter().filter(|x| x.role == role).count();
        let name = format!("{}{count}", role.name());
        let about = describe(self.scheme, role, &w.local);
        self.index.insert((role, w.key), k);
        self.kinds.push(Kind { role, local: w.local, about });
        self.names.push(name);
        k
    }

    /// The state of the cell of `role` anchored at `h` in `m`, and its walk's order.
    fn state_at(&mut self, role: Role, m: &Local, h: Half) -> Result<(usize, Vec<usize>), MeshError> {
        let set = neighbourhood(self.scheme, role, m, h);
        let w = walk(m, &set, h).ok_or_else(|| {
            MeshError::Automaton(format!(
                "the neighbourhood of a {} is not one piece of surface (a vertex where two fans of faces touch)",
                role.name()
            ))
        })?;
        let order = w.order.clone();
        Ok((self.intern(role, w), order))
    }

    /// The renumbering arrow from the cell's state anchored at `z` to the
    /// one anchored at `y`: a path ending in the first, followed by it, gives
    /// the control points in the second's order.
    fn renumber(&mut self, role: Role, m: &Local, y: Half, z: Half) -> Result<Option<String>, MeshError> {
        if y == z {
            return Ok(None);
        }
        let (a, oa) = self.state_at(role, m, y)?;
        let (b, ob) = self.state_at(role, m, z)?;
        let select: Vec<usize> = oa
            .iter()
            .map(|v| ob.iter().position(|x| x == v))
            .collect::<Option<_>>()
            .ok_or_else(|| MeshError::Automaton("two anchors of one cell see different neighbourhoods".into()))?;
        if a == b && select.iter().enumerate().all(|(i, &j)| i == j) {
            return Ok(None);
        }
        let key = (b, a, select.clone());
        if let Some(name) = self.renumber.get(&key) {
            return Ok(Some(name.clone()));
        }
        let name = format!("turn{}", self.renumber.len());
        self.renumber.insert(key, name.clone());
        self.selects.push((name.clone(), b, a, select));
        Ok(Some(name))
    }

    /// Subdivides state `k`: its child arrows, boundary arrows and constraints.
    fn process(&mut self, k: usize) -> Result<(), MeshError> {
        let (scheme, role) = (self.scheme, self.kinds[k].role);
        let m = self.kinds[k].local.clone();
        let name = self.names[k].clone();
        let s = step(&m, &mut self.weights);
        let anchor = (0, 0);
        // Children.
        let kids = children_of(scheme, role, &m, &s, anchor);
        let mut child_states = Vec::new();
        for (c, &x) in kids.iter().enumerate() {
            if x.0 >= s.mesh.faces.len() {
                return Err(MeshError::Automaton(format!("{name}: a child is missing from its parent's subdivision")));
            }
            let (to, order) = self.state_at(role, &s.mesh, x)?;
            let mut rows = vec![vec![Lin::default(); order.len()]; m.vertices];
            for (j, &p) in order.iter().enumerate() {
                let sym = s.points[p].as_ref().ok_or_else(|| {
                    MeshError::Automaton(format!("{name}: a child's control point depends on points outside the cell"))
                })?;
                for (i, wt) in sym {
                    rows[*i][j] = wt.clone();
                }
            }
            self.arrows.push((format!("{name}_{c}"), k, to, rows));
            child_states.push(to);
        }
        // Sides.
        let sides = sides_of(scheme, role, &m, anchor);
        let side_role = role.side();
        let mut side_states = Vec::with_capacity(sides.len());
        for (j, &h) in sides.iter().enumerate() {
            let (to, order) = self.state_at(side_role, &m, h)?;
            self.selects.push((side_name(&name, role, j), k, to, order));
            side_states.push(to);
        }
        // Constraints: each side of each child lies on a side of the cell or on another child's side.
        let parent_parts: Vec<(usize, usize, Half)> = sides
            .iter()
            .enumerate()
            .flat_map(|(j, &h)| {
                children_of(scheme, side_role, &m, &s, h).into_iter().enumerate().map(move |(t, z)| (j, t, z))
            })
            .collect();
        let child_sides: Vec<(usize, usize, Half)> = kids
            .iter()
            .enumerate()
            .flat_map(|(c, &x)| sides_of(scheme, role, &s.mesh, x).into_iter().enumerate().map(move |(q, y)| (c, q, y)))
            .collect();
        for (a, &(c, q, y)) in child_sides.iter().enumerate() {
            let here = cell(scheme, side_role, &s.mesh, y);
            let lhs = format!("{name}_{c} {}", side_name(&self.names[child_states[c]], role, q));
            if let Some(&(j, t, z)) = parent_parts.iter().find(|p| cell(scheme, side_role, &s.mesh, p.2) == here) {
                let side_state = side_states[j];
                let turn = self.renumber(side_role, &s.mesh, y, z)?;
                let rhs = format!("{} {}_{t}", side_name(&name, role, j), self.names[side_state]);
                self.incidence.push(format!("{lhs} = {rhs}{}", turn.map(|t| format!(" {t}")).unwrap_or_default()));
            } else if let Some(&(d, r, z)) =
                child_sides[a + 1..].iter().find(|p| p.0 != c && cell(scheme, side_role, &s.mesh, p.2) == here)
            {
                let turn = self.renumber(side_role, &s.mesh, y, z)?;
                let rhs = format!("{name}_{d} {}", side_name(&self.names[child_states[d]], role, r));
                self.adjacency.push(format!("{lhs} = {rhs}{}", turn.map(|t| format!(" {t}")).unwrap_or_default()));
            }
        }
        Ok(())
    }
}

fn side_name(state: &str, role: Role, j: usize) -> String {
    match role {
        Role::Edge => format!("{state}_{}", if j == 0 { "start" } else { "end" }),
        _ => format!("{state}_side{j}"),
    }
}

/// One line about a neighbourhood: the centre and the valences or degrees around it.
fn describe(scheme: Scheme, role: Role, m: &Local) -> String {
    let border = m.sides.iter().flatten().filter(|s| **s == Side::Border).count();
    let on_border = if border > 0 { ", on the border" } else { "" };
    let valence = |v: usize| {
        let n = m.around[v].len();
        if m.closed_at(v) { n.to_string() } else { format!("{n}+") }
    };
    let centre = match (scheme, role) {
        (Scheme::DooSabin, Role::Face) => {
            let degs: Vec<String> = m.fan((0, 0)).iter().map(|h| m.deg(h.0).to_string()).collect();
            format!("the patch of a vertex whose faces have {} sides", degs.join(", "))
        }
        (Scheme::DooSabin, Role::Edge) => {
            format!("an edge between faces of {} and {} sides", m.deg(0), m.deg(m.faces.len() - 1))
        }
        (Scheme::DooSabin, Role::Vertex) => format!("the centroid of a face of {} sides", m.deg(0)),
        (_, Role::Face) => {
            let v: Vec<String> = m.faces[0].iter().map(|&v| valence(v)).collect();
            format!("a face of {} sides at vertices of valence {}", m.deg(0), v.join(", "))
        }
        (_, Role::Edge) => {
            format!("an edge between vertices of valence {} and {}", valence(m.at((0, 0))), valence(m.head((0, 0))))
        }
        (_, Role::Vertex) => format!("a vertex of valence {}", valence(m.at((0, 0)))),
    };
    format!("{centre}{on_border}: {} control points, {} faces", m.vertices, m.faces.len())
}

impl PolyMesh {
    /// The mesh as a BC-IFS automaton for `scheme` (see the module
    /// documentation): states for the kinds of patches, curves and points
    /// that occur, exact subdivision matrices whose entries are affine in
    /// the scheme's weights (named parameters whose defaults are the classic
    /// weights, or `weights`), the incidence and adjacency constraints, and
    /// a model whose control points are the mesh's vertices.
    ///
    /// ```
    /// use bcifs::mesh::{PolyMesh, Scheme};
    /// let design = PolyMesh::cube().automaton(Scheme::CatmullClark, None).unwrap();
    /// let family = bcifs::solve(&design).unwrap();
    /// // The constraints hold for every weight: the edge rule's and, at the
    /// // cube's valence 3 and the new vertices' 4, the vertex rule's two.
    /// assert_eq!(family.parameter_names(), ["ring3", "faces3", "edge_faces", "ring4", "faces4"]);
    /// ```
    ///
    /// # Errors
    /// √3 on an open mesh (its border rule alternates); a triangle scheme on
    /// a face that is not a triangle; a neighbourhood that is not one piece
    /// of surface.
    pub fn automaton(&self, scheme: Scheme, weights: Option<RuleWeights>) -> Result<Design, MeshError> {
        if scheme == Scheme::Sqrt3 && !self.is_closed() {
            return Err(MeshError::Automaton(
                "√3 is generated as an automaton on closed meshes only: its border rule changes from one step to the next, so a border triangle's children are not a ternary split".into(),
            ));
        }
        if scheme == Scheme::DooSabin && !self.has_interior_vertex() {
            return Err(MeshError::NoInteriorVertex);
        }
        if scheme.triangles_only()
            && let Some(f) = (0..self.face_count()).find(|&f| self.face(f).len() != 3)
        {
            return Err(MeshError::NotTriangles { scheme: scheme.name(), face: f, degree: self.face(f).len() });
        }
        let weights = Weights {
            scheme,
            names: Vec::new(),
            defaults: Vec::new(),
            quad: weights.and_then(RuleWeights::quad).unwrap_or(QuadWeights::CLASSIC),
            triangle: weights.and_then(RuleWeights::triangle).unwrap_or(LoopWeights::CLASSIC),
        };
        let mut g = Generator {
            scheme,
            weights,
            kinds: Vec::new(),
            index: HashMap::new(),
            names: Vec::new(),
            arrows: Vec::new(),
            selects: Vec::new(),
            renumber: HashMap::new(),
            incidence: Vec::new(),
            adjacency: Vec::new(),
        };
        let mesh = Local::of_mesh(self);
        // The patches: every face, or (Doo-Sabin) every interior vertex.
        let anchors: Vec<Half> = if scheme == Scheme::DooSabin {
            (0..mesh.vertices).filter(|&v| mesh.closed_at(v)).map(|v| mesh.around[v][0]).collect()
        } else {
            (0..mesh.faces.len()).map(|f| (f, 0)).collect()
        };
        let mut roots = Vec::new();
        for &h in &anchors {
            roots.push(g.state_at(Role::Face, &mesh, h)?);
        }
        let mut done = 0;
        while done < g.kinds.len() {
            g.process(done)?;
            done += 1;
        }
        g.design(self, roots)
    }
}

impl Generator {
    fn design(self, mesh: &PolyMesh, roots: Vec<(usize, Vec<usize>)>) -> Result<Design, MeshError> {
        let name = format!("mesh_{}", self.scheme.name().replace('-', "_"));
        let mut b = DesignBuilder::new(name);
        let patches = if self.scheme == Scheme::DooSabin { "interior vertex" } else { "face" };
        b.description(format!(
            "{} on a mesh of {} vertices and {} faces: {} patches, {} states",
            self.scheme.name(),
            mesh.positions.len(),
            mesh.face_count(),
            roots.len(),
            self.kinds.len()
        ));
        b.doc(format!(
            "Generated by bcifs from a mesh ({} scheme). Every state is a kind of cell: a patch of the limit surface\n\
             (face), a curve where patches meet (edge) or a point (vertex); its control points are the mesh\n\
             vertices its limit depends on, numbered by a walk of its neighbourhood from an anchor half-edge.\n\
             The model's points are the mesh's vertices; `patches` lists the control points of each patch (one per {patches}),\n\
             whose state is the same entry of `root`.",
            self.scheme.name()
        ));
        for (k, kind) in self.kinds.iter().enumerate() {
            b.state(self.names[k].clone(), kind.local.vertices, kind.role.kind());
            b.doc(kind.about.clone());
        }
        for (name, from, to, rows) in &self.arrows {
            let rows: Vec<Vec<Value>> =
                rows.iter().map(|r| r.iter().map(|l| l.value(&self.weights.names)).collect()).collect();
            b.arrow(
                name.clone(),
                self.names[*from].clone(),
                self.names[*to].clone(),
                ArrowKind::Subdivision,
                Matrix::Rows(rows),
            );
        }
        for (name, from, to, select) in &self.selects {
            b.select(name.clone(), self.names[*from].clone(), self.names[*to].clone(), select.clone());
        }
        for e in &self.adjacency {
            b.adjacency(e.clone());
        }
        for e in &self.incidence {
            b.incidence(e.clone());
        }
        for (n, d) in self.weights.names.iter().zip(&self.weights.defaults) {
            b.parameter(n.clone());
            b.default_value(n, d.clone());
        }
        let points = mesh.positions.iter().map(|p| p.to_vec()).collect();
        let (states, patches): (Vec<String>, Vec<Vec<usize>>) =
            roots.into_iter().map(|(k, order)| (self.names[k].clone(), order)).unzip();
        b.model(
            Model::new("", points)
                .with_patches(states, patches)
                .with_net(mesh.faces().map(<[usize]>::to_vec).collect())
                // The mesh file's axes: Y-up, so that rendering it writes the same file as subdividing it.
                .with_y_up(true),
        );
        b.build().map_err(|e| MeshError::Automaton(format!("the generated automaton is not well formed: {e}")))
    }
}
