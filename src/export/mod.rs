//! Writers: streaming OBJ, SVG, PNG pictures; files are replaced atomically.

mod atomic;
mod obj;
mod png;
mod svg;

pub use atomic::{AtomicFile, remove_temporary_files, write_atomic};
pub use obj::{ObjWriter, Up, write_obj};
pub use png::{
    Density, RasterSettings, RasterTooLarge, Tone, View, ascii, density, density_image, raster, raster_bytes, write_png,
};
pub use svg::svg;
