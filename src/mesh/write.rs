//! Polygon meshes as text: OFF (what CGAL and MeshLab read) and OBJ (faces
//! of any degree, 1-based), coordinates printed so that they read back
//! exactly.

use std::fmt::Write as _;

use super::polymesh::PolyMesh;

fn coordinate(out: &mut String, x: f64) {
    let mut b = ryu::Buffer::new();
    out.push_str(b.format_finite(if x == 0.0 { 0.0 } else { x }));
}

impl PolyMesh {
    /// The faces a file gets: all but digons (Doo-Sabin's faces of interior
    /// vertices of valence 2), which are doubled edges that no client takes;
    /// the surface is closed without them.
    pub fn written_faces(&self) -> impl Iterator<Item = &[usize]> {
        self.faces().filter(|f| f.len() >= 3)
    }

    /// The mesh as an OFF file.
    pub fn to_off(&self) -> String {
        let mut out = String::with_capacity(32 * (self.positions.len() + self.face_count()));
        let _ = writeln!(out, "OFF\n{} {} 0", self.positions.len(), self.written_faces().count());
        for p in &self.positions {
            for (a, x) in p.iter().enumerate() {
                if a > 0 {
                    out.push(' ');
                }
                coordinate(&mut out, *x);
            }
            out.push('\n');
        }
        for face in self.written_faces() {
            let _ = write!(out, "{}", face.len());
            for v in face {
                let _ = write!(out, " {v}");
            }
            out.push('\n');
        }
        out
    }

    /// The mesh as an OBJ file (one object `name`; `y_up` writes the model's
    /// z as the file's y, as [`crate::export::Up::Y`] does for evaluated shapes).
    pub fn to_obj(&self, name: &str, y_up: bool) -> String {
        let mut out = String::with_capacity(32 * (self.positions.len() + self.face_count()));
        let _ = writeln!(out, "# bcifs polygon mesh\no {name}");
        for p in &self.positions {
            let q = if y_up { [p[0], p[2], -p[1]] } else { *p };
            out.push('v');
            for x in q {
                out.push(' ');
                coordinate(&mut out, x);
            }
            out.push('\n');
        }
        for face in self.written_faces() {
            out.push('f');
            for v in face {
                let _ = write!(out, " {}", v + 1);
            }
            out.push('\n');
        }
        out
    }
}

impl PolyMesh {
    /// The mesh as a shape (quads and triangles as they are, larger faces
    /// fanned into triangles), for pictures.
    pub fn to_shape(&self, name: &str) -> crate::geometry::Shape {
        use crate::geometry::Sink;
        let mut shape = crate::geometry::Shape::default();
        let flat: Vec<f64> = self.positions.iter().flatten().copied().collect();
        let (mut quads, mut triangles) = (Vec::new(), Vec::new());
        for f in self.faces() {
            match f.len() {
                4 => quads.push([f[0], f[1], f[2], f[3]]),
                n => triangles.extend((1..n - 1).map(|i| [f[0], f[i], f[i + 1]])),
            }
        }
        // Writing into memory cannot fail.
        let _ = shape.object(name);
        let _ = shape.vertices(3, &flat, None);
        let _ = shape.faces(&quads, None);
        let _ = shape.triangles(&triangles);
        shape
    }
}
