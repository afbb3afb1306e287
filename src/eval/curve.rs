//! Curves and point sets: every root cell expanded to a fixed depth (in
//! memory in parallel, or streamed a subtree at a time), or adaptively
//! until its control polygon is smaller than a tolerance; polylines join
//! the samples of edge cells.

use std::io;

use super::ball::Balls;
use super::prepared::{Evaluator, diameter, mul_into, project_into};
use super::settings::{EvalError, MAX_ADAPTIVE_DEPTH};
use crate::geometry::Sink;
use crate::progress::Steps;
use crate::space::CellKind;

/// Largest number of samples a streamed subtree holds in memory at once.
const STREAM_CHUNK: usize = 1 << 16;

/// A curve being streamed: the sink, a reusable chunk buffer, and the
/// number of vertices written so far.
struct CurveStream<'s> {
    sink: &'s mut dyn Sink,
    buf: Vec<f64>,
    vertices: &'s mut usize,
    /// A lacunar curve's leaves, joined where one starts at the end of the one before.
    runs: Option<&'s mut Runs>,
}

/// The polylines of a lacunar curve (each leaf emits its two ends): a leaf
/// that starts where the one before it ends (parts that share an end, as
/// `T3 b1 = T4 b0` says) continues its polyline, sharing that vertex;
/// the others start a polyline of their own.
pub(super) struct Runs {
    /// Two ends within this distance are one point (the constraint holds to rounding).
    q: f64,
    /// The end of the last leaf, empty before the first.
    last: Vec<f64>,
    /// The vertices of each polyline, in order.
    lengths: Vec<usize>,
}

impl Runs {
    /// No leaf yet: ends within `q` are one point.
    pub(super) fn new(q: f64) -> Runs {
        Runs { q, last: Vec::new(), lengths: Vec::new() }
    }

    /// Joins the leaves in `buf` (each its start then its end, `d`
    /// coordinates a point) to the polylines so far, keeping in `buf` only
    /// the points written: a start equal to the end before it is dropped.
    pub(super) fn join(&mut self, d: usize, buf: &mut Vec<f64>) {
        let mut kept = 0;
        for leaf in 0..buf.len() / (2 * d) {
            let (a, b) = (leaf * 2 * d, leaf * 2 * d + d);
            let continues = !self.last.is_empty() && (0..d).all(|i| (buf[a + i] - self.last[i]).abs() <= self.q);
            match self.lengths.last_mut().filter(|_| continues) {
                Some(n) => *n += 1,
                None => {
                    buf.copy_within(a..a + d, kept);
                    kept += d;
                    self.lengths.push(2);
                }
            }
            buf.copy_within(b..b + d, kept);
            kept += d;
            self.last.clear();
            self.last.extend_from_slice(&buf[kept - d..kept]);
        }
        buf.truncate(kept);
    }

    /// Writes the polylines from vertex `first` on, and forgets them.
    fn write(&mut self, first: usize, sink: &mut dyn Sink) -> io::Result<()> {
        let mut at = first;
        for n in self.lengths.drain(..) {
            sink.polyline(at, n, false)?;
            at += n;
        }
        self.last.clear();
        Ok(())
    }
}

impl Evaluator {
    pub(super) fn curves_fixed(&self, k: usize, sink: &mut dyn Sink, in_memory: bool) -> Result<(), EvalError> {
        let d = self.pieces.dim;
        let threads = self.pool.current_num_threads();
        let mut first_vertex = 0usize;
        let count = self.pieces.pieces.len();
        let mut steps = Steps::new(self.settings.progress.as_ref(), count as u64);
        let mut run_start = 0usize;
        for (pi, piece) in self.pieces.pieces.iter().enumerate() {
            self.check_cancel()?;
            let sp = self.plan.state(piece.state);
            let is_edge = sp.kind == CellKind::Edge && sp.end.is_some();
            let joined = is_edge && self.pieces.connected;
            if pi == 0 || !joined {
                sink.object(&piece.name)?;
            }
            let mut runs = self.runs(piece);
            if in_memory {
                let mut out = Vec::new();
                self.fill_piece(pi, k, &mut out);
                if let Some(runs) = runs.as_mut() {
                    runs.join(d, &mut out);
                }
                sink.vertices(d, &out, None)?;
                first_vertex += out.len() / d;
            } else {
                // Streaming: one subtree at a time, each at most a bounded chunk.
                let tasks = self.tasks(piece.state, piece.control.clone(), d, k, 16 * threads);
                let mut out =
                    CurveStream { sink: &mut *sink, buf: Vec::new(), vertices: &mut first_vertex, runs: runs.as_mut() };
                for (s, c, r) in tasks {
                    self.stream_subtree(s, &c, r, &mut out)?;
                }
            }
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start, runs.as_mut())?;
            steps.step();
        }
        Ok(())
    }

    /// The samples of a depth-`r` subtree of `state` with control points
    /// `c`, in chunks of at most `STREAM_CHUNK` points.
    fn stream_subtree(&self, state: usize, c: &[f64], r: usize, out: &mut CurveStream<'_>) -> io::Result<()> {
        let d = self.pieces.dim;
        let n = self.count(state, r);
        if n <= STREAM_CHUNK as u128 {
            out.buf.resize(n as usize * d, 0.0);
            self.fill(state, c, d, r, &mut out.buf);
            if let Some(runs) = out.runs.as_deref_mut() {
                runs.join(d, &mut out.buf);
            }
            out.sink.vertices(d, &out.buf, None)?;
            *out.vertices += out.buf.len() / d;
            return Ok(());
        }
        let sp = self.plan.state(state);
        for (_, t, m) in &sp.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, sp.dim, m, nt, &mut child);
            self.stream_subtree(*t, &child, r - 1, out)?;
        }
        Ok(())
    }

    pub(super) fn curves_adaptive(&self, eps: f64, sink: &mut dyn Sink) -> Result<(), EvalError> {
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
            let ball =
                (sp.kind == CellKind::Free).then(|| Balls::of(&self.plan, piece.state, &piece.control, d)).flatten();
            // The samples of one piece are held in memory: bounded by the memory limit.
            let room = (self.settings.memory_limit / 8).saturating_sub(first_vertex * d);
            let run = Adaptive { d, eps, room, ball: ball.as_ref() };
            let estimate = self.probe(piece.state, &piece.control, &run);
            if estimate > 4 * room as u128 {
                return Err(EvalError::TooLarge {
                    estimate: estimate.saturating_mul(8),
                    limit: self.settings.memory_limit,
                });
            }
            let mut out = Vec::new();
            self.adaptive(piece.state, &piece.control, &run, 0, &mut out)?;
            let mut runs = self.runs(piece);
            if let Some(runs) = runs.as_mut() {
                runs.join(d, &mut out);
            }
            first_vertex += out.len() / d;
            sink.vertices(d, &out, None)?;
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start, runs.as_mut())?;
        }
        Ok(())
    }

    /// After the samples of `piece`: closes its polyline when it is an edge
    /// that ends a curve (the last piece of a connected curve, or any piece
    /// of a union), adding the end point unless the curve is closed. With
    /// dropped arrows the samples are a subset with gaps: points, no line.
    fn end_curve(
        &self,
        piece: &super::pieces::Piece,
        last: bool,
        sink: &mut dyn Sink,
        first_vertex: &mut usize,
        run_start: &mut usize,
        runs: Option<&mut Runs>,
    ) -> io::Result<()> {
        let sp = self.plan.state(piece.state);
        if let Some(runs) = runs {
            // A lacunar curve: its leaves' segments, joined where parts share an end.
            runs.write(*run_start, sink)?;
        }
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
        if self.settings.dropped.is_empty() {
            sink.polyline(*run_start, *first_vertex - *run_start, closed)?;
        }
        *run_start = *first_vertex;
        Ok(())
    }

    /// The polylines of `piece` when it is a lacunar curve drawn as lines
    /// (not with dropped arrows: those are points).
    fn runs(&self, piece: &super::pieces::Piece) -> Option<Runs> {
        let sp = self.plan.state(piece.state);
        let scale = piece.control.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        (sp.gapped && self.settings.dropped.is_empty())
            .then(|| Runs::new(crate::algebra::tolerance::SAME_POINT * scale))
    }

    /// The samples of a cell with control points `c`, subdivided until it is small.
    fn adaptive(
        &self,
        state: usize,
        c: &[f64],
        run: &Adaptive<'_>,
        level: usize,
        out: &mut Vec<f64>,
    ) -> Result<(), EvalError> {
        let sp = self.plan.state(state);
        let d = run.d;
        if level >= MAX_ADAPTIVE_DEPTH || run.small(state, c, sp.dim) || sp.children.is_empty() {
            let samples = run.samples(state, &self.tails[state][0]);
            let start = out.len();
            let len = samples.len() / sp.dim * d;
            if start + len > run.room {
                return Err(EvalError::TooLarge {
                    estimate: (start as u128 + 1) * 8,
                    limit: self.settings.memory_limit,
                });
            }
            out.resize(start + len, 0.0);
            project_into(c, d, sp.dim, samples, &mut out[start..]);
            return Ok(());
        }
        for (_, t, m) in &sp.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, sp.dim, m, nt, &mut child);
            self.adaptive(*t, &child, run, level + 1, out)?;
        }
        Ok(())
    }

    /// An estimate of the coordinates an adaptive run from the cell `c`
    /// writes (Knuth's estimator: the mean, over random descents, of the
    /// product of the branching factors met, times the leaf's samples),
    /// so that a tolerance whose output cannot fit is refused at once.
    fn probe(&self, state: usize, c: &[f64], run: &Adaptive<'_>) -> u128 {
        const PROBES: u32 = 256;
        let d = run.d;
        let mut rng = 0x9E37_79B9_7F4A_7C15u64;
        let mut total = 0f64;
        for _ in 0..PROBES {
            let (mut s, mut cell, mut weight) = (state, c.to_vec(), 1f64);
            for level in 0.. {
                let sp = self.plan.state(s);
                if level >= MAX_ADAPTIVE_DEPTH || run.small(s, &cell, sp.dim) || sp.children.is_empty() {
                    total += weight * (run.samples(s, &self.tails[s][0]).len() / sp.dim * d) as f64;
                    break;
                }
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                let (_, t, m) = &sp.children[(rng % sp.children.len() as u64) as usize];
                let nt = self.plan.state(*t).dim;
                let mut child = vec![0.0; d * nt];
                mul_into(&cell, d, sp.dim, m, nt, &mut child);
                weight *= sp.children.len() as f64;
                (s, cell) = (*t, child);
            }
        }
        (total / f64::from(PROBES)).min(u128::MAX as f64) as u128
    }
}

/// An adaptive run: point dimension, tolerance, coordinates the output may
/// hold before the memory limit, and the piece's invariant balls if it has them.
struct Adaptive<'b> {
    d: usize,
    eps: f64,
    room: usize,
    ball: Option<&'b Balls>,
}

impl Adaptive<'_> {
    /// Whether the cell `c` (`n` control points) is below the tolerance: its
    /// part of the attractor, bounded by the balls, for a plain IFS; its
    /// control polygon otherwise.
    fn small(&self, state: usize, c: &[f64], n: usize) -> bool {
        match self.ball {
            Some(b) => b.cell_diameter(state, c, self.d) < self.eps,
            None => diameter(c, self.d, n) < self.eps,
        }
    }

    /// What a leaf emits: its state's ball centre for a plain IFS, the state's samples otherwise.
    fn samples<'s>(&'s self, state: usize, own: &'s [f64]) -> &'s [f64] {
        self.ball.map_or(own, |b| b.centre(state))
    }
}
