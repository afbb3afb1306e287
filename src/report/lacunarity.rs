//! Porosity and lacunarity of a design's attractor (issue 44 §5): how much
//! of the cell its depth-k cells leave empty, and how those holes are
//! distributed — the gliding-box lacunarity curve `Λ(r)` of Allain and
//! Cloitre (1991) on the depth-k cells drawn into a grid.

use super::error::ReportError;
use crate::design::Design;
use crate::family::instantiate;
use crate::geometry::{Shape, fan};

/// What the holes of a design's attractor are.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LacunarityReport {
    /// The dimension measured: 3 (volumes: volume), 2 (faces: area), 1 (curves: length).
    pub dimension: usize,
    /// Per depth from 1: the fraction of the depth-0 cell's measure (area or length) that the
    /// depth-k cells leave empty (`1 − (8/9)^k` for the carpet, `1 − (2/3)^k` for the Cantor set).
    pub porosity: Vec<f64>,
    /// The grid's cells per side the lacunarity is measured on (the cells at the deepest depth drawn into it).
    pub grid: usize,
    /// Pairs `[r, Λ(r)]`: box side `r` in grid cells, `Λ = E[M²] / E[M]²` over every position of
    /// an `r`-box (`M` the occupied cells it holds); `Λ(1)` is one over the filled fraction and
    /// `Λ` falls to 1 at the grid's side.
    pub lacunarity: Vec<[f64; 2]>,
}

/// The depth a lacunarity report goes to unless asked: 5, or 4 for a solid
/// (its depth-5 cells are 20⁵ for the Menger sponge).
pub fn lacunarity_depth(design: &Design) -> usize {
    let solid = || -> Option<bool> {
        let instance = instantiate(design, &[]).ok()?;
        let model = super::error::model_of(design).ok()?;
        let ev = crate::eval::Evaluator::new(&instance.automaton, &model, crate::eval::EvalSettings::default()).ok()?;
        Some(ev.volumes())
    };
    if solid().unwrap_or(false) { 4 } else { 5 }
}

/// The porosity of `design` at depths 1 to `depth` and its lacunarity curve at `depth`.
///
/// ```
/// let cantor = bcifs::builtin_design("cantor").unwrap();
/// let l = bcifs::report::lacunarity_report(&cantor, &[], 3)?;
/// assert!((l.porosity[2] - (1.0 - (2.0f64 / 3.0).powi(3))).abs() < 1e-12);
/// # Ok::<(), bcifs::report::ReportError>(())
/// ```
///
/// # Errors
/// No model, parameters, evaluation; a design whose cells are points (no measure).
pub fn lacunarity_report(
    design: &Design,
    params: &[(String, f64)],
    depth: usize,
) -> Result<LacunarityReport, ReportError> {
    let (dimension, porosity, deepest) = porosities(design, params, depth, true)?;
    if dimension == 3 {
        // Solids' cells drawn into voxels straight (no boundary mesh).
        let instance = instantiate(design, params)?;
        let model = super::error::model_of(design)?;
        let settings = crate::eval::EvalSettings::default().with_depth(depth.max(1));
        let ev = crate::eval::Evaluator::new(&instance.automaton, &model, settings)?;
        let (grid, occupied) = super::solid_holes::voxels(&ev, depth.max(1))?;
        let lacunarity = super::solid_holes::gliding_box(&occupied, grid);
        return Ok(LacunarityReport { dimension, porosity, grid, lacunarity });
    }
    let deepest = deepest.unwrap_or_default();
    let (grid, occupied) = raster(&deepest, dimension);
    Ok(LacunarityReport { dimension, porosity, grid, lacunarity: gliding_box(&occupied, grid, dimension) })
}

/// The porosity of `design` at depths 1 to `depth`: [`lacunarity_report`]'s
/// `porosity`, without the lacunarity curve (what a fit measures, many times).
///
/// ```
/// let carpet = bcifs::builtin_design("menger").unwrap();
/// let p = bcifs::report::porosity(&carpet, &[], 2)?;
/// assert!((p[1] - (1.0 - (20.0f64 / 27.0).powi(2))).abs() < 1e-12);
/// # Ok::<(), bcifs::report::ReportError>(())
/// ```
///
/// # Errors
/// As [`lacunarity_report`].
pub fn porosity(design: &Design, params: &[(String, f64)], depth: usize) -> Result<Vec<f64>, ReportError> {
    Ok(porosities(design, params, depth, false)?.1)
}

/// The measure's dimension, the porosity at depths 1 to `depth`, and (when
/// `deepest`) the depth-`depth` cells evaluated.
fn porosities(
    design: &Design,
    params: &[(String, f64)],
    depth: usize,
    deepest: bool,
) -> Result<(usize, Vec<f64>, Option<Shape>), ReportError> {
    use crate::eval::{EvalSettings, Evaluator};
    let instance = instantiate(design, params)?;
    let model = super::error::model_of(design)?;
    let evaluator = |k: usize| Evaluator::new(&instance.automaton, &model, EvalSettings::default().with_depth(k));
    let ev = evaluator(depth.max(1))?;
    // The deepest depth decides what fits: refused before the shallower ones are made.
    let limit = EvalSettings::default().memory_limit;
    let estimate = ev.estimate_bytes(depth.max(1));
    if deepest && estimate > limit as u128 {
        return Err(crate::eval::EvalError::TooLarge { estimate, limit }.into());
    }
    // The cells measured on their own patches, summed at each depth.
    let d = ev.pieces().dim;
    let measured = |k: usize| -> Result<(usize, f64), ReportError> {
        let (mut dimension, mut total, mut why) = (0, 0.0, None);
        ev.for_each_cell(k, &mut |sp, c| {
            match super::measure::cell_measure(sp, c, d) {
                Ok(m) => total += m,
                Err(e) => why = Some(e),
            }
            dimension = dimension.max(match sp.kind {
                crate::space::CellKind::Edge => 1,
                crate::space::CellKind::Face => 2,
                _ => 3,
            });
            Ok(())
        })?;
        match why {
            Some(why) => Err(ReportError::Unsupported(why)),
            None => Ok((dimension, total)),
        }
    };
    let (dimension, whole) = measured(0)?;
    if dimension == 0 || whole <= 0.0 {
        return Err(ReportError::Unsupported(
            "its cells are points, with no length, area or volume to leave empty".into(),
        ));
    }
    let mut porosity = Vec::new();
    for k in 1..=depth.max(1) {
        let share = 1.0 - measured(k)?.1 / whole;
        // Parts that are parts of their cell leave a share of it in [0, 1], to rounding.
        if share < -crate::algebra::tolerance::SLACK {
            return Err(ReportError::Unsupported(format!(
                "its depth-{k} cells measure {:.6} times their cell (a porosity of {share:.4}): they are not parts of it \
                 (a curve bending away from its chord, a patch folded over), so they leave no share of it empty",
                1.0 - share
            )));
        }
        porosity.push(share.max(0.0));
    }
    let shape = if deepest && dimension < 3 { Some(evaluator(depth.max(1))?.evaluate()?) } else { None };
    Ok((dimension, porosity, shape))
}

fn faces(shape: &Shape) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = shape.quads.iter().map(|q| q.iter().map(|&v| v as usize).collect()).collect();
    out.extend(shape.triangles.iter().map(|t| t.to_vec()));
    out
}

fn segments(shape: &Shape) -> Vec<[usize; 2]> {
    shape
        .polylines()
        .flat_map(|(first, count, _)| (first..first + count.saturating_sub(1)).map(|i| [i, i + 1]))
        .collect()
}

/// Cells per side of the lacunarity grid.
const GRID: usize = 243;

/// The cells drawn into a grid over the two (or one) largest axes of their
/// bounding box: a grid cell is occupied when its centre lies in a face
/// (or a segment passes through it).
fn raster(shape: &Shape, dimension: usize) -> (usize, Vec<bool>) {
    let n = shape.vertex_count();
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for i in 0..n {
        let p = shape.point(i);
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| (hi[b] - lo[b]).total_cmp(&(hi[a] - lo[a])));
    let (ax, ay) = (axes[0], axes[1]);
    let span = |k: usize| (hi[k] - lo[k]).max(f64::MIN_POSITIVE);
    let at = |p: [f64; 3]| [(p[ax] - lo[ax]) / span(ax) * GRID as f64, (p[ay] - lo[ay]) / span(ay) * GRID as f64];
    if dimension == 1 {
        let mut cells = vec![false; GRID];
        for [a, b] in segments(shape) {
            let (x0, x1) = (at(shape.point(a))[0], at(shape.point(b))[0]);
            let (from, to) = (x0.min(x1), x0.max(x1));
            // The cells whose centres the segment covers.
            let first = (from - 0.5).ceil().max(0.0) as usize;
            let last = (to - 0.5).floor().min(GRID as f64 - 1.0);
            if last >= first as f64 {
                cells[first..=last as usize].iter_mut().for_each(|c| *c = true);
            }
        }
        return (GRID, cells);
    }
    let mut cells = vec![false; GRID * GRID];
    for face in faces(shape) {
        for [a, b, c] in fan(&face, 0) {
            let [pa, pb, pc] = [a, b, c].map(|v| at(shape.point(v)));
            fill_triangle(&mut cells, pa, pb, pc);
        }
    }
    (GRID, cells)
}

/// Marks the grid cells whose centres lie in the triangle (either orientation, edges included).
fn fill_triangle(cells: &mut [bool], a: [f64; 2], b: [f64; 2], c: [f64; 2]) {
    let cross = |o: [f64; 2], p: [f64; 2], q: [f64; 2]| (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    let area = cross(a, b, c);
    if area.abs() < 1e-12 {
        return;
    }
    let range = |v: [f64; 3]| {
        let lo = (v.iter().copied().fold(f64::INFINITY, f64::min) - 0.5).ceil().max(0.0) as usize;
        let hi = (v.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 0.5).floor().min(GRID as f64 - 1.0);
        (lo, hi)
    };
    let (x0, x1) = range([a[0], b[0], c[0]]);
    let (y0, y1) = range([a[1], b[1], c[1]]);
    if x1 < 0.0 || y1 < 0.0 {
        return;
    }
    let eps = 1e-9 * area.abs();
    for y in y0..=y1 as usize {
        for x in x0..=x1 as usize {
            let p = [x as f64 + 0.5, y as f64 + 0.5];
            let (w0, w1, w2) = (cross(b, c, p), cross(c, a, p), cross(a, b, p));
            let inside =
                if area > 0.0 { w0 >= -eps && w1 >= -eps && w2 >= -eps } else { w0 <= eps && w1 <= eps && w2 <= eps };
            if inside {
                cells[y * GRID + x] = true;
            }
        }
    }
}

/// `Λ(r) = E[M²] / E[M]²` over every position of an `r`-box (a square of
/// `r × r` cells, or `r` cells on a line), for `r` = 1, 3, 9, … up to the grid.
fn gliding_box(cells: &[bool], n: usize, dimension: usize) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    let mut r = 1;
    while r <= n {
        let (mut sum, mut sum2, mut boxes) = (0f64, 0f64, 0f64);
        if dimension == 1 {
            let mut m: usize = cells[..r].iter().filter(|&&c| c).count();
            for start in 0..=n - r {
                if start > 0 {
                    m = m + usize::from(cells[start + r - 1]) - usize::from(cells[start - 1]);
                }
                let mf = m as f64;
                (sum, sum2, boxes) = (sum + mf, sum2 + mf * mf, boxes + 1.0);
            }
        } else {
            // Summed-area table: each box's mass in four lookups.
            let mut table = vec![0u32; (n + 1) * (n + 1)];
            for y in 0..n {
                for x in 0..n {
                    table[(y + 1) * (n + 1) + x + 1] =
                        u32::from(cells[y * n + x]) + table[y * (n + 1) + x + 1] + table[(y + 1) * (n + 1) + x]
                            - table[y * (n + 1) + x];
                }
            }
            let at = |x: usize, y: usize| i64::from(table[y * (n + 1) + x]);
            for y in 0..=n - r {
                for x in 0..=n - r {
                    let m = (at(x + r, y + r) - at(x, y + r) - at(x + r, y) + at(x, y)) as f64;
                    (sum, sum2, boxes) = (sum + m, sum2 + m * m, boxes + 1.0);
                }
            }
        }
        if sum > 0.0 {
            out.push([r as f64, sum2 * boxes / (sum * sum)]);
        }
        r *= 3;
    }
    out
}
