//! A polygon mesh as a BC-IFS automaton: one state per kind of
//! neighbourhood that occurs, exact subdivision matrices, and the incidence
//! and adjacency constraints between neighbouring sub-cells.
//!
//! A *cell* is a patch of the limit surface (a face state), a curve where
//! two patches meet (an edge state) or a point where curves meet (a vertex
//! state). Its control points are the mesh vertices its limit depends on:
//!
//! | scheme | face (patch) | edge | vertex |
//! |---|---|---|---|
//! | Catmull-Clark, Loop | a mesh face, with every face that shares a vertex with it | a mesh edge, with the faces around its two ends | a mesh vertex, with its faces |
//! | Doo-Sabin | an interior mesh vertex, with its faces (corners: their centroids) | a mesh edge: its two faces | a mesh face (its centroid) |
//!
//! A cell is *anchored* at a half-edge (a face and a corner), and its
//! control points are numbered by a breadth-first walk of its neighbourhood
//! from the anchor: two cells with the same walk (same faces, same sides on
//! the border) are the same state, and the walk, not the mesh's numbering,
//! says which control point is which. One exact subdivision step of a
//! state's neighbourhood (the scheme's rules over rationals, with the
//! weights as parameters) gives the new points as affine combinations of
//! the old ones; the children's neighbourhoods are found in the subdivided
//! one, anchored at the child half-edges, and their walks give the columns
//! of the subdivision matrices. New states are processed until none
//! appears: for the classic schemes a face next to an extraordinary vertex
//! subdivides into one such face and regular ones, so the automaton has a
//! few states per valence (and per n-gon for Doo-Sabin).
//!
//! The constraints are found the same way: a child's side that lies on a
//! side of its parent gives an incidence equation (`T_c b_k = b_j U_t`), a
//! side two children share gives an adjacency equation (`T_c b_k = T_d b_l
//! P`), where `P` renumbers the shared cell from one anchor to the other (a
//! selection arrow between edge or vertex states). They hold identically in
//! the weights: `bcifs solve` keeps every weight free, and `bcifs check`
//! finds residuals of zero.
//!
//! The weights are the rotationally symmetric rules on each scheme's
//! stencils: Doo-Sabin `alpha, beta, gamma` on quads and `a{n}_{k}` (corner
//! `i + k`'s share) on other n-gons; Loop `w` and `beta{n}` per valence;
//! Catmull-Clark `edge_faces` and, per valence, `ring{n}` and `faces{n}`.
//!
//! The model is the user's mesh itself: its vertices are the control
//! points, and the `patches` layout lists each patch's root state and
//! control points (pieces that share points are welded).
//!
//! √3 rotates the triangles, so a triangle is nested in its parent only
//! after two steps: an arrow of the √3 automaton is two steps (a ternary
//! split into nine), its cells reach one ring further (the faces around
//! the faces around a cell's vertices: 27 points for the regular patch),
//! and its weights are the classic `(4 − 2cos(2π/n))/9` (exact where they
//! are rational, the float's decimal otherwise): two steps would multiply
//! weights, and the constraints would no longer be linear in them. Closed
//! meshes only: its border rule changes from one step to the next.

mod error;
mod generator;
mod local;
mod rules;

use std::collections::HashMap;

use crate::design::Design;
use crate::mesh::{LoopWeights, PolyMesh, QuadWeights, RuleWeights, Scheme, SubdivideError};
pub use error::MeshAutomatonError;
use generator::Generator;
use local::{Half, Local, Role};
use rules::Weights;

/// The mesh as a BC-IFS automaton for `scheme` (see the module
/// documentation): states for the kinds of patches, curves and points
/// that occur, exact subdivision matrices whose entries are affine in
/// the scheme's weights (named parameters whose defaults are the classic
/// weights, or `weights`), the incidence and adjacency constraints, and
/// a model whose control points are the mesh's vertices.
///
/// ```
/// use bcifs::mesh::{PolyMesh, Scheme};
/// let design = bcifs::schemes::mesh_automaton(&PolyMesh::cube(), Scheme::CatmullClark, None).unwrap();
/// let family = bcifs::solve(&design).unwrap();
/// // The constraints hold for every weight: the edge rule's and, at the
/// // cube's valence 3 and the new vertices' 4, the vertex rule's two.
/// assert_eq!(family.parameter_names(), ["ring3", "faces3", "edge_faces", "ring4", "faces4"]);
/// ```
///
/// # Errors
/// √3 on an open mesh (its border rule alternates); a triangle scheme on
/// a face that is not a triangle; a neighbourhood that is not one piece
/// of surface.
pub fn mesh_automaton(
    mesh: &PolyMesh,
    scheme: Scheme,
    weights: Option<RuleWeights>,
) -> Result<Design, MeshAutomatonError> {
    if scheme == Scheme::Sqrt3 && !mesh.is_closed() {
        return Err(MeshAutomatonError::OpenSqrt3);
    }
    if scheme == Scheme::DooSabin && !mesh.has_interior_vertex() {
        return Err(SubdivideError::NoInteriorVertex.into());
    }
    if scheme.triangles_only()
        && let Some(f) = (0..mesh.face_count()).find(|&f| mesh.face(f).len() != 3)
    {
        return Err(SubdivideError::NotTriangles { scheme: scheme.name(), face: f, degree: mesh.face(f).len() }.into());
    }
    let weights = Weights {
        scheme,
        names: Vec::new(),
        defaults: Vec::new(),
        quad: weights.and_then(RuleWeights::quad).unwrap_or(QuadWeights::CLASSIC),
        triangle: weights.and_then(RuleWeights::triangle).unwrap_or(LoopWeights::CLASSIC),
    };
    let mut g = Generator {
        scheme,
        weights,
        kinds: Vec::new(),
        index: HashMap::new(),
        names: Vec::new(),
        arrows: Vec::new(),
        selects: Vec::new(),
        renumber: HashMap::new(),
        incidence: Vec::new(),
        adjacency: Vec::new(),
    };
    let local = Local::of_mesh(mesh);
    // The patches: every face, or (Doo-Sabin) every interior vertex.
    let anchors: Vec<Half> = if scheme == Scheme::DooSabin {
        (0..local.vertices).filter(|&v| local.closed_at(v)).map(|v| local.around[v][0]).collect()
    } else {
        (0..local.faces.len()).map(|f| (f, 0)).collect()
    };
    let mut roots = Vec::new();
    for &h in &anchors {
        roots.push(g.state_at(Role::Face, &local, h)?);
    }
    let mut done = 0;
    while done < g.kinds.len() {
        g.process(done)?;
        done += 1;
    }
    g.design(mesh, roots)
}
