//! Stanford PLY (what MeshLab, CloudCompare and trimesh read whole): the one
//! place PLY records are formatted. Binary little-endian by default, ASCII
//! on request.

use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;

use super::atomic::{AtomicFile, Spool, Target};
use super::axes::Coordinates;
use super::number::push_f64;
use crate::geometry::Sink;

/// Bytes reserved for the header: every property, 20-digit counts, with room to spare.
const HEADER_BYTES: usize = 1024;

/// A [`Sink`] that streams a PLY file: vertices (with normals and RGB
/// colours when given), faces of any degree (`list int int`, which MeshLab,
/// trimesh and Blender read; MeshLab refuses `uint` counts), polylines as
/// edges, points as vertices alone. The header counts every element: its
/// bytes are reserved at the start and written by [`PlyWriter::finish`]
/// (padded with a comment line), vertices go straight to the file, faces
/// and edges to side files appended at the end; memory stays bounded
/// whatever the size.
/// Coordinates are `double`, or `float` when at most 7 significant digits
/// are asked ([`Coordinates::precision`]). Whether vertices carry normals
/// and colours is decided by the first vertices written.
///
/// ```
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-ply-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("square.ply");
/// let mut ply = bcifs::export::PlyWriter::create(&path, true)?;
/// ply.vertices(2, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], None)?;
/// ply.polygons(&[0, 4], &[0, 1, 2, 3])?;
/// ply.finish()?;
/// let text = std::fs::read_to_string(&path)?;
/// assert!(text.starts_with("ply\nformat ascii 1.0\n"));
/// assert!(text.ends_with("end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"));
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub struct PlyWriter {
    coordinates: Coordinates,
    ascii: bool,
    main: Option<AtomicFile>,
    face_spool: Option<Spool>,
    edge_spool: Option<Spool>,
    vertices: usize,
    faces: usize,
    edges: usize,
    /// Whether vertices carry normals and colours (decided by the first vertices).
    layout: Option<(bool, bool)>,
    colours: Vec<[u8; 3]>,
    buf: Vec<u8>,
}

impl PlyWriter {
    /// Starts writing `path`, binary little-endian, or ASCII when `ascii`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path, ascii: bool) -> io::Result<PlyWriter> {
        PlyWriter::create_in(&Target::from(path), ascii)
    }

    /// Starts writing `target`: a file, or a buffer ([`Target::Memory`]).
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target, ascii: bool) -> io::Result<PlyWriter> {
        Ok(PlyWriter {
            coordinates: Coordinates::default(),
            ascii,
            main: Some({
                let mut main = AtomicFile::create_in(target)?;
                main.writer().write_all(&[b' '; HEADER_BYTES])?;
                main
            }),
            face_spool: Some(Spool::create(&target.beside(), "elements")?),
            edge_spool: Some(Spool::create(&target.beside(), "elements")?),
            vertices: 0,
            faces: 0,
            edges: 0,
            layout: None,
            colours: Vec::new(),
            buf: Vec::with_capacity(1 << 16),
        })
    }

    /// The same writer, with the axes and digits of `coordinates`.
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> PlyWriter {
        self.coordinates = coordinates;
        self
    }

    /// Single-precision coordinates (at most 7 significant digits asked).
    fn float32(&self) -> bool {
        self.coordinates.precision.is_some_and(|d| d <= 7)
    }

    /// The header: the elements and their properties, with their counts.
    fn header(&self) -> String {
        let (normals, colours) = self.layout.unwrap_or((false, false));
        let scalar = if self.float32() { "float" } else { "double" };
        let format = if self.ascii { "ascii" } else { "binary_little_endian" };
        let mut h = format!("ply\nformat {format} 1.0\ncomment bcifs {}\n", env!("CARGO_PKG_VERSION"));
        h += &format!("element vertex {}\n", self.vertices);
        for axis in ["x", "y", "z"] {
            h += &format!("property {scalar} {axis}\n");
        }
        if normals {
            for axis in ["nx", "ny", "nz"] {
                h += &format!("property {scalar} {axis}\n");
            }
        }
        if colours {
            h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        }
        h += &format!("element face {}\nproperty list int int vertex_indices\n", self.faces);
        if self.edges > 0 {
            h += &format!("element edge {}\nproperty int vertex1\nproperty int vertex2\n", self.edges);
        }
        h + "end_header\n"
    }

    /// Completes the file: the header, the vertices, the faces and the
    /// edges, renamed onto the target. Without it the target is left as it
    /// was and the temporary files are removed.
    ///
    /// # Errors
    /// An I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let mut main = self.main.take().expect("finish once");
        let header = self.header();
        // The reserved bytes, exactly: the header, comment lines of padding (short: MeshLab reads
        // header lines of limited length) before `end_header`.
        let body = header.strip_suffix("end_header\n").unwrap_or(&header);
        if body.len() + "comment \nend_header\n".len() > HEADER_BYTES {
            return Err(io::Error::other("the PLY header outgrew its reserved bytes"));
        }
        let mut full = body.to_string();
        let mut left = HEADER_BYTES - body.len() - "end_header\n".len();
        while left > 0 {
            let line = if left > 72 { 64 } else { left };
            full += &format!("comment{}\n", " ".repeat(line - "comment\n".len()));
            left -= line;
        }
        full += "end_header\n";
        let w = main.writer();
        w.seek(SeekFrom::Start(0))?;
        w.write_all(full.as_bytes())?;
        w.seek(SeekFrom::End(0))?;
        self.face_spool.take().expect("finish once").append_to(&mut main)?;
        self.edge_spool.take().expect("finish once").append_to(&mut main)?;
        main.commit()
    }

    /// Writes the buffer of vertices to the file.
    fn spill_vertices(&mut self) -> io::Result<()> {
        let buf = std::mem::take(&mut self.buf);
        let result = self.main.as_mut().expect("not finished").writer().write_all(&buf);
        self.buf = buf;
        self.buf.clear();
        result
    }

    /// Writes the buffer to a side file.
    fn spill(&mut self, spool: fn(&mut PlyWriter) -> &mut Option<Spool>) -> io::Result<()> {
        let buf = std::mem::take(&mut self.buf);
        let result = spool(self).as_mut().expect("not finished").writer().write_all(&buf);
        self.buf = buf;
        self.buf.clear();
        result
    }

    /// One number of a vertex.
    fn scalar(&mut self, x: f64, ryu: &mut ryu::Buffer, first: bool) {
        if self.ascii {
            if !first {
                self.buf.push(b' ');
            }
            push_f64(&mut self.buf, ryu, x, self.coordinates.precision);
        } else if self.float32() {
            self.buf.extend_from_slice(&(x as f32).to_le_bytes());
        } else {
            self.buf.extend_from_slice(&x.to_le_bytes());
        }
    }

    /// One list of indices (a face: counted; an edge: not).
    fn indices(&mut self, list: &[usize], counted: bool) {
        let mut ints = itoa::Buffer::new();
        if self.ascii {
            let mut first = true;
            if counted {
                self.buf.extend_from_slice(ints.format(list.len()).as_bytes());
                first = false;
            }
            for &v in list {
                if !first {
                    self.buf.push(b' ');
                }
                self.buf.extend_from_slice(ints.format(v).as_bytes());
                first = false;
            }
            self.buf.push(b'\n');
        } else {
            if counted {
                self.buf.extend_from_slice(&(list.len() as i32).to_le_bytes());
            }
            for &v in list {
                self.buf.extend_from_slice(&(v as i32).to_le_bytes());
            }
        }
    }

    /// Binary vertices without colours, the common case, in one tight loop:
    /// coordinates (and normals, zeros where not given) as `double` or `float`.
    fn binary_vertices(
        &mut self,
        dim: usize,
        positions: &[f64],
        normals: Option<&[f64]>,
        with_normals: bool,
        turn: super::axes::Turn,
    ) -> io::Result<()> {
        let float32 = self.float32();
        let count = positions.len() / dim;
        for (i, p) in positions.chunks_exact(dim).enumerate() {
            let v = turn.apply([p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)]);
            let n = match normals {
                Some(n) => turn.apply([n[3 * i], n[3 * i + 1], n[3 * i + 2]]),
                None => [0.0; 3],
            };
            let values = [v[0], v[1], v[2], n[0], n[1], n[2]];
            let used = if with_normals { &values[..] } else { &values[..3] };
            if float32 {
                used.iter().for_each(|x| self.buf.extend_from_slice(&(*x as f32).to_le_bytes()));
            } else {
                used.iter().for_each(|x| self.buf.extend_from_slice(&x.to_le_bytes()));
            }
            if self.buf.len() >= 1 << 20 {
                self.spill_vertices()?;
            }
        }
        self.vertices += count;
        self.spill_vertices()
    }

    /// Face records, digons left out.
    fn face_records<'a>(&mut self, faces: impl Iterator<Item = &'a [usize]>) -> io::Result<()> {
        for face in faces.filter(|f| f.len() >= 3) {
            self.indices(face, true);
            self.faces += 1;
            if self.buf.len() >= 1 << 20 {
                self.spill(|w| &mut w.face_spool)?;
            }
        }
        self.spill(|w| &mut w.face_spool)
    }
}

impl Sink for PlyWriter {
    fn object(&mut self, _: &str) -> io::Result<()> {
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, normals)?;
        let dim = dim.max(1);
        let count = positions.len() / dim;
        let colours = std::mem::take(&mut self.colours);
        let (with_normals, with_colours) =
            *self.layout.get_or_insert((normals.is_some(), colours.len() == count && count > 0));
        let turn = self.coordinates.turn(dim);
        if !self.ascii && !with_colours {
            return self.binary_vertices(dim, positions, normals.filter(|_| with_normals), with_normals, turn);
        }
        let mut ryu = ryu::Buffer::new();
        for (i, p) in positions.chunks_exact(dim).enumerate() {
            let v = [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)];
            for (k, x) in turn.apply(v).into_iter().enumerate() {
                self.scalar(x, &mut ryu, k == 0);
            }
            if with_normals {
                let n = normals.map_or([0.0; 3], |n| [n[3 * i], n[3 * i + 1], n[3 * i + 2]]);
                for x in turn.apply(n) {
                    self.scalar(x, &mut ryu, false);
                }
            }
            if with_colours {
                let c = colours.get(i).copied().unwrap_or([255; 3]);
                if self.ascii {
                    let mut ints = itoa::Buffer::new();
                    for channel in c {
                        self.buf.push(b' ');
                        self.buf.extend_from_slice(ints.format(channel).as_bytes());
                    }
                } else {
                    self.buf.extend_from_slice(&c);
                }
            }
            if self.ascii {
                self.buf.push(b'\n');
            }
            if self.buf.len() >= 1 << 20 {
                self.spill_vertices()?;
            }
        }
        self.vertices += count;
        self.spill_vertices()
    }

    fn colours(&mut self, rgb: &[[u8; 3]]) -> io::Result<()> {
        self.colours = rgb.to_vec();
        Ok(())
    }

    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }

    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        let segments = if closed && count > 2 { count } else { count.saturating_sub(1) };
        for k in 0..segments {
            self.indices(&[first + k, first + (k + 1) % count], false);
            self.edges += 1;
            if self.buf.len() >= 1 << 20 {
                self.spill(|w| &mut w.edge_spool)?;
            }
        }
        self.spill(|w| &mut w.edge_spool)
    }

    fn faces(&mut self, quads: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
        self.face_records(quads.iter().map(|q| q.as_slice()))
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.face_records(triangles.iter().map(|t| t.as_slice()))
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        self.face_records(starts.windows(2).map(|w| &corners[w[0]..w[1]]))
    }
}
