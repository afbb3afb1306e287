//! An automaton prepared for deterministic evaluation with a model: the
//! plan of every state, the pieces of the model, the tabulated last levels
//! of the subdivision tree, the thread pool. Curves (`curve.rs`) and
//! surfaces (`surface.rs`) are evaluated from it; `evaluate.rs` chooses.
//!
//! Hot path: the last levels of the subdivision tree are tabulated once per
//! state (barycentric points of all leaf samples of a subtree), so a subtree
//! costs one `d × n` by `n × m` product; subtrees are spread over threads
//! with rayon and write into disjoint parts of a preallocated buffer.

use std::io;

use rayon::prelude::*;

use super::pieces::{Pieces, pieces};
use super::plan::Plan;
use super::settings::{Depth, EvalError, EvalSettings, MAX_DEPTH};
use crate::analysis::{JsrSettings, Verdict, jsr};
use crate::automaton::Automaton;
use crate::design::Model;
use crate::progress::Steps;
use crate::space::CellKind;

/// Largest number of leaf samples tabulated per state (fits in L2 cache).
const TAIL_POINTS: usize = 2048;
/// Deepest tabulated level (a state with one child never exceeds `TAIL_POINTS`).
const MAX_TAIL_LEVEL: usize = 16;

/// An automaton prepared for evaluation with a model.
pub struct Evaluator {
    /// What the convergence bounds say when they do not decide (empty when they prove convergence).
    pub(super) warnings: Vec<String>,
    pub(super) plan: Plan,
    pub(super) pieces: Pieces,
    /// tails[state][r]: leaf samples of a depth-r subtree, `n` barycentric coordinates each.
    pub(super) tails: Vec<Vec<Vec<f64>>>,
    /// counts[state][r]: number of leaf samples of a depth-r subtree (saturating).
    pub(super) counts: Vec<Vec<u128>>,
    pub(super) pool: rayon::ThreadPool,
    pub(super) settings: EvalSettings,
}

/// Refuses a fixed depth over [`MAX_DEPTH`].
fn check_depth(depth: Depth) -> Result<(), EvalError> {
    match depth {
        Depth::Fixed(k) if k > MAX_DEPTH => Err(EvalError::Unsupported(format!(
            "depth {k} is beyond any evaluation (at most {MAX_DEPTH}: two maps already give 2^{MAX_DEPTH} cells)"
        ))),
        _ => Ok(()),
    }
}

/// Refuses a system whose joint spectral radius bounds prove divergence
/// (unless `force`); a warning when they leave it undecided.
pub(super) fn convergence_warnings(automaton: &Automaton<f64>, force: bool) -> Result<Vec<String>, EvalError> {
    let Ok(bounds) = jsr(automaton, &JsrSettings::quick()) else {
        return Ok(Vec::new()); // not stochastic: the plan refuses it with a better message
    };
    match bounds.verdict() {
        Verdict::Converges => Ok(Vec::new()),
        Verdict::Diverges if !force => Err(EvalError::Diverges { witness: bounds.witness_text() }),
        Verdict::Diverges => {
            Ok(vec![format!("the subdivision diverges ({}); evaluated on request", bounds.witness_text())])
        }
        Verdict::Undecided => {
            Ok(vec![format!("convergence is undecided: {bounds}; the picture may not converge to an attractor")])
        }
    }
}

/// `C (d × n) · M (n × m)` into `out (d × m)`, all row-major.
#[inline]
pub(super) fn mul_into(c: &[f64], d: usize, n: usize, m: &[f64], cols: usize, out: &mut [f64]) {
    for a in 0..d {
        let row = &mut out[a * cols..(a + 1) * cols];
        row.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..n {
            let cai = c[a * n + i];
            if cai != 0.0 {
                for (x, mij) in row.iter_mut().zip(&m[i * cols..(i + 1) * cols]) {
                    *x += cai * mij;
                }
            }
        }
    }
}

/// Points `C · λ_j` for barycentric `λ_j` (`n` each, packed) into `out` (`d` each, packed).
#[inline]
/// A union of curves end to end (each piece starts where the previous one
/// ends, to rounding) is drawn as one polyline, closed when the last piece
/// ends where the first starts: a contour of Bézier arcs and segments.
fn join_union_curves(plan: &Plan, pieces: &mut Pieces) {
    let d = pieces.dim;
    let mut ends = Vec::with_capacity(pieces.pieces.len());
    for piece in &pieces.pieces {
        let sp = plan.state(piece.state);
        let (Some(start), Some(end)) = (sp.samples.first(), sp.end.as_ref()) else { return };
        if sp.kind != CellKind::Edge {
            return;
        }
        let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
        project_into(&piece.control, d, sp.dim, start, &mut a);
        project_into(&piece.control, d, sp.dim, end, &mut b);
        ends.push((a, b));
    }
    let scale = pieces.pieces.iter().flat_map(|p| p.control.iter()).fold(1.0f64, |m, x| m.max(x.abs()));
    let same = |p: &[f64], q: &[f64]| {
        p.iter().zip(q).all(|(x, y)| (x - y).abs() <= crate::algebra::tolerance::SAME_POINT * scale)
    };
    if ends.len() < 2 || !ends.windows(2).all(|w| same(&w[0].1, &w[1].0)) {
        return;
    }
    pieces.connected = true;
    pieces.closed = same(&ends[ends.len() - 1].1, &ends[0].0);
}

pub(super) fn project_into(c: &[f64], d: usize, n: usize, lambdas: &[f64], out: &mut [f64]) {
    match (d, n) {
        (2, 3) => {
            let (c0, c1) = (&c[0..3], &c[3..6]);
            for (o, l) in out.chunks_exact_mut(2).zip(lambdas.chunks_exact(3)) {
                o[0] = c0[0] * l[0] + c0[1] * l[1] + c0[2] * l[2];
                o[1] = c1[0] * l[0] + c1[1] * l[1] + c1[2] * l[2];
            }
        }
        _ => {
            for (o, l) in out.chunks_exact_mut(d).zip(lambdas.chunks_exact(n)) {
                for (a, x) in o.iter_mut().enumerate() {
                    *x = c[a * n..(a + 1) * n].iter().zip(l).map(|(p, q)| p * q).sum();
                }
            }
        }
    }
}

pub(super) fn diameter(c: &[f64], d: usize, n: usize) -> f64 {
    let mut best: f64 = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            let s: f64 = (0..d).map(|a| (c[a * n + i] - c[a * n + j]).powi(2)).sum();
            best = best.max(s);
        }
    }
    best.sqrt()
}

impl Evaluator {
    /// Prepares `automaton` with `model`: checks stochasticity and
    /// contractivity, cuts the pieces, tabulates the last levels. The
    /// model's start sets are used, except for the states that
    /// `settings.start` gives its own.
    ///
    /// # Errors
    /// See [`EvalError`].
    pub fn new(automaton: &Automaton<f64>, model: &Model, settings: EvalSettings) -> Result<Evaluator, EvalError> {
        let mut start: Vec<(String, Vec<Vec<f64>>)> =
            model.start.iter().filter(|(s, _)| !settings.start.iter().any(|(t, _)| t == s)).cloned().collect();
        start.extend(settings.start.iter().cloned());
        check_depth(settings.depth)?;
        let mut plan = Plan::new(automaton, &start)?;
        // Faces over the model's start sets (not over a set the settings replace).
        for (state, faces) in model.start_faces.iter().filter(|(s, _)| !settings.start.iter().any(|(t, _)| t == s)) {
            if let Some(sp) = plan.states.iter_mut().flatten().find(|sp| sp.name == *state) {
                sp.faces.clone_from(faces);
            }
        }
        let warnings = convergence_warnings(automaton, settings.force)?;
        for name in &settings.dropped {
            let found = plan.states.iter_mut().flatten().any(|s| {
                let before = s.children.len();
                s.children.retain(|(e, _, _)| automaton.arrow(*e).name != *name);
                s.quadrants.truncate(s.children.len());
                before != s.children.len()
            });
            if !found {
                return Err(EvalError::UnknownArrow(name.clone()));
            }
        }
        let mut pieces = pieces(automaton, model)?;
        // An attractor with no map is empty: nothing would be drawn or written.
        if let Some(p) = pieces.pieces.iter().find(|p| plan.state(p.state).children.is_empty()) {
            let name = &plan.state(p.state).name;
            let why = if settings.dropped.is_empty() {
                "has no subdivision arrow".to_string()
            } else {
                format!("has no subdivision arrow left once {} dropped", settings.dropped.join(", "))
            };
            return Err(EvalError::Unsupported(format!("the attractor of state `{name}` is empty: it {why}")));
        }
        if model.layout == crate::design::Layout::Union {
            join_union_curves(&plan, &mut pieces);
        }
        let kinds: Vec<CellKind> = pieces.pieces.iter().map(|p| plan.state(p.state).kind).collect();
        if kinds.contains(&CellKind::Face) && !settings.dropped.is_empty() {
            return Err(EvalError::Unsupported(
                "dropping arrows of a face leaves holes: the mesh cannot be welded".into(),
            ));
        }
        let threads = settings.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| io::Error::other(e.to_string()))?;
        let mut ev = Evaluator { warnings, plan, pieces, tails: Vec::new(), counts: Vec::new(), pool, settings };
        ev.tabulate();
        Ok(ev)
    }

    /// The same prepared evaluation at another depth (its plan, tables and
    /// verdict do not depend on the depth): what a picture that needs less
    /// than the depth asked for evaluates.
    ///
    /// # Errors
    /// A fixed depth beyond any evaluation.
    pub fn set_depth(&mut self, depth: Depth) -> Result<(), EvalError> {
        check_depth(depth)?;
        self.settings.depth = depth;
        Ok(())
    }

    /// Warnings about the input: the joint spectral radius bounds left
    /// convergence undecided (the picture may show no attractor).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The pieces of the model.
    pub fn pieces(&self) -> &Pieces {
        &self.pieces
    }

    fn tabulate(&mut self) {
        let size = self.plan.states.len();
        self.tails = vec![Vec::new(); size];
        self.counts = vec![Vec::new(); size];
        for (i, s) in self.plan.states.iter().enumerate() {
            if let Some(s) = s {
                self.tails[i].push(s.samples.concat());
                self.counts[i].push(s.samples.len() as u128);
            }
        }
        // Grow tables level by level while they stay small.
        loop {
            let mut grew = false;
            for i in 0..size {
                let Some(s) = &self.plan.states[i] else { continue };
                if s.kind == CellKind::Face {
                    continue;
                }
                let r = self.tails[i].len();
                // Faces have no table: a state with face children saturates.
                let total: u128 = s
                    .children
                    .iter()
                    .map(|(_, t, _)| self.counts[*t].get(r - 1).copied().unwrap_or(u128::MAX))
                    .fold(0, u128::saturating_add);
                if r > MAX_TAIL_LEVEL
                    || total as usize > TAIL_POINTS
                    || s.children.iter().any(|(_, t, _)| self.tails[*t].len() < r)
                {
                    continue;
                }
                let mut table = Vec::with_capacity(total as usize * s.dim);
                for (_, t, m) in &s.children {
                    let nt = self.plan.state(*t).dim;
                    for l in self.tails[*t][r - 1].chunks_exact(nt) {
                        table.extend((0..s.dim).map(|row| (0..nt).map(|j| m[row * nt + j] * l[j]).sum::<f64>()));
                    }
                }
                self.tails[i].push(table);
                self.counts[i].push(total);
                grew = true;
            }
            if !grew {
                break;
            }
        }
    }

    /// The number of leaf samples of a depth-`r` subtree of `state`
    /// (saturating): the tabulated count, or level by level from level 0
    /// (`O(r · arrows)`, no recursion).
    pub(super) fn count(&self, state: usize, r: usize) -> u128 {
        if let Some(c) = self.counts[state].get(r) {
            return *c;
        }
        let mut level: Vec<u128> = self.counts.iter().map(|c| c.first().copied().unwrap_or(0)).collect();
        for depth in 1..=r {
            level = (0..level.len())
                .map(|s| match (self.counts[s].get(depth), &self.plan.states[s]) {
                    (Some(c), _) => *c,
                    (None, Some(p)) => p.children.iter().fold(0u128, |a, (_, t, _)| a.saturating_add(level[*t])),
                    (None, None) => 0,
                })
                .collect();
        }
        level[state]
    }

    /// Fills `out` with the `d`-dimensional samples of the subtree of `state`
    /// with control points `c`, `r` levels deep.
    pub(super) fn fill(&self, state: usize, c: &[f64], d: usize, r: usize, out: &mut [f64]) {
        let s = self.plan.state(state);
        if let Some(tail) = self.tails[state].get(r) {
            project_into(c, d, s.dim, tail, out);
            return;
        }
        let mut offset = 0;
        let mut child = Vec::new();
        for (_, t, m) in &s.children {
            let nt = self.plan.state(*t).dim;
            child.resize(d * nt, 0.0);
            mul_into(c, d, s.dim, m, nt, &mut child);
            let len = self.count(*t, r - 1) as usize * d;
            self.fill(*t, &child, d, r - 1, &mut out[offset..offset + len]);
            offset += len;
        }
    }

    /// Subtrees at the level where there are enough of them to keep every
    /// thread busy: `(state, control points, remaining depth)`, in order.
    pub(super) fn tasks(
        &self,
        state: usize,
        c: Vec<f64>,
        d: usize,
        depth: usize,
        want: usize,
    ) -> Vec<(usize, Vec<f64>, usize)> {
        let mut level = vec![(state, c, depth)];
        while level.len() < want && level.iter().all(|(s, _, r)| *r > 0 && self.tails[*s].get(*r).is_none()) {
            let mut next = Vec::new();
            for (s, c, r) in level {
                let sp = self.plan.state(s);
                for (_, t, m) in &sp.children {
                    let nt = self.plan.state(*t).dim;
                    let mut child = vec![0.0; d * nt];
                    mul_into(&c, d, sp.dim, m, nt, &mut child);
                    next.push((*t, child, r - 1));
                }
            }
            level = next;
        }
        level
    }

    /// Whether the roots are volumes (solids: their evaluation is their boundary mesh).
    pub fn volumes(&self) -> bool {
        self.root_kind().is_ok_and(|k| k == CellKind::Volume)
    }

    pub(super) fn root_kind(&self) -> Result<CellKind, EvalError> {
        let mut kinds = self.pieces.pieces.iter().map(|p| self.plan.state(p.state).kind);
        let k = kinds.next().unwrap_or(CellKind::Free);
        Ok(k)
    }

    pub(super) fn uses_start_set(&self, state: usize) -> bool {
        self.settings.start.iter().any(|(n, _)| *n == self.plan.state(state).name)
    }

    /// Bytes the in-memory output of a fixed-depth evaluation would take.
    pub fn estimate_bytes(&self, depth: usize) -> u128 {
        let d = self.pieces.dim as u128;
        match self.root_kind() {
            Ok(CellKind::Face) if !self.pieces.pieces.iter().any(|p| self.uses_start_set(p.state)) => {
                // Sub-faces per face: split² for a full grid, fewer for a lace (the carpet keeps 8 of 9).
                let root = self.plan.state(self.pieces.pieces[0].state);
                let split = root.split.max(2) as u128;
                // A face plan without a full grid (split 0): its subdivision arrows when more than
                // a 2×2 split's (a lace: the carpet keeps 8 of 9), never fewer (an estimate stays an upper one).
                let children = match root.split {
                    0 => (root.children.len() as u128).max(split * split),
                    _ => split * split,
                };
                let n = children.saturating_pow(depth.min(120) as u32);
                let cells = (self.pieces.pieces.len() as u128).saturating_mul(n);
                // positions + normals + uvs (8 bytes each) and two index quads.
                cells.saturating_mul((d + 3 + 2) * 8 + 64)
            }
            Ok(CellKind::Volume) => {
                // A volume's leaves are meshed by their faces (six for a hexahedron), welded.
                let cells =
                    self.pieces.pieces.iter().fold(0u128, |n, p| n.saturating_add(self.face_cells(p.state, depth)));
                cells.saturating_mul(6 * 4 * (8 * d + 16))
            }
            _ => self
                .pieces
                .pieces
                .iter()
                .map(|p| self.count(p.state, depth).saturating_add(1))
                .fold(0u128, |a, b| a.saturating_add(b))
                .saturating_mul(d * 8),
        }
    }

    /// Bytes of OBJ text a streamed fixed-depth evaluation would write, roughly
    /// (a vertex with its normal and a quad: ~200 bytes; a curve or cloud
    /// point and its line record: ~70; a solid's cell at most 600, all its
    /// faces on the boundary): for refusing outputs that would not fit the
    /// disk before writing any.
    pub fn estimate_obj_bytes(&self, depth: usize) -> u128 {
        if let Ok(CellKind::Volume) = self.root_kind() {
            // A solid's cell writes at most its six faces (twelve STL triangles of 50 bytes, or
            // its corners and quads as text): 600 bytes, whatever the format.
            let cells = self.pieces.pieces.iter().fold(0u128, |n, p| n.saturating_add(self.face_cells(p.state, depth)));
            return cells.saturating_mul(600);
        }
        let per_cell: u128 = match self.root_kind() {
            Ok(CellKind::Face) => 200,
            _ => 70,
        };
        let d = self.pieces.dim as u128;
        let per_memory_cell = match self.root_kind() {
            Ok(CellKind::Face) => (d + 3 + 2) * 8 + 64,
            _ => d * 8,
        };
        (self.estimate_bytes(depth) / per_memory_cell.max(1)).saturating_mul(per_cell)
    }

    /// Quads of the mesh at depth `k` (saturating), or `None` when the
    /// output is not a mesh.
    pub fn quads_at(&self, k: usize) -> Option<u128> {
        if !self.meshes() {
            return None;
        }
        let split = self.plan.state(self.pieces.pieces[0].state).split.max(2) as u128;
        let side = split.saturating_pow(k.min(120) as u32);
        Some((self.pieces.pieces.len() as u128).saturating_mul(side.saturating_mul(side)))
    }

    /// Number of leaf samples of piece `piece` at depth `k` (points it fills).
    pub fn sample_count(&self, piece: usize, k: usize) -> usize {
        self.count(self.pieces.pieces[piece].state, k).min(usize::MAX as u128) as usize
    }

    /// The samples of every piece at depth `k` (saturating).
    pub fn total_samples(&self, k: usize) -> usize {
        (0..self.pieces.pieces.len()).fold(0usize, |a, p| a.saturating_add(self.sample_count(p, k)))
    }

    /// Fills `out` (resized to `sample_count(piece, k) · d`, reusing its
    /// allocation) with the leaf samples of one piece at depth `k`, in
    /// order, on the evaluator's threads: the hot path without the sink.
    pub fn fill_piece(&self, piece: usize, k: usize, out: &mut Vec<f64>) {
        let d = self.pieces.dim;
        let p = &self.pieces.pieces[piece];
        let threads = self.pool.current_num_threads();
        let tasks = self.tasks(p.state, p.control.clone(), d, k, 16 * threads);
        let len = self.sample_count(piece, k) * d;
        if out.capacity() >= len {
            out.resize(len, 0.0);
        } else {
            // Zeroed pages are mapped as the threads first write them, in parallel.
            *out = vec![0.0; len];
        }
        let mut slices = Vec::with_capacity(tasks.len());
        let mut rest = out.as_mut_slice();
        for (s, _, r) in &tasks {
            let (head, tail) = rest.split_at_mut(self.count(*s, *r) as usize * d);
            slices.push(head);
            rest = tail;
        }
        if threads == 1 {
            tasks.iter().zip(slices).for_each(|((s, c, r), slot)| self.fill(*s, c, d, *r, slot));
        } else {
            self.pool
                .install(|| tasks.par_iter().zip(slices).for_each(|((s, c, r), slot)| self.fill(*s, c, d, *r, slot)));
        }
    }

    /// What the output is made of, when it is one thing: `Some(true)` when
    /// every object is one polyline through all its vertices (curves: edge
    /// pieces, no dropped arrows), `Some(false)` when it is points only,
    /// `None` for a mesh or a mix.
    pub fn polylines(&self) -> Option<bool> {
        if self.meshes() || self.polygon_faces() {
            return None;
        }
        let line = |p: &super::pieces::Piece| {
            let sp = self.plan.state(p.state);
            sp.kind == CellKind::Edge && sp.end.is_some() && self.settings.dropped.is_empty()
        };
        let lines = self.pieces.pieces.iter().filter(|p| line(p)).count();
        match lines {
            0 => Some(false),
            n if n == self.pieces.pieces.len() => Some(true),
            _ => None,
        }
    }

    /// Whether the output is a quad mesh (face roots without start sets).
    pub(super) fn meshes(&self) -> bool {
        self.pieces
            .pieces
            .iter()
            .any(|p| self.plan.state(p.state).kind == CellKind::Face && !self.uses_start_set(p.state))
    }

    /// The smallest uniform depth at which every cell of every piece is
    /// below `eps`: each cell is followed, depth first, until its control
    /// points are within `eps` (the sub-cells of a cell whose matrices are
    /// stochastic and non-negative lie in its hull, so they stay below), in
    /// memory for one path of cells.
    ///
    /// # Errors
    /// A cell still larger than `eps` at depth 12.
    pub fn depth_for_tolerance(&self, eps: f64) -> Result<usize, EvalError> {
        self.depth_for_tolerance_within(eps, usize::MAX)
    }

    /// [`Evaluator::depth_for_tolerance`], stopped as soon as the cells
    /// already met would take more than `memory` bytes as a mesh in memory
    /// (the mesh at that depth has at least as many): a slowly contracting
    /// system is refused at the cost of the budget, not of its whole mesh.
    ///
    /// # Errors
    /// As [`Evaluator::depth_for_tolerance`]; [`EvalError::TooLarge`].
    pub fn depth_for_tolerance_within(&self, eps: f64, memory: usize) -> Result<usize, EvalError> {
        const MAX: usize = 12;
        let d = self.pieces.dim;
        /// The walk: the tolerance, and the cells that may still be met.
        struct Walk {
            eps: f64,
            left: u128,
        }
        // Depth needed below a cell, at most `MAX - level` (MAX + 1: not fine enough or over the budget).
        fn needed(ev: &Evaluator, state: usize, c: &[f64], d: usize, walk: &mut Walk, budget: usize) -> usize {
            let sp = ev.plan.state(state);
            if walk.left == 0 {
                return MAX + 1;
            }
            walk.left -= 1;
            if diameter(c, d, sp.dim) < walk.eps {
                return 0;
            }
            if budget == 0 {
                return MAX + 1;
            }
            let mut worst = 0;
            for (_, t, m) in &sp.children {
                let nt = ev.plan.state(*t).dim;
                let mut child = vec![0.0; d * nt];
                mul_into(c, d, sp.dim, m, nt, &mut child);
                worst = worst.max(1 + needed(ev, *t, &child, d, walk, budget - 1));
                if worst > MAX {
                    break;
                }
            }
            worst
        }
        let per_cell = (self.estimate_bytes(0) / self.pieces.pieces.len().max(1) as u128).max(1);
        let cells = memory as u128 / per_cell;
        let mut walk = Walk { eps, left: cells };
        let k =
            self.pieces.pieces.iter().map(|p| needed(self, p.state, &p.control, d, &mut walk, MAX)).max().unwrap_or(0);
        if walk.left == 0 {
            return Err(EvalError::TooLarge { estimate: (cells + 1) * per_cell, limit: memory });
        }
        if k > MAX {
            return Err(EvalError::Unsupported(format!(
                "surface cells are still larger than {eps} at depth {MAX}: raise the tolerance or give a depth"
            )));
        }
        Ok(k)
    }

    pub(super) fn plan(&self) -> &Plan {
        &self.plan
    }

    pub(super) fn pool(&self) -> &rayon::ThreadPool {
        &self.pool
    }

    pub(super) fn progress(&self, total: u64) -> Steps<'_> {
        Steps::new(self.settings.progress.as_ref(), total)
    }

    /// Whether the settings' cancel flag is set (work in progress skips what is left).
    pub(super) fn cancelled(&self) -> bool {
        self.settings.cancel.as_ref().is_some_and(crate::progress::Cancel::is_cancelled)
    }

    /// [`EvalError::Cancelled`] once the settings' cancel flag is set.
    pub(super) fn check_cancel(&self) -> Result<(), EvalError> {
        if self.cancelled() { Err(EvalError::Cancelled) } else { Ok(()) }
    }
}
