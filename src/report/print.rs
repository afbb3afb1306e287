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
    /// Every vertex's faces make one fan (no two pieces share a vertex).
    pub manifold: bool,
    /// The area of the print's bottom within its first layer (half a nozzle
    /// above its lowest point), projected on the bed: what the first layer lays down.
    pub bed_contact: f64,
    /// Millimetres per model unit: the figures above are in millimetres when
    /// printed ([`PrintStyle`]), in model units (a scale of 1) otherwise.
    pub scale: f64,
    /// What a slicer or a printer will not like, each with its place (in
    /// the figures' unit): several pieces, pieces above the bed, a first
    /// layer that touches the bed at points only, walls or holes thinner
    /// than the nozzle, a place where the mesh is not a closed 2-manifold.
    pub warnings: Vec<String>,
}

/// How a mesh is printed: its physical size and the printer's nozzle.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PrintStyle {
    /// The longest side of the bounding box, in millimetres (`None`: see `scale`).
    pub size: Option<f64>,
    /// Millimetres per model unit (`None` and no `size`: 1, a model unit is a millimetre).
    pub scale: Option<f64>,
    /// The nozzle's width in millimetres: thinner walls and narrower holes are warned of.
    pub nozzle: f64,
    /// Write a print file even where the mesh is not a closed 2-manifold (warned of).
    pub allow_non_manifold: bool,
}

impl Default for PrintStyle {
    fn default() -> PrintStyle {
        PrintStyle { size: None, scale: None, nozzle: DEFAULT_NOZZLE, allow_non_manifold: false }
    }
}

/// The nozzle a print is checked against unless told: 0.4 mm, the common one.
pub const DEFAULT_NOZZLE: f64 = 0.4;

/// Less than this area (mm²) of a print's bottom within its first layer is
/// no foothold: a slicer lays down nothing, or a speck that will not hold
/// (a square of two nozzles' widths).
const FIRST_LAYER_AREA: f64 = 0.64;

/// A first layer under this share of the print's mean cross-section holds
/// it badly (a tricubic twist standing on a curved edge: 3 %).
const FOOTHOLD: f64 = 0.1;

/// Below this longest side (millimetres) a print is too small to print.
const TOO_SMALL: f64 = 5.0;

impl PrintStyle {
    /// Millimetres per model unit for a mesh whose bounding box is `bbox`.
    pub fn scale_for(&self, bbox: &[[f64; 3]; 2]) -> f64 {
        match (self.size, self.scale) {
            (Some(mm), _) => {
                let longest = (0..3).map(|a| bbox[1][a] - bbox[0][a]).fold(0.0, f64::max);
                if longest > 0.0 { mm / longest } else { 1.0 }
            }
            (None, Some(s)) => s,
            (None, None) => 1.0,
        }
    }
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
    let (closed, oriented, edges) = edge_counts(&directed);
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
    let fans = several_fans(&triangles, shape.vertex_count());
    let warnings = manifold_warnings(&fans, &directed, &at);
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
        manifold: fans.is_empty() && closed && oriented,
        bed_contact: 0.0,
        scale: 1.0,
        warnings,
    }
}

/// The area of the faces turned down below `top` along `up`, projected on the
/// bed, and the lowest point of one of them.
fn first_layer(triangles: &[[usize; 3]], at: &dyn Fn(usize) -> [f64; 3], up: usize, top: f64) -> (f64, [f64; 3]) {
    let (mut contact, mut bottom, mut deepest) = (0.0, [0.0; 3], f64::INFINITY);
    let (a1, a2) = ((up + 1) % 3, (up + 2) % 3);
    for t in triangles {
        let corners = t.map(at);
        let (u, w) =
            ([0, 1, 2].map(|x| corners[1][x] - corners[0][x]), [0, 1, 2].map(|x| corners[2][x] - corners[0][x]));
        let normal_up = u[a1] * w[a2] - u[a2] * w[a1];
        if normal_up >= 0.0 {
            continue;
        }
        let below = clip_below(&corners, up, top);
        let area = (0..below.len())
            .map(|k| {
                let (p, q) = (below[k], below[(k + 1) % below.len()]);
                p[a1] * q[a2] - q[a1] * p[a2]
            })
            .sum::<f64>()
            .abs()
            / 2.0;
        contact += area;
        if let Some(low) = corners.iter().min_by(|p, q| p[up].total_cmp(&q[up]))
            && area > 0.0
            && low[up] < deepest
        {
            (bottom, deepest) = (*low, low[up]);
        }
    }
    (contact, bottom)
}

/// The part of the triangle `corners` whose coordinate `up` is at most `top` (Sutherland–Hodgman, one plane).
fn clip_below(corners: &[[f64; 3]; 3], up: usize, top: f64) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity(4);
    for k in 0..3 {
        let (p, q) = (corners[k], corners[(k + 1) % 3]);
        let (pin, qin) = (p[up] <= top, q[up] <= top);
        if pin {
            out.push(p);
        }
        if pin != qin {
            let t = (top - p[up]) / (q[up] - p[up]);
            out.push([0, 1, 2].map(|x| p[x] + t * (q[x] - p[x])));
        }
    }
    out
}

/// Where the mesh is not a closed, oriented 2-manifold: a vertex of several
/// fans, an edge not in two faces, an edge run twice the same way (the first of each).
fn manifold_warnings(
    fans: &[usize],
    directed: &FxHashMap<(usize, usize), u32>,
    at: &dyn Fn(usize) -> [f64; 3],
) -> Vec<String> {
    let mut warnings = Vec::new();
    if let Some(&v) = fans.first() {
        warnings.push(format!(
            "{} vertex(es) join pieces that share nothing else (the first at {}): not a 2-manifold there",
            fans.len(),
            place(at(v))
        ));
    }
    let faces =
        |a: usize, b: usize| directed.get(&(a, b)).copied().unwrap_or(0) + directed.get(&(b, a)).copied().unwrap_or(0);
    if let Some((&(a, b), _)) = directed.iter().find(|&(&(a, b), _)| faces(a, b) != 2) {
        warnings.push(format!(
            "the mesh is not closed: an edge in {} face(s) at {} (every edge of a solid's boundary is in two)",
            faces(a, b),
            place(middle(at(a), at(b)))
        ));
    } else if let Some((&(a, b), _)) =
        directed.iter().find(|&(&(a, b), &n)| n != 1 || directed.get(&(b, a)) != Some(&1))
    {
        warnings.push(format!(
            "the faces are not consistently oriented: an edge run twice the same way at {}",
            place(middle(at(a), at(b)))
        ));
    }
    warnings
}

/// Whether every edge is in two faces, whether each is run once each way, and how many edges there are.
fn edge_counts(directed: &FxHashMap<(usize, usize), u32>) -> (bool, bool, i64) {
    let (mut closed, mut oriented, mut edges) = (true, true, 0i64);
    for (&(a, b), &n) in directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        oriented &= n == 1 && back == 1;
        closed &= n + back == 2;
        if a < b || back == 0 {
            edges += 1;
        }
    }
    (closed, oriented, edges)
}

/// `(x, y, z)` with a few digits.
fn place(p: [f64; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4})", p[0], p[1], p[2])
}

fn middle(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|x| (a[x] + b[x]) / 2.0)
}

/// The vertices whose triangles make more than one fan (joined through the edges at the vertex they share).
fn several_fans(triangles: &[[usize; 3]], n: usize) -> Vec<usize> {
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (t, tri) in triangles.iter().enumerate() {
        tri.iter().for_each(|&v| around[v].push(t as u32));
    }
    let mut out = Vec::new();
    for (v, ts) in around.iter().enumerate().filter(|(_, ts)| ts.len() > 1) {
        let mut parent: Vec<usize> = (0..ts.len()).collect();
        let others = |t: u32| triangles[t as usize].into_iter().filter(move |&w| w != v);
        for a in 0..ts.len() {
            for b in a + 1..ts.len() {
                if others(ts[a]).any(|w| others(ts[b]).any(|x| x == w)) {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    parent[ra] = rb;
                }
            }
        }
        if (0..ts.len()).filter(|&a| root(&mut parent, a) == a).count() > 1 {
            out.push(v);
        }
    }
    out
}

fn root(parent: &mut [usize], mut v: usize) -> usize {
    while parent[v] != v {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    v
}

/// The print report of `shape` printed as `style` says, its figures in
/// millimetres, with what a slicer or a printer will not like added to its
/// warnings: several pieces and those that float above the bed (the plane
/// of the lowest point along `up`, the model's axis that points up when
/// printed: 2, or 1 for a Y-up mesh file), a first layer (half the nozzle
/// high) that touches the bed at points or lines only, walls and holes
/// thinner than the nozzle, a print too small to slice.
pub fn printed(shape: &Shape, style: &PrintStyle, up: usize) -> PrintReport {
    let mut r = print_report_of(shape);
    let s = style.scale_for(&r.bbox);
    let mm = |p: [f64; 3]| p.map(|x| x * s);
    r.scale = s;
    r.volume *= s * s * s;
    r.area *= s * s;
    r.bbox = r.bbox.map(mm);
    r.smallest_wall = r.smallest_wall.map(|w| w * s);
    r.smallest_hole = r.smallest_hole.map(|w| w * s);
    r.smallest_wall_at = r.smallest_wall_at.map(mm);
    r.smallest_hole_at = r.smallest_hole_at.map(mm);
    for w in &mut r.warnings {
        *w = format!("{w} (model units)");
    }
    let longest = (0..3).map(|a| r.bbox[1][a] - r.bbox[0][a]).fold(0.0, f64::max);
    if longest < TOO_SMALL {
        r.warnings.push(format!(
            "the print is {longest:.3} mm across at {s} mm a model unit: too small to slice; give it a print size (its longest side in millimetres)"
        ));
    }
    let nozzle = style.nozzle;
    if let (Some(w), Some(at)) = (r.smallest_wall, r.smallest_wall_at)
        && w < nozzle
    {
        r.warnings.push(format!(
            "a wall {w:.3} mm thin at {} mm: thinner than the nozzle ({nozzle} mm), it will not print",
            place(at)
        ));
    }
    if let (Some(h), Some(at)) = (r.smallest_hole, r.smallest_hole_at)
        && h < nozzle
    {
        r.warnings.push(format!(
            "a hole or gap {h:.3} mm narrow at {} mm: narrower than the nozzle ({nozzle} mm), it will close up",
            place(at)
        ));
    }
    bed(shape, s, up, nozzle / 2.0, &mut r);
    r
}

/// The pieces and the first layer on the bed (see [`printed`]).
fn bed(shape: &Shape, s: f64, up: usize, layer: f64, r: &mut PrintReport) {
    let triangles: Vec<[usize; 3]> = shape
        .quads
        .iter()
        .flat_map(|q| {
            let q = q.map(|v| v as usize);
            [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
        })
        .chain(shape.triangles.iter().copied())
        .collect();
    if triangles.is_empty() {
        return;
    }
    let at = |v: usize| shape.point(v).map(|x| x * s);
    let height = |v: usize| at(v)[up];
    let floor = triangles.iter().flatten().map(|&v| height(v)).fold(f64::INFINITY, f64::min);
    // The pieces (through shared vertices) and each one's lowest point.
    let mut parent: Vec<usize> = (0..shape.vertex_count()).collect();
    for t in &triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a] = b;
        }
    }
    let mut lowest: FxHashMap<usize, usize> = FxHashMap::default();
    for &v in triangles.iter().flatten() {
        let p = root(&mut parent, v);
        let e = lowest.entry(p).or_insert(v);
        if height(v) < height(*e) {
            *e = v;
        }
    }
    // Pieces that do not reach the bed print in the air: the slicer leaves empty layers below them.
    let mut floating: Vec<usize> = lowest.values().copied().filter(|&v| height(v) > floor + layer).collect();
    floating.sort_by(|&a, &b| height(a).total_cmp(&height(b)));
    if let Some(&v) = floating.first() {
        r.warnings.push(format!(
            "{} of its {} separate pieces float above the bed (the lowest at {} mm, {:.3} mm up): they print in the air unless supported",
            floating.len(),
            lowest.len(),
            place(at(v)),
            height(v) - floor
        ));
    }
    // The first layer: the faces turned down, cut at its top, projected on the bed.
    let (contact, bottom) = first_layer(&triangles, &at, up, floor + layer);
    r.bed_contact = contact;
    // The print's mean cross-section: its volume over its height.
    let tall = r.bbox[1][up] - r.bbox[0][up];
    let section = if tall > 0.0 { r.volume.abs() / tall } else { 0.0 };
    if contact < FIRST_LAYER_AREA || contact < FOOTHOLD * section {
        r.warnings.push(format!(
            "the first layer touches the bed over {contact:.4} mm² only ({:.1} % of the print's mean cross-section, near {} mm): a slicer finds little or nothing to lay down there, and what it lays will not hold; turn the model or add supports",
            if section > 0.0 { 100.0 * contact / section } else { 0.0 },
            place(bottom)
        ));
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
