//! Welded quad meshes of face automata (`p × p` splits: 2×2 for the quad
//! patch, 3×3 for ternary schemes) over grids of patches.
//!
//! At depth `k` every patch is a `p^k × p^k` lattice of quads. The lattice
//! of all patches is cut into square blocks of `B = p^L` quads; each lattice
//! vertex is *owned* by exactly one block (the one it is the lower-left
//! corner of; the far row and column of an open sheet come last), which
//! gives it one index: neighbouring patches share their boundary vertices by
//! construction, and on a torus the lattice wraps. A block's points are
//! `C · Λ_L`, with `Λ_L` the tabulated barycentric lattice of a depth-`L`
//! subtree, and `C` the control points of the block's cell, reached from
//! its patch by the sub-face path given by the base-`p` digits of its block
//! coordinates.

use rayon::prelude::*;

use super::deterministic::{EvalError, Evaluator, mul_into as mat_mul_into, project_into as project};
use crate::geometry::{Buffers, Quad, Sink};

/// Blocks have at most `BLOCK_SIDE` quads on a side (33² lattice points, 9 coordinates each: ~80 KB).
const BLOCK_SIDE: usize = 32;
/// Blocks computed in parallel before their output is pushed to the sink.
const BATCH_BLOCKS: usize = 256;

struct Lattice {
    /// Patches along v (rows) and u (columns); torus or open sheet.
    pr: usize,
    pc: usize,
    torus: bool,
    /// Quads per patch side, per block side; blocks per patch side.
    n: usize,
    b: usize,
    s: usize,
}

impl Lattice {
    fn nu(&self) -> usize {
        self.pc * self.n
    }
    fn nv(&self) -> usize {
        self.pr * self.n
    }
    fn owned(&self) -> usize {
        self.pr * self.pc * self.n * self.n
    }
    fn vertex_count(&self) -> usize {
        self.owned() + if self.torus { 0 } else { self.nu() + self.nv() + 1 }
    }
    /// Where block `g` is: its patch, its block coordinates in the patch and
    /// its first lattice vertex.
    fn block(&self, g: usize) -> Block {
        let patch = g / (self.s * self.s);
        let (bv, bu) = ((g % (self.s * self.s)) / self.s, g % self.s);
        let (pv, pu) = (patch / self.pc, patch % self.pc);
        Block { patch, bu, bv, u0: pu * self.n + bu * self.b, v0: pv * self.n + bv * self.b }
    }

    /// The index of lattice vertex `(u, v)` (global lattice coordinates).
    fn index(&self, u: usize, v: usize) -> usize {
        let (nu, nv) = (self.nu(), self.nv());
        let (u, v) = if self.torus { (u % nu, v % nv) } else { (u, v) };
        if !self.torus && u == nu {
            return if v < nv { self.owned() + v } else { self.owned() + nv + u };
        }
        if !self.torus && v == nv {
            return self.owned() + nv + u;
        }
        let (pu, ru) = (u / self.n, u % self.n);
        let (pv, rv) = (v / self.n, v % self.n);
        let block = ((pv * self.pc + pu) * self.s + rv / self.b) * self.s + ru / self.b;
        block * self.b * self.b + (rv % self.b) * self.b + ru % self.b
    }
}

/// The position of a block of the lattice (see [`Lattice::block`]).
struct Block {
    patch: usize,
    bu: usize,
    bv: usize,
    u0: usize,
    v0: usize,
}

/// A vertex of the far row or column of an open sheet: `(index, position, normal)`.
type Extra = (usize, Vec<f64>, [f64; 3]);

fn normal(d: usize, du: &[f64], dv: &[f64]) -> [f64; 3] {
    if d < 3 {
        return [0.0, 0.0, 1.0];
    }
    let n = [du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 { [n[0] / len, n[1] / len, n[2] / len] } else { [0.0, 0.0, 1.0] }
}

pub(super) fn mesh(ev: &Evaluator, k: usize, sink: &mut dyn Sink, in_memory: bool) -> Result<(), EvalError> {
    let pieces = ev.pieces();
    let plan = ev.plan();
    let d = pieces.dim;
    let (pr, pc, torus) = match pieces.grid {
        Some(g) => g,
        None if pieces.pieces.len() == 1 => (1, 1, false),
        None => return Err(EvalError::Unsupported("several face pieces need a grid or torus layout".into())),
    };
    let state = pieces.pieces[0].state;
    if pieces.pieces.iter().any(|p| p.state != state) {
        return Err(EvalError::Unsupported("all patches of a mesh must have the same root state".into()));
    }
    let sp = plan.state(state);
    let n9 = sp.dim;
    let p = sp.split;
    let mut level = 0;
    while level < k && p.pow(level as u32 + 1) <= BLOCK_SIDE {
        level += 1;
    }
    let pow = |e: usize| p.pow(e as u32);
    let lat = Lattice { pr, pc, torus, n: pow(k), b: pow(level), s: pow(k - level) };

    // Λ_r: barycentric lattice of a depth-r subtree, (p^r + 1)² points, row v then column u.
    let mut table: Vec<f64> = [0usize, 1, 3, 2].iter().flat_map(|&c| sp.samples[c].clone()).collect();
    for r in 1..=level {
        let (side, half) = (pow(r) + 1, pow(r - 1));
        let prev = pow(r - 1) + 1;
        let mut next = vec![0.0; side * side * n9];
        for ((_, _, m), &(du, dv)) in sp.children.iter().zip(&sp.quadrants) {
            for v in 0..prev {
                for u in 0..prev {
                    let l = &table[(v * prev + u) * n9..(v * prev + u + 1) * n9];
                    let at = ((dv * half + v) * side + du * half + u) * n9;
                    for row in 0..n9 {
                        next[at + row] = (0..n9).map(|j| m[row * n9 + j] * l[j]).sum();
                    }
                }
            }
        }
        table = next;
    }
    let side = lat.b + 1;
    let mut child_of = vec![0usize; p * p];
    for (i, &(du, dv)) in sp.quadrants.iter().enumerate() {
        child_of[dv * p + du] = i;
    }

    let mut recycled = if in_memory { sink.recycle().unwrap_or_default() } else { Buffers::default() };
    sink.object("surface")?;
    // Texture coordinates: the natural parameterisation of each patch.
    let np = lat.n + 1;
    let uv_range = |from: usize, to: usize| -> Vec<f64> {
        (from..to).flat_map(|i| [(i % np) as f64 / lat.n as f64, (i / np) as f64 / lat.n as f64]).collect()
    };
    // Every patch has the same parameterisation: one shared table of (p^k + 1)² texture points.
    if in_memory {
        let mut uvs = std::mem::take(&mut recycled.uvs);
        uvs.clear();
        uvs.extend(uv_range(0, np * np));
        sink.uvs_owned(uvs)?;
    } else {
        // Fixed-size chunks: memory does not grow with the depth.
        const UV_CHUNK: usize = 1 << 15;
        for from in (0..np * np).step_by(UV_CHUNK) {
            sink.uvs(&uv_range(from, (from + UV_CHUNK).min(np * np)))?;
        }
    }

    let blocks = pr * pc * lat.s * lat.s;
    let batch = if in_memory { blocks } else { BATCH_BLOCKS };
    let mut steps = ev.progress((blocks / batch.max(1)).max(1) as u64);
    let mut extras: Vec<Extra> = Vec::new();
    let bb = lat.b * lat.b;
    // Writes block `g`: its owned positions, normals, quads and texture quads
    // into the given slices; returns the far-boundary vertices it touches.
    let compute = |g: usize, pos: &mut [f64], nrm: &mut [f64]| -> Vec<Extra> {
        let Block { patch, bu, bv, u0, v0 } = lat.block(g);
        // Control points of the block's cell: follow the base-p digits of its coordinates.
        let mut c = pieces.pieces[patch].control.clone();
        let mut tmp = vec![0.0; d * n9];
        let steps = k - level;
        for t in 0..steps {
            let place = pow(steps - 1 - t);
            let q = (bv / place % p) * p + bu / place % p;
            mat_mul_into(&c, d, n9, &sp.children[child_of[q]].2, n9, &mut tmp);
            std::mem::swap(&mut c, &mut tmp);
        }
        let mut pts = vec![0.0; side * side * d];
        project(&c, d, n9, &table, &mut pts);
        let at = |u: usize, v: usize| (v * side + u) * d;
        let mut extras = Vec::new();
        let (mut du, mut dv) = ([0.0; 3], [0.0; 3]);
        for v in 0..side {
            for u in 0..side {
                let (gu, gv) = (u0 + u, v0 + v);
                let owned = u < lat.b && v < lat.b;
                if !owned && (torus || (gu != lat.nu() && gv != lat.nv())) {
                    continue;
                }
                // Forward differences inside the block, backward on its far side.
                let (a, b) = if u < lat.b { (at(u + 1, v), at(u, v)) } else { (at(u, v), at(u - 1, v)) };
                let (e, f) = if v < lat.b { (at(u, v + 1), at(u, v)) } else { (at(u, v), at(u, v - 1)) };
                for x in 0..d {
                    du[x] = pts[a + x] - pts[b + x];
                    dv[x] = pts[e + x] - pts[f + x];
                }
                let n = normal(d, &du[..d], &dv[..d]);
                let p = &pts[at(u, v)..at(u, v) + d];
                if owned {
                    let o = v * lat.b + u;
                    pos[o * d..(o + 1) * d].copy_from_slice(p);
                    nrm[o * 3..o * 3 + 3].copy_from_slice(&n);
                } else {
                    extras.push((lat.index(gu, gv), p.to_vec(), n));
                }
            }
        }
        extras
    };
    let (mut pos, mut nrm) = (Vec::new(), Vec::new());
    // Quads in memory hold u32 indices (the in-memory limit keeps them below 2^32: half the
    // memory of usize); streamed quads are usize (a streamed mesh may be larger).
    let (mut quads, mut quv): (Vec<[usize; 4]>, Vec<[usize; 4]>) = (Vec::new(), Vec::new());
    let (mut quads32, mut quv32): (Vec<Quad>, Vec<Quad>) = (Vec::new(), Vec::new());
    if in_memory && lat.vertex_count().max(np * np) > u32::MAX as usize {
        return Err(EvalError::Unsupported("an in-memory mesh needs fewer than 2^32 vertices: stream it".into()));
    }
    for start in (0..blocks).step_by(batch.max(1)) {
        let end = (start + batch).min(blocks);
        let count = (end - start) * bb;
        if in_memory {
            // The sink's earlier buffers when it has some (overwritten in place), else
            // fresh zeroed allocations: their pages are mapped as they are first written.
            fn reuse<T: Copy + Default>(mut v: Vec<T>, len: usize) -> Vec<T> {
                if v.len() == len {
                    v
                } else if v.capacity() >= len {
                    v.clear();
                    v.resize(len, T::default());
                    v
                } else {
                    vec![T::default(); len]
                }
            }
            pos = reuse(std::mem::take(&mut recycled.positions), count * d);
            nrm = reuse(std::mem::take(&mut recycled.normals), count * 3);
            quads32 = reuse::<Quad>(std::mem::take(&mut recycled.quads), count);
            quv32 = reuse::<Quad>(std::mem::take(&mut recycled.quad_uvs), count);
        } else {
            pos.resize(count * d, 0.0);
            nrm.resize(count * 3, 0.0);
            quads.resize(count, [0; 4]);
            quv.resize(count, [0; 4]);
        }
        let found: Vec<Extra> = ev.pool().install(|| {
            if in_memory {
                fill_batch(&lat, np, start, bb, d, &mut pos, &mut nrm, &mut quads32, &mut quv32, &compute)
            } else {
                fill_batch(&lat, np, start, bb, d, &mut pos, &mut nrm, &mut quads, &mut quv, &compute)
            }
        });
        extras.extend(found);
        if in_memory {
            sink.vertices_owned(d, std::mem::take(&mut pos), Some(std::mem::take(&mut nrm)))?;
            sink.faces_compact(std::mem::take(&mut quads32), Some(std::mem::take(&mut quv32)))?;
        } else {
            sink.vertices(d, &pos, Some(&nrm))?;
            sink.faces(&quads, Some(&quv))?;
        }
        steps.step();
    }
    if !torus {
        extras.sort_by_key(|e| e.0);
        extras.dedup_by_key(|e| e.0);
        debug_assert_eq!(extras.len(), lat.vertex_count() - lat.owned());
        let positions: Vec<f64> = extras.iter().flat_map(|e| e.1.iter().copied()).collect();
        let normals: Vec<f64> = extras.iter().flat_map(|e| e.2).collect();
        sink.vertices(d, &positions, Some(&normals))?;
    }
    drop(steps);
    Ok(())
}

/// An index type of quads: `u32` in memory, `usize` when streamed.
trait QuadIndex: Copy + Send {
    fn of(i: usize) -> Self;
}

impl QuadIndex for usize {
    fn of(i: usize) -> usize {
        i
    }
}

impl QuadIndex for u32 {
    fn of(i: usize) -> u32 {
        // Checked by the caller: in-memory meshes have fewer than 2^32 vertices.
        i as u32
    }
}

/// The quads and texture quads of block `g` (lattice offsets `u0`, `v0`).
fn block_quads<I: QuadIndex>(lat: &Lattice, np: usize, g: usize, quads: &mut [[I; 4]], quv: &mut [[I; 4]]) {
    let bb = lat.b * lat.b;
    let Block { bu, bv, u0, v0, .. } = lat.block(g);
    let base = g * bb;
    let of = I::of;
    for v in 0..lat.b {
        for u in 0..lat.b {
            let corner = if u + 1 < lat.b && v + 1 < lat.b {
                let i = base + v * lat.b + u;
                [of(i), of(i + 1), of(i + 1 + lat.b), of(i + lat.b)]
            } else {
                let (gu, gv) = (u0 + u, v0 + v);
                [
                    of(lat.index(gu, gv)),
                    of(lat.index(gu + 1, gv)),
                    of(lat.index(gu + 1, gv + 1)),
                    of(lat.index(gu, gv + 1)),
                ]
            };
            quads[v * lat.b + u] = corner;
            let (lu, lv) = (bu * lat.b + u, bv * lat.b + v);
            let t = lv * np + lu;
            quv[v * lat.b + u] = [of(t), of(t + 1), of(t + 1 + np), of(t + np)];
        }
    }
}

/// Computes the points and normals a block owns; returns the far-boundary vertices it touches.
type BlockPoints<'a> = dyn Fn(usize, &mut [f64], &mut [f64]) -> Vec<Extra> + Sync + 'a;

/// Fills a batch of blocks from `start` in parallel: points and normals by
/// `compute`, quads by [`block_quads`]; returns the far-boundary vertices.
#[allow(clippy::too_many_arguments)]
fn fill_batch<I: QuadIndex>(
    lat: &Lattice,
    np: usize,
    start: usize,
    bb: usize,
    d: usize,
    pos: &mut [f64],
    nrm: &mut [f64],
    quads: &mut [[I; 4]],
    quv: &mut [[I; 4]],
    compute: &BlockPoints,
) -> Vec<Extra> {
    pos.par_chunks_mut(bb * d)
        .zip(nrm.par_chunks_mut(bb * 3))
        .zip(quads.par_chunks_mut(bb))
        .zip(quv.par_chunks_mut(bb))
        .enumerate()
        .flat_map_iter(|(i, (((p, n), q), t))| {
            block_quads(lat, np, start + i, q, t);
            compute(start + i, p, n)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_indices_are_a_bijection() {
        for torus in [false, true] {
            let lat = Lattice { pr: 2, pc: 3, torus, n: 4, b: 2, s: 2 };
            let (nu, nv) = (lat.nu(), lat.nv());
            let (mu, mv) = if torus { (nu, nv) } else { (nu + 1, nv + 1) };
            let mut seen = vec![false; lat.vertex_count()];
            for v in 0..mv {
                for u in 0..mu {
                    let i = lat.index(u, v);
                    assert!(!seen[i], "index {i} twice");
                    seen[i] = true;
                }
            }
            assert!(seen.iter().all(|s| *s));
            if torus {
                assert_eq!(lat.index(nu, 1), lat.index(0, 1));
            }
        }
    }
}
