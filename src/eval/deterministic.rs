//! Deterministic evaluation: expand every root cell to a fixed depth (or
//! until its control polygon is smaller than a tolerance) and emit what each
//! leaf cell's kind asks for.
//!
//! Hot path: the last levels of the subdivision tree are tabulated once per
//! state (barycentric points of all leaf samples of a subtree), so a subtree
//! costs one `d × n` by `n × m` product; subtrees are spread over threads
//! with rayon and write into disjoint parts of a preallocated buffer.

use std::io;

use rayon::prelude::*;

use super::pieces::{ModelError, Pieces, pieces};
use super::plan::{Plan, PlanError};
use crate::automaton::Automaton;
use crate::design::Model;
use crate::geometry::{Shape, Sink};
use crate::progress::{Progress, Steps};
use crate::space::CellKind;

/// Default in-memory output limit: 4 GiB.
pub const DEFAULT_MEMORY_LIMIT: usize = 4 << 30;
/// Default depth.
pub const DEFAULT_DEPTH: usize = 8;
/// Deepest level the adaptive mode goes to, whatever the tolerance.
pub const MAX_ADAPTIVE_DEPTH: usize = 40;
/// Largest number of leaf samples tabulated per state (fits in L2 cache).
const TAIL_POINTS: usize = 2048;
/// Largest number of samples a streamed subtree holds in memory at once.
const STREAM_CHUNK: usize = 1 << 16;
/// Deepest tabulated level (a state with one child never exceeds `TAIL_POINTS`).
const MAX_TAIL_LEVEL: usize = 16;

/// How deep to evaluate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Depth {
    /// Every root cell to exactly this depth.
    Fixed(usize),
    /// Until every cell's control polygon has diameter below this (modelling units).
    Tolerance(f64),
}

/// Settings of an evaluation.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct EvalSettings {
    /// Depth or tolerance.
    pub depth: Depth,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// In-memory output larger than this (bytes) is refused.
    pub memory_limit: usize,
    /// Start sets: barycentric points per state name, emitted at leaves instead of the kind's default.
    pub start: Vec<(String, Vec<Vec<f64>>)>,
    /// Subdivision arrows to leave out (a subset of the attractor).
    pub dropped: Vec<String>,
    /// Told how far a long evaluation is (`None`: nobody listens).
    pub progress: Option<Progress>,
}

impl Default for EvalSettings {
    fn default() -> EvalSettings {
        EvalSettings {
            depth: Depth::Fixed(DEFAULT_DEPTH),
            threads: None,
            memory_limit: DEFAULT_MEMORY_LIMIT,
            start: Vec::new(),
            dropped: Vec::new(),
            progress: None,
        }
    }
}

impl EvalSettings {
    /// With a fixed depth.
    pub fn with_depth(mut self, depth: usize) -> Self {
        self.depth = Depth::Fixed(depth);
        self
    }
    /// With a tolerance.
    pub fn with_tolerance(mut self, eps: f64) -> Self {
        self.depth = Depth::Tolerance(eps);
        self
    }
    /// With a thread count.
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
    }
    /// With a memory limit in bytes.
    pub fn with_memory_limit(mut self, bytes: usize) -> Self {
        self.memory_limit = bytes;
        self
    }
    /// With a start set for a state.
    pub fn with_start(mut self, state: &str, points: Vec<Vec<f64>>) -> Self {
        self.start.push((state.to_string(), points));
        self
    }
    /// With a progress callback.
    pub fn with_progress(mut self, progress: Progress) -> Self {
        self.progress = Some(progress);
        self
    }
    /// Without the given subdivision arrows.
    pub fn without(mut self, arrows: &[&str]) -> Self {
        self.dropped.extend(arrows.iter().map(|s| s.to_string()));
        self
    }
}

/// Where an evaluation writes: a shape in memory (whose buffers the mesher
/// reuses), or a streaming sink.
pub(super) enum Output<'a> {
    /// In memory, overwriting this shape.
    Memory(&'a mut Shape),
    /// Streamed in bounded batches.
    Stream(&'a mut dyn Sink),
}

/// Why an evaluation failed.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The automaton cannot be evaluated.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The model does not fit the automaton.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The output would not fit the memory limit.
    #[error("the output would take about {estimate} bytes ({:.1} GiB), over the in-memory limit of {:.1} GiB: lower the depth or stream it (`-o FILE.obj`)", *estimate as f64 / (1u64 << 30) as f64, *limit as f64 / (1u64 << 30) as f64)]
    TooLarge {
        /// Estimated bytes.
        estimate: u128,
        /// The limit.
        limit: usize,
    },
    /// A dropped arrow that does not exist.
    #[error("no subdivision arrow named `{0}` to drop")]
    UnknownArrow(String),
    /// Writing to the sink failed.
    #[error("cannot write the output: {0}")]
    Io(#[from] io::Error),
    /// Faces mixed with other root kinds, or a face evaluated adaptively past the limit.
    #[error("{0}")]
    Unsupported(String),
}

/// An automaton prepared for evaluation with a model.
pub struct Evaluator {
    plan: Plan,
    pieces: Pieces,
    /// tails[state][r]: leaf samples of a depth-r subtree, `n` barycentric coordinates each.
    tails: Vec<Vec<Vec<f64>>>,
    /// counts[state][r]: number of leaf samples of a depth-r subtree (saturating).
    counts: Vec<Vec<u128>>,
    pool: rayon::ThreadPool,
    settings: EvalSettings,
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

fn diameter(c: &[f64], d: usize, n: usize) -> f64 {
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
        let mut plan = Plan::new(automaton, &start)?;
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
        let pieces = pieces(automaton, model)?;
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
        let mut ev = Evaluator { plan, pieces, tails: Vec::new(), counts: Vec::new(), pool, settings };
        ev.tabulate();
        Ok(ev)
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
                let total: u128 =
                    s.children.iter().map(|(_, t, _)| self.counts[*t].get(r - 1).copied().unwrap_or(u128::MAX)).sum();
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

    fn count(&self, state: usize, r: usize) -> u128 {
        if let Some(c) = self.counts[state].get(r) {
            return *c;
        }
        let s = self.plan.state(state);
        s.children.iter().map(|(_, t, _)| self.count(*t, r - 1)).fold(0u128, |a, b| a.saturating_add(b))
    }

    /// Fills `out` with the `d`-dimensional samples of the subtree of `state`
    /// with control points `c`, `r` levels deep.
    fn fill(&self, state: usize, c: &[f64], d: usize, r: usize, out: &mut [f64]) {
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
    fn tasks(&self, state: usize, c: Vec<f64>, d: usize, depth: usize, want: usize) -> Vec<(usize, Vec<f64>, usize)> {
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

    fn root_kind(&self) -> Result<CellKind, EvalError> {
        let mut kinds = self.pieces.pieces.iter().map(|p| self.plan.state(p.state).kind);
        let k = kinds.next().unwrap_or(CellKind::Free);
        Ok(k)
    }

    fn uses_start_set(&self, state: usize) -> bool {
        self.settings.start.iter().any(|(n, _)| *n == self.plan.state(state).name)
    }

    /// Bytes the in-memory output of a fixed-depth evaluation would take.
    pub fn estimate_bytes(&self, depth: usize) -> u128 {
        let d = self.pieces.dim as u128;
        match self.root_kind() {
            Ok(CellKind::Face) if !self.pieces.pieces.iter().any(|p| self.uses_start_set(p.state)) => {
                let split = self.plan.state(self.pieces.pieces[0].state).split.max(2) as u128;
                let n = split.saturating_pow(depth.min(120) as u32);
                let cells = (self.pieces.pieces.len() as u128).saturating_mul(n.saturating_mul(n));
                // positions + normals + uvs (8 bytes each) and two index quads.
                cells.saturating_mul((d + 3 + 2) * 8 + 64)
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

    /// Number of leaf samples of piece `piece` at depth `k` (points it fills).
    pub fn sample_count(&self, piece: usize, k: usize) -> usize {
        self.count(self.pieces.pieces[piece].state, k).min(usize::MAX as u128) as usize
    }

    /// Fills `out` (resized to `sample_count(piece, k) · d`, reusing its
    /// allocation) with the leaf samples of one piece at depth `k`, in
    /// order, on the evaluator's threads: the hot path without the sink.
    pub fn fill_piece(&self, piece: usize, k: usize, out: &mut Vec<f64>) {
        let d = self.pieces.dim;
        let p = &self.pieces.pieces[piece];
        let threads = self.pool.current_num_threads();
        let tasks = self.tasks(p.state, p.control.clone(), d, k, 16 * threads);
        out.resize(self.sample_count(piece, k) * d, 0.0);
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

    /// Evaluates into memory.
    ///
    /// # Errors
    /// An output over the memory limit (with the estimate), or an unsupported combination.
    pub fn evaluate(&self) -> Result<Shape, EvalError> {
        let mut shape = Shape::default();
        self.evaluate_into(&mut shape)?;
        Ok(shape)
    }

    /// Evaluates into `shape`, reusing its buffers: re-evaluating a mesh of
    /// the same size (a parameter changed) allocates nothing.
    ///
    /// # Errors
    /// As [`Evaluator::evaluate`].
    pub fn evaluate_into(&self, shape: &mut Shape) -> Result<(), EvalError> {
        if let Depth::Fixed(k) = self.settings.depth {
            let estimate = self.estimate_bytes(k);
            if estimate > self.settings.memory_limit as u128 {
                return Err(EvalError::TooLarge { estimate, limit: self.settings.memory_limit });
            }
        }
        // The mesher overwrites the shape's buffers in place; the other outputs start afresh.
        if !self.meshes() {
            *shape = Shape::default();
        }
        self.run(Output::Memory(shape))
    }

    /// Whether the output is a quad mesh (face roots without start sets).
    fn meshes(&self) -> bool {
        self.pieces
            .pieces
            .iter()
            .any(|p| self.plan.state(p.state).kind == CellKind::Face && !self.uses_start_set(p.state))
    }

    /// Evaluates into any sink, streaming: memory stays bounded whatever
    /// the depth. The caller finishes the sink (an
    /// [`crate::export::ObjWriter`] by its consuming `finish`).
    ///
    /// # Errors
    /// A write error of the sink, or an unsupported combination.
    pub fn stream(&self, sink: &mut dyn Sink) -> Result<(), EvalError> {
        self.run(Output::Stream(sink))
    }

    fn run(&self, out: Output<'_>) -> Result<(), EvalError> {
        if self.meshes() {
            let depth = match self.settings.depth {
                Depth::Fixed(k) => k,
                Depth::Tolerance(eps) => self.depth_for_tolerance(eps)?,
            };
            return super::surface::mesh(self, depth, out);
        }
        let in_memory = matches!(out, Output::Memory(_));
        let sink: &mut dyn Sink = match out {
            Output::Memory(shape) => shape,
            Output::Stream(sink) => sink,
        };
        match self.settings.depth {
            Depth::Fixed(k) => self.curves_fixed(k, sink, in_memory),
            Depth::Tolerance(eps) => self.curves_adaptive(eps, sink),
        }
    }

    /// The smallest uniform depth at which every cell of every piece is below `eps`.
    fn depth_for_tolerance(&self, eps: f64) -> Result<usize, EvalError> {
        let d = self.pieces.dim;
        let mut level: Vec<(usize, Vec<f64>)> =
            self.pieces.pieces.iter().map(|p| (p.state, p.control.clone())).collect();
        for k in 0..=12 {
            if level.iter().all(|(s, c)| diameter(c, d, self.plan.state(*s).dim) < eps) {
                return Ok(k);
            }
            let mut next = Vec::new();
            for (s, c) in &level {
                let sp = self.plan.state(*s);
                for (_, t, m) in &sp.children {
                    let nt = self.plan.state(*t).dim;
                    let mut child = vec![0.0; d * nt];
                    mul_into(c, d, sp.dim, m, nt, &mut child);
                    next.push((*t, child));
                }
            }
            level = next;
        }
        Err(EvalError::Unsupported(format!(
            "surface cells are still larger than {eps} at depth 12: raise the tolerance or give a depth"
        )))
    }

    fn curves_fixed(&self, k: usize, sink: &mut dyn Sink, in_memory: bool) -> Result<(), EvalError> {
        let d = self.pieces.dim;
        let threads = self.pool.current_num_threads();
        let mut first_vertex = 0usize;
        let count = self.pieces.pieces.len();
        let mut steps = Steps::new(self.settings.progress.as_ref(), count as u64);
        let mut run_start = 0usize;
        for (pi, piece) in self.pieces.pieces.iter().enumerate() {
            let sp = self.plan.state(piece.state);
            let is_edge = sp.kind == CellKind::Edge && sp.end.is_some();
            let joined = is_edge && self.pieces.connected;
            if pi == 0 || !joined {
                sink.object(&piece.name)?;
            }
            let tasks = self.tasks(piece.state, piece.control.clone(), d, k, 16 * threads);
            if in_memory {
                let total: usize = tasks.iter().map(|(s, _, r)| self.count(*s, *r) as usize).sum();
                let mut out = vec![0.0; total * d];
                let mut slices = Vec::with_capacity(tasks.len());
                let mut rest = out.as_mut_slice();
                for (s, _, r) in &tasks {
                    let (head, tail) = rest.split_at_mut(self.count(*s, *r) as usize * d);
                    slices.push(head);
                    rest = tail;
                }
                self.pool.install(|| {
                    tasks.par_iter().zip(slices).for_each(|((s, c, r), slot)| self.fill(*s, c, d, *r, slot));
                });
                sink.vertices(d, &out, None)?;
                first_vertex += total;
            } else {
                // Streaming: one subtree at a time, each at most a bounded chunk.
                let mut buf = Vec::new();
                for (s, c, r) in tasks {
                    self.stream_subtree(s, &c, d, r, &mut buf, sink, &mut first_vertex)?;
                }
            }
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start)?;
            steps.step();
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn stream_subtree(
        &self,
        state: usize,
        c: &[f64],
        d: usize,
        r: usize,
        buf: &mut Vec<f64>,
        sink: &mut dyn Sink,
        first_vertex: &mut usize,
    ) -> io::Result<()> {
        let n = self.count(state, r);
        if n <= STREAM_CHUNK as u128 {
            buf.resize(n as usize * d, 0.0);
            self.fill(state, c, d, r, buf);
            sink.vertices(d, buf, None)?;
            *first_vertex += n as usize;
            return Ok(());
        }
        let sp = self.plan.state(state);
        for (_, t, m) in &sp.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, sp.dim, m, nt, &mut child);
            self.stream_subtree(*t, &child, d, r - 1, buf, sink, first_vertex)?;
        }
        Ok(())
    }

    fn curves_adaptive(&self, eps: f64, sink: &mut dyn Sink) -> Result<(), EvalError> {
        let d = self.pieces.dim;
        let mut first_vertex = 0usize;
        let mut run_start = 0usize;
        let count = self.pieces.pieces.len();
        for (pi, piece) in self.pieces.pieces.iter().enumerate() {
            let sp = self.plan.state(piece.state);
            let joined = sp.kind == CellKind::Edge && sp.end.is_some() && self.pieces.connected;
            if pi == 0 || !joined {
                sink.object(&piece.name)?;
            }
            let mut out = Vec::new();
            self.adaptive(piece.state, &piece.control, d, eps, 0, &mut out);
            first_vertex += out.len() / d;
            sink.vertices(d, &out, None)?;
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start)?;
        }
        Ok(())
    }

    /// After the samples of `piece`: closes its polyline when it is an edge
    /// that ends a curve (the last piece of a connected curve, or any piece
    /// of a union), adding the end point unless the curve is closed.
    fn end_curve(
        &self,
        piece: &super::pieces::Piece,
        last: bool,
        sink: &mut dyn Sink,
        first_vertex: &mut usize,
        run_start: &mut usize,
    ) -> io::Result<()> {
        let sp = self.plan.state(piece.state);
        let Some(end) = sp.end.as_ref().filter(|_| sp.kind == CellKind::Edge) else {
            *run_start = *first_vertex;
            return Ok(());
        };
        let connected = self.pieces.connected;
        if connected && !last {
            return Ok(());
        }
        let closed = connected && self.pieces.closed;
        if !closed {
            let d = self.pieces.dim;
            let mut p = vec![0.0; d];
            project_into(&piece.control, d, sp.dim, end, &mut p);
            sink.vertices(d, &p, None)?;
            *first_vertex += 1;
        }
        sink.polyline(*run_start, *first_vertex - *run_start, closed)?;
        *run_start = *first_vertex;
        Ok(())
    }

    fn adaptive(&self, state: usize, c: &[f64], d: usize, eps: f64, level: usize, out: &mut Vec<f64>) {
        let sp = self.plan.state(state);
        if level >= MAX_ADAPTIVE_DEPTH || diameter(c, d, sp.dim) < eps || sp.children.is_empty() {
            let start = out.len();
            out.resize(start + sp.samples.len() * d, 0.0);
            project_into(c, d, sp.dim, &self.tails[state][0], &mut out[start..]);
            return;
        }
        for (_, t, m) in &sp.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, sp.dim, m, nt, &mut child);
            self.adaptive(*t, &child, d, eps, level + 1, out);
        }
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
}
