//! The holes of a solid (a union of volume cells, evaluated as its outward
//! boundary mesh): its volume by the divergence theorem, and its cells
//! drawn into a grid of voxels for the gliding-box lacunarity in space.

use crate::geometry::{Shape, fan};

/// Voxels per side of the grid a solid's lacunarity is measured on.
pub(super) const GRID: usize = 81;

/// The outward triangles of a shape's faces.
fn triangles(shape: &Shape) -> impl Iterator<Item = [[f64; 3]; 3]> + '_ {
    let quads = shape.quads.iter().flat_map(|q| fan(&q.map(|v| v as usize), 0).collect::<Vec<_>>());
    quads.chain(shape.triangles.iter().copied()).map(|t| t.map(|v| shape.point(v)))
}

/// The volume a closed outward mesh encloses: `Σ a · (b × c) / 6`.
pub(super) fn volume(shape: &Shape) -> f64 {
    triangles(shape)
        .map(|[a, b, c]| {
            a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum::<f64>()
        / 6.0
}

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

/// The voxels (of a [`GRID`]³ grid over the bounding box, x fastest) whose
/// sample point ([`sample`]: one vertical line per column, a height per
/// voxel) lies inside the solid: an odd number of the boundary's crossings
/// of the line below it.
pub(super) fn voxels(shape: &Shape) -> (usize, Vec<bool>) {
    let n = GRID;
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for i in 0..shape.vertex_count() {
        let p = shape.point(i);
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let span = |k: usize| (hi[k] - lo[k]).max(f64::MIN_POSITIVE);
    let at = |p: [f64; 3]| [0, 1, 2].map(|k| (p[k] - lo[k]) / span(k) * n as f64);
    // Each column's vertical line (through its samples' x and y), and the heights it crosses the boundary at.
    let line = |x: usize, y: usize| {
        let s = sample(x, y, 0);
        [x as f64 + s[0], y as f64 + s[1]]
    };
    let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); n * n];
    for t in triangles(shape) {
        let [a, b, c] = t.map(at);
        let (x0, x1) = (a[0].min(b[0]).min(c[0]), a[0].max(b[0]).max(c[0]));
        let (y0, y1) = (a[1].min(b[1]).min(c[1]), a[1].max(b[1]).max(c[1]));
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if det.abs() < 1e-15 {
            continue; // seen edge-on from the lines
        }
        let cells =
            |v0: f64, v1: f64| (v0.floor().max(0.0) as usize)..=(v1.floor().min(n as f64 - 1.0).max(0.0) as usize);
        for y in cells(y0, y1) {
            for x in cells(x0, x1) {
                let [px, py] = line(x, y);
                let u = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / det;
                let v = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / det;
                if u >= 0.0 && v >= 0.0 && u + v < 1.0 {
                    crossings[y * n + x].push(a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]));
                }
            }
        }
    }
    let mut cells = vec![false; n * n * n];
    for (column, heights) in crossings.iter_mut().enumerate() {
        heights.sort_by(f64::total_cmp);
        let (x, y) = (column % n, column / n);
        for z in 0..n {
            let height = z as f64 + sample(x, y, z)[2];
            cells[z * n * n + column] = heights.partition_point(|&h| h < height) % 2 == 1;
        }
    }
    (n, cells)
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
