//! Writers, one per format, each a [`crate::geometry::Sink`]: streaming OBJ
//! and OFF, SVG and PNG pictures; density pictures of the chaos game; the
//! axes, digits and atomic files they share.

mod atomic;
mod axes;
mod density;
mod draw;
mod flame;
mod gltf;
mod normals;
mod number;
mod obj;
mod off;
mod picture;
mod ply;
mod png;
mod stl;
mod svg;
mod view;

pub use atomic::{AtomicFile, check_target, remove_temporary_files, resolve_target, same_file, write_atomic};
pub use axes::{Coordinates, Up};
pub use density::{Density, Palette, Tone, density, density_bytes, density_image, picture_frame};
pub use draw::{
    POINTS_PER_PIXEL, SEGMENTS_PER_PIXEL, curve_picture_depth, picture, picture_bytes, picture_depth,
    point_picture_depth,
};
pub use flame::{FlameError, flame_text, write_flame};
pub use gltf::GltfWriter;
pub(crate) use normals::{NormalSpill, Replay};
pub use obj::{ObjWriter, write_evaluation, write_obj};
pub use off::OffWriter;
pub use picture::{PictureError, PictureKind, PictureWriter, write_picture};
pub use ply::PlyWriter;
pub use png::{Matte, ascii, raster, write_png, write_png_matte, write_png_text};
pub use stl::StlWriter;
pub use svg::{svg, svg_surface};
pub use view::{RasterSettings, RasterTooLarge, View, raster_bytes};

/// Refuses vertices with a coordinate or normal that is not finite: no file
/// bcifs writes holds NaN or an infinity, which every client refuses or
/// draws wrong (a design's control points so large that its sums overflow
/// `f64`). The atomic writers then leave the target as it was.
pub fn finite_vertices(positions: &[f64], normals: Option<&[f64]>) -> std::io::Result<()> {
    let bad = |xs: &[f64]| xs.iter().any(|x| !x.is_finite());
    if bad(positions) || normals.is_some_and(bad) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "a vertex has a coordinate or normal that is not a finite number (the evaluation overflowed f64: \
             scale the control points or mesh below ±1e150); nothing is written",
        ));
    }
    Ok(())
}
