//! Streaming Wavefront OBJ writer.

use std::fs::File;
use std::io::{self, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use super::atomic::{AtomicFile, forget, temp_path};
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
    up: Up,
    main: Option<AtomicFile>,
    spool_path: PathBuf,
    spool: Option<BufWriter<File>>,
    vertices: usize,
    normals: bool,
    bytes: u64,
    ryu: ryu::Buffer,
    ints: itoa::Buffer,
}

/// Which model axis is "up" in the file. OBJ is Y-up by convention (Blender's
/// importer turns file Y into its Z), so a model whose z is up is written
/// with model z as file y (`(x, y, z)` → `(x, z, −y)`, a rotation); 2D
/// curves stay in the xy plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    /// Model z becomes the file's y (the convention; the default).
    #[default]
    Y,
    /// The model's axes as they are.
    Z,
}

impl ObjWriter {
    /// The same writer, with the model's axes mapped as `up` says.
    pub fn with_up(mut self, up: Up) -> ObjWriter {
        self.up = up;
        self
    }

    /// Starts writing `path`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<ObjWriter> {
        let mut main = AtomicFile::create(path)?;
        writeln!(main.writer(), "# bcifs {}", env!("CARGO_PKG_VERSION"))?;
        let spool_path = temp_path(path, "elements");
        let spool = BufWriter::with_capacity(1 << 20, File::create(&spool_path)?);
        Ok(ObjWriter {
            up: Up::Y,
            main: Some(main),
            spool_path,
            spool: Some(spool),
            vertices: 0,
            normals: false,
            bytes: 0,
            ryu: ryu::Buffer::new(),
            ints: itoa::Buffer::new(),
        })
    }

    /// Completes the file: appends the elements and renames the temporary
    /// file onto the target. Without it (an error, a panic) the target is
    /// left as it was and the temporary files are removed.
    ///
    /// # Errors
    /// An I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let mut spool = self.spool.take().expect("finish once");
        spool.flush()?;
        drop(spool);
        let mut reader = File::open(&self.spool_path)?;
        let mut buf = vec![0u8; 1 << 20];
        loop {
            let n = reader.read(&mut buf)?;
            if n == 0 {
                break;
            }
            self.main().write_all(&buf[..n])?;
        }
        let _ = std::fs::remove_file(&self.spool_path);
        forget(&self.spool_path);
        self.main.take().expect("finish once").commit()
    }

    /// Bytes of vertex text written so far.
    pub fn bytes_written(&self) -> u64 {
        self.bytes
    }

    fn main(&mut self) -> &mut BufWriter<File> {
        self.main.as_mut().expect("not finished").writer()
    }

    fn spool(&mut self) -> &mut BufWriter<File> {
        self.spool.as_mut().expect("not finished")
    }
}

/// Appends `x` as the shortest text that reads back to the same `f64`.
#[inline]
fn push_f64(line: &mut Vec<u8>, buf: &mut ryu::Buffer, x: f64) {
    if x == x.trunc() && x.abs() < 1e15 {
        let mut ib = itoa::Buffer::new();
        line.extend_from_slice(ib.format(x as i64).as_bytes());
    } else {
        line.extend_from_slice(buf.format(x).as_bytes());
    }
}

impl Sink for ObjWriter {
    fn object(&mut self, name: &str) -> io::Result<()> {
        let clean: String = name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
        writeln!(self.spool(), "o {clean}")
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        let count = positions.len() / dim.max(1);
        let mut line = Vec::with_capacity(count * 48);
        let mut ryu = std::mem::replace(&mut self.ryu, ryu::Buffer::new());
        let turn = dim == 3 && self.up == Up::Y;
        let axes = |v: [f64; 3]| if turn { [v[0], v[2], -v[1]] } else { v };
        for (i, p) in positions.chunks_exact(dim).enumerate() {
            line.extend_from_slice(b"v");
            let v = [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)];
            for x in axes(v) {
                line.push(b' ');
                push_f64(&mut line, &mut ryu, x);
            }
            line.push(b'\n');
            if let Some(n) = normals {
                line.extend_from_slice(b"vn");
                for x in axes([n[i * 3], n[i * 3 + 1], n[i * 3 + 2]]) {
                    line.push(b' ');
                    push_f64(&mut line, &mut ryu, x);
                }
                line.push(b'\n');
            }
        }
        self.ryu = ryu;
        self.normals |= normals.is_some();
        self.vertices += count;
        self.bytes += line.len() as u64;
        self.main().write_all(&line)
    }

    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        let mut line = Vec::with_capacity(uvs.len() * 12);
        let mut ryu = std::mem::replace(&mut self.ryu, ryu::Buffer::new());
        for t in uvs.chunks_exact(2) {
            line.extend_from_slice(b"vt ");
            push_f64(&mut line, &mut ryu, t[0]);
            line.push(b' ');
            push_f64(&mut line, &mut ryu, t[1]);
            line.push(b'\n');
        }
        self.ryu = ryu;
        self.bytes += line.len() as u64;
        self.main().write_all(&line)
    }

    /// One `l a b` record per segment: MeshLab (vcglib) and Blender's
    /// importer keep only the first segment of a longer `l` record, and
    /// trimesh drops them; two-vertex records load whole in all of them.
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        let mut ints = std::mem::replace(&mut self.ints, itoa::Buffer::new());
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
            line.extend_from_slice(ints.format(a).as_bytes());
            line.push(b' ');
            line.extend_from_slice(ints.format(b).as_bytes());
            line.push(b'\n');
        }
        self.ints = ints;
        self.spool().write_all(&line)
    }

    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        // Texture indices count only when there is one quad of them per face.
        let uvs = uvs.filter(|t| t.len() == quads.len());
        let mut ints = std::mem::replace(&mut self.ints, itoa::Buffer::new());
        let normals = self.normals;
        let mut line = Vec::with_capacity(quads.len() * 64);
        for (k, q) in quads.iter().enumerate() {
            line.push(b'f');
            for c in 0..4 {
                line.push(b' ');
                line.extend_from_slice(ints.format(q[c] + 1).as_bytes());
                if let Some(t) = uvs {
                    line.push(b'/');
                    line.extend_from_slice(ints.format(t[k][c] + 1).as_bytes());
                    if normals {
                        line.push(b'/');
                        line.extend_from_slice(ints.format(q[c] + 1).as_bytes());
                    }
                } else if normals {
                    line.extend_from_slice(b"//");
                    line.extend_from_slice(ints.format(q[c] + 1).as_bytes());
                }
            }
            line.push(b'\n');
        }
        self.ints = ints;
        self.spool().write_all(&line)
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        let mut ints = std::mem::replace(&mut self.ints, itoa::Buffer::new());
        let normals = self.normals;
        let mut line = Vec::with_capacity(triangles.len() * 40);
        for t in triangles {
            line.push(b'f');
            for &v in t {
                line.push(b' ');
                line.extend_from_slice(ints.format(v + 1).as_bytes());
                if normals {
                    line.extend_from_slice(b"//");
                    line.extend_from_slice(ints.format(v + 1).as_bytes());
                }
            }
            line.push(b'\n');
        }
        self.ints = ints;
        self.spool().write_all(&line)
    }
}

impl Drop for ObjWriter {
    fn drop(&mut self) {
        if self.spool.take().is_some() {
            let _ = std::fs::remove_file(&self.spool_path);
            forget(&self.spool_path);
        }
    }
}
