//! The smallest wall and the smallest hole of a closed mesh, as a
//! 3D-printing check measures them: from the middle of each face a ray along
//! its inward normal to the first face it meets (the wall's thickness
//! there), and one along its outward normal (the gap across a hole, a tunnel
//! or to another piece). Rays are cast through a bounding-volume hierarchy
//! of the triangles, in parallel; the least of each, with its place, is kept.

use rayon::prelude::*;

/// A length measured on a mesh and where: the middle of the face its ray starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// The length.
    pub value: f64,
    /// The middle of the face it was measured from.
    pub at: [f64; 3],
}

/// A node of the hierarchy: its box, and either two children or a run of triangles.
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// The children, or `u32::MAX` for a leaf.
    left: u32,
    right: u32,
    /// A leaf's triangles: `order[first..first + count]`.
    first: u32,
    count: u32,
}

/// Triangles in a bounding-volume hierarchy (median splits along the longest side, four a leaf).
struct Bvh<'a> {
    points: &'a [[f64; 3]],
    triangles: &'a [[usize; 3]],
    order: Vec<u32>,
    nodes: Vec<Node>,
}

impl<'a> Bvh<'a> {
    fn new(points: &'a [[f64; 3]], triangles: &'a [[usize; 3]]) -> Bvh<'a> {
        let centre: Vec<[f64; 3]> =
            triangles.iter().map(|t| [0, 1, 2].map(|a| t.iter().map(|&v| points[v][a]).sum::<f64>() / 3.0)).collect();
        let mut bvh = Bvh { points, triangles, order: (0..triangles.len() as u32).collect(), nodes: Vec::new() };
        let mut stack = vec![(0usize, triangles.len(), usize::MAX, false)];
        while let Some((first, end, parent, right)) = stack.pop() {
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &t in &bvh.order[first..end] {
                for &v in &triangles[t as usize] {
                    for a in 0..3 {
                        lo[a] = lo[a].min(points[v][a]);
                        hi[a] = hi[a].max(points[v][a]);
                    }
                }
            }
            let id = bvh.nodes.len() as u32;
            let count = (end - first) as u32;
            bvh.nodes.push(Node { lo, hi, left: u32::MAX, right: u32::MAX, first: first as u32, count });
            if parent != usize::MAX {
                if right {
                    bvh.nodes[parent].right = id;
                } else {
                    bvh.nodes[parent].left = id;
                }
            }
            if end - first > 4 {
                let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
                let mid = first + (end - first) / 2;
                bvh.order[first..end].select_nth_unstable_by(mid - first, |&x, &y| {
                    centre[x as usize][axis].total_cmp(&centre[y as usize][axis])
                });
                stack.push((first, mid, id as usize, false));
                stack.push((mid, end, id as usize, true));
            }
        }
        bvh
    }

    /// Where the ray enters the box of node `n` within `(near, far)`, if it meets it.
    fn enters(&self, n: u32, origin: [f64; 3], inv: [f64; 3], near: f64, far: f64) -> Option<f64> {
        let node = &self.nodes[n as usize];
        let (mut t0, mut t1) = (near, far);
        for a in 0..3 {
            let (p, q) = ((node.lo[a] - origin[a]) * inv[a], (node.hi[a] - origin[a]) * inv[a]);
            let (p, q) = if p <= q { (p, q) } else { (q, p) };
            // NaN (a ray in the plane of the box's side) keeps the box: max and min ignore it.
            t0 = t0.max(p);
            t1 = t1.min(q);
        }
        (t0 <= t1).then_some(t0)
    }

    /// The nearest hit of the ray `origin + t·dir` with `t` in `(near, far)`, leaving out triangle `skip`.
    fn cast(&self, origin: [f64; 3], dir: [f64; 3], near: f64, mut far: f64, skip: usize) -> Option<(f64, usize)> {
        let inv = dir.map(|x| 1.0 / x);
        let mut best = None;
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        if let Some(t) = self.enters(0, origin, inv, near, far) {
            stack.push((0, t));
        }
        while let Some((n, entry)) = stack.pop() {
            if entry > far {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.left != u32::MAX {
                let a = self.enters(node.left, origin, inv, near, far).map(|t| (node.left, t));
                let b = self.enters(node.right, origin, inv, near, far).map(|t| (node.right, t));
                // The nearer child last, so that it is searched first.
                match (a, b) {
                    (Some(a), Some(b)) if a.1 < b.1 => stack.extend([b, a]),
                    (Some(a), Some(b)) => stack.extend([a, b]),
                    (Some(x), None) | (None, Some(x)) => stack.push(x),
                    (None, None) => {}
                }
                continue;
            }
            for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                if t as usize == skip {
                    continue;
                }
                if let Some(d) = hit(self.triangles[t as usize].map(|v| self.points[v]), origin, dir)
                    && d > near
                    && d < far
                {
                    far = d;
                    best = Some((d, t as usize));
                }
            }
        }
        best
    }
}

/// What a triangle's two rays met (the wall inward, the hole outward), and where they start.
type Rays = (Option<f64>, Option<f64>, [f64; 3]);

/// Where the ray `origin + t·dir` meets the triangle `p` (Möller and Trumbore), if it does.
fn hit(p: [[f64; 3]; 3], origin: [f64; 3], dir: [f64; 3]) -> Option<f64> {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross =
        |a: [f64; 3], b: [f64; 3]| [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let h = cross(dir, e2);
    let det = dot(e1, h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = sub(origin, p[0]);
    let u = dot(s, h) / det;
    let q = cross(s, e1);
    let v = dot(dir, q) / det;
    // Inclusive edges (with rounding's room): a ray through a shared edge meets one of its faces.
    let slack = 1e-12;
    if u < -slack || v < -slack || u + v > 1.0 + slack {
        return None;
    }
    Some(dot(e2, q) / det)
}

/// The smallest wall and the smallest hole of the closed, outward
/// `triangles` over `points`: per triangle a ray from its middle along its
/// inward and its outward unit normal to the first other triangle it meets
/// (farther than 10⁻⁹ of the mesh's size), counted when that face is the
/// other side of a wall or a hole: its outward normal within 60° of the ray
/// (a wall's far side) or of its reverse (across a hole). Near an edge a ray
/// leaves through the neighbouring side, which is neither; `None`
/// where no ray meets one (a convex solid has no hole). The first `paired` triangles come in pairs
/// (the halves of quads): one ray each way per pair.
pub fn walls_and_holes(
    points: &[[f64; 3]],
    triangles: &[[usize; 3]],
    paired: usize,
) -> (Option<Measured>, Option<Measured>) {
    if triangles.is_empty() {
        return (None, None);
    }
    let bvh = Bvh::new(points, triangles);
    let root = &bvh.nodes[0];
    let size = (0..3).map(|a| root.hi[a] - root.lo[a]).fold(0.0, f64::max);
    let near = 1e-9 * size.max(f64::MIN_POSITIVE);
    let per: Vec<Rays> = triangles
        .par_iter()
        .enumerate()
        .map(|(i, t)| {
            if i < paired && i % 2 == 1 {
                return (None, None, [0.0; 3]);
            }
            let p = t.map(|v| points[v]);
            let middle = [0, 1, 2].map(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0);
            let (u, w) = ([0, 1, 2].map(|a| p[1][a] - p[0][a]), [0, 1, 2].map(|a| p[2][a] - p[0][a]));
            let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if len <= 0.0 || !len.is_finite() {
                return (None, None, middle);
            }
            let out = n.map(|x| x / len);
            // A hit counts when the face met is turned along the ray (`sign` 1: a wall's far side) or
            // back toward it (−1: across a hole).
            let facing = |(d, t): (f64, usize), dir: [f64; 3], sign: f64| {
                let q = triangles[t].map(|v| points[v]);
                let (u, w) = ([0, 1, 2].map(|a| q[1][a] - q[0][a]), [0, 1, 2].map(|a| q[2][a] - q[0][a]));
                let m = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
                let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                let cos = (m[0] * dir[0] + m[1] * dir[1] + m[2] * dir[2]) / len;
                (sign * cos > 0.5).then_some(d)
            };
            let back = out.map(|x| -x);
            let inward = bvh.cast(middle, back, near, f64::INFINITY, i).and_then(|h| facing(h, back, 1.0));
            let outward = bvh.cast(middle, out, near, f64::INFINITY, i).and_then(|h| facing(h, out, -1.0));
            (inward, outward, middle)
        })
        .collect();
    let least = |pick: fn(&Rays) -> Option<f64>| {
        per.iter()
            .filter_map(|x| pick(x).map(|v| Measured { value: v, at: x.2 }))
            .min_by(|a, b| a.value.total_cmp(&b.value))
    };
    (least(|x| x.0), least(|x| x.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit cubes 0.25 apart along x, faces outward: walls of 1, a gap of 0.25.
    #[test]
    fn two_cubes_have_walls_of_one_and_a_gap_between_them() {
        let mut points = Vec::new();
        let mut triangles = Vec::new();
        for x0 in [0.0, 1.25] {
            let base = points.len();
            for i in 0..8u32 {
                points.push([x0 + f64::from(i & 1), f64::from(i >> 1 & 1), f64::from(i >> 2 & 1)]);
            }
            for q in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
                triangles.push([base + q[0], base + q[1], base + q[2]]);
                triangles.push([base + q[0], base + q[2], base + q[3]]);
            }
        }
        let (wall, hole) = walls_and_holes(&points, &triangles, 0);
        assert!((wall.unwrap().value - 1.0).abs() < 1e-12);
        let hole = hole.unwrap();
        assert!((hole.value - 0.25).abs() < 1e-12, "{hole:?}");
        assert!((hole.at[0] - 1.0).abs() < 1e-12 || (hole.at[0] - 1.25).abs() < 1e-12, "{hole:?}");
        // One cube alone: no hole.
        assert_eq!(walls_and_holes(&points[..8], &triangles[..12], 12).1, None);
    }
}
