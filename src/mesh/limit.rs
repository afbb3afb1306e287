//! Points of the limit surface, meshed as welded quads.
//!
//! Doo-Sabin keeps the centroid of every face (its corner rule is a
//! circulant whose columns sum to 1) while the face shrinks to a point, so
//! the centroids of the faces of the net after `k ≥ 1` steps are points of
//! the limit surface; every interior vertex of that net has four faces, and
//! their centroids make a quad (the dual mesh). Catmull-Clark's limit
//! position of a net vertex of valence `n` is
//! `(n² v + 4 Σ e_j + Σ f_j) / (n (n + 5))` (edge neighbours `e_j`, the
//! opposite corners `f_j` of its quads), `(u + 4v + w)/6` on the border (the
//! cubic B-spline of the boundary polygon); the quads are the net's.

use super::emit::Emit;
use super::error::SubdivideError;
use super::polymesh::{PolyMesh, Scheme};
use super::subdivide::RuleWeights;
use super::topology::{BORDER, Topology};
use crate::geometry::{Shape, Sink};

impl PolyMesh {
    /// Points of the limit surface of `scheme` (classic weights) at the
    /// vertices of the net after `depth` steps (at least 1), as welded quads
    /// oriented like the input.
    ///
    /// # Errors
    /// An output over [`super::polymesh::DEFAULT_MESH_MEMORY`], with the estimate.
    pub fn limit(&self, scheme: Scheme, depth: usize) -> Result<Shape, SubdivideError> {
        self.limit_with(scheme, depth, None, super::polymesh::DEFAULT_MESH_MEMORY)
    }

    /// As [`PolyMesh::limit`], with rule weights (Doo-Sabin's quad rule, Loop's) and a memory limit.
    ///
    /// # Errors
    /// An output over `memory_limit`, with the estimate.
    pub fn limit_with(
        &self,
        scheme: Scheme,
        depth: usize,
        weights: Option<RuleWeights>,
        memory_limit: usize,
    ) -> Result<Shape, SubdivideError> {
        let (points, quads) = match scheme {
            Scheme::DooSabin => {
                let dual = self.doo_sabin_limit(depth, weights, memory_limit)?;
                let quads = dual.faces().map(|f| [f[0], f[1], f[2], f[3]]).collect();
                (dual.positions, quads)
            }
            Scheme::CatmullClark => {
                let (net, t) = self.net_and_topology(scheme, depth.max(1), weights, memory_limit)?;
                catmull_clark_limit(&net, &t)
            }
            Scheme::Loop | Scheme::Sqrt3 => {
                let (net, t) = self.net_and_topology(scheme, depth.max(1), weights, memory_limit)?;
                let points =
                    net.triangle_limit_points(&t, scheme == Scheme::Sqrt3, weights.and_then(RuleWeights::triangle));
                let mut shape = Shape::default();
                let flat: Vec<f64> = points.iter().flatten().copied().collect();
                let triangles: Vec<[usize; 3]> = net.faces().map(|f| [f[0], f[1], f[2]]).collect();
                // Writing into memory cannot fail.
                let _ = shape.object(scheme.name());
                let _ = shape.vertices(3, &flat, None);
                let _ = shape.triangles(&triangles);
                return Ok(shape);
            }
        };
        let mut shape = Shape::default();
        // Writing into memory cannot fail.
        let _ = shape.object(scheme.name());
        let flat: Vec<f64> = points.iter().flatten().copied().collect();
        let _ = shape.vertices(3, &flat, None);
        let _ = shape.faces(&quads, None);
        Ok(shape)
    }
}

impl PolyMesh {
    /// Doo-Sabin's limit surface after `depth` steps as a mesh: the limit
    /// points of the dual of the net before the last step, and its quads.
    ///
    /// # Errors
    /// That net over `memory_limit`, or a mesh without interior vertex.
    pub(crate) fn doo_sabin_limit(
        &self,
        depth: usize,
        weights: Option<RuleWeights>,
        memory_limit: usize,
    ) -> Result<PolyMesh, SubdivideError> {
        if !self.has_interior_vertex() {
            return Err(SubdivideError::NoInteriorVertex);
        }
        let (net, t) = self.net_and_topology(Scheme::DooSabin, depth.max(1) - 1, weights, memory_limit)?;
        let mut out = Emit::memory(net.face_count() * 3, 4 * net.corner_count());
        // Writing into memory fails only when cancelled.
        net.limit_step_into(&t, Scheme::DooSabin, weights, &mut out).map_err(SubdivideError::Write)?;
        Ok(out.finish())
    }

    /// The limit surface of Doo-Sabin, Catmull-Clark or Loop after one more
    /// step of this net (its points and faces, numbered as that step numbers
    /// them) into `out`, the next net named but not made. √3 has none: its
    /// limit points are a mask on the last net ([`PolyMesh::triangle_limit_into`]).
    ///
    /// # Errors
    /// `out`'s error; √3.
    pub(crate) fn limit_step_into(
        &self,
        t: &Topology,
        scheme: Scheme,
        weights: Option<RuleWeights>,
        out: &mut Emit<'_>,
    ) -> std::io::Result<()> {
        match scheme {
            Scheme::DooSabin => self.doo_sabin_limit_into(t, weights.and_then(RuleWeights::quad), out),
            Scheme::CatmullClark => self.catmull_clark_limit_into(t, out),
            Scheme::Loop => self.loop_limit_into(t, weights.and_then(RuleWeights::triangle), out),
            Scheme::Sqrt3 => Err(std::io::Error::other("√3's limit is taken on the last net, not after one more step")),
        }
    }
}

fn catmull_clark_limit(net: &PolyMesh, t: &Topology) -> (Vec<[f64; 3]>, Vec<[usize; 4]>) {
    let p = |c: usize| net.positions[net.indices[c]];
    let mut points = Vec::with_capacity(net.positions.len());
    for v in 0..net.positions.len() {
        let x = net.positions[v];
        let c0 = t.first(v);
        if c0 == BORDER {
            points.push(x);
            continue;
        }
        let mut out = [0.0; 3];
        if t.on_border(v) {
            let (u, w) = t.border_neighbours(net, c0);
            let (u, w) = (net.positions[u], net.positions[w]);
            (0..3).for_each(|a| out[a] = (u[a] + 4.0 * x[a] + w[a]) / 6.0);
        } else {
            let (mut e, mut f, mut n) = ([0.0; 3], [0.0; 3], 0usize);
            let mut c = c0;
            loop {
                let (en, fn_) = (p(t.next(net, c)), p(t.next(net, t.next(net, c))));
                (0..3).for_each(|a| {
                    e[a] += en[a];
                    f[a] += fn_[a];
                });
                n += 1;
                c = t.rotate(net, c);
                if c == c0 {
                    break;
                }
            }
            let nf = n as f64;
            (0..3).for_each(|a| out[a] = (nf * nf * x[a] + 4.0 * e[a] + f[a]) / (nf * (nf + 5.0)));
        }
        points.push(out);
    }
    let quads = net.faces().map(|f| [f[0], f[1], f[2], f[3]]).collect();
    (points, quads)
}

/// The net after one more step, named from this net without being made:
/// its corners' next, previous and twin corners and their vertices'
/// positions, as [`Topology::trusted`] and the step would find them on the
/// made net, so walks over it visit corners in the same order and limit
/// masks on it give the made net's numbers bit for bit.
pub(crate) trait NextMesh {
    /// The corner after `x` in its face.
    fn next(&self, x: usize) -> usize;
    /// The corner before `x` in its face.
    fn prev(&self, x: usize) -> usize;
    /// The twin of half-edge `x`, or [`BORDER`].
    fn twin(&self, x: usize) -> usize;
    /// The position of the vertex of corner `x`.
    fn position(&self, x: usize) -> [f64; 3];

    /// The next outgoing corner around the vertex of `x`, or [`BORDER`].
    fn rotate(&self, x: usize) -> usize {
        self.twin(self.prev(x))
    }

    /// The positions of the border neighbours `(u, w)` of the border vertex
    /// whose first corner is `c0` ([`Topology::border_neighbours`]).
    fn border_neighbours(&self, c0: usize) -> ([f64; 3], [f64; 3]) {
        let w = self.position(self.next(c0));
        let mut last = c0;
        while self.rotate(last) != BORDER {
            last = self.rotate(last);
        }
        (self.position(self.prev(last)), w)
    }

    /// The outgoing corners around the interior vertex whose first corner is `c0`, in order.
    fn fan(&self, c0: usize) -> Vec<usize> {
        let mut corners = vec![c0];
        let mut c = self.rotate(c0);
        while c != BORDER && c != c0 {
            corners.push(c);
            c = self.rotate(c);
        }
        corners
    }
}

/// The net after one more Catmull-Clark step: the quad of corner `k` is
/// `[v'(k), e'(k), F'(face k), e'(prev k)]`, its corners `4k .. 4k + 3`, as
/// [`PolyMesh::catmull_clark_into`] makes them.
///
/// The centroids of large faces and the vertex points of vertices of large
/// valence are made once: each is asked by every neighbour of a point, and
/// a face of 100,000 corners made that quadratic.
struct NextNet<'a> {
    net: &'a PolyMesh,
    t: &'a Topology,
    centroids: std::collections::HashMap<usize, [f64; 3]>,
    vertex_points: std::collections::HashMap<usize, [f64; 3]>,
}

/// Faces and valences above this many corners have their points made once.
const LARGE: usize = 16;

impl<'a> NextNet<'a> {
    fn new(net: &'a PolyMesh, t: &'a Topology) -> NextNet<'a> {
        let centroids: std::collections::HashMap<usize, [f64; 3]> =
            (0..net.face_count()).filter(|&f| net.face(f).len() > LARGE).map(|f| (f, net.centroid(f))).collect();
        let mut valence = vec![0u32; net.positions.len()];
        for &v in &net.indices {
            valence[v] += 1;
        }
        let mut next = NextNet { net, t, centroids, vertex_points: std::collections::HashMap::new() };
        let vertex_points = (0..valence.len())
            .filter(|&v| valence[v] as usize > LARGE)
            .map(|v| (v, net.cc_vertex_point(t, v, |f| next.centroid(f))))
            .collect();
        next.vertex_points = vertex_points;
        next
    }

    /// The centroid of face `f` of this net.
    fn centroid(&self, f: usize) -> [f64; 3] {
        self.centroids.get(&f).copied().unwrap_or_else(|| self.net.centroid(f))
    }
}

impl NextMesh for NextNet<'_> {
    fn next(&self, x: usize) -> usize {
        x - x % 4 + (x + 1) % 4
    }

    fn prev(&self, x: usize) -> usize {
        x - x % 4 + (x + 3) % 4
    }

    fn twin(&self, x: usize) -> usize {
        let (net, t, k) = (self.net, self.t, x / 4);
        match (x % 4, t.twin(k)) {
            (0, BORDER) => BORDER,
            (0, tw) => 4 * t.next(net, tw) + 3,
            (1, _) => 4 * t.next(net, k) + 2,
            (2, _) => 4 * t.prev(net, k) + 1,
            _ => match t.twin(t.prev(net, k)) {
                BORDER => BORDER,
                tp => 4 * tp,
            },
        }
    }

    fn position(&self, x: usize) -> [f64; 3] {
        let (net, t, k) = (self.net, self.t, x / 4);
        match x % 4 {
            0 => {
                let v = net.indices[k];
                match self.vertex_points.get(&v) {
                    Some(p) => *p,
                    None => net.cc_vertex_point(t, v, |f| self.centroid(f)),
                }
            }
            1 => self.edge(k),
            2 => self.centroid(t.face(k)),
            _ => self.edge(t.prev(net, k)),
        }
    }
}

impl NextNet<'_> {
    /// The edge point of the edge of half-edge `k`.
    fn edge(&self, k: usize) -> [f64; 3] {
        let (net, t) = (self.net, self.t);
        match t.twin(k) {
            BORDER => net.border_midpoint(t, k),
            tw => net.cc_edge_point(t, k.min(tw), k.max(tw), |f| self.centroid(f)),
        }
    }

    /// The limit point of the vertex whose first corner is `c0` (`on_border`:
    /// a border vertex), as `catmull_clark_limit` computes it on the made net.
    fn limit(&self, c0: usize, on_border: bool) -> [f64; 3] {
        let x = self.position(c0);
        let mut out = [0.0; 3];
        if on_border {
            let (u, w) = self.border_neighbours(c0);
            (0..3).for_each(|a| out[a] = (u[a] + 4.0 * x[a] + w[a]) / 6.0);
            return out;
        }
        let (mut e, mut f) = ([0.0; 3], [0.0; 3]);
        let fan = self.fan(c0);
        for &c in &fan {
            let (en, fn_) = (self.position(self.next(c)), self.position(self.next(self.next(c))));
            (0..3).for_each(|a| {
                e[a] += en[a];
                f[a] += fn_[a];
            });
        }
        let nf = fan.len() as f64;
        (0..3).for_each(|a| out[a] = (nf * nf * x[a] + 4.0 * e[a] + f[a]) / (nf * (nf + 5.0)));
        out
    }
}

impl PolyMesh {
    /// Catmull-Clark's limit after one more step, straight from this net:
    /// the limit points of the next net's vertices (vertex, edge and face
    /// points, numbered as [`PolyMesh::catmull_clark_into`] numbers them) and
    /// its quads, the same numbers as [`PolyMesh::limit_with`] computes on
    /// the made net, without making it: memory of this net only.
    pub(crate) fn catmull_clark_limit_into(&self, t: &Topology, out: &mut Emit<'_>) -> std::io::Result<()> {
        let next = NextNet::new(self, t);
        out.vertices_with(self.positions.len(), |v| match t.first(v) {
            BORDER => self.positions[v], // unused by any face: kept as is
            c0 => next.limit(4 * c0, t.on_border(v)),
        })?;
        let (edge_of, edges) = self.edge_numbering(t, out, |c, tw| {
            let nc = t.next(self, c);
            match tw {
                None => next.limit(4 * nc + 3, true),
                Some(tw) => {
                    let first = [4 * c + 1, 4 * nc + 3, 4 * tw + 1, 4 * t.next(self, tw) + 3];
                    next.limit(first.into_iter().min().unwrap_or(4 * c + 1), false)
                }
            }
        })?;
        out.vertices_with(self.face_count(), |f| next.limit(4 * self.starts[f] + 2, false))?;
        let nv = self.positions.len();
        self.cc_quads(t, (nv, nv + edges), &edge_of, out)
    }
}
