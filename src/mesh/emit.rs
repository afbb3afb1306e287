//! The one output of every subdivision step: vertices then faces, held in
//! memory or pushed into a [`Sink`].

use std::io;

use super::polymesh::PolyMesh;
use crate::geometry::Sink;

/// What was written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Written {
    /// Vertices.
    pub vertices: usize,
    /// Faces (digons, which files leave out, not counted).
    pub faces: usize,
}

/// Where a subdivision step puts its mesh: vertices (numbered from 0 in
/// order), then faces of those numbers. Held in memory (the net of the next
/// step, or only the points), or pushed into a [`Sink`] in batches (the last
/// step of a streamed subdivision): the one output of every step.
pub(crate) struct Emit<'s> {
    positions: Vec<[f64; 3]>,
    starts: Vec<usize>,
    indices: Vec<usize>,
    /// Faces are kept (not for points only).
    faces: bool,
    sink: Option<&'s mut dyn Sink>,
    written: Written,
    /// The sink was told that every vertex was pushed.
    sealed: bool,
    /// The thread's ambient flag when the output was made ([`crate::progress::Cancel::scope`]).
    cancel: Option<crate::progress::Cancel>,
    /// Items pushed since the flag was last looked at.
    ticks: usize,
}

/// Vertices (and faces) pushed into a sink at a time.
const BATCH: usize = 1 << 14;

impl<'s> Emit<'s> {
    /// A mesh built in memory.
    pub(crate) fn memory(vertices: usize, corners: usize) -> Emit<'static> {
        let mut starts = Vec::with_capacity(corners / 3 + 2);
        starts.push(0);
        Emit {
            positions: Vec::with_capacity(vertices),
            starts,
            indices: Vec::with_capacity(corners),
            faces: true,
            sink: None,
            written: Written::default(),
            sealed: false,
            cancel: crate::progress::Cancel::ambient(),
            ticks: 0,
        }
    }

    /// The points of a step, its faces dropped.
    pub(crate) fn points() -> Emit<'static> {
        Emit { faces: false, ..Emit::memory(0, 0) }
    }

    /// Vertices and faces pushed into `sink` as they come, in batches.
    pub(crate) fn into_sink(sink: &'s mut dyn Sink) -> Emit<'s> {
        let mut starts = Vec::with_capacity(BATCH + 1);
        starts.push(0);
        Emit {
            positions: Vec::with_capacity(BATCH),
            starts,
            indices: Vec::with_capacity(4 * BATCH),
            faces: true,
            sink: Some(sink),
            written: Written::default(),
            sealed: false,
            cancel: crate::progress::Cancel::ambient(),
            ticks: 0,
        }
    }

    /// Counts `n` items pushed; every [`BATCH`] of them, an
    /// [`io::ErrorKind::Interrupted`] error once the ambient flag is set.
    #[inline]
    fn tick(&mut self, n: usize) -> io::Result<()> {
        self.ticks += n;
        if self.ticks < BATCH {
            return Ok(());
        }
        self.ticks = 0;
        self.cancel.as_ref().map_or(Ok(()), crate::progress::Cancel::check_io)
    }

    /// A vertex.
    #[inline]
    pub(crate) fn vertex(&mut self, p: [f64; 3]) -> io::Result<()> {
        self.tick(1)?;
        self.positions.push(p);
        self.written.vertices += 1;
        if self.sink.is_some() && self.positions.len() >= BATCH { self.push_vertices() } else { Ok(()) }
    }

    /// Vertices `point(0)`, …, `point(n − 1)`, in that order: computed a
    /// batch at a time on the threads of the current pool (the same numbers
    /// as one by one: each point is computed on its own).
    pub(crate) fn vertices_with(&mut self, n: usize, point: impl Fn(usize) -> [f64; 3] + Sync) -> io::Result<()> {
        self.vertices_of(0..n, |k| Some(point(k)))
    }

    /// The vertices `point(k)` of the `k` in `range` where it is `Some`, in
    /// order, computed as [`Emit::vertices_with`] computes them.
    pub(crate) fn vertices_of(
        &mut self,
        range: std::ops::Range<usize>,
        point: impl Fn(usize) -> Option<[f64; 3]> + Sync,
    ) -> io::Result<()> {
        use rayon::prelude::*;
        let mut at = range.start;
        while at < range.end {
            let end = (at + BATCH).min(range.end);
            self.tick(end - at)?;
            let before = self.positions.len();
            self.positions.par_extend((at..end).into_par_iter().filter_map(&point));
            self.written.vertices += self.positions.len() - before;
            if self.sink.is_some() && self.positions.len() >= BATCH {
                self.push_vertices()?;
            }
            at = end;
        }
        Ok(())
    }

    /// A face, its vertices counter-clockwise.
    #[inline]
    pub(crate) fn face(&mut self, vertices: impl IntoIterator<Item = usize>) -> io::Result<()> {
        self.tick(1)?;
        if !self.faces {
            return Ok(());
        }
        let before = self.indices.len();
        self.indices.extend(vertices);
        self.starts.push(self.indices.len());
        if self.indices.len() - before >= 3 {
            self.written.faces += 1;
        }
        if self.sink.is_some() && self.starts.len() > BATCH { self.push_faces() } else { Ok(()) }
    }

    fn push_vertices(&mut self) -> io::Result<()> {
        if let Some(sink) = self.sink.as_deref_mut()
            && !self.positions.is_empty()
        {
            sink.vertices(3, self.positions.as_flattened(), None)?;
            self.positions.clear();
        }
        Ok(())
    }

    /// Pushes the faces (after the vertices, so that every face's vertices
    /// came first; the first time, the sink hears that no vertex follows).
    fn push_faces(&mut self) -> io::Result<()> {
        self.push_vertices()?;
        if let Some(sink) = self.sink.as_deref_mut()
            && self.starts.len() > 1
        {
            if !self.sealed {
                sink.vertices_complete()?;
                self.sealed = true;
            }
            sink.polygons(&self.starts, &self.indices)?;
            self.starts.truncate(1);
            self.indices.clear();
        }
        Ok(())
    }

    /// Pushes what is left into the sink; what was written.
    pub(crate) fn flush(mut self) -> io::Result<Written> {
        self.push_faces()?;
        Ok(self.written)
    }

    /// The mesh built in memory.
    pub(crate) fn finish(self) -> PolyMesh {
        PolyMesh::from_flat(self.positions, self.starts, self.indices)
    }

    /// The points built in memory.
    pub(crate) fn into_points(self) -> Vec<[f64; 3]> {
        self.positions
    }
}
