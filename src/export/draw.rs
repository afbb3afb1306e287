//! Pictures of deterministic curves and point sets drawn while they are
//! evaluated: the evaluation is streamed twice (once for the frame, once to
//! draw), so memory is the picture's buffers whatever the depth.

use std::io;

use image::RgbImage;

use super::png::{finish_picture, wu_line};
use super::view::{Canvas, DMat3, RasterSettings, RasterTooLarge, screen};
use crate::geometry::Sink;

/// The screen position of a point under the view (see [`screen`]).
#[derive(Clone, Copy)]
struct Projection {
    turn: DMat3,
}

impl Projection {
    fn new(settings: &RasterSettings) -> Projection {
        Projection { turn: settings.view.turn() }
    }
    #[inline]
    fn screen(&self, p: &[f64]) -> [f64; 3] {
        screen(&self.turn, p)
    }
}

/// The first pass: the extent of the projected points, and the longest
/// step between consecutive vertices of an object (a segment of a curve).
struct Extent {
    projection: Projection,
    lo: [f64; 2],
    hi: [f64; 2],
    vertices: usize,
    longest: f64,
    last: Option<[f64; 2]>,
}

impl Extent {
    fn new(projection: Projection) -> Extent {
        Extent { projection, lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2], vertices: 0, longest: 0.0, last: None }
    }
}

/// The second pass: lines between consecutive vertices of each object
/// (curves), or counts per pixel (points).
struct Drawing {
    projection: Projection,
    canvas: Canvas,
    lines: bool,
    cov: Vec<f32>,
    density: Vec<u32>,
    first: Option<(f64, f64)>,
    last: Option<(f64, f64)>,
}

fn unsupported() -> io::Error {
    io::Error::other("a streamed picture draws curves and points, not faces")
}

impl Sink for Extent {
    fn object(&mut self, _: &str) -> io::Result<()> {
        self.last = None;
        Ok(())
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, None)?;
        for p in positions.chunks_exact(dim) {
            let s = self.projection.screen(p);
            for ((lo, hi), x) in self.lo.iter_mut().zip(&mut self.hi).zip(s) {
                *lo = lo.min(x);
                *hi = hi.max(x);
            }
            if let Some([x, y]) = self.last {
                self.longest = self.longest.max((s[0] - x).hypot(s[1] - y));
            }
            self.last = Some([s[0], s[1]]);
        }
        self.vertices += positions.len() / dim.max(1);
        Ok(())
    }
    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }
    fn polyline(&mut self, _: usize, _: usize, _: bool) -> io::Result<()> {
        self.last = None;
        Ok(())
    }
    fn faces(&mut self, _: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
        Err(unsupported())
    }
    fn triangles(&mut self, _: &[[usize; 3]]) -> io::Result<()> {
        Err(unsupported())
    }
}

impl Sink for Drawing {
    fn object(&mut self, _: &str) -> io::Result<()> {
        (self.first, self.last) = (None, None);
        Ok(())
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> io::Result<()> {
        let (w, h) = (self.canvas.w, self.canvas.h);
        for p in positions.chunks_exact(dim) {
            let at = self.canvas.px(self.projection.screen(p));
            if self.lines {
                match self.last {
                    Some(from) => wu_line(&mut self.cov, w, h, from, at),
                    None => self.first = Some(at),
                }
                self.last = Some(at);
            } else if at.0 >= 0.0 && at.1 >= 0.0 && (at.0 as usize) < w && (at.1 as usize) < h {
                self.density[at.1 as usize * w + at.0 as usize] += 1;
            }
        }
        Ok(())
    }
    fn uvs(&mut self, _: &[f64]) -> io::Result<()> {
        Ok(())
    }
    fn polyline(&mut self, _: usize, count: usize, closed: bool) -> io::Result<()> {
        if let (true, true, Some(first), Some(last)) = (self.lines, closed && count > 1, self.first, self.last) {
            wu_line(&mut self.cov, self.canvas.w, self.canvas.h, last, first);
        }
        (self.first, self.last) = (None, None);
        Ok(())
    }
    fn faces(&mut self, _: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> io::Result<()> {
        Err(unsupported())
    }
    fn triangles(&mut self, _: &[[usize; 3]]) -> io::Result<()> {
        Err(unsupported())
    }
}

/// Bytes [`stream_picture`] allocates: a coverage and a count per pixel, and the picture.
pub fn picture_bytes(settings: &RasterSettings) -> u128 {
    u128::from(settings.width.max(1)) * u128::from(settings.height.max(1)) * 11
}

/// Draws a stream of curves (`lines`) or points while it is made, twice
/// (`stream` is called once for the frame, once to draw, with the sink to
/// push into): the same picture as [`super::raster`] of the whole shape, in
/// the memory of the picture alone, and the number of vertices drawn.
///
/// ```
/// use bcifs::eval::{EvalSettings, Evaluator};
/// let design = bcifs::builtin_design("levy").unwrap();
/// let inst = bcifs::instantiate(&design, &[]).unwrap();
/// let settings = EvalSettings::default().with_depth(12);
/// let ev = Evaluator::new(&inst.automaton, design.model().unwrap(), settings).unwrap();
/// let raster = bcifs::export::RasterSettings::default().with_size(200, 100);
/// let stream = |sink: &mut dyn bcifs::geometry::Sink| ev.stream(sink).map_err(bcifs::render::RenderError::from);
/// let (picture, vertices) = bcifs::export::stream_picture(true, stream, &raster)?;
/// assert_eq!((picture.dimensions(), vertices), ((200, 100), (1 << 12) + 1));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// The stream's error, or [`RasterTooLarge`] for a picture whose buffers
/// would not fit the memory limit.
pub fn stream_picture<E: From<RasterTooLarge>>(
    lines: bool,
    mut stream: impl FnMut(&mut dyn Sink) -> Result<(), E>,
    settings: &RasterSettings,
) -> Result<(RgbImage, usize), E> {
    let needed = picture_bytes(settings);
    if needed > settings.memory_limit as u128 {
        let (width, height, limit) = (settings.width, settings.height, settings.memory_limit);
        return Err(RasterTooLarge { width, height, vertices: 0, needed, limit }.into());
    }
    let projection = Projection::new(settings);
    let mut extent = Extent::new(projection);
    stream(&mut extent)?;
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    if extent.vertices == 0 {
        return Ok((RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255])), 0));
    }
    let corners = [[extent.lo[0], extent.lo[1], 0.0], [extent.hi[0], extent.hi[1], 0.0]];
    let canvas = Canvas::fit(&corners, w, h);
    let pixels = w as usize * h as usize;
    let mut drawing = Drawing {
        projection,
        canvas,
        lines,
        cov: vec![0.0; if lines { pixels } else { 0 }],
        density: vec![0; if lines { 0 } else { pixels }],
        first: None,
        last: None,
    };
    stream(&mut drawing)?;
    let Drawing { mut cov, mut density, .. } = drawing;
    cov.resize(pixels, 0.0);
    density.resize(pixels, 0);
    Ok((finish_picture(w, h, &cov, &density), extent.vertices))
}

/// What a picture of a stream of curves would draw: its vertices, and its
/// longest segment in pixels (0 when it has no vertex).
///
/// # Errors
/// The stream's error.
pub fn stream_extent<E>(
    stream: impl FnOnce(&mut dyn Sink) -> Result<(), E>,
    settings: &RasterSettings,
) -> Result<(usize, f64), E> {
    let mut extent = Extent::new(Projection::new(settings));
    stream(&mut extent)?;
    if extent.vertices == 0 {
        return Ok((0, 0.0));
    }
    let corners = [[extent.lo[0], extent.lo[1], 0.0], [extent.hi[0], extent.hi[1], 0.0]];
    let canvas = Canvas::fit(&corners, settings.width.max(1), settings.height.max(1));
    Ok((extent.vertices, extent.longest * canvas.scale))
}
