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
                if !self.has_interior_vertex() {
                    return Err(SubdivideError::NoInteriorVertex);
                }
                let net = self.subdivide_with(scheme, depth.max(1) - 1, weights, memory_limit)?;
                let t = Topology::trusted(&net);
                let mut out = Emit::memory(net.face_count() * 3, 4 * net.corner_count());
                // Writing into memory cannot fail.
                let _ = net.doo_sabin_limit_into(&t, weights.and_then(RuleWeights::quad), &mut out);
                let dual = out.finish();
                (dual.positions.clone(), dual.faces().map(|f| [f[0], f[1], f[2], f[3]]).collect())
            }
            Scheme::CatmullClark => {
                let net = self.subdivide_with(scheme, depth.max(1), weights, memory_limit)?;
                catmull_clark_limit(&net, &Topology::trusted(&net))
            }
            Scheme::Loop | Scheme::Sqrt3 => {
                let net = self.subdivide_with(scheme, depth.max(1), weights, memory_limit)?;
                let points = net.triangle_limit_points(
                    &Topology::trusted(&net),
                    scheme == Scheme::Sqrt3,
                    weights.and_then(RuleWeights::triangle),
                );
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
