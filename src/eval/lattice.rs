//! Solids whose volume splits into a grid of copies of itself (every
//! hexahedron pattern: the Menger sponge, the Jerusalem cube): their leaf
//! cells sit on a lattice, so a face is on the boundary exactly when the
//! cell across it is not kept (read off the pattern's digits), and corners
//! are numbered by their lattice point. No face of the solid's inside is
//! ever made or hashed. The faces go to the sink as they are made, one
//! layer of cells at a time, and only the corners of the layer being made
//! are held: memory stays bounded whatever the depth. Where kept cells
//! touch along an edge or at a corner only (a pinch), each fan of faces
//! around the corner gets its own vertex, read off the 8 cells around it.

use rustc_hash::FxHashMap;

use crate::geometry::Sink;

use super::plan::StatePlan;
use super::prepared::Evaluator;
use super::settings::EvalError;
use crate::space::CellKind;

/// A face's axis and side (0 at the start, 1 at the end).
type Side = (usize, u64);

/// A volume state subdividing into a `dims` grid of copies of itself.
pub(super) struct SolidGrid {
    dims: [u64; 3],
    /// Per child (in the plan's order): its place in the grid.
    place: Vec<[u64; 3]>,
    /// Per grid place (`x + dx·(y + dy·z)`): a child is there.
    kept: Vec<bool>,
    /// Per corner (sample): its corner of the unit cube.
    corner: Vec<[u64; 3]>,
    /// Per face: its axis and side.
    side: Vec<Side>,
    /// The corners of the children, each lattice point once: its weights on the parent's control points.
    points: Vec<Vec<f64>>,
    /// Per child, per corner: its lattice point in `points`.
    point_of: Vec<[usize; 8]>,
    /// Per corner of the unit cube (`x + 2y + 4z`): its corner (sample).
    by_code: [usize; 8],
}

/// Equal to rounding (the constraints make shared corners equal).
fn same(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-9 * x.abs().max(1.0))
}

impl SolidGrid {
    /// The grid of `sp` (state number `s`), if it is one: a hexahedron (8
    /// corners, 6 faces of 4) whose children are all of its state, placed by
    /// the faces they share, filling a box whose corner children hold the
    /// cell's corners.
    pub(super) fn of(sp: &StatePlan, s: usize) -> Option<SolidGrid> {
        if sp.kind != CellKind::Volume || sp.samples.len() != 8 || sp.faces.len() != 6 {
            return None;
        }
        if sp.faces.iter().any(|f| f.len() != 4) || sp.children.iter().any(|c| c.1 != s) || sp.children.is_empty() {
            return None;
        }
        let (side, corner) = axes(sp)?;
        let code = |c: [u64; 3]| corner.iter().position(|&k| k == c);
        if (0..8).any(|i| code([i & 1, i >> 1 & 1, i >> 2 & 1]).is_none()) {
            return None;
        }
        // Each child's corners in the cell's coordinates.
        let n = sp.dim;
        let corners: Vec<Vec<Vec<f64>>> = sp
            .children
            .iter()
            .map(|(_, _, m)| {
                sp.samples.iter().map(|b| (0..n).map(|r| (0..n).map(|c| m[r * n + c] * b[c]).sum()).collect()).collect()
            })
            .collect();
        let holds = |child: usize, c: [u64; 3]| code(c).is_some_and(|j| same(&corners[child][j], &sp.samples[j]));
        let first = (0..corners.len()).find(|&c| holds(c, [0, 0, 0]))?;
        let mut place: Vec<Option<[u64; 3]>> = vec![None; corners.len()];
        place[first] = Some([0, 0, 0]);
        let mut queue = vec![first];
        while let Some(a) = queue.pop() {
            let at = place[a]?;
            for b in 0..corners.len() {
                for ax in 0..3 {
                    // b is a's neighbour along ax when a's end face is b's start face, corner for corner.
                    let meets = (0..4u64).all(|q| {
                        let mut c = [0u64; 3];
                        let others: Vec<usize> = (0..3).filter(|&x| x != ax).collect();
                        c[others[0]] = q & 1;
                        c[others[1]] = q >> 1;
                        let mut end = c;
                        end[ax] = 1;
                        match (code(end), code(c)) {
                            (Some(i), Some(j)) => same(&corners[a][i], &corners[b][j]),
                            _ => false,
                        }
                    });
                    if meets {
                        let mut next = at;
                        next[ax] += 1;
                        match place[b] {
                            None => {
                                place[b] = Some(next);
                                queue.push(b);
                            }
                            Some(p) if p != next => return None,
                            _ => {}
                        }
                    }
                }
            }
        }
        let place: Vec<[u64; 3]> = place.into_iter().collect::<Option<_>>()?;
        let dims = [0, 1, 2].map(|x| place.iter().map(|p| p[x]).max().unwrap_or(0) + 1);
        let last = (0..corners.len()).find(|&c| holds(c, [1, 1, 1]))?;
        if place[last] != [dims[0] - 1, dims[1] - 1, dims[2] - 1] {
            return None;
        }
        let mut kept = vec![false; (dims[0] * dims[1] * dims[2]) as usize];
        for p in &place {
            let i = (p[0] + dims[0] * (p[1] + dims[1] * p[2])) as usize;
            if std::mem::replace(&mut kept[i], true) {
                return None;
            }
        }
        let (points, point_of) = lattice_points(sp, &place, &corner, dims);
        let by_code = [0, 1, 2, 3, 4, 5, 6, 7].map(|i| code([i & 1, i >> 1 & 1, i >> 2 & 1]).unwrap_or(0));
        Some(SolidGrid { dims, place, kept, corner, side, points, point_of, by_code })
    }

    /// The corner Jacobians of a cell (corners `at`): per corner of the unit
    /// cube, the determinant of the cell's three edges through it, and the
    /// product of their squared lengths (its scale, squared).
    fn jacobians(&self, at: &[[f64; 3]; 8]) -> [(f64, f64); 8] {
        let p = |c: usize| at[self.by_code[c]];
        let mut out = [(0.0, 0.0); 8];
        for (c, slot) in out.iter_mut().enumerate() {
            let mut e = [[0.0f64; 3]; 3];
            for (a, bit) in [1usize, 2, 4].into_iter().enumerate() {
                let (lo, hi) = (p(c & !bit), p(c | bit));
                e[a] = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
            }
            let det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
            let len2 = |v: [f64; 3]| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            *slot = (det, len2(e[0]) * len2(e[1]) * len2(e[2]));
        }
        out
    }

    /// Whether the leaf at lattice place `p` of the depth-`k` grid is kept.
    fn kept_at(&self, mut p: [u64; 3], k: usize) -> bool {
        for _ in 0..k {
            let digit = [0, 1, 2].map(|x| p[x] % self.dims[x]);
            if !self.kept[(digit[0] + self.dims[0] * (digit[1] + self.dims[1] * digit[2])) as usize] {
                return false;
            }
            p = [0, 1, 2].map(|x| p[x] / self.dims[x]);
        }
        p == [0, 0, 0]
    }
}

/// The children's corners by lattice point (in children's units): one
/// weight vector each on the parent's control points (`m · b`), and per
/// child its corners' entries.
fn lattice_points(
    sp: &StatePlan,
    place: &[[u64; 3]],
    corner: &[[u64; 3]],
    dims: [u64; 3],
) -> (Vec<Vec<f64>>, Vec<[usize; 8]>) {
    let n = sp.dim;
    let mut key_of: FxHashMap<u64, usize> = FxHashMap::default();
    let (mut points, mut point_of) = (Vec::new(), Vec::new());
    for ((_, _, m), p) in sp.children.iter().zip(place) {
        let mut ids = [0usize; 8];
        for (j, b) in sp.samples.iter().enumerate() {
            let q = [0, 1, 2].map(|x| p[x] + corner[j][x]);
            let key = q[0] + (dims[0] + 1) * (q[1] + (dims[1] + 1) * q[2]);
            ids[j] = *key_of.entry(key).or_insert_with(|| {
                points.push((0..n).map(|r| (0..n).map(|c| m[r * n + c] * b[c]).sum()).collect());
                points.len() - 1
            });
        }
        point_of.push(ids);
    }
    (points, point_of)
}

/// The axes of a hexahedron's plan: opposite faces share no corner; each
/// pair an axis, its first face at the start. Per face its axis and side,
/// per corner its corner of the unit cube (all eight different).
fn axes(sp: &StatePlan) -> Option<(Vec<Side>, Vec<[u64; 3]>)> {
    // Opposite faces share no corner: three axes, the first face of each pair at the start.
    let mut side = vec![(usize::MAX, 0u64); 6];
    let mut corner = vec![[0u64; 3]; 8];
    let mut axis = 0;
    for f in 0..6 {
        if side[f].0 != usize::MAX {
            continue;
        }
        let g = (f + 1..6).find(|&g| sp.faces[g].iter().all(|j| !sp.faces[f].contains(j)))?;
        if axis == 3 {
            return None;
        }
        side[f] = (axis, 0);
        side[g] = (axis, 1);
        sp.faces[g].iter().for_each(|&j| corner[j][axis] = 1);
        axis += 1;
    }
    Some((side, corner))
}

/// Around a lattice point, per occupancy of its 8 cells (bit `x + 2y + 4z`,
/// 1 for the cell after the point along that axis): per face through the
/// point (slot `4a + o_b + 2o_c` for a face across axis `a` between the cells
/// at offsets `o_b, o_c` along the other two axes, `b < c`) the fan it
/// belongs to, or `u8::MAX` where it is no boundary face. Faces are joined
/// through an edge that two of them share; where four meet (two cells
/// touching along the edge only), each cell's two.
fn fan_table() -> Vec<[u8; 12]> {
    let others = |a: usize| -> [usize; 2] { [[1, 2], [0, 2], [0, 1]][a] };
    let slot = |a: usize, o: [usize; 3]| {
        let [b, c] = others(a);
        4 * a + o[b] + 2 * o[c]
    };
    let octant = |o: [usize; 3]| o[0] + 2 * o[1] + 4 * o[2];
    (0..256usize)
        .map(|occupancy| {
            let kept = |o: [usize; 3]| occupancy >> octant(o) & 1 == 1;
            // Per slot: whether it is a boundary face, and its kept cell.
            let mut owner = [None; 12];
            for a in 0..3 {
                for (ob, oc) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let [b, c] = others(a);
                    let mut o = [0; 3];
                    (o[b], o[c]) = (ob, oc);
                    let lo = o;
                    o[a] = 1;
                    if kept(lo) != kept(o) {
                        owner[slot(a, lo)] = Some(if kept(lo) { octant(lo) } else { octant(o) });
                    }
                }
            }
            let mut parent: [usize; 12] = std::array::from_fn(|i| i);
            let root = |parent: &[usize; 12], mut x: usize| {
                while parent[x] != x {
                    x = parent[x];
                }
                x
            };
            // Each half-edge from the point: along axis e, toward side s; its four faces.
            for e in 0..3 {
                for side in 0..2 {
                    let mut around = Vec::new();
                    for a in others(e) {
                        for t in 0..2 {
                            let mut o = [0; 3];
                            o[e] = side;
                            let rest = 3 - a - e;
                            o[rest] = t;
                            let f = slot(a, o);
                            if let Some(cell) = owner[f] {
                                around.push((f, cell));
                            }
                        }
                    }
                    for (n, &(f, cell)) in around.iter().enumerate() {
                        for &(g, other) in &around[n + 1..] {
                            if around.len() == 2 || cell == other {
                                let (x, y) = (root(&parent, f), root(&parent, g));
                                parent[x] = y;
                            }
                        }
                    }
                }
            }
            let mut fans = [u8::MAX; 12];
            let mut roots: Vec<usize> = Vec::new();
            for f in 0..12 {
                if owner[f].is_some() {
                    let r = root(&parent, f);
                    let n = roots.iter().position(|&x| x == r).unwrap_or_else(|| {
                        roots.push(r);
                        roots.len() - 1
                    });
                    fans[f] = n as u8;
                }
            }
            fans
        })
        .collect()
}

/// The slot (see [`fan_table`]) of the face across `axis` of a cell whose
/// octant around the point is `o`.
fn slot_of(axis: usize, o: [usize; 3]) -> usize {
    let [b, c] = [[1, 2], [0, 2], [0, 1]][axis];
    4 * axis + o[b] + 2 * o[c]
}

/// A lattice point met: its fans (per face slot) and the vertex of each fan.
struct Corner {
    fans: [u8; 12],
    ids: [usize; 8],
}

/// A grid solid's walk to its leaves, writing its boundary to a sink as it goes.
struct Walk<'a> {
    grid: &'a SolidGrid,
    sp: &'a StatePlan,
    k: usize,
    /// Cells per direction at depth `k`.
    cells: [u64; 3],
    /// Lattice points per direction at depth `k`.
    side: [u64; 3],
    /// The first vertex's number, and the vertices written.
    first: usize,
    written: usize,
    /// The corners of the layer being made (and of its top plane, kept for the next).
    corners: FxHashMap<u64, Corner>,
    /// Per depth-`k` cell (`x + cells·(y + cells·z)`), kept or not, when that fits in 64 MiB.
    bits: Option<Vec<u64>>,
    table: Vec<[u8; 12]>,
    /// The root's orientation (the sign of its corner Jacobians), 0 when unknown (not 3D, flat).
    sign: f64,
    d: usize,
    positions: Vec<f64>,
    quads: Vec<[usize; 4]>,
    /// The faces cut at a doubled edge, as triangles.
    triangles: Vec<[usize; 3]>,
}

impl<'a> Walk<'a> {
    /// A walk to depth `k` of the cells of `sp` on `grid`, its vertices numbered from `first`.
    fn new(grid: &'a SolidGrid, sp: &'a StatePlan, k: usize, first: usize, sign: f64, d: usize) -> Walk<'a> {
        let cells = [0, 1, 2].map(|x| grid.dims[x].pow(k as u32));
        Walk {
            grid,
            sp,
            k,
            cells,
            side: cells.map(|c| c + 1),
            first,
            written: 0,
            corners: FxHashMap::default(),
            bits: Walk::kept_bits(grid, k, cells),
            table: fan_table(),
            sign,
            d,
            positions: Vec::new(),
            quads: Vec::new(),
            triangles: Vec::new(),
        }
    }

    /// The kept cells at depth `k`, one bit each: set by walking the
    /// pattern's tree (no geometry), `None` over 64 MiB.
    fn kept_bits(grid: &SolidGrid, k: usize, cells: [u64; 3]) -> Option<Vec<u64>> {
        let total = cells.iter().try_fold(1u64, |n, &c| n.checked_mul(c))?;
        if total / 8 > 64 << 20 {
            return None;
        }
        let mut bits = vec![0u64; total.div_ceil(64) as usize];
        let mut stack = vec![([0u64; 3], 0usize)];
        while let Some((p, level)) = stack.pop() {
            if level == k {
                let i = p[0] + cells[0] * (p[1] + cells[1] * p[2]);
                bits[(i / 64) as usize] |= 1 << (i % 64);
                continue;
            }
            for place in &grid.place {
                stack.push(([0, 1, 2].map(|x| p[x] * grid.dims[x] + place[x]), level + 1));
            }
        }
        Some(bits)
    }

    /// Whether the depth-`k` cell at `p` (which may be outside) is kept.
    fn kept(&self, p: [i64; 3]) -> bool {
        if p[0] < 0 || p[1] < 0 || p[2] < 0 {
            return false;
        }
        let p = p.map(|x| x as u64);
        if p[0] >= self.cells[0] || p[1] >= self.cells[1] || p[2] >= self.cells[2] {
            return false;
        }
        match &self.bits {
            Some(bits) => {
                let i = p[0] + self.cells[0] * (p[1] + self.cells[1] * p[2]);
                bits[(i / 64) as usize] >> (i % 64) & 1 == 1
            }
            None => self.grid.kept_at(p, self.k),
        }
    }

    /// The vertex of lattice point `q` for the face across `axis` of the
    /// cell at `p`, placed at `at` when new.
    fn vertex(&mut self, q: [u64; 3], p: [u64; 3], axis: usize, at: &[f64]) -> usize {
        let key = q[0] + self.side[0] * (q[1] + self.side[1] * q[2]);
        if !self.corners.contains_key(&key) {
            let mut occupancy = 0;
            for o in 0..8usize {
                let c = [0, 1, 2].map(|x| q[x] as i64 - 1 + (o >> x & 1) as i64);
                occupancy |= usize::from(self.kept(c)) << o;
            }
            self.corners.insert(key, Corner { fans: self.table[occupancy], ids: [usize::MAX; 8] });
        }
        let o = [0, 1, 2].map(|x| usize::from(p[x] == q[x]));
        let corner = self.corners.get_mut(&key).expect("inserted");
        let fan = usize::from(corner.fans[slot_of(axis, o)]).min(7);
        if corner.ids[fan] == usize::MAX {
            corner.ids[fan] = self.first + self.written;
            self.written += 1;
            self.positions.extend_from_slice(at);
        }
        corner.ids[fan]
    }

    /// A leaf at lattice place `p`, its corners at `at`: checked not turned
    /// over, and its faces whose cell across is not kept, made.
    fn leaf(&mut self, at: &[[f64; 3]; 8], p: [u64; 3]) -> Result<(), EvalError> {
        let grid = self.grid;
        if self.sign != 0.0 {
            for (c, (det, scale2)) in grid.jacobians(at).into_iter().enumerate() {
                if det * self.sign < 0.0 && det * det > 1e-18 * scale2 {
                    let corner = at[grid.by_code[c]];
                    return Err(EvalError::Folded { at: corner, depth: self.k, jacobian: det / scale2.sqrt() });
                }
            }
        }
        let centre = [0, 1, 2].map(|a| at.iter().map(|q| q[a]).sum::<f64>() / 8.0);
        // This cell's own vertices at the middle of its doubled edges ([`Walk::doubled`]), by the edge's corners.
        let mut middles: Vec<([usize; 2], usize)> = Vec::new();
        for (f, face) in self.sp.faces.iter().enumerate() {
            let (axis, end) = grid.side[f];
            let mut across = p.map(|x| x as i64);
            across[axis] += if end == 1 { 1 } else { -1 };
            if self.kept(across) {
                continue;
            }
            let mut ids = [0usize; 4];
            for (slot, &j) in ids.iter_mut().zip(face) {
                let q = [0, 1, 2].map(|x| p[x] + grid.corner[j][x]);
                *slot = self.vertex(q, p, axis, &at[j][..self.d]);
            }
            // The face's corners, with a vertex of this cell's own in each doubled edge.
            let mut polygon: Vec<usize> = Vec::with_capacity(6);
            for k in 0..4 {
                polygon.push(ids[k]);
                let (ja, jb) = (face[k], face[(k + 1) % 4]);
                let [qa, qb] = [ja, jb].map(|j| [0, 1, 2].map(|x| p[x] + grid.corner[j][x]));
                if !self.doubled(p, axis, across, qa, qb) {
                    continue;
                }
                let key = [ja.min(jb), ja.max(jb)];
                let middle = match middles.iter().find(|m| m.0 == key) {
                    Some(m) => m.1,
                    None => {
                        let id = self.first + self.written;
                        self.written += 1;
                        let mid: Vec<f64> = (0..self.d).map(|x| (at[ja][x] + at[jb][x]) / 2.0).collect();
                        self.positions.extend_from_slice(&mid);
                        middles.push((key, id));
                        id
                    }
                };
                polygon.push(middle);
            }
            // Turned outward: its Newell normal away from the cell's centroid.
            let points = [face[0], face[1], face[2], face[3]].map(|j| at[j]);
            let mut normal = [0.0; 3];
            for k in 0..4 {
                let (a, b) = (points[k], points[(k + 1) % 4]);
                normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
                normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
                normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
            }
            let mid = [0, 1, 2].map(|a| points.iter().map(|q| q[a]).sum::<f64>() / 4.0);
            if (0..3).map(|a| normal[a] * (mid[a] - centre[a])).sum::<f64>() < 0.0 {
                ids.reverse();
                polygon.reverse();
            }
            if polygon.len() == 4 {
                self.quads.push(ids);
            } else {
                // Fanned from a middle vertex: no triangle lies along the cut edge.
                let start = polygon.iter().position(|v| !ids.contains(v)).unwrap_or(0);
                polygon.rotate_left(start);
                self.triangles.extend((1..polygon.len() - 1).map(|t| [polygon[0], polygon[t], polygon[t + 1]]));
            }
        }
        Ok(())
    }

    /// Whether the edge `qa`–`qb` of the face across `axis` of the cell at
    /// `p` (the cell across it, `across`, not kept) is doubled: the cell
    /// diagonally across the edge is kept and the fourth around it is not
    /// (two cells touching along the edge only), and at each end the two
    /// cells' faces there are one fan (one vertex). The split surface then
    /// runs along the edge twice between the same vertices: each cell's run
    /// gets a middle vertex of its own.
    fn doubled(&mut self, p: [u64; 3], axis: usize, across: [i64; 3], qa: [u64; 3], qb: [u64; 3]) -> bool {
        let Some(e) = (0..3).find(|&x| qa[x] != qb[x]) else { return false };
        let r = 3 - axis - e;
        let mut side = p.map(|x| x as i64);
        side[r] += if qa[r] == p[r] { -1 } else { 1 };
        let mut diagonal = side;
        diagonal[axis] = across[axis];
        if self.kept(side) || !self.kept(diagonal) {
            return false;
        }
        let octant = |cell: [i64; 3], q: [u64; 3]| [0, 1, 2].map(|x| usize::from(cell[x] == q[x] as i64));
        let here = p.map(|x| x as i64);
        [qa, qb].into_iter().all(|q| {
            let key = q[0] + self.side[0] * (q[1] + self.side[1] * q[2]);
            self.corners
                .get(&key)
                .is_some_and(|c| c.fans[slot_of(axis, octant(here, q))] == c.fans[slot_of(axis, octant(diagonal, q))])
        })
    }

    /// Sends what was made: the vertices first, then the faces that use them.
    fn flush(&mut self, sink: &mut dyn Sink) -> Result<(), EvalError> {
        if !self.positions.is_empty() {
            sink.vertices(self.d, &self.positions, None)?;
            self.positions.clear();
        }
        if !self.quads.is_empty() {
            sink.faces(&self.quads, None)?;
            self.quads.clear();
        }
        if !self.triangles.is_empty() {
            sink.triangles(&self.triangles)?;
            self.triangles.clear();
        }
        Ok(())
    }
}

/// The fold check of hexahedral cells outside the lattice mesher (pieces
/// welded across a larger lattice): every leaf's corner Jacobians must have
/// the sign of the first piece's.
pub(super) struct Folds {
    grid: SolidGrid,
    state: usize,
    sign: f64,
}

/// The orientation of a hexahedral cell at `control` (the sign of its corner Jacobians' sum), 0 when flat or not 3D.
fn orientation(grid: &SolidGrid, sp: &StatePlan, control: &[f64], d: usize) -> f64 {
    if d != 3 {
        return 0.0;
    }
    let root = corners_of(control, d, sp.dim, &sp.samples);
    let jacobians = grid.jacobians(&root);
    let total: f64 = jacobians.iter().map(|j| j.0).sum();
    let scale: f64 = jacobians.iter().map(|j| j.1.sqrt()).sum();
    if total.abs() > 1e-9 * scale { total.signum() } else { 0.0 }
}

impl Folds {
    /// The check for cells of `sp` (state `s`), oriented as the cell at `control`; `None` when not hexahedra in 3D.
    pub(super) fn of(sp: &StatePlan, s: usize, control: &[f64], d: usize) -> Option<Folds> {
        let grid = SolidGrid::of(sp, s)?;
        let sign = orientation(&grid, sp, control, d);
        (sign != 0.0).then_some(Folds { grid, state: s, sign })
    }

    /// A leaf cell of state `s` with control points `c` at depth `depth`: an error where it is turned over.
    pub(super) fn check(&self, sp: &StatePlan, s: usize, c: &[f64], depth: usize) -> Result<(), EvalError> {
        if s != self.state {
            return Ok(());
        }
        let at = corners_of(c, 3, sp.dim, &sp.samples);
        for (k, (det, scale2)) in self.grid.jacobians(&at).into_iter().enumerate() {
            if det * self.sign < 0.0 && det * det > 1e-18 * scale2 {
                return Err(EvalError::Folded { at: at[self.grid.by_code[k]], depth, jacobian: det / scale2.sqrt() });
            }
        }
        Ok(())
    }
}

/// The corners of a cell with control points `c` (`d` coordinates of `n` points) at the weights `samples`.
fn corners_of(c: &[f64], d: usize, n: usize, samples: &[Vec<f64>]) -> [[f64; 3]; 8] {
    let mut at = [[0.0f64; 3]; 8];
    for (j, b) in samples.iter().enumerate().take(8) {
        for a in 0..d {
            at[j][a] = (0..n).map(|i| c[a * n + i] * b[i]).sum();
        }
    }
    at
}

impl Evaluator {
    /// The boundary of the depth-`k` cells of a grid solid rooted at
    /// `control` (state `s`), to `sink` (vertices numbered from `first`):
    /// corners numbered by lattice point (one per fan of faces around it), a
    /// face made when the cell across it is not kept. The cells are made one
    /// layer of depth-`k − 1` cells at a time (along the third axis), whose
    /// corners are computed once per lattice point of their parent; only
    /// the layer's corners are held. Returns the vertices written.
    ///
    /// # Errors
    /// A cell turned over ([`EvalError::Folded`]); the sink's errors; cancelled.
    pub(super) fn lattice_solid(
        &self,
        grid: &SolidGrid,
        s: usize,
        control: &[f64],
        k: usize,
        sink: &mut dyn Sink,
        first: usize,
    ) -> Result<usize, EvalError> {
        let d = self.pieces.dim;
        let sp = self.plan.state(s);
        let n = sp.dim;
        let root = corners_of(control, d, n, &sp.samples);
        let sign = orientation(grid, sp, control, d);
        let mut walk = Walk::new(grid, sp, k, first, sign, d);
        if k == 0 {
            walk.leaf(&root, [0, 0, 0])?;
            walk.flush(sink)?;
            return Ok(walk.written);
        }
        let dz = grid.dims[2];
        let mut table = vec![[0.0f64; 3]; grid.points.len()];
        let mut visited = 0usize;
        // One layer of depth-(k − 1) cells at a time: z is its place along the third axis.
        for z in 0..dz.pow(k as u32 - 1) {
            let mut stack: Vec<(Vec<f64>, usize, [u64; 3])> = vec![(control.to_vec(), k, [0, 0, 0])];
            while let Some((c, r, p)) = stack.pop() {
                visited += 1;
                if visited.is_multiple_of(256) {
                    self.check_cancel()?;
                }
                let below = [0, 1, 2].map(|x| p[x] * grid.dims[x]);
                if r > 1 {
                    for ((_, _, m), place) in sp.children.iter().zip(&grid.place) {
                        let q = [0, 1, 2].map(|x| below[x] + place[x]);
                        // The child's cells at depth k − 1 span z / dz^(r − 2) along the third axis.
                        if q[2] != z / dz.pow(r as u32 - 2) {
                            continue;
                        }
                        let mut child = vec![0.0; d * n];
                        super::prepared::mul_into(&c, d, n, m, n, &mut child);
                        stack.push((child, r - 1, q));
                    }
                    continue;
                }
                for (slot, w) in table.iter_mut().zip(&grid.points) {
                    for a in 0..d {
                        let row = &c[a * n..(a + 1) * n];
                        slot[a] = row.iter().zip(w).map(|(x, y)| x * y).sum();
                    }
                }
                for (ids, place) in grid.point_of.iter().zip(&grid.place) {
                    let at = ids.map(|i| table[i]);
                    walk.leaf(&at, [0, 1, 2].map(|x| below[x] + place[x]))?;
                }
                if walk.quads.len() >= 1 << 16 {
                    walk.flush(sink)?;
                }
            }
            walk.flush(sink)?;
            // Only the layer's top plane is met again (by the next layer).
            let (top, plane) = ((z + 1) * dz, walk.side[0] * walk.side[1]);
            walk.corners.retain(|key, _| key / plane == top);
        }
        Ok(walk.written)
    }
}

#[cfg(test)]
mod tests {
    use super::SolidGrid;
    use crate::eval::{EvalSettings, Evaluator};

    fn grid(name: &str) -> Option<SolidGrid> {
        let design = crate::format::builtin_design(name).unwrap();
        let instance = crate::family::instantiate(&design, &[]).unwrap();
        let ev = Evaluator::new(&instance.automaton, design.model().unwrap(), EvalSettings::default()).unwrap();
        let s = ev.pieces().pieces[0].state;
        SolidGrid::of(ev.plan().state(s), s)
    }

    /// The sponges are grids (their boundary comes from the lattice); Cantor
    /// dust's cubes share no face and the tetrahedron is no hexahedron: the
    /// general mesher takes them.
    #[test]
    fn grid_solids_are_recognised_by_the_faces_their_children_share() {
        for name in ["menger", "jerusalem"] {
            let g = grid(name).unwrap_or_else(|| panic!("{name} is a grid"));
            assert_eq!((g.dims, g.place.len(), g.kept.iter().filter(|k| **k).count()), ([3, 3, 3], 20, 20), "{name}");
            // The middle of the cube and the middles of its faces are holes.
            assert!(!g.kept_at([1, 1, 1], 1) && !g.kept_at([1, 1, 0], 1) && g.kept_at([0, 0, 0], 1));
            assert!(g.kept_at([8, 8, 8], 2) && !g.kept_at([4, 4, 0], 2) && !g.kept_at([9, 0, 0], 2));
        }
        assert!(grid("cantor_dust").is_none());
        assert!(grid("sierpinski_tetrahedron").is_none());
    }

    /// A sink that counts what comes, and how many batches of vertices.
    #[derive(Default)]
    struct Count {
        batches: usize,
        vertices: usize,
        quads: usize,
        largest: usize,
    }

    impl crate::geometry::Sink for Count {
        fn object(&mut self, _: &str) -> std::io::Result<()> {
            Ok(())
        }
        fn vertices(&mut self, dim: usize, positions: &[f64], _: Option<&[f64]>) -> std::io::Result<()> {
            self.batches += 1;
            self.vertices += positions.len() / dim;
            Ok(())
        }
        fn uvs(&mut self, _: &[f64]) -> std::io::Result<()> {
            Ok(())
        }
        fn polyline(&mut self, _: usize, _: usize, _: bool) -> std::io::Result<()> {
            Ok(())
        }
        fn faces(&mut self, quads: &[[usize; 4]], _: Option<&[[usize; 4]]>) -> std::io::Result<()> {
            self.quads += quads.len();
            self.largest = self.largest.max(quads.iter().flatten().copied().max().unwrap_or(0));
            Ok(())
        }
        fn triangles(&mut self, _: &[[usize; 3]]) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// The sponge's boundary comes one layer of cells at a time (nine
    /// layers of depth-2 cells at depth 3), every face naming vertices
    /// already sent: 18,048 quads on 15,232 corners, as the print report says.
    #[test]
    fn grid_solids_stream_their_boundary_layer_by_layer() {
        let design = crate::format::builtin_design("menger").unwrap();
        let instance = crate::family::instantiate(&design, &[]).unwrap();
        let ev = Evaluator::new(&instance.automaton, design.model().unwrap(), EvalSettings::default()).unwrap();
        let piece = &ev.pieces().pieces[0];
        let g = SolidGrid::of(ev.plan().state(piece.state), piece.state).unwrap();
        let mut count = Count::default();
        let written = ev.lattice_solid(&g, piece.state, &piece.control, 3, &mut count, 0).unwrap();
        assert_eq!((count.vertices, written, count.quads), (15232, 15232, 18048));
        assert!(count.batches >= 9 && count.largest < count.vertices, "{} batches", count.batches);
    }
}
