//! One step of Doo-Sabin or Catmull-Clark on a checked mesh, as CGAL's
//! `Subdivision_method_3` does it (same points, same faces with the same
//! orientation, up to numbering), and `k` steps with the memory check.
//!
//! Doo-Sabin (CGAL's `DooSabin_mask_3` and `DQQ_1step`): corner `i` of an
//! `n`-gon gets `Σ_k α_k v_{i+k}`, `α_0 = 1/4 + 5/(4n)`, `α_k = (3 + 2cos(2πk/n))/(4n)`
//! (on quads, optionally any weights `(α, β, γ, δ)` for the corner, the
//! next, the previous and the opposite one); the new faces are one per face,
//! one per interior edge (a quad) and one per interior vertex. Catmull-Clark
//! (`CatmullClark_mask_3`, `PQQ_1step`): face points are centroids, edge
//! points `(a + b + f + g)/4`, vertex points `(Q + 2R + (n − 3)v)/n`; on the
//! border, edge points are midpoints and vertex points `(u + 6v + w)/8`.

use std::f64::consts::PI;
use std::io;

use super::emit::Emit;
use super::error::SubdivideError;
use super::polymesh::{PolyMesh, Scheme};
use super::rules::{self, CcEdge, CcVertex, Mix};
use super::topology::{BORDER, Made, Net, Topology, ring};

/// Weights of the Doo-Sabin-like quad rule: the corner, the next corner,
/// the previous corner; the opposite one gets `1 − α − β − γ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadWeights {
    /// The corner itself.
    pub alpha: f64,
    /// The next corner (counter-clockwise).
    pub beta: f64,
    /// The previous corner.
    pub gamma: f64,
}

impl QuadWeights {
    /// The classic Doo-Sabin weights `(9/16, 3/16, 3/16)`, opposite `1/16`.
    pub const CLASSIC: QuadWeights = QuadWeights { alpha: 0.5625, beta: 0.1875, gamma: 0.1875 };

    /// Sokolov et al. 2010 Fig. 12's "geometric textures" of the cube, as the gallery
    /// draws them: the classic smooth surface, a bilinear corner cutting
    /// (`δ = 0`), a creased one, a bulging one, a negative opposite weight and
    /// a chiral rule (`β ≠ γ`, rough). Each passes [`check_quad_weights`](crate::analysis::check_quad_weights).
    pub const TEXTURES: [QuadWeights; 6] = [
        QuadWeights::CLASSIC,
        QuadWeights { alpha: 0.5, beta: 0.25, gamma: 0.25 },
        QuadWeights { alpha: 0.3, beta: 0.3, gamma: 0.3 },
        QuadWeights { alpha: 0.7, beta: 0.1, gamma: 0.1 },
        QuadWeights { alpha: 0.6, beta: 0.35, gamma: 0.35 },
        QuadWeights { alpha: 0.45, beta: 0.35, gamma: 0.1 },
    ];

    /// The weight of the opposite corner.
    pub fn delta(&self) -> f64 {
        1.0 - self.alpha - self.beta - self.gamma
    }

    /// Moduli of the eigenvalues of the face rule on the differences (the
    /// circulant's `λ_k = α + β i^k + γ i^−k + δ (−1)^k`, `k = 1, 2, 3`):
    /// each below 1 is necessary for the faces to shrink to points.
    pub fn face_eigenvalues(&self) -> [f64; 3] {
        let (a, b, g, d) = (self.alpha, self.beta, self.gamma, self.delta());
        let l1 = ((a - d).powi(2) + (b - g).powi(2)).sqrt(); // k = 1, 3: (a − d) ± i(b − g)
        let l2 = (a - b - g + d).abs();
        [l1, l2, l1]
    }
}

/// Weights of Loop-like triangle rules: edge points
/// `w (a + b) + (1/2 − w)(c + d)`, and at a vertex of valence `n` the ring
/// weight `nβ(n) = 1 − w − σ λ₁(n)²` with `λ₁(n) = w + (1 − 2w) cos(2π/n)`
/// (the 1-ring's eigenvalues are then `σ λ₁²` for the average and
/// `w + (1 − 2w) cos(2πk/n)` for the other frequencies). Loop is `w = 3/8`,
/// `σ = 1` at every valence; the border keeps the cubic B-spline rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopWeights {
    /// Weight of each end of an edge (the two opposite vertices get `1/2 − w`).
    pub w: f64,
    /// The vertex eigenvalue relative to Loop's choice `λ₁²`.
    pub sigma: f64,
}

impl LoopWeights {
    /// Loop's weights.
    pub const CLASSIC: LoopWeights = LoopWeights { w: 0.375, sigma: 1.0 };

    /// Geometric textures of a triangle mesh, as the gallery draws them on
    /// the icosahedron (Sokolov et al. 2010 Fig. 12's idea on triangles): Loop, a
    /// flatter vertex rule, a sharper one, heavier edge ends (bulging),
    /// lighter edge ends (creased) and a negative vertex eigenvalue (rough).
    /// Each passes [`check_loop_weights`](crate::analysis::check_loop_weights) on the icosahedron.
    pub const TEXTURES: [LoopWeights; 6] = [
        LoopWeights::CLASSIC,
        LoopWeights { w: 0.375, sigma: 3.0 },
        LoopWeights { w: 0.25, sigma: 1.0 },
        LoopWeights { w: 0.15, sigma: 0.5 },
        LoopWeights { w: 0.6, sigma: 1.0 },
        LoopWeights { w: 0.42, sigma: -2.0 },
    ];

    /// `λ₁(n) = w + (1 − 2w) cos(2π/n)`.
    pub fn lambda1(&self, n: usize) -> f64 {
        self.w + (1.0 - 2.0 * self.w) * (2.0 * PI / n as f64).cos()
    }

    /// The ring weight `nβ(n)`.
    pub fn ring(&self, n: usize) -> f64 {
        1.0 - self.w - self.sigma * self.lambda1(n).powi(2)
    }
}

/// Weights of a scheme's rules other than the classic ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RuleWeights {
    /// Doo-Sabin's quad rule.
    Quad(QuadWeights),
    /// Loop's edge and vertex rules.
    Loop(LoopWeights),
}

impl RuleWeights {
    /// The Doo-Sabin weights, if these are.
    pub fn quad(self) -> Option<QuadWeights> {
        match self {
            RuleWeights::Quad(q) => Some(q),
            RuleWeights::Loop(_) => None,
        }
    }

    /// The Loop weights, if these are.
    pub fn triangle(self) -> Option<LoopWeights> {
        match self {
            RuleWeights::Loop(l) => Some(l),
            RuleWeights::Quad(_) => None,
        }
    }
}

impl From<QuadWeights> for RuleWeights {
    fn from(q: QuadWeights) -> RuleWeights {
        RuleWeights::Quad(q)
    }
}

impl From<LoopWeights> for RuleWeights {
    fn from(l: LoopWeights) -> RuleWeights {
        RuleWeights::Loop(l)
    }
}

/// The classic Doo-Sabin weights of an `n`-gon, `α_0 .. α_{n−1}` (`α_k`
/// on corner `i + k` for the new point of corner `i`): `(1 + 5/n)/4` and
/// `(3 + 2cos(2πk/n))/(4n)`, CGAL's arithmetic. The one definition: the
/// subdivision and the generated automaton's defaults use it.
///
/// ```
/// let w = bcifs::mesh::doo_sabin_weights(4);
/// assert_eq!(w, [9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0]);
/// assert!((bcifs::mesh::doo_sabin_weights(7).iter().sum::<f64>() - 1.0).abs() < 1e-15);
/// ```
pub fn doo_sabin_weights(n: usize) -> Vec<f64> {
    if n == 4 {
        // CGAL spells the quad out: exactly these values.
        return vec![9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0];
    }
    let nf = n as f64;
    (0..n)
        .map(
            |k| if k == 0 { (5.0 / nf + 1.0) / 4.0 } else { (3.0 + 2.0 * (2.0 * k as f64 * PI / nf).cos()) / nf / 4.0 },
        )
        .collect()
}

/// `a += w b`.
pub(crate) fn add(a: &mut [f64; 3], b: [f64; 3], w: f64) {
    a.add(&b, &w);
}

impl PolyMesh {
    /// The control mesh after `depth` steps of `scheme` (classic weights).
    ///
    /// # Errors
    /// An output over [`super::polymesh::DEFAULT_MESH_MEMORY`], with the estimate.
    pub fn subdivide(&self, scheme: Scheme, depth: usize) -> Result<PolyMesh, SubdivideError> {
        self.subdivide_with(scheme, depth, None, super::polymesh::DEFAULT_MESH_MEMORY)
    }

    /// The control mesh after `depth` steps of `scheme`, with Doo-Sabin quad
    /// weights (`None`: classic) and an in-memory limit in bytes.
    ///
    /// # Errors
    /// An output over `memory_limit`, with the estimate.
    pub fn subdivide_with(
        &self,
        scheme: Scheme,
        depth: usize,
        weights: Option<RuleWeights>,
        memory_limit: usize,
    ) -> Result<PolyMesh, SubdivideError> {
        self.check_input(scheme, depth, memory_limit)?;
        if depth == 0 {
            return Ok(self.clone());
        }
        let (net, t) = self.steps(scheme, depth - 1, weights).map_err(SubdivideError::Write)?;
        net.step(scheme, depth - 1, &t, weights).map_err(SubdivideError::Write)
    }

    /// A mesh `scheme` applies to (triangles for Loop and √3), whose net after
    /// `depth` steps fits `memory_limit`.
    fn check_input(&self, scheme: Scheme, depth: usize, memory_limit: usize) -> Result<(), SubdivideError> {
        if scheme.triangles_only()
            && let Some((face, f)) = self.faces().enumerate().find(|(_, f)| f.len() != 3)
        {
            return Err(SubdivideError::NotTriangles { scheme: scheme.name(), face, degree: f.len() });
        }
        self.check_size(scheme, depth, memory_limit)
    }

    /// [`PolyMesh::subdivide_with`] and the net's topology (Loop's and
    /// Catmull-Clark's read off the step before, the others' found).
    pub(crate) fn net_and_topology(
        &self,
        scheme: Scheme,
        depth: usize,
        weights: Option<RuleWeights>,
        memory_limit: usize,
    ) -> Result<(PolyMesh, Topology), SubdivideError> {
        self.check_input(scheme, depth, memory_limit)?;
        self.steps(scheme, depth, weights).map_err(SubdivideError::Write)
    }

    /// The net after `depth` steps and its topology, unchecked.
    ///
    /// # Errors
    /// Cancelled ([`crate::progress::Cancel::scope`]).
    fn steps(&self, scheme: Scheme, depth: usize, weights: Option<RuleWeights>) -> io::Result<(PolyMesh, Topology)> {
        let mut mesh = self.clone();
        let mut t = Topology::trusted(&mesh);
        for step in 0..depth {
            // Loop's and Catmull-Clark's topologies are read off the step before; the others' are
            // found once the net before is dropped (a quarter of the memory).
            let next = mesh.step(scheme, step, &t, weights)?;
            let derived = match scheme {
                Scheme::Loop => Some(t.loop_child(&next)),
                Scheme::CatmullClark => Some(t.catmull_clark_child(&mesh, &next)),
                Scheme::DooSabin | Scheme::Sqrt3 => None,
            };
            mesh = next;
            t = match derived {
                Some(child) => child,
                None => {
                    drop(t);
                    Topology::trusted_or_cancelled(&mesh)?
                }
            };
        }
        Ok((mesh, t))
    }

    /// The mesh after `depth` steps of `scheme` fits `memory_limit` bytes
    /// ([`PolyMesh::estimate`]) and numbers its corners in 32 bits.
    ///
    /// # Errors
    /// [`SubdivideError::TooLarge`] with the estimate.
    pub(crate) fn check_size(&self, scheme: Scheme, depth: usize, memory_limit: usize) -> Result<(), SubdivideError> {
        let (faces, bytes) = self.estimate(scheme, depth);
        // Corners are numbered in 32 bits: a mesh with 2³² of them is refused whatever the memory.
        if bytes > memory_limit as u128 || faces.saturating_mul(4) >= u128::from(u32::MAX) {
            return Err(SubdivideError::TooLarge {
                what: "the subdivided mesh",
                depth,
                faces,
                bytes,
                limit: memory_limit,
            });
        }
        Ok(())
    }

    /// Faces and bytes of the mesh after `depth` steps (every step multiplies
    /// the corners by about 4; a corner takes an index, a face a start, a
    /// vertex a position, with the working arrays of the last step).
    pub fn estimate(&self, scheme: Scheme, depth: usize) -> (u128, u128) {
        let corners = self.corner_count() as u128;
        let grow = |k: u128| k.saturating_pow(depth.min(80) as u32);
        let faces = match (scheme, depth) {
            (_, 0) => self.face_count() as u128,
            (Scheme::CatmullClark, _) => corners.saturating_mul(grow(4) / 4),
            (Scheme::DooSabin, _) => corners.saturating_mul(grow(4) / 4).saturating_add(self.face_count() as u128),
            (Scheme::Loop, _) => (self.face_count() as u128).saturating_mul(grow(4)),
            (Scheme::Sqrt3, _) => (self.face_count() as u128).saturating_mul(grow(3)),
        };
        // Per face of the result: 4 corners × (index + twin + face) + start + position + topology map.
        (faces, faces.saturating_mul(4 * 24 + 8 + 24 + 64))
    }

    /// Step number `step` (from 0) of `scheme` in memory.
    ///
    /// # Errors
    /// Cancelled ([`crate::progress::Cancel::scope`]): memory itself cannot fail.
    pub(super) fn step(
        &self,
        scheme: Scheme,
        step: usize,
        t: &Topology,
        weights: Option<RuleWeights>,
    ) -> io::Result<PolyMesh> {
        let mut out = Emit::memory(self.positions.len() + self.corner_count(), 4 * self.corner_count());
        self.step_into(scheme, step, t, weights, &mut out)?;
        Ok(out.finish())
    }

    /// Step number `step` (from 0: √3 refines the border on odd ones) of `scheme` into `out`.
    pub(crate) fn step_into(
        &self,
        scheme: Scheme,
        step: usize,
        t: &Topology,
        weights: Option<RuleWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        match scheme {
            Scheme::DooSabin => self.doo_sabin_into(t, weights.and_then(RuleWeights::quad), out),
            Scheme::CatmullClark => self.catmull_clark_into(t, out),
            Scheme::Loop => self.loop_into(t, weights.and_then(RuleWeights::triangle), out),
            Scheme::Sqrt3 => self.sqrt3_into(t, step % 2 == 1, out),
        }
    }

    /// The new position of corner `i` of face `f` (Doo-Sabin): a sum over
    /// the face's corners for small faces, O(1) from the face's Fourier
    /// coefficients for large ones (see [`Weights`]).
    #[inline]
    fn corner_point(&self, f: usize, i: usize, weights: &Weights) -> [f64; 3] {
        let face = self.face(f);
        let n = face.len();
        if let Some(w) = weights.by_degree.get(n) {
            return rules::doo_sabin_corner(i, |j| self.positions[face[j]], w);
        }
        // α_k = 3/(4n) + cos(2πk/n)/(2n), plus 1/4 on the corner itself:
        // q_i = p_i/4 + 3/(4n) Σp + Re(e^{−2πi·i/n} C)/(2n), C = Σ_j e^{2πi·j/n} p_j.
        let (sum, re, im) = weights.large[&f];
        let nf = n as f64;
        let (sin, cos) = (2.0 * PI * i as f64 / nf).sin_cos();
        let mut p = [0.0; 3];
        add(&mut p, self.positions[face[i]], 0.25);
        add(&mut p, sum, 3.0 / (4.0 * nf));
        add(&mut p, re, cos / (2.0 * nf));
        add(&mut p, im, sin / (2.0 * nf));
        p
    }

    /// One Doo-Sabin step into `out`: the corners' points face by face (so
    /// the vertices are numbered as the corners), then the faces of the
    /// faces, of the interior edges and of the interior vertices.
    pub(crate) fn doo_sabin_into(&self, t: &Topology, quad: Option<QuadWeights>, out: &mut Emit<'_>) -> io::Result<()> {
        let weights = Weights::new(self, quad);
        for f in 0..self.face_count() {
            for i in 0..self.face(f).len() {
                out.vertex(self.corner_point(f, i, &weights))?;
            }
        }
        for f in 0..self.face_count() {
            out.face(&mut (self.starts[f]..self.starts[f + 1]))?;
        }
        for c in 0..self.corner_count() {
            let tw = t.twin(c);
            if tw != BORDER && c < tw {
                out.face([t.next(self, c), c, t.next(self, tw), tw])?;
            }
        }
        for v in 0..self.positions.len() {
            let c0 = t.first(v);
            if c0 != BORDER && !t.on_border(v) {
                out.face(&mut Rotation { mesh: self, t, first: c0, at: Some(c0) })?;
            }
        }
        Ok(())
    }

    /// Doo-Sabin's limit after one more step, straight from this net:
    /// the centroids of the next net's faces (a face keeps its centroid, the
    /// edges' and vertices' faces are made of corner points), and a quad per
    /// corner at an interior vertex, around the next net's vertex there:
    /// `[F(face), E(previous edge), V(vertex), E(edge)]`.
    #[allow(clippy::needless_range_loop)] // a vertex indexes the mesh and the numbering
    pub(crate) fn doo_sabin_limit_into(
        &self,
        t: &Topology,
        quad: Option<QuadWeights>,
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        let weights = Weights::new(self, quad);
        let point = |c: usize| {
            let f = t.face(c);
            self.corner_point(f, c - self.starts[f], &weights)
        };
        let nf = self.face_count();
        for f in 0..nf {
            out.vertex(self.centroid(f))?;
        }
        // Edge faces, numbered in corner order; both half-edges know the number.
        let mut edge = vec![u32::MAX; self.corner_count()];
        let mut count = 0u32;
        for c in 0..self.corner_count() {
            let tw = t.twin(c);
            if tw != BORDER && c < tw {
                let mut p = [0.0; 3];
                for q in [t.next(self, c), c, t.next(self, tw), tw] {
                    add(&mut p, point(q), 0.25);
                }
                out.vertex(p)?;
                (edge[c], edge[tw]) = (count, count);
                count += 1;
            }
        }
        let mut vertex = vec![u32::MAX; self.positions.len()];
        let mut interior = 0u32;
        for v in 0..self.positions.len() {
            let c0 = t.first(v);
            if c0 != BORDER && !t.on_border(v) {
                let corners: Vec<usize> = Rotation { mesh: self, t, first: c0, at: Some(c0) }.collect();
                let mut p = [0.0; 3];
                corners.iter().for_each(|&c| add(&mut p, point(c), 1.0 / corners.len() as f64));
                out.vertex(p)?;
                vertex[v] = interior;
                interior += 1;
            }
        }
        let (e0, v0) = (nf, nf + count as usize);
        for c in 0..self.corner_count() {
            let v = self.indices[c];
            if vertex[v] != u32::MAX {
                let p = t.prev(self, c);
                let quad = [t.face(c), e0 + edge[p] as usize, v0 + vertex[v] as usize, e0 + edge[c] as usize];
                out.face(quad)?;
            }
        }
        Ok(())
    }

    /// One Catmull-Clark step into `out`: vertex points, edge points (in
    /// corner order), face points; a quad per corner.
    pub(crate) fn catmull_clark_into(&self, t: &Topology, out: &mut Emit<'_>) -> io::Result<()> {
        let (nv, nf) = (self.positions.len(), self.face_count());
        let face_points: Vec<[f64; 3]> = (0..nf).map(|f| self.centroid(f)).collect();
        for v in 0..nv {
            out.vertex(self.cc_vertex_point(t, v, |f| face_points[f]))?;
        }
        let (edge_of, edges) = self.edge_points(t, out, |c, tw| self.cc_edge_point(t, c, tw, |f| face_points[f]))?;
        for p in &face_points {
            out.vertex(*p)?;
        }
        self.cc_quads(t, (nv, nv + edges), &edge_of, out)
    }
}

impl PolyMesh {
    /// Catmull-Clark's new point of vertex `v` (`face_point(f)`: the centroid
    /// of face `f`): `(Q + 2R + (n − 3)v)/n`, the cubic B-spline rule on the
    /// border, `v` itself when no face uses it.
    pub(crate) fn cc_vertex_point(&self, t: &Topology, v: usize, face_point: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
        let p = self.positions[v];
        let c0 = t.first(v);
        if c0 == BORDER {
            return p; // unused by any face: kept as is
        }
        if t.on_border(v) {
            return border_curve_point(&Made { mesh: self, t }, c0);
        }
        let ring = (Rotation { mesh: self, t, first: c0, at: Some(c0) })
            .map(|c| (self.positions[self.indices[t.next(self, c)]], face_point(t.face(c))));
        rules::cc_vertex(&p, ring, CcVertex::classic)
    }

    /// Catmull-Clark's point of the interior edge of the corners `c < tw`:
    /// `(a + b + f + g)/4`.
    pub(crate) fn cc_edge_point(
        &self,
        t: &Topology,
        c: usize,
        tw: usize,
        face_point: impl Fn(usize) -> [f64; 3],
    ) -> [f64; 3] {
        let ends = [self.positions[self.indices[c]], self.positions[self.indices[tw]]];
        let faces = [face_point(t.face(c)), face_point(t.face(tw))];
        rules::cc_edge(&ends[0], &ends[1], &faces[0], &faces[1], &CcEdge::CLASSIC)
    }

    /// The midpoint of the border half-edge `c`.
    pub(crate) fn border_midpoint(&self, t: &Topology, c: usize) -> [f64; 3] {
        border_midpoint(&Made { mesh: self, t }, c)
    }
}

/// One point per edge of a net of `corners` corners (twins `twin`) into
/// `out`, from its numbering corner (the smaller of an interior edge's), in
/// corner order: `point(c, twin)` (`None`: a border edge).
pub(crate) fn edge_points_into(
    corners: usize,
    twin: impl Fn(usize) -> usize + Sync,
    point: impl Fn(usize, Option<usize>) -> [f64; 3] + Sync,
    out: &mut Emit<'_>,
) -> io::Result<()> {
    out.vertices_of(0..corners, |c| match twin(c) {
        BORDER => Some(point(c, None)),
        tw if tw < c => None,
        tw => Some(point(c, Some(tw))),
    })
}

/// √3's vertex weight `a` at valence `n`.
pub fn sqrt3_alpha(n: usize) -> f64 {
    (4.0 - 2.0 * (2.0 * PI / n as f64).cos()) / 9.0
}

/// √3's new position of vertex `v` of `net` (kept on the border on steps that do not refine it).
pub(crate) fn sqrt3_vertex<N: Net>(net: &N, refine_border: bool, v: usize) -> [f64; 3] {
    let p = net.point(v);
    let c0 = net.first(v);
    if c0 == BORDER || (net.on_border(v) && !refine_border) {
        return p;
    }
    if net.on_border(v) {
        return border_mix(net, c0, 4.0 / 27.0, 19.0 / 27.0);
    }
    with_ring(net, c0, |ring| {
        let n = ring.len();
        let a = sqrt3_alpha(n);
        rules::sqrt3_vertex(&p, ring.iter().map(|&u| net.point(u)), &(1.0 - a), &(a / n as f64))
    })
}

/// `f` of the ring of the interior vertex whose first corner is `c0`
/// ([`ring`]), walked once (into a buffer on the stack unless the valence is large).
pub(crate) fn with_ring<N: Net, T>(net: &N, c0: usize, f: impl FnOnce(&[usize]) -> T) -> T {
    let mut buffer = [0usize; 16];
    let mut n = 0;
    for u in ring(net, c0) {
        if n == buffer.len() {
            return f(&ring(net, c0).collect::<Vec<_>>());
        }
        buffer[n] = u;
        n += 1;
    }
    f(&buffer[..n])
}

/// √3's two points on the border edge of corner `cb` of `net` (a face split on a border-refining step).
pub(crate) fn sqrt3_border_points<N: Net>(net: &N, cb: usize) -> [[f64; 3]; 2] {
    let (a, b) = (net.vertex(cb), net.vertex(net.next(cb)));
    let (a2, _) = net.border_neighbours(net.first(a));
    let (_, b2) = net.border_neighbours(net.first(b));
    let (pa, pb) = (net.point(a), net.point(b));
    let mut x1 = [0.0; 3];
    add(&mut x1, net.point(a2), 1.0 / 27.0);
    add(&mut x1, pa, 16.0 / 27.0);
    add(&mut x1, pb, 10.0 / 27.0);
    let mut x2 = [0.0; 3];
    add(&mut x2, pa, 10.0 / 27.0);
    add(&mut x2, pb, 16.0 / 27.0);
    add(&mut x2, net.point(b2), 1.0 / 27.0);
    [x1, x2]
}

/// `side · u + middle · p + side · w` for the border vertex `p` of corner
/// `c0` of `net` between its border neighbours `u` and `w` (summed in that order).
pub(crate) fn border_mix<N: Net>(net: &N, c0: usize, side: f64, middle: f64) -> [f64; 3] {
    let (u, w) = net.border_neighbours(c0);
    let mut q = [0.0; 3];
    add(&mut q, net.point(u), side);
    add(&mut q, net.point(net.vertex(c0)), middle);
    add(&mut q, net.point(w), side);
    q
}

/// The cubic B-spline point `(u + 6v + w)/8` of the border vertex `v` whose
/// first corner is `c0` (Catmull-Clark's and Loop's border rule).
pub(crate) fn border_curve_point<N: Net>(net: &N, c0: usize) -> [f64; 3] {
    let (u, w) = net.border_neighbours(c0);
    rules::border_curve(&net.point(u), &net.point(net.vertex(c0)), &net.point(w))
}

/// The midpoint of the border half-edge `c` of `net`.
pub(crate) fn border_midpoint<N: Net>(net: &N, c: usize) -> [f64; 3] {
    rules::midpoint(&net.point(net.vertex(c)), &net.point(net.vertex(net.next(c))))
}

impl PolyMesh {
    /// One point per edge into `out`, numbered in corner order (the smaller
    /// corner of an interior edge): the midpoint of a border edge, `interior(c, twin)`
    /// otherwise. Returns each corner's edge number, and the number of edges.
    pub(crate) fn edge_points(
        &self,
        t: &Topology,
        out: &mut Emit<'_>,
        interior: impl Fn(usize, usize) -> [f64; 3] + Sync,
    ) -> io::Result<(Vec<u32>, usize)> {
        self.edge_numbering(t, out, |c, tw| match tw {
            None => self.border_midpoint(t, c),
            Some(tw) => interior(c, tw),
        })
    }

    /// One point per edge into `out`, numbered in corner order (the smaller
    /// corner of an interior edge): `point(c, twin)` (`None`: a border edge).
    /// Returns each corner's edge number, and the number of edges.
    pub(crate) fn edge_numbering(
        &self,
        t: &Topology,
        out: &mut Emit<'_>,
        point: impl Fn(usize, Option<usize>) -> [f64; 3] + Sync,
    ) -> io::Result<(Vec<u32>, usize)> {
        let numbers = self.edge_numbers(t);
        edge_points_into(self.corner_count(), |c| t.twin(c), point, out)?;
        Ok(numbers)
    }

    /// Each corner's edge number, in corner order (the smaller corner of an
    /// interior edge numbers it), and the number of edges.
    pub(crate) fn edge_numbers(&self, t: &Topology) -> (Vec<u32>, usize) {
        let mut edge_of = vec![0u32; self.corner_count()];
        let mut edges = 0u32;
        for c in 0..self.corner_count() {
            let tw = t.twin(c);
            if tw != BORDER && tw < c {
                continue;
            }
            if tw != BORDER {
                edge_of[tw] = edges;
            }
            edge_of[c] = edges;
            edges += 1;
        }
        (edge_of, edges as usize)
    }

    /// Catmull-Clark's quads, one per corner `[v, e(c), f, e(prev c)]`, the
    /// edge points numbered from `e0` (`edge_of`) and the face points from `f0`.
    pub(crate) fn cc_quads(
        &self,
        t: &Topology,
        (e0, f0): (usize, usize),
        edge_of: &[u32],
        out: &mut Emit<'_>,
    ) -> io::Result<()> {
        for c in 0..self.corner_count() {
            let quad =
                [self.indices[c], e0 + edge_of[c] as usize, f0 + t.face(c), e0 + edge_of[t.prev(self, c)] as usize];
            out.face(quad)?;
        }
        Ok(())
    }
}

/// Faces of more corners than this get Doo-Sabin's corner points from
/// their Fourier coefficients (O(n) a face instead of O(n²)); smaller ones
/// from the weights, as CGAL spells them.
const DIRECT_MAX: usize = 64;

/// The weights of the Doo-Sabin corner rule, computed once: per face degree
/// up to [`DIRECT_MAX`] (and no further, so a face of a million corners
/// costs no table of a million rows), and for each larger face the sum of
/// its corners and the real and imaginary parts of `Σ_j e^{2πi·j/n} p_j`.
struct Weights {
    by_degree: Vec<Vec<f64>>,
    large: std::collections::HashMap<usize, Fourier>,
}

/// A large face's corner sum and the real and imaginary parts of `Σ_j e^{2πi·j/n} p_j`.
type Fourier = ([f64; 3], [f64; 3], [f64; 3]);

impl Weights {
    fn new(mesh: &PolyMesh, quad: Option<QuadWeights>) -> Weights {
        let largest = mesh.faces().map(<[usize]>::len).max().unwrap_or(0).min(DIRECT_MAX);
        let by_degree = (0..=largest)
            .map(|n| match (n, quad) {
                // A digon (the face of an interior vertex of valence 2) has corners too: (7/8, 1/8).
                (0..=1, _) => Vec::new(),
                (4, Some(q)) => vec![q.alpha, q.beta, q.delta(), q.gamma],
                _ => doo_sabin_weights(n),
            })
            .collect();
        let mut large = std::collections::HashMap::new();
        for (f, face) in mesh.faces().enumerate().filter(|(_, face)| face.len() > DIRECT_MAX) {
            let (mut sum, mut re, mut im) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            let n = face.len() as f64;
            for (j, &v) in face.iter().enumerate() {
                let (sin, cos) = (2.0 * PI * j as f64 / n).sin_cos();
                add(&mut sum, mesh.positions[v], 1.0);
                add(&mut re, mesh.positions[v], cos);
                add(&mut im, mesh.positions[v], sin);
            }
            large.insert(f, (sum, re, im));
        }
        Weights { by_degree, large }
    }
}

/// The outgoing corners around a vertex, from `first` by the rotation, to
/// the border or back to `first`.
struct Rotation<'a> {
    mesh: &'a PolyMesh,
    t: &'a Topology,
    first: usize,
    at: Option<usize>,
}

impl Iterator for Rotation<'_> {
    type Item = usize;
    fn next(&mut self) -> Option<usize> {
        let c = self.at?;
        let r = self.t.rotate(self.mesh, c);
        self.at = (r != BORDER && r != self.first).then_some(r);
        Some(c)
    }
}
