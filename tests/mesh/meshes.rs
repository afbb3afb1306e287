//! Reading and checking meshes.
