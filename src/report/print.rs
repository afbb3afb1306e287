//! What a 3D-printing user asks of a mesh before slicing it (issue 45): its
//! volume, area and bounding box, whether it is closed and consistently
//! oriented, its pieces and its genus, its smallest wall and hole.

use rustc_hash::FxHashMap;

use crate::geometry::Shape;

/// The print report of a mesh: measures of its faces (quads split along a
/// diagonal), its edges and its pieces.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PrintReport {
    /// The enclosed volume (divergence theorem over the faces; positive when
    /// they are turned outward). Meaningful when `closed`.
    pub volume: f64,
    /// The surface area.
    pub area: f64,
    /// The bounding box: `[min, max]`.
    pub bbox: [[f64; 3]; 2],
    /// Connected pieces (through shared vertices).
    pub components: usize,
    /// Every edge has exactly two faces (watertight).
    pub closed: bool,
    /// Every edge is run once each way by its two faces (consistently oriented).
    pub oriented: bool,
    /// `V − E + F` of the triangles (the vertices faces use).
    pub euler: i64,
    /// The total genus (handles of all pieces, `components − euler/2`) of a
    /// closed, oriented mesh; `None` otherwise.
    pub genus: Option<i64>,
    /// Triangles (quads count two).
    pub triangles: usize,
    /// Vertices used by a face.
    pub vertices: usize,
    /// The thinnest wall of a closed, oriented mesh: the least distance from
    /// a face's middle, along its inward normal, to the face it meets
    /// ([`super::walls::walls_and_holes`]); `None` for other meshes.
    pub smallest_wall: Option<f64>,
    /// The middle of the face the thinnest wall was measured from.
    pub smallest_wall_at: Option<[f64; 3]>,
    /// The narrowest hole, tunnel or gap between pieces of a closed, oriented
    /// mesh: the least distance along a face's outward normal to the face it
    /// meets; `None` when no outward ray meets one (a convex solid) or the mesh is not closed.
    pub smallest_hole: Option<f64>,
    /// The middle of the face the narrowest hole was measured from.
    pub smallest_hole_at: Option<[f64; 3]>,
}

/// The print report of `shape` (its quads and triangles; 2D shapes lie at `z = 0`).
///
/// ```
/// // The unit cube: 6 quads turned outward.
/// let mut cube = bcifs::geometry::Shape { dim: 3, ..Default::default() };
/// for i in 0..8u32 {
///     cube.positions.extend([f64::from(i & 1), f64::from(i >> 1 & 1), f64::from(i >> 2 & 1)]);
/// }
/// cube.quads = vec![[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
/// let r = bcifs::report::print_report_of(&cube);
/// assert!((r.volume - 1.0).abs() < 1e-15 && (r.area - 6.0).abs() < 1e-15);
/// assert_eq!((r.closed, r.oriented, r.genus, r.components), (true, true, Some(0), 1));
/// ```
pub fn print_report_of(shape: &Shape) -> PrintReport {
    let triangles: Vec<[usize; 3]> = shape
        .quads
        .iter()
        .flat_map(|q| {
            let q = q.map(|v| v as usize);
            [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
        })
        .chain(shape.triangles.iter().copied())
        .collect();
    let at = |v: usize| shape.point(v);
    let (mut volume, mut area) = (0.0, 0.0);
    let mut bbox = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    let mut used = vec![false; shape.vertex_count()];
    for t in &triangles {
        let [p, q, r] = t.map(at);
        let (u, w) = ([0, 1, 2].map(|a| q[a] - p[a]), [0, 1, 2].map(|a| r[a] - p[a]));
        let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
        area += n.iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0;
        let c = [q[1] * r[2] - q[2] * r[1], q[2] * r[0] - q[0] * r[2], q[0] * r[1] - q[1] * r[0]];
        volume += (p[0] * c[0] + p[1] * c[1] + p[2] * c[2]) / 6.0;
        for v in t {
            used[*v] = true;
        }
    }
    for (v, _) in used.iter().enumerate().filter(|(_, u)| **u) {
        let p = at(v);
        for a in 0..3 {
            bbox[0][a] = bbox[0][a].min(p[a]);
            bbox[1][a] = bbox[1][a].max(p[a]);
        }
    }
    // Directed edges: how many faces run each.
    let mut directed: FxHashMap<(usize, usize), u32> = FxHashMap::default();
    for t in &triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    let (mut closed, mut oriented, mut edges) = (true, true, 0i64);
    for (&(a, b), &n) in &directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        oriented &= n == 1 && back == 1;
        closed &= n + back == 2;
        if a < b || back == 0 {
            edges += 1;
        }
    }
    let components = pieces(shape.vertex_count(), &triangles);
    let vertices = used.iter().filter(|u| **u).count();
    let euler = vertices as i64 - edges + triangles.len() as i64;
    let genus = (closed && oriented).then(|| components as i64 - euler / 2);
    if triangles.is_empty() {
        bbox = [[0.0; 3]; 2];
    }
    let (wall, hole) = if closed && oriented {
        let points: Vec<[f64; 3]> = (0..shape.vertex_count()).map(at).collect();
        super::walls::walls_and_holes(&points, &triangles, 2 * shape.quads.len())
    } else {
        (None, None)
    };
    PrintReport {
        volume,
        area,
        bbox,
        components,
        closed,
        oriented,
        euler,
        genus,
        triangles: triangles.len(),
        vertices,
        smallest_wall: wall.map(|m| m.value),
        smallest_wall_at: wall.map(|m| m.at),
        smallest_hole: hole.map(|m| m.value),
        smallest_hole_at: hole.map(|m| m.at),
    }
}

/// The connected pieces of the triangles over `n` vertices.
fn pieces(n: usize, triangles: &[[usize; 3]]) -> usize {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for t in triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a] = b;
        }
    }
    let mut roots: Vec<usize> = triangles.iter().map(|t| root(&mut parent, t[0])).collect();
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}
