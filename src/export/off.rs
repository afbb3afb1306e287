//! Object File Format (what CGAL, MeshLab and Geomview read): the one place
//! OFF records are formatted.

use std::io::{self, Write};
use std::path::Path;

use super::atomic::{AtomicFile, Spool, Target};
use super::axes::Coordinates;
use crate::geometry::Sink;

/// A [`Sink`] that streams an OFF file: the header counts vertices and
/// faces, so vertices and faces go to two side files and the file is put
/// together by [`OffWriter::finish`] (the kernel copies them; memory stays
/// bounded whatever the size). OFF holds faces of any degree and points;
/// polylines are refused. The target appears only when `finish` succeeds.
///
/// ```
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-off-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("square.off");
/// let mut off = bcifs::export::OffWriter::create(&path)?;
/// // A unit square in the plane (2D vertices stay in the file's xy plane).
/// off.vertices(2, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], None)?;
/// off.polygons(&[0, 4], &[0, 1, 2, 3])?;
/// off.finish()?;
/// assert_eq!(std::fs::read_to_string(&path)?, "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub struct OffWriter {
    coordinates: Coordinates,
    main: Option<AtomicFile>,
    vertex_spool: Option<Spool>,
    face_spool: Option<Spool>,
    vertices: usize,
    faces: usize,
    line: Vec<u8>,
}

impl OffWriter {
    /// Starts writing `path`, in the model's axes turned as [`Coordinates::default`] says.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<OffWriter> {
        OffWriter::create_in(&Target::from(path))
    }

    /// Starts writing `target`: a file, or a buffer ([`Target::Memory`]).
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target) -> io::Result<OffWriter> {
        let main = AtomicFile::create_in(target)?;
        Ok(OffWriter {
            coordinates: Coordinates::default(),
            main: Some(main),
            vertex_spool: Some(Spool::create(&target.beside(), "vertices")?),
            face_spool: Some(Spool::create(&target.beside(), "elements")?),
            vertices: 0,
            faces: 0,
            line: Vec::with_capacity(1 << 16),
        })
    }

    /// The same writer, with the axes and digits of `coordinates`.
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> OffWriter {
        self.coordinates = coordinates;
        self
    }

    /// Completes the file: the header, the vertices, the faces, renamed
    /// onto the target. Without it (an error, a panic) the target is left
    /// as it was and the temporary files are removed.
    ///
    /// # Errors
    /// An I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        let mut main = self.main.take().expect("finish once");
        writeln!(main.writer(), "OFF\n{} {} 0", self.vertices, self.faces)?;
        self.vertex_spool.take().expect("finish once").append_to(&mut main)?;
        self.face_spool.take().expect("finish once").append_to(&mut main)?;
        main.commit()
    }

    /// Writes the line buffer to a side file when it is full (`force`: always).
    fn flush(&mut self, faces: bool, force: bool) -> io::Result<()> {
        if force || self.line.len() >= 1 << 20 {
            let spool = if faces { &mut self.face_spool } else { &mut self.vertex_spool };
            spool.as_mut().expect("not finished").writer().write_all(&self.line)?;
            self.line.clear();
        }
        Ok(())
    }

    /// One face record, `n a b c …`; digons are left out.
    fn face(&mut self, corners: &[usize]) -> io::Result<()> {
        if corners.len() < 3 {
            return Ok(());
        }
        let mut ints = itoa::Buffer::new();
        self.line.extend_from_slice(ints.format(corners.len()).as_bytes());
        for &v in corners {
            self.line.push(b' ');
            self.line.extend_from_slice(ints.format(v).as_bytes());
        }
        self.line.push(b'\n');
        self.faces += 1;
        self.flush(true, false)
    }
}

impl Sink for OffWriter {
    fn object(&mut self, _: &str) -> io::Result<()> {
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, None)?;
        let dim = dim.max(1);
        let turn = self.coordinates.turn(dim);
        let mut ryu = ryu::Buffer::new();
        for p in positions.chunks_exact(dim) {
            self.coordinates.push(&mut self.line, &mut ryu, turn, p);
            self.line.push(b'\n');
            self.vertices += 1;
            self.flush(false, false)?;
        }
        self.flush(false, true)
    }

    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }

    fn polyline(&mut self, _: usize, _: usize, _: bool) -> io::Result<()> {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "an OFF file holds faces and points, not curves: write curves as .obj or .svg",
        ))
    }

    fn faces(&mut self, quads: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
        quads.iter().try_for_each(|q| self.face(q))?;
        self.flush(true, true)
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        triangles.iter().try_for_each(|t| self.face(t))?;
        self.flush(true, true)
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        starts.windows(2).try_for_each(|w| self.face(&corners[w[0]..w[1]]))?;
        self.flush(true, true)
    }
}
