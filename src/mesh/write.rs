//! Polygon meshes pushed into a sink (a file writer, a shape for pictures).

use super::emit::Written;
use super::polymesh::PolyMesh;
use crate::geometry::Sink;

impl PolyMesh {
    /// The faces a file gets: all but digons (Doo-Sabin's faces of interior
    /// vertices of valence 2), which are doubled edges that no client takes;
    /// the surface is closed without them.
    pub fn written_faces(&self) -> impl Iterator<Item = &[usize]> {
        self.faces().filter(|f| f.len() >= 3)
    }

    /// Pushes the mesh into `sink` as it is: its vertices, then its faces
    /// of any degree ([`Sink::polygons`]; digons are left out by files).
    /// Returns what was written.
    ///
    /// # Errors
    /// The sink's error.
    pub fn push_into(&self, sink: &mut dyn Sink) -> std::io::Result<Written> {
        sink.vertices(3, self.positions.as_flattened(), None)?;
        sink.polygons(&self.starts, &self.indices)?;
        Ok(Written { vertices: self.positions.len(), faces: self.written_faces().count() })
    }
}

impl PolyMesh {
    /// The mesh as a shape (quads and triangles as they are, larger faces
    /// fanned into triangles), for pictures.
    pub fn to_shape(&self, name: &str) -> crate::geometry::Shape {
        let mut shape = crate::geometry::Shape::default();
        // Writing into memory cannot fail.
        let _ = shape.object(name);
        let _ = self.push_into(&mut shape);
        shape
    }
}
