//! The holes of a solid (a union of volume cells): its cells drawn into a
//! grid of voxels for the gliding-box lacunarity in space.

use crate::eval::{EvalError, Evaluator};

/// Voxels per side of the grid a solid's lacunarity is measured on.
pub(super) const GRID: usize = 81;

/// Where in voxel `(x, y, z)` the point sampling it sits (each coordinate
/// in `[0, 1)`): Roberts's low-discrepancy `R₃` sequence over the voxels,
/// so that the samples do not line up with a self-similar solid's own grid
/// (the centres of an 81-voxel grid all lie in the Menger sponge's tunnels
/// from depth 5 on, and so would any one offset repeated).
fn sample(x: usize, y: usize, z: usize) -> [f64; 3] {
    const G: f64 = 1.220_744_084_605_759_5; // the plastic-like root of g⁴ = g + 1
    let k = ((z * GRID + y) * GRID + x) as f64;
    [1.0 / G, 1.0 / (G * G), 1.0 / (G * G * G)].map(|a| (0.5 + k * a).fract())
}

/// The voxels (of a [`GRID`]³ grid over the cells' bounding box, x
/// fastest) whose sample point ([`sample`]) lies in a depth-`k` cell: on
/// the inner side of each of the cell's faces (their planes through their
/// corners' middle, turned away from the cell's centre). A cell is
/// tested against the voxels of its own box only; where the cells are the
/// grid's own (the depth-4 Menger sponge on 81³), each voxel is one cell
/// and the count is exact.
///
/// # Errors
/// Cancelled.
pub(super) fn voxels(ev: &Evaluator, k: usize) -> Result<(usize, Vec<bool>), EvalError> {
    let n = GRID;
    let d = ev.pieces().dim;
    let corners = |sp: &crate::eval::StatePlan, c: &[f64]| -> Vec<[f64; 3]> {
        sp.samples
            .iter()
            .map(|b| {
                let mut p = [0.0; 3];
                for (a, x) in p.iter_mut().enumerate().take(d) {
                    *x = (0..sp.dim).map(|i| c[a * sp.dim + i] * b[i]).sum();
                }
                p
            })
            .collect()
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    ev.for_each_cell(k, &mut |sp, c| {
        for p in corners(sp, c) {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        Ok(())
    })?;
    let span = [0, 1, 2].map(|a| (hi[a] - lo[a]).max(f64::MIN_POSITIVE));
    let mut occupied = vec![false; n * n * n];
    ev.for_each_cell(k, &mut |sp, c| {
        let ps: Vec<[f64; 3]> =
            corners(sp, c).iter().map(|p| [0, 1, 2].map(|a| (p[a] - lo[a]) / span[a] * n as f64)).collect();
        let centre = [0, 1, 2].map(|a| ps.iter().map(|p| p[a]).sum::<f64>() / ps.len() as f64);
        // Each face's plane: (its middle, its normal turned outward).
        let planes: Vec<([f64; 3], [f64; 3])> = sp
            .faces
            .iter()
            .map(|f| {
                let mid = [0, 1, 2].map(|a| f.iter().map(|&i| ps[i][a]).sum::<f64>() / f.len() as f64);
                let mut normal = crate::geometry::area_vector(f.len(), |j| ps[f[j]]);
                if (0..3).map(|a| normal[a] * (mid[a] - centre[a])).sum::<f64>() < 0.0 {
                    normal = normal.map(|x| -x);
                }
                (mid, normal)
            })
            .collect();
        let range = |a: usize| {
            let (l, h) = ps.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[a]), h.max(p[a])));
            (l.floor().max(0.0) as usize)..=(h.floor().min(n as f64 - 1.0).max(0.0) as usize)
        };
        for z in range(2) {
            for y in range(1) {
                for x in range(0) {
                    let s = sample(x, y, z);
                    let p = [x as f64 + s[0], y as f64 + s[1], z as f64 + s[2]];
                    let inside = planes.iter().all(|(m, nv)| (0..3).map(|a| (p[a] - m[a]) * nv[a]).sum::<f64>() <= 0.0);
                    if inside {
                        occupied[(z * n + y) * n + x] = true;
                    }
                }
            }
        }
        Ok(())
    })?;
    Ok((n, occupied))
}

/// `Λ(r) = E[M²] / E[M]²` over every position of an `r × r × r` box of
/// voxels, for `r` = 1, 3, 9, … up to the grid (a summed-volume table gives
/// each box's mass in eight lookups).
pub(super) fn gliding_box(cells: &[bool], n: usize) -> Vec<[f64; 2]> {
    let m = n + 1;
    let mut table = vec![0i64; m * m * m];
    let id = |x: usize, y: usize, z: usize| (z * m + y) * m + x;
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                table[id(x + 1, y + 1, z + 1)] = i64::from(cells[(z * n + y) * n + x])
                    + table[id(x, y + 1, z + 1)]
                    + table[id(x + 1, y, z + 1)]
                    + table[id(x + 1, y + 1, z)]
                    - table[id(x, y, z + 1)]
                    - table[id(x, y + 1, z)]
                    - table[id(x + 1, y, z)]
                    + table[id(x, y, z)];
            }
        }
    }
    let mut out = Vec::new();
    let mut r = 1;
    while r <= n {
        let (mut sum, mut sum2, mut boxes) = (0f64, 0f64, 0f64);
        for z in 0..=n - r {
            for y in 0..=n - r {
                for x in 0..=n - r {
                    let (x1, y1, z1) = (x + r, y + r, z + r);
                    let mass =
                        table[id(x1, y1, z1)] - table[id(x, y1, z1)] - table[id(x1, y, z1)] - table[id(x1, y1, z)]
                            + table[id(x, y, z1)]
                            + table[id(x, y1, z)]
                            + table[id(x1, y, z)]
                            - table[id(x, y, z)];
                    let mf = mass as f64;
                    (sum, sum2, boxes) = (sum + mf, sum2 + mf * mf, boxes + 1.0);
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
