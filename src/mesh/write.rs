//! Polygon meshes as text: OFF (what CGAL and MeshLab read) and OBJ (faces
//! of any degree, 1-based), coordinates printed so that they read back
//! exactly.

use std::fmt::Write as _;

use super::PolyMesh;

fn coordinate(out: &mut String, x: f64) {
    let mut b = ryu::Buffer::new();
    out.push_str(b.format_finite(if x == 0.0 { 0.0 } else { x }));
}

impl PolyMesh {
    /// The mesh as an OFF file.
    pub fn to_off(&self) -> String {
        let mut out = String::with_capacity(32 * (self.positions.len() + self.face_count()));
        let _ = writeln!(out, "OFF\n{} {} 0", self.positions.len(), self.face_count());
        for p in &self.positions {
            for (a, x) in p.iter().enumerate() {
                if a > 0 {
                    out.push(' ');
                }
                coordinate(&mut out, *x);
            }
            out.push('\n');
        }
        for face in self.faces() {
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
        for face in self.faces() {
            out.push('f');
            for v in face {
                let _ = write!(out, " {}", v + 1);
            }
            out.push('\n');
        }
        out
    }
}
