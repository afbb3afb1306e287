//! Polygon meshes a user brings: read from OBJ or OFF (or built in memory),
//! checked (a manifold with consistently oriented, non-degenerate faces of
//! any degree, closed or with boundary), subdivided by Doo-Sabin or
//! Catmull-Clark exactly as CGAL's `Subdivision_method_3` does it, and
//! evaluated on the limit surface.
//!
//! ```
//! use bcifs::mesh::{PolyMesh, Scheme};
//! // A cube, faces counter-clockwise seen from outside.
//! let positions = vec![
//!     [-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0],
//!     [-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, 1.0], [-1.0, 1.0, 1.0],
//! ];
//! let faces = vec![
//!     vec![0, 3, 2, 1], vec![4, 5, 6, 7], vec![0, 1, 5, 4],
//!     vec![1, 2, 6, 5], vec![2, 3, 7, 6], vec![3, 0, 4, 7],
//! ];
//! let cube = PolyMesh::new(positions, faces).unwrap();
//! let net = cube.subdivide(Scheme::CatmullClark, 2).unwrap();
//! assert_eq!(net.face_count(), 6 * 16);
//! let limit = cube.limit(Scheme::DooSabin, 3).unwrap();
//! assert!(limit.quads.len() > 0);
//! ```

mod emit;
mod error;
mod limit;
mod named;
mod polymesh;
mod read;
pub mod rules;
mod sources;
mod stream;
mod subdivide;
mod texture;
mod thicken;
mod topology;
mod triangles;
mod write;

pub use emit::Written;
pub use error::{MeshCheckError, MeshReadError, SubdivideError};
pub use polymesh::{DEFAULT_MESH_MEMORY, Place, PolyMesh, Scheme};
pub use read::{read_mesh, read_obj, read_off};
pub use stream::Subdivision;
pub use subdivide::{LoopWeights, QuadWeights, RuleWeights, doo_sabin_weights, sqrt3_alpha};
pub use thicken::{ThickenError, thicken};
pub use topology::{BORDER, Topology};
pub use triangles::loop_beta;
