//! Why a mesh cannot be made an automaton.

use crate::mesh::SubdivideError;

/// Why a mesh cannot be made an automaton.
#[derive(Debug, thiserror::Error)]
pub enum MeshAutomatonError {
    /// √3 on a mesh with a border.
    #[error(
        "√3 is generated as an automaton on closed meshes only: its border rule changes from one step to the next, so a border triangle's children are not a ternary split"
    )]
    OpenSqrt3,
    /// The scheme cannot subdivide the mesh (Doo-Sabin without an interior vertex, a triangle scheme on other faces).
    #[error(transparent)]
    Mesh(#[from] SubdivideError),
    /// The neighbourhood of a cell is not one piece of surface.
    #[error("the neighbourhood of a {cell} is not one piece of surface (a vertex where two fans of faces touch)")]
    NotOnePiece {
        /// The kind of cell: face, edge or vertex.
        cell: &'static str,
    },
    /// Two anchors of one cell see different neighbourhoods.
    #[error("two anchors of one cell see different neighbourhoods")]
    Anchors,
    /// A child cell not found where the scheme puts it, in the state named.
    #[error("{state}: {what}")]
    Child {
        /// The parent state.
        state: String,
        /// What is wrong.
        what: &'static str,
    },
    /// The generated automaton is not well formed (a defect of the generator).
    #[error("the generated automaton is not well formed")]
    Build(#[source] crate::design::BuildError),
}
