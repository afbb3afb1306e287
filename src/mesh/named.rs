//! Nets named from the net before them, without their faces being made:
//! a Loop step's corners, twins, first corners and edge numbers are read off
//! its parent's ([`LoopChild`]), so the rules and limit masks written on
//! [`Net`] give the made net's numbers bit for bit, in a fraction of its memory.

use super::polymesh::PolyMesh;
use super::subdivide::LoopWeights;
use super::topology::{BORDER, Made, Net, Topology};

/// The corner of the Loop step of a triangle net that is corner `j` of
/// child `i` of the face of coarse corner `c`: face `f`'s children are
/// `[v0, e0, e2]`, `[v1, e1, e0]`, `[v2, e2, e1]`, `[e0, e1, e2]`, their
/// corners `12f .. 12f + 11` ([`PolyMesh::loop_into`]).
#[inline]
pub(crate) fn loop_corner(c: usize, i: usize, j: usize) -> usize {
    12 * (c / 3) + 3 * i + j
}

/// The twin of corner `x` of the Loop step of a triangle net whose twins
/// are `twin` ([`super::topology::Topology::loop_child`] makes the same).
#[inline(always)]
pub(crate) fn loop_child_twin(twin: impl Fn(usize) -> usize, x: usize) -> usize {
    let (f, i, j) = (x / 12, x % 12 / 3, x % 3);
    match (i, j) {
        (3, j) => 12 * f + 3 * ((j + 1) % 3) + 1,
        (i, 0) => match twin(3 * f + i) {
            BORDER => BORDER,
            tw => loop_corner(tw, (tw % 3 + 1) % 3, 2),
        },
        (i, 1) => 12 * f + 9 + (i + 2) % 3,
        (i, _) => match twin(3 * f + (i + 2) % 3) {
            BORDER => BORDER,
            tp => loop_corner(tp, tp % 3, 0),
        },
    }
}

/// The Loop step of a triangle net, named from it: its points made (the
/// vertex points, then the edge points in edge order, as
/// [`PolyMesh::loop_into`] makes them), its corners, twins, first corners
/// and edge numbers read off the net before, its faces never made. At a
/// depth-9 icosahedron this is 24 bytes a vertex and under 3 a corner,
/// where the made net with its topology and edge numbers takes 74 bytes a
/// face.
pub(crate) struct LoopChild<'a> {
    parent: Made<'a>,
    /// The points of this net.
    points: Vec<[f64; 3]>,
    /// The parent's edge numbers, by corner.
    edge_of: Vec<u32>,
    /// Per vertex: an outgoing corner (the border one), as [`Topology`] picks it.
    first: Vec<u32>,
    /// Per vertex: on the border.
    on_border: Vec<bool>,
    /// Per parent face: the corners among its twelve children's that number
    /// an edge (the smaller of a pair, or a border one), as bits.
    numbering: Vec<u16>,
    /// Per parent face: the edges numbered before its children's corners.
    edges_before: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl<'a> LoopChild<'a> {
    /// The Loop step (weights `custom`, `None` for Loop's) of the triangle net `mesh`, named.
    pub(crate) fn new(mesh: &'a PolyMesh, t: &'a Topology, custom: Option<LoopWeights>) -> LoopChild<'a> {
        let parent = Made { mesh, t };
        let mut points = super::emit::Emit::points();
        // Writing into memory cannot fail.
        let (edge_of, _) = mesh.loop_points_into(t, custom, &mut points).unwrap_or_default();
        let mut child = LoopChild {
            parent,
            points: points.into_points(),
            edge_of,
            first: Vec::new(),
            on_border: Vec::new(),
            numbering: Vec::new(),
            edges_before: Vec::new(),
        };
        let (nv, nc, faces) = (child.points.len(), child.corner_count(), mesh.face_count());
        // First corners as `Topology` finds them: the border corner, else the first one.
        let (mut first, mut on_border) = (vec![NONE; nv], vec![false; nv]);
        let (mut numbering, mut edges_before) = (vec![0u16; faces], vec![0u32; faces]);
        let mut edges = 0u32;
        for x in 0..nc {
            let (v, tw) = (child.vertex(x), child.twin(x));
            if tw == BORDER {
                on_border[v] = true;
                first[v] = x as u32;
            } else if first[v] == NONE {
                first[v] = x as u32;
            }
            if x % 12 == 0 {
                edges_before[x / 12] = edges;
            }
            if tw == BORDER || x < tw {
                numbering[x / 12] |= 1 << (x % 12);
                edges += 1;
            }
        }
        (child.first, child.on_border, child.numbering, child.edges_before) =
            (first, on_border, numbering, edges_before);
        child
    }

    /// The edge number of corner `x`, as [`PolyMesh::edge_numbering`] numbers the made net's.
    #[inline]
    pub(crate) fn edge(&self, x: usize) -> usize {
        let tw = self.twin(x);
        let y = if tw == BORDER || x < tw { x } else { tw };
        let (f, k) = (y / 12, y % 12);
        self.edges_before[f] as usize + (self.numbering[f] & ((1u16 << k) - 1)).count_ones() as usize
    }
}

impl Net for LoopChild<'_> {
    #[inline]
    fn vertex_count(&self) -> usize {
        self.points.len()
    }
    #[inline]
    fn corner_count(&self) -> usize {
        4 * self.parent.corner_count()
    }
    #[inline(always)]
    fn vertex(&self, x: usize) -> usize {
        let (s, i, j) = (x / 12 * 3, x % 12 / 3, x % 3);
        let nv = self.parent.vertex_count();
        let m = |c: usize| nv + self.edge_of[c] as usize;
        match (i, j) {
            (3, j) => m(s + j),
            (i, 0) => self.parent.vertex(s + i),
            (i, 1) => m(s + i),
            (i, _) => m(s + (i + 2) % 3),
        }
    }
    #[inline]
    fn point(&self, v: usize) -> [f64; 3] {
        self.points[v]
    }
    #[inline]
    fn twin(&self, x: usize) -> usize {
        loop_child_twin(|c| self.parent.twin(c), x)
    }
    #[inline]
    fn first(&self, v: usize) -> usize {
        match self.first[v] {
            NONE => BORDER,
            c => c as usize,
        }
    }
    #[inline]
    fn on_border(&self, v: usize) -> bool {
        self.on_border[v]
    }
    #[inline]
    fn next(&self, x: usize) -> usize {
        x - x % 3 + (x + 1) % 3
    }
    #[inline]
    fn prev(&self, x: usize) -> usize {
        x - x % 3 + (x + 2) % 3
    }
}
