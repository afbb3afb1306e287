//! Streaming Wavefront OBJ writer: the one place OBJ records are formatted.

use std::io::{self, Write};
use std::path::Path;

use super::atomic::{AtomicFile, Spool, Target};
use super::axes::{Coordinates, Turn, Up};
use super::number::push_f64;
use crate::geometry::{Shape, Sink};

/// Writes a shape held in memory as an OBJ file (through a temporary file
/// renamed at the end, Y-up: see [`Up`]); `name` names its object when it
/// has none.
///
/// # Errors
/// An I/O error; nothing is left half-written.
pub fn write_obj(shape: &Shape, name: &str, path: &Path) -> io::Result<()> {
    let mut writer = ObjWriter::create(path)?;
    if shape.objects.is_empty() {
        writer.object(name)?;
    }
    shape.replay(&mut writer)?;
    writer.finish()
}

/// A [`Sink`] that streams OBJ text: `v` (and `vn`) and `vt` lines go to the
/// file as they come, elements (`o`, `l`, `f`) to a spool file appended at
/// the end, so memory stays bounded whatever the size. The target appears
/// only when [`ObjWriter::finish`] succeeds.
pub struct ObjWriter {
    coordinates: Coordinates,
    main: Option<AtomicFile>,
    spool: Option<Spool>,
    vertices: usize,
    normals: bool,
    bytes: u64,
    /// Elements go straight to the file (every vertex is already written).
    direct: bool,
    /// Colours of the next vertices (MeshLab's `v x y z r g b`), if given.
    colours: Vec<[u8; 3]>,
    /// Text buffers, reused call after call (one per piece in flight).
    texts: Vec<Vec<u8>>,
    /// Threads formatting large calls in parallel (`None`: one).
    pool: Option<rayon::ThreadPool>,
}

/// Items (vertices, faces) per piece of text formatted at once: a large
/// call is formatted piece by piece on the pool's threads.
const PIECE: usize = 8192;

impl ObjWriter {
    /// The same writer, with the model's axes mapped as `up` says.
    pub fn with_up(mut self, up: Up) -> ObjWriter {
        self.coordinates.up = up;
        self
    }

    /// The same writer, for shapes whose coordinates are already Y-up
    /// (`true`: a mesh file's axes, [`crate::Model::y_up`]): the file's up
    /// axis is still the one [`ObjWriter::with_up`] asks, so they are written
    /// as they are for [`Up::Y`] and turned back for [`Up::Z`].
    pub fn with_y_up_input(mut self, y_up: bool) -> ObjWriter {
        self.coordinates.y_up_input = y_up;
        self
    }

    /// Starts writing `path`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<ObjWriter> {
        ObjWriter::create_in(&Target::from(path))
    }

    /// Starts writing `target`: a file, or a buffer ([`Target::Memory`]).
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target) -> io::Result<ObjWriter> {
        let mut main = AtomicFile::create_in(target)?;
        writeln!(main.writer(), "# bcifs {}", env!("CARGO_PKG_VERSION"))?;
        let spool = Spool::create(&target.beside(), "elements")?;
        Ok(ObjWriter {
            coordinates: Coordinates::default(),
            main: Some(main),
            spool: Some(spool),
            vertices: 0,
            normals: false,
            bytes: 0,
            direct: false,
            colours: Vec::new(),
            texts: Vec::new(),
            pool: None,
        })
    }

    /// The same writer, formatting large calls on `threads` threads (the
    /// text is written in order, the same whatever the threads).
    ///
    /// # Errors
    /// The threads cannot be started.
    pub fn with_threads(mut self, threads: usize) -> io::Result<ObjWriter> {
        self.pool = match threads {
            0 | 1 => None,
            n => Some(rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(io::Error::other)?),
        };
        Ok(self)
    }

    /// The same writer, with coordinates rounded to `digits` significant
    /// digits (1 to 15; `None`, or 16 and more: the shortest text that reads
    /// back to the same `f64`, the default).
    pub fn with_precision(mut self, digits: Option<u32>) -> ObjWriter {
        self.coordinates = self.coordinates.with_precision(digits);
        self
    }

    /// The same writer, with the axes and digits of `coordinates`.
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> ObjWriter {
        self.coordinates = coordinates;
        self
    }

    /// Completes the file: appends the elements and renames the temporary
    /// file onto the target. Without it (an error, a panic) the target is
    /// left as it was and the temporary files are removed.
    ///
    /// # Errors
    /// An I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let mut main = self.main.take().expect("finish once");
        if let Some(spool) = self.spool.take() {
            spool.append_to(&mut main)?;
        }
        main.commit()
    }

    /// Bytes of vertex text written so far.
    pub fn bytes_written(&self) -> u64 {
        self.bytes
    }

    fn main(&mut self) -> &mut dyn Write {
        self.main.as_mut().expect("not finished").writer()
    }

    fn spool(&mut self) -> &mut dyn Write {
        if self.direct || self.spool.is_none() {
            return self.main();
        }
        self.spool.as_mut().expect("checked above").writer()
    }
}

/// Writes a stream into `writer` in two passes, the vertices and then the
/// elements (faces, lines) straight after them: `stream` is called twice
/// with the sink to push the same output into (an evaluation run twice),
/// and the text is written once, without holding the elements in a side
/// file. Returns the numbers of vertices and of faces (quads and
/// triangles). Once `cancel` is set, the next write stops with an
/// [`io::ErrorKind::Interrupted`] error.
///
/// # Errors
/// A write error, or the stream's.
pub fn write_two_passes<E>(
    writer: &mut ObjWriter,
    mut stream: impl FnMut(&mut dyn Sink) -> Result<(), E>,
    cancel: Option<&crate::progress::Cancel>,
) -> Result<(usize, usize), E> {
    let mut pass = Pass { writer, cancel, elements: false, vertices: 0, faces: 0 };
    stream(&mut pass)?;
    pass.writer.direct = true;
    pass.elements = true;
    let result = stream(&mut pass);
    pass.writer.direct = false;
    result?;
    Ok((pass.vertices, pass.faces))
}

/// One pass of [`write_two_passes`]: the vertices, or the elements.
struct Pass<'w> {
    writer: &'w mut ObjWriter,
    cancel: Option<&'w crate::progress::Cancel>,
    elements: bool,
    vertices: usize,
    faces: usize,
}

impl Pass<'_> {
    fn check(&self) -> io::Result<()> {
        self.cancel.map_or(Ok(()), crate::progress::Cancel::check_io)
    }
}

impl Sink for Pass<'_> {
    fn object(&mut self, name: &str) -> io::Result<()> {
        self.check()?;
        if self.elements { self.writer.object(name) } else { Ok(()) }
    }
    fn group(&mut self, name: &str) -> io::Result<()> {
        if self.elements { self.writer.group(name) } else { Ok(()) }
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        self.check()?;
        if self.elements {
            return Ok(());
        }
        self.vertices += positions.len() / dim.max(1);
        self.writer.vertices(dim, positions, normals)
    }
    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        if self.elements { Ok(()) } else { self.writer.uvs(uvs) }
    }
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        if self.elements { self.writer.polyline(first, count, closed) } else { Ok(()) }
    }
    fn cloud(&mut self, first: usize, count: usize) -> io::Result<()> {
        if self.elements { self.writer.cloud(first, count) } else { Ok(()) }
    }
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        self.check()?;
        if !self.elements {
            return Ok(());
        }
        self.faces += quads.len();
        self.writer.faces(quads, uvs)
    }
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.check()?;
        if !self.elements {
            return Ok(());
        }
        self.faces += triangles.len();
        self.writer.triangles(triangles)
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        self.check()?;
        if !self.elements {
            return Ok(());
        }
        self.faces += starts.windows(2).filter(|w| w[1] - w[0] >= 3).count();
        self.writer.polygons(starts, corners)
    }
}

/// The OBJ text of vertices (and normals, and colours): `v` lines (and `vn`), axes as `turn` says.
fn format_vertices(
    line: &mut Vec<u8>,
    dim: usize,
    positions: &[f64],
    normals: Option<&[f64]>,
    colours: Option<&[[u8; 3]]>,
    turn: Turn,
    coordinates: &Coordinates,
) {
    let mut ryu = ryu::Buffer::new();
    for (i, p) in positions.chunks_exact(dim).enumerate() {
        line.extend_from_slice(b"v ");
        coordinates.push(line, &mut ryu, turn, p);
        if let Some(c) = colours.and_then(|c| c.get(i)) {
            for channel in c {
                line.push(b' ');
                push_f64(line, &mut ryu, f64::from(*channel) / 255.0, Some(6));
            }
        }
        line.push(b'\n');
        if let Some(n) = normals {
            line.extend_from_slice(b"vn ");
            coordinates.push(line, &mut ryu, turn, &n[i * 3..i * 3 + 3]);
            line.push(b'\n');
        }
    }
}

/// One `f` record: the corners 1-based, each with its texture index when
/// given and its normal index when the vertices have normals.
#[inline]
fn push_face(line: &mut Vec<u8>, corners: &[usize], uvs: Option<&[usize]>, normals: bool) {
    let mut ints = itoa::Buffer::new();
    line.push(b'f');
    for (k, &v) in corners.iter().enumerate() {
        line.push(b' ');
        line.extend_from_slice(ints.format(v + 1).as_bytes());
        if let Some(t) = uvs {
            line.push(b'/');
            line.extend_from_slice(ints.format(t[k] + 1).as_bytes());
            if normals {
                line.push(b'/');
                line.extend_from_slice(ints.format(v + 1).as_bytes());
            }
        } else if normals {
            line.extend_from_slice(b"//");
            line.extend_from_slice(ints.format(v + 1).as_bytes());
        }
    }
    line.push(b'\n');
}

/// The OBJ text of faces of any degree (`corners[starts[k]..starts[k + 1]]`),
/// with texture indices when given (`uvs`, parallel to `corners`) and normal
/// indices when the vertices have normals; faces of fewer than three
/// corners are left out.
fn format_polygons(
    line: &mut Vec<u8>,
    starts: &[usize],
    corners: &[usize],
    uvs: Option<&[usize]>,
    normals: bool,
) -> usize {
    let mut written = 0;
    for w in starts.windows(2) {
        let face = &corners[w[0]..w[1]];
        if face.len() < 3 {
            continue;
        }
        push_face(line, face, uvs.map(|t| &t[w[0]..w[1]]), normals);
        written += 1;
    }
    written
}

/// The OBJ text of quads, with texture and normal indices as the writer has them.
fn format_quads(line: &mut Vec<u8>, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>, normals: bool) {
    for (k, q) in quads.iter().enumerate() {
        push_face(line, q, uvs.map(|t| &t[k][..]), normals);
    }
}

impl ObjWriter {
    /// Formats `count` items by `format(text, range)` and writes the text in
    /// order, to the vertex file (counted in [`ObjWriter::bytes_written`]) or
    /// to the elements' spool. A large call is cut into pieces formatted by
    /// the pool's threads while this thread writes the finished ones: at
    /// most a few pieces are in flight (a bounded queue), and the text is
    /// the same whatever the threads.
    fn write_formatted(
        &mut self,
        count: usize,
        spool: bool,
        format: impl Fn(&mut Vec<u8>, std::ops::Range<usize>) + Sync,
    ) -> io::Result<()> {
        let pieces = count.div_ceil(PIECE);
        let Some(pool) = self.pool.take().filter(|_| pieces > 1) else {
            let mut text = self.texts.pop().unwrap_or_default();
            text.clear();
            format(&mut text, 0..count);
            let result = self.write_text(&text, spool);
            self.keep(text);
            return result;
        };
        let in_flight = 2 * pool.current_num_threads() + 2;
        let (done, finished) = std::sync::mpsc::channel::<(usize, Vec<u8>)>();
        let format = &format;
        let result = pool.in_place_scope(|scope| {
            let spawn = |k: usize, mut text: Vec<u8>| {
                let done = done.clone();
                scope.spawn(move |_| {
                    text.clear();
                    format(&mut text, k * PIECE..((k + 1) * PIECE).min(count));
                    // The receiver waits for every piece it spawned.
                    let _ = done.send((k, text));
                });
            };
            let (mut spawned, mut received, mut written) = (0, 0, 0);
            while spawned < pieces.min(in_flight) {
                spawn(spawned, self.texts.pop().unwrap_or_default());
                spawned += 1;
            }
            let mut ready: std::collections::BTreeMap<usize, Vec<u8>> = std::collections::BTreeMap::new();
            let mut result = Ok(());
            while received < spawned {
                let Ok((k, text)) = finished.recv() else { break };
                received += 1;
                ready.insert(k, text);
                while let Some(text) = ready.remove(&written) {
                    written += 1;
                    if result.is_ok() {
                        result = self.write_text(&text, spool);
                    }
                    if result.is_ok() && spawned < pieces {
                        spawn(spawned, text);
                        spawned += 1;
                    } else {
                        self.keep(text);
                    }
                }
            }
            result
        });
        self.pool = Some(pool);
        result
    }

    fn write_text(&mut self, text: &[u8], spool: bool) -> io::Result<()> {
        if spool {
            return self.spool().write_all(text);
        }
        if self.spool.is_none() {
            return Err(io::Error::other(
                "OBJ vertices after the last ones were announced: they would follow the faces",
            ));
        }
        self.bytes += text.len() as u64;
        self.main().write_all(text)
    }

    /// Keeps a text buffer for the next call (a few, and no huge one).
    fn keep(&mut self, text: Vec<u8>) {
        if text.capacity() <= 64 << 20 && self.texts.len() < 16 {
            self.texts.push(text);
        }
    }
}

impl Sink for ObjWriter {
    fn object(&mut self, name: &str) -> io::Result<()> {
        let clean: String = name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
        writeln!(self.spool(), "o {clean}")
    }

    fn group(&mut self, name: &str) -> io::Result<()> {
        let clean: String = name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
        writeln!(self.spool(), "g {clean}")
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, normals)?;
        let dim = dim.max(1);
        let count = positions.len() / dim;
        let turn = self.coordinates.turn(dim);
        let coordinates = self.coordinates;
        let colours = std::mem::take(&mut self.colours);
        let colours = (colours.len() == count).then_some(colours);
        self.normals |= normals.is_some();
        self.vertices += count;
        self.write_formatted(count, false, |text, r| {
            let n = normals.map(|n| &n[r.start * 3..r.end * 3]);
            let c = colours.as_deref().map(|c| &c[r.clone()]);
            format_vertices(text, dim, &positions[r.start * dim..r.end * dim], n, c, turn, &coordinates);
        })
    }

    fn colours(&mut self, rgb: &[[u8; 3]]) -> io::Result<()> {
        self.colours = rgb.to_vec();
        Ok(())
    }

    /// The elements kept apart so far go after the vertices now, and the
    /// next ones straight after them: the same file, without copying the
    /// elements from the side file at the end.
    fn vertices_complete(&mut self) -> io::Result<()> {
        if let (Some(spool), Some(main)) = (self.spool.take(), self.main.as_mut()) {
            spool.append_to(main)?;
        }
        Ok(())
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        if starts.len() < 2 {
            return Ok(());
        }
        let normals = self.normals;
        let faces = starts.len() - 1;
        self.write_formatted(faces, true, |text, r| {
            format_polygons(text, &starts[r.start..=r.end], corners, None, normals);
        })
    }

    fn textured_polygons(&mut self, starts: &[usize], corners: &[usize], uv_corners: &[usize]) -> io::Result<()> {
        if starts.len() < 2 || uv_corners.len() != corners.len() {
            return self.polygons(starts, corners);
        }
        let normals = self.normals;
        let faces = starts.len() - 1;
        self.write_formatted(faces, true, |text, r| {
            format_polygons(text, &starts[r.start..=r.end], corners, Some(uv_corners), normals);
        })
    }

    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        let digits = self.coordinates.precision;
        self.write_formatted(uvs.len() / 2, false, |text, r| {
            let mut ryu = ryu::Buffer::new();
            for t in uvs[r.start * 2..r.end * 2].chunks_exact(2) {
                text.extend_from_slice(b"vt ");
                push_f64(text, &mut ryu, t[0], digits);
                text.push(b' ');
                push_f64(text, &mut ryu, t[1], digits);
                text.push(b'\n');
            }
        })
    }

    /// One `l a b` record per segment: MeshLab (vcglib) and Blender's
    /// importer keep only the first segment of a longer `l` record, and
    /// trimesh drops them; two-vertex records load whole in all of them.
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        let mut line = Vec::with_capacity(1 << 16);
        let segments = if closed && count > 2 { count } else { count.saturating_sub(1) };
        for k in 0..segments {
            if line.len() > (1 << 20) {
                // Bounded memory whatever the length of the polyline.
                self.spool().write_all(&line)?;
                line.clear();
            }
            let (a, b) = (first + k + 1, first + (k + 1) % count + 1);
            line.extend_from_slice(b"l ");
            line.extend_from_slice(itoa::Buffer::new().format(a).as_bytes());
            line.push(b' ');
            line.extend_from_slice(itoa::Buffer::new().format(b).as_bytes());
            line.push(b'\n');
        }
        self.spool().write_all(&line)
    }

    /// `p` records of up to 16 points each, after the object's `o`: the
    /// OBJ grouping of a cloud's points (Blender 3.4 and MeshLab read the
    /// vertices and leave the records out; glTF keeps each cloud apart).
    fn cloud(&mut self, first: usize, count: usize) -> io::Result<()> {
        self.write_formatted(count.div_ceil(16), true, |text, r| {
            let mut ints = itoa::Buffer::new();
            for line in r {
                text.push(b'p');
                for v in first + 16 * line..(first + 16 * (line + 1)).min(first + count) {
                    text.push(b' ');
                    text.extend_from_slice(ints.format(v + 1).as_bytes());
                }
                text.push(b'\n');
            }
        })
    }

    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        // Texture indices count only when there is one quad of them per face.
        let uvs = uvs.filter(|t| t.len() == quads.len());
        let normals = self.normals;
        self.write_formatted(quads.len(), true, |text, r| {
            format_quads(text, &quads[r.clone()], uvs.map(|t| &t[r]), normals);
        })
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        let normals = self.normals;
        self.write_formatted(triangles.len(), true, |text, r| {
            for t in &triangles[r] {
                push_face(text, t, None, normals);
            }
        })
    }
}

#[cfg(test)]
mod finite_tests {
    use crate::geometry::Sink as _;

    /// No writer puts NaN or an infinity in a file: the vertices are
    /// refused and the target is left as it was.
    #[test]
    fn non_finite_vertices_are_refused_and_nothing_is_written() {
        let dir = std::env::temp_dir().join(format!("bcifs-finite-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (x, normal) in [(f64::NAN, 0.0), (f64::INFINITY, 0.0), (0.0, f64::NAN)] {
            let path = dir.join("nan.obj");
            let mut obj = super::ObjWriter::create(&path).unwrap();
            let e =
                obj.vertices(3, &[0.0, 0.0, 0.0, x, 1.0, 0.0], Some(&[0.0, 0.0, 1.0, 0.0, normal, 1.0])).unwrap_err();
            assert!(e.to_string().contains("not a finite number"), "{e}");
            drop(obj);
            assert!(!path.exists());
            let stl = dir.join("nan.stl");
            let mut w = crate::export::StlWriter::create(&stl).unwrap();
            assert!(w.vertices(3, &[x, 0.0, 0.0], None).is_err() || normal.is_nan());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
