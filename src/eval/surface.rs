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

use nalgebra::Vector3;

/// A point or direction in space.
type DVec3 = Vector3<f64>;

/// `v` scaled to length 1; `None` when its length is 0, infinite or not a number.
use rayon::prelude::*;

use super::prepared::{Evaluator, mul_into as mat_mul_into, project_into as project};
use super::settings::EvalError;
use crate::geometry::{Shape, Sink};

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
        let block = self.block_at(u, v);
        block * self.b * self.b + (v % self.n % self.b) * self.b + u % self.n % self.b
    }

    /// The block that owns lattice vertex `(u, v)` (inside the lattice, no wrapping).
    fn block_at(&self, u: usize, v: usize) -> usize {
        let (pu, ru) = (u / self.n, u % self.n);
        let (pv, rv) = (v / self.n, v % self.n);
        ((pv * self.pc + pu) * self.s + rv / self.b) * self.s + ru / self.b
    }

    /// The lattice coordinate one step before `x` along an axis of `len`
    /// quads: wraps on a torus, none before the first row of a sheet.
    fn before(&self, x: usize, len: usize) -> Option<usize> {
        match x {
            0 if self.torus => Some(len - 1),
            0 => None,
            _ => Some(x - 1),
        }
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

/// The area vector of the quad `a, b, c, e` (lattice order (0,0), (1,0),
/// (1,1), (0,1)): half the cross product of its diagonals, along `du × dv`.
fn quad_area(a: &[f64], b: &[f64], c: &[f64], e: &[f64]) -> DVec3 {
    let v = |p: &[f64]| DVec3::new(p[0], p[1], p[2]);
    let (a, b, c, e) = (v(a), v(b), v(c), v(e));
    0.5 * (c - a).cross(&(e - b))
}

/// The normals of the triangles that hold corner `k` of the quad `q`
/// (lattice order, counter-clockwise) in either of its two splits into
/// triangles: the corner's own triangle and the two along the diagonal from
/// it. A client that splits the quad (trimesh, a renderer) shades with one
/// of them.
fn corner_triangles(q: &[DVec3; 4], k: usize) -> [DVec3; 3] {
    let at = |i: usize| q[(k + i) % 4];
    let tri = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(&(c - a));
    [tri(at(3), at(0), at(1)), tri(at(0), at(1), at(2)), tri(at(0), at(2), at(3))]
}

/// The unit normal of a vertex from the quads around it (`faces`: each
/// quad's corners and which of them is the vertex; `None` where there is
/// no quad): the sum of their area vectors (area weighting), unless on a
/// rough surface that points against one of the triangles a client may
/// split a quad into; then the centre of the smallest cap of the sphere
/// holding the unit normals of those triangles (spanned by one, two or three
/// of them), which agrees with every one whenever any direction does. `+z`
/// when all faces are degenerate.
fn agreeing_normal(faces: &[Option<([DVec3; 4], usize)>; 4]) -> DVec3 {
    let sum: DVec3 = faces.iter().flatten().map(|(q, _)| 0.5 * (q[2] - q[0]).cross(&(q[3] - q[1]))).sum();
    let triangles: Vec<DVec3> = faces.iter().flatten().flat_map(|(q, k)| corner_triangles(q, *k)).collect();
    crate::geometry::agreeing(sum, &triangles)
}

/// Everything a block needs, prepared once per evaluation.
struct Mesher<'a> {
    ev: &'a Evaluator,
    lat: Lattice,
    /// Control-point dimension, cell dimension, split, depth, tabulated levels.
    d: usize,
    n9: usize,
    p: usize,
    k: usize,
    level: usize,
    /// The face state's plan.
    state: usize,
    /// Λ_level: barycentric lattice of a depth-`level` subtree, `(p^level + 1)²` points.
    table: Vec<f64>,
    /// The child arrow at each quadrant `dv * p + du`.
    child_of: Vec<usize>,
    /// Write texture coordinates (one parameterization of the whole grid or torus).
    uv: bool,
    /// Reverse every quad and normal: a closed surface faces outwards.
    flip: bool,
}

/// The welded mesh of a face automaton at depth `k` into `shape`, reusing its buffers.
pub(super) fn mesh_into(ev: &Evaluator, k: usize, shape: &mut Shape) -> Result<(), EvalError> {
    Mesher::new(ev, k)?.fill_shape(shape)
}

/// The welded mesh of a face automaton at depth `k`, streamed to `sink` in fixed-size batches.
pub(super) fn mesh_stream(ev: &Evaluator, k: usize, sink: &mut dyn Sink) -> Result<(), EvalError> {
    Mesher::new(ev, k)?.stream(sink)
}

impl<'a> Mesher<'a> {
    fn new(ev: &'a Evaluator, k: usize) -> Result<Mesher<'a>, EvalError> {
        let pieces = ev.pieces();
        let (pr, pc, torus) = match pieces.grid {
            Some(g) => g,
            None if pieces.pieces.len() == 1 => (1, 1, false),
            None => return Err(EvalError::Unsupported("several face pieces need a grid or torus layout".into())),
        };
        let state = pieces.pieces[0].state;
        if pieces.pieces.iter().any(|p| p.state != state) {
            return Err(EvalError::Unsupported("all patches of a mesh must have the same root state".into()));
        }
        let sp = ev.plan().state(state);
        let (n9, p) = (sp.dim, sp.split);
        let mut level = 0;
        while level < k && p.pow(level as u32 + 1) <= BLOCK_SIDE {
            level += 1;
        }
        let pow = |e: usize| p.pow(e as u32);
        let lat = Lattice { pr, pc, torus, n: pow(k), b: pow(level), s: pow(k - level) };
        // Λ_r from Λ_{r-1}: each quadrant is a child's image of the previous lattice.
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
        let mut child_of = vec![0usize; p * p];
        for (i, &(du, dv)) in sp.quadrants.iter().enumerate() {
            child_of[dv * p + du] = i;
        }
        let flip = torus && signed_volume_of_corners(ev, state) < 0.0;
        Ok(Mesher { ev, lat, d: pieces.dim, n9, p, k, level, state, table, child_of, uv: ev.settings.uv, flip })
    }

    /// Points of the texture table: `(u, v)` over the whole grid or torus,
    /// `(nu + 1) × (nv + 1)` of them (a torus repeats its seam), `from..to`.
    fn uvs(&self, from: usize, to: usize) -> impl Iterator<Item = f64> + '_ {
        let (nu, nv) = (self.lat.nu(), self.lat.nv());
        (from..to).flat_map(move |i| [(i % (nu + 1)) as f64 / nu as f64, (i / (nu + 1)) as f64 / nv as f64])
    }

    fn uv_count(&self) -> usize {
        (self.lat.nu() + 1) * (self.lat.nv() + 1)
    }

    fn blocks(&self) -> usize {
        self.lat.pr * self.lat.pc * self.lat.s * self.lat.s
    }

    /// Block `g`: its owned positions and normals into the given slices;
    /// returns the far-boundary vertices it touches.
    /// The control points of block `g`'s cell: its patch's, followed down
    /// the base-`p` digits of the block coordinates.
    fn cell(&self, g: usize) -> Vec<f64> {
        let (d, n9, p) = (self.d, self.n9, self.p);
        let sp = self.ev.plan().state(self.state);
        let Block { patch, bu, bv, .. } = self.lat.block(g);
        let mut c = self.ev.pieces().pieces[patch].control.clone();
        let mut tmp = vec![0.0; d * n9];
        let steps = self.k - self.level;
        for t in 0..steps {
            let place = p.pow((steps - 1 - t) as u32);
            let q = (bv / place % p) * p + bu / place % p;
            mat_mul_into(&c, d, n9, &sp.children[self.child_of[q]].2, n9, &mut tmp);
            std::mem::swap(&mut c, &mut tmp);
        }
        c
    }

    /// The points of block `g` with the ring before it: `(b + 2)²` points,
    /// lattice `(u0 - 1 + i, v0 - 1 + j)` at `j * (b + 2) + i`; the ring
    /// comes from the neighbouring cells (NaN before the edge of a sheet).
    fn ringed_points(&self, g: usize) -> Vec<f64> {
        let (lat, d, n9) = (&self.lat, self.d, self.n9);
        let Block { u0, v0, .. } = lat.block(g);
        let (side, wide) = (lat.b + 1, lat.b + 2);
        let mut pts = vec![f64::NAN; wide * wide * d];
        let mut put = |c: &[f64], rows: std::ops::Range<usize>, cols: std::ops::Range<usize>, i0: usize, j0: usize| {
            for (j, v) in rows.enumerate() {
                let (from, to) = (v * side + cols.start, v * side + cols.end);
                let at = ((j0 + j) * wide + i0) * d;
                project(c, d, n9, &self.table[from * n9..to * n9], &mut pts[at..at + (to - from) * d]);
            }
        };
        put(&self.cell(g), 0..side, 0..side, 1, 1);
        let left = lat.before(u0, lat.nu());
        let below = lat.before(v0, lat.nv());
        if let Some(u) = left {
            put(&self.cell(lat.block_at(u, v0)), 0..side, lat.b - 1..lat.b, 0, 1);
        }
        if let Some(v) = below {
            put(&self.cell(lat.block_at(u0, v)), lat.b - 1..lat.b, 0..side, 1, 0);
        }
        if let (Some(u), Some(v)) = (left, below) {
            put(&self.cell(lat.block_at(u, v)), lat.b - 1..lat.b, lat.b - 1..lat.b, 0, 0);
        }
        pts
    }

    /// The area vectors of the quads of a ringed block: `(b + 1)²`, quad
    /// `(i, j)` (lower-left corner at ringed point `(i, j)`) at `j * (b + 1) + i`;
    /// zero where a corner is missing (before the edge of a sheet) and for
    /// planar sheets.
    fn quad_areas(&self, pts: &[f64]) -> Vec<DVec3> {
        let (d, wide) = (self.d, self.lat.b + 2);
        let mut areas = vec![DVec3::zeros(); (wide - 1) * (wide - 1)];
        if d < 3 {
            return areas;
        }
        let at = |i: usize, j: usize| &pts[(j * wide + i) * d..(j * wide + i + 1) * d];
        for j in 0..wide - 1 {
            for i in 0..wide - 1 {
                // A NaN corner makes a NaN area: counted as no face.
                let f = quad_area(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                areas[j * (wide - 1) + i] = if f.iter().all(|x| x.is_finite()) { f } else { DVec3::zeros() };
            }
        }
        areas
    }

    /// The unit normal at point `(i, j)` (both ≥ 1) of a ringed block, from
    /// the (up to four) quads around it (`areas` says which exist): see
    /// [`agreeing_normal`]; `+z` for planar sheets and degenerate points.
    fn area_normal(&self, pts: &[f64], areas: &[DVec3], i: usize, j: usize) -> [f64; 3] {
        if self.d < 3 {
            return [0.0, 0.0, 1.0];
        }
        let (q, wide, d) = (self.lat.b + 1, self.lat.b + 2, self.d);
        let at = |i: usize, j: usize| DVec3::from_column_slice(&pts[(j * wide + i) * d..(j * wide + i) * d + 3]);
        // Quad (qi, qj) and the corner of it that is point (i, j).
        let face = |qi: usize, qj: usize, k: usize| {
            (qi < q && qj < q && areas[qj * q + qi] != DVec3::zeros())
                .then(|| ([at(qi, qj), at(qi + 1, qj), at(qi + 1, qj + 1), at(qi, qj + 1)], k))
        };
        let n = agreeing_normal(&[face(i - 1, j - 1, 2), face(i, j - 1, 3), face(i - 1, j, 1), face(i, j, 0)]);
        let n = [n.x, n.y, n.z];
        if self.flip { n.map(|x| -x) } else { n }
    }

    fn block_points(&self, g: usize, pos: &mut [f64], nrm: &mut [f64]) -> Vec<Extra> {
        let (lat, d) = (&self.lat, self.d);
        let Block { u0, v0, .. } = lat.block(g);
        let (side, wide) = (lat.b + 1, lat.b + 2);
        let pts = self.ringed_points(g);
        let areas = self.quad_areas(&pts);
        let at = |u: usize, v: usize| ((v + 1) * wide + u + 1) * d;
        let mut extras = Vec::new();
        for v in 0..side {
            for u in 0..side {
                let (gu, gv) = (u0 + u, v0 + v);
                let owned = u < lat.b && v < lat.b;
                // A vertex of the far column (row) of a sheet comes from the block
                // above (right of) it when there is one: that block holds both
                // quads around it.
                let (far_u, far_v) = (!lat.torus && gu == lat.nu(), !lat.torus && gv == lat.nv());
                let kept = owned || (far_u && (v < lat.b || far_v)) || (far_v && u < lat.b);
                if !kept {
                    continue;
                }
                let n = self.area_normal(&pts, &areas, u + 1, v + 1);
                let q = &pts[at(u, v)..at(u, v) + d];
                if owned {
                    let o = v * lat.b + u;
                    pos[o * d..(o + 1) * d].copy_from_slice(q);
                    nrm[o * 3..o * 3 + 3].copy_from_slice(&n);
                } else {
                    extras.push((lat.index(gu, gv), q.to_vec(), n));
                }
            }
        }
        extras
    }

    /// Fills the blocks `start..` that the slices hold, in parallel: points
    /// and normals by [`Mesher::block_points`], quads by [`block_quads`],
    /// texture quads when asked; returns the far-boundary vertices.
    fn fill<I: QuadIndex>(&self, start: usize, out: BatchSlices<'_, I>) -> Vec<Extra> {
        let (bb, d) = (self.lat.b * self.lat.b, self.d);
        self.ev.pool().install(|| {
            if let Some(quv) = out.quv {
                quv.par_chunks_mut(bb).enumerate().for_each(|(i, t)| self.uv_quads(start + i, t));
            }
            out.pos
                .par_chunks_mut(bb * d)
                .zip(out.nrm.par_chunks_mut(bb * 3))
                .zip(out.quads.par_chunks_mut(bb))
                .enumerate()
                .flat_map_iter(|(i, ((p, n), q))| {
                    // Once cancelled, the blocks left are skipped (the caller reports it).
                    if self.ev.cancelled() {
                        return Vec::new();
                    }
                    block_quads(&self.lat, start + i, self.flip, q);
                    self.block_points(start + i, p, n)
                })
                .collect()
        })
    }

    /// The texture quads of block `g`: global lattice corners, no wrapping.
    fn uv_quads<I: QuadIndex>(&self, g: usize, quv: &mut [[I; 4]]) {
        let lat = &self.lat;
        let Block { u0, v0, .. } = lat.block(g);
        let tu = lat.nu() + 1;
        for v in 0..lat.b {
            for u in 0..lat.b {
                let t = (v0 + v) * tu + u0 + u;
                let q = [t, t + 1, t + 1 + tu, t + tu].map(I::of);
                quv[v * lat.b + u] = if self.flip { [q[0], q[3], q[2], q[1]] } else { q };
            }
        }
    }

    /// The far row and column of an open sheet, each vertex once, in index order.
    fn far_side(&self, mut extras: Vec<Extra>) -> (Vec<f64>, Vec<f64>) {
        extras.sort_by_key(|e| e.0);
        extras.dedup_by_key(|e| e.0);
        debug_assert_eq!(extras.len(), self.lat.vertex_count() - self.lat.owned());
        (extras.iter().flat_map(|e| e.1.iter().copied()).collect(), extras.iter().flat_map(|e| e.2).collect())
    }

    /// All blocks at once into the shape's own buffers (overwritten in
    /// place when the sizes repeat: no allocation, no page faults).
    fn fill_shape(&self, shape: &mut Shape) -> Result<(), EvalError> {
        let (d, lat) = (self.d, &self.lat);
        if lat.vertex_count().max(self.uv_count()) > u32::MAX as usize {
            return Err(EvalError::Unsupported("an in-memory mesh needs fewer than 2^32 vertices: stream it".into()));
        }
        let mut steps = self.ev.progress(1);
        let count = self.blocks() * lat.b * lat.b;
        // Same size: overwritten in place. Larger: a fresh zeroed allocation, whose
        // pages the kernel maps as the parallel fill first writes them (resizing
        // would touch them all on this one thread first).
        fn resized<T: Copy + Default>(v: &mut Vec<T>, len: usize) -> &mut [T] {
            if v.len() != len {
                if v.capacity() >= len {
                    v.clear();
                    v.resize(len, T::default());
                } else {
                    *v = vec![T::default(); len];
                }
            }
            v
        }
        shape.reuse_as_mesh(d, "surface");
        if self.uv {
            let n = self.uv_count();
            resized(&mut shape.uvs, n * 2).iter_mut().zip(self.uvs(0, n)).for_each(|(o, x)| *o = x);
        } else {
            shape.uvs.clear();
            shape.quad_uvs.clear();
        }
        let extras = self.fill::<u32>(
            0,
            BatchSlices {
                pos: resized(&mut shape.positions, count * d),
                nrm: resized(&mut shape.normals, count * 3),
                quads: resized(&mut shape.quads, count),
                quv: if self.uv { Some(resized(&mut shape.quad_uvs, count)) } else { None },
            },
        );
        self.ev.check_cancel()?;
        if !lat.torus {
            let (positions, normals) = self.far_side(extras);
            shape.positions.extend_from_slice(&positions);
            shape.normals.extend_from_slice(&normals);
        }
        shape.close_mesh();
        steps.step();
        Ok(())
    }

    /// Batches of blocks pushed to the sink as they are done: memory stays
    /// bounded whatever the depth.
    fn stream(&self, sink: &mut dyn Sink) -> Result<(), EvalError> {
        let (d, lat) = (self.d, &self.lat);
        sink.object("surface")?;
        if self.uv {
            // Fixed-size chunks of the texture table.
            const UV_CHUNK: usize = 1 << 15;
            let n = self.uv_count();
            for from in (0..n).step_by(UV_CHUNK) {
                sink.uvs(&self.uvs(from, (from + UV_CHUNK).min(n)).collect::<Vec<_>>())?;
            }
        }
        let blocks = self.blocks();
        let bb = lat.b * lat.b;
        let mut steps = self.ev.progress(blocks.div_ceil(BATCH_BLOCKS) as u64);
        let mut extras: Vec<Extra> = Vec::new();
        let (mut pos, mut nrm, mut quads, mut quv) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for start in (0..blocks).step_by(BATCH_BLOCKS) {
            let count = ((start + BATCH_BLOCKS).min(blocks) - start) * bb;
            pos.resize(count * d, 0.0);
            nrm.resize(count * 3, 0.0);
            quads.resize(count, [0usize; 4]);
            quv.resize(if self.uv { count } else { 0 }, [0usize; 4]);
            let uv = self.uv.then_some(quv.as_mut_slice());
            extras.extend(
                self.fill::<usize>(start, BatchSlices { pos: &mut pos, nrm: &mut nrm, quads: &mut quads, quv: uv }),
            );
            self.ev.check_cancel()?;
            sink.vertices(d, &pos, Some(&nrm))?;
            sink.faces(&quads, self.uv.then_some(quv.as_slice()))?;
            steps.step();
        }
        if !lat.torus {
            let (positions, normals) = self.far_side(extras);
            sink.vertices(d, &positions, Some(&normals))?;
        }
        Ok(())
    }
}

/// The output slices of a batch of blocks.
struct BatchSlices<'s, I> {
    pos: &'s mut [f64],
    nrm: &'s mut [f64],
    quads: &'s mut [[I; 4]],
    quv: Option<&'s mut [[I; 4]]>,
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

/// The quads of block `g` (counter-clockwise in the lattice, or reversed
/// when `flip`).
fn block_quads<I: QuadIndex>(lat: &Lattice, g: usize, flip: bool, quads: &mut [[I; 4]]) {
    let bb = lat.b * lat.b;
    let Block { u0, v0, .. } = lat.block(g);
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
            quads[v * lat.b + u] = if flip { [corner[0], corner[3], corner[2], corner[1]] } else { corner };
        }
    }
}

/// The signed volume enclosed by the quads of the patches' corners (the
/// coarsest picture of a closed surface): positive when the lattice
/// orientation faces outwards.
fn signed_volume_of_corners(ev: &Evaluator, state: usize) -> f64 {
    let pieces = ev.pieces();
    let sp = ev.plan().state(state);
    let (d, n) = (pieces.dim, sp.dim);
    if d < 3 {
        return 0.0;
    }
    let mut volume = 0.0;
    for piece in &pieces.pieces {
        // The face's samples are its corners in cyclic order: (0,0), (1,0), (1,1), (0,1).
        let corner = |c: usize| {
            let mut p = [0.0; 3];
            project(&piece.control, d, n, &sp.samples[c], &mut p);
            DVec3::from(p)
        };
        let [a, b, c, e] = [0usize, 1, 2, 3].map(corner);
        volume += (a.dot(&b.cross(&c)) + a.dot(&c.cross(&e))) / 6.0;
    }
    volume
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
