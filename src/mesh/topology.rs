//! The half-edge structure of a polygon mesh, checked: corner `c` of face
//! `f` (the `i`-th) is `starts[f] + i`; it is also the half-edge from its
//! vertex to the next one of the face. Its twin runs the other way in the
//! neighbouring face, or is [`BORDER`].

use std::collections::HashMap;

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
        // Undirected uses per edge first: three faces is non-manifold, two the same way is orientation.
        let mut uses: HashMap<(usize, usize), (u32, usize)> = HashMap::with_capacity(corners);
        for c in 0..corners {
            let (a, b) = (mesh.indices[c], mesh.indices[next(c)]);
            let e = uses.entry((a.min(b), a.max(b))).or_insert((0, c));
            e.0 += 1;
            if e.0 > 2 {
                return Err(MeshError::NonManifoldEdge { place: place(face[c]), a, b, count: e.0 as usize });
            }
        }
        let mut half: HashMap<(usize, usize), usize> = HashMap::with_capacity(corners);
        for c in 0..corners {
            let (a, b) = (mesh.indices[c], mesh.indices[next(c)]);
            if let Some(&other) = half.get(&(a, b)) {
                return Err(MeshError::Orientation { place: place(face[c]), a, b, other: place(face[other]) });
            }
            half.insert((a, b), c);
        }
        let mut twin = vec![BORDER; corners];
        for c in 0..corners {
            let (a, b) = (mesh.indices[c], mesh.indices[next(c)]);
            if let Some(&t) = half.get(&(b, a)) {
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
        let mut fans: HashMap<usize, Vec<usize>> = HashMap::new();
        for c in 0..corners {
            let r = root(&mut parent, c);
            let roots = fans.entry(mesh.indices[c]).or_default();
            if !roots.contains(&r) {
                roots.push(r);
            }
        }
        if let Some((&v, roots)) = fans.iter().filter(|(_, r)| r.len() > 1).min_by_key(|(v, _)| **v) {
            return Err(MeshError::NonManifoldVertex(v, roots.len()));
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
