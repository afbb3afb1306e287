//! Nets named from the net before them, without their faces being made:
//! a Loop step's corners, twins, first corners and edge numbers are read off
//! its parent's ([`LoopChild`]), so the rules and limit masks written on
//! [`Net`] give the made net's numbers bit for bit, in a fraction of its memory.

use super::polymesh::PolyMesh;
use super::subdivide::LoopWeights;
use super::topology::{BORDER, Made, Net, Topology, fans, triangle_next, triangle_prev, wide};

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
        let (nc, faces) = (child.corner_count(), mesh.face_count());
        (child.first, child.on_border) = fans(child.points.len(), 0..nc, |x| child.vertex(x), |x| child.twin(x));
        let (mut numbering, mut edges_before) = (vec![0u16; faces], vec![0u32; faces]);
        let mut edges = 0u32;
        for x in 0..nc {
            let tw = child.twin(x);
            if x % 12 == 0 {
                edges_before[x / 12] = edges;
            }
            if tw == BORDER || x < tw {
                numbering[x / 12] |= 1 << (x % 12);
                edges += 1;
            }
        }
        (child.numbering, child.edges_before) = (numbering, edges_before);
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
        wide(self.first[v])
    }
    #[inline]
    fn on_border(&self, v: usize) -> bool {
        self.on_border[v]
    }
    #[inline]
    fn next(&self, x: usize) -> usize {
        triangle_next(x)
    }
    #[inline]
    fn prev(&self, x: usize) -> usize {
        triangle_prev(x)
    }
}

/// One √3 step of a triangle net (made or itself named), named from it:
/// the step [`PolyMesh::sqrt3_into`] makes, without its faces being made.
/// A face of the step is numbered by the parent corner that emits it and
/// its slot: corner `6e + 3s + j` is corner `j` of the `s`-th face emitted
/// for parent corner `e` (a border corner emits one face, the smaller corner
/// of an interior edge two, the other none), so the order of these numbers
/// is the made net's corner order and the first corner of a vertex is the
/// smallest of its numbers, as [`Topology`] picks it. Only the vertices'
/// first corners, the parent faces' first new points and (for the parent
/// named once) the points are kept.
pub(crate) struct Sqrt3Child<'a, P> {
    parent: &'a P,
    /// This step splits the border (CGAL's odd steps, counted from 0).
    refine: bool,
    /// Per parent face (corner / 3): the number of its first new point.
    first_point: Vec<u32>,
    /// Per parent face: its border corner (0 to 2) when this step splits it, else 3.
    split: Vec<u8>,
    /// Per new point (vertex number minus the parent's vertices): its parent face.
    point_face: Vec<u32>,
    /// The points, when kept (else computed when asked).
    points: Vec<[f64; 3]>,
    /// Per vertex: an outgoing corner (the border one), as [`Topology`] picks it.
    first: Vec<u32>,
    /// Per vertex: on the border.
    on_border: Vec<bool>,
}

impl<'a, P: Net> Sqrt3Child<'a, P> {
    /// The √3 step of `parent` (`refine`: a border-splitting step), its
    /// points kept when `keep_points`. `None` when a face of `parent` has
    /// two border edges on a splitting step (the made step is used then).
    pub(crate) fn new(parent: &'a P, refine: bool, keep_points: bool) -> Option<Sqrt3Child<'a, P>> {
        let faces = parent.corner_count() / 3;
        let mut child = Sqrt3Child {
            parent,
            refine,
            first_point: vec![NONE; faces],
            split: vec![3; faces],
            point_face: Vec::new(),
            points: Vec::new(),
            first: Vec::new(),
            on_border: Vec::new(),
        };
        let mut next_point = parent.vertex_count();
        // Corner and vertex numbers are kept in 32 bits.
        u32::try_from(child.corner_count()).ok()?;
        for f in (0..faces).filter(|&f| parent.is_corner(3 * f)) {
            let mut borders = (0..3u8).filter(|&i| parent.twin(3 * f + usize::from(i)) == BORDER);
            let new = match (refine, borders.next(), borders.next()) {
                (true, Some(_), Some(_)) => return None,
                (true, Some(i), None) => {
                    child.split[f] = i;
                    2
                }
                _ => 1,
            };
            child.first_point[f] = u32::try_from(next_point).ok()?;
            child.point_face.extend(std::iter::repeat_n(f as u32, new));
            next_point += new;
        }
        let nv = next_point;
        let corners = (0..child.corner_count()).filter(|&x| child.is_corner(x));
        (child.first, child.on_border) = fans(nv, corners, |x| child.vertex(x), |x| child.twin(x));
        if keep_points {
            use rayon::prelude::*;
            child.points = (0..nv).into_par_iter().map(|v| child.point(v)).collect();
        }
        Some(child)
    }

    /// The border corner of parent face `f` when this step splits it.
    #[inline]
    fn split(&self, f: usize) -> Option<usize> {
        match self.split[f] {
            3 => None,
            i => Some(3 * f + usize::from(i)),
        }
    }

    /// The new point across from parent half-edge `e` in its face: the
    /// centroid, or on a split face the border point beside `e`'s end.
    #[inline]
    fn opposite(&self, e: usize) -> usize {
        let f = e / 3;
        let first = self.first_point[f] as usize;
        match self.split(f) {
            Some(cb) if e == self.parent.next(cb) => first + 1,
            _ => first,
        }
    }

    /// The corner of the new half-edge from `e`'s new point to `e`'s start (`e` not a split border corner).
    #[inline]
    fn out_corner(&self, e: usize) -> usize {
        match self.parent.twin(e) {
            BORDER => 6 * e + 2,
            tw if e < tw => 6 * e + 3,
            tw => 6 * tw,
        }
    }

    /// The corner of the new half-edge from `e`'s end to `e`'s new point.
    #[inline]
    fn in_corner(&self, e: usize) -> usize {
        match self.parent.twin(e) {
            BORDER => 6 * e + 1,
            tw if e < tw => 6 * e + 1,
            tw => 6 * tw + 4,
        }
    }

    /// The twin of [`Sqrt3Child::out_corner`]`(e)`.
    #[inline]
    fn twin_of_out(&self, e: usize) -> usize {
        let p = self.parent;
        match self.split(e / 3) {
            Some(cb) if e == p.next(cb) => BORDER,
            Some(cb) if e == p.prev(cb) => 6 * cb + 2,
            _ => self.in_corner(p.prev(e)),
        }
    }

    /// The twin of [`Sqrt3Child::in_corner`]`(e)`.
    #[inline]
    fn twin_of_in(&self, e: usize) -> usize {
        let p = self.parent;
        match self.split(e / 3) {
            Some(cb) if e == p.next(cb) => 6 * cb + 1,
            Some(cb) if e == p.prev(cb) => BORDER,
            _ => self.out_corner(p.next(e)),
        }
    }
}

impl<P: Net> Net for Sqrt3Child<'_, P> {
    fn vertex_count(&self) -> usize {
        self.parent.vertex_count() + self.point_face.len()
    }
    fn corner_count(&self) -> usize {
        6 * self.parent.corner_count()
    }
    fn is_corner(&self, x: usize) -> bool {
        let (e, s) = (x / 6, x % 6 / 3);
        self.parent.is_corner(e)
            && match self.parent.twin(e) {
                BORDER => s == 0,
                tw => e < tw,
            }
    }
    fn vertex(&self, x: usize) -> usize {
        let (e, s, j) = (x / 6, x % 6 / 3, x % 3);
        let p = self.parent;
        match p.twin(e) {
            BORDER => match self.split(e / 3) {
                Some(_) => {
                    let first = self.first_point[e / 3] as usize;
                    [first, first + 1, p.vertex(p.prev(e))][j]
                }
                None => [p.vertex(e), p.vertex(p.next(e)), self.opposite(e)][j],
            },
            tw if s == 0 => [self.opposite(tw), p.vertex(p.next(e)), self.opposite(e)][j],
            tw => [self.opposite(e), p.vertex(e), self.opposite(tw)][j],
        }
    }
    fn point(&self, v: usize) -> [f64; 3] {
        if let Some(p) = self.points.get(v) {
            return *p;
        }
        let nv = self.parent.vertex_count();
        if v < nv {
            return super::subdivide::sqrt3_vertex(self.parent, self.refine, v);
        }
        let f = self.point_face[v - nv] as usize;
        match self.split(f) {
            Some(cb) => super::subdivide::sqrt3_border_points(self.parent, cb)[v - self.first_point[f] as usize],
            None => {
                let mut c = [0.0; 3];
                for k in 3 * f..3 * f + 3 {
                    let q = self.parent.point(self.parent.vertex(k));
                    (0..3).for_each(|a| c[a] += q[a] / 3.0);
                }
                c
            }
        }
    }
    fn twin(&self, x: usize) -> usize {
        let (e, s, j) = (x / 6, x % 6 / 3, x % 3);
        let p = self.parent;
        let tw = p.twin(e);
        if tw == BORDER {
            // `[a, b, F]` (or split: `[X1, X2, w]`): its first side is on the border.
            return match (j, self.split(e / 3).is_some()) {
                (0, _) => BORDER,
                (1, true) => self.in_corner(p.next(e)),
                (_, true) => self.out_corner(p.prev(e)),
                (1, false) => self.twin_of_in(e),
                (_, false) => self.twin_of_out(e),
            };
        }
        // `[F(tw), b, F(e)]` and `[F(e), a, F(tw)]`: spokes, then the flipped edge.
        match (s, j) {
            (0, 0) => self.twin_of_out(tw),
            (0, 1) => self.twin_of_in(e),
            (1, 0) => self.twin_of_out(e),
            (1, 1) => self.twin_of_in(tw),
            (s, _) => 6 * e + 3 * (1 - s) + 2,
        }
    }
    fn first(&self, v: usize) -> usize {
        wide(self.first[v])
    }
    fn on_border(&self, v: usize) -> bool {
        self.on_border[v]
    }
    fn next(&self, x: usize) -> usize {
        triangle_next(x)
    }
    fn prev(&self, x: usize) -> usize {
        triangle_prev(x)
    }
}
