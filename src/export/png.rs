//! PNG pictures: anti-aliased curves, point clouds by density, shaded
//! previews of surfaces, drawn on the canvas of [`super::view`], and PNG
//! encoding.

use std::io;
use std::path::Path;

use image::{Rgb, RgbImage};
use nalgebra::Vector3;

use super::atomic::write_atomic;
use super::view::{Canvas, RasterSettings, RasterTooLarge, project, raster_bytes};
use crate::algebra::tolerance::{DEGENERATE, SLACK};
use crate::geometry::Shape;

pub(super) const INK: [f64; 3] = [27.0, 58.0, 107.0];
pub(super) const PAPER: [f64; 3] = [255.0, 255.0, 255.0];

/// `x.floor()` for `|x| < 2^62`, without a call into libm (the baseline
/// x86-64 target has no rounding instruction); saturates beyond.
#[inline(always)]
fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// `x.round()` (half away from zero), as [`floor_i64`].
#[inline(always)]
fn round_i64(x: f64) -> i64 {
    let i = x as i64;
    let frac = x - i as f64;
    if frac >= 0.5 {
        i + 1
    } else if frac <= -0.5 {
        i - 1
    } else {
        i
    }
}

/// Xiaolin Wu's anti-aliased line into a coverage buffer (the part of it
/// on the picture: a line far off the picture costs nothing).
#[inline(always)]
pub(super) fn wu_line(cov: &mut [f32], w: usize, h: usize, (mut x0, mut y0): (f64, f64), (mut x1, mut y1): (f64, f64)) {
    let mut plot = |x: i64, y: i64, c: f64| {
        if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
            let cell = &mut cov[y as usize * w + x as usize];
            *cell = (*cell + c as f32).min(1.0);
        }
    };
    let steep = (y1 - y0).abs() > (x1 - x0).abs();
    if steep {
        std::mem::swap(&mut x0, &mut y0);
        std::mem::swap(&mut x1, &mut y1);
    }
    if x0 > x1 {
        std::mem::swap(&mut x0, &mut x1);
        std::mem::swap(&mut y0, &mut y1);
    }
    let dx = x1 - x0;
    let gradient = if dx.abs() < DEGENERATE { 1.0 } else { (y1 - y0) / dx };
    let span = if steep { h } else { w } as i64;
    let (xs, xe) = (round_i64(x0).max(-1), round_i64(x1).min(span));
    let mut y = y0 + gradient * (xs as f64 - x0);
    for x in xs..=xe {
        let fl = floor_i64(y);
        let fr = y - fl as f64;
        if steep {
            plot(fl, x, 1.0 - fr);
            plot(fl + 1, x, fr);
        } else {
            plot(x, fl, 1.0 - fr);
            plot(x, fl + 1, fr);
        }
        y += gradient;
    }
}

pub(super) fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> Rgb<u8> {
    let t = t.clamp(0.0, 1.0);
    Rgb([0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * t).round() as u8))
}

/// Draws the shape.
///
/// # Errors
/// A picture whose buffers ([`raster_bytes`]) would exceed the settings'
/// memory limit, refused before allocating.
pub fn raster(shape: &Shape, settings: &RasterSettings) -> Result<RgbImage, RasterTooLarge> {
    let needed = raster_bytes(shape.vertex_count(), settings);
    if needed > settings.memory_limit as u128 {
        return Err(RasterTooLarge {
            width: settings.width,
            height: settings.height,
            vertices: shape.vertex_count(),
            needed,
            limit: settings.memory_limit,
        });
    }
    Ok(draw(shape, settings))
}

fn draw(shape: &Shape, settings: &RasterSettings) -> RgbImage {
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    let mut img = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    let pts = project(shape, settings.view);
    if pts.is_empty() {
        return img;
    }
    let canvas = Canvas::fit(&pts, w, h);
    let (wu, hu) = (w as usize, h as usize);
    if !shape.quads.is_empty() || !shape.triangles.is_empty() {
        shade(shape, &pts, &canvas, &mut img);
        return img;
    }
    let mut on_line = vec![false; pts.len()];
    let mut cov = vec![0f32; wu * hu];
    for (first, count, closed) in shape.polylines() {
        on_line[first..first + count].iter_mut().for_each(|x| *x = true);
        for i in first + 1..first + count {
            wu_line(&mut cov, wu, hu, canvas.px(pts[i - 1]), canvas.px(pts[i]));
        }
        if closed && count > 1 {
            wu_line(&mut cov, wu, hu, canvas.px(pts[first + count - 1]), canvas.px(pts[first]));
        }
    }
    // Remaining vertices: a point cloud, coloured by log density.
    let mut density = vec![0u32; wu * hu];
    for (p, used) in pts.iter().zip(&on_line) {
        if !used {
            let (x, y) = canvas.px(*p);
            if x >= 0.0 && y >= 0.0 && (x as usize) < wu && (y as usize) < hu {
                density[y as usize * wu + x as usize] += 1;
            }
        }
    }
    finish_picture(w, h, &cov, &density)
}

/// The picture of line coverage `cov` and point counts `density` (one per
/// pixel): ink by the coverage, or by the log density of the points.
pub(super) fn finish_picture(w: u32, h: u32, cov: &[f32], density: &[u32]) -> RgbImage {
    let mut img = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    let max = density.iter().copied().max().unwrap_or(0);
    let norm = (1.0 + f64::from(max)).ln().max(DEGENERATE);
    for (i, px) in img.pixels_mut().enumerate() {
        let dens = if density[i] > 0 { 0.35 + 0.65 * (1.0 + f64::from(density[i])).ln() / norm } else { 0.0 };
        *px = mix(PAPER, INK, f64::from(cov[i]).max(dens));
    }
    img
}

/// The flat shade of a triangle of projected points (screen x right, y up,
/// depth into the screen; light from the viewer's upper left, both sides
/// lit); `None` when degenerate.
pub(super) fn face_colour(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<Rgb<u8>> {
    let light = Vector3::new(-0.4, 0.6, -0.7).normalize();
    let (va, vb, vc) = (Vector3::from(a), Vector3::from(b), Vector3::from(c));
    let n = (vb - va).cross(&(vc - va));
    let r = 1.0 / n.norm();
    if !(r.is_finite() && r > 0.0) {
        return None;
    }
    Some(mix([40.0, 52.0, 80.0], [214.0, 226.0, 245.0], 0.15 + 0.85 * (n * r).dot(&light).abs()))
}

fn shade(shape: &Shape, pts: &[[f64; 3]], canvas: &Canvas, img: &mut RgbImage) {
    let (w, h) = (canvas.w, canvas.h);
    let mut depth = vec![f64::INFINITY; w * h];
    let split =
        shape.quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]].map(|t| t.map(|i| i as usize)));
    for tri in split.chain(shape.triangles.iter().copied()) {
        let [a, b, c] = tri.map(|i| pts[i]);
        let Some(colour) = face_colour(a, b, c) else { continue };
        let s = [a, b, c].map(|p| canvas.px(p));
        let (x0, x1) = (
            s.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
            s.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            s.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
            s.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
        );
        let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[2].0 - s[0].0) * (s[1].1 - s[0].1);
        if area.abs() < DEGENERATE {
            continue;
        }
        let (xs, xe) = (x0.floor().max(0.0) as usize, (x1.ceil() as usize).min(w.saturating_sub(1)));
        let (ys, ye) = (y0.floor().max(0.0) as usize, (y1.ceil() as usize).min(h.saturating_sub(1)));
        if x1 < 0.0 || y1 < 0.0 {
            continue;
        }
        for y in ys..=ye {
            for x in xs..=xe {
                let (fx, fy) = (x as f64 + 0.5, y as f64 + 0.5);
                let w0 = ((s[1].0 - fx) * (s[2].1 - fy) - (s[2].0 - fx) * (s[1].1 - fy)) / area;
                let w1 = ((s[2].0 - fx) * (s[0].1 - fy) - (s[0].0 - fx) * (s[2].1 - fy)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < -SLACK || w1 < -SLACK || w2 < -SLACK {
                    continue;
                }
                let z = w0 * a[2] + w1 * b[2] + w2 * c[2];
                let cell = &mut depth[y * w + x];
                if z < *cell {
                    *cell = z;
                    img.put_pixel(x as u32, y as u32, colour);
                }
            }
        }
    }
}

/// Encodes `img` as PNG into `path`, atomically.
///
/// # Errors
/// An encoding or I/O error.
pub fn write_png(path: &Path, img: &RgbImage) -> io::Result<()> {
    write_atomic(path, &png_bytes(img, &[], None, Compression::Small)?)
}

/// How hard a PNG is compressed: files keep `Small`; a picture sent to a
/// browser on the same machine is made `Fast`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Compression {
    /// Balanced deflate, adaptive filters: what files get.
    #[default]
    Small,
    /// The fastest deflate: about as large, several times quicker to make.
    Fast,
}

/// The PNG of an RGB picture, in memory: its `tEXt` chunks (see
/// [`write_png_text`]), its background made transparent by `matte` when
/// given (an RGBA picture). The one PNG encoder: every picture bcifs writes
/// or sends goes through it.
///
/// ```
/// let img = image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]));
/// let text = [("Software".to_string(), "bcifs".to_string())];
/// let png = bcifs::export::png_bytes(&img, &text, None, bcifs::export::Compression::Fast)?;
/// assert!(png.starts_with(b"\x89PNG") && png.windows(5).any(|w| w == b"bcifs"));
/// assert_eq!(image::load_from_memory(&png)?.to_rgb8(), img);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// A keyword PNG refuses (empty, or over 79 characters).
pub fn png_bytes(
    img: &RgbImage,
    text: &[(String, String)],
    matte: Option<Matte>,
    compression: Compression,
) -> io::Result<Vec<u8>> {
    let (width, height) = img.dimensions();
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(match compression {
            Compression::Small => png::Compression::Balanced,
            Compression::Fast => png::Compression::Fastest,
        });
        // `tEXt` holds Latin-1; a value beyond it (α, ω, √) goes in an `iTXt` chunk, UTF-8.
        let latin1 = |t: &str| t.chars().map(|c| if (c as u32) < 256 { c } else { '?' }).collect::<String>();
        for (keyword, value) in text {
            if value.chars().all(|c| (c as u32) < 256) {
                encoder.add_text_chunk(latin1(keyword), value.clone()).map_err(io::Error::other)?;
            } else {
                encoder.add_itxt_chunk(latin1(keyword), value.clone()).map_err(io::Error::other)?;
            }
        }
        let rgba: Vec<u8>;
        let pixels = match matte {
            None => {
                encoder.set_color(png::ColorType::Rgb);
                img.as_raw()
            }
            Some(matte) => {
                encoder.set_color(png::ColorType::Rgba);
                rgba = img.pixels().flat_map(|px| matte.apply(px.0)).collect();
                &rgba
            }
        };
        let mut writer = encoder.write_header().map_err(io::Error::other)?;
        writer.write_image_data(pixels).map_err(io::Error::other)?;
        writer.finish().map_err(io::Error::other)?;
    }
    Ok(bytes)
}

/// How a picture's background becomes transparent (`--transparent`): the
/// pictures are ink mixed over a paper colour, and the matte recovers how
/// much ink each pixel holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Matte {
    /// Opaque shapes (shaded surfaces) on a paper no face colour equals:
    /// the paper's pixels transparent, the others opaque.
    Key([u8; 3]),
    /// One ink mixed over the paper (curves, clouds, one-colour density
    /// pictures): the ink, as opaque as the mix says.
    Ink {
        /// The background.
        paper: [u8; 3],
        /// The ink.
        ink: [u8; 3],
    },
    /// Inks of any colour over the paper (palette density pictures): the
    /// least opaque colour that, over the paper, gives the pixel (GIMP's
    /// "colour to alpha").
    Unmix([u8; 3]),
}

impl Matte {
    /// The matte of pictures of `shape` ([`Matte::Key`] for surfaces, the
    /// default ink otherwise).
    pub(crate) fn of_shape(shape: &Shape) -> Matte {
        if shape.quads.is_empty() && shape.triangles.is_empty() { Matte::default_ink() } else { Matte::Key([255; 3]) }
    }

    /// The default ink on white paper.
    pub fn default_ink() -> Matte {
        Matte::Ink { paper: PAPER.map(|c| c as u8), ink: INK.map(|c| c as u8) }
    }

    /// The pixel `px` with its alpha.
    pub fn apply(self, px: [u8; 3]) -> [u8; 4] {
        let f = px.map(f64::from);
        match self {
            Matte::Key(paper) => {
                let a = if px == paper { 0 } else { 255 };
                [px[0], px[1], px[2], a]
            }
            Matte::Ink { paper, ink } => {
                let (p, i) = (paper.map(f64::from), ink.map(f64::from));
                let d = [0, 1, 2].map(|k| p[k] - i[k]);
                let norm: f64 = d.iter().map(|x| x * x).sum();
                let v = if norm > 0.0 { (0..3).map(|k| (p[k] - f[k]) * d[k]).sum::<f64>() / norm } else { 1.0 };
                [ink[0], ink[1], ink[2], (v.clamp(0.0, 1.0) * 255.0).round() as u8]
            }
            Matte::Unmix(paper) => {
                let p = paper.map(f64::from);
                let alpha = (0..3)
                    .map(|k| match f[k].total_cmp(&p[k]) {
                        std::cmp::Ordering::Greater => (f[k] - p[k]) / (255.0 - p[k]),
                        std::cmp::Ordering::Less => (p[k] - f[k]) / p[k],
                        std::cmp::Ordering::Equal => 0.0,
                    })
                    .fold(0.0, f64::max);
                if alpha <= 0.0 {
                    return [0; 4];
                }
                let c = [0, 1, 2].map(|k| (p[k] + (f[k] - p[k]) / alpha).round().clamp(0.0, 255.0) as u8);
                [c[0], c[1], c[2], (alpha * 255.0).round() as u8]
            }
        }
    }
}

/// Writes an RGB picture as PNG with `tEXt` chunks (keyword, text), as
/// flam3 records its genome: the settings that made the picture travel
/// with it (`Software`, `Title`, `Description`, `Comment` are PNG's
/// registered keywords). Keywords are 1 to 79 Latin-1 characters; the
/// text is Latin-1 (others are replaced by `?`).
///
/// # Errors
/// An I/O error or a keyword PNG refuses; nothing is left half-written.
pub fn write_png_text(path: &Path, img: &RgbImage, text: &[(String, String)]) -> io::Result<()> {
    write_atomic(path, &png_bytes(img, text, None, Compression::Small)?)
}

/// [`write_png_text`], the background made transparent by `matte` when
/// given (an RGBA picture), the RGB picture as it is otherwise.
///
/// # Errors
/// As [`write_png_text`].
pub fn write_png_matte(path: &Path, img: &RgbImage, text: &[(String, String)], matte: Option<Matte>) -> io::Result<()> {
    write_atomic(path, &png_bytes(img, text, matte, Compression::Small)?)
}

/// The picture as `#`/`.` text (a pixel is `#` when darker than half), for golden tests.
pub fn ascii(img: &RgbImage) -> String {
    let mut out = String::new();
    for y in 0..img.height() {
        for x in 0..img.width() {
            out.push(if img.get_pixel(x, y)[0] < 160 { '#' } else { '.' });
        }
        out.push('\n');
    }
    out
}
