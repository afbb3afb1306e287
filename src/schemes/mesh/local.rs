//! The neighbourhood of a cell: a small mesh with open sides, walked from an anchor half-edge.

use std::collections::{HashMap, VecDeque};

use crate::mesh::{PolyMesh, Scheme};
use crate::space::CellKind;

/// What a cell is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Role {
    Face,
    Edge,
    Vertex,
}

impl Role {
    pub(super) fn name(self) -> &'static str {
        match self {
            Role::Face => "face",
            Role::Edge => "edge",
            Role::Vertex => "vertex",
        }
    }
    pub(super) fn kind(self) -> CellKind {
        match self {
            Role::Face => CellKind::Face,
            Role::Edge => CellKind::Edge,
            Role::Vertex => CellKind::Vertex,
        }
    }
    /// The role of its sides.
    pub(super) fn side(self) -> Role {
        match self {
            Role::Face => Role::Edge,
            _ => Role::Vertex,
        }
    }
}

/// What is across a side of a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Side {
    /// Another face of the same (local) mesh.
    Inner,
    /// Nothing: the border of the surface.
    Border,
    /// A face outside the neighbourhood.
    Cut,
}

/// A half-edge: face `.0`, from its corner `.1` to the next.
pub(super) type Half = (usize, usize);

/// A mesh with its half-edges (the input, a neighbourhood, or a subdivided one).
#[derive(Clone, Debug)]
pub(super) struct Local {
    pub(super) faces: Vec<Vec<usize>>,
    pub(super) sides: Vec<Vec<Side>>,
    pub(super) vertices: usize,
    /// The half-edge from `a` to `b` of a face of three or more corners, by `(a, b)`.
    pub(super) twin: HashMap<(usize, usize), Half>,
    /// The half-edge from `a` to `b` of a two-corner face (Doo-Sabin's face of a border vertex
    /// between two faces), by `(a, b)`: it lies between the two faces of that edge.
    digon: HashMap<(usize, usize), Half>,
    pub(super) around: Vec<Vec<Half>>,
}

impl Local {
    pub(super) fn new(faces: Vec<Vec<usize>>, sides: Vec<Vec<Side>>, vertices: usize) -> Local {
        let (mut twin, mut digon) = (HashMap::new(), HashMap::new());
        let mut around = vec![Vec::new(); vertices];
        for (f, face) in faces.iter().enumerate() {
            let by = if face.len() == 2 { &mut digon } else { &mut twin };
            for (i, &v) in face.iter().enumerate() {
                by.insert((v, face[(i + 1) % face.len()]), (f, i));
                around[v].push((f, i));
            }
        }
        Local { faces, sides, vertices, twin, digon, around }
    }

    /// A mesh whose sides without a face across are all `open`: the
    /// border of a whole mesh, or the cut edge of a neighbourhood.
    pub(super) fn with_open_sides(faces: Vec<Vec<usize>>, vertices: usize, open: Side) -> Local {
        let mut local = Local::new(faces, Vec::new(), vertices);
        local.sides = (0..local.faces.len())
            .map(|f| {
                (0..local.faces[f].len())
                    .map(|i| if local.twin_of((f, i)).is_some() { Side::Inner } else { open })
                    .collect()
            })
            .collect();
        local
    }

    pub(super) fn of_mesh(mesh: &PolyMesh) -> Local {
        Local::with_open_sides(mesh.faces().map(<[usize]>::to_vec).collect(), mesh.positions.len(), Side::Border)
    }

    pub(super) fn deg(&self, f: usize) -> usize {
        self.faces[f].len()
    }
    pub(super) fn at(&self, (f, i): Half) -> usize {
        self.faces[f][i % self.deg(f)]
    }
    pub(super) fn head(&self, (f, i): Half) -> usize {
        self.faces[f][(i + 1) % self.deg(f)]
    }
    pub(super) fn next(&self, (f, i): Half) -> Half {
        (f, (i + 1) % self.deg(f))
    }
    pub(super) fn prev(&self, (f, i): Half) -> Half {
        (f, (i + self.deg(f) - 1) % self.deg(f))
    }
    /// The half-edge across `h`. A two-corner face sits between the two faces of its edge: each
    /// of its sides is across one of theirs (the subdivision's nets pair them so).
    pub(super) fn twin_of(&self, h: Half) -> Option<Half> {
        let back = (self.head(h), self.at(h));
        if self.deg(h.0) == 2 {
            return self.twin.get(&back).copied();
        }
        self.digon.get(&back).or_else(|| self.twin.get(&back)).copied()
    }
    /// The next half-edge out of the same vertex, counter-clockwise.
    pub(super) fn rotate(&self, h: Half) -> Option<Half> {
        self.twin_of(self.prev(h))
    }
    /// Whether every side at vertex `v` has a face across it.
    pub(super) fn closed_at(&self, v: usize) -> bool {
        !self.around[v].is_empty()
            && self.around[v].iter().all(|&h| self.sides[h.0][h.1] == Side::Inner && self.twin_of(h).is_some())
    }
    /// The half-edges out of `v` counter-clockwise from `h` (a closed fan).
    pub(super) fn fan(&self, h: Half) -> Vec<Half> {
        let mut out = vec![h];
        let mut at = h;
        while let Some(r) = self.rotate(at) {
            if r == h || out.len() > self.around[self.at(h)].len() {
                break;
            }
            out.push(r);
            at = r;
        }
        out
    }
    /// The side of half-edge `h` as seen from a neighbourhood of faces `set`.
    pub(super) fn side_in(&self, h: Half, set: &[usize]) -> Side {
        match self.twin_of(h) {
            Some((g, _)) if set.binary_search(&g).is_ok() => Side::Inner,
            Some(_) => Side::Cut,
            None => self.sides[h.0][h.1],
        }
    }
}

/// A cell's neighbourhood walked from its anchor: the canonical local mesh,
/// the mesh vertices in the order of its control points, and its key.
pub(super) struct Walk {
    pub(super) local: Local,
    pub(super) order: Vec<usize>,
    pub(super) key: Vec<u32>,
}

/// The faces a cell's limit depends on (sorted).
pub(super) fn neighbourhood(scheme: Scheme, role: Role, m: &Local, h: Half) -> Vec<usize> {
    let faces_at = |v: usize| m.around[v].iter().map(|&(f, _)| f);
    // √3's stencils reach further in two steps: the faces around the faces' vertices.
    let widen = |faces: Vec<usize>| -> Vec<usize> {
        faces.iter().flat_map(|&f| m.faces[f].iter().flat_map(|&v| faces_at(v))).collect()
    };
    let mut set: Vec<usize> = match (scheme, role) {
        (Scheme::Sqrt3, Role::Face) => widen(m.faces[h.0].iter().flat_map(|&v| faces_at(v)).collect()),
        (Scheme::Sqrt3, Role::Edge) => widen(faces_at(m.at(h)).chain(faces_at(m.head(h))).collect()),
        (Scheme::Sqrt3, Role::Vertex) => widen(faces_at(m.at(h)).collect()),
        (Scheme::DooSabin, Role::Face) => faces_at(m.at(h)).collect(),
        (Scheme::DooSabin, Role::Edge) => std::iter::once(h.0).chain(m.twin_of(h).map(|t| t.0)).collect(),
        (Scheme::DooSabin, Role::Vertex) => vec![h.0],
        (_, Role::Face) => m.faces[h.0].iter().flat_map(|&v| faces_at(v)).collect(),
        (_, Role::Edge) => faces_at(m.at(h)).chain(faces_at(m.head(h))).collect(),
        (_, Role::Vertex) => faces_at(m.at(h)).collect(),
    };
    set.sort_unstable();
    set.dedup();
    set
}

/// Walks the faces `set` of `m` breadth first from half-edge `h`: faces
/// are entered at the half-edge they share with the face they are reached
/// from, vertices numbered as they are met.
pub(super) fn walk(m: &Local, set: &[usize], h: Half) -> Option<Walk> {
    let mut number: HashMap<usize, usize> = HashMap::new();
    let mut order = Vec::new();
    let (mut faces, mut sides, mut key) = (Vec::new(), Vec::new(), Vec::new());
    let mut seen = vec![h.0];
    let mut queue = VecDeque::from([h]);
    while let Some((f, s)) = queue.pop_front() {
        let d = m.deg(f);
        let (mut face, mut side) = (Vec::with_capacity(d), Vec::with_capacity(d));
        key.push(d as u32);
        for k in 0..d {
            let c = (f, (s + k) % d);
            let v = m.at(c);
            let id = *number.entry(v).or_insert_with(|| {
                order.push(v);
                order.len() - 1
            });
            face.push(id);
            key.push(id as u32);
            let sd = m.side_in(c, set);
            if sd == Side::Inner {
                let t = m.twin_of(c)?;
                if !seen.contains(&t.0) {
                    seen.push(t.0);
                    queue.push_back(t);
                }
            }
            key.push(sd as u32);
            side.push(sd);
        }
        faces.push(face);
        sides.push(side);
    }
    // A neighbourhood that is not one piece: a vertex where two fans touch.
    if seen.len() != set.len() {
        return None;
    }
    let n = order.len();
    Some(Walk { local: Local::new(faces, sides, n), order, key })
}

/// Where the children of a cell are, and its sides, as half-edges.
pub(super) fn sides_of(scheme: Scheme, role: Role, m: &Local, h: Half) -> Vec<Half> {
    match (scheme, role) {
        (_, Role::Vertex) => Vec::new(),
        (Scheme::DooSabin, Role::Face) => m.fan(h).into_iter().map(|g| m.prev(g)).collect(),
        (Scheme::DooSabin, Role::Edge) => vec![h, m.twin_of(h).unwrap_or(h)],
        (_, Role::Face) => (0..m.deg(h.0)).map(|k| (h.0, (h.1 + k) % m.deg(h.0))).collect(),
        (_, Role::Edge) => vec![h, m.next(h)],
    }
}
