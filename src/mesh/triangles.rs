//! Triangle schemes, as CGAL's `Subdivision_method_3` makes them.
//!
//! Loop (`Loop_mask_3`, `PTQ_1step`): edge points `3/8 (a + b) + 1/8 (c + d)`,
//! vertex points `(1 − nβ) v + β Σ p_i` with
//! `β = (5/8 − (3/8 + cos(2π/n)/4)²)/n` (`(10 v + Σ p_i)/16` at valence 6);
//! on the border, midpoints and `(u + 6v + w)/8`, so the boundary is the
//! cubic B-spline of the boundary polygon; each triangle becomes four.
//! √3 (Kobbelt; `Sqrt3_mask_3`, `Sqrt3_1step`): a centroid per face, vertex
//! points `(1 − a) v + a/n Σ p_i` with `a = (4 − 2cos(2π/n))/9`, and every
//! interior edge flipped to join the centroids of its two faces. Border rule
//! (Kobbelt's, as CGAL does it): on odd steps the border stays; on even
//! steps each border edge is split in three (`(16a + 10b + a')/27`,
//! `(10a + 16b + b')/27`) and border vertices move to `(4u + 19v + 4w)/27`,
//! so two steps make a ternary refinement of the boundary polygon.

use std::f64::consts::PI;
use std::io;

use super::emit::Emit;
use super::limit::NextMesh;
use super::named::{LoopChild, Sqrt3Child, loop_child_twin, loop_corner};
use super::polymesh::PolyMesh;
use super::rules::{self, LoopEdge, LoopVertex};
use super::subdivide::{
    LoopWeights, add, border_curve_point, border_midpoint, border_mix, edge_points_into, sqrt3_alpha,
    sqrt3_border_points, sqrt3_vertex, with_ring,
};
use super::topology::{BORDER, Made, Net, Topology, ring, triangle_next, triangle_prev};

/// Loop's vertex weight `β` at valence `n`.
pub fn loop_beta(n: usize) -> f64 {
    let c = 3.0 + 2.0 * (2.0 * PI / n as f64).cos();
    (5.0 / 8.0 - c * c / 64.0) / n as f64
}

/// Loop's interior vertex point of `p` of valence `n` whose neighbours sum to `r`.
fn loop_vertex(p: [f64; 3], r: [f64; 3], n: usize, custom: Option<LoopWeights>) -> [f64; 3] {
    let weights = if let Some(l) = custom {
        let ring = l.ring(n);
        LoopVertex { keep: 1.0 - ring, each: ring / n as f64 }
    } else if n == 6 {
        LoopVertex { keep: 10.0 / 16.0, each: 1.0 / 16.0 }
    } else {
        // CGAL's arithmetic: (Sw v + R) / W with Cn = nβ, Sw = n(1 − Cn)/Cn, W = n/Cn.
        let cn = loop_beta(n) * n as f64;
        let (sw, w) = (n as f64 * (1.0 - cn) / cn, n as f64 / cn);
        LoopVertex { keep: sw / w, each: 1.0 / w }
    };
    rules::loop_vertex(&p, &r, &weights)
}

/// Loop's interior edge point of the edge `[a, b]` with the opposite vertices `[c, d]`: `[a, b, c, d]`.
fn loop_edge([a, b, c, d]: [[f64; 3]; 4], custom: Option<LoopWeights>) -> [f64; 3] {
    let (end, opposite) = custom.map_or((3.0 / 8.0, 1.0 / 8.0), |l| (l.w, 0.5 - l.w));
    rules::loop_edge(&a, &b, &c, &d, &LoopEdge { end, opposite })
}

/// Loop's new point of vertex `v` of `net` (`custom`: weights other than Loop's).
pub(crate) fn loop_vertex_point<N: Net>(net: &N, v: usize, custom: Option<LoopWeights>) -> [f64; 3] {
    let p = net.point(v);
    let c0 = net.first(v);
    if c0 == BORDER {
        p
    } else if net.on_border(v) {
        border_curve_point(net, c0)
    } else {
        let mut n = 0usize;
        let r = rules::sum(ring(net, c0).map(|u| {
            n += 1;
            net.point(u)
        }));
        loop_vertex(p, r, n, custom)
    }
}

/// The points of one Loop step of `net` into `out`: its vertices' new
/// points, then a point per edge in corner order (the smaller corner of an
/// interior edge; [`edge_points_into`]), the numbering of [`PolyMesh::edge_numbers`].
fn loop_points_of<N: Net>(net: &N, weights: Option<LoopWeights>, out: &mut Emit<'_>) -> io::Result<()> {
    let custom = weights.filter(|w| *w != LoopWeights::CLASSIC);
    out.vertices_with(net.vertex_count(), |v| loop_vertex_point(net, v, custom))?;
    edge_points_into(
        net.corner_count(),
        |c| net.twin(c),
        |c, tw| match tw {
            None => border_midpoint(net, c),
            Some(tw) => loop_edge_point(net, c, tw, custom),
        },
        out,
    )
}

/// Loop's point of the interior edge of the corners `c < tw` of `net`.
pub(crate) fn loop_edge_point<N: Net>(net: &N, c: usize, tw: usize, custom: Option<LoopWeights>) -> [f64; 3] {
    let p = |c: usize| net.point(net.vertex(c));
    loop_edge([p(c), p(tw), p(net.prev(c)), p(net.prev(tw))], custom)
}

/// The limit point of vertex `v` of a Loop (`sqrt3` false) or √3 net (see
/// [`PolyMesh::triangle_limit_points`]).
pub(crate) fn triangle_limit_point<N: Net>(net: &N, v: usize, sqrt3: bool, weights: Option<LoopWeights>) -> [f64; 3] {
    let p = net.point(v);
    let c0 = net.first(v);
    if c0 == BORDER {
        return p;
    }
    if net.on_border(v) {
        return border_mix(net, c0, 1.0 / 6.0, 4.0 / 6.0);
    }
    let mut out = [0.0; 3];
    let (q, n) = with_ring(net, c0, |ring| {
        let mut q = [0.0; 3];
        ring.iter().for_each(|&u| add(&mut q, net.point(u), 1.0 / ring.len() as f64));
        (q, ring.len())
    });
    let s = match weights.filter(|w| !sqrt3 && *w != LoopWeights::CLASSIC) {
        Some(l) => l.ring(n) / l.w,
        None if sqrt3 => 3.0 * sqrt3_alpha(n),
        None => 8.0 * n as f64 * loop_beta(n) / 3.0,
    };
    add(&mut out, p, 1.0 / (1.0 + s));
    add(&mut out, q, s / (1.0 + s));
    out
}

impl PolyMesh {
    /// One Loop step into `out`: vertex points, edge points (in corner
    /// order), four triangles per triangle.
    /// With weights other than Loop's, the general rules of [`LoopWeights`].
    pub(crate) fn loop_into(&self, t: &Topology, weights: Option<LoopWeights>, out: &mut Emit<'_>) -> io::Result<()> {
        let (edge_of, _) = self.loop_points_into(t, weights, out)?;
        let nv = self.positions.len();
        loop_faces(self.face_count(), |c| self.indices[c], |c| nv + edge_of[c] as usize, out)
    }

    /// The points of one Loop step into `out`: vertex points, then edge
    /// points in corner order. Returns each corner's edge number and the
    /// number of edges.
    pub(crate) fn loop_points_into(
        &self,
        t: &Topology,
        weights: Option<LoopWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<(Vec<u32>, usize)> {
        loop_points_of(&Made { mesh: self, t }, weights, out)?;
        Ok(self.edge_numbers(t))
    }

    /// Two Loop steps into `out` without the net between them, which would
    /// take four times this net's memory: that net is named from this one
    /// ([`LoopChild`]: its points made, its corners read off this net's), and
    /// the second step runs on it with the rules of a made net, so the
    /// output is two steps in memory, vertex for vertex and bit for bit.
    pub(crate) fn loop_twice_into(
        &self,
        t: &Topology,
        weights: Option<LoopWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        let net = LoopChild::new(self, t, weights);
        loop_points_of(&net, weights, out)?;
        let nv = net.vertex_count();
        loop_faces(net.corner_count() / 3, |c| net.vertex(c), |c| nv + net.edge(c), out)
    }

    /// One √3 step into `out`: vertex points, a centroid per face, and every
    /// interior edge flipped to join the points of its two faces. With
    /// `refine_border` (CGAL's even steps), a face on the border gets two
    /// points on its border edge instead of a centroid, `(16a + 10b + a')/27`
    /// and `(10a + 16b + b')/27`, and border vertices move to
    /// `(4u + 19v + 4w)/27`; otherwise border vertices and edges stay.
    #[allow(clippy::needless_range_loop)] // a face indexes the mesh and the new numbering
    pub(crate) fn sqrt3_into(&self, t: &Topology, refine_border: bool, out: &mut Emit<'_>) -> io::Result<()> {
        let (nv, nf) = (self.positions.len(), self.face_count());
        for v in 0..nv {
            out.vertex(sqrt3_vertex(&Made { mesh: self, t }, refine_border, v))?;
        }
        // Per face: its border corner when it is split, and the number of its first new point.
        let mut split = vec![BORDER; nf];
        let mut first = vec![0u32; nf];
        let mut next_point = nv;
        for f in 0..nf {
            first[f] = next_point as u32;
            let s = self.starts[f];
            if let Some(cb) = (s..s + 3).find(|&c| refine_border && t.twin(c) == BORDER) {
                split[f] = cb;
                let [x1, x2] = sqrt3_border_points(&Made { mesh: self, t }, cb);
                out.vertex(x1)?;
                out.vertex(x2)?;
                next_point += 2;
            } else {
                out.vertex(self.centroid(f))?;
                next_point += 1;
            }
        }
        // The point across from half-edge c in its face: the centroid, or on a split face
        // the border point beside c's end (X2 for the edge after the border one, X1 before).
        let opposite = |c: usize| {
            let f = t.face(c);
            let cb = split[f];
            if cb == BORDER {
                first[f] as usize
            } else if c == t.next(self, cb) {
                first[f] as usize + 1
            } else {
                first[f] as usize
            }
        };
        for c in 0..self.corner_count() {
            let tw = t.twin(c);
            let (a, b) = (self.indices[c], self.indices[t.next(self, c)]);
            if tw == BORDER {
                let f = t.face(c);
                if split[f] == BORDER {
                    out.face([a, b, opposite(c)])?;
                } else {
                    let w = self.indices[t.prev(self, c)];
                    out.face([first[f] as usize, first[f] as usize + 1, w])?;
                }
            } else if c < tw {
                let (cf, cg) = (opposite(c), opposite(tw));
                out.face([cg, b, cf])?;
                out.face([cf, a, cg])?;
            }
        }
        Ok(())
    }

    /// Limit positions of the vertices of a Loop (`sqrt3` false) or √3 net:
    /// `(3v + 8nβ q)/(3 + 8nβ)` for Loop and `(v + 3a q)/(1 + 3a)` for √3
    /// (`q` the average of the ring: the left eigenvector of the step on
    /// `(v, q)`), `(u + 4v + w)/6` on the border (both borders are cubic
    /// B-splines: Loop's binary, √3's ternary every two steps). A √3
    /// interior vertex next to the border is approximate: the border's
    /// splitting steps change its ring.
    /// With Loop weights `(w, σ)`, the 2×2 step on `(v, ring average)` is
    /// `[[1 − s, s], [w, 1 − w]]` (`s = nβ(n)`), whose left fixed vector
    /// gives `(w v + s Q)/(w + s)`.
    pub(crate) fn triangle_limit_points(
        &self,
        t: &Topology,
        sqrt3: bool,
        weights: Option<LoopWeights>,
    ) -> Vec<[f64; 3]> {
        let net = Made { mesh: self, t };
        (0..self.positions.len()).map(|v| triangle_limit_point(&net, v, sqrt3, weights)).collect()
    }

    /// The limit points of this (last) net's vertices, then its triangles,
    /// into `out` as they are computed: no copy of the net is made.
    pub(crate) fn triangle_limit_into(
        &self,
        t: &Topology,
        sqrt3: bool,
        weights: Option<LoopWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        for v in 0..self.positions.len() {
            out.vertex(triangle_limit_point(&Made { mesh: self, t }, v, sqrt3, weights))?;
        }
        self.faces().try_for_each(|f| out.face(f.iter().copied()))
    }

    /// √3's net after two more steps of this net (step numbers `step` and
    /// `step + 1`, from 0), or with `limit` its limit points, the same points
    /// and triangles in the same order as [`PolyMesh::sqrt3_into`] on the net
    /// before (or [`PolyMesh::triangle_limit_into`] on that net), with the
    /// two nets between named ([`Sqrt3Child`]) instead of made. `false`, and
    /// nothing written, when a face of a border-splitting step has two
    /// border edges.
    pub(crate) fn sqrt3_twice_into(
        &self,
        t: &Topology,
        step: usize,
        limit: bool,
        out: &mut Emit<'_>,
    ) -> io::Result<bool> {
        let net = Made { mesh: self, t };
        let Some(once) = Sqrt3Child::new(&net, !step.is_multiple_of(2), true) else { return Ok(false) };
        let Some(twice) = Sqrt3Child::new(&once, step.is_multiple_of(2), false) else { return Ok(false) };
        out.vertices_with(twice.vertex_count(), |v| match limit {
            true => triangle_limit_point(&twice, v, true, None),
            false => twice.point(v),
        })?;
        for x in (0..twice.corner_count()).step_by(3).filter(|&x| twice.is_corner(x)) {
            out.face([x, x + 1, x + 2].map(|x| twice.vertex(x)))?;
        }
        Ok(true)
    }

    /// The mesh with every face of more than three vertices split into a fan
    /// of triangles. The fan's apex is the first corner (of the first few
    /// tried) whose diagonals are neither edges of the mesh nor diagonals
    /// of another face: two faces that share two vertices not joined by an
    /// edge (beside a vertex of valence 2) would otherwise both draw that
    /// diagonal, an edge in four triangles.
    pub fn triangulated(&self) -> PolyMesh {
        /// Apexes tried per face: a face of n corners costs O(n) whatever n.
        const TRIES: usize = 8;
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        let mut edges: std::collections::HashSet<(usize, usize)> = std::collections::HashSet::new();
        for f in self.faces() {
            edges.extend((0..f.len()).map(|i| key(f[i], f[(i + 1) % f.len()])));
        }
        let mut starts = vec![0];
        let mut indices = Vec::with_capacity(3 * self.corner_count());
        let mut apexes = Vec::with_capacity(self.face_count());
        for f in self.faces() {
            let n = f.len();
            let diagonals = |r: usize| (2..n - 1).map(move |i| key(f[r], f[(r + i) % n]));
            let apex = (0..n.min(TRIES)).find(|&r| diagonals(r).all(|d| !edges.contains(&d))).unwrap_or(0);
            edges.extend(diagonals(apex));
            for t in crate::geometry::fan(f, apex) {
                indices.extend(t);
                starts.push(indices.len());
            }
            apexes.push(apex);
        }
        // The texture mesh split alike, corner for corner.
        let texture = self.texture.as_deref().map(|uv| {
            let mut corners = Vec::with_capacity(indices.len());
            for (f, &apex) in uv.faces().zip(&apexes) {
                corners.extend(crate::geometry::fan(f, apex).flatten());
            }
            Box::new(PolyMesh::from_flat(uv.positions.clone(), starts.clone(), corners))
        });
        // A group starts at the first triangle of its first face.
        let first: Vec<usize> = std::iter::once(0)
            .chain(self.faces().scan(0, |n, f| {
                *n += f.len().saturating_sub(2);
                Some(*n)
            }))
            .collect();
        let groups = self.groups.iter().map(|(g, at)| (g.clone(), first[(*at).min(first.len() - 1)])).collect();
        PolyMesh {
            texture,
            groups,
            name: self.name.clone(),
            ..PolyMesh::from_flat(self.positions.clone(), starts, indices)
        }
    }
}
/// The net after one more Loop step of a triangle net, named from it
/// without being made: face `f`'s children are `[v0, e0, e2]`, `[v1, e1, e0]`,
/// `[v2, e2, e1]`, `[e0, e1, e2]`, their corners `12f .. 12f + 11`, as
/// [`PolyMesh::loop_into`] makes them ([`loop_corner`]).
///
/// The vertex points of vertices of high valence are made once: each is
/// asked by every neighbour (a fan of 100,000 triangles made that quadratic).
struct NextLoop<'a, N> {
    net: &'a N,
    custom: Option<LoopWeights>,
    vertex_points: std::collections::HashMap<usize, [f64; 3]>,
}

/// Valences above this have their vertex points made once.
const LARGE_VALENCE: u32 = 16;

impl<'a, N: Net> NextLoop<'a, N> {
    fn new(net: &'a N, custom: Option<LoopWeights>) -> NextLoop<'a, N> {
        let mut valence = vec![0u32; net.vertex_count()];
        for c in 0..net.corner_count() {
            valence[net.vertex(c)] += 1;
        }
        let vertex_points = (0..valence.len())
            .filter(|&v| valence[v] > LARGE_VALENCE)
            .map(|v| (v, loop_vertex_point(net, v, custom)))
            .collect();
        NextLoop { net, custom, vertex_points }
    }
}

impl<N: Net> NextMesh for NextLoop<'_, N> {
    fn next(&self, x: usize) -> usize {
        triangle_next(x)
    }

    fn prev(&self, x: usize) -> usize {
        triangle_prev(x)
    }

    fn twin(&self, x: usize) -> usize {
        loop_child_twin(|c| self.net.twin(c), x)
    }

    fn position(&self, x: usize) -> [f64; 3] {
        let (f, i, j) = (x / 12, x % 12 / 3, x % 3);
        match (i, j) {
            (3, j) => self.edge(3 * f + j),
            (i, 0) => {
                let v = self.net.vertex(3 * f + i);
                self.vertex_points.get(&v).copied().unwrap_or_else(|| loop_vertex_point(self.net, v, self.custom))
            }
            (i, 1) => self.edge(3 * f + i),
            (i, _) => self.edge(3 * f + (i + 2) % 3),
        }
    }
}

impl<N: Net> NextLoop<'_, N> {
    /// The edge point of the edge of half-edge `k`.
    fn edge(&self, k: usize) -> [f64; 3] {
        match self.net.twin(k) {
            BORDER => border_midpoint(self.net, k),
            tw => loop_edge_point(self.net, k.min(tw), k.max(tw), self.custom),
        }
    }

    /// The limit point of the fine vertex whose first corner is `c0`, as
    /// [`PolyMesh::triangle_limit_points`] computes it on the made net.
    fn limit(&self, c0: usize, on_border: bool, weights: Option<LoopWeights>) -> [f64; 3] {
        let p = self.position(c0);
        let mut out = [0.0; 3];
        if on_border {
            let (u, w) = self.border_neighbours(c0);
            add(&mut out, u, 1.0 / 6.0);
            add(&mut out, p, 4.0 / 6.0);
            add(&mut out, w, 1.0 / 6.0);
            return out;
        }
        let ring = self.fan(c0);
        let n = ring.len();
        let mut q = [0.0; 3];
        ring.iter().for_each(|&c| add(&mut q, self.position(self.next(c)), 1.0 / n as f64));
        let s = match weights.filter(|w| *w != LoopWeights::CLASSIC) {
            Some(l) => l.ring(n) / l.w,
            None => 8.0 * n as f64 * loop_beta(n) / 3.0,
        };
        add(&mut out, p, 1.0 / (1.0 + s));
        add(&mut out, q, s / (1.0 + s));
        out
    }

    /// The limit point of the next net's vertex point of `v`.
    fn vertex_limit(&self, v: usize, weights: Option<LoopWeights>) -> [f64; 3] {
        match self.net.first(v) {
            BORDER => self.net.point(v), // unused by any face: kept as is
            c0 => self.limit(loop_corner(c0, c0 % 3, 0), self.net.on_border(v), weights),
        }
    }

    /// The limit point of the next net's edge point of the edge of corner
    /// `c` (its twin `tw`, `None` on the border), from the first of its
    /// corners there.
    fn edge_limit(&self, c: usize, tw: Option<usize>, weights: Option<LoopWeights>) -> [f64; 3] {
        let (i, second_half) = (c % 3, loop_corner(c, (c % 3 + 1) % 3, 2));
        match tw {
            None => self.limit(second_half, true, weights),
            Some(tw) => {
                let i2 = tw % 3;
                let corners = [
                    loop_corner(c, i, 1),
                    second_half,
                    loop_corner(c, 3, i),
                    loop_corner(tw, i2, 1),
                    loop_corner(tw, (i2 + 1) % 3, 2),
                    loop_corner(tw, 3, i2),
                ];
                self.limit(corners.into_iter().min().unwrap_or(second_half), false, weights)
            }
        }
    }
}

impl PolyMesh {
    /// Loop's limit after one more step, straight from this triangle net:
    /// the limit points of the next net's vertices (vertex points, then edge
    /// points in edge order, as [`PolyMesh::loop_into`] numbers them) and its
    /// triangles, the same numbers as [`PolyMesh::limit_with`] computes on the
    /// made net, without making it: memory of this net only.
    pub(crate) fn loop_limit_into(
        &self,
        t: &Topology,
        weights: Option<LoopWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        let (edge_of, _) = self.edge_numbers(t);
        loop_limit_of(&Made { mesh: self, t }, weights, |c| edge_of[c] as usize, out)
    }

    /// Loop's limit after two more steps of this triangle net, the same
    /// points and triangles in the same order as [`PolyMesh::loop_limit_into`]
    /// on the net after one step, with that net named ([`LoopChild`]) instead
    /// of made: a quarter of its memory.
    pub(crate) fn loop_limit_twice_into(
        &self,
        t: &Topology,
        weights: Option<LoopWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        let net = LoopChild::new(self, t, weights);
        loop_limit_of(&net, weights, |c| net.edge(c), out)
    }
}

/// Loop's limit after one more step of `net` (its corners' edge numbers
/// `edge`): the limit points of the next net's vertex points, then of its
/// edge points in edge order, then its triangles, as [`PolyMesh::loop_into`]
/// numbers and makes them.
fn loop_limit_of<N: Net>(
    net: &N,
    weights: Option<LoopWeights>,
    edge: impl Fn(usize) -> usize,
    out: &mut Emit<'_>,
) -> io::Result<()> {
    let next = NextLoop::new(net, weights.filter(|w| *w != LoopWeights::CLASSIC));
    out.vertices_with(net.vertex_count(), |v| next.vertex_limit(v, weights))?;
    edge_points_into(net.corner_count(), |c| net.twin(c), |c, tw| next.edge_limit(c, tw, weights), out)?;
    let nv = net.vertex_count();
    loop_faces(net.corner_count() / 3, |c| net.vertex(c), |c| nv + edge(c), out)
}

/// Loop's four triangles per triangle of a net of `faces` triangles
/// (corner `c` of vertex `vertex(c)`), the edge points numbered `edge(c)`.
fn loop_faces(
    faces: usize,
    vertex: impl Fn(usize) -> usize,
    edge: impl Fn(usize) -> usize,
    out: &mut Emit<'_>,
) -> io::Result<()> {
    for f in 0..faces {
        let s = 3 * f;
        let (v, e) = ([0, 1, 2].map(|i| vertex(s + i)), [0, 1, 2].map(|i| edge(s + i)));
        // Corners a, b, c with edges e0 = ab, e1 = bc, e2 = ca.
        out.face([v[0], e[0], e[2]])?;
        out.face([v[1], e[1], e[0]])?;
        out.face([v[2], e[2], e[1]])?;
        out.face([e[0], e[1], e[2]])?;
    }
    Ok(())
}
