//! From a picture to a segments file (the Bézier-fractal contours paper §6): threshold, the outer
//! contour of the largest shape, corners by IPAN99, and each piece between
//! corners fitted by a line segment or a quadratic Bézier arc, split further
//! where the fit is off by more than the tolerance.
//!
//! Choices: the threshold is Otsu's unless given; the shape is the side of
//! the threshold that covers less of the picture's border (dark on light or
//! light on dark both work); of its 8-connected components the largest is
//! taken (the others are counted in [`Fit::components`]); only its outer
//! contour is traced (holes are ignored). The contour runs through the
//! midpoints of the cracks between the shape's pixels and the outside
//! (pixel centres at integer coordinates), counter-clockwise on screen
//! (x right, y down): on the edge the picture draws, within half a pixel of
//! the true edge, in sharp notches too.

use super::segments::Segment;
use crate::algebra::tolerance::{DEGENERATE, ROUNDING};

/// IPAN99's parameters (Chetverikov and Szabó): a point is a corner
/// candidate when a triangle `(p⁻, p, p⁺)` with sides `|p − p⁻|`,
/// `|p − p⁺|` in `[d_min, d_max]` has an opening angle at most `alpha_max`;
/// the sharpest candidate within `d_max` wins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ipan {
    /// Shortest side, pixels (published default 7).
    pub d_min: f64,
    /// Longest side, pixels (published default 9).
    pub d_max: f64,
    /// Widest opening angle of a corner, degrees (published default 150).
    pub alpha_max: f64,
}

impl Default for Ipan {
    fn default() -> Ipan {
        Ipan { d_min: 7.0, d_max: 9.0, alpha_max: 150.0 }
    }
}

/// How to fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSettings {
    /// Grey level in 0..=255 separating shape and background (`None`: Otsu's).
    pub threshold: Option<u8>,
    /// The corner detector.
    pub ipan: Ipan,
    /// Largest Hausdorff distance, pixels, between the traced contour and
    /// the fitted one (piece by piece, both ways).
    pub tolerance: f64,
}

impl Default for FitSettings {
    fn default() -> FitSettings {
        FitSettings { threshold: None, ipan: Ipan::default(), tolerance: 1.0 }
    }
}

/// What [`fit_contour`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The threshold used.
    pub threshold: u8,
    /// 8-connected components of the shape's side (the largest is fitted).
    pub components: usize,
    /// The traced contour (the midpoints of the cracks between the shape's
    /// pixels and the outside, pixel centres at integer coordinates; closed:
    /// the last point is not repeated).
    pub contour: Vec<[f64; 2]>,
    /// The corners, as points of the contour.
    pub corners: Vec<[f64; 2]>,
    /// The fitted pieces, in contour order, end to end, closed.
    pub segments: Vec<Segment>,
    /// The largest Hausdorff distance between a piece and the run of the
    /// traced contour it stands for (both ways: every traced point near the
    /// piece, every point of the piece near the traced contour), except
    /// within [`Fit::cut_corners`].
    pub max_distance: f64,
    /// The sharp corners the picture cut off (a spike drawn only where it is
    /// a pixel wide) or filled in (a notch as narrow): each joint where two
    /// fitted edges meet beyond the traced pixels, and the radius around it
    /// within which the fit and the traced contour are not compared (half a
    /// pixel over `1 / tan(θ / 2)` for an opening θ).
    pub cut_corners: Vec<([f64; 2], f64)>,
}

/// Why a picture gives no contour.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FitError {
    /// An empty picture.
    #[error("the picture is empty")]
    Empty,
    /// One grey level, or a threshold that leaves one side empty.
    #[error("nothing to trace: every pixel is on the same side of the threshold {0} (a blank picture?)")]
    Uniform(u8),
    /// A shape too small to have a contour.
    #[error("the largest shape has {0} pixel(s): too small to trace")]
    TooSmall(usize),
}

/// Otsu's threshold of a histogram: the level maximising the between-class
/// variance (pixels `≤ t` on one side).
pub fn otsu(histogram: &[u64; 256]) -> u8 {
    let total: u64 = histogram.iter().sum();
    let sum: f64 = histogram.iter().enumerate().map(|(i, &h)| i as f64 * h as f64).sum();
    let (mut below, mut sum_below, mut best, mut level) = (0u64, 0.0, -1.0, 0u8);
    for (t, &h) in histogram.iter().enumerate() {
        below += h;
        sum_below += t as f64 * h as f64;
        let above = total - below;
        if below == 0 || above == 0 {
            continue;
        }
        let (m0, m1) = (sum_below / below as f64, (sum - sum_below) / above as f64);
        let between = below as f64 * above as f64 * (m0 - m1) * (m0 - m1);
        if between > best {
            best = between;
            level = t as u8;
        }
    }
    level
}

/// Fits the outer contour of the largest shape of a grey picture
/// (`width × height`, row by row, 0 black), in pixels: pixel `(c, r)`'s
/// centre at `(c, r)`, the picture's top-left corner at `(−0.5, −0.5)`, y
/// down; the contour runs along the shape's edge, half a pixel outside the
/// centres of its border pixels.
///
/// # Errors
/// An empty or uniform picture, or a shape of fewer than 3 pixels.
pub fn fit_contour(grey: &[u8], width: usize, height: usize, settings: &FitSettings) -> Result<Fit, FitError> {
    if width == 0 || height == 0 || grey.len() < width * height {
        return Err(FitError::Empty);
    }
    let mut histogram = [0u64; 256];
    grey.iter().for_each(|&g| histogram[g as usize] += 1);
    let threshold = settings.threshold.unwrap_or_else(|| otsu(&histogram));
    let dark: Vec<bool> = grey.iter().map(|&g| g <= threshold).collect();
    let count = dark.iter().filter(|&&d| d).count();
    if count == 0 || count == dark.len() {
        return Err(FitError::Uniform(threshold));
    }
    // The shape is the side that covers less of the border.
    let border = (0..width)
        .flat_map(|x| [x, (height - 1) * width + x])
        .chain((0..height).flat_map(|y| [y * width, y * width + width - 1]));
    let (mut dark_border, mut all_border) = (0usize, 0usize);
    for i in border {
        all_border += 1;
        dark_border += usize::from(dark[i]);
    }
    let shape_is_dark = 2 * dark_border <= all_border;
    let inside: Vec<bool> = dark.iter().map(|&d| d == shape_is_dark).collect();
    let (largest, components) = largest_component(&inside, width, height);
    if largest.len() < 3 {
        return Err(FitError::TooSmall(largest.len()));
    }
    let mut mask = vec![false; width * height];
    largest.iter().for_each(|&i| mask[i] = true);
    let contour = trace(&mask, width, height, largest.iter().copied().min().unwrap_or(0));
    let corner_index = corners(&contour, &settings.ipan);
    let (segments, max_distance, cut_corners) = fit_pieces(&contour, &corner_index, settings.tolerance);
    if segments.is_empty() {
        return Err(FitError::TooSmall(largest.len()));
    }
    Ok(Fit {
        threshold,
        components,
        corners: corner_index.iter().map(|&i| contour[i]).collect(),
        contour,
        segments,
        max_distance,
        cut_corners,
    })
}

/// The largest 8-connected component of `inside` (pixel indices) and the number of components.
fn largest_component(inside: &[bool], w: usize, h: usize) -> (Vec<usize>, usize) {
    let mut label = vec![false; inside.len()];
    let (mut best, mut components) = (Vec::new(), 0);
    let mut stack = Vec::new();
    for start in 0..inside.len() {
        if !inside[start] || label[start] {
            continue;
        }
        components += 1;
        let mut pixels = Vec::new();
        label[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            pixels.push(i);
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for (dx, dy) in NEIGHBOURS {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if inside[j] && !label[j] {
                    label[j] = true;
                    stack.push(j);
                }
            }
        }
        if pixels.len() > best.len() {
            best = pixels;
        }
    }
    (best, components)
}

/// The eight neighbours, clockwise on screen from the east (y down).
const NEIGHBOURS: [(i64, i64); 8] = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)];

/// The outer boundary of `mask` (8-connected) as the cracks between its
/// pixels and the outside, from the top edge of its first pixel in row order
/// (`start`): the midpoint of each crack (pixel centres at integer
/// coordinates), counter-clockwise on screen. The cracks lie on the shape's
/// edge as the picture draws it; pixel centres lie half a pixel inside it, so
/// that two edges meeting in a sharp notch, fitted through centres, crossed
/// more than a pixel from the notch (a 10-pointed star's notches were split
/// into extra pieces to stay within one pixel).
fn trace(mask: &[bool], w: usize, h: usize, start: usize) -> Vec<[f64; 2]> {
    /// East, south, west, north: clockwise on screen (y down).
    const STEPS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
    let inside =
        |(x, y): (i64, i64)| x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && mask[y as usize * w + x as usize];
    // The crack from pixel corner `v` (the top-left corner of pixel `v`) one step along `d`: the
    // pixels on its right and on its left; it bounds the shape when the right one is inside and the
    // left one is not (the walk keeps the shape on its right: clockwise on screen).
    let sides = |(x, y): (i64, i64), d: usize| match d {
        0 => ((x, y), (x, y - 1)),
        1 => ((x - 1, y), (x, y)),
        2 => ((x - 1, y - 1), (x - 1, y)),
        _ => ((x, y - 1), (x - 1, y - 1)),
    };
    let bounds = |v, d| {
        let (right, left) = sides(v, d);
        inside(right) && !inside(left)
    };
    let first = ((start % w) as i64, (start / w) as i64);
    let (mut v, mut d) = (first, 0usize);
    let mut out = Vec::new();
    let limit = 4 * w * h + 4;
    while out.len() < limit {
        let (dx, dy) = STEPS[d];
        out.push([v.0 as f64 - 0.5 + 0.5 * dx as f64, v.1 as f64 - 0.5 + 0.5 * dy as f64]);
        v = (v.0 + dx, v.1 + dy);
        // Left first: two pixels touching at a corner are one shape (8-connected).
        let Some(next) = [3, 0, 1, 2].into_iter().map(|turn| (d + turn) % 4).find(|&n| bounds(v, n)) else {
            break;
        };
        if v == first && next == 0 {
            break;
        }
        d = next;
    }
    out.reverse();
    out
}

/// IPAN99 on a closed contour: the indices of the corners, in order.
fn corners(c: &[[f64; 2]], ipan: &Ipan) -> Vec<usize> {
    let n = c.len();
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let cos_max = ipan.alpha_max.to_radians().cos();
    let reach = (ipan.d_max.ceil() as usize + 2).min(n / 2);
    // Sharpness π − α of the sharpest admissible triangle, or 0.
    let mut sharp = vec![0.0f64; n];
    for i in 0..n {
        let p = c[i];
        let mut best: Option<f64> = None;
        for k in 1..=reach {
            let pm = c[(i + n - k) % n];
            let dm = d(p, pm);
            if dm < ipan.d_min {
                continue;
            }
            if dm > ipan.d_max {
                break;
            }
            for l in 1..=reach {
                let pp = c[(i + l) % n];
                let dp = d(p, pp);
                if dp < ipan.d_min {
                    continue;
                }
                if dp > ipan.d_max {
                    break;
                }
                let cos = ((pm[0] - p[0]) * (pp[0] - p[0]) + (pm[1] - p[1]) * (pp[1] - p[1])) / (dm * dp);
                if cos >= cos_max {
                    // The opening angle is at most α_max; the smallest angle is the sharpest.
                    let alpha = cos.clamp(-1.0, 1.0).acos();
                    best = Some(best.map_or(alpha, |b: f64| b.min(alpha)));
                }
            }
        }
        if let Some(alpha) = best {
            sharp[i] = std::f64::consts::PI - alpha;
        }
    }
    // Non-maximum suppression within d_max along the contour.
    (0..n)
        .filter(|&i| {
            sharp[i] > 0.0
                && (1..=reach).all(|k| {
                    let (a, b) = ((i + n - k) % n, (i + k) % n);
                    let near = |j: usize| d(c[i], c[j]) <= ipan.d_max;
                    (!near(a) || sharp[a] < sharp[i] || sharp[a] == sharp[i] && a > i)
                        && (!near(b) || sharp[b] < sharp[i] || sharp[b] == sharp[i] && b > i)
                })
        })
        .collect()
}

/// Distance from `p` to the segment `a b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (vx, vy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = vx * vx + vy * vy;
    let t = if len2 > 0.0 { (((p[0] - a[0]) * vx + (p[1] - a[1]) * vy) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p[0] - a[0] - t * vx).hypot(p[1] - a[1] - t * vy)
}

/// Distance from `p` to a piece (an arc by its polyline of 64 chords, then refined near the best).
fn to_piece(p: [f64; 2], s: &Segment) -> f64 {
    if !s.is_arc() {
        return to_segment(p, s.start(), s.end());
    }
    const N: usize = 64;
    let (mut best, mut at) = (f64::INFINITY, 0);
    for k in 0..N {
        let dd = to_segment(p, s.at(k as f64 / N as f64), s.at((k + 1) as f64 / N as f64));
        if dd < best {
            best = dd;
            at = k;
        }
    }
    // A finer look at the best chord's neighbourhood.
    let (lo, hi) = (at.saturating_sub(1) as f64 / N as f64, ((at + 2).min(N)) as f64 / N as f64);
    (0..32)
        .map(|j| {
            let (u0, u1) = (lo + (hi - lo) * j as f64 / 32.0, lo + (hi - lo) * (j + 1) as f64 / 32.0);
            to_segment(p, s.at(u0), s.at(u1))
        })
        .fold(best, f64::min)
}

/// Whether a distance is within the tolerance, allowing the rounding of
/// distances computed from pixel centres (a chord one pixel off computes as
/// 1.0000000000000284).
fn within(distance: f64, tolerance: f64) -> bool {
    distance <= tolerance * (1.0 + ROUNDING) + ROUNDING
}

/// Distance from `p` to the polyline through `run`.
fn to_polyline(p: [f64; 2], run: &[[f64; 2]]) -> f64 {
    match run {
        [] => f64::INFINITY,
        [a] => (p[0] - a[0]).hypot(p[1] - a[1]),
        _ => run.windows(2).map(|w| to_segment(p, w[0], w[1])).fold(f64::INFINITY, f64::min),
    }
}

/// Points of a piece every quarter pixel or closer (at least 16): what the
/// piece draws, measured against the traced contour.
fn samples(s: &Segment) -> impl Iterator<Item = [f64; 2]> + '_ {
    let length = s.points.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum::<f64>();
    let k = ((4.0 * length).ceil() as usize).clamp(16, 1 << 16);
    (0..=k).map(move |j| s.at(j as f64 / k as f64))
}

/// The Hausdorff distance between a piece and the traced run it stands for:
/// every traced point is within it of the piece, and every point of the
/// piece within it of the traced polyline (an arc that overshoots is as
/// wrong as one that falls short).
fn hausdorff(s: &Segment, run: &[[f64; 2]]) -> f64 {
    hausdorff_cut(s, run, [0.0; 2])
}

/// [`hausdorff`], where the piece and the run within `cut[0]` of its start and `cut[1]` of its
/// end are not held to each other: a corner the picture cut off or filled in (see [`tip_cut`]).
fn hausdorff_cut(s: &Segment, run: &[[f64; 2]], cut: [f64; 2]) -> f64 {
    let (a, b) = (s.start(), s.end());
    let near = |q: [f64; 2], e: [f64; 2], c: f64| c > 0.0 && (q[0] - e[0]).hypot(q[1] - e[1]) < c;
    let held = |q: &[f64; 2]| !near(*q, a, cut[0]) && !near(*q, b, cut[1]);
    let to = run.iter().filter(|p| held(p)).map(|&p| to_piece(p, s)).fold(0.0, f64::max);
    samples(s).filter(held).map(|q| to_polyline(q, run)).fold(to, f64::max)
}

/// How far a corner of opening angle `angle` (radians) is not drawn as two
/// edges: a spike is drawn only where it is at least a pixel wide, and as a
/// chain of single pixels where it is less than two, that is within
/// `1 / tan(angle / 2)` of where its edges meet (5.7 pixels for a spike of
/// 20°, 1 for a right angle); plus half a pixel (the cracks' steps). A notch
/// as sharp is filled in as far.
fn tip_cut(angle: f64) -> f64 {
    1.0 / (0.5 * angle).tan().max(1e-3) + 0.5
}

/// The total-least-squares line of `points`: a point on it, its unit
/// direction, and the largest distance of a point from it.
fn best_line(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2], f64) {
    let n = points.len() as f64;
    let c = [0, 1].map(|k| points.iter().map(|p| p[k]).sum::<f64>() / n);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let (x, y) = (p[0] - c[0], p[1] - c[1]);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let d = [angle.cos(), angle.sin()];
    let dev = points.iter().map(|p| ((p[0] - c[0]) * d[1] - (p[1] - c[1]) * d[0]).abs()).fold(0.0, f64::max);
    (c, d, dev)
}

/// The best piece through `points[0]` and `points[last]`: a line when the
/// points are straight within `tolerance` (their best line; the ends are
/// moved onto it later), else the least-squares quadratic Bézier
/// (chord-length parameters, refined by projection); its worst distance.
/// `strict`: a line only when its chord is within the tolerance.
fn fit_one(points: &[[f64; 2]], tolerance: f64, strict: bool) -> (Segment, f64) {
    let (a, b) = (points[0], points[points.len() - 1]);
    let line = Segment { points: vec![a, b] };
    let worst = |s: &Segment| hausdorff(s, points);
    // Straightness by the best line, also without the corner pixel at either end (it lies
    // inside a sharp corner, off both edges; the joints move to where best lines cross).
    let n = points.len();
    let trims: &[(usize, usize)] = if n >= 6 { &[(0, 0), (1, 0), (0, 1), (1, 1)] } else { &[(0, 0)] };
    let straight = trims.iter().map(|&(a, b)| best_line(&points[a..n - b]).2).fold(f64::INFINITY, f64::min);
    let line_error = worst(&line);
    if within(line_error, tolerance) || points.len() < 4 {
        return (line, line_error);
    }
    if within(straight, tolerance) {
        // Straight: accepted by its best line's deviation (measured again once the ends move onto
        // it); when that chord is still off (`strict`), a straight run is split into lines, not bent.
        return (line, if strict { line_error } else { straight });
    }
    // Chord-length parameters.
    let mut t: Vec<f64> = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    t.push(0.0);
    for w in points.windows(2) {
        acc += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        t.push(acc);
    }
    t.iter_mut().for_each(|x| *x /= acc.max(1e-300));
    let mut arc = line.clone();
    for _ in 0..6 {
        // P1 minimising Σ |B(tᵢ) − qᵢ|² with the ends fixed.
        let (mut num, mut den) = ([0.0; 2], 0.0);
        for (q, &u) in points.iter().zip(&t) {
            let (b0, b1, b2) = ((1.0 - u) * (1.0 - u), 2.0 * u * (1.0 - u), u * u);
            for k in 0..2 {
                num[k] += b1 * (q[k] - b0 * a[k] - b2 * b[k]);
            }
            den += b1 * b1;
        }
        if den <= 0.0 {
            break;
        }
        arc = Segment { points: vec![a, [num[0] / den, num[1] / den], b] };
        // Reparameterise: one Newton step of each point's projection on the arc.
        for (q, u) in points.iter().zip(t.iter_mut()) {
            let p = &arc.points;
            let d1 = [0, 1].map(|k| 2.0 * ((1.0 - *u) * (p[1][k] - p[0][k]) + *u * (p[2][k] - p[1][k])));
            let d2 = [0, 1].map(|k| 2.0 * (p[2][k] - 2.0 * p[1][k] + p[0][k]));
            let at = arc.at(*u);
            let r = [at[0] - q[0], at[1] - q[1]];
            let f = r[0] * d1[0] + r[1] * d1[1];
            let df = d1[0] * d1[0] + d1[1] * d1[1] + r[0] * d2[0] + r[1] * d2[1];
            if df.abs() > DEGENERATE {
                *u = (*u - f / df).clamp(0.0, 1.0);
            }
        }
    }
    let arc_error = worst(&arc);
    if arc_error < line_error { (arc, arc_error) } else { (line, line_error) }
}

/// Fits the closed contour piece by piece between corners (four equally
/// spaced cuts when there is none), splitting a piece at its worst point
/// while it is off by more than `tolerance`; then every joint between two
/// line segments moves to the intersection of their best lines (a corner
/// pixel lies inside a sharp corner), and the distances are measured again.
fn fit_pieces(contour: &[[f64; 2]], corners: &[usize], tolerance: f64) -> FittedPieces {
    let n = contour.len();
    let cuts: Vec<usize> = if corners.len() >= 2 {
        corners.to_vec()
    } else {
        let first = corners.first().copied().unwrap_or(0);
        (0..4).map(|k| (first + k * n / 4) % n).collect()
    };
    let mut pieces: Vec<(Segment, Vec<[f64; 2]>)> = Vec::new();
    for (k, &from) in cuts.iter().enumerate() {
        let to = cuts[(k + 1) % cuts.len()];
        let len = (to + n - from) % n;
        let len = if len == 0 { n } else { len };
        let run: Vec<[f64; 2]> = (0..=len).map(|j| contour[(from + j) % n]).collect();
        fit_run(&run, tolerance, &mut pieces, 0, false);
    }
    // Every joint between two line segments moves at once to where their best lines cross;
    // a piece that ends up off by more than the tolerance (and worse than before) gets its
    // joints back, until none does. Beyond a sharp corner's last pixels (a spike the picture
    // cut off) the moved joint is not held to them: its tip's reach is the joint's cut.
    let m = pieces.len();
    let original: Vec<Segment> = pieces.iter().map(|(s, _)| s.clone()).collect();
    let mut moved: Vec<Option<([f64; 2], f64)>> = (0..m).map(|k| moved_joint(&pieces, k, tolerance)).collect();
    let cuts = |moved: &[Option<([f64; 2], f64)>], k: usize| {
        [moved[(k + m - 1) % m].filter(|_| m > 1).map_or(0.0, |j| j.1), moved[k].map_or(0.0, |j| j.1)]
    };
    for _ in 0..m + 1 {
        for k in 0..m {
            let mut s = original[k].clone();
            if let Some((x, _)) = moved[(k + m - 1) % m].filter(|_| m > 1) {
                s.points[0] = x;
            }
            if let Some((x, _)) = moved[k] {
                *s.points.last_mut().expect("a piece has points") = x;
            }
            pieces[k].0 = s;
        }
        let bad: Vec<usize> = (0..m)
            .filter(|&k| !within(hausdorff_cut(&pieces[k].0, &pieces[k].1, cuts(&moved, k)), tolerance))
            .collect();
        if bad.iter().all(|&k| moved[k].is_none() && moved[(k + m - 1) % m].is_none()) {
            break;
        }
        for k in bad {
            moved[k] = None;
            moved[(k + m - 1) % m] = None;
        }
    }
    // A line accepted for its straightness whose chord (between corner pixels) is still off:
    // fitted again with the chord as the measure, which may split it.
    let mut out: Vec<(Segment, Vec<[f64; 2]>, [f64; 2])> = Vec::with_capacity(pieces.len());
    for (k, (s, run)) in pieces.into_iter().enumerate() {
        let cut = cuts(&moved, k);
        if !within(hausdorff_cut(&s, &run, cut), tolerance) && !s.is_arc() {
            let mut refit = Vec::new();
            fit_run(&run, tolerance, &mut refit, 0, true);
            out.extend(refit.into_iter().map(|(s, run)| (s, run, [0.0; 2])));
        } else {
            out.push((s, run, cut));
        }
    }
    // A piece of no length (a one-pixel spur) is left out: its neighbours meet there already.
    out.retain(|(s, _, _)| s.is_arc() || s.start() != s.end());
    let worst = out.iter().map(|(s, run, cut)| hausdorff_cut(s, run, *cut)).fold(0.0, f64::max);
    let cut_corners = out.iter().filter(|(_, _, cut)| cut[1] > 0.0).map(|(s, _, cut)| (s.end(), cut[1])).collect();
    (out.into_iter().map(|(s, _, _)| s).collect(), worst, cut_corners)
}

/// Where the joint after piece `k` moves (where the best lines of two line
/// pieces cross, unless they are nearly parallel or it would move too far)
/// and the cut of the corner's tip there.
fn moved_joint(pieces: &[(Segment, Vec<[f64; 2]>)], k: usize, tolerance: f64) -> Option<([f64; 2], f64)> {
    let m = pieces.len();
    let next = (k + 1) % m;
    if m < 2 || pieces[k].0.is_arc() || pieces[next].0.is_arc() {
        return None;
    }
    let ((c1, d1, _), (c2, d2, _)) = (best_line(&pieces[k].1), best_line(&pieces[next].1));
    let det = d1[0] * d2[1] - d1[1] * d2[0];
    if det.abs() < 0.05 {
        return None; // nearly parallel: keep the joint
    }
    let t = ((c2[0] - c1[0]) * d2[1] - (c2[1] - c1[1]) * d2[0]) / det;
    let x = [c1[0] + t * d1[0], c1[1] + t * d1[1]];
    // The corner's opening: between the directions from the joint to the pieces' far ends.
    let (from, to) = (pieces[k].0.start(), pieces[next].0.end());
    let (u, v) = ([from[0] - x[0], from[1] - x[1]], [to[0] - x[0], to[1] - x[1]]);
    let cos = (u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1])).max(1e-300);
    let cut = tip_cut(cos.clamp(-1.0, 1.0).acos());
    let joint = pieces[k].0.end();
    ((x[0] - joint[0]).hypot(x[1] - joint[1]) <= (3.0 * tolerance.max(1.0)).max(cut + tolerance)).then_some((x, cut))
}

/// The pieces, their largest distance, the cut corners (see [`Fit::cut_corners`]).
type FittedPieces = (Vec<Segment>, f64, Vec<([f64; 2], f64)>);

/// Smallest turn, degrees, between two straight halves of a run for them to
/// be a corner the detector missed rather than a gentle arc.
const MISSED_CORNER_DEG: f64 = 20.0;

fn fit_run(run: &[[f64; 2]], tolerance: f64, out: &mut Vec<(Segment, Vec<[f64; 2]>)>, depth: usize, strict: bool) {
    let (piece, error) = fit_one(run, tolerance, strict);
    // Split at the point farthest from the chord (a natural knot), or the middle.
    let (a, b) = (run[0], run[run.len() - 1]);
    let far = (1..run.len() - 1).max_by(|&i, &j| to_segment(run[i], a, b).total_cmp(&to_segment(run[j], a, b)));
    let mid = far.filter(|&i| i >= 2 && i + 2 < run.len()).unwrap_or(run.len() / 2);
    if within(error, tolerance) && piece.is_arc() && run.len() >= 8 {
        // An arc over a corner the detector missed (or placed a pixel or two off, leaving a
        // hook at an end): two straight parts that turn there are its edges.
        let knee = far.unwrap_or(mid);
        let (left, right) = (&run[..=knee], &run[knee..]);
        let ((_, d1, s1), (_, d2, s2)) = (best_line(left), best_line(right));
        let turn = (d1[0] * d2[1] - d1[1] * d2[0]).abs().asin().to_degrees();
        if s1 <= tolerance && s2 <= tolerance && turn >= MISSED_CORNER_DEG {
            fit_run(left, tolerance, out, depth + 1, strict);
            fit_run(right, tolerance, out, depth + 1, strict);
            return;
        }
    }
    if within(error, tolerance) || run.len() < 3 || depth > 30 {
        out.push((piece, run.to_vec()));
        return;
    }
    fit_run(&run[..=mid], tolerance, out, depth + 1, strict);
    fit_run(&run[mid..], tolerance, out, depth + 1, strict);
}
