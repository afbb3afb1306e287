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

/// How a cell's control points make its own patch (the cell whole, holes
/// and all): what its length, area or volume is measured on ([`crate::report::porosity`]).
/// The layouts are the pattern generator's: a segment's `D` points in
/// order, a quadrilateral's `D × D` grid (index `D·row + col`), a
/// triangle's net of `D(D + 1)/2` points row by row from its first side, a
/// hexahedron's `D × D × D` grid (index `D²·w + D·v + u`), a tetrahedron's
/// four corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Patch {
    /// Bézier: the polynomial curve, patch or volume of degree `D − 1`
    /// whose Bernstein coefficients the points are (degree 1: the segment,
    /// the bilinear quadrilateral, the flat triangle, the trilinear hexahedron).
    Bezier,
    /// The uniform B-spline of degree `D − 1` over one knot span along each direction.
    BSpline,
    /// The polygon of the cell's corners, as drawn (a flat lace's gaps).
    Polygon,
}

impl Patch {
    /// Every patch, in the order they are documented.
    pub const ALL: [Patch; 3] = [Patch::Bezier, Patch::BSpline, Patch::Polygon];

    /// The keyword used in automaton files.
    pub fn keyword(self) -> &'static str {
        match self {
            Patch::Bezier => "bezier",
            Patch::BSpline => "bspline",
            Patch::Polygon => "polygon",
        }
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
    /// The patch its control points make, when the design says (`None`: not known).
    pub patch: Option<Patch>,
}

impl State {
    /// The same state, its control points making `patch`.
    pub fn with_patch(mut self, patch: Option<Patch>) -> State {
        self.patch = patch;
        self
    }

    /// A state named `name` of dimension `dim` and kind `kind`.
    pub fn new(name: impl Into<String>, dim: usize, kind: CellKind) -> State {
        State { name: name.into(), dim, kind, patch: None }
    }
}
