//! The states, arrows and constraints found by subdividing neighbourhoods until no new kind of cell appears.

use std::collections::HashMap;

use super::error::MeshAutomatonError;
use super::local::{Half, Local, Role, Side, Walk, neighbourhood, sides_of, walk};
use super::rules::{Lin, Step, Weights, sqrt3_children, step, value};
use crate::automaton::ArrowKind;
use crate::design::{Design, DesignBuilder, Matrix, Model, Value};
use crate::mesh::{PolyMesh, Scheme};

/// The children of a cell anchored at `h`, anchored in the subdivided mesh.
pub(super) fn children_of(scheme: Scheme, role: Role, m: &Local, s: &Step, h: Half) -> Vec<Half> {
    let (f, i) = h;
    match (scheme, role) {
        (Scheme::Sqrt3, _) => sqrt3_children(role, m, s, h),
        (Scheme::DooSabin, Role::Face) => m
            .fan(h)
            .into_iter()
            .enumerate()
            .map(|(k, (g, j))| {
                // The k-th face around turned back by k quarter turns: the child keeps the parent's orientation.
                let fan = s.mesh.fan((s.child[g][0], j));
                fan[(4 - k % 4) % 4 % fan.len()]
            })
            .collect(),
        (Scheme::DooSabin, Role::Edge) => {
            let (e, c) = s.edge_face.get(&h).copied().unwrap_or((usize::MAX, 0));
            // a_f → b_f in the face's face; then the edge face's side shared with the twin's face.
            vec![(s.child[f][0], i), (e, (c + 1) % 4)]
        }
        (Scheme::DooSabin, Role::Vertex) => vec![(s.child[f][0], i)],
        (_, Role::Face) => {
            // Translated copies: the child at corner i + k is anchored at its corner
            // that the translation takes the parent's anchor to; Loop's middle
            // triangle is a half-turned copy.
            let d = m.deg(f);
            let mut out: Vec<Half> = (0..d)
                .map(|k| {
                    let child = s.child[f][(i + k) % d];
                    let n = s.mesh.deg(child);
                    (child, (n - k % n) % n)
                })
                .collect();
            if scheme == Scheme::Loop {
                out.push((s.middle[f], (i + 1) % 3));
            }
            out
        }
        (_, Role::Edge) => {
            let last = s.mesh.deg(s.child[f][(i + 1) % m.deg(f)]) - 1;
            vec![(s.child[f][i], 0), (s.child[f][(i + 1) % m.deg(f)], last)]
        }
        (_, Role::Vertex) => vec![(s.child[f][i], 0)],
    }
}

/// Which cell an anchored half-edge stands for (two anchors of one cell give the same). The two
/// edges of a two-corner face join the same two vertices: the face's side tells them apart.
pub(super) fn cell(scheme: Scheme, role: Role, m: &Local, h: Half) -> (usize, usize, Option<Half>) {
    let (a, b) = (m.at(h), m.head(h));
    match (scheme, role) {
        (Scheme::DooSabin, Role::Vertex) => (h.0, usize::MAX, None),
        (_, Role::Vertex) => (a, usize::MAX, None),
        _ => {
            let digon = [Some(h), m.twin_of(h)].into_iter().flatten().find(|g| m.deg(g.0) == 2);
            (a.min(b), a.max(b), digon)
        }
    }
}

/// A state of the generated automaton.
pub(super) struct Kind {
    pub(super) role: Role,
    pub(super) local: Local,
    /// A line for the file: what the neighbourhood is.
    pub(super) about: String,
}

/// The generated automaton, before it is a design.
pub(super) struct Generator {
    pub(super) scheme: Scheme,
    pub(super) weights: Weights,
    pub(super) kinds: Vec<Kind>,
    pub(super) index: HashMap<(Role, Vec<u32>), usize>,
    pub(super) names: Vec<String>,
    /// Subdivision arrows `(name, from, to, rows)`.
    pub(super) arrows: Vec<(String, usize, usize, Vec<Vec<Lin>>)>,
    /// Boundary (and renumbering) arrows `(name, from, to, select)`.
    pub(super) selects: Vec<(String, usize, usize, Vec<usize>)>,
    pub(super) renumber: HashMap<(usize, usize, Vec<usize>), String>,
    pub(super) incidence: Vec<String>,
    pub(super) adjacency: Vec<String>,
}

impl Generator {
    pub(super) fn intern(&mut self, role: Role, w: Walk) -> usize {
        if let Some(&k) = self.index.get(&(role, w.key.clone())) {
            return k;
        }
        let k = self.kinds.len();
        let count = self.kinds.iter().filter(|x| x.role == role).count();
        let name = format!("{}{count}", role.name());
        let about = describe(self.scheme, role, &w.local);
        self.index.insert((role, w.key), k);
        self.kinds.push(Kind { role, local: w.local, about });
        self.names.push(name);
        k
    }

    /// The state of the cell of `role` anchored at `h` in `m`, and its walk's order.
    pub(super) fn state_at(
        &mut self,
        role: Role,
        m: &Local,
        h: Half,
    ) -> Result<(usize, Vec<usize>), MeshAutomatonError> {
        let set = neighbourhood(self.scheme, role, m, h);
        let w = walk(m, &set, h).ok_or_else(|| MeshAutomatonError::NotOnePiece { cell: role.name() })?;
        let order = w.order.clone();
        Ok((self.intern(role, w), order))
    }

    /// The renumbering arrow from the cell's state anchored at `z` to the
    /// one anchored at `y`: a path ending in the first, followed by it, gives
    /// the control points in the second's order.
    pub(super) fn renumber(
        &mut self,
        role: Role,
        m: &Local,
        y: Half,
        z: Half,
    ) -> Result<Option<String>, MeshAutomatonError> {
        if y == z {
            return Ok(None);
        }
        let (a, oa) = self.state_at(role, m, y)?;
        let (b, ob) = self.state_at(role, m, z)?;
        let select: Vec<usize> = oa
            .iter()
            .map(|v| ob.iter().position(|x| x == v))
            .collect::<Option<_>>()
            .ok_or(MeshAutomatonError::Anchors)?;
        if a == b && select.iter().enumerate().all(|(i, &j)| i == j) {
            return Ok(None);
        }
        let key = (b, a, select.clone());
        if let Some(name) = self.renumber.get(&key) {
            return Ok(Some(name.clone()));
        }
        let name = format!("turn{}", self.renumber.len());
        self.renumber.insert(key, name.clone());
        self.selects.push((name.clone(), b, a, select));
        Ok(Some(name))
    }

    /// Subdivides state `k`: its child arrows, boundary arrows and constraints.
    pub(super) fn process(&mut self, k: usize) -> Result<(), MeshAutomatonError> {
        let (scheme, role) = (self.scheme, self.kinds[k].role);
        let m = self.kinds[k].local.clone();
        let name = self.names[k].clone();
        let s = step(&m, &mut self.weights);
        let anchor = (0, 0);
        // Children.
        let kids = children_of(scheme, role, &m, &s, anchor);
        let mut child_states = Vec::new();
        for (c, &x) in kids.iter().enumerate() {
            if x.0 >= s.mesh.faces.len() {
                return Err(MeshAutomatonError::Child {
                    state: name,
                    what: "a child is missing from its parent's subdivision",
                });
            }
            let (to, order) = self.state_at(role, &s.mesh, x)?;
            let mut rows = vec![vec![crate::algebra::Affine::zero(); order.len()]; m.vertices];
            for (j, &p) in order.iter().enumerate() {
                let sym = s.points[p].as_ref().ok_or_else(|| MeshAutomatonError::Child {
                    state: name.clone(),
                    what: "a child's control point depends on points outside the cell",
                })?;
                for (i, wt) in sym {
                    rows[*i][j] = wt.clone();
                }
            }
            self.arrows.push((format!("{name}_{c}"), k, to, rows));
            child_states.push(to);
        }
        // Sides.
        let sides = sides_of(scheme, role, &m, anchor);
        let side_role = role.side();
        let mut side_states = Vec::with_capacity(sides.len());
        for (j, &h) in sides.iter().enumerate() {
            let (to, order) = self.state_at(side_role, &m, h)?;
            self.selects.push((side_name(&name, role, j), k, to, order));
            side_states.push(to);
        }
        // Constraints: each side of each child lies on a side of the cell or on another child's side.
        let parent_parts: Vec<(usize, usize, Half)> = sides
            .iter()
            .enumerate()
            .flat_map(|(j, &h)| {
                children_of(scheme, side_role, &m, &s, h).into_iter().enumerate().map(move |(t, z)| (j, t, z))
            })
            .collect();
        let child_sides: Vec<(usize, usize, Half)> = kids
            .iter()
            .enumerate()
            .flat_map(|(c, &x)| sides_of(scheme, role, &s.mesh, x).into_iter().enumerate().map(move |(q, y)| (c, q, y)))
            .collect();
        for (a, &(c, q, y)) in child_sides.iter().enumerate() {
            let here = cell(scheme, side_role, &s.mesh, y);
            let lhs = format!("{name}_{c} {}", side_name(&self.names[child_states[c]], role, q));
            if let Some(&(j, t, z)) = parent_parts.iter().find(|p| cell(scheme, side_role, &s.mesh, p.2) == here) {
                let side_state = side_states[j];
                let turn = self.renumber(side_role, &s.mesh, y, z)?;
                let rhs = format!("{} {}_{t}", side_name(&name, role, j), self.names[side_state]);
                self.incidence.push(format!("{lhs} = {rhs}{}", turn.map(|t| format!(" {t}")).unwrap_or_default()));
            } else if let Some(&(d, r, z)) =
                child_sides[a + 1..].iter().find(|p| p.0 != c && cell(scheme, side_role, &s.mesh, p.2) == here)
            {
                let turn = self.renumber(side_role, &s.mesh, y, z)?;
                let rhs = format!("{name}_{d} {}", side_name(&self.names[child_states[d]], role, r));
                self.adjacency.push(format!("{lhs} = {rhs}{}", turn.map(|t| format!(" {t}")).unwrap_or_default()));
            }
        }
        Ok(())
    }
}

pub(super) fn side_name(state: &str, role: Role, j: usize) -> String {
    match role {
        Role::Edge => format!("{state}_{}", if j == 0 { "start" } else { "end" }),
        _ => format!("{state}_side{j}"),
    }
}

/// One line about a neighbourhood: the centre and the valences or degrees around it.
pub(super) fn describe(scheme: Scheme, role: Role, m: &Local) -> String {
    let border = m.sides.iter().flatten().filter(|s| **s == Side::Border).count();
    let on_border = if border > 0 { ", on the border" } else { "" };
    let valence = |v: usize| {
        let n = m.around[v].len();
        if m.closed_at(v) { n.to_string() } else { format!("{n}+") }
    };
    let centre = match (scheme, role) {
        (Scheme::DooSabin, Role::Face) => {
            let degs: Vec<String> = m.fan((0, 0)).iter().map(|h| m.deg(h.0).to_string()).collect();
            format!("the patch of a vertex whose faces have {} sides", degs.join(", "))
        }
        (Scheme::DooSabin, Role::Edge) => {
            format!("an edge between faces of {} and {} sides", m.deg(0), m.deg(m.faces.len() - 1))
        }
        (Scheme::DooSabin, Role::Vertex) => format!("the centroid of a face of {} sides", m.deg(0)),
        (_, Role::Face) => {
            let v: Vec<String> = m.faces[0].iter().map(|&v| valence(v)).collect();
            format!("a face of {} sides at vertices of valence {}", m.deg(0), v.join(", "))
        }
        (_, Role::Edge) => {
            format!("an edge between vertices of valence {} and {}", valence(m.at((0, 0))), valence(m.head((0, 0))))
        }
        (_, Role::Vertex) => format!("a vertex of valence {}", valence(m.at((0, 0)))),
    };
    format!("{centre}{on_border}: {} control points, {} faces", m.vertices, m.faces.len())
}

impl Generator {
    pub(super) fn design(self, mesh: &PolyMesh, roots: Vec<(usize, Vec<usize>)>) -> Result<Design, MeshAutomatonError> {
        let name = format!("mesh_{}", self.scheme.name().replace('-', "_"));
        let mut b = DesignBuilder::new(name);
        let patches = if self.scheme == Scheme::DooSabin { "interior vertex" } else { "face" };
        b.description(format!(
            "{} on a mesh of {} vertices and {} faces: {} patches, {} states",
            self.scheme.name(),
            mesh.positions.len(),
            mesh.face_count(),
            roots.len(),
            self.kinds.len()
        ));
        b.doc(format!(
            "Generated by bcifs from a mesh ({} scheme). Every state is a kind of cell: a patch of the limit surface\n\
             (face), a curve where patches meet (edge) or a point (vertex); its control points are the mesh\n\
             vertices its limit depends on, numbered by a walk of its neighbourhood from an anchor half-edge.\n\
             The model's points are the mesh's vertices; `patches` lists the control points of each patch (one per {patches}),\n\
             whose state is the same entry of `root`.",
            self.scheme.name()
        ));
        for (k, kind) in self.kinds.iter().enumerate() {
            b.state(self.names[k].clone(), kind.local.vertices, kind.role.kind());
            b.doc(kind.about.clone());
        }
        for (name, from, to, rows) in &self.arrows {
            let rows: Vec<Vec<Value>> =
                rows.iter().map(|r| r.iter().map(|l| value(l, &self.weights.names)).collect()).collect();
            b.arrow(
                name.clone(),
                self.names[*from].clone(),
                self.names[*to].clone(),
                ArrowKind::Subdivision,
                Matrix::Rows(rows),
            );
        }
        for (name, from, to, select) in &self.selects {
            b.select(name.clone(), self.names[*from].clone(), self.names[*to].clone(), select.clone());
        }
        for e in &self.adjacency {
            b.adjacency(e.clone());
        }
        for e in &self.incidence {
            b.incidence(e.clone());
        }
        for (n, d) in self.weights.names.iter().zip(&self.weights.defaults) {
            b.parameter(n.clone());
            b.default_value(n, d.clone());
        }
        let points = mesh.positions.iter().map(|p| p.to_vec()).collect();
        let (states, patches): (Vec<String>, Vec<Vec<usize>>) =
            roots.into_iter().map(|(k, order)| (self.names[k].clone(), order)).unzip();
        b.model(
            Model::new("", points)
                .with_patches(states, patches)
                .with_net(mesh.faces().map(<[usize]>::to_vec).collect())
                // The mesh file's axes: Y-up, so that rendering it writes the same file as subdividing it.
                .with_y_up(true),
        );
        b.build().map_err(MeshAutomatonError::Build)
    }
}
