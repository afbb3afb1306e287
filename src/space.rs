//! Barycentric spaces: the states of an automaton.

use std::fmt;
use std::str::FromStr;

/// The topological role of a barycentric space in a B-rep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// A vertex: its attractor is a point; evaluation emits nothing by itself.
    Vertex,
    /// An edge: evaluation emits its two end points, in curve order.
    Edge,
    /// A face: evaluation emits its four corners, as a quad.
    Face,
    /// A volume (a hexahedron or a tetrahedron): evaluation emits its
    /// corners (its boundary faces' corners) as points; the solids' meshes
    /// are made from its boundary cells.
    Volume,
    /// A plain IFS space: evaluation emits one point per cell.
    Free,
}

impl CellKind {
    /// All kinds, in the order they are documented.
    pub const ALL: [CellKind; 5] = [CellKind::Vertex, CellKind::Edge, CellKind::Face, CellKind::Volume, CellKind::Free];

    /// The keyword used in automaton files.
    pub fn keyword(self) -> &'static str {
        match self {
            CellKind::Vertex => "vertex",
            CellKind::Edge => "edge",
            CellKind::Face => "face",
            CellKind::Volume => "volume",
            CellKind::Free => "free",
        }
    }
}

impl fmt::Display for CellKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

impl FromStr for CellKind {
    type Err = ();
    fn from_str(s: &str) -> Result<CellKind, ()> {
        CellKind::ALL.into_iter().find(|k| k.keyword() == s).ok_or(())
    }
}

/// A state: the barycentric space `BI^dim = { λ ∈ R^dim : Σ λ_i = 1 }` of a
/// topological cell that depends on `dim` control points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct State {
    /// Unique name within the automaton.
    pub name: String,
    /// Number of control points (barycentric coordinates).
    pub dim: usize,
    /// Cell kind, which decides what evaluation emits.
    pub kind: CellKind,
}

impl State {
    /// A state named `name` of dimension `dim` and kind `kind`.
    pub fn new(name: impl Into<String>, dim: usize, kind: CellKind) -> State {
        State { name: name.into(), dim, kind }
    }
}
