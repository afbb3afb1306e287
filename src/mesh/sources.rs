//! Where each face of a subdivided mesh comes from: the input face whose
//! data (a material, a group, a colour) it carries.

use super::polymesh::{PolyMesh, Scheme};
use super::stream::Subdivision;
use super::topology::{BORDER, Topology};

impl PolyMesh {
    /// For each face of `depth` steps of `job`'s scheme (`limit`: of its
    /// limit surface, face for face [`PolyMesh::subdivided`]), the input
    /// face it comes from, so that per-face data follows the scheme as
    /// `data[sources[k]]`. Catmull-Clark's and Loop's faces split their
    /// face: each has one source. Doo-Sabin's and √3's faces of edges and
    /// vertices span several faces: each takes the lowest-numbered of
    /// them (a Doo-Sabin face takes the lowest source of its corners, each
    /// corner point that of the face it was made in, so that a face of an
    /// edge takes the lower of the two faces beside it; √3's two triangles
    /// across an edge, the lower of the two faces it joined).
    /// Faces of fewer than three corners (Doo-Sabin's digon at a vertex
    /// of valence 2) are counted as the net has them.
    ///
    /// ```
    /// use bcifs::mesh::{DEFAULT_MESH_MEMORY, PolyMesh, Scheme, Subdivision};
    /// let job = Subdivision { scheme: Scheme::CatmullClark, depth: 1, weights: None, memory_limit: DEFAULT_MESH_MEMORY };
    /// let sources = PolyMesh::cube().face_sources(&job, false);
    /// // Each quad of the cube splits into four, in order.
    /// assert_eq!(sources, (0..6).flat_map(|f| [f; 4]).collect::<Vec<u32>>());
    /// ```
    pub fn face_sources(&self, job: &Subdivision, limit: bool) -> Vec<u32> {
        let Subdivision { scheme, depth, weights, .. } = *job;
        // Doo-Sabin's limit is one step of faces after `depth − 1` nets; the
        // others' limits keep the faces of the net at `depth` (at least 1).
        let steps = if limit { depth.max(1) } else { depth };
        let mut sources = Sources { faces: (0..self.face_count() as u32).collect(), vertices: None };
        let mut mesh = self.clone();
        for step in 0..steps {
            let t = Topology::trusted(&mesh);
            let last_limit = limit && step + 1 == steps && scheme == Scheme::DooSabin;
            sources = sources.after(&mesh, scheme, &t, last_limit);
            if step + 1 < steps {
                // No ambient flag is looked at here (face_sources takes none): only memory, which cannot fail.
                mesh = crate::progress::Cancel::new().scope(|| mesh.step(scheme, step, &t, weights)).expect("memory");
            }
        }
        sources.faces
    }
}

/// The input face each face of a net comes from, and for Doo-Sabin's nets
/// after the first step each vertex's (a corner point of one face: `None`
/// for the input, whose vertices have none).
struct Sources {
    faces: Vec<u32>,
    vertices: Option<Vec<u32>>,
}

impl Sources {
    /// The sources of the faces of one step of `scheme` on `mesh` (these
    /// are its faces' and vertices'), in the order the step writes them
    /// (see [`PolyMesh::step_into`]); `limit`: of Doo-Sabin's limit step.
    fn after(&self, mesh: &PolyMesh, scheme: Scheme, t: &Topology, limit: bool) -> Sources {
        let face = |c: usize| self.faces[t.face(c)];
        let faces = match scheme {
            // A quad per corner.
            Scheme::CatmullClark => (0..mesh.corner_count()).map(face).collect(),
            // Four triangles per triangle.
            Scheme::Loop => self.faces.iter().flat_map(|&f| [f; 4]).collect(),
            // Per half-edge: one triangle on the border, two for an interior edge at its first half-edge.
            Scheme::Sqrt3 => (0..mesh.corner_count())
                .flat_map(|c| {
                    let tw = t.twin(c);
                    let (count, source) = match tw {
                        BORDER => (1, face(c)),
                        _ => (2 * usize::from(c < tw), face(c).min(face(tw))),
                    };
                    std::iter::repeat_n(source, count)
                })
                .collect(),
            Scheme::DooSabin => return self.doo_sabin(mesh, t, limit),
        };
        Sources { faces, vertices: None }
    }

    /// Doo-Sabin: each new vertex is the corner point of a corner, and
    /// takes that corner's source (its vertex's once the vertices have one,
    /// else its face's); each new face the lowest of its corners' (a face's
    /// face: its own), the limit's quad around a corner that corner's.
    fn doo_sabin(&self, mesh: &PolyMesh, t: &Topology, limit: bool) -> Sources {
        let corner: Vec<u32> = (0..mesh.corner_count())
            .map(|c| match &self.vertices {
                Some(v) => v[mesh.corners()[c]],
                None => self.faces[t.face(c)],
            })
            .collect();
        let interior = |v: usize| t.first(v) != BORDER && !t.on_border(v);
        if limit {
            let faces = (0..mesh.corner_count()).filter(|&c| interior(mesh.corners()[c])).map(|c| corner[c]).collect();
            return Sources { faces, vertices: None };
        }
        let lowest = |cs: &mut dyn Iterator<Item = usize>| cs.map(|c| corner[c]).min().expect("a face has corners");
        let faces = (0..mesh.face_count()).map(|f| lowest(&mut (mesh.offsets()[f]..mesh.offsets()[f + 1])));
        let edges = (0..mesh.corner_count())
            .filter(|&c| t.twin(c) != BORDER && c < t.twin(c))
            .map(|c| lowest(&mut [t.next(mesh, c), c, t.next(mesh, t.twin(c)), t.twin(c)].into_iter()));
        let vertices = (0..mesh.positions.len()).filter(|&v| interior(v)).map(|v| lowest(&mut around(mesh, t, v)));
        Sources { faces: faces.chain(edges).chain(vertices).collect(), vertices: Some(corner.clone()) }
    }
}

/// The corners around the interior vertex `v`.
fn around<'a>(mesh: &'a PolyMesh, t: &'a Topology, v: usize) -> impl Iterator<Item = usize> + 'a {
    let first = t.first(v);
    let mut at = Some(first);
    std::iter::from_fn(move || {
        let c = at?;
        let r = t.rotate(mesh, c);
        at = (r != BORDER && r != first).then_some(r);
        Some(c)
    })
}
