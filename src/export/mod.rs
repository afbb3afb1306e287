//! Writers: streaming OBJ, SVG, PNG pictures; files are replaced atomically.

mod atomic;
mod axes;
mod density;
mod draw;
mod number;
mod obj;
mod off;
mod png;
mod svg;
mod view;

pub use atomic::{AtomicFile, check_target, remove_temporary_files, write_atomic};
pub use axes::{Coordinates, Up};
pub use density::{Density, Palette, Tone, density, density_bytes, density_image};
pub use draw::{SEGMENTS_PER_PIXEL, curve_picture_depth, picture, picture_bytes, picture_depth};
pub use obj::{ObjWriter, write_evaluation, write_obj};
pub use off::OffWriter;
pub use png::{ascii, raster, write_png};
pub use svg::{svg, svg_surface};
pub use view::{RasterSettings, RasterTooLarge, View, raster_bytes};
