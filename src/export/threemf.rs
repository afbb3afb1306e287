//! 3MF, the 3D Manufacturing Format (the 3MF Consortium's core
//! specification): what slicers (PrusaSlicer, Cura, Bambu Studio) open
//! with units and one closed mesh per object. An OPC package: a ZIP of the
//! content types, the relationships, and `3D/3dmodel.model` (XML: the
//! vertices, then the triangles, counter-clockwise seen from outside).

use std::io::{self, Read, Write};
use std::path::Path;

use super::atomic::{AtomicFile, Spool, Target};
use super::axes::{Coordinates, Turn};
use crate::geometry::Sink;

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>
"#;

const RELATIONSHIPS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>
"#;

/// A [`Sink`] that writes a 3MF package: the vertices (in millimetres, one
/// unit of the model a millimetre) and every face as triangles (quads and
/// larger faces as fans), one object. The vertices and the triangles go to
/// side files while they come (a face may come before its vertices), and
/// are deflated into the package at [`ThreeMfWriter::finish`]: memory stays
/// bounded whatever the mesh.
///
/// ```
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-3mf-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("tetrahedron.3mf");
/// let mut out = bcifs::export::ThreeMfWriter::create(&path)?;
/// out.vertices(3, &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], None)?;
/// out.triangles(&[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]])?;
/// out.finish()?;
/// let bytes = std::fs::read(&path)?;
/// assert_eq!(&bytes[..4], b"PK\x03\x04"); // a ZIP package
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub struct ThreeMfWriter {
    coordinates: Coordinates,
    main: Option<AtomicFile>,
    vertices: Option<Spool>,
    triangles: Option<Spool>,
    count: usize,
    faces: u64,
    /// The largest vertex a face named, to check at the end that it was written.
    largest: Option<usize>,
    buf: String,
}

impl ThreeMfWriter {
    /// Starts writing `path`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<ThreeMfWriter> {
        ThreeMfWriter::create_in(&Target::from(path))
    }

    /// Starts writing `target`: a file, or a buffer.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target) -> io::Result<ThreeMfWriter> {
        Ok(ThreeMfWriter {
            coordinates: Coordinates::default(),
            main: Some(AtomicFile::create_in(target)?),
            vertices: Some(Spool::create(&target.beside(), "vertices")?),
            triangles: Some(Spool::create(&target.beside(), "triangles")?),
            count: 0,
            faces: 0,
            largest: None,
            buf: String::with_capacity(1 << 16),
        })
    }

    /// The same writer, with the axes of `coordinates`.
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> ThreeMfWriter {
        self.coordinates = coordinates;
        self
    }

    /// Completes the package and renames it onto the target.
    ///
    /// # Errors
    /// No face (a 3MF object is a closed mesh), a face naming a vertex never
    /// written, a model over 4 GiB, or an I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let invalid = |text: &str| io::Error::new(io::ErrorKind::InvalidInput, text.to_string());
        if self.faces == 0 {
            return Err(invalid(
                "a 3MF file holds solids: this output has no face (write curves and point clouds as .obj or .ply)",
            ));
        }
        if self.largest.is_some_and(|v| v >= self.count) {
            return Err(invalid("a 3MF triangle refers to a vertex never written"));
        }
        let mut main = self.main.take().expect("finish once");
        let mut zip = Zip::default();
        zip.entry(main.writer(), "[Content_Types].xml", &mut CONTENT_TYPES.as_bytes())?;
        zip.entry(main.writer(), "_rels/.rels", &mut RELATIONSHIPS.as_bytes())?;
        let head = format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" \
             xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n\
             <metadata name=\"Application\">bcifs {}</metadata>\n<resources>\n<object id=\"1\" type=\"model\">\n<mesh>\n<vertices>\n",
            env!("CARGO_PKG_VERSION")
        );
        let middle = "</vertices>\n<triangles>\n";
        let tail =
            "</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n<item objectid=\"1\"/>\n</build>\n</model>\n";
        let vertices = self.vertices.as_mut().expect("finish once").reader()?;
        let triangles = self.triangles.as_mut().expect("finish once").reader()?;
        let mut model =
            head.as_bytes().chain(vertices).chain(middle.as_bytes()).chain(triangles).chain(tail.as_bytes());
        zip.entry(main.writer(), "3D/3dmodel.model", &mut model)?;
        zip.finish(main.writer())?;
        drop(self.vertices.take());
        drop(self.triangles.take());
        main.commit()
    }

    fn fans<'a>(&mut self, faces: impl Iterator<Item = &'a [usize]>) -> io::Result<()> {
        use std::fmt::Write as _;
        for face in faces.filter(|f| f.len() >= 3) {
            let top = face.iter().copied().max().unwrap_or(0);
            self.largest = Some(self.largest.map_or(top, |l| l.max(top)));
            for k in 1..face.len() - 1 {
                let _ = writeln!(self.buf, "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>", face[0], face[k], face[k + 1]);
                self.faces += 1;
            }
            if self.buf.len() >= 1 << 16 {
                self.triangles.as_mut().expect("not finished").writer().write_all(self.buf.as_bytes())?;
                self.buf.clear();
            }
        }
        self.triangles.as_mut().expect("not finished").writer().write_all(self.buf.as_bytes())?;
        self.buf.clear();
        Ok(())
    }
}

impl Sink for ThreeMfWriter {
    fn object(&mut self, _: &str) -> io::Result<()> {
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, None)?;
        let dim = dim.max(1);
        let turn: Turn = self.coordinates.turn(dim);
        let mut text = String::with_capacity(48 * positions.len() / dim);
        let mut number = ryu::Buffer::new();
        for p in positions.chunks_exact(dim) {
            let q = turn.apply([p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)]);
            text.push_str("<vertex");
            for (name, x) in [" x=\"", " y=\"", " z=\""].into_iter().zip(q) {
                text.push_str(name);
                text.push_str(number.format(x as f32));
                text.push('"');
            }
            text.push_str("/>\n");
            self.count += 1;
        }
        self.vertices.as_mut().expect("not finished").writer().write_all(text.as_bytes())
    }

    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }

    fn polyline(&mut self, _: usize, _: usize, _: bool) -> io::Result<()> {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "a 3MF file holds solids, not curves: write curves as .obj, .ply or .svg",
        ))
    }

    fn faces(&mut self, quads: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
        self.fans(quads.iter().map(|q| q.as_slice()))
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.fans(triangles.iter().map(|t| t.as_slice()))
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        self.fans(starts.windows(2).map(|w| &corners[w[0]..w[1]]))
    }
}

/// A ZIP archive written in one pass: each entry deflated as it is read,
/// its CRC and sizes in a data descriptor after it, then the central directory.
#[derive(Default)]
struct Zip {
    /// Per entry: name, CRC-32, compressed and uncompressed sizes, offset of its local header.
    entries: Vec<(String, u32, u32, u32, u32)>,
    offset: u64,
}

impl Zip {
    fn entry(&mut self, out: &mut impl Write, name: &str, data: &mut impl Read) -> io::Result<()> {
        let too_large = || io::Error::new(io::ErrorKind::InvalidInput, "a 3MF part over 4 GiB: lower the depth");
        let start = u32::try_from(self.offset).map_err(|_| too_large())?;
        let mut header = Vec::with_capacity(30 + name.len());
        header.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        // Version 2.0, a data descriptor follows (bit 3), deflated, no time.
        for x in [20u16, 0x0008, 8, 0, 0x21] {
            header.extend_from_slice(&x.to_le_bytes());
        }
        header.extend_from_slice(&[0; 12]);
        header.extend_from_slice(&(name.len() as u16).to_le_bytes());
        header.extend_from_slice(&0u16.to_le_bytes());
        header.extend_from_slice(name.as_bytes());
        out.write_all(&header)?;
        let mut counting = Counting { inner: out, written: 0 };
        let mut crc = crc32fast::Hasher::new();
        let mut read = 0u64;
        {
            let mut deflate = flate2::write::DeflateEncoder::new(&mut counting, flate2::Compression::fast());
            let mut chunk = vec![0u8; 1 << 16];
            loop {
                let n = data.read(&mut chunk)?;
                if n == 0 {
                    break;
                }
                crc.update(&chunk[..n]);
                deflate.write_all(&chunk[..n])?;
                read += n as u64;
            }
            deflate.finish()?;
        }
        let written = counting.written;
        let (crc, packed, size) = (
            crc.finalize(),
            u32::try_from(written).map_err(|_| too_large())?,
            u32::try_from(read).map_err(|_| too_large())?,
        );
        let mut descriptor = Vec::with_capacity(16);
        for x in [0x0807_4b50u32, crc, packed, size] {
            descriptor.extend_from_slice(&x.to_le_bytes());
        }
        out.write_all(&descriptor)?;
        self.offset += header.len() as u64 + written + descriptor.len() as u64;
        self.entries.push((name.to_string(), crc, packed, size, start));
        Ok(())
    }

    fn finish(self, out: &mut impl Write) -> io::Result<()> {
        let mut directory = Vec::new();
        for (name, crc, packed, size, start) in &self.entries {
            directory.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
            for x in [20u16, 20, 0x0008, 8, 0, 0x21] {
                directory.extend_from_slice(&x.to_le_bytes());
            }
            for x in [*crc, *packed, *size] {
                directory.extend_from_slice(&x.to_le_bytes());
            }
            for x in [name.len() as u16, 0, 0, 0, 0] {
                directory.extend_from_slice(&x.to_le_bytes());
            }
            directory.extend_from_slice(&0u32.to_le_bytes());
            directory.extend_from_slice(&start.to_le_bytes());
            directory.extend_from_slice(name.as_bytes());
        }
        let at = u32::try_from(self.offset)
            .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a 3MF package over 4 GiB: lower the depth"))?;
        let n = self.entries.len() as u16;
        let mut end = Vec::with_capacity(22);
        end.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
        for x in [0u16, 0, n, n] {
            end.extend_from_slice(&x.to_le_bytes());
        }
        end.extend_from_slice(&(directory.len() as u32).to_le_bytes());
        end.extend_from_slice(&at.to_le_bytes());
        end.extend_from_slice(&0u16.to_le_bytes());
        out.write_all(&directory)?;
        out.write_all(&end)
    }
}

/// A writer that counts what passes through it.
struct Counting<'a, W: Write> {
    inner: &'a mut W,
    written: u64,
}

impl<W: Write> Write for Counting<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.written += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}
