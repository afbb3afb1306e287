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

use super::topology::{BORDER, Topology};
use super::{MeshError, Place, PolyMesh, Scheme};

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

    /// Seed 004 Fig. 12's "geometric textures" of the cube, as the gallery
    /// draws them: the classic smooth surface, a bilinear corner cutting
    /// (`δ = 0`), a creased one, a bulging one, a negative opposite weight and
    /// a chiral rule (`β ≠ γ`, rough). Each passes [`QuadWeights::check`].
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

/// The classic Doo-Sabin weights of an `n`-gon, `α_0 .. α_{n−1}`.
fn doo_sabin_weights(n: usize) -> Vec<f64> {
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

fn add(a: &mut [f64; 3], b: [f64; 3], w: f64) {
    a[0] += w * b[0];
    a[1] += w * b[1];
    a[2] += w * b[2];
}

impl PolyMesh {
    /// The control mesh after `depth` steps of `scheme` (classic weights).
    ///
    /// # Errors
    /// An output over [`super::DEFAULT_MESH_MEMORY`], with the estimate.
    pub fn subdivide(&self, scheme: Scheme, depth: usize) -> Result<PolyMesh, MeshError> {
        self.subdivide_with(scheme, depth, None, super::DEFAULT_MESH_MEMORY)
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
        quad: Option<QuadWeights>,
        memory_limit: usize,
    ) -> Result<PolyMesh, MeshError> {
        let (faces, bytes) = self.estimate(scheme, depth);
        if bytes > memory_limit as u128 {
            return Err(MeshError::TooLarge { what: "the subdivided mesh", depth, faces, bytes, limit: memory_limit });
        }
        let mut mesh = self.clone();
        for _ in 0..depth {
            let topology = Topology::new(&mesh, &|face| Place { file: None, line: None, face })?;
            mesh = match scheme {
                Scheme::DooSabin => mesh.doo_sabin_step(&topology, quad),
                Scheme::CatmullClark => mesh.catmull_clark_step(&topology),
            };
        }
        Ok(mesh)
    }

    /// Faces and bytes of the mesh after `depth` steps (every step multiplies
    /// the corners by about 4; a corner takes an index, a face a start, a
    /// vertex a position, with the working arrays of the last step).
    pub fn estimate(&self, scheme: Scheme, depth: usize) -> (u128, u128) {
        let corners = self.corner_count() as u128;
        let grow = 4u128.saturating_pow(depth.min(60) as u32);
        let faces = match (scheme, depth) {
            (_, 0) => self.face_count() as u128,
            (Scheme::CatmullClark, _) => corners.saturating_mul(grow / 4),
            (Scheme::DooSabin, _) => corners.saturating_mul(grow / 4).saturating_add(self.face_count() as u128),
        };
        // Per face of the result: 4 corners × (index + twin + face) + start + position + topology map.
        (faces, faces.saturating_mul(4 * 24 + 8 + 24 + 64))
    }

    fn doo_sabin_step(&self, t: &Topology, quad: Option<QuadWeights>) -> PolyMesh {
        let corners = self.corner_count();
        let mut positions = vec![[0.0; 3]; corners];
        let mut weights: Vec<Vec<f64>> = Vec::new();
        for f in 0..self.face_count() {
            let face = self.face(f);
            let n = face.len();
            if weights.len() <= n {
                weights.resize(n + 1, Vec::new());
            }
            if weights[n].is_empty() {
                weights[n] = match (n, quad) {
                    (4, Some(q)) => vec![q.alpha, q.beta, q.delta(), q.gamma],
                    _ => doo_sabin_weights(n),
                };
            }
            let w = &weights[n];
            for i in 0..n {
                let p = &mut positions[self.starts[f] + i];
                for (k, wk) in w.iter().enumerate() {
                    add(p, self.positions[face[(i + k) % n]], *wk);
                }
            }
        }
        let mut starts = self.starts.clone();
        let mut indices = self.indices.clone();
        indices.iter_mut().enumerate().for_each(|(c, x)| *x = c);
        // An E-face per interior edge: [next(c), c, next(t), t].
        for c in 0..corners {
            let tw = t.twin[c];
            if tw != BORDER && c < tw {
                indices.extend([t.next(self, c), c, t.next(self, tw), tw]);
                starts.push(indices.len());
            }
        }
        // A V-face per interior vertex: its corners in rotation order.
        for v in 0..self.positions.len() {
            let c0 = t.first[v];
            if c0 == BORDER || t.on_border[v] {
                continue;
            }
            let mut c = c0;
            loop {
                indices.push(c);
                c = t.rotate(self, c);
                if c == c0 {
                    break;
                }
            }
            starts.push(indices.len());
        }
        PolyMesh::from_flat(positions, starts, indices)
    }

    fn catmull_clark_step(&self, t: &Topology) -> PolyMesh {
        let (nv, nf, corners) = (self.positions.len(), self.face_count(), self.corner_count());
        // Face points.
        let mut face_points = vec![[0.0; 3]; nf];
        for (f, fp) in face_points.iter_mut().enumerate() {
            let face = self.face(f);
            face.iter().for_each(|&v| add(fp, self.positions[v], 1.0 / face.len() as f64));
        }
        // Edges: one per interior pair of half-edges (the smaller corner) or border half-edge.
        let mut edge_of = vec![0usize; corners];
        let mut edge_points: Vec<[f64; 3]> = Vec::with_capacity(corners / 2 + 1);
        for c in 0..corners {
            let tw = t.twin[c];
            if tw != BORDER && tw < c {
                continue;
            }
            let (a, b) = (self.positions[self.indices[c]], self.positions[self.indices[t.next(self, c)]]);
            let mut p = [0.0; 3];
            if tw == BORDER {
                add(&mut p, a, 0.5);
                add(&mut p, b, 0.5);
            } else {
                for q in [a, b, face_points[t.face[c]], face_points[t.face[tw]]] {
                    add(&mut p, q, 0.25);
                }
                edge_of[tw] = nv + edge_points.len();
            }
            edge_of[c] = nv + edge_points.len();
            edge_points.push(p);
        }
        // Vertex points.
        let mut positions = Vec::with_capacity(nv + edge_points.len() + nf);
        for v in 0..nv {
            let p = self.positions[v];
            let c0 = t.first[v];
            if c0 == BORDER {
                positions.push(p); // unused by any face: kept as is
                continue;
            }
            if t.on_border[v] {
                // The fan runs from the border half-edge going out (to w) to the one coming in (from u).
                let w = self.positions[self.indices[t.next(self, c0)]];
                let mut last = c0;
                while t.rotate(self, last) != BORDER {
                    last = t.rotate(self, last);
                }
                let u = self.positions[self.indices[t.prev(self, last)]];
                let mut q = [0.0; 3];
                add(&mut q, u, 1.0 / 8.0);
                add(&mut q, p, 6.0 / 8.0);
                add(&mut q, w, 1.0 / 8.0);
                positions.push(q);
                continue;
            }
            let (mut q, mut r, mut n) = ([0.0; 3], [0.0; 3], 0usize);
            let mut c = c0;
            loop {
                add(&mut q, face_points[t.face[c]], 1.0);
                add(&mut r, p, 0.5);
                add(&mut r, self.positions[self.indices[t.next(self, c)]], 0.5);
                n += 1;
                c = t.rotate(self, c);
                if c == c0 {
                    break;
                }
            }
            let nf64 = n as f64;
            let mut out = [0.0; 3];
            add(&mut out, q, 1.0 / nf64 / nf64);
            add(&mut out, r, 2.0 / nf64 / nf64);
            add(&mut out, p, (nf64 - 3.0) / nf64);
            positions.push(out);
        }
        positions.extend(edge_points);
        let face_base = positions.len();
        positions.extend(face_points);
        let mut starts = Vec::with_capacity(corners + 1);
        let mut indices = Vec::with_capacity(4 * corners);
        starts.push(0);
        for c in 0..corners {
            let f = t.face[c];
            indices.extend([self.indices[c], edge_of[c], face_base + f, edge_of[t.prev(self, c)]]);
            starts.push(indices.len());
        }
        PolyMesh::from_flat(positions, starts, indices)
    }
}

/// What the convergence check of quad weights found.
#[derive(Clone, Debug, PartialEq)]
pub enum WeightsVerdict {
    /// The joint spectral radius bounds of the regular quad patch prove convergence.
    Converges,
    /// Not decided; why.
    Undecided(String),
}

impl QuadWeights {
    /// Checks the weights before subdividing: finite, the face rule's
    /// eigenvalues on the differences below 1 in modulus (necessary), and for
    /// mirror-symmetric weights (`β = γ`) the joint spectral radius bounds of
    /// the shipped regular patch `doo_sabin_quad` (sufficient when they decide).
    ///
    /// # Errors
    /// [`MeshError::Weights`] naming the weights and what fails.
    pub fn check(&self) -> Result<WeightsVerdict, MeshError> {
        for (name, x) in [("alpha", self.alpha), ("beta", self.beta), ("gamma", self.gamma)] {
            if !x.is_finite() {
                return Err(MeshError::Weights(format!("{name} = {x} is not a finite number")));
            }
        }
        let named = format!(
            "alpha = {}, beta = {}, gamma = {} (opposite corner {})",
            self.alpha,
            self.beta,
            self.gamma,
            self.delta()
        );
        let [l1, l2, _] = self.face_eigenvalues();
        if l1 >= 1.0 || l2 >= 1.0 {
            return Err(MeshError::Weights(format!(
                "{named}: the face rule has eigenvalues of modulus {l1:.6} (twice) and {l2:.6} on the differences; \
                 one is not below 1, so faces do not shrink to points: the subdivision diverges"
            )));
        }
        if self.beta != self.gamma {
            return Ok(WeightsVerdict::Undecided(format!(
                "{named}: beta ≠ gamma makes the quad rule chiral; its convergence is not decided beyond the face rule's eigenvalues"
            )));
        }
        let Some(design) = crate::builtin_design("doo_sabin_quad") else {
            return Ok(WeightsVerdict::Undecided("the regular patch is not available".into()));
        };
        let values =
            [("alpha", self.alpha), ("beta", self.beta), ("gamma", self.gamma)].map(|(n, v)| (n.to_string(), v));
        let instance = crate::instantiate(&design, &values).map_err(|e| MeshError::Weights(format!("{named}: {e}")))?;
        match crate::analysis::jsr(&instance.automaton, &crate::analysis::JsrSettings::quick()) {
            Ok(bounds) => match bounds.verdict() {
                crate::analysis::Verdict::Converges => Ok(WeightsVerdict::Converges),
                crate::analysis::Verdict::Diverges => Err(MeshError::Weights(format!(
                    "{named}: the regular patch diverges ({}): choose weights inside the convergence domain",
                    bounds.witness_text()
                ))),
                crate::analysis::Verdict::Undecided => {
                    Ok(WeightsVerdict::Undecided(format!("{named}: convergence is undecided ({bounds})")))
                }
            },
            Err(e) => Ok(WeightsVerdict::Undecided(format!("{named}: {e}"))),
        }
    }
}
