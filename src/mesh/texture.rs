//! Texture coordinates through subdivision, face-varying (seams stay
//! seams), as OpenSubdiv's face-varying interpolation with linear
//! boundaries (`FVAR_LINEAR_BOUNDARIES`, Blender's "Keep Boundaries", its
//! Subdivision Surface modifier's default) gives them.
//!
//! The texture vertices make a mesh of their own: the same faces, corner
//! for corner, over texture vertices `(u, v, 0)`; a seam is an edge whose
//! two sides have different texture vertices, a border of that mesh. One
//! step of the scheme on it (Catmull-Clark's or Loop's rules inside, the
//! same weights as the surface) with its border kept linear: border texture
//! vertices keep their values, border edges get their midpoints. The steps
//! emit faces in an order that depends only on the faces (a quad per corner,
//! four triangles per triangle), so the texture mesh's faces stay the
//! surface's, corner for corner, at every depth.

use super::error::MeshCheckError;
use super::polymesh::{Place, PolyMesh, Scheme};
use super::subdivide::RuleWeights;
use super::topology::{BORDER, Topology};

impl PolyMesh {
    /// The texture coordinates: a mesh of texture vertices `(u, v, 0)`
    /// whose face `f` has, corner for corner, the texture vertices of face
    /// `f` of this mesh; `None` when the mesh has none.
    pub fn texture(&self) -> Option<&PolyMesh> {
        self.texture.as_deref()
    }

    /// The same mesh with texture coordinates: `uvs` the texture vertices,
    /// `corners` one texture vertex per corner, face after face.
    ///
    /// ```
    /// use bcifs::mesh::{PolyMesh, Scheme};
    /// let square = PolyMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], vec![vec![0, 1, 2, 3]])?;
    /// let square = square.with_texture(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], vec![0, 1, 2, 3])?;
    /// // The border is linear: the texture's corners stay, the edges get their midpoints.
    /// let uv = square.texture_after(Scheme::CatmullClark, 1, None).unwrap();
    /// assert_eq!(&uv.positions[..4], &square.texture().unwrap().positions[..]);
    /// # Ok::<(), bcifs::mesh::MeshCheckError>(())
    /// ```
    ///
    /// # Errors
    /// Not one texture vertex per corner, or an index out of range.
    pub fn with_texture(mut self, uvs: Vec<[f64; 2]>, corners: Vec<usize>) -> Result<PolyMesh, MeshCheckError> {
        let place = |face| Place { file: None, line: None, face };
        if corners.len() != self.indices.len() {
            return Err(MeshCheckError::IndexOutOfRange {
                place: place(0),
                index: corners.len() as i64,
                count: uvs.len(),
            });
        }
        if let Some(k) = corners.iter().position(|&t| t >= uvs.len()) {
            let face = self.starts.partition_point(|&s| s <= k) - 1;
            return Err(MeshCheckError::IndexOutOfRange {
                place: place(face),
                index: corners[k] as i64,
                count: uvs.len(),
            });
        }
        let positions = uvs.iter().map(|t| [t[0], t[1], 0.0]).collect();
        self.texture = Some(Box::new(PolyMesh::from_flat(positions, self.starts.clone(), corners)));
        Ok(self)
    }

    /// The same mesh without texture coordinates.
    pub fn without_texture(mut self) -> PolyMesh {
        self.texture = None;
        self
    }

    /// The groups of faces (see [`PolyMesh::groups`]) after `depth` steps
    /// of `scheme`: each group's first face followed through the face splits
    /// (Catmull-Clark: a quad per corner, Loop: four triangles per
    /// triangle); `None` for the schemes whose faces come from edges and
    /// vertices too (Doo-Sabin, √3).
    pub fn groups_after(&self, scheme: Scheme, depth: usize) -> Option<Vec<(String, usize)>> {
        if !matches!(scheme, Scheme::CatmullClark | Scheme::Loop) {
            return None;
        }
        let split = |at: usize, step: usize| match (scheme, step) {
            // The first step: one quad per corner of the faces before.
            (Scheme::CatmullClark, 0) => self.starts[at.min(self.face_count())],
            _ => 4 * at,
        };
        Some(self.groups.iter().map(|(name, first)| (name.clone(), (0..depth).fold(*first, &split))).collect())
    }

    /// The texture mesh after `depth` steps of `scheme` (with the surface's
    /// rule `weights`), face for face the faces of
    /// [`PolyMesh::subdivide_with`]'s net; `None` when the mesh has no
    /// texture coordinates, when the scheme does not split faces
    /// (Doo-Sabin's and √3's faces come from edges and vertices too: no
    /// texture corner to follow), or when the texture mesh is not a
    /// manifold with consistently oriented faces.
    pub fn texture_after(&self, scheme: Scheme, depth: usize, weights: Option<RuleWeights>) -> Option<PolyMesh> {
        if !matches!(scheme, Scheme::CatmullClark | Scheme::Loop) {
            return None;
        }
        let mut uv = self.texture.as_deref()?.clone();
        for step in 0..depth {
            let t = Topology::new(&uv, &|face| Place { file: None, line: None, face }).ok()?;
            let mut next = uv.step(scheme, step, &t, weights).ok()?;
            // Linear border: the vertex points come first, one per texture vertex, in order.
            for v in 0..uv.positions.len() {
                if t.first(v) != BORDER && t.on_border(v) {
                    next.positions[v] = uv.positions[v];
                }
            }
            uv = next;
        }
        Some(uv)
    }
}
