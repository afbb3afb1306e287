//! Why a mesh cannot be read, is not a surface, or cannot be subdivided.

use super::polymesh::Place;

/// A mesh file that cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum MeshReadError {
    /// The file cannot be read.
    #[error("cannot read {file}")]
    Io {
        /// The file.
        file: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a mesh of the format: `file:line:column: what was expected`.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What was expected.
        message: String,
    },
    /// The extension is neither `.obj` nor `.off`.
    #[error("unknown mesh format `{0}`: expected .obj or .off")]
    Format(String),
    /// The file holds a mesh that is not a surface bcifs can subdivide.
    #[error(transparent)]
    Check(#[from] MeshCheckError),
}

/// A mesh that is not a surface bcifs can subdivide: a manifold with
/// consistently oriented, non-degenerate faces, closed or with boundary.
#[derive(Debug, thiserror::Error)]
pub enum MeshCheckError {
    /// No face.
    #[error("the mesh has no face")]
    Empty,
    /// A vertex index past the last vertex.
    #[error("{place}: vertex index {index} is out of range (the mesh has {count} vertices)")]
    IndexOutOfRange {
        /// The face.
        place: Place,
        /// The index.
        index: i64,
        /// Vertices of the mesh.
        count: usize,
    },
    /// A face with fewer than 3 distinct vertices, or a vertex twice.
    #[error("{place}: degenerate face {vertices:?} (a face needs at least 3 distinct vertices, each once)")]
    Degenerate {
        /// The face.
        place: Place,
        /// Its vertices.
        vertices: Vec<usize>,
    },
    /// A face whose corners are all at one point: it has no extent, no
    /// normal, and every scheme's weights collapse onto it.
    #[error("{place}: face {vertices:?} has all its corners at one point {point:?} (a face needs an extent)")]
    Collapsed {
        /// The face.
        place: Place,
        /// Its vertices.
        vertices: Vec<usize>,
        /// The one point.
        point: [f64; 3],
    },
    /// A vertex position that is not a finite number.
    #[error("vertex {0} has a coordinate that is not a finite number")]
    NotFinite(usize),
    /// A coordinate so large that the subdivision's sums, or the squares
    /// of its normals and lengths, would overflow `f64` (to infinities and
    /// NaN in the file).
    #[error(
        "vertex {vertex} has the coordinate {value:e}: beyond ±{:e}, sums and squares (normals, lengths) overflow f64; scale the mesh down",
        crate::geometry::MAX_COORDINATE
    )]
    Scale {
        /// The vertex.
        vertex: usize,
        /// Its largest coordinate.
        value: f64,
    },
    /// An edge in more than two faces.
    #[error("{place}: edge {a}–{b} is in {count} faces (a surface has at most two on an edge)")]
    NonManifoldEdge {
        /// The third face on the edge.
        place: Place,
        /// Its vertices.
        a: usize,
        /// Its vertices.
        b: usize,
        /// Faces on the edge.
        count: usize,
    },
    /// Two faces that run through an edge in the same direction.
    #[error("{place}: edge {a}→{b} runs the same way in {other}: the faces are not consistently oriented")]
    Orientation {
        /// The second face.
        place: Place,
        /// The edge.
        a: usize,
        /// The edge.
        b: usize,
        /// The first face.
        other: Place,
    },
    /// Faces around a vertex that form more than one fan (two cones touching at a point).
    #[error("vertex {0} is not a manifold vertex: its faces form {1} separate fans")]
    NonManifoldVertex(usize, usize),
    /// More corners or vertices than 32-bit numbers count.
    #[error("the mesh has {corners} corners and {vertices} vertices: a mesh numbers fewer than 2^32 of each")]
    TooLarge {
        /// Corners (the sum of the faces' degrees).
        corners: usize,
        /// Vertices.
        vertices: usize,
    },
}

/// A subdivision that cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum SubdivideError {
    /// Doo-Sabin's limit surface (or its generated automaton) of a mesh
    /// whose vertices are all on its border: empty.
    #[error(
        "every vertex of the mesh is on its border, and Doo-Sabin's limit surface has a patch around each interior vertex only: it is empty (write the control net instead)"
    )]
    NoInteriorVertex,
    /// A face that is not a triangle, for a triangle scheme.
    #[error(
        "face {face} has {degree} vertices: {scheme} subdivides triangle meshes; triangulate the faces first (fans of triangles), or use doo-sabin or catmull-clark"
    )]
    NotTriangles {
        /// The scheme.
        scheme: &'static str,
        /// The first face that is not a triangle.
        face: usize,
        /// Its degree.
        degree: usize,
    },
    /// A depth whose output would not fit memory.
    #[error("{what} at depth {depth} would have about {faces} faces ({}): over the in-memory limit of {} (the memory budget) or the 2^32 corners a mesh can number; lower the depth", crate::progress::bytes_text(*bytes), crate::progress::bytes_text(*limit as u128))]
    TooLarge {
        /// What.
        what: &'static str,
        /// Depth asked for.
        depth: usize,
        /// Faces it would have.
        faces: u128,
        /// Bytes it would take.
        bytes: u128,
        /// The limit.
        limit: usize,
    },
    /// Writing the output failed.
    #[error("cannot write the mesh")]
    Write(#[source] std::io::Error),
}
