//! The half-edge structure of a polygon mesh, checked: corner `c` of face
//! `f` (the `i`-th) is `starts[f] + i`; it is also the half-edge from its
//! vertex to the next one of the face. Its twin runs the other way in the
//! neighbouring face, or is [`BORDER`].

use super::{MeshError, Place, PolyMesh};

/// The twin of a border half-edge.
pub const BORDER: usize = usize::MAX;

/// Half-edges of a checked mesh.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Face of each corner.
    pub face: Vec<usize>,
    /// Twin half-edge of each corner, or [`BORDER`].
    pub twin: Vec<usize>,
    /// Per vertex: an outgoing corner (for a border vertex, the one whose
    /// half-edge is on the border: the rotation [`Topology::rotate`] walks its
    /// fan from there to the corner whose incoming half-edge is on the
    /// border), or `BORDER` when unused.
    pub first: Vec<usize>,
    /// Per vertex: on the border.
    pub on_border: Vec<bool>,
}

impl Topology {
    /// The half-edges of `mesh`, checked: no edge in three faces, faces
    /// consistently oriented, every vertex a single fan.
    ///
    /// # Errors
    /// The first problem found, its face named by `place`.
    #[allow(clippy::needless_range_loop)] // a corner indexes several arrays at once
    pub fn new(mesh: &PolyMesh, place: &dyn Fn(usize) -> Place) -> Result<Topology, MeshError> {
        let corners = mesh.corner_count();
        let mut face = vec![0; corners];
        for f in 0..mesh.face_count() {
            face[mesh.starts[f]..mesh.starts[f + 1]].iter_mut().for_each(|x| *x = f);
        }
        let next = |c: usize| if c + 1 == mesh.starts[face[c] + 1] { mesh.starts[face[c]] } else { c + 1 };
        // Outgoing corners per vertex (a counting sort), to find each half-edge's twin among few.
        let nv = mesh.positions.len();
        let mut out_start = vec![0usize; nv + 1];
        mesh.indices.iter().for_each(|&v| out_start[v + 1] += 1);
        for v in 0..nv {
            out_start[v + 1] += out_start[v];
        }
        let mut fill = out_start.clone();
        let mut out = vec![0usize; corners];
        for c in 0..corners {
            let v = mesh.indices[c];
            out[fill[v]] = c;
            fill[v] += 1;
        }
        let ends = |a: usize, b: usize| {
            out[out_start[a]..out_start[a + 1]].iter().copied().filter(move |&d| mesh.indices[next(d)] == b)
        };
        let mut twin = vec![BORDER; corners];
        for c in 0..corners {
            let (a, b) = (mesh.indices[c], mesh.indices[next(c)]);
            let (same, back) = (ends(a, b).count(), ends(b, a).count());
            if same + back > 2 {
                // Named at the face that comes last in the file: the one too many.
                let last = ends(a, b).chain(ends(b, a)).map(|d| face[d]).max().unwrap_or(face[c]);
                return Err(MeshError::NonManifoldEdge {
                    place: place(last),
                    a: a.min(b),
                    b: a.max(b),
                    count: same + back,
                });
            }
            if same > 1 {
                let other = ends(a, b).find(|&d| d != c).unwrap_or(c);
                let (first, second) = (c.min(other), c.max(other));
                return Err(MeshError::Orientation { place: place(face[second]), a, b, other: place(face[first]) });
            }
            if let Some(t) = ends(b, a).next() {
                twin[c] = t;
            }
        }
        let mut topology = Topology {
            face,
            twin,
            first: vec![BORDER; mesh.positions.len()],
            on_border: vec![false; mesh.positions.len()],
        };
        // Fans: outgoing corners of a vertex joined by the rotation c → twin(prev(c)).
        let mut parent: Vec<usize> = (0..corners).collect();
        fn root(parent: &mut [usize], mut c: usize) -> usize {
            while parent[c] != c {
                parent[c] = parent[parent[c]];
                c = parent[c];
            }
            c
        }
        for c in 0..corners {
            let r = topology.rotate(mesh, c);
            if r != BORDER {
                let (a, b) = (root(&mut parent, c), root(&mut parent, r));
                parent[a] = b;
            }
            let v = mesh.indices[c];
            if topology.twin[c] == BORDER {
                // The outgoing half-edge is on the border: the fan starts here.
                topology.on_border[v] = true;
                topology.first[v] = c;
            } else if topology.first[v] == BORDER {
                topology.first[v] = c;
            }
        }
        let mut roots = Vec::new();
        for v in 0..nv {
            roots.clear();
            for &c in &out[out_start[v]..out_start[v + 1]] {
                let r = root(&mut parent, c);
                if !roots.contains(&r) {
                    roots.push(r);
                }
            }
            if roots.len() > 1 {
                return Err(MeshError::NonManifoldVertex(v, roots.len()));
            }
        }
        Ok(topology)
    }

    /// The next outgoing corner around the vertex of `c` (counter-clockwise
    /// seen from outside): the twin of the half-edge coming into it in its
    /// face, or [`BORDER`].
    pub fn rotate(&self, mesh: &PolyMesh, c: usize) -> usize {
        self.twin[self.prev(mesh, c)]
    }

    /// The corner after `c` in its face.
    #[inline]
    pub fn next(&self, mesh: &PolyMesh, c: usize) -> usize {
        let f = self.face[c];
        if c + 1 == mesh.starts[f + 1] { mesh.starts[f] } else { c + 1 }
    }

    /// The corner before `c` in its face.
    #[inline]
    pub fn prev(&self, mesh: &PolyMesh, c: usize) -> usize {
        let f = self.face[c];
        if c == mesh.starts[f] { mesh.starts[f + 1] - 1 } else { c - 1 }
    }

    /// Number of border half-edges.
    pub fn boundary_edges(&self) -> usize {
        self.twin.iter().filter(|t| **t == BORDER).count()
    }
}
