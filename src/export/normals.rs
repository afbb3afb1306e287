//! Vertex normals of a mesh too large to hold: its vertices and faces go
//! to side files as they are streamed, and are replayed into the real sink
//! with area-weighted normals computed a block at a time, so the memory
//! taken is that of the blocks, whatever the mesh's size.
//!
//! The normals are [`area_normals`]'s, bit for bit: each face's area
//! vector is computed from its corners in order ([`area_vector`]), each
//! vertex sums its faces' in face order, and the sums are normalised alike
//! ([`unit_or_zero`]). The passes over the side files:
//!
//! 1. the faces a chunk at a time: the chunk's corners sorted by stretch of
//!    the positions file (a counting sort), their points read from it in
//!    that order (only the stretches they fall in, each once: a subdivided
//!    mesh's faces in a row use vertices in a few runs), each face's area
//!    vector appended to a third side file and added to the sums of its
//!    corners in the first block of vertices, whose vertices are then pushed
//!    into the sink with their normals;
//! 2. for each further block of vertices (Loop's depth 10 on the icosahedron has two more),
//!    the faces and their area vectors read in order, each added to the
//!    sums of its corners in the block, the block pushed;
//! 3. the faces pushed into the sink, the groups between them.
//!
//! [`area_normals`]: crate::geometry::area_normals

use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom, Write};
use std::path::Path;

use super::atomic::Spool;
use crate::geometry::{Sink, area_vector, unit_or_zero};
use crate::progress::Cancel;

/// Bytes of a position (three `f64`) and of an area vector in the side files.
const POINT: usize = 24;

/// Vertices read from the positions file at a time while points are gathered.
const STRETCH: usize = 1 << 12;

/// Faces pushed into the sink at a time when they are replayed (a writer
/// formats a large call on several threads).
const FACE_BATCH: usize = 1 << 17;

/// Vertices pushed into the sink at a time.
const VERTEX_BATCH: usize = 1 << 18;

/// A [`Sink`] that keeps a streamed mesh (one object: vertices, then faces of
/// any degree) in side files beside the target, to be replayed with vertex
/// normals by [`NormalSpill::replay`]. The side files are removed whatever happens.
pub(crate) struct NormalSpill {
    name: String,
    /// Three little-endian `f64` a vertex.
    positions: Spool,
    /// A face's corner count, then its corners, little-endian `u32` each.
    faces: Spool,
    /// Three little-endian `f64` a face of three corners or more, in face order.
    areas: Spool,
    vertices: usize,
    face_count: usize,
    corners: usize,
    /// The most corners of a face.
    widest: usize,
}

/// Where the vertices and faces of a replay go: the sink, the groups of
/// faces (a name and the face it starts at, in order), the flag that stops
/// it, and the bytes the replay may take (a quarter for a chunk of faces,
/// the rest for the sums of a block of vertices).
pub(crate) struct Replay<'a> {
    pub(crate) sink: &'a mut dyn Sink,
    pub(crate) groups: &'a [(Option<String>, usize)],
    pub(crate) cancel: &'a Cancel,
    pub(crate) budget: usize,
}

fn too_many(what: &str) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("{what}: more than 2^32, which vertex normals streamed cannot index"),
    )
}

/// Reads `buf.len()` bytes or up to the end of `file`: how many.
fn fill(file: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut at = 0;
    while at < buf.len() {
        match file.read(&mut buf[at..]) {
            Ok(0) => break,
            Ok(n) => at += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(at)
}

fn point_at(bytes: &[u8]) -> [f64; 3] {
    let x = |k: usize| f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().expect("8 bytes"));
    [x(0), x(1), x(2)]
}

fn put_point(bytes: &mut [u8], p: [f64; 3]) {
    for (k, x) in p.iter().enumerate() {
        bytes[8 * k..8 * k + 8].copy_from_slice(&x.to_le_bytes());
    }
}

/// The faces of the faces side file, read in order, a face at a time.
struct Faces {
    file: File,
    /// Words read and not yet taken: `words[at..]`.
    words: Vec<usize>,
    at: usize,
    bytes: Vec<u8>,
    left: usize,
}

impl Faces {
    fn open(spill: &mut NormalSpill) -> io::Result<Faces> {
        let file = spill.faces.reader()?;
        Ok(Faces { file, words: Vec::new(), at: 0, bytes: vec![0; 1 << 20], left: spill.face_count })
    }

    /// The next face's corners, or `None` after the last.
    fn next(&mut self) -> io::Result<Option<&[usize]>> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        let n = match self.words.get(self.at) {
            Some(&n) if self.at + n < self.words.len() => n,
            _ => {
                // Refilled: the words left, then the next bytes of the file (a face's words whole).
                self.words.drain(..self.at);
                self.at = 0;
                while self.words.first().is_none_or(|&n| n + 1 > self.words.len()) {
                    let read = fill(&mut self.file, &mut self.bytes)?;
                    if read < 4 {
                        return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "the faces side file ended early"));
                    }
                    let words = self.bytes[..read - read % 4].chunks_exact(4);
                    self.words.extend(words.map(|w| u32::from_le_bytes(w.try_into().expect("4 bytes")) as usize));
                }
                self.words[0]
            }
        };
        let face = &self.words[self.at + 1..self.at + 1 + n];
        self.at += n + 1;
        Ok(Some(face))
    }
}

impl NormalSpill {
    /// Side files beside `target` (removed when this is dropped).
    pub(crate) fn create(target: &Path) -> io::Result<NormalSpill> {
        Ok(NormalSpill {
            name: String::new(),
            positions: Spool::create(target, "normals")?,
            faces: Spool::create(target, "normals")?,
            areas: Spool::create(target, "normals")?,
            vertices: 0,
            face_count: 0,
            corners: 0,
            widest: 0,
        })
    }

    fn face(&mut self, corners: impl ExactSizeIterator<Item = usize>) -> io::Result<()> {
        let n = corners.len();
        let w = self.faces.writer();
        w.write_all(&u32::try_from(n).map_err(|_| too_many("a face's corners"))?.to_le_bytes())?;
        for c in corners {
            if c >= self.vertices {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("corner {c} of a face: no such vertex"),
                ));
            }
            // Vertices are fewer than 2^32 (checked as they come).
            w.write_all(&(c as u32).to_le_bytes())?;
        }
        self.face_count += 1;
        self.corners += n;
        self.widest = self.widest.max(n);
        Ok(())
    }

    /// Pushes the mesh into `to.sink` with its vertex normals: the object,
    /// the vertices with their normals, then the faces (the groups at the
    /// faces they start at), each block within `to.budget` bytes.
    ///
    /// # Errors
    /// An I/O error of the side files or the sink's, or
    /// [`io::ErrorKind::Interrupted`] when `to.cancel` is set.
    pub(crate) fn replay(mut self, to: Replay<'_>) -> io::Result<()> {
        // A block's vertex: its sum (then normal), 24 bytes; a chunk's corner 40.
        let block = (to.budget / 4 * 3 / POINT).max(1);
        let block = self.vertices.div_ceil(self.vertices.div_ceil(block).max(1)).max(1);
        let chunk = (to.budget / 4 / 40).max(self.widest).max(1);
        let mut sums = self.areas_and_first_block(block, chunk, to.cancel)?;
        to.sink.object(&self.name)?;
        let mut positions = BufReader::with_capacity(1 << 20, self.positions.reader()?);
        let mut first = 0;
        while first < self.vertices {
            to.cancel.check_io()?;
            let end = (first + block).min(self.vertices);
            if first > 0 {
                self.sum_block(first..end, &mut sums)?;
            }
            sums.iter_mut().for_each(|n| *n = unit_or_zero(*n));
            push_vertices(&mut positions, &sums, to.sink)?;
            first = end;
        }
        drop(sums);
        to.sink.vertices_complete()?;
        let mut faces = Faces::open(&mut self)?;
        let (mut starts, mut corners) = (vec![0], Vec::with_capacity(4 * FACE_BATCH));
        let mut cuts = to.groups.iter().peekable();
        for f in 0..=self.face_count {
            // Groups start before face `f` (those past the last face, empty, after it).
            while let Some((name, _)) = cuts.next_if(|(_, at)| *at <= f || f == self.face_count) {
                if starts.len() > 1 {
                    to.sink.polygons(&starts, &corners)?;
                    starts.truncate(1);
                    corners.clear();
                }
                if let Some(name) = name {
                    to.sink.group(name)?;
                }
            }
            let Some(face) = faces.next()? else { break };
            corners.extend_from_slice(face);
            starts.push(corners.len());
            if starts.len() > FACE_BATCH {
                to.cancel.check_io()?;
                to.sink.polygons(&starts, &corners)?;
                starts.truncate(1);
                corners.clear();
            }
        }
        if starts.len() > 1 {
            to.sink.polygons(&starts, &corners)?;
        }
        Ok(())
    }

    /// Pass 1: the area vector of each face of three corners or more, in
    /// face order, into the areas side file, and the sums of the first
    /// `block` vertices; a chunk of faces at a time, each chunk's corners'
    /// points gathered in one ordered read of the positions.
    fn areas_and_first_block(&mut self, block: usize, chunk: usize, cancel: &Cancel) -> io::Result<Vec<[f64; 3]>> {
        let mut sums = vec![[0.0; 3]; block.min(self.vertices)];
        let mut faces = Faces::open(self)?;
        let mut file = self.positions.reader()?;
        let (mut sizes, mut vertices) = (Vec::new(), Vec::with_capacity(chunk.min(self.corners)));
        let (mut starts, mut order) = (Vec::new(), Vec::with_capacity(chunk.min(self.corners)));
        let mut points: Vec<[f64; 3]> = Vec::with_capacity(chunk.min(self.corners));
        let mut stretch = vec![0u8; POINT * STRETCH];
        let mut left = self.face_count;
        while left > 0 {
            cancel.check_io()?;
            sizes.clear();
            vertices.clear();
            while left > 0 && vertices.len() + self.widest <= chunk {
                let Some(face) = faces.next()? else { break };
                left -= 1;
                sizes.push(face.len());
                vertices.extend_from_slice(face);
            }
            // The corners by stretch of the positions (a counting sort), each stretch read once, in order.
            starts.clear();
            starts.resize(self.vertices.div_ceil(STRETCH) + 1, 0);
            vertices.iter().for_each(|&v| starts[v / STRETCH + 1] += 1);
            (1..starts.len()).for_each(|k| starts[k] += starts[k - 1]);
            order.resize(vertices.len(), 0);
            let mut fill_at = starts.clone();
            for (k, &v) in vertices.iter().enumerate() {
                order[fill_at[v / STRETCH]] = k;
                fill_at[v / STRETCH] += 1;
            }
            points.clear();
            points.resize(vertices.len(), [0.0; 3]);
            for (s, w) in starts.windows(2).enumerate().filter(|(_, w)| w[1] > w[0]) {
                file.seek(SeekFrom::Start((s * STRETCH * POINT) as u64))?;
                let n = fill(&mut file, &mut stretch)? / POINT;
                for &k in &order[w[0]..w[1]] {
                    let v = vertices[k] - s * STRETCH;
                    if v >= n {
                        return Err(io::Error::new(
                            io::ErrorKind::UnexpectedEof,
                            "the positions side file ended early",
                        ));
                    }
                    points[k] = point_at(&stretch[v * POINT..]);
                }
            }
            let (mut at, mut bytes) = (0, [0u8; POINT]);
            let areas = self.areas.writer();
            for &n in &sizes {
                if n >= 3 {
                    let area = area_vector(n, |k| points[at + k]);
                    put_point(&mut bytes, area);
                    areas.write_all(&bytes)?;
                    add_to(&mut sums, 0, &vertices[at..at + n], area);
                }
                at += n;
            }
        }
        Ok(sums)
    }

    /// Pass 2: the sums of the vertices `range`, from every face and its
    /// area vector read in order.
    fn sum_block(&mut self, range: std::ops::Range<usize>, sums: &mut Vec<[f64; 3]>) -> io::Result<()> {
        sums.clear();
        sums.resize(range.len(), [0.0; 3]);
        let mut faces = Faces::open(self)?;
        let mut areas = BufReader::with_capacity(1 << 20, self.areas.reader()?);
        let mut bytes = [0u8; POINT];
        while let Some(face) = faces.next()? {
            if face.len() >= 3 {
                areas.read_exact(&mut bytes)?;
                add_to(sums, range.start, face, point_at(&bytes));
            }
        }
        Ok(())
    }
}

/// Adds `area` to the sums (of the vertices from `first` on) of the corners
/// of `face` that have one, as [`area_normals`](crate::geometry::area_normals) adds it.
#[inline]
fn add_to(sums: &mut [[f64; 3]], first: usize, face: &[usize], area: [f64; 3]) {
    for &a in face {
        if let Some(s) = a.checked_sub(first).and_then(|k| sums.get_mut(k)) {
            (0..3).for_each(|c| s[c] += area[c]);
        }
    }
}

/// Pushes the next `normals.len()` vertices of `positions` into `sink` with
/// `normals`, a batch at a time.
fn push_vertices(positions: &mut impl Read, normals: &[[f64; 3]], sink: &mut dyn Sink) -> io::Result<()> {
    let mut bytes = vec![0u8; POINT * VERTEX_BATCH.min(normals.len())];
    let mut flat: Vec<f64> = Vec::with_capacity(3 * VERTEX_BATCH.min(normals.len()));
    for normals in normals.chunks(VERTEX_BATCH) {
        let bytes = &mut bytes[..POINT * normals.len()];
        positions.read_exact(bytes)?;
        flat.clear();
        flat.extend(bytes.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))));
        sink.vertices(3, &flat, Some(normals.as_flattened()))?;
    }
    Ok(())
}

impl Sink for NormalSpill {
    fn object(&mut self, name: &str) -> io::Result<()> {
        if self.vertices > 0 || !self.name.is_empty() {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, "vertex normals streamed: one object only"));
        }
        self.name = name.to_string();
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], _normals: Option<&[f64]>) -> io::Result<()> {
        let dim = dim.max(1);
        let count = positions.len() / dim;
        if u32::try_from(self.vertices + count).is_err() {
            return Err(too_many("vertices"));
        }
        let (w, mut bytes) = (self.positions.writer(), [0u8; POINT]);
        for p in positions.chunks_exact(dim) {
            put_point(&mut bytes, [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)]);
            w.write_all(&bytes)?;
        }
        self.vertices += count;
        Ok(())
    }

    fn uvs(&mut self, _uvs: &[f64]) -> io::Result<()> {
        Err(io::Error::new(io::ErrorKind::InvalidInput, "vertex normals streamed: no texture coordinates"))
    }

    fn polyline(&mut self, _first: usize, _count: usize, _closed: bool) -> io::Result<()> {
        Err(io::Error::new(io::ErrorKind::InvalidInput, "vertex normals streamed: faces only, no polylines"))
    }

    fn faces(&mut self, quads: &[[usize; 4]], _uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        quads.iter().try_for_each(|q| self.face(q.iter().copied()))
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        triangles.iter().try_for_each(|t| self.face(t.iter().copied()))
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        starts.windows(2).try_for_each(|w| self.face(corners[w[0]..w[1]].iter().copied()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::area_normals;

    /// What a replay pushed: the object, vertices and normals, faces, and
    /// each group with the number of faces before it.
    #[derive(Default)]
    struct Record {
        object: Vec<String>,
        positions: Vec<f64>,
        normals: Vec<f64>,
        starts: Vec<usize>,
        corners: Vec<usize>,
        groups: Vec<(String, usize)>,
        sealed: bool,
    }

    impl Sink for Record {
        fn object(&mut self, name: &str) -> io::Result<()> {
            self.object.push(name.into());
            Ok(())
        }
        fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
            assert!(dim == 3 && !self.sealed);
            self.positions.extend_from_slice(positions);
            self.normals.extend_from_slice(normals.expect("normals"));
            Ok(())
        }
        fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
            unreachable!()
        }
        fn polyline(&mut self, _: usize, _: usize, _: bool) -> io::Result<()> {
            unreachable!()
        }
        fn faces(&mut self, _: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
            unreachable!()
        }
        fn triangles(&mut self, _: &[[usize; 3]]) -> io::Result<()> {
            unreachable!()
        }
        fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
            assert!(self.sealed, "faces after the vertices");
            for w in starts.windows(2) {
                self.corners.extend_from_slice(&corners[w[0]..w[1]]);
                self.starts.push(self.corners.len());
            }
            Ok(())
        }
        fn group(&mut self, name: &str) -> io::Result<()> {
            self.groups.push((name.into(), self.starts.len()));
            Ok(())
        }
        fn vertices_complete(&mut self) -> io::Result<()> {
            self.sealed = true;
            Ok(())
        }
    }

    /// A mesh of `n` vertices (some at the same place, some in no face) and
    /// faces of 1 to 7 corners in a scattered order (digons, corners
    /// repeated in a face, faces of zero area among them).
    fn scattered(n: usize, faces: usize) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut points: Vec<[f64; 3]> = (0..n)
            .map(|_| [0; 3].map(|_| (next() % 2001) as f64 / 1000.0 - 1.0 + 1e-9 * (next() % 7) as f64))
            .collect();
        for k in (0..n).step_by(97) {
            points[k] = points[k / 2];
        }
        let faces = (0..faces)
            .map(|f| {
                let size = 1 + (next() % 7) as usize;
                // Near vertices mostly (as subdivision numbers them), far ones sometimes.
                let base = (f * 3) % (n - 1);
                (0..size)
                    .map(|_| {
                        if next() % 5 == 0 {
                            (next() % (n as u64 - 10)) as usize
                        } else {
                            base + (next() % 8) as usize % (n - base)
                        }
                    })
                    .collect()
            })
            .collect();
        (points, faces)
    }

    fn replayed(
        points: &[[f64; 3]],
        faces: &[Vec<usize>],
        groups: &[(Option<String>, usize)],
        budget: usize,
    ) -> Record {
        let dir = std::env::temp_dir().join(format!("bcifs-normals-{}-{budget}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut spill = NormalSpill::create(&dir.join("out.obj")).unwrap();
        spill.object("shape").unwrap();
        for part in points.chunks(1000) {
            spill.vertices(3, part.as_flattened(), None).unwrap();
        }
        for part in faces.chunks(333) {
            let mut starts = vec![0];
            let corners: Vec<usize> = part.iter().flat_map(|f| f.iter().copied()).collect();
            part.iter().for_each(|f| starts.push(starts.last().unwrap() + f.len()));
            spill.polygons(&starts, &corners).unwrap();
        }
        let mut record = Record::default();
        let cancel = Cancel::new();
        spill.replay(Replay { sink: &mut record, groups, cancel: &cancel, budget }).unwrap();
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.file_name()).collect();
        assert!(left.is_empty(), "side files left: {left:?}");
        std::fs::remove_dir_all(&dir).unwrap();
        record
    }

    /// The normals streamed are `area_normals`' bit for bit, the vertices
    /// and faces those pushed, in order, whatever the blocks and chunks (one
    /// block; several blocks and chunks; a block of a few vertices and a
    /// chunk of one face), across stretches of the positions file.
    #[test]
    fn streamed_normals_are_the_in_memory_ones() {
        let (points, faces) = scattered(3 * STRETCH + 123, 20_000);
        let expected = area_normals(&points, faces.iter().map(Vec::as_slice));
        assert!(expected.contains(&[0.0; 3]) && expected.iter().any(|n| *n != [0.0; 3]));
        let groups = [(None, 0), (Some("a".to_string()), 5), (Some("b".to_string()), 5), (Some("c".into()), 20_000)];
        for budget in [1 << 30, 1 << 20, 300] {
            let r = replayed(&points, &faces, &groups, budget);
            assert_eq!(r.object, ["shape"]);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&r.positions), bits(points.as_flattened()), "budget {budget}");
            assert_eq!(bits(&r.normals), bits(expected.as_flattened()), "budget {budget}");
            assert_eq!(r.corners, faces.concat());
            assert_eq!(r.starts.len(), faces.len());
            assert_eq!(r.groups, [("a".to_string(), 5), ("b".to_string(), 5), ("c".to_string(), 20_000)]);
        }
    }

    /// A cancelled replay stops with [`io::ErrorKind::Interrupted`] before
    /// the sink hears anything, and its side files are removed.
    #[test]
    fn a_cancelled_replay_stops_and_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("bcifs-normals-cancel-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (points, faces) = scattered(500, 400);
        let mut spill = NormalSpill::create(&dir.join("out.obj")).unwrap();
        spill.vertices(3, points.as_flattened(), None).unwrap();
        for f in &faces {
            spill.polygons(&[0, f.len()], f).unwrap();
        }
        let (cancel, mut record) = (Cancel::new(), Record::default());
        cancel.cancel();
        let e = spill.replay(Replay { sink: &mut record, groups: &[], cancel: &cancel, budget: 1 << 20 }).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::Interrupted);
        assert!(record.object.is_empty() && record.positions.is_empty());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A face that names a vertex not pushed is an error, not a panic later.
    #[test]
    fn a_face_past_the_vertices_is_refused() {
        let dir = std::env::temp_dir().join(format!("bcifs-normals-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut spill = NormalSpill::create(&dir.join("out.obj")).unwrap();
        spill.vertices(3, &[0.0; 9], None).unwrap();
        let e = spill.polygons(&[0, 3], &[0, 1, 3]).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        drop(spill);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
