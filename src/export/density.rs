//! Density pictures of the chaos game, made as flame renderers make them:
//! samples are counted per cell (never stored), optionally coloured by the
//! arrows they went through, spread by a density-estimation blur where they
//! are sparse, and tone-mapped by log-density.

use std::io;
use std::path::Path;

use image::{Rgb, RgbImage};

use super::png::{INK, PAPER, mix};
use super::view::{Canvas, RasterSettings, RasterTooLarge, screen};
use crate::geometry::{BATCH, CHUNK, PointBatches};

/// Colours indexed by the colour coordinate `c ∈ [0, 1]` (256 entries), as
/// in flame renderers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Palette(pub Vec<[u8; 3]>);

/// The named palettes: name, colours along the coordinate (spread evenly,
/// interpolated linearly in between).
const NAMED: [(&str, &[[u8; 3]]); 5] = [
    ("fire", &[[110, 0, 0], [215, 40, 0], [255, 150, 0], [255, 240, 150]]),
    ("ocean", &[[8, 29, 88], [34, 94, 168], [29, 145, 192], [127, 205, 187], [237, 248, 177]]),
    ("rainbow", &[[255, 0, 0], [255, 255, 0], [0, 255, 0], [0, 255, 255], [0, 0, 255], [255, 0, 255]]),
    ("viridis", &[[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]]),
    ("sunset", &[[63, 0, 125], [190, 40, 120], [250, 110, 60], [255, 210, 90]]),
];

impl Palette {
    /// The colour at coordinate `c` in `[0, 1]` (as the density pictures pick it).
    pub fn colour(&self, c: f32) -> [u8; 3] {
        self.0.get(index(c)).or(self.0.last()).copied().unwrap_or([0; 3])
    }

    /// The names [`Palette::named`] knows.
    pub fn names() -> impl Iterator<Item = &'static str> {
        NAMED.iter().map(|(n, _)| *n)
    }

    /// A named palette (see [`Palette::names`]).
    ///
    /// ```
    /// let fire = bcifs::export::Palette::named("fire").unwrap();
    /// assert_eq!((fire.0.len(), fire.0[0]), (256, [110, 0, 0]));
    /// ```
    pub fn named(name: &str) -> Option<Palette> {
        let (_, stops) = NAMED.iter().find(|(n, _)| *n == name)?;
        Some(Palette::through(stops))
    }

    /// 256 colours through `stops`, spread evenly from 0 to 1.
    pub fn through(stops: &[[u8; 3]]) -> Palette {
        let last = stops.len().saturating_sub(1).max(1) as f64;
        Palette(
            (0..256)
                .map(|i| {
                    let t = i as f64 / 255.0 * last;
                    let k = (t.floor() as usize).min(stops.len().saturating_sub(2));
                    let (a, b) = (stops[k], stops[(k + 1).min(stops.len() - 1)]);
                    let f = t - k as f64;
                    [0, 1, 2].map(|j| (f64::from(a[j]) + (f64::from(b[j]) - f64::from(a[j])) * f).round() as u8)
                })
                .collect(),
        )
    }

    /// The colours of a picture's middle row, left to right, resampled to
    /// 256 entries (flam3 takes palettes from pictures too).
    ///
    /// # Errors
    /// An unreadable picture.
    pub fn from_image(path: &Path) -> io::Result<Palette> {
        let img = image::open(path).map_err(io::Error::other)?.to_rgb8();
        if img.width() == 0 || img.height() == 0 {
            return Err(io::Error::other("the palette picture is empty"));
        }
        let y = img.height() / 2;
        let w = u64::from(img.width());
        Ok(Palette((0..256u64).map(|i| img.get_pixel(((i * w) / 256) as u32, y).0).collect()))
    }

    /// A palette by name, or else the picture file of that path.
    ///
    /// # Errors
    /// Neither a name nor a readable picture: what was tried and the names.
    pub fn parse(spec: &str) -> Result<Palette, String> {
        if let Some(p) = Palette::named(spec) {
            return Ok(p);
        }
        let names = Palette::names().collect::<Vec<_>>().join(", ");
        Palette::from_image(Path::new(spec))
            .map_err(|e| format!("`{spec}` is not a palette name ({names}) nor a readable picture: {e}"))
    }

    /// The colour of coordinate `c` (clamped to `[0, 1]`).
    #[inline]
    pub fn at(&self, c: f32) -> [u8; 3] {
        self.0[index(c)]
    }
}

#[inline(always)]
fn index(c: f32) -> usize {
    usize::from((c * 255.999) as u8)
}

/// Tone mapping of a density picture, as flame renderers do it. A pixel
/// averages its `s × s` cells into a count `c` and (with a palette) a mean
/// colour `m`; `v = (ln(1 + b c) / ln(1 + b max))^(1/γ)` is its ink's share
/// over the background. The ink is the default blue, or with a palette
/// `vib · m · v + (1 − vib) · (ln(1 + b c m) / ln(1 + b max))^(1/γ)` per
/// channel: vibrancy 1 keeps the hues, 0 tone-maps each channel on its own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tone {
    /// `b`: larger shows sparse regions brighter (default 1).
    pub brightness: f64,
    /// `γ` (default 2.2).
    pub gamma: f64,
    /// `vib` in `[0, 1]` (default 1).
    pub vibrancy: f64,
    /// Cells per pixel side (default 1).
    pub supersample: u32,
    /// Density-estimation blur: the largest kernel radius, in pixels (0:
    /// off). A cell of count `c` is spread over a disc of radius
    /// `blur / c^curve` (at least half a cell), so sparse regions are smoothed and dense
    /// ones stay sharp (flam3's `estimator_radius`).
    pub blur: f64,
    /// How fast the kernel shrinks with the count (default 0.4, flam3's `estimator_curve`).
    pub blur_curve: f64,
    /// The background (default: white paper for ink, black for a palette).
    pub background: Option<[u8; 3]>,
}

impl Default for Tone {
    fn default() -> Tone {
        Tone {
            brightness: 1.0,
            gamma: 2.2,
            vibrancy: 1.0,
            supersample: 1,
            blur: 0.0,
            blur_curve: 0.4,
            background: None,
        }
    }
}

impl Tone {
    /// The settings checked: positive finite brightness and gamma,
    /// supersampling 1 to 8, vibrancy in [0, 1], a blur radius of 0 to 64
    /// pixels and a blur curve from 0 up; the message names what is wrong.
    ///
    /// # Errors
    /// A setting out of its range.
    pub fn checked(self) -> Result<Tone, String> {
        let Tone { brightness, gamma, vibrancy, supersample, blur, blur_curve, .. } = self;
        if !(brightness > 0.0 && brightness.is_finite() && gamma > 0.0 && gamma.is_finite()) {
            return Err("brightness and gamma must be positive numbers".into());
        }
        if !(1..=8).contains(&supersample) {
            return Err(format!("supersample {supersample}: expected 1 to 8"));
        }
        if !(0.0..=1.0).contains(&vibrancy) {
            return Err(format!("vibrancy {vibrancy}: expected a number between 0 and 1"));
        }
        if !(blur.is_finite() && (0.0..=64.0).contains(&blur) && blur_curve.is_finite() && blur_curve >= 0.0) {
            return Err(format!("blur {blur} (curve {blur_curve}): a radius from 0 to 64 pixels, a curve from 0 up"));
        }
        Ok(self)
    }

    /// A colour: `RRGGBB` in hexadecimal (an optional `#`), `white` or `black`.
    ///
    /// # Errors
    /// Any other text.
    pub fn parse_colour(text: &str) -> Result<[u8; 3], String> {
        match text {
            "white" => return Ok([255; 3]),
            "black" => return Ok([0; 3]),
            _ => {}
        }
        let hex = text.trim_start_matches('#');
        let channel = |k: usize| hex.get(2 * k..2 * k + 2).and_then(|h| u8::from_str_radix(h, 16).ok());
        match (hex.len(), channel(0), channel(1), channel(2)) {
            (6, Some(r), Some(g), Some(b)) => Ok([r, g, b]),
            _ => Err(format!("`{text}`: expected a colour, RRGGBB in hexadecimal, white or black")),
        }
    }

    /// The paper of a density picture: the background, or white for one
    /// ink and black for a palette.
    pub fn paper(&self, palette: bool) -> [u8; 3] {
        self.background.unwrap_or(if palette { [0; 3] } else { PAPER.map(|c| c as u8) })
    }

    /// How the background of a density picture becomes transparent: the
    /// one ink unmixed from the paper, or a palette's inks.
    pub fn matte(&self, palette: bool) -> super::png::Matte {
        if palette {
            super::png::Matte::Unmix(self.paper(true))
        } else {
            super::png::Matte::Ink { paper: self.paper(false), ink: INK.map(|c| c as u8) }
        }
    }
}

/// Samples of a chaos game counted per cell: `width · s × height · s` cells
/// for a `width × height` picture with `s × s` cells per pixel, and with a
/// palette the sums of their colours.
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
    /// Per cell, the sums over its samples of their palette colour's
    /// channels shifted right by `shift` bits (empty without a palette).
    pub colours: Vec<[u32; 3]>,
    /// Bits dropped from each sample's colour channels so that no sum can
    /// overflow (0 unless a cell gets more than 16.8 million samples).
    pub shift: u32,
}

/// Bytes per cell of one thread's accumulator: a byte of count and (touched
/// only where cells spill) a 32-bit count, or with colours a word of 16-bit
/// lanes and (touched only where cells spill) 32-bit sums.
fn cell_bytes(colour: bool) -> u128 {
    if colour { 24 } else { 5 }
}

/// What [`density_counts`] and [`Density::image`] allocate for a picture.
pub fn density_bytes(settings: &RasterSettings, supersample: u32, colour: bool, blur: bool) -> u128 {
    let s = u128::from(supersample.clamp(1, 8));
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    let cells = pixels * s * s;
    let threads = rayon::current_num_threads().max(2) as u128;
    let accumulators = cells * cell_bytes(colour) * threads;
    let result = cells * if colour { 16 } else { 4 };
    let blurred = if blur { cells * 16 } else { 0 };
    accumulators + result + blurred + pixels * 19 + CHUNK as u128 * 32 * threads
}

impl Density {
    /// The tone-mapped picture (see [`Tone`]).
    pub fn image(&self, tone: &Tone) -> RgbImage {
        let (w, h, s) = (self.width, self.height, self.supersample);
        let sw = w * s;
        let colour = !self.colours.is_empty();
        // Per pixel: the mean count of its cells and its colour sums (0–1 per sample).
        let mut count = vec![0f32; w * h];
        let mut paint = vec![[0f32; 3]; if colour { w * h } else { 0 }];
        let per_cell = 1.0 / (s * s) as f32;
        let unit = f32::from(1u16 << self.shift.min(8)) / 255.0 * per_cell;
        let pixel = |i: usize| (i / sw / s) * w + (i % sw) / s;
        if tone.blur > 0.0 {
            let (cells, paints) = self.blurred(tone.blur * s as f64, tone.blur_curve);
            for (i, c) in cells.iter().enumerate() {
                count[pixel(i)] += c * per_cell;
            }
            for (i, p) in paints.iter().enumerate() {
                let q = &mut paint[pixel(i)];
                (0..3).for_each(|k| q[k] += p[k] * unit);
            }
        } else {
            for (i, c) in self.counts.iter().enumerate() {
                count[pixel(i)] += *c as f32 * per_cell;
            }
            for (i, p) in self.colours.iter().enumerate() {
                let q = &mut paint[pixel(i)];
                (0..3).for_each(|k| q[k] += p[k] as f32 * unit);
            }
        }
        let max = f64::from(count.iter().copied().fold(0.0, f32::max));
        let b = tone.brightness.max(crate::algebra::tolerance::SLACK);
        let norm = (1.0 + b * max).ln().max(1e-300);
        let gamma = 1.0 / tone.gamma.max(1e-3);
        let vib = tone.vibrancy.clamp(0.0, 1.0);
        let level = |c: f64| ((1.0 + b * c).ln() / norm).clamp(0.0, 1.0).powf(gamma);
        let paper = tone.paper(colour).map(f64::from);
        let mut img = RgbImage::new(w as u32, h as u32);
        let empty = Rgb(paper.map(|c| c.round() as u8));
        for (i, px) in img.pixels_mut().enumerate() {
            let c = f64::from(count[i]);
            if c <= 0.0 {
                *px = empty;
                continue;
            }
            let v = level(c);
            *px = if colour {
                let mean = paint[i].map(|p| f64::from(p) / c);
                Rgb([0, 1, 2].map(|k| {
                    let flat = if vib < 1.0 { (1.0 - vib) * level(c * mean[k]) } else { 0.0 };
                    let ink = vib * mean[k] * v + flat;
                    (paper[k] * (1.0 - v) + 255.0 * ink).round().clamp(0.0, 255.0) as u8
                }))
            } else {
                mix(paper, INK, v)
            };
        }
        img
    }

    /// The samples as dots, as a scatter plot draws them: a pixel is ink
    /// when any sample fell in it, whatever their number.
    pub fn dots(&self) -> RgbImage {
        let (w, h, s) = (self.width, self.height, self.supersample);
        let mut img = RgbImage::from_pixel(w as u32, h as u32, mix(PAPER, INK, 0.0));
        for (i, _) in self.counts.iter().enumerate().filter(|(_, c)| **c > 0) {
            let (x, y) = ((i % (w * s)) / s, i / (w * s) / s);
            img.put_pixel(x as u32, y as u32, mix(PAPER, INK, 1.0));
        }
        img
    }

    /// The cells spread by the density-estimation kernel: counts and
    /// colour sums as floats (colour sums in the units of `colours`).
    fn blurred(&self, radius: f64, curve: f64) -> (Vec<f32>, Vec<[f32; 3]>) {
        let (sw, sh) = ((self.width * self.supersample) as i64, (self.height * self.supersample) as i64);
        let colour = !self.colours.is_empty();
        let mut cells = vec![0f32; self.counts.len()];
        let mut paints = vec![[0f32; 3]; self.colours.len()];
        // Kernels by radius in quarter cells: Epanechnikov weights (1 − d²/(r + ½)²), summing to 1.
        let mut kernels: Vec<Option<(i64, Vec<f32>)>> = Vec::new();
        let curve = curve.max(0.0);
        for (i, &c) in self.counts.iter().enumerate() {
            if c == 0 {
                continue;
            }
            let r = radius / f64::from(c).powf(curve);
            let (x, y) = (i as i64 % sw, i as i64 / sw);
            let paint = if colour { self.colours[i].map(|v| v as f32) } else { [0.0; 3] };
            if r < 0.5 {
                cells[i] += c as f32;
                if colour {
                    (0..3).for_each(|k| paints[i][k] += paint[k]);
                }
                continue;
            }
            let q = (r * 4.0).round() as usize;
            if kernels.len() <= q {
                kernels.resize(q + 1, None);
            }
            let (reach, weights) = kernels[q].get_or_insert_with(|| {
                let r = q as f64 / 4.0 + 0.5;
                let reach = r.floor() as i64;
                let mut wts: Vec<f32> = (-reach..=reach)
                    .flat_map(|dy| (-reach..=reach).map(move |dx| (dx, dy)))
                    .map(|(dx, dy)| (1.0 - ((dx * dx + dy * dy) as f64) / (r * r)).max(0.0) as f32)
                    .collect();
                let total: f32 = wts.iter().sum();
                wts.iter_mut().for_each(|w| *w /= total);
                (reach, wts)
            });
            let side = 2 * *reach + 1;
            for (j, wt) in weights.iter().enumerate() {
                let (tx, ty) = (x + j as i64 % side - *reach, y + j as i64 / side - *reach);
                if *wt == 0.0 || tx < 0 || ty < 0 || tx >= sw || ty >= sh {
                    continue;
                }
                let t = (ty * sw + tx) as usize;
                cells[t] += c as f32 * wt;
                if colour {
                    (0..3).for_each(|k| paints[t][k] += paint[k] * wt);
                }
            }
        }
        (cells, paints)
    }
}

/// The chaos game of `game` as a density picture: [`density_counts`], tone-mapped.
///
/// # Errors
/// [`RasterTooLarge`] when the buffers would not fit `settings.memory_limit`.
pub fn density_image(
    game: &impl PointBatches,
    points: usize,
    settings: &RasterSettings,
    tone: &Tone,
    palette: Option<&Palette>,
) -> Result<RgbImage, RasterTooLarge> {
    let needed = density_bytes(settings, tone.supersample, palette.is_some(), tone.blur > 0.0);
    if needed > settings.memory_limit as u128 {
        return Err(too_large(settings, points, needed));
    }
    Ok(density_counts(game, points, settings, tone.supersample, palette)?.image(tone))
}

fn too_large(settings: &RasterSettings, points: usize, needed: u128) -> RasterTooLarge {
    RasterTooLarge {
        width: settings.width,
        height: settings.height,
        vertices: points,
        needed,
        limit: settings.memory_limit,
    }
}

/// `points` samples of the chaos game of `game` counted per cell (and with
/// a palette, their colours summed: each sample has the colour of its
/// colour coordinate, see [`crate::eval::RandomSettings::colours`]), one
/// buffer per thread merged by summing integers (so the same seed gives
/// the same picture with any number of threads), never stored: memory is
/// `pixels · s²` bytes per thread and up to 4 more where cells pass 255
/// samples (with a palette 8, and up to 16 more), whatever `points`, and
/// the merged counts (4 bytes a cell, 16 with a palette). The frame is
/// fitted on the first batch of points (with a margin of 3%); samples
/// outside it are left out.
///
/// ```
/// use bcifs::eval::{ChaosGame, RandomSettings};
/// use bcifs::export::{Palette, RasterSettings, Tone, density_counts};
/// let design = bcifs::builtin_design("gasket").unwrap();
/// let inst = bcifs::instantiate(&design, &[]).unwrap();
/// let game = ChaosGame::new(&inst.automaton, design.model().unwrap(), &RandomSettings::default()).unwrap();
/// let fire = Palette::named("fire").unwrap();
/// let raster = RasterSettings::default().with_size(64, 64);
/// let cells = density_counts(&game, 100_000, &raster, 1, Some(&fire)).unwrap();
/// assert!(cells.counts.iter().map(|&c| c as usize).sum::<usize>() > 99_900);
/// let picture = cells.image(&Tone { blur: 1.0, ..Tone::default() });
/// assert_eq!(picture.dimensions(), (64, 64));
/// ```
///
/// # Errors
/// [`RasterTooLarge`] when the buffers would not fit `settings.memory_limit`.
pub fn density_counts(
    game: &impl PointBatches,
    points: usize,
    settings: &RasterSettings,
    supersample: u32,
    palette: Option<&Palette>,
) -> Result<Density, RasterTooLarge> {
    let s = supersample.clamp(1, 8) as usize;
    let (w, h) = (settings.width.max(1) as usize, settings.height.max(1) as usize);
    let (sw, sh) = (w * s, h * s);
    let needed = density_bytes(settings, supersample, palette.is_some(), false);
    if needed > settings.memory_limit as u128 {
        return Err(too_large(settings, points, needed));
    }
    let (first, frame) = Frame::of_first_batch(game, points, settings, (sw, sh));
    let Some(palette) = palette else {
        let counts = count_points(game, points, &frame);
        return Ok(Density { width: w, height: h, supersample: s, counts, colours: Vec::new(), shift: 0 });
    };
    let (counts, colours, shift) = paint_points(game, points, &frame, &first, palette);
    Ok(Density { width: w, height: h, supersample: s, counts, colours, shift })
}

/// Where a density picture of `game` looks, for a picture of the plane:
/// the modelling point at its centre and its pixels per modelling unit
/// (what a `.flame` file's `center` and `scale` say), fitted on the first
/// batch of points as [`density_counts`] fits it.
pub fn picture_frame(game: &impl PointBatches, points: usize, settings: &RasterSettings) -> ([f64; 2], f64) {
    let (w, h) = (settings.width.max(1) as usize, settings.height.max(1) as usize);
    let (_, frame) = Frame::of_first_batch(game, points, settings, (w, h));
    let centre = [(w as f64 / 2.0 - frame.ox) / frame.scale, (frame.oy - h as f64 / 2.0) / frame.scale];
    (centre, frame.scale)
}

impl Frame {
    /// The frame of the picture: the first batch's extent, centred, 3%
    /// wider; and the first batch's projected points.
    fn of_first_batch(
        game: &impl PointBatches,
        points: usize,
        settings: &RasterSettings,
        (sw, sh): (usize, usize),
    ) -> (Vec<[f64; 3]>, Frame) {
        let d = game.dim();
        let turn = settings.view.turn();
        let first: Vec<[f64; 3]> = game.fold(
            BATCH.min(points.max(1)),
            false,
            Vec::new,
            |acc: &mut Vec<[f64; 3]>, xs, _| {
                let finite = |p: &[f64; 3]| p.iter().all(|x| x.is_finite());
                acc.extend(xs.chunks_exact(d).map(|p| screen(&turn, p)).filter(finite))
            },
            |mut a, b| {
                a.extend(b);
                a
            },
        );
        let canvas = Canvas::fill(&first, sw as u32, sh as u32, 0.97);
        let frame = Frame {
            turn: [0, 1, 2].map(|j| [turn.row(0)[j], turn.row(2)[j]]),
            d,
            scale: canvas.scale,
            ox: canvas.off[0],
            oy: canvas.h as f64 - canvas.off[1],
            sw,
            sh,
        };
        (first, frame)
    }
}

/// The samples counted per cell. Cells of a chunk first, then the
/// increments in a tight loop (many cache misses in flight), each into a
/// byte per cell that carries 256 into the cell's 32-bit count when it
/// wraps: a quarter of the memory of 32-bit counts, so that a 4096²
/// picture's counts (16 MiB) stay in the last-level cache, and the 32-bit
/// counts' pages are touched only where cells pass 255 samples. A sample
/// outside the frame goes to the extra cell at the end, dropped.
fn count_points(game: &impl PointBatches, points: usize, frame: &Frame) -> Vec<u32> {
    let (trash, d) = (frame.sw * frame.sh, frame.d);
    let partials = game.fold(
        points,
        false,
        || vec![Spilling::<u8, u32>::new(trash + 1)],
        |parts, xs, _| {
            let acc = &mut parts[0];
            let mut cells = [0u32; CHUNK];
            frame.cells(xs, &mut cells);
            for &i in &cells[..xs.len() / d] {
                let c = &mut acc.low[i as usize];
                *c = c.wrapping_add(1);
                if *c == 0 {
                    acc.spill(i as usize, |h| *h = h.saturating_add(256));
                }
            }
        },
        |mut a, b| {
            a.extend(b);
            a
        },
    );
    let mut counts = vec![0u32; trash];
    {
        use rayon::prelude::*;
        counts.par_chunks_mut(1 << SPILL_BLOCK).enumerate().for_each(|(b, n)| {
            // Written before it is read: a zeroed page read first would be
            // mapped to the zero page and copied on the first write, with a
            // TLB shootdown across the threads each time.
            n.fill(0);
            for a in &partials {
                a.for_block(b, n.len(), |j, low, high| n[j] = n[j].saturating_add(low.into()).saturating_add(high));
            }
        });
    }
    counts
}

/// One thread's cells: a small number per cell (a byte of count, or a word
/// of 16-bit lanes), carried into large ones when it would overflow. The
/// large numbers' pages are touched only where cells carry (zeroed memory
/// that is never written is never mapped), and flagged, so that summing
/// reads only those.
struct Spilling<L, H> {
    low: Vec<L>,
    high: Vec<H>,
    spilled: Vec<bool>,
}

/// log2 of the cells per flag of [`Spilling::spilled`].
const SPILL_BLOCK: u32 = 10;

impl<L: Clone + Default, H: Clone + Default> Spilling<L, H> {
    /// Zeros for `cells` cells.
    fn new(cells: usize) -> Self {
        Spilling {
            low: vec![L::default(); cells],
            high: vec![H::default(); cells],
            spilled: vec![false; (cells >> SPILL_BLOCK) + 1],
        }
    }

    /// Carries into the large numbers of cell `i`.
    #[inline(always)]
    fn spill(&mut self, i: usize, carry: impl FnOnce(&mut H)) {
        carry(&mut self.high[i]);
        self.spilled[i >> SPILL_BLOCK] = true;
    }

    /// The first `len` cells of block `b` (of `2^SPILL_BLOCK` cells), each
    /// handed to `add` with its place in the block, its small numbers and
    /// its large ones (zero, unread, where the block never carried).
    #[inline(always)]
    fn for_block(&self, b: usize, len: usize, mut add: impl FnMut(usize, L, H))
    where
        L: Copy,
        H: Copy,
    {
        let start = b << SPILL_BLOCK;
        let low = &self.low[start..start + len];
        if self.spilled[b] {
            let high = &self.high[start..start + len];
            low.iter().zip(high).enumerate().for_each(|(j, (l, h))| add(j, *l, *h));
        } else {
            low.iter().enumerate().for_each(|(j, l)| add(j, *l, H::default()));
        }
    }
}

/// The samples counted per cell with their colour sums (the palette's
/// colours shifted right by the shift returned, so that no sum overflows).
fn paint_points(
    game: &impl PointBatches,
    points: usize,
    frame: &Frame,
    first: &[[f64; 3]],
    palette: &Palette,
) -> (Vec<u32>, Vec<[u32; 3]>, u32) {
    let trash = frame.sw * frame.sh;
    // Colour sums must not overflow: the densest cell of the first batch,
    // scaled to all the points with a margin of 4, bounds a cell's count.
    let mut hits: Vec<u32> = first.iter().map(|p| frame.cell_of(p[0], p[1])).filter(|&i| i as usize != trash).collect();
    hits.sort_unstable();
    let densest = hits.chunk_by(|a, b| a == b).map(<[u32]>::len).max().unwrap_or(1);
    let bound = densest as f64 / first.len().max(1) as f64 * points as f64 * 4.0 + 1024.0;
    let shift = (0..=8).find(|&k| bound * f64::from(255u32 >> k) < f64::from(u32::MAX)).unwrap_or(8);
    // Per cell, the count and the three channel sums as four 16-bit lanes
    // of one word (8 bytes: twice as many cells stay in the caches as with
    // 32-bit sums), added in one addition: no lane carries into the next,
    // since a cell is spilled into the 32-bit sums when its count reaches
    // 255 (its channels are then at most 255 · 255 < 2^16).
    let lane = |c: u8| u64::from(c >> shift);
    let table: Vec<u64> =
        palette.0.iter().map(|c| 1 | lane(c[0]) << 16 | lane(c[1]) << 32 | lane(c[2]) << 48).collect();
    // One accumulator per thread, kept apart: they are summed once, cell by
    // cell, straight into the counts and colour sums.
    let partials = game.fold(
        points,
        true,
        || vec![Spilling::<u64, [u32; 4]>::new(trash + 1)],
        |parts, xs, cs| {
            let acc = &mut parts[0];
            let mut cells = [0u32; CHUNK];
            frame.cells(xs, &mut cells);
            for (&i, c) in cells.iter().zip(cs) {
                let a = &mut acc.low[i as usize];
                *a += table[index(*c)];
                if *a & 0xffff == 255 {
                    let lanes = std::mem::take(a);
                    acc.spill(i as usize, |s| {
                        (0..4).for_each(|k| s[k] = s[k].saturating_add((lanes >> (16 * k)) as u32 & 0xffff))
                    });
                }
            }
        },
        |mut a, b| {
            a.extend(b);
            a
        },
    );
    let mut counts = vec![0u32; trash];
    let mut colours = vec![[0u32; 3]; trash];
    {
        use rayon::prelude::*;
        let block = 1 << SPILL_BLOCK;
        counts.par_chunks_mut(block).zip(colours.par_chunks_mut(block)).enumerate().for_each(|(b, (n, c))| {
            // Written before read, as in `count_points`.
            n.fill(0);
            c.fill([0; 3]);
            for a in &partials {
                a.for_block(b, n.len(), |j, low, high| {
                    let lane = |k: usize| (low >> (16 * k)) as u32 & 0xffff;
                    n[j] = n[j].saturating_add(high[0]).saturating_add(lane(0));
                    (1..4).for_each(|k| c[j][k - 1] = c[j][k - 1].saturating_add(high[k]).saturating_add(lane(k)));
                });
            }
        });
    }
    (counts, colours, shift)
}

/// Where samples land: the view's rotation (screen x and y rows) and the fitted frame.
#[derive(Clone, Copy)]
struct Frame {
    turn: [[f64; 2]; 3],
    d: usize,
    scale: f64,
    ox: f64,
    oy: f64,
    sw: usize,
    sh: usize,
}

impl Frame {
    /// The cell of screen point `(a, b)`, or `sw · sh` outside the frame.
    #[inline(always)]
    fn cell_of(&self, a: f64, b: f64) -> u32 {
        // One cell to the right and down, so that truncation is the floor
        // on the frame and one unsigned comparison per axis tests it (NaN → 0 → out).
        let x = (a * self.scale + self.ox + 1.0) as i64 - 1;
        let y = (self.oy - b * self.scale + 1.0) as i64 - 1;
        if (x as u64) < self.sw as u64 && (y as u64) < self.sh as u64 {
            (y as usize * self.sw + x as usize) as u32
        } else {
            (self.sw * self.sh) as u32
        }
    }

    /// The cells of the points `xs` (`d` coordinates each) into `cells`.
    #[inline(always)]
    fn cells(&self, xs: &[f64], cells: &mut [u32]) {
        if self.d == 2 {
            for (p, c) in xs.chunks_exact(2).zip(cells) {
                *c = self.cell_of(p[0], p[1]);
            }
        } else {
            let t = &self.turn;
            for (p, c) in xs.chunks_exact(self.d).zip(cells) {
                let a = t[0][0] * p[0] + t[1][0] * p[1] + t[2][0] * p[2];
                let b = t[0][1] * p[0] + t[1][1] * p[1] + t[2][1] * p[2];
                *c = self.cell_of(a, b);
            }
        }
    }
}
