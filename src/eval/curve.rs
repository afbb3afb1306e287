//! Curves and point sets: every root cell expanded to a fixed depth (in
//! memory in parallel, or streamed a subtree at a time), or adaptively
//! until its control polygon is smaller than a tolerance; polylines join
//! the samples of edge cells.

use std::io;

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
            let sp = self.plan.state(piece.state);
            let is_edge = sp.kind == CellKind::Edge && sp.end.is_some();
            let joined = is_edge && self.pieces.connected;
            if pi == 0 || !joined {
                sink.object(&piece.name)?;
            }
            if in_memory {
                let mut out = Vec::new();
                self.fill_piece(pi, k, &mut out);
                sink.vertices(d, &out, None)?;
                first_vertex += out.len() / d;
            } else {
                // Streaming: one subtree at a time, each at most a bounded chunk.
                let tasks = self.tasks(piece.state, piece.control.clone(), d, k, 16 * threads);
                let mut out = CurveStream { sink: &mut *sink, buf: Vec::new(), vertices: &mut first_vertex };
                for (s, c, r) in tasks {
                    self.stream_subtree(s, &c, r, &mut out)?;
                }
            }
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start)?;
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
            out.sink.vertices(d, &out.buf, None)?;
            *out.vertices += n as usize;
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
            let mut out = Vec::new();
            // The samples of one piece are held in memory: bounded by the memory limit.
            let room = (self.settings.memory_limit / 8).saturating_sub(first_vertex * d);
            self.adaptive(piece.state, &piece.control, (d, eps, room), 0, &mut out)?;
            first_vertex += out.len() / d;
            sink.vertices(d, &out, None)?;
            self.end_curve(piece, pi + 1 == count, sink, &mut first_vertex, &mut run_start)?;
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
        if self.settings.dropped.is_empty() {
            sink.polyline(*run_start, *first_vertex - *run_start, closed)?;
        }
        *run_start = *first_vertex;
        Ok(())
    }

    /// The samples of a cell with control points `c`, subdivided until its
    /// control polygon is below `eps` (`(d, eps, room)`: point dimension,
    /// tolerance, coordinates `out` may hold before the memory limit).
    fn adaptive(
        &self,
        state: usize,
        c: &[f64],
        (d, eps, room): (usize, f64, usize),
        level: usize,
        out: &mut Vec<f64>,
    ) -> Result<(), EvalError> {
        let sp = self.plan.state(state);
        if level >= MAX_ADAPTIVE_DEPTH || diameter(c, d, sp.dim) < eps || sp.children.is_empty() {
            let start = out.len();
            if start + sp.samples.len() * d > room {
                return Err(EvalError::TooLarge {
                    estimate: (start as u128 + 1) * 8,
                    limit: self.settings.memory_limit,
                });
            }
            out.resize(start + sp.samples.len() * d, 0.0);
            project_into(c, d, sp.dim, &self.tails[state][0], &mut out[start..]);
            return Ok(());
        }
        for (_, t, m) in &sp.children {
            let nt = self.plan.state(*t).dim;
            let mut child = vec![0.0; d * nt];
            mul_into(c, d, sp.dim, m, nt, &mut child);
            self.adaptive(*t, &child, (d, eps, room), level + 1, out)?;
        }
        Ok(())
    }
}
