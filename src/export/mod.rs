//! Writers, one per format, each a [`crate::geometry::Sink`]: streaming OBJ
//! and OFF, SVG and PNG pictures; density pictures of the chaos game; the
//! axes, digits and atomic files they share.

mod atomic;
mod axes;
mod density;
mod draw;
mod finite;
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
mod threemf;
mod view;

pub use atomic::{
    AtomicFile, MemoryFile, Out, Target, check_target, remove_temporary_files, resolve_target, same_file, write_atomic,
    write_to,
};
pub use axes::{Coordinates, Up};
pub use density::{Density, Palette, Tone, density_bytes, density_counts, density_image, picture_frame};
pub use draw::{picture_bytes, stream_extent, stream_picture};
pub use finite::finite_vertices;
pub use flame::{FlameError, flame_text, write_flame};
pub use gltf::GltfWriter;
pub(crate) use normals::{NormalSpill, Replay};
pub use obj::{ObjWriter, write_obj, write_two_passes};
pub use off::OffWriter;
pub use picture::{PictureError, PictureKind, PictureWriter, write_picture};
pub use ply::PlyWriter;
pub use png::{Compression, Matte, ascii, png_bytes, raster, write_png, write_png_matte, write_png_text};
pub use stl::StlWriter;
pub use svg::{svg, svg_surface};
pub use threemf::ThreeMfWriter;
pub use view::{RasterSettings, RasterTooLarge, View, raster_bytes};
