//! The polygon mesh type, the schemes, and what can go wrong.

use std::fmt;

/// A polygon mesh: positions and faces (vertex indices, counter-clockwise
/// seen from the outside), checked when built. Faces are stored flat:
/// face `f` is `indices[starts[f]..starts[f + 1]]`. Two meshes are equal
/// when their positions, faces and texture coordinates are: the name does
/// not count.
#[derive(Clone, Debug)]
pub struct PolyMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Where each face starts in `indices`, and one past the last face.
    pub(crate) starts: Vec<usize>,
    /// The vertices of all faces, face after face.
    pub(crate) indices: Vec<usize>,
    /// Texture coordinates, face-varying: a mesh of texture vertices
    /// `(u, v, 0)` with the same faces, corner for corner (see [`PolyMesh::texture`]).
    pub(crate) texture: Option<Box<PolyMesh>>,
    /// The name the file gives the mesh (OBJ's first `o`, else its first `g`).
    pub name: Option<String>,
    /// Named groups of faces (OBJ's `o` and `g`): each from its first face on.
    pub groups: Vec<(String, usize)>,
}

/// A subdivision scheme on polygon meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Scheme {
    /// Doo-Sabin: a new vertex per face corner (`α_0 = 1/4 + 5/(4n)`,
    /// `α_k = (3 + 2cos(2πk/n))/(4n)`), faces for the faces, the interior
    /// edges and the interior vertices.
    DooSabin,
    /// Catmull-Clark: face, edge and vertex points, a quad per face corner;
    /// boundaries by the cubic B-spline rules (midpoints, `(1, 6, 1)/8`).
    CatmullClark,
    /// Loop, on triangle meshes: edge and vertex points, four triangles per
    /// triangle; the cubic B-spline rules on the border.
    Loop,
    /// Kobbelt's √3, on triangle meshes: a centroid per face, the old edges
    /// flipped; the border kept.
    Sqrt3,
}

impl Scheme {
    /// Every scheme.
    pub const ALL: [Scheme; 4] = [Scheme::DooSabin, Scheme::CatmullClark, Scheme::Loop, Scheme::Sqrt3];

    /// The scheme of a name: `doo-sabin` or `catmull-clark`.
    pub fn from_name(name: &str) -> Option<Scheme> {
        match name {
            "doo-sabin" => Some(Scheme::DooSabin),
            "catmull-clark" => Some(Scheme::CatmullClark),
            "loop" => Some(Scheme::Loop),
            "sqrt3" => Some(Scheme::Sqrt3),
            _ => None,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::DooSabin => "doo-sabin",
            Scheme::CatmullClark => "catmull-clark",
            Scheme::Loop => "loop",
            Scheme::Sqrt3 => "sqrt3",
        }
    }

    /// Whether the scheme needs a triangle mesh.
    pub fn triangles_only(self) -> bool {
        matches!(self, Scheme::Loop | Scheme::Sqrt3)
    }
}

/// Where a mesh problem is: a face (and its line in the file, when read).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Place {
    /// The file, when read from one.
    pub file: Option<String>,
    /// 1-based line of the face in the file, when read from one.
    pub line: Option<usize>,
    /// 0-based face index.
    pub face: usize,
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: face {}", self.face),
            _ => write!(f, "face {}", self.face),
        }
    }
}

impl PartialEq for PolyMesh {
    fn eq(&self, other: &PolyMesh) -> bool {
        (&self.positions, &self.starts, &self.indices, &self.texture)
            == (&other.positions, &other.starts, &other.indices, &other.texture)
    }
}

/// Default in-memory limit of mesh subdivision (4 GiB).
pub const DEFAULT_MESH_MEMORY: usize = 4 << 30;

impl PolyMesh {
    /// A mesh from flat faces (not checked: for meshes made by subdivision).
    pub(crate) fn from_flat(positions: Vec<[f64; 3]>, starts: Vec<usize>, indices: Vec<usize>) -> PolyMesh {
        PolyMesh { positions, starts, indices, texture: None, name: None, groups: Vec::new() }
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.starts.len() - 1
    }

    /// The vertices of face `f`, counter-clockwise.
    pub fn face(&self, f: usize) -> &[usize] {
        &self.indices[self.starts[f]..self.starts[f + 1]]
    }

    /// The centroid of face `f` (the average of its vertices).
    pub fn centroid(&self, f: usize) -> [f64; 3] {
        super::rules::centroid(self.face(f).iter().map(|&v| &self.positions[v]))
    }

    /// All faces in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        (0..self.face_count()).map(|f| self.face(f))
    }

    /// Number of face corners (the sum of the face degrees).
    pub fn corner_count(&self) -> usize {
        self.indices.len()
    }

    /// The faces flat: face `f` is `corners()[offsets()[f]..offsets()[f + 1]]`.
    pub fn offsets(&self) -> &[usize] {
        &self.starts
    }

    /// Every face's vertices, face after face (see [`PolyMesh::offsets`]).
    pub fn corners(&self) -> &[usize] {
        &self.indices
    }

    /// The cube `[-1, 1]³`, faces counter-clockwise seen from outside
    /// (Sokolov et al. 2010 Fig. 12 subdivides it).
    pub fn cube() -> PolyMesh {
        let positions = (0..8)
            .map(|i| {
                let (x, y, z) =
                    ([-1.0, 1.0, 1.0, -1.0][i % 4], [-1.0, -1.0, 1.0, 1.0][i % 4], if i < 4 { -1.0 } else { 1.0 });
                [x, y, z]
            })
            .collect();
        let faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
        let starts = (0..=6).map(|f| 4 * f).collect();
        PolyMesh::from_flat(positions, starts, faces.concat())
    }

    /// The regular icosahedron with vertices `(0, ±1, ±φ)` and their cyclic
    /// permutations, faces counter-clockwise seen from outside: every vertex
    /// of valence 5 (Loop's and √3's extraordinary case).
    pub fn icosahedron() -> PolyMesh {
        let phi = (1.0 + 5f64.sqrt()) / 2.0;
        let mut positions = Vec::with_capacity(12);
        for axis in 0..3 {
            for (a, b) in [(-1.0, -phi), (-1.0, phi), (1.0, -phi), (1.0, phi)] {
                let mut p = [0.0; 3];
                p[(axis + 1) % 3] = a;
                p[(axis + 2) % 3] = b;
                positions.push(p);
            }
        }
        // Faces: triples of mutually adjacent vertices (edge length 2), oriented outwards.
        let d = |i: usize, j: usize| (0..3).map(|a| (positions[i][a] - positions[j][a]).powi(2)).sum::<f64>();
        let near = |i: usize, j: usize| (d(i, j) - 4.0).abs() < crate::algebra::tolerance::SAME_POINT;
        let mut faces = Vec::new();
        for i in 0..12 {
            for j in i + 1..12 {
                for k in j + 1..12 {
                    if near(i, j) && near(j, k) && near(i, k) {
                        let (a, b, c) = (positions[i], positions[j], positions[k]);
                        let n = [
                            (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                            (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]),
                        ];
                        let outward = (0..3).map(|x| n[x] * (a[x] + b[x] + c[x])).sum::<f64>() > 0.0;
                        faces.push(if outward { [i, j, k] } else { [i, k, j] });
                    }
                }
            }
        }
        let starts = (0..=faces.len()).map(|f| 3 * f).collect();
        PolyMesh::from_flat(positions, starts, faces.concat())
    }

    /// Number of vertices used by faces.
    pub fn used_vertices(&self) -> usize {
        let mut used = vec![false; self.positions.len()];
        self.indices.iter().for_each(|&v| used[v] = true);
        used.iter().filter(|u| **u).count()
    }

    /// The same mesh with every closed piece that faces inward (encloses a
    /// negative volume) turned outward, its texture faces with it; `None`
    /// when no face needs turning. What bcifs writes of a closed mesh faces
    /// outward whatever the input's orientation ([`crate::geometry::inward_faces`]).
    pub fn outward(&self) -> Option<PolyMesh> {
        let turn = crate::geometry::inward_faces(
            self.positions.len(),
            self.face_count(),
            |f| self.face(f),
            |v| self.positions[v],
        );
        if !turn.contains(&true) {
            return None;
        }
        let mut out = self.clone();
        let reverse = |m: &mut PolyMesh| {
            for (f, _) in turn.iter().enumerate().filter(|(_, t)| **t) {
                m.indices[m.starts[f] + 1..m.starts[f + 1]].reverse();
            }
        };
        reverse(&mut out);
        if let Some(t) = out.texture.as_deref_mut() {
            reverse(t);
        }
        Some(out)
    }

    /// The signed volume enclosed (positive when a closed mesh faces outwards).
    pub fn signed_volume(&self) -> f64 {
        self.faces()
            .map(|f| {
                let p0 = self.positions[f[0]];
                (1..f.len() - 1)
                    .map(|i| {
                        let (a, b) = (self.positions[f[i]], self.positions[f[i + 1]]);
                        p0[0] * (a[1] * b[2] - a[2] * b[1]) - p0[1] * (a[0] * b[2] - a[2] * b[0])
                            + p0[2] * (a[0] * b[1] - a[1] * b[0])
                    })
                    .sum::<f64>()
                    / 6.0
            })
            .sum()
    }
}
