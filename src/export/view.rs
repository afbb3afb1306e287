//! How a picture looks at a shape: the view (yaw, pitch, up axis), the
//! picture's settings, the projection to the screen and the canvas that
//! fits the projected points in the picture. Shared by every picture: the
//! PNG raster, the streamed curve pictures, the density images and SVG.

use nalgebra::{Matrix3, Vector3};

/// A rotation of space.
pub(super) type DMat3 = Matrix3<f64>;

use crate::algebra::tolerance::DEGENERATE;
use crate::geometry::Shape;

/// Where a 3D shape is looked at from: rotation about the vertical (z) axis,
/// then elevation, in degrees. 2D shapes ignore it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Rotation about z, degrees.
    pub yaw: f64,
    /// Elevation, degrees.
    pub pitch: f64,
    /// The shape's coordinates are Y-up (a mesh read from an OBJ or OFF
    /// file): turned Z-up, `(x, y, z) ↦ (x, −z, y)`, before the view.
    pub y_up: bool,
}

impl Default for View {
    fn default() -> View {
        View { yaw: 30.0, pitch: 35.0, y_up: false }
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
    /// PNG with an alpha channel: the background transparent (see [`super::Matte`]).
    pub transparent: bool,
}

impl Default for RasterSettings {
    fn default() -> RasterSettings {
        RasterSettings {
            width: 800,
            height: 800,
            view: View::default(),
            memory_limit: crate::eval::DEFAULT_MEMORY_LIMIT,
            transparent: false,
        }
    }
}

/// A picture that would not fit the memory limit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "a {width}×{height} picture of {vertices} points needs about {} to draw, over the in-memory limit of {} (the memory budget): make it smaller",
    crate::progress::bytes_text(*needed),
    crate::progress::bytes_text(*limit as u128)
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

/// Bytes [`super::raster`] allocates for a picture of `vertices` points: 11 per
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
        self.view = View { yaw, pitch, ..self.view };
        self
    }
    /// For shapes whose coordinates are Y-up (`true`) or Z-up (`false`, the default).
    pub fn with_y_up(mut self, y_up: bool) -> Self {
        self.view.y_up = y_up;
        self
    }
    /// PNG pictures with a transparent background (RGBA).
    pub fn with_transparent(mut self, transparent: bool) -> Self {
        self.transparent = transparent;
        self
    }
    /// With a memory limit in bytes.
    pub fn with_memory_limit(mut self, bytes: usize) -> Self {
        self.memory_limit = bytes;
        self
    }
}

impl View {
    /// The view's rotation: about z by the yaw, then about x by the pitch.
    pub(super) fn turn(self) -> DMat3 {
        let about_x = |a: f64| {
            let (s, c) = a.sin_cos();
            DMat3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
        };
        let (s, c) = self.yaw.to_radians().sin_cos();
        let view = about_x(self.pitch.to_radians()) * DMat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        if self.y_up { view * about_x(std::f64::consts::FRAC_PI_2) } else { view }
    }
}

/// Where a point of 2 or 3 coordinates lands, `(screen x, screen y up,
/// depth)`, under the rotation `turn` of a [`View`]: x stays right, z goes
/// up the screen and y into it; 2D points are seen as they are.
#[inline]
pub(super) fn screen(turn: &DMat3, p: &[f64]) -> [f64; 3] {
    if p.len() < 3 {
        return [p[0], p.get(1).copied().unwrap_or(0.0), 0.0];
    }
    let q = turn * Vector3::new(p[0], p[1], p[2]);
    [q.x, q.z, q.y]
}

/// Projects shape vertices with [`screen`].
pub(super) fn project(shape: &Shape, view: View) -> Vec<[f64; 3]> {
    let turn = view.turn();
    (0..shape.vertex_count()).map(|i| screen(&turn, &shape.point(i)[..shape.dim.clamp(2, 3)])).collect()
}

pub(super) struct Canvas {
    pub(super) w: usize,
    pub(super) h: usize,
    pub(super) scale: f64,
    pub(super) off: [f64; 2],
}

impl Canvas {
    pub(super) fn fit(points: &[[f64; 3]], w: u32, h: u32) -> Canvas {
        Canvas::fill(points, w, h, 0.94)
    }

    /// The points' extent centred, filling the share `fill` of the picture.
    pub(super) fn fill(points: &[[f64; 3]], w: u32, h: u32, fill: f64) -> Canvas {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let (w, h) = (w as usize, h as usize);
        let span = [(hi[0] - lo[0]).max(DEGENERATE), (hi[1] - lo[1]).max(DEGENERATE)];
        let scale = fill * (w as f64 / span[0]).min(h as f64 / span[1]);
        let off =
            [(w as f64 - span[0] * scale) / 2.0 - lo[0] * scale, (h as f64 - span[1] * scale) / 2.0 - lo[1] * scale];
        Canvas { w, h, scale, off }
    }
    /// Pixel coordinates (x right, y down).
    pub(super) fn px(&self, p: [f64; 3]) -> (f64, f64) {
        (p[0] * self.scale + self.off[0], self.h as f64 - (p[1] * self.scale + self.off[1]))
    }
}
