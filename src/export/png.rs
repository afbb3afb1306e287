//! PNG pictures: anti-aliased curves, point clouds by density, shaded
//! previews of surfaces.

use std::io;
use std::path::Path;

use glam::{DMat3, DVec3};
use image::{ImageFormat, Rgb, RgbImage};

use super::atomic::write_atomic;
use crate::geometry::Shape;

/// Where a 3D shape is looked at from: rotation about the vertical (z) axis,
/// then elevation, in degrees. 2D shapes ignore it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Rotation about z, degrees.
    pub yaw: f64,
    /// Elevation, degrees.
    pub pitch: f64,
}

impl Default for View {
    fn default() -> View {
        View { yaw: 30.0, pitch: 35.0 }
    }
}

/// Picture settings.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RasterSettings {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// View of 3D shapes.
    pub view: View,
    /// The most bytes drawing may allocate (picture, coverage and depth
    /// buffers, projected points); a larger picture is refused.
    pub memory_limit: usize,
}

impl Default for RasterSettings {
    fn default() -> RasterSettings {
        RasterSettings {
            width: 800,
            height: 800,
            view: View::default(),
            memory_limit: crate::eval::DEFAULT_MEMORY_LIMIT,
        }
    }
}

/// A picture that would not fit the memory limit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "a {width}×{height} picture of {vertices} points needs about {:.1} GiB to draw, over the in-memory limit of {:.1} GiB (--memory-mib): make it smaller",
    *needed as f64 / (1u64 << 30) as f64,
    *limit as f64 / (1u64 << 30) as f64
)]
pub struct RasterTooLarge {
    /// Width asked for.
    pub width: u32,
    /// Height asked for.
    pub height: u32,
    /// Points of the shape.
    pub vertices: usize,
    /// Bytes drawing would allocate.
    pub needed: u128,
    /// The limit.
    pub limit: usize,
}

/// Bytes [`raster`] allocates for a picture of `vertices` points: 11 per
/// pixel (the picture's 3, and 8 of coverage and density, or of depth)
/// and 25 per point (its projection and a flag).
pub fn raster_bytes(vertices: usize, settings: &RasterSettings) -> u128 {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    pixels * 11 + vertices as u128 * 25
}

impl RasterSettings {
    /// With a size.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.width = width;
        self.height = height;
        self
    }
    /// With a view.
    pub fn with_view(mut self, yaw: f64, pitch: f64) -> Self {
        self.view = View { yaw, pitch };
        self
    }
    /// With a memory limit in bytes.
    pub fn with_memory_limit(mut self, bytes: usize) -> Self {
        self.memory_limit = bytes;
        self
    }
}

const INK: [f64; 3] = [27.0, 58.0, 107.0];
const PAPER: [f64; 3] = [255.0, 255.0, 255.0];

/// Projects shape vertices to `(screen x, screen y up, depth)`: rotate
/// about z by the yaw, then tilt about x by the pitch, so x stays right, z
/// goes up the screen and y into it.
fn project(shape: &Shape, view: View) -> Vec<[f64; 3]> {
    let turn = DMat3::from_rotation_x(view.pitch.to_radians()) * DMat3::from_rotation_z(view.yaw.to_radians());
    (0..shape.vertex_count())
        .map(|i| {
            let p = shape.point(i);
            if shape.dim < 3 {
                return [p[0], p[1], 0.0];
            }
            let q = turn * DVec3::from(p);
            [q.x, q.z, q.y]
        })
        .collect()
}

struct Canvas {
    w: usize,
    h: usize,
    scale: f64,
    off: [f64; 2],
}

impl Canvas {
    fn fit(points: &[[f64; 3]], w: u32, h: u32) -> Canvas {
        Canvas::fill(points, w, h, 0.94)
    }

    /// The points' extent centred, filling the share `fill` of the picture.
    fn fill(points: &[[f64; 3]], w: u32, h: u32, fill: f64) -> Canvas {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let (w, h) = (w as usize, h as usize);
        let span = [(hi[0] - lo[0]).max(1e-12), (hi[1] - lo[1]).max(1e-12)];
        let scale = fill * (w as f64 / span[0]).min(h as f64 / span[1]);
        let off =
            [(w as f64 - span[0] * scale) / 2.0 - lo[0] * scale, (h as f64 - span[1] * scale) / 2.0 - lo[1] * scale];
        Canvas { w, h, scale, off }
    }
    /// Pixel coordinates (x right, y down).
    fn px(&self, p: [f64; 3]) -> (f64, f64) {
        (p[0] * self.scale + self.off[0], self.h as f64 - (p[1] * self.scale + self.off[1]))
    }
}

/// Tone mapping of a density picture, as flame renderers do it: the count
/// `c` of a pixel becomes `v = (ln(1 + b c) / ln(1 + b max))^(1/γ)`, the
/// ink's share of the pixel; `supersample` draws `s × s` cells per pixel
/// and averages their counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tone {
    /// `b`: larger shows sparse regions brighter (default 1).
    pub brightness: f64,
    /// `γ` (default 2.2).
    pub gamma: f64,
    /// Cells per pixel side (default 1).
    pub supersample: u32,
}

impl Default for Tone {
    fn default() -> Tone {
        Tone { brightness: 1.0, gamma: 2.2, supersample: 1 }
    }
}

/// Samples of a chaos game counted per cell: `width · s × height · s` cells
/// for a `width × height` picture with `s × s` cells per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Density {
    /// Picture width in pixels.
    pub width: usize,
    /// Picture height in pixels.
    pub height: usize,
    /// Cells per pixel side.
    pub supersample: usize,
    /// Counts, row by row over the cells.
    pub counts: Vec<u32>,
}

impl Density {
    /// The tone-mapped picture: each pixel's cells averaged, then
    /// `v = (ln(1 + b c) / ln(1 + b max))^(1/γ)` of ink.
    pub fn image(&self, tone: &Tone) -> RgbImage {
        let (w, h, s) = (self.width, self.height, self.supersample);
        let sw = w * s;
        let mut pixel = vec![0f64; w * h];
        for (i, c) in self.counts.iter().enumerate() {
            pixel[(i / sw / s) * w + (i % sw) / s] += f64::from(*c) / (s * s) as f64;
        }
        let max = pixel.iter().copied().fold(0.0, f64::max);
        let b = tone.brightness.max(1e-9);
        let norm = (1.0 + b * max).ln().max(1e-300);
        let gamma = tone.gamma.max(1e-3);
        let mut img = RgbImage::from_pixel(w as u32, h as u32, Rgb([255, 255, 255]));
        for (px, c) in img.pixels_mut().zip(&pixel) {
            let v = ((1.0 + b * c).ln() / norm).powf(1.0 / gamma);
            *px = mix(PAPER, INK, v.clamp(0.0, 1.0));
        }
        img
    }
}

/// The chaos game of `game` as a density picture: [`density`], tone-mapped.
///
/// # Errors
/// [`RasterTooLarge`] when the count buffers would not fit `settings.memory_limit`.
pub fn density_image(
    game: &crate::eval::ChaosGame,
    points: usize,
    settings: &RasterSettings,
    tone: &Tone,
) -> Result<RgbImage, RasterTooLarge> {
    Ok(density(game, points, settings, tone.supersample)?.image(tone))
}

/// `points` samples of the chaos game of `game` counted per cell, one count
/// buffer per thread merged by summing (so the same seed gives the same
/// counts with any number of threads), never stored: memory is
/// `4 · pixels · s²` bytes per thread and a batch of points, whatever
/// `points`. The frame is fitted on the first batch of points (with a
/// margin of 3%); samples outside it are left out.
///
/// # Errors
/// [`RasterTooLarge`] when the count buffers would not fit `settings.memory_limit`.
pub fn density(
    game: &crate::eval::ChaosGame,
    points: usize,
    settings: &RasterSettings,
    supersample: u32,
) -> Result<Density, RasterTooLarge> {
    let s = supersample.clamp(1, 8) as usize;
    let (w, h) = (settings.width.max(1) as usize, settings.height.max(1) as usize);
    let (sw, sh) = (w * s, h * s);
    let threads = rayon::current_num_threads().max(2) as u128;
    let needed = (sw * sh) as u128 * 4 * threads + (w * h * 11) as u128 + crate::eval::BATCH as u128 * 24 * threads;
    if needed > settings.memory_limit as u128 {
        return Err(RasterTooLarge {
            width: settings.width,
            height: settings.height,
            vertices: points,
            needed,
            limit: settings.memory_limit,
        });
    }
    let d = game.dim();
    let turn = DMat3::from_rotation_x(settings.view.pitch.to_radians())
        * DMat3::from_rotation_z(settings.view.yaw.to_radians());
    let screen = move |p: &[f64]| -> [f64; 3] {
        if d < 3 {
            return [p[0], p[1], 0.0];
        }
        let q = turn * DVec3::new(p[0], p[1], p[2]);
        [q.x, q.z, q.y]
    };
    // The frame: the first batch's extent, centred, 3% wider.
    let first: Vec<[f64; 3]> = game.fold(
        crate::eval::BATCH.min(points.max(1)),
        Vec::new,
        |acc: &mut Vec<[f64; 3]>, batch| acc.extend(batch.chunks_exact(d).map(screen)),
        |mut a, b| {
            a.extend(b);
            a
        },
    );
    let finite: Vec<[f64; 3]> = first.into_iter().filter(|p| p.iter().all(|x| x.is_finite())).collect();
    let canvas = Canvas::fill(&finite, sw as u32, sh as u32, 0.97);
    let counts = game.fold(
        points,
        || vec![0u32; sw * sh],
        |acc, batch| {
            for p in batch.chunks_exact(d) {
                let (x, y) = canvas.px(screen(p));
                if x >= 0.0 && y >= 0.0 && (x as usize) < sw && (y as usize) < sh {
                    let cell = &mut acc[y as usize * sw + x as usize];
                    *cell = cell.saturating_add(1);
                }
            }
        },
        |mut a, b| {
            a.iter_mut().zip(&b).for_each(|(x, y)| *x = x.saturating_add(*y));
            a
        },
    );
    Ok(Density { width: w, height: h, supersample: s, counts })
}

/// Xiaolin Wu's anti-aliased line into a coverage buffer.
fn wu_line(cov: &mut [f32], w: usize, h: usize, (mut x0, mut y0): (f64, f64), (mut x1, mut y1): (f64, f64)) {
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
    let gradient = if dx.abs() < 1e-12 { 1.0 } else { (y1 - y0) / dx };
    let (xs, xe) = (x0.round() as i64, x1.round() as i64);
    let mut y = y0 + gradient * (xs as f64 - x0);
    for x in xs..=xe {
        let (fl, fr) = (y.floor(), y - y.floor());
        if steep {
            plot(fl as i64, x, 1.0 - fr);
            plot(fl as i64 + 1, x, fr);
        } else {
            plot(x, fl as i64, 1.0 - fr);
            plot(x, fl as i64 + 1, fr);
        }
        y += gradient;
    }
}

fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> Rgb<u8> {
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
    let max = density.iter().copied().max().unwrap_or(0);
    let norm = (1.0 + f64::from(max)).ln().max(1e-12);
    for (i, px) in img.pixels_mut().enumerate() {
        let dens = if density[i] > 0 { 0.35 + 0.65 * (1.0 + f64::from(density[i])).ln() / norm } else { 0.0 };
        *px = mix(PAPER, INK, f64::from(cov[i]).max(dens));
    }
    img
}

fn shade(shape: &Shape, pts: &[[f64; 3]], canvas: &Canvas, img: &mut RgbImage) {
    let (w, h) = (canvas.w, canvas.h);
    let mut depth = vec![f64::INFINITY; w * h];
    // Screen: x right, y up, depth into the screen: light from the viewer's upper left.
    let light = DVec3::new(-0.4, 0.6, -0.7).normalize();
    let split =
        shape.quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]].map(|t| t.map(|i| i as usize)));
    for tri in split.chain(shape.triangles.iter().copied()) {
        let [a, b, c] = tri.map(|i| pts[i]);
        let (va, vb, vc) = (DVec3::from(a), DVec3::from(b), DVec3::from(c));
        let Some(n) = (vb - va).cross(vc - va).try_normalize() else { continue };
        let lambert = n.dot(light).abs();
        let colour = mix([40.0, 52.0, 80.0], [214.0, 226.0, 245.0], 0.15 + 0.85 * lambert);
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
        if area.abs() < 1e-12 {
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
                if w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9 {
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
    let mut bytes = io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, ImageFormat::Png).map_err(io::Error::other)?;
    write_atomic(path, bytes.get_ref())
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
