//! The half-edge structure of a polygon mesh: corner `c` of face `f` (the
//! `i`-th) is `starts[f] + i`; it is also the half-edge from its vertex to
//! the next one of the face. Its twin runs the other way in the
//! neighbouring face, or is [`BORDER`]. Stored in 32 bits (a mesh in memory
//! has fewer than 2³² corners), so a deep net's structure costs 9 bytes a
//! corner. [`Net`] is a net seen through its half-edges, whether made in
//! memory ([`Made`]: a mesh and its topology) or named from the net before it
//! without its faces being made (`named::LoopChild`, `named::Sqrt3Child`): the rules of a step
//! and the limit masks written once on it give a named net the made one's
//! numbers bit for bit.

use super::error::MeshCheckError;
use super::polymesh::{Place, PolyMesh};

/// The twin of a border half-edge, and the first corner of an unused vertex.
pub const BORDER: usize = usize::MAX;

const NONE: u32 = u32::MAX;

/// Half-edges of a mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topology {
    /// Face of each corner.
    face: Faces,
    /// Twin half-edge of each corner, or `NONE`.
    twin: Vec<u32>,
    /// Per vertex: an outgoing corner, or `NONE` when unused.
    first: Vec<u32>,
    /// Per vertex: on the border.
    on_border: Vec<bool>,
}

/// The face of each corner: implicit when every face has the same number of
/// corners (a net after a Loop or Catmull-Clark step: 4 bytes a corner saved).
#[derive(Clone, Debug, PartialEq, Eq)]
enum Faces {
    /// Every face has this many corners: corner `c` is in face `c / n`.
    Uniform(usize),
    /// The face of each corner.
    Listed(Vec<u32>),
}

impl Faces {
    /// `face` unless every face has the same size.
    fn of(mesh: &PolyMesh, face: Vec<u32>) -> Faces {
        let n = mesh.starts.get(1).copied().unwrap_or(0);
        if n > 0 && mesh.starts.iter().enumerate().all(|(f, &s)| s == n * f) {
            Faces::Uniform(n)
        } else {
            Faces::Listed(face)
        }
    }

    #[inline]
    fn of_corner(&self, c: usize) -> usize {
        match *self {
            // Constant divisors for the common sizes (a multiplication, not a division).
            Faces::Uniform(3) => c / 3,
            Faces::Uniform(4) => c / 4,
            Faces::Uniform(n) => c / n,
            Faces::Listed(ref face) => face[c] as usize,
        }
    }
}

/// A stored corner number, [`BORDER`] for none.
#[inline]
pub(crate) fn wide(x: u32) -> usize {
    if x == NONE { BORDER } else { x as usize }
}

/// Each vertex's first corner (the one whose half-edge is on the border,
/// else the first in order) and whether it is on the border, from the
/// `corners` in order (numbers below 2³²), their vertices and twins: the
/// fans of [`Topology`], for made and named nets alike.
pub(crate) fn fans(
    vertices: usize,
    corners: impl Iterator<Item = usize>,
    vertex: impl Fn(usize) -> usize,
    twin: impl Fn(usize) -> usize,
) -> (Vec<u32>, Vec<bool>) {
    let (mut first, mut on_border) = (vec![NONE; vertices], vec![false; vertices]);
    for c in corners {
        let v = vertex(c);
        if twin(c) == BORDER {
            // The outgoing half-edge is on the border: the fan starts here.
            on_border[v] = true;
            first[v] = c as u32;
        } else if first[v] == NONE {
            first[v] = c as u32;
        }
    }
    (first, on_border)
}

/// The corner after `c` in its triangle (corners `3f .. 3f + 2`).
#[inline]
pub(crate) fn triangle_next(c: usize) -> usize {
    c - c % 3 + (c + 1) % 3
}

/// The corner before `c` in its triangle.
#[inline]
pub(crate) fn triangle_prev(c: usize) -> usize {
    c - c % 3 + (c + 2) % 3
}

/// Pairs the half-edges `forth` (a → b) with `back` (b → a) when the pair
/// of vertices carries more than one edge. That happens only in meshes made
/// by subdivision: Doo-Sabin turns an interior vertex of valence 2 into a
/// two-sided face (a digon, as CGAL does), whose two sides join the two
/// faces beside it. A face is never its own neighbour: the half-edges of a
/// face that runs both ways (the digon) are paired first, each with one of
/// another face, then the rest in order.
fn pair_multi_edge(twin: &mut [u32], face: &[u32], mut forth: Vec<usize>, mut back: Vec<usize>) {
    forth.retain(|&c| twin[c] == NONE);
    back.retain(|&c| twin[c] == NONE);
    let both = |c: usize, other: &[usize]| other.iter().any(|&d| face[d] == face[c]);
    // Half-edges of faces that run both ways first.
    forth.sort_by_key(|&c| !both(c, &back));
    for c in forth {
        let pick = back.iter().position(|&d| face[d] != face[c]);
        if let Some(i) = pick {
            let d = back.remove(i);
            (twin[c], twin[d]) = (d as u32, c as u32);
        }
    }
}

/// The half-edges of a mesh by vertex, outgoing and incoming (counting
/// sorts): a half-edge's twin is found among the fewer of its end's
/// outgoing or its start's incoming ones, so a vertex of valence n (a
/// fan's apex) costs O(n), not O(n²).
struct ByVertex<'m> {
    mesh: &'m PolyMesh,
    /// The face of each corner.
    face: Vec<u32>,
    out_start: Vec<u32>,
    out: Vec<u32>,
    in_start: Vec<u32>,
    incoming: Vec<u32>,
}

impl<'m> ByVertex<'m> {
    fn new(mesh: &'m PolyMesh, face: Vec<u32>) -> ByVertex<'m> {
        let (corners, nv) = (mesh.corner_count(), mesh.positions.len());
        let next = |c: usize| {
            let f = face[c] as usize;
            if c + 1 == mesh.starts[f + 1] { mesh.starts[f] } else { c + 1 }
        };
        let by_vertex = |key: &dyn Fn(usize) -> usize| {
            let mut start = vec![0u32; nv + 1];
            (0..corners).for_each(|c| start[key(c) + 1] += 1);
            for v in 0..nv {
                start[v + 1] += start[v];
            }
            let mut list = vec![0u32; corners];
            let mut fill: Vec<u32> = start[..nv].to_vec();
            for c in 0..corners {
                let v = key(c);
                list[fill[v] as usize] = c as u32;
                fill[v] += 1;
            }
            (start, list)
        };
        let (out_start, out) = by_vertex(&|c| mesh.indices[c]);
        let (in_start, incoming) = by_vertex(&|c| mesh.indices[next(c)]);
        ByVertex { mesh, face, out_start, out, in_start, incoming }
    }

    /// The corner after `c` in its face.
    #[inline]
    fn next(&self, c: usize) -> usize {
        let f = self.face[c] as usize;
        if c + 1 == self.mesh.starts[f + 1] { self.mesh.starts[f] } else { c + 1 }
    }

    /// The half-edges out of `a` (the outgoing lists stay valid once `face` is taken).
    fn outgoing(&self, a: usize) -> impl Iterator<Item = usize> + '_ {
        self.out[self.out_start[a] as usize..self.out_start[a + 1] as usize].iter().map(|&d| d as usize)
    }

    /// The half-edges `a → b`.
    fn ends(&self, a: usize, b: usize) -> impl Iterator<Item = usize> + '_ {
        let from_a = &self.out[self.out_start[a] as usize..self.out_start[a + 1] as usize];
        let into_b = &self.incoming[self.in_start[b] as usize..self.in_start[b + 1] as usize];
        let by_start = from_a.len() <= into_b.len();
        let list = if by_start { from_a } else { into_b };
        let indices = &self.mesh.indices;
        list.iter()
            .map(|&d| d as usize)
            .filter(move |&d| if by_start { indices[self.next(d)] == b } else { indices[d] == a })
    }

    /// Checks the edge of the half-edge `c = a → b`: in at most two faces, run
    /// once each way; the faces named by `place`.
    fn check_edge(
        &self,
        c: usize,
        (a, b): (usize, usize),
        place: &dyn Fn(usize) -> Place,
    ) -> Result<(), MeshCheckError> {
        let (same, back) = (self.ends(a, b).count(), self.ends(b, a).count());
        if same + back > 2 {
            // Named at the face that comes last in the file: the one too many.
            let last = self.ends(a, b).chain(self.ends(b, a)).map(|d| self.face[d] as usize).max().unwrap_or(0);
            return Err(MeshCheckError::NonManifoldEdge {
                place: place(last),
                a: a.min(b),
                b: a.max(b),
                count: same + back,
            });
        }
        if same > 1 {
            let other = self.ends(a, b).find(|&d| d != c).unwrap_or(c);
            let (first, second) = (c.min(other), c.max(other));
            return Err(MeshCheckError::Orientation {
                place: place(self.face[second] as usize),
                a,
                b,
                other: place(self.face[first] as usize),
            });
        }
        Ok(())
    }
}

impl Topology {
    /// The half-edges of `mesh`, checked: no edge in three faces, faces
    /// consistently oriented, every vertex a single fan.
    ///
    /// # Errors
    /// The first problem found, its face named by `place`; a mesh too large
    /// for 32-bit corner numbers.
    pub fn new(mesh: &PolyMesh, place: &dyn Fn(usize) -> Place) -> Result<Topology, MeshCheckError> {
        Topology::build(mesh, Some(place), None)
    }

    /// The half-edges of a mesh known to be valid (made by subdividing a
    /// checked one): no checks, less memory.
    pub(crate) fn trusted(mesh: &PolyMesh) -> Topology {
        // Without checks the only failure is the size, excluded by the memory estimate.
        Topology::build(mesh, None, None).unwrap_or_else(|_| Topology::empty())
    }

    /// [`Topology::trusted`], stopped once the thread's ambient flag
    /// ([`crate::progress::Cancel::scope`]) is set.
    ///
    /// # Errors
    /// [`std::io::ErrorKind::Interrupted`]: cancelled.
    pub(crate) fn trusted_or_cancelled(mesh: &PolyMesh) -> std::io::Result<Topology> {
        let cancel = crate::progress::Cancel::ambient();
        let t = Topology::build(mesh, None, cancel.as_ref()).unwrap_or_else(|_| Topology::empty());
        // A topology cut short by the flag is never used.
        cancel.map_or(Ok(()), |c| c.check_io())?;
        Ok(t)
    }

    fn empty() -> Topology {
        Topology { face: Faces::Listed(Vec::new()), twin: Vec::new(), first: Vec::new(), on_border: Vec::new() }
    }

    #[allow(clippy::needless_range_loop)] // a corner indexes several arrays at once
    fn build(
        mesh: &PolyMesh,
        check: Option<&dyn Fn(usize) -> Place>,
        cancel: Option<&crate::progress::Cancel>,
    ) -> Result<Topology, MeshCheckError> {
        let corners = mesh.corner_count();
        let nv = mesh.positions.len();
        if corners >= NONE as usize || nv >= NONE as usize {
            return Err(MeshCheckError::TooLarge { corners, vertices: nv });
        }
        let mut face = vec![0u32; corners];
        for f in 0..mesh.face_count() {
            face[mesh.starts[f]..mesh.starts[f + 1]].iter_mut().for_each(|x| *x = f as u32);
        }
        let mut by = ByVertex::new(mesh, face);
        let mut twin = vec![NONE; corners];
        for c in 0..corners {
            if c % (1 << 16) == 0 && cancel.is_some_and(crate::progress::Cancel::is_cancelled) {
                return Ok(Topology::empty());
            }
            let (a, b) = (mesh.indices[c], mesh.indices[by.next(c)]);
            if let Some(place) = check {
                by.check_edge(c, (a, b), place)?;
            }
            if twin[c] != NONE {
                continue;
            }
            let mut back = by.ends(b, a).filter(|&d| twin[d] == NONE && d != c);
            match (back.next(), back.next()) {
                (None, _) => {}
                (Some(d), None) if by.ends(a, b).nth(1).is_none() => (twin[c], twin[d]) = (d as u32, c as u32),
                _ => pair_multi_edge(&mut twin, &by.face, by.ends(a, b).collect(), by.ends(b, a).collect()),
            }
        }
        let topology = Topology::with_fans(mesh, Faces::of(mesh, std::mem::take(&mut by.face)), twin);
        if check.is_some() {
            topology.check_fans(mesh, &by)?;
        }
        Ok(topology)
    }

    /// The topology of `mesh` from its corners' faces and twins: each vertex's
    /// first corner and whether it is on the border.
    fn with_fans(mesh: &PolyMesh, face: Faces, twin: Vec<u32>) -> Topology {
        let (first, on_border) =
            fans(mesh.positions.len(), 0..mesh.corner_count(), |c| mesh.indices[c], |c| wide(twin[c]));
        Topology { face, twin, first, on_border }
    }

    /// The topology of `child`, the Loop step of the triangle mesh this is the
    /// topology of, read off this one instead of searched for (the same
    /// arrays as [`Topology::trusted`] finds: a mesh made by subdividing a
    /// checked one has at most one half-edge each way between two vertices,
    /// so its twins are unique). Child `k` of face `f` is `4f + k`, corners
    /// `[v_k, m_k, m_{k−1}]`; the middle one `4f + 3` is `[m_0, m_1, m_2]`
    /// ([`PolyMesh::loop_into`]).
    pub(crate) fn loop_child(&self, child: &PolyMesh) -> Topology {
        let corners = child.corner_count();
        debug_assert_eq!(corners, 4 * self.twin.len());
        let mut twin = vec![NONE; corners];
        for (parent, &tw) in self.twin.iter().enumerate() {
            let (f, k) = (parent / 3, parent % 3);
            let base = 12 * f;
            // The middle triangle's sides: child k's corner 1 (m_k → m_{k−1}) and the middle's
            // corner (k + 2) % 3 (m_{k−1} → m_k).
            let (side, middle) = (base + 3 * k + 1, base + 9 + (k + 2) % 3);
            (twin[side], twin[middle]) = (middle as u32, side as u32);
            // The halves of the edge v_k → v_{k+1}: child k's corner 0 and child (k+1)'s corner 2;
            // the twin edge's halves run back, first half against second.
            if tw != NONE {
                let (g, j) = (tw as usize / 3, tw as usize % 3);
                let (first, second) = (base + 3 * k, base + 3 * ((k + 1) % 3) + 2);
                let (twin_first, twin_second) = (12 * g + 3 * j, 12 * g + 3 * ((j + 1) % 3) + 2);
                (twin[first], twin[second]) = (twin_second as u32, twin_first as u32);
            }
        }
        Topology::with_fans(child, Faces::Uniform(3), twin)
    }

    /// The topology of `child`, the Catmull-Clark step of `parent` (whose
    /// topology this is), read off this one as [`Topology::loop_child`] is:
    /// the quad of parent corner `c` is `4c..4c + 4`, `[v_c, m(e_c), F,
    /// m(e_prev(c))]` ([`PolyMesh::cc_quads`]).
    pub(crate) fn catmull_clark_child(&self, parent: &PolyMesh, child: &PolyMesh) -> Topology {
        let corners = child.corner_count();
        debug_assert_eq!(corners, 4 * self.twin.len());
        let mut twin = vec![NONE; corners];
        for (c, &tw) in self.twin.iter().enumerate() {
            let next = self.next(parent, c);
            // Across the face: m(e_c) → F in quad c, F → m(e_c) in quad next(c).
            (twin[4 * c + 1], twin[4 * next + 2]) = ((4 * next + 2) as u32, (4 * c + 1) as u32);
            // The halves of e_c = v_c → v_next: quad c's corner 0 and quad next(c)'s corner 3,
            // against the halves of its twin (corner 0 of quad tw, corner 3 of quad next(tw)).
            if tw != NONE {
                let tw = tw as usize;
                let tw_next = self.next(parent, tw);
                (twin[4 * c], twin[4 * next + 3]) = ((4 * tw_next + 3) as u32, (4 * tw) as u32);
            }
        }
        Topology::with_fans(child, Faces::Uniform(4), twin)
    }

    /// One fan per vertex: walks of the rotation, from the border corners
    /// first, cover its corners. Corners already walked are marked, then
    /// unmarked vertex by vertex: linear in all.
    fn check_fans(&self, mesh: &PolyMesh, by: &ByVertex<'_>) -> Result<(), MeshCheckError> {
        let mut seen = vec![false; mesh.corner_count()];
        for v in 0..mesh.positions.len() {
            let mut fans = 0;
            let starts = by.outgoing(v).filter(|&c| self.twin[c] == NONE).chain(by.outgoing(v));
            for c0 in starts {
                if seen[c0] {
                    continue;
                }
                fans += 1;
                let mut c = c0;
                while c != BORDER && !seen[c] {
                    seen[c] = true;
                    c = self.rotate(mesh, c);
                }
            }
            by.outgoing(v).for_each(|c| seen[c] = false);
            if fans > 1 {
                return Err(MeshCheckError::NonManifoldVertex(v, fans));
            }
        }
        Ok(())
    }

    /// The face of corner `c`.
    #[inline]
    pub fn face(&self, c: usize) -> usize {
        self.face.of_corner(c)
    }

    /// The twin of half-edge `c`, or [`BORDER`].
    #[inline]
    pub fn twin(&self, c: usize) -> usize {
        wide(self.twin[c])
    }

    /// An outgoing corner of vertex `v` ([`BORDER`] when unused): for a
    /// border vertex, the one whose half-edge is on the border, from which
    /// [`Topology::rotate`] walks its whole fan.
    #[inline]
    pub fn first(&self, v: usize) -> usize {
        wide(self.first[v])
    }

    /// Whether vertex `v` is on the border.
    #[inline]
    pub fn on_border(&self, v: usize) -> bool {
        self.on_border[v]
    }

    /// The corner after `c` in its face.
    #[inline]
    pub fn next(&self, mesh: &PolyMesh, c: usize) -> usize {
        let f = self.face(c);
        if c + 1 == mesh.starts[f + 1] { mesh.starts[f] } else { c + 1 }
    }

    /// The corner before `c` in its face.
    #[inline]
    pub fn prev(&self, mesh: &PolyMesh, c: usize) -> usize {
        let f = self.face(c);
        if c == mesh.starts[f] { mesh.starts[f + 1] - 1 } else { c - 1 }
    }

    /// The next outgoing corner around the vertex of `c` (counter-clockwise
    /// seen from outside): the twin of the half-edge coming into it in its
    /// face, or [`BORDER`].
    #[inline]
    pub fn rotate(&self, mesh: &PolyMesh, c: usize) -> usize {
        self.twin(self.prev(mesh, c))
    }

    /// The border neighbours `(u, w)` of the border vertex whose first
    /// corner is `c0`: `w` ends the border half-edge going out, `u` starts the
    /// one coming in.
    pub fn border_neighbours(&self, mesh: &PolyMesh, c0: usize) -> (usize, usize) {
        Made { mesh, t: self }.border_neighbours(c0)
    }

    /// The number of faces around the interior vertex `v` (its outgoing
    /// corners, walked by the rotation); for a border vertex, those of its fan.
    pub fn valence(&self, mesh: &PolyMesh, v: usize) -> usize {
        let first = self.first(v);
        let (mut c, mut n) = (first, 0);
        while c != BORDER {
            n += 1;
            c = self.rotate(mesh, c);
            if c == first {
                break;
            }
        }
        n
    }

    /// Number of border half-edges.
    pub fn boundary_edges(&self) -> usize {
        self.twin.iter().filter(|t| **t == NONE).count()
    }
}

/// A net: vertices with positions, corners (half-edges) with their vertex,
/// the next and previous corner of their face and their twin.
pub(crate) trait Net: Sync {
    /// Vertices.
    fn vertex_count(&self) -> usize;
    /// Corners: the numbers of corners are below this (all of them are
    /// corners unless [`Net::is_corner`] says otherwise).
    fn corner_count(&self) -> usize;
    /// Whether `c` numbers a corner (a named net may skip numbers; a face's three are all corners or none).
    fn is_corner(&self, _c: usize) -> bool {
        true
    }
    /// The vertex of corner `c`.
    fn vertex(&self, c: usize) -> usize;
    /// The position of vertex `v`.
    fn point(&self, v: usize) -> [f64; 3];
    /// The twin of half-edge `c`, or [`BORDER`].
    fn twin(&self, c: usize) -> usize;
    /// An outgoing corner of `v` (the border one for a border vertex), or [`BORDER`] when unused.
    fn first(&self, v: usize) -> usize;
    /// Whether `v` is on the border.
    fn on_border(&self, v: usize) -> bool;
    /// The corner after `c` in its face.
    fn next(&self, c: usize) -> usize;
    /// The corner before `c` in its face.
    fn prev(&self, c: usize) -> usize;

    /// The next outgoing corner around the vertex of `c`, or [`BORDER`] ([`Topology::rotate`]).
    #[inline]
    fn rotate(&self, c: usize) -> usize {
        self.twin(self.prev(c))
    }

    /// The border neighbours `(u, w)` of the border vertex whose first corner
    /// is `c0`: `w` ends the border half-edge going out, `u` starts the one
    /// coming in.
    fn border_neighbours(&self, c0: usize) -> (usize, usize) {
        let w = self.vertex(self.next(c0));
        let mut last = c0;
        while self.rotate(last) != BORDER {
            last = self.rotate(last);
        }
        (self.vertex(self.prev(last)), w)
    }
}

/// The ring of the interior vertex whose first corner is `c0`: its neighbours in rotation order.
pub(crate) fn ring<N: Net>(net: &N, c0: usize) -> impl Iterator<Item = usize> + '_ {
    let mut at = Some(c0);
    std::iter::from_fn(move || {
        let c = at?;
        let r = net.rotate(c);
        at = (r != BORDER && r != c0).then_some(r);
        Some(net.vertex(net.next(c)))
    })
}

/// A net in memory.
#[derive(Clone, Copy)]
pub(crate) struct Made<'a> {
    pub(crate) mesh: &'a PolyMesh,
    pub(crate) t: &'a Topology,
}

impl Net for Made<'_> {
    #[inline]
    fn vertex_count(&self) -> usize {
        self.mesh.positions.len()
    }
    #[inline]
    fn corner_count(&self) -> usize {
        self.mesh.indices.len()
    }
    #[inline]
    fn vertex(&self, c: usize) -> usize {
        self.mesh.indices[c]
    }
    #[inline]
    fn point(&self, v: usize) -> [f64; 3] {
        self.mesh.positions[v]
    }
    #[inline]
    fn twin(&self, c: usize) -> usize {
        self.t.twin(c)
    }
    #[inline]
    fn first(&self, v: usize) -> usize {
        self.t.first(v)
    }
    #[inline]
    fn on_border(&self, v: usize) -> bool {
        self.t.on_border(v)
    }
    #[inline]
    fn next(&self, c: usize) -> usize {
        self.t.next(self.mesh, c)
    }
    #[inline]
    fn prev(&self, c: usize) -> usize {
        self.t.prev(self.mesh, c)
    }
}

impl PolyMesh {
    /// A checked mesh.
    ///
    /// # Errors
    /// Indices out of range, degenerate faces, non-finite coordinates,
    /// non-manifold edges or vertices, inconsistent orientation, no face.
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<Vec<usize>>) -> Result<PolyMesh, MeshCheckError> {
        let mut starts = Vec::with_capacity(faces.len() + 1);
        starts.push(0);
        for f in &faces {
            starts.push(starts[starts.len() - 1] + f.len());
        }
        let mesh = PolyMesh::from_flat(positions, starts, faces.concat());
        mesh.check(&|face| Place { file: None, line: None, face })?;
        Ok(mesh)
    }

    /// Checks the mesh, naming faces with `place`.
    pub(crate) fn check(&self, place: &dyn Fn(usize) -> Place) -> Result<(), MeshCheckError> {
        if self.face_count() == 0 {
            return Err(MeshCheckError::Empty);
        }
        if let Some(i) = self.positions.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(MeshCheckError::NotFinite(i));
        }
        if let Some((vertex, p)) =
            self.positions.iter().enumerate().find(|(_, p)| p.iter().any(|x| x.abs() > crate::geometry::MAX_COORDINATE))
        {
            let value = p.iter().copied().max_by(|a, b| a.abs().total_cmp(&b.abs())).unwrap_or(0.0);
            return Err(MeshCheckError::Scale { vertex, value });
        }
        for (f, face) in self.faces().enumerate() {
            if let Some(&index) = face.iter().find(|&&v| v >= self.positions.len()) {
                return Err(MeshCheckError::IndexOutOfRange {
                    place: place(f),
                    index: index as i64,
                    count: self.positions.len(),
                });
            }
            let mut sorted = face.to_vec();
            sorted.sort_unstable();
            sorted.dedup();
            if face.len() < 3 || sorted.len() != face.len() {
                return Err(MeshCheckError::Degenerate { place: place(f), vertices: face.to_vec() });
            }
            let point = self.positions[face[0]];
            if face.iter().all(|&v| self.positions[v] == point) {
                return Err(MeshCheckError::Collapsed { place: place(f), vertices: face.to_vec(), point });
            }
        }
        Topology::new(self, place).map(|_| ())
    }

    /// The valences of the interior vertices that occur (sorted, once
    /// each), and 6, which subdivision makes everywhere.
    pub fn interior_valences(&self) -> Vec<usize> {
        let t = Topology::trusted(self);
        let mut count = vec![0usize; self.positions.len()];
        self.indices.iter().for_each(|&v| count[v] += 1);
        let mut out: Vec<usize> = (0..self.positions.len())
            .filter(|&v| t.first(v) != BORDER && !t.on_border(v))
            .map(|v| count[v])
            .chain([6])
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Whether some vertex is inside the mesh (not on its border).
    pub fn has_interior_vertex(&self) -> bool {
        let t = Topology::trusted(self);
        (0..self.positions.len()).any(|v| t.first(v) != BORDER && !t.on_border(v))
    }

    /// Whether every edge is in two faces.
    pub fn is_closed(&self) -> bool {
        Topology::trusted(self).boundary_edges() == 0
    }
}
