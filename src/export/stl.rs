//! Binary STL (what slicers read, for 3D printing): the one place STL
//! records are formatted.

use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;

use super::atomic::{AtomicFile, Target};
use super::axes::{Coordinates, Turn};
use crate::geometry::Sink;

/// A [`Sink`] that writes a binary STL file: every face as triangles (quads
/// and larger faces as fans), each with its unit normal, counter-clockwise
/// seen from outside as the faces come. STL holds surfaces only: curves are
/// refused, and a file with no face is refused at [`StlWriter::finish`].
/// Triangles refer to vertex positions, which the writer keeps (12 bytes a
/// vertex); the triangles go straight to the file, under a header whose
/// count is written at the end. A face may come before its vertices (a
/// streamed surface sends a block's faces first): it waits, as indices,
/// until [`StlWriter::finish`].
///
/// ```
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-stl-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("square.stl");
/// let mut stl = bcifs::export::StlWriter::create(&path)?;
/// stl.vertices(2, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], None)?;
/// stl.polygons(&[0, 4], &[0, 1, 2, 3])?;
/// stl.finish()?;
/// // 80-byte header, a count of 2 triangles, 50 bytes each.
/// assert_eq!(std::fs::metadata(&path)?.len(), 84 + 2 * 50);
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub struct StlWriter {
    coordinates: Coordinates,
    main: Option<AtomicFile>,
    /// Vertex positions in the file's axes.
    positions: Vec<[f32; 3]>,
    /// Faces that named a vertex not yet written: their corner counts' ends and corners.
    waiting: (Vec<usize>, Vec<usize>),
    triangles: u64,
    buf: Vec<u8>,
}

impl StlWriter {
    /// Starts writing `path`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<StlWriter> {
        StlWriter::create_in(&Target::from(path))
    }

    /// Starts writing `target`: a file, or a buffer ([`Target::Memory`]).
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target) -> io::Result<StlWriter> {
        let mut main = AtomicFile::create_in(target)?;
        // The header and the count, written again at the end.
        main.writer().write_all(&[0u8; 84])?;
        Ok(StlWriter {
            coordinates: Coordinates::default(),
            main: Some(main),
            positions: Vec::new(),
            waiting: (vec![0], Vec::new()),
            triangles: 0,
            buf: Vec::with_capacity(1 << 16),
        })
    }

    /// The same writer, with the axes of `coordinates` (STL has no digits: `float`).
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> StlWriter {
        self.coordinates = coordinates;
        self
    }

    /// Completes the file: the header and the triangle count, then the
    /// triangles, renamed onto the target.
    ///
    /// # Errors
    /// No face was written (STL holds surfaces), more than 2^32 − 1
    /// triangles, or an I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let (ends, corners) = std::mem::take(&mut self.waiting);
        if ends.len() > 1 {
            if corners.iter().any(|&v| v >= self.positions.len()) {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "an STL face refers to a vertex never written",
                ));
            }
            self.fans(ends.windows(2).map(|w| &corners[w[0]..w[1]]))?;
        }
        if self.triangles == 0 {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "an STL file holds surfaces: this output has no face (write curves and point clouds as .obj or .ply)",
            ));
        }
        let count = u32::try_from(self.triangles).map_err(|_| {
            io::Error::new(io::ErrorKind::InvalidInput, "an STL file holds fewer than 2^32 triangles: lower the depth")
        })?;
        let mut main = self.main.take().expect("finish once");
        let mut header = [b' '; 80];
        let text = format!("binary STL written by bcifs {}", env!("CARGO_PKG_VERSION"));
        header[..text.len()].copy_from_slice(text.as_bytes());
        let w = main.writer();
        w.seek(SeekFrom::Start(0))?;
        w.write_all(&header)?;
        w.write_all(&count.to_le_bytes())?;
        main.commit()
    }

    /// Faces as fans of triangles, each with its unit normal.
    fn fans<'a>(&mut self, faces: impl Iterator<Item = &'a [usize]>) -> io::Result<()> {
        for face in faces.filter(|f| f.len() >= 3) {
            if face.iter().any(|&v| v >= self.positions.len()) {
                let (ends, corners) = &mut self.waiting;
                corners.extend_from_slice(face);
                ends.push(corners.len());
                continue;
            }
            for k in 1..face.len() - 1 {
                let p = [face[0], face[k], face[k + 1]].map(|v| self.positions[v]);
                let (u, w) = ([0, 1, 2].map(|a| p[1][a] - p[0][a]), [0, 1, 2].map(|a| p[2][a] - p[0][a]));
                let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
                let len = n.iter().map(|x| x * x).sum::<f32>().sqrt();
                let n = if len > 0.0 && len.is_finite() { n.map(|x| x / len) } else { [0.0; 3] };
                for x in n.iter().chain(p.iter().flatten()) {
                    self.buf.extend_from_slice(&x.to_le_bytes());
                }
                self.buf.extend_from_slice(&0u16.to_le_bytes());
                self.triangles += 1;
            }
            if self.buf.len() >= 1 << 20 {
                self.flush()?;
            }
        }
        self.flush()
    }

    fn flush(&mut self) -> io::Result<()> {
        self.main.as_mut().expect("not finished").writer().write_all(&self.buf)?;
        self.buf.clear();
        Ok(())
    }
}

impl Sink for StlWriter {
    fn object(&mut self, _: &str) -> io::Result<()> {
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, None)?;
        let dim = dim.max(1);
        let turn: Turn = self.coordinates.turn(dim);
        self.positions.extend(positions.chunks_exact(dim).map(|p| {
            turn.apply([p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)]).map(|x| x as f32)
        }));
        Ok(())
    }

    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }

    fn polyline(&mut self, _: usize, _: usize, _: bool) -> io::Result<()> {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "an STL file holds surfaces, not curves: write curves as .obj, .ply or .svg",
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
