//! Subdivided meshes written as they are made: the net before the last
//! step is held in memory, the last step (the net, or Doo-Sabin's limit) goes
//! straight to the writer, so a depth-10 cube (6.3 million faces) needs the
//! memory of depth 9 only.

use std::io::{self, Write};

use super::polymesh::{MeshError, PolyMesh, Scheme};
use super::subdivide::{MeshOut, RuleWeights};
use super::topology::{BORDER, Topology};

/// Loop nets of more faces than this before the last step are written two
/// steps from the net before them (at depth 10 on the icosahedron: the
/// 1.3 million faces of depth 8 held instead of the 5.2 million of depth 9).
pub(crate) const TWO_STEPS_FROM: u128 = 1 << 18;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat<'a> {
    /// Wavefront OBJ, one object of this name, in the mesh's own axes.
    Obj(&'a str),
    /// OFF.
    Off,
}

/// A subdivision to run: the scheme, the steps, Doo-Sabin quad weights
/// (`None`: classic) and the in-memory limit in bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Subdivision {
    /// The scheme.
    pub scheme: Scheme,
    /// Steps.
    pub depth: usize,
    /// Doo-Sabin quad weights (`None`: classic).
    pub weights: Option<RuleWeights>,
    /// The most bytes the net before the last step may take.
    pub memory_limit: usize,
}

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Written {
    /// Vertices.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
}

/// Vertices and faces as text, in a buffer flushed by the megabyte.
struct Text<'w> {
    out: &'w mut dyn Write,
    buf: Vec<u8>,
    obj: bool,
    ryu: ryu::Buffer,
    written: Written,
    /// The face being written.
    corners: Vec<usize>,
}

impl Text<'_> {
    fn flush_if_full(&mut self) -> io::Result<()> {
        if self.buf.len() >= 1 << 20 {
            self.out.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    fn finish(self) -> io::Result<Written> {
        self.out.write_all(&self.buf)?;
        self.out.flush()?;
        Ok(self.written)
    }
}

impl MeshOut for Text<'_> {
    fn vertex(&mut self, p: [f64; 3]) -> io::Result<()> {
        if self.obj {
            self.buf.push(b'v');
        }
        for (a, x) in p.iter().enumerate() {
            if self.obj || a > 0 {
                self.buf.push(b' ');
            }
            let x = if *x == 0.0 { 0.0 } else { *x };
            self.buf.extend_from_slice(self.ryu.format_finite(x).as_bytes());
        }
        self.buf.push(b'\n');
        self.written.vertices += 1;
        self.flush_if_full()
    }

    fn face(&mut self, vertices: &mut dyn Iterator<Item = usize>) -> io::Result<()> {
        self.corners.clear();
        self.corners.extend(vertices);
        if self.corners.len() < 3 {
            // A digon (Doo-Sabin's face of a valence-2 vertex) is a doubled edge: no client takes it,
            // and the surface is closed without it (its two sides are one edge of the file).
            return Ok(());
        }
        let mut ints = itoa::Buffer::new();
        if self.obj {
            self.buf.push(b'f');
        } else {
            self.buf.extend_from_slice(ints.format(self.corners.len()).as_bytes());
        }
        let base = usize::from(self.obj);
        for &v in &self.corners {
            self.buf.push(b' ');
            self.buf.extend_from_slice(ints.format(v + base).as_bytes());
        }
        self.buf.push(b'\n');
        self.written.faces += 1;
        self.flush_if_full()
    }
}

impl PolyMesh {
    /// Writes the net after `job.depth` steps of `job.scheme` (or, with
    /// `limit`, the points of the limit surface at its vertices) to `out`,
    /// holding only the net before the last step in memory.
    ///
    /// # Errors
    /// That net over `memory_limit` (with the estimate), or a write error.
    pub fn write_subdivided(
        &self,
        job: &Subdivision,
        limit: bool,
        format: MeshFormat<'_>,
        out: &mut dyn Write,
    ) -> Result<Written, MeshError> {
        let Subdivision { scheme, depth, weights, memory_limit } = *job;
        let depth = if limit { depth.max(1) } else { depth };
        if limit && scheme == Scheme::DooSabin && !self.has_interior_vertex() {
            return Err(MeshError::NoInteriorVertex);
        }
        let obj = matches!(format, MeshFormat::Obj(_));
        let mut text = Text {
            out,
            buf: Vec::with_capacity(1 << 21),
            obj,
            ryu: ryu::Buffer::new(),
            written: Written { vertices: 0, faces: 0 },
            corners: Vec::new(),
        };
        let io = MeshError::Write;
        if let MeshFormat::Obj(name) = format {
            writeln!(
                text.buf,
                "# bcifs: {} {} of depth {depth}\no {name}",
                scheme.name(),
                if limit { "limit surface" } else { "net" }
            )
            .map_err(io)?;
        }
        if limit && scheme != Scheme::DooSabin {
            // Limit positions need the last net's neighbourhoods: in memory.
            let shape = self.limit_with(scheme, depth, weights, memory_limit)?;
            if !obj {
                let faces = shape.quads.len() + shape.triangles.len();
                writeln!(text.buf, "OFF\n{} {faces} 0", shape.vertex_count()).map_err(io)?;
            }
            for p in shape.positions.chunks_exact(3) {
                text.vertex([p[0], p[1], p[2]]).map_err(io)?;
            }
            for q in &shape.quads {
                text.face(&mut q.iter().map(|&v| v as usize)).map_err(io)?;
            }
            for tri in &shape.triangles {
                text.face(&mut tri.iter().copied()).map_err(io)?;
            }
            return text.finish().map_err(io);
        }
        if depth == 0 {
            if !obj {
                writeln!(text.buf, "OFF\n{} {} 0", self.positions.len(), self.face_count()).map_err(io)?;
            }
            for p in &self.positions {
                text.vertex(*p).map_err(io)?;
            }
            for f in self.faces() {
                text.face(&mut f.iter().copied()).map_err(io)?;
            }
            return text.finish().map_err(io);
        }
        if scheme == Scheme::Loop && !limit && depth >= 2 && self.estimate(scheme, depth - 1).0 > TWO_STEPS_FROM {
            // The last two steps from the net before them: a quarter of the memory.
            let net = self.subdivide_with(scheme, depth - 2, weights, memory_limit)?;
            let t = Topology::trusted(&net);
            if !obj {
                let (v, _) = net.last_step_counts(&t, scheme, false, depth - 2);
                let (nv, nf) = (net.positions.len(), net.face_count());
                writeln!(text.buf, "OFF\n{} {} 0", v + 2 * (v - nv) + 3 * nf, 16 * nf).map_err(io)?;
            }
            net.loop_twice_into(&t, weights.and_then(RuleWeights::triangle), &mut text).map_err(io)?;
            return text.finish().map_err(io);
        }
        let net = self.subdivide_with(scheme, depth - 1, weights, memory_limit)?;
        let t = Topology::trusted(&net);
        if !obj {
            let (v, f) = net.last_step_counts(&t, scheme, limit, depth - 1);
            writeln!(text.buf, "OFF\n{v} {f} 0").map_err(io)?;
        }
        if limit {
            net.doo_sabin_limit_into(&t, weights.and_then(RuleWeights::quad), &mut text)
        } else {
            net.step_into(scheme, depth - 1, &t, weights, &mut text)
        }
        .map_err(io)?;
        text.finish().map_err(io)
    }

    /// Vertices and faces the last step writes from this net.
    fn last_step_counts(&self, t: &Topology, scheme: Scheme, limit: bool, step: usize) -> (usize, usize) {
        let corners = self.corner_count();
        let interior_edges = (0..corners).filter(|&c| t.twin(c) != BORDER && c < t.twin(c)).count();
        let edges = (0..corners).filter(|&c| t.twin(c) == BORDER || c < t.twin(c)).count();
        let interior_vertices = (0..self.positions.len()).filter(|&v| t.first(v) != BORDER && !t.on_border(v)).count();
        let nf = self.face_count();
        match (scheme, limit) {
            (Scheme::DooSabin, false) => {
                // Digons (faces of interior vertices of valence 2, and what they become) are not written.
                let digons = self.faces().filter(|f| f.len() < 3).count()
                    + (0..self.positions.len())
                        .filter(|&v| t.first(v) != BORDER && !t.on_border(v) && t.valence(self, v) == 2)
                        .count();
                (corners, nf + interior_edges + interior_vertices - digons)
            }
            (Scheme::DooSabin, true) => {
                let quads = (0..corners).filter(|&c| {
                    let v = self.indices[c];
                    t.first(v) != BORDER && !t.on_border(v)
                });
                (nf + interior_edges + interior_vertices, quads.count())
            }
            (Scheme::CatmullClark, _) => (self.positions.len() + edges + nf, corners),
            (Scheme::Loop, _) => (self.positions.len() + edges, 4 * nf),
            (Scheme::Sqrt3, _) => {
                // On border-refining steps a face on the border has two points instead of one.
                let split = if step % 2 == 1 { edges - interior_edges } else { 0 };
                (self.positions.len() + nf + split, 2 * interior_edges + (edges - interior_edges))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::LoopWeights;
    use crate::mesh::subdivide::Builder;

    /// The faces of a mesh as position triples, each rotated to start at its
    /// smallest vertex (positions rounded to 1e-12), sorted.
    fn faces_by_position(m: &PolyMesh) -> Vec<Vec<[i64; 3]>> {
        let key = |v: usize| m.positions[v].map(|x| (x * 1e12).round() as i64);
        let mut out: Vec<Vec<[i64; 3]>> = m
            .faces()
            .map(|f| {
                let mut k: Vec<[i64; 3]> = f.iter().map(|&v| key(v)).collect();
                let first = (0..k.len()).min_by_key(|&i| k[i]).unwrap_or(0);
                k.rotate_left(first);
                k
            })
            .collect();
        out.sort();
        out
    }

    /// Two Loop steps written at once are two steps in memory, up to the
    /// numbering of the vertices (positions to 1e-12, faces and their
    /// orientation): closed and open meshes, valences 3 to 6, Loop's and other weights.
    #[test]
    fn two_loop_steps_at_once_are_two_steps() {
        let ico = PolyMesh::icosahedron();
        let open = PolyMesh::new(ico.positions.clone(), ico.faces().skip(3).map(<[usize]>::to_vec).collect()).unwrap();
        let tet = PolyMesh::new(
            vec![[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]],
            vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]],
        )
        .unwrap();
        for mesh in [ico, open, tet, PolyMesh::cube().triangulated()] {
            for weights in [None, Some(LoopWeights { w: 0.3, sigma: 0.9 })] {
                let once = mesh.subdivide_with(Scheme::Loop, 1, weights.map(Into::into), 1 << 30).unwrap();
                let t = Topology::trusted(&once);
                let mut out = Builder::with_capacity(0, 0);
                once.loop_twice_into(&t, weights, &mut out).unwrap();
                let ours = out.finish();
                let theirs = mesh.subdivide_with(Scheme::Loop, 3, weights.map(Into::into), 1 << 30).unwrap();
                assert_eq!(ours.positions.len(), theirs.positions.len());
                assert_eq!(faces_by_position(&ours), faces_by_position(&theirs));
            }
        }
    }
}
