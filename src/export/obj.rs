//! Streaming Wavefront OBJ writer.

use std::fs::File;
use std::io::{self, BufWriter, Write};
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
    /// The shapes' coordinates are already Y-up (a mesh file's axes).
    y_up_input: bool,
    main: Option<AtomicFile>,
    spool_path: PathBuf,
    spool: Option<BufWriter<File>>,
    vertices: usize,
    normals: bool,
    bytes: u64,
    ints: itoa::Buffer,
    /// Elements go straight to the file (every vertex is already written).
    direct: bool,
    /// Text buffers, reused call after call (one per chunk formatted in parallel).
    texts: Vec<Vec<u8>>,
    /// Threads formatting large calls in parallel (`None`: one).
    pool: Option<rayon::ThreadPool>,
    /// Significant digits of coordinates (`None`: shortest round-trip).
    precision: Option<u32>,
}

/// Vertices below which a call is formatted on one thread.
const PARALLEL_VERTICES: usize = 8192;

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

    /// The same writer, for shapes whose coordinates are already Y-up
    /// (`true`: a mesh file's axes, [`crate::Model::y_up`]): the file's up
    /// axis is still the one [`ObjWriter::with_up`] asks, so they are written
    /// as they are for [`Up::Y`] and turned back for [`Up::Z`].
    pub fn with_y_up_input(mut self, y_up: bool) -> ObjWriter {
        self.y_up_input = y_up;
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
            y_up_input: false,
            main: Some(main),
            spool_path,
            spool: Some(spool),
            vertices: 0,
            normals: false,
            bytes: 0,
            ints: itoa::Buffer::new(),
            direct: false,
            texts: vec![Vec::new()],
            pool: None,
            precision: None,
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
        self.texts.resize(threads.max(1) * 2, Vec::new());
        Ok(self)
    }

    /// The same writer, with coordinates rounded to `digits` significant
    /// digits (1 to 15; `None`, or 16 and more: the shortest text that reads
    /// back to the same `f64`, the default).
    pub fn with_precision(mut self, digits: Option<u32>) -> ObjWriter {
        self.precision = digits.filter(|&d| d < 16).map(|d| d.max(1));
        self
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
        // File to file: the kernel copies (copy_file_range), no round trip through a buffer.
        let mut reader = File::open(&self.spool_path)?;
        let main = self.main();
        main.flush()?;
        io::copy(&mut reader, main.get_mut())?;
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
        if self.direct {
            return self.main();
        }
        self.spool.as_mut().expect("not finished")
    }
}

/// Writes the output of `ev` into `writer` in two streamed passes, the
/// vertices and then the elements (faces, lines) straight after them: the
/// same file as [`crate::eval::Evaluator::stream`] into the writer, without holding the
/// elements in a side file (the evaluation runs twice, the text is written
/// once). Returns the numbers of vertices and of faces (quads and triangles).
///
/// # Errors
/// A write or evaluation error.
pub fn write_evaluation(
    ev: &crate::eval::Evaluator,
    writer: &mut ObjWriter,
) -> Result<(usize, usize), crate::eval::EvalError> {
    let mut pass = Pass { writer, elements: false, vertices: 0, faces: 0 };
    ev.stream(&mut pass)?;
    pass.writer.direct = true;
    pass.elements = true;
    let result = ev.stream(&mut pass);
    pass.writer.direct = false;
    result?;
    Ok((pass.vertices, pass.faces))
}

/// One pass of [`write_evaluation`]: the vertices, or the elements.
struct Pass<'w> {
    writer: &'w mut ObjWriter,
    elements: bool,
    vertices: usize,
    faces: usize,
}

impl Sink for Pass<'_> {
    fn object(&mut self, name: &str) -> io::Result<()> {
        if self.elements { self.writer.object(name) } else { Ok(()) }
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
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
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        if !self.elements {
            return Ok(());
        }
        self.faces += quads.len();
        self.writer.faces(quads, uvs)
    }
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        if !self.elements {
            return Ok(());
        }
        self.faces += triangles.len();
        self.writer.triangles(triangles)
    }
}

/// Appends `x` as the shortest text that reads back to the same `f64`,
/// or with `digits` significant digits: `x` rounded to the nearest decimal
/// of that many digits, whose shortest text has at most that many.
#[inline]
fn push_f64(line: &mut Vec<u8>, buf: &mut ryu::Buffer, x: f64, digits: Option<u32>) {
    let x = match digits {
        Some(n) if x != 0.0 && x.is_finite() => {
            if push_digits(line, x, n) {
                return;
            }
            round_significant(x, n)
        }
        _ => x,
    };
    // Whole numbers as integers (a conversion, not a call to trunc).
    let whole = x as i64;
    if whole as f64 == x && x.abs() < 1e15 {
        let mut ib = itoa::Buffer::new();
        line.extend_from_slice(ib.format(whole).as_bytes());
    } else {
        line.extend_from_slice(buf.format(x).as_bytes());
    }
}

/// The decimal exponent of `a > 0`: `floor(log10(a))`, from the binary one
/// corrected by a comparison each way (no call into libm).
fn decimal_exponent(a: f64) -> i32 {
    let mut e = ((a.to_bits() >> 52) as i32 - 1023) * 30103 / 100_000;
    let ten = |k: i32| if (0..23).contains(&k) { POW10[k as usize] } else { 10f64.powi(k) };
    if a < ten(e) {
        e -= 1;
    }
    if a >= ten(e + 1) {
        e += 1;
    }
    e
}

/// Appends `x` with `n` significant digits in positional notation
/// (trailing zeros dropped), formatting the rounded integer of digits
/// directly; `false` (nothing written) when `x` needs an exponent
/// (below 1e-5 or at least 1e15 in magnitude, or more digits than a
/// power-of-ten table holds).
#[inline]
fn push_digits(line: &mut Vec<u8>, x: f64, n: u32) -> bool {
    let a = x.abs();
    if !(1e-5..1e15).contains(&a) {
        return false;
    }
    let mut shift = n as i32 - 1 - decimal_exponent(a);
    if (-14..0).contains(&shift) {
        // A whole number of more than `n` digits: its first `n`, then zeros.
        let m = (a / POW10[-shift as usize] + 0.5) as u64;
        if x < 0.0 {
            line.push(b'-');
        }
        line.extend_from_slice(itoa::Buffer::new().format(m).as_bytes());
        line.extend(std::iter::repeat_n(b'0', -shift as usize));
        return true;
    }
    if !(0..=22).contains(&shift) {
        return false;
    }
    let mut m = (a * POW10[shift as usize] + 0.5) as u64;
    while shift > 0 && m.is_multiple_of(10) {
        m /= 10;
        shift -= 1;
    }
    if x < 0.0 && m > 0 {
        line.push(b'-');
    }
    let mut ib = itoa::Buffer::new();
    let text = ib.format(m).as_bytes();
    let shift = shift as usize;
    if shift == 0 {
        line.extend_from_slice(text);
    } else if text.len() > shift {
        let point = text.len() - shift;
        line.extend_from_slice(&text[..point]);
        line.push(b'.');
        line.extend_from_slice(&text[point..]);
    } else {
        line.extend_from_slice(b"0.");
        line.extend(std::iter::repeat_n(b'0', shift - text.len()));
        line.extend_from_slice(text);
    }
    true
}

/// Exact powers of ten.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// `x` rounded to `n` significant digits: the nearest `f64` to that decimal
/// (an integer of at most 17 digits divided or multiplied by an exact
/// power of ten, one correctly rounded operation), without calls into libm.
fn round_significant(x: f64, n: u32) -> f64 {
    let e = decimal_exponent(x.abs());
    let shift = n as i32 - 1 - e;
    // Half away from zero, through an integer (below 10^17 < 2^63).
    let round = |y: f64| (y + 0.5f64.copysign(y)) as i64 as f64;
    if (0..=22).contains(&shift) {
        round(x * POW10[shift as usize]) / POW10[shift as usize]
    } else if (-22..0).contains(&shift) {
        round(x / POW10[-shift as usize]) * POW10[-shift as usize]
    } else {
        // Beyond exact powers of ten: the text of `n` digits read back.
        format!("{:.*e}", (n - 1) as usize, x).parse().unwrap_or(x)
    }
}

/// The OBJ text of vertices (and normals): `v` lines (and `vn`), axes as `turn` says.
/// How coordinates are turned on their way to the file (rotations about x).
#[derive(Clone, Copy)]
enum Turn {
    None,
    /// Model z becomes the file's y: `(x, y, z) ↦ (x, z, −y)`.
    ZToY,
    /// A Y-up shape written Z-up: `(x, y, z) ↦ (x, −z, y)`.
    YToZ,
}

fn format_vertices(
    line: &mut Vec<u8>,
    dim: usize,
    positions: &[f64],
    normals: Option<&[f64]>,
    turn: Turn,
    digits: Option<u32>,
) {
    let mut ryu = ryu::Buffer::new();
    let axes = |v: [f64; 3]| match turn {
        Turn::None => v,
        Turn::ZToY => [v[0], v[2], -v[1]],
        Turn::YToZ => [v[0], -v[2], v[1]],
    };
    for (i, p) in positions.chunks_exact(dim).enumerate() {
        line.extend_from_slice(b"v");
        let v = [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)];
        for x in axes(v) {
            line.push(b' ');
            push_f64(line, &mut ryu, x, digits);
        }
        line.push(b'\n');
        if let Some(n) = normals {
            line.extend_from_slice(b"vn");
            for x in axes([n[i * 3], n[i * 3 + 1], n[i * 3 + 2]]) {
                line.push(b' ');
                push_f64(line, &mut ryu, x, digits);
            }
            line.push(b'\n');
        }
    }
}

/// The OBJ text of quads, with texture and normal indices as the writer has them.
fn format_quads(line: &mut Vec<u8>, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>, normals: bool) {
    let mut ints = itoa::Buffer::new();
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
}

impl ObjWriter {
    /// Formats `count` items by `format(text, range)` into the reused text
    /// buffers, in parallel chunks when the call is large, and returns how
    /// many buffers hold the text, in order.
    fn format_chunks(&mut self, count: usize, format: impl Fn(&mut Vec<u8>, std::ops::Range<usize>) + Sync) -> usize {
        let chunks = match &self.pool {
            Some(_) if count >= PARALLEL_VERTICES => self.texts.len(),
            _ => 1,
        };
        let per = count.div_ceil(chunks).max(1);
        let texts = &mut self.texts[..chunks];
        let job = |(k, text): (usize, &mut Vec<u8>)| {
            text.clear();
            format(text, (k * per).min(count)..((k + 1) * per).min(count));
        };
        match &self.pool {
            Some(pool) if chunks > 1 => {
                use rayon::prelude::*;
                pool.install(|| texts.par_iter_mut().enumerate().for_each(job));
            }
            _ => texts.iter_mut().enumerate().for_each(job),
        }
        chunks
    }

    /// Writes the first `chunks` text buffers to the vertex file (counted
    /// in [`ObjWriter::bytes_written`]), or to the elements' spool.
    fn write_texts(&mut self, chunks: usize, spool: bool) -> io::Result<()> {
        let mut texts = std::mem::take(&mut self.texts);
        let result = texts[..chunks].iter().try_for_each(|t| {
            if spool {
                return self.spool().write_all(t);
            }
            self.bytes += t.len() as u64;
            self.main().write_all(t)
        });
        // Large buffers are kept for the next call; a huge one is not hoarded.
        for t in &mut texts {
            if t.capacity() > 64 << 20 {
                *t = Vec::new();
            }
        }
        self.texts = texts;
        result
    }
}

impl Sink for ObjWriter {
    fn object(&mut self, name: &str) -> io::Result<()> {
        let clean: String = name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
        writeln!(self.spool(), "o {clean}")
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        let dim = dim.max(1);
        let count = positions.len() / dim;
        let turn = match (dim == 3, self.y_up_input, self.up) {
            (true, false, Up::Y) => Turn::ZToY,
            (true, true, Up::Z) => Turn::YToZ,
            _ => Turn::None,
        };
        let digits = self.precision;
        let chunks = self.format_chunks(count, |text, r| {
            let n = normals.map(|n| &n[r.start * 3..r.end * 3]);
            format_vertices(text, dim, &positions[r.start * dim..r.end * dim], n, turn, digits);
        });
        self.normals |= normals.is_some();
        self.vertices += count;
        self.write_texts(chunks, false)
    }

    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        let digits = self.precision;
        let chunks = self.format_chunks(uvs.len() / 2, |text, r| {
            let mut ryu = ryu::Buffer::new();
            for t in uvs[r.start * 2..r.end * 2].chunks_exact(2) {
                text.extend_from_slice(b"vt ");
                push_f64(text, &mut ryu, t[0], digits);
                text.push(b' ');
                push_f64(text, &mut ryu, t[1], digits);
                text.push(b'\n');
            }
        });
        self.write_texts(chunks, false)
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
        let normals = self.normals;
        let chunks = self.format_chunks(quads.len(), |text, r| {
            format_quads(text, &quads[r.clone()], uvs.map(|t| &t[r]), normals);
        });
        self.write_texts(chunks, true)
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

#[cfg(test)]
mod tests {
    use super::*;

    fn text(x: f64, digits: Option<u32>) -> String {
        let mut line = Vec::new();
        push_f64(&mut line, &mut ryu::Buffer::new(), x, digits);
        String::from_utf8(line).unwrap()
    }

    #[test]
    fn significant_digits() {
        for (x, n, expected) in [
            (3.434_921_7, 6, "3.43492"),
            (-0.424_263_9, 6, "-0.424264"),
            (0.000_123_456_78, 4, "0.0001235"),
            (123_456_789.0, 6, "123457000"),
            (9.999_999_6, 6, "10"),
            (2.5, 6, "2.5"),
            (-1.0, 3, "-1"),
            (0.0, 3, "0"),
            (1e-9, 3, "1e-9"),
            (6.02214076e23, 4, "6.022e23"),
        ] {
            assert_eq!(text(x, Some(n)), expected, "{x} to {n} digits");
        }
        // Shortest round trip by default.
        assert_eq!(text(0.1 + 0.2, None), "0.30000000000000004");
    }

    /// Random values over 40 decades: `n` digits at most, and within half a
    /// unit of the `n`-th digit of the value (relative 5·10^−n, plus rounding).
    #[test]
    fn significant_digits_read_back_close() {
        let mut state = 0x1234_5678_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..20_000 {
            let mantissa = (next() >> 11) as f64 / (1u64 << 53) as f64 + 0.1;
            let x = mantissa * 10f64.powi((next() % 40) as i32 - 20) * if next() % 2 == 0 { 1.0 } else { -1.0 };
            let n = (next() % 15 + 1) as u32;
            let t = text(x, Some(n));
            let back: f64 = t.parse().unwrap();
            let tol = 5.0 * 10f64.powi(-(n as i32)) * x.abs() * 1.000_001;
            assert!((back - x).abs() <= tol, "{x} to {n} digits: {t}");
            let digits = t.split('e').next().unwrap().trim_start_matches(['-', '0', '.']).replace('.', "");
            assert!(digits.trim_end_matches('0').len() <= n as usize, "{x} to {n} digits: {t}");
        }
    }
}
