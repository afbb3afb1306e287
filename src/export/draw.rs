//! Pictures of deterministic curves and point sets drawn while they are
//! evaluated: the evaluation is streamed twice (once for the frame, once to
//! draw), so memory is the picture's buffers whatever the depth.

use std::io;

use image::RgbImage;

use super::png::{finish_picture, wu_line};
use super::view::{Canvas, DMat3, RasterSettings, screen};
use crate::eval::{Depth, EvalError, Evaluator};
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

/// Bytes [`picture`] allocates: a coverage and a count per pixel, and the picture.
pub fn picture_bytes(settings: &RasterSettings) -> u128 {
    u128::from(settings.width.max(1)) * u128::from(settings.height.max(1)) * 11
}

/// Draws the curves or points of `ev` while they are evaluated, twice
/// streamed (the frame, then the drawing): the same picture as
/// [`super::raster`] of the evaluated shape, in the memory of the picture
/// alone, and the number of vertices drawn. `None` when the output is a surface or mixes curves and points
/// (those are drawn from memory).
///
/// ```
/// use bcifs::eval::{EvalSettings, Evaluator};
/// let design = bcifs::builtin_design("levy").unwrap();
/// let inst = bcifs::instantiate(&design, &[]).unwrap();
/// let settings = EvalSettings::default().with_depth(12);
/// let ev = Evaluator::new(&inst.automaton, design.model().unwrap(), settings).unwrap();
/// let raster = bcifs::export::RasterSettings::default().with_size(200, 100);
/// let (picture, vertices) = bcifs::export::picture(&ev, &raster).unwrap().expect("a curve");
/// assert_eq!((picture.dimensions(), vertices), ((200, 100), (1 << 12) + 1));
/// ```
///
/// # Errors
/// An evaluation error, or [`EvalError::TooLarge`] for a picture whose
/// buffers would not fit the memory limit.
pub fn picture(ev: &Evaluator, settings: &RasterSettings) -> Result<Option<(RgbImage, usize)>, EvalError> {
    let Some(lines) = ev.polylines() else { return Ok(None) };
    let needed = picture_bytes(settings);
    if needed > settings.memory_limit as u128 {
        return Err(EvalError::TooLarge { estimate: needed, limit: settings.memory_limit });
    }
    let projection = Projection::new(settings);
    let mut extent = Extent::new(projection);
    ev.stream(&mut extent)?;
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    if extent.vertices == 0 {
        return Ok(Some((RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255])), 0)));
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
    ev.stream(&mut drawing)?;
    let Drawing { mut cov, mut density, .. } = drawing;
    cov.resize(pixels, 0.0);
    density.resize(pixels, 0);
    Ok(Some((finish_picture(w, h, &cov, &density), extent.vertices)))
}

/// Segments per pixel beyond which a curve picture stops subdividing even
/// if some segment is still longer than a pixel (a curve that does not
/// contract, drawn with `--force`).
pub const SEGMENTS_PER_PIXEL: u128 = 64;

/// The depth a picture of a curve needs, at most `depth`: the first whose
/// segments are all shorter than a pixel (deeper ones only move the curve
/// within the pixels it covers), or whose segments outnumber the pixels
/// [`SEGMENTS_PER_PIXEL`] times. Each probe streams `ev` once at a
/// shallower depth (the depths before the answer cost less than the
/// answer's picture); `ev` is left at the depth returned. `depth` for points.
///
/// # Errors
/// An evaluation error.
pub fn curve_picture_depth(ev: &mut Evaluator, settings: &RasterSettings, depth: usize) -> Result<usize, EvalError> {
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    let pixels = u128::from(w) * u128::from(h);
    if ev.polylines() == Some(true) {
        for k in 0..depth {
            ev.set_depth(Depth::Fixed(k))?;
            let mut extent = Extent::new(Projection::new(settings));
            ev.stream(&mut extent)?;
            if extent.vertices == 0 {
                return Ok(k);
            }
            let corners = [[extent.lo[0], extent.lo[1], 0.0], [extent.hi[0], extent.hi[1], 0.0]];
            let canvas = Canvas::fit(&corners, w, h);
            if extent.longest * canvas.scale < 1.0 || extent.vertices as u128 >= SEGMENTS_PER_PIXEL * pixels {
                return Ok(k);
            }
        }
    }
    ev.set_depth(Depth::Fixed(depth))?;
    Ok(depth)
}

/// Points per pixel beyond which a picture of points stops subdividing:
/// deeper, the points only fill the pixels they already darken.
pub const POINTS_PER_PIXEL: u128 = 64;

/// The depth a picture of points (a plain IFS, a fractal cell) needs, at
/// most `depth`: the deepest whose points number at most
/// [`POINTS_PER_PIXEL`] times the pixels (at least depth 0). Counted, not
/// evaluated: the gasket at depth 60 would be 3⁶⁰ points.
pub fn point_picture_depth(ev: &Evaluator, settings: &RasterSettings, depth: usize) -> usize {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    let points = |k: usize| ev.total_samples(k) as u128;
    (1..=depth).take_while(|&k| points(k) <= POINTS_PER_PIXEL * pixels).last().unwrap_or(0)
}

/// The depth a picture of a surface needs: the first one whose quads
/// outnumber the pixels (deeper, a quad is smaller than a pixel and the
/// picture changes only by sub-pixel shading), at most
/// `depth`; `depth` for curves and points, which [`picture`] streams.
pub fn picture_depth(ev: &Evaluator, settings: &RasterSettings, depth: usize) -> usize {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    (0..depth).find(|&k| ev.quads_at(k).is_some_and(|q| q >= pixels)).unwrap_or(depth)
}
