//! The topology promise, kept by counts that share nothing with bcifs's
//! path (issue 56 §5): for random patterns of every cell kind (random
//! splits, masks, degrees, members near the classical one) and for every
//! shipped design, the Betti numbers bcifs reports, the mesh it writes (read
//! back from the OBJ file by a parser written here) and a count of the
//! pattern's cells on an integer lattice (exact: no coordinates, no
//! welding) must agree; porosities must equal a quadrature written here.
//!
//! The lattice count: a depth-`k` cell is the image of the unit cell under
//! the pattern's placements, kept as its corners' integer points; its faces,
//! edges and vertices are deduplicated by their sorted corners, so that the
//! complex is the union the constraints promise. `χ` is the alternating
//! count, `b0` its components through shared edges, `b2` the cavities (the
//! bounded components of the empty cells, across their open faces), and
//! `b1 = b0 + b2 − χ`. A solid's written mesh is its boundary with cells
//! that touch along an edge or at a corner only pulled apart: the boundary
//! faces, paired at an edge of four by their cell, each corner split by the
//! faces' fans around it; the surface has that `χ` and those pieces.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use bcifs::schemes::{Pattern, PatternCell};
use proptest::prelude::*;

/// A lattice point (up to four integer coordinates: a tetrahedron's are barycentric).
type Point = [i64; 4];

/// A depth-`k` cell: its corners, in the cell kind's order.
type Cell = Vec<Point>;

/// The kind of a pattern's cells, as far as the count goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Segment,
    Quad,
    Triangle,
    Cube,
    Tetrahedron,
}

impl Kind {
    fn of(cell: PatternCell) -> Kind {
        match cell {
            PatternCell::Segment => Kind::Segment,
            PatternCell::Quad => Kind::Quad,
            PatternCell::Triangle => Kind::Triangle,
            PatternCell::Hexahedron => Kind::Cube,
            PatternCell::Tetrahedron => Kind::Tetrahedron,
        }
    }

    fn dimension(self) -> usize {
        match self {
            Kind::Segment => 1,
            Kind::Quad | Kind::Triangle => 2,
            Kind::Cube | Kind::Tetrahedron => 3,
        }
    }

    /// The cell's faces of each dimension below its own, as lists of corner positions.
    fn boundary(self, dim: usize) -> Vec<Vec<usize>> {
        let pairs =
            |n: usize| -> Vec<Vec<usize>> { (0..n).flat_map(|a| (a + 1..n).map(move |b| vec![a, b])).collect() };
        match (self, dim) {
            (_, 0) => (0..self.corners()).map(|c| vec![c]).collect(),
            (Kind::Quad, 1) => vec![vec![0, 1], vec![1, 2], vec![2, 3], vec![3, 0]],
            (Kind::Triangle, 1) | (Kind::Tetrahedron, 1) => pairs(self.corners()),
            // Cube corners are numbered x + 2y + 4z: an edge joins corners one bit apart.
            (Kind::Cube, 1) => pairs(8).into_iter().filter(|p| (p[0] ^ p[1]).count_ones() == 1).collect(),
            (Kind::Cube, 2) => (0..3)
                .flat_map(|axis| {
                    (0..2).map(move |side| {
                        let mut f: Vec<usize> = (0..8).filter(|c| (c >> axis) & 1 == side).collect();
                        // In cyclic order: swap the last two of the four (bits of the two other axes).
                        f.swap(2, 3);
                        f
                    })
                })
                .collect(),
            (Kind::Tetrahedron, 2) => (0..4).map(|skip| (0..4).filter(|&c| c != skip).collect()).collect(),
            _ => vec![(0..self.corners()).collect()],
        }
    }

    fn corners(self) -> usize {
        match self {
            Kind::Segment => 2,
            Kind::Quad => 4,
            Kind::Triangle => 3,
            Kind::Cube => 8,
            Kind::Tetrahedron => 4,
        }
    }
}

/// The kept cells of a pattern's first level, as maps of the unit cell's
/// corners (at the scale `scale` of one level) into the parent's lattice.
struct Placements {
    kind: Kind,
    /// Each kept sub-cell's corners in the pattern's own unit lattice.
    kept: Vec<Cell>,
    /// Lattice units per cell side at one level.
    scale: i64,
}

impl Placements {
    fn of(p: &Pattern) -> Placements {
        let kind = Kind::of(p.cell);
        let mut kept = Vec::new();
        let mut all: Vec<Cell> = Vec::new();
        match kind {
            Kind::Segment => all.extend((0..p.split[0] as i64).map(|i| vec![[i, 0, 0, 0], [i + 1, 0, 0, 0]])),
            Kind::Quad => {
                for j in 0..p.split[1] as i64 {
                    for i in 0..p.split[0] as i64 {
                        all.push(vec![[i, j, 0, 0], [i + 1, j, 0, 0], [i + 1, j + 1, 0, 0], [i, j + 1, 0, 0]]);
                    }
                }
            }
            Kind::Triangle => {
                // Row by row from side AB, left to right: U(a, b), then D(a, b) where there is one.
                let n = p.split[0] as i64;
                for b in 0..n {
                    for a in 0..n - b {
                        all.push(vec![[a, b, 0, 0], [a + 1, b, 0, 0], [a, b + 1, 0, 0]]);
                        if a + b + 1 < n {
                            all.push(vec![[a + 1, b + 1, 0, 0], [a, b + 1, 0, 0], [a + 1, b, 0, 0]]);
                        }
                    }
                }
            }
            Kind::Cube => {
                let s = &p.split;
                for w in 0..s[2] as i64 {
                    for v in 0..s[1] as i64 {
                        for u in 0..s[0] as i64 {
                            all.push((0..8i64).map(|c| [u + (c & 1), v + (c >> 1 & 1), w + (c >> 2 & 1), 0]).collect());
                        }
                    }
                }
            }
            Kind::Tetrahedron => {
                // Corner j: the corner doubled, and the midpoints of its edges.
                for j in 0..4 {
                    all.push((0..4).map(|i| std::array::from_fn(|x| i64::from(x == i) + i64::from(x == j))).collect());
                }
            }
        }
        for (cell, &k) in all.into_iter().zip(&p.keep) {
            if k {
                kept.push(cell);
            }
        }
        // Cubes and quads may split unevenly (k × l × m): the lattice is per axis, one unit per part.
        let scale = match kind {
            Kind::Tetrahedron => 2,
            _ => p.split[0] as i64,
        };
        Placements { kind, kept, scale }
    }

    /// The depth-`k` cells: each level's kept sub-cells placed in its parent.
    fn cells(&self, split: &[usize], k: usize) -> Vec<Cell> {
        let unit: Cell = match self.kind {
            Kind::Segment => vec![[0, 0, 0, 0], [1, 0, 0, 0]],
            Kind::Quad => vec![[0, 0, 0, 0], [1, 0, 0, 0], [1, 1, 0, 0], [0, 1, 0, 0]],
            Kind::Triangle => vec![[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]],
            Kind::Cube => (0..8i64).map(|c| [c & 1, c >> 1 & 1, c >> 2 & 1, 0]).collect(),
            Kind::Tetrahedron => (0..4).map(|i| std::array::from_fn(|x| i64::from(x == i))).collect(),
        };
        let mut cells = vec![unit];
        for _ in 0..k {
            let mut next = Vec::with_capacity(cells.len() * self.kept.len());
            for cell in &cells {
                for sub in &self.kept {
                    next.push(self.place(cell, sub, split));
                }
            }
            cells = next;
        }
        let _ = self.scale;
        cells
    }

    /// The sub-cell `sub` (in the unit cell's lattice of one level) placed in `cell`, one level finer.
    fn place(&self, cell: &Cell, sub: &Cell, split: &[usize]) -> Cell {
        match self.kind {
            // Axis-aligned grids: the parent's origin scaled per axis, plus the part's place.
            Kind::Segment | Kind::Quad | Kind::Cube => {
                let o = cell[0];
                sub.iter()
                    .map(|q| std::array::from_fn(|x| if x < split.len() { o[x] * split[x] as i64 + q[x] } else { 0 }))
                    .collect()
            }
            // Affine: X = n·P0 + x (P1 − P0) + y (P2 − P0).
            Kind::Triangle => {
                let n = split[0] as i64;
                let (p0, p1, p2) = (cell[0], cell[1], cell[2]);
                sub.iter()
                    .map(|q| std::array::from_fn(|x| n * p0[x] + q[0] * (p1[x] - p0[x]) + q[1] * (p2[x] - p0[x])))
                    .collect()
            }
            // Barycentric: X = Σ_i q_i P_i (the sub-cell's weights on the parent's corners, doubled).
            Kind::Tetrahedron => {
                sub.iter().map(|q| std::array::from_fn(|x| (0..4).map(|i| q[i] * cell[i][x]).sum())).collect()
            }
        }
    }
}

/// What a complex of cells is: its counts and Betti numbers, and its pinches as bcifs counts them.
#[derive(Debug, PartialEq, Eq)]
struct Count {
    cells: usize,
    euler: i64,
    betti: [i64; 3],
    pinches: usize,
}

fn root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

fn join(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (root(parent, a), root(parent, b));
    parent[ra] = rb;
}

/// The complex of the union of `cells` (of `kind`), counted on the lattice.
fn count(kind: Kind, cells: &[Cell]) -> Count {
    let top = kind.dimension();
    // Every face of every dimension, by its sorted corners; and per cell, the faces it has.
    let mut faces: Vec<BTreeMap<Vec<Point>, usize>> = vec![BTreeMap::new(); top + 1];
    let mut keys: Vec<Vec<Vec<Point>>> = vec![Vec::new(); top + 1];
    let mut of_cell: Vec<Vec<Vec<usize>>> = Vec::with_capacity(cells.len());
    for cell in cells {
        let mut mine = vec![Vec::new(); top + 1];
        for (dim, slot) in mine.iter_mut().enumerate() {
            for f in kind.boundary(dim) {
                let mut key: Vec<Point> = f.iter().map(|&i| cell[i]).collect();
                key.sort_unstable();
                let n = faces[dim].len();
                let i = *faces[dim].entry(key.clone()).or_insert(n);
                if i == n {
                    keys[dim].push(key);
                }
                slot.push(i);
            }
        }
        of_cell.push(mine);
    }
    let euler: i64 =
        keys.iter().enumerate().map(|(d, f)| if d % 2 == 0 { f.len() as i64 } else { -(f.len() as i64) }).sum();
    let nv = keys[0].len();
    let vertex: HashMap<Point, usize> = keys[0].iter().enumerate().map(|(i, k)| (k[0], i)).collect();
    let mut parent: Vec<usize> = (0..nv).collect();
    for key in &keys[1] {
        join(&mut parent, vertex[&key[0]], vertex[&key[1]]);
    }
    let b0 = (0..nv).filter(|&v| root(&mut parent, v) == v).count() as i64;
    let b2 = if kind == Kind::Cube { cavities(cells) } else { 0 };
    // The cells at each face of each dimension.
    let mut at: Vec<Vec<Vec<usize>>> = keys.iter().map(|k| vec![Vec::new(); k.len()]).collect();
    for (c, mine) in of_cell.iter().enumerate() {
        for (dim, fs) in mine.iter().enumerate() {
            for &f in fs {
                at[dim][f].push(c);
            }
        }
    }
    // Pinches: surfaces, a vertex whose cells are not one group through the sides at it;
    // solids, a vertex whose cells are not one group through shared edges, an edge whose
    // cells are not one group through shared faces; curves, a vertex of three segments or more.
    let groups = |members: &[usize], linked: &dyn Fn(usize, usize) -> bool| {
        let mut p: Vec<usize> = (0..members.len()).collect();
        for a in 0..members.len() {
            for b in a + 1..members.len() {
                if linked(members[a], members[b]) {
                    join(&mut p, a, b);
                }
            }
        }
        (0..members.len()).filter(|&a| root(&mut p, a) == a).count()
    };
    let common = |a: usize, b: usize, dim: usize, through: Option<Point>| {
        of_cell[a][dim]
            .iter()
            .any(|f| of_cell[b][dim].contains(f) && through.is_none_or(|v| keys[dim][*f].contains(&v)))
    };
    let pinches = match top {
        1 => at[0].iter().filter(|cs| cs.len() > 2).count(),
        2 => (0..nv).filter(|&v| groups(&at[0][v], &|a, b| common(a, b, 1, Some(keys[0][v][0]))) > 1).count(),
        _ => {
            (0..nv).filter(|&v| groups(&at[0][v], &|a, b| common(a, b, 1, None)) > 1).count()
                + (0..keys[1].len()).filter(|&e| groups(&at[1][e], &|a, b| common(a, b, 2, None)) > 1).count()
        }
    };
    Count { cells: cells.len(), euler, betti: [b0, b0 + b2 - euler, b2], pinches }
}

/// The cavities of a union of unit cubes: the components of the empty
/// cubes of its box padded by one (joined across their faces, which no
/// kept cube holds), less the outside one.
fn cavities(cells: &[Cell]) -> i64 {
    let kept: BTreeSet<[i64; 3]> = cells.iter().map(|c| [c[0][0], c[0][1], c[0][2]]).collect();
    let lo = [0, 1, 2].map(|a| kept.iter().map(|p| p[a]).min().unwrap_or(0) - 1);
    let hi = [0, 1, 2].map(|a| kept.iter().map(|p| p[a]).max().unwrap_or(0) + 1);
    let size = [0, 1, 2].map(|a| (hi[a] - lo[a] + 1) as usize);
    let index =
        |p: [i64; 3]| ((p[2] - lo[2]) as usize * size[1] + (p[1] - lo[1]) as usize) * size[0] + (p[0] - lo[0]) as usize;
    let mut seen = vec![false; size.iter().product()];
    let mut components = 0;
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                let start = [x, y, z];
                if kept.contains(&start) || seen[index(start)] {
                    continue;
                }
                components += 1;
                let mut stack = vec![start];
                seen[index(start)] = true;
                while let Some(p) = stack.pop() {
                    for a in 0..3 {
                        for s in [-1, 1] {
                            let mut q = p;
                            q[a] += s;
                            if (0..3).all(|b| q[b] >= lo[b] && q[b] <= hi[b]) && !kept.contains(&q) && !seen[index(q)] {
                                seen[index(q)] = true;
                                stack.push(q);
                            }
                        }
                    }
                }
            }
        }
    }
    components - 1
}

/// The boundary surface of a union of volume cells with the cells that
/// touch along an edge or at a corner only pulled apart: `(χ, pieces)`.
fn split_boundary(kind: Kind, cells: &[Cell]) -> (i64, usize) {
    // Boundary faces: those of one cell only, with their cell.
    let mut owners: BTreeMap<Vec<Point>, Vec<usize>> = BTreeMap::new();
    for (c, cell) in cells.iter().enumerate() {
        for f in kind.boundary(2) {
            let mut key: Vec<Point> = f.iter().map(|&i| cell[i]).collect();
            key.sort_unstable();
            owners.entry(key).or_default().push(c);
        }
    }
    let boundary: Vec<(Vec<Point>, usize)> =
        owners.into_iter().filter(|(_, o)| o.len() == 1).map(|(k, o)| (k, o[0])).collect();
    // Per edge, the boundary faces along it, paired: two alone, else those of one cell.
    let mut along: BTreeMap<[Point; 2], Vec<usize>> = BTreeMap::new();
    for (f, (corners, _)) in boundary.iter().enumerate() {
        for e in edges_of(kind, corners) {
            along.entry(e).or_default().push(f);
        }
    }
    let mut pairs: Vec<(usize, usize, [Point; 2])> = Vec::new();
    let mut edges = 0i64;
    for (e, fs) in &along {
        edges += (fs.len() / 2) as i64;
        if fs.len() == 2 {
            pairs.push((fs[0], fs[1], *e));
        } else {
            for (i, &a) in fs.iter().enumerate() {
                for &b in &fs[i + 1..] {
                    if boundary[a].1 == boundary[b].1 {
                        pairs.push((a, b, *e));
                    }
                }
            }
        }
    }
    let mut parent: Vec<usize> = (0..boundary.len()).collect();
    for &(a, b, _) in &pairs {
        join(&mut parent, a, b);
    }
    let pieces = (0..boundary.len()).filter(|&f| root(&mut parent, f) == f).count();
    // Per corner, its boundary faces grouped through the pairs at an edge through it: one vertex a group.
    let mut at: BTreeMap<Point, Vec<usize>> = BTreeMap::new();
    for (f, (corners, _)) in boundary.iter().enumerate() {
        for &p in corners {
            at.entry(p).or_default().push(f);
        }
    }
    let mut vertices = 0i64;
    for (p, fs) in &at {
        let mut g: Vec<usize> = (0..fs.len()).collect();
        for &(a, b, e) in &pairs {
            if e.contains(p)
                && let (Some(i), Some(j)) = (fs.iter().position(|&x| x == a), fs.iter().position(|&x| x == b))
            {
                join(&mut g, i, j);
            }
        }
        vertices += (0..fs.len()).filter(|&i| root(&mut g, i) == i).count() as i64;
    }
    (vertices - edges + boundary.len() as i64, pieces)
}

/// The edges of a face (its corners sorted, as the keys are): for a square, the sides, not the diagonals.
fn edges_of(kind: Kind, corners: &[Point]) -> Vec<[Point; 2]> {
    let mut out = Vec::new();
    for (i, &a) in corners.iter().enumerate() {
        for &b in &corners[i + 1..] {
            let apart = (0..4).filter(|&x| a[x] != b[x]).count();
            if kind != Kind::Cube || apart == 1 {
                out.push([a.min(b), a.max(b)]);
            }
        }
    }
    out
}

/// A mesh read back from an OBJ file by the parser here: positions, faces, polylines.
#[derive(Default)]
struct Obj {
    positions: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    /// Per face: its corners, and the normal of each when given.
    faces: Vec<Vec<(usize, Option<usize>)>>,
    lines: Vec<Vec<usize>>,
}

fn read_obj(path: &std::path::Path) -> Obj {
    let text = std::fs::read_to_string(path).unwrap();
    let mut obj = Obj::default();
    let number = |t: &str| t.parse::<f64>().unwrap();
    for line in text.lines() {
        let mut t = line.split_whitespace();
        match t.next() {
            Some("v") => {
                obj.positions.push([number(t.next().unwrap()), number(t.next().unwrap()), number(t.next().unwrap())])
            }
            Some("vn") => {
                obj.normals.push([number(t.next().unwrap()), number(t.next().unwrap()), number(t.next().unwrap())])
            }
            Some("f") => obj.faces.push(
                t.map(|c| {
                    let mut parts = c.split('/');
                    let v = parts.next().unwrap().parse::<usize>().unwrap() - 1;
                    let n = parts.nth(1).and_then(|n| n.parse::<usize>().ok()).map(|n| n - 1);
                    (v, n)
                })
                .collect(),
            ),
            Some("l") => obj.lines.push(t.map(|c| c.parse::<usize>().unwrap() - 1).collect()),
            _ => {}
        }
    }
    obj
}

/// What the mesh says of itself: `χ` (used vertices − edges + faces, or − segments), pieces,
/// the faces an edge has (smallest, largest), whether every edge is run once each way, the
/// signed volume, and the vertices whose faces make more than one fan.
#[derive(Debug)]
struct MeshCount {
    euler: i64,
    pieces: usize,
    edge_faces: (usize, usize),
    oriented: bool,
    volume: f64,
    fans: usize,
}

fn mesh_count(obj: &Obj) -> MeshCount {
    let faces: Vec<Vec<usize>> = obj.faces.iter().map(|f| f.iter().map(|c| c.0).collect()).collect();
    let segments: Vec<[usize; 2]> = obj.lines.iter().flat_map(|l| l.windows(2).map(|w| [w[0], w[1]])).collect();
    let n = obj.positions.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut used = vec![false; n];
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &faces {
        for k in 0..f.len() {
            used[f[k]] = true;
            join(&mut parent, f[k], f[(k + 1) % f.len()]);
            *directed.entry((f[k], f[(k + 1) % f.len()])).or_default() += 1;
        }
    }
    let mut undirected: BTreeSet<(usize, usize)> = BTreeSet::new();
    for s in &segments {
        used[s[0]] = true;
        used[s[1]] = true;
        join(&mut parent, s[0], s[1]);
        undirected.insert((s[0].min(s[1]), s[0].max(s[1])));
    }
    let mut degree: HashMap<(usize, usize), usize> = HashMap::new();
    for (&(a, b), &c) in &directed {
        *degree.entry((a.min(b), a.max(b))).or_default() += c;
    }
    let oriented = directed.iter().all(|(&(a, b), &c)| c == 1 && directed.get(&(b, a)) == Some(&1));
    let edges = if faces.is_empty() { undirected.len() } else { degree.len() };
    let vertices = used.iter().filter(|u| **u).count();
    let pieces = (0..n).filter(|&v| used[v] && root(&mut parent, v) == v).count();
    let mut volume = 0.0;
    for f in &faces {
        let p = |i: usize| obj.positions[f[i]];
        for k in 1..f.len() - 1 {
            let (a, b, c) = (p(0), p(k), p(k + 1));
            volume += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
    }
    // Fans: around each vertex, its faces joined through the edges at it that they share.
    let mut around: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, f) in faces.iter().enumerate() {
        for &v in f {
            around.entry(v).or_default().push(i);
        }
    }
    let neighbours = |f: &[usize], v: usize| {
        let k = f.iter().position(|&x| x == v).unwrap();
        [f[(k + 1) % f.len()], f[(k + f.len() - 1) % f.len()]]
    };
    let fans = around
        .iter()
        .filter(|(v, fs)| {
            let mut g: Vec<usize> = (0..fs.len()).collect();
            for a in 0..fs.len() {
                for b in a + 1..fs.len() {
                    let (na, nb) = (neighbours(&faces[fs[a]], **v), neighbours(&faces[fs[b]], **v));
                    if na.iter().any(|x| nb.contains(x)) {
                        join(&mut g, a, b);
                    }
                }
            }
            (0..fs.len()).filter(|&i| root(&mut g, i) == i).count() > 1
        })
        .count();
    let faces_n = faces.len() as i64;
    let euler = vertices as i64 - edges as i64 + faces_n;
    let (lo, hi) = degree.values().fold((usize::MAX, 0), |(l, h), &d| (l.min(d), h.max(d)));
    MeshCount { euler, pieces, edge_faces: (lo, hi), oriented, volume: volume / 6.0, fans }
}

/// The face corners whose normal points against a triangle of the face
/// through that corner (of either diagonal of a quad: a client may split it
/// either way), at the vertices where some direction agrees with all of
/// their triangles: there the triangles' unit normals are pairwise less than
/// 90° apart, so their sum agrees with each. (At a fold — a quad whose two
/// halves face opposite ways — no normal can agree with both; it is not
/// counted.) Triangles of no area, to rounding, do not count.
fn normals_against_faces(obj: &Obj) -> usize {
    // Per vertex: each triangle's unit normal at it, with the vertex's normal in that face.
    type Pairs = Vec<([f64; 3], [f64; 3])>;
    let mut at: HashMap<usize, Pairs> = HashMap::new();
    for face in &obj.faces {
        let p = |i: usize| obj.positions[face[i].0];
        let n = face.len();
        let triangles: Vec<[usize; 3]> = match n {
            4 => vec![[0, 1, 2], [0, 2, 3], [0, 1, 3], [1, 2, 3]],
            _ => (1..n - 1).map(|k| [0, k, k + 1]).collect(),
        };
        for t in triangles {
            let [a, b, c] = t.map(p);
            let (u, v) = ([0, 1, 2].map(|x| b[x] - a[x]), [0, 1, 2].map(|x| c[x] - a[x]));
            let normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            let size = [u, v].iter().map(|w| w.iter().map(|x| x * x).sum::<f64>()).fold(0.0, f64::max);
            let len = normal.iter().map(|x| x * x).sum::<f64>();
            if len <= 1e-24 * size * size {
                continue;
            }
            let unit = normal.map(|x| x / len.sqrt());
            for &i in &t {
                if let Some(m) = face[i].1.map(|m| obj.normals[m]) {
                    at.entry(face[i].0).or_default().push((unit, m));
                }
            }
        }
    }
    let dot = |a: [f64; 3], b: [f64; 3]| (0..3).map(|x| a[x] * b[x]).sum::<f64>();
    at.values()
        .filter(|here| here.iter().all(|(a, _)| here.iter().all(|(b, _)| dot(*a, *b) > 0.0)))
        .map(|here| here.iter().filter(|(t, m)| dot(*t, *m) <= 0.0).count())
        .sum()
}

/// A pattern's design at `depth` with `params`, checked three ways: bcifs's
/// topology report, the OBJ file it writes (read here), and the lattice.
/// `Err` with the reason where the member cannot be evaluated (a fold, no
/// convergence): the case says nothing.
fn check_pattern(design: &bcifs::Design, p: &Pattern, params: &[(String, f64)], depth: usize) -> Result<(), String> {
    let report = bcifs::render::topology_report(design, params, depth).map_err(|e| e.to_string())?;
    let place = Placements::of(p);
    let cells = place.cells(&p.split, depth);
    let truth = count(place.kind, &cells);
    let shown: Vec<String> = params.iter().take(6).map(|(n, v)| format!("{n}={v:.4}")).collect();
    let more = if params.len() > 6 { format!(" and {} more", params.len() - 6) } else { String::new() };
    let shown = shown.join(", ");
    let what = format!(
        "{} split {:?} mask {} degree {} depth {depth} at {shown}{more}",
        p.cell.name(),
        p.split,
        p.mask(),
        p.degree
    );
    assert_eq!(
        (report.cells, report.euler, report.betti, report.pinches),
        (truth.cells, truth.euler, truth.betti, truth.pinches),
        "{what}: bcifs's topology report (left) against the lattice (right)"
    );
    let dir =
        std::env::temp_dir().join(format!("bcifs-oracle-{}-{:?}", std::process::id(), std::thread::current().id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("shape.obj");
    let options =
        bcifs::render::Options { params: params.to_vec(), ..bcifs::render::Options::default().with_depth(depth) };
    bcifs::render::render(design, &options, &file).map_err(|e| e.to_string())?;
    let obj = read_obj(&file);
    let mesh = mesh_count(&obj);
    assert_eq!(normals_against_faces(&obj), 0, "{what}: vertex normals against a face they belong to");
    std::fs::remove_dir_all(&dir).ok();
    match place.kind.dimension() {
        3 => {
            let (euler, pieces) = split_boundary(place.kind, &cells);
            assert_eq!(
                (mesh.euler, mesh.pieces),
                (euler, pieces),
                "{what}: the written boundary (left) against the lattice's, pinches pulled apart"
            );
            assert_eq!(mesh.edge_faces, (2, 2), "{what}: every edge of a solid's mesh in two faces");
            assert!(
                mesh.oriented && mesh.fans == 0,
                "{what}: oriented {}, {} vertices of several fans",
                mesh.oriented,
                mesh.fans
            );
            assert!(mesh.volume > 0.0, "{what}: the boundary faces inward (volume {})", mesh.volume);
        }
        _ => {
            assert_eq!(
                (mesh.euler, mesh.pieces, mesh.fans),
                (truth.euler, truth.betti[0] as usize, if place.kind.dimension() == 2 { truth.pinches } else { 0 }),
                "{what}: the written mesh (left) against the lattice"
            );
        }
    }
    Ok(())
}

/// A random pattern: a cell, a split, a mask keeping something, a degree.
fn pattern() -> impl Strategy<Value = Pattern> {
    let cell = prop_oneof![
        Just(PatternCell::Segment),
        Just(PatternCell::Quad),
        Just(PatternCell::Triangle),
        Just(PatternCell::Hexahedron),
        Just(PatternCell::Tetrahedron),
    ];
    cell.prop_flat_map(|cell| {
        let split: BoxedStrategy<Vec<usize>> = match cell {
            PatternCell::Segment => prop::collection::vec(2usize..=5, 1).boxed(),
            PatternCell::Quad => prop::collection::vec(2usize..=3, 2).boxed(),
            PatternCell::Triangle => prop::collection::vec(2usize..=3, 1).boxed(),
            PatternCell::Hexahedron => prop::collection::vec(2usize..=3, 3).boxed(),
            PatternCell::Tetrahedron => Just(vec![2]).boxed(),
        };
        let degree = match cell {
            PatternCell::Tetrahedron | PatternCell::Hexahedron => Just(2usize).boxed(),
            _ => (2usize..=4).boxed(),
        };
        (Just(cell), split, degree)
    })
    .prop_flat_map(|(cell, split, degree)| {
        let n = match cell {
            PatternCell::Triangle => split[0] * split[0],
            PatternCell::Tetrahedron => 4,
            _ => split.iter().product(),
        };
        (Just(cell), Just(split), prop::collection::vec(any::<bool>(), n), Just(degree))
    })
    .prop_filter("keeps a cell", |(_, _, keep, _)| keep.iter().any(|k| *k))
    .prop_map(|(cell, split, keep, degree)| {
        let split = split.iter().map(ToString::to_string).collect::<Vec<_>>().join("x");
        let mask: String = keep.iter().map(|&k| if k { '1' } else { '0' }).collect();
        Pattern::parse(cell, &split, Some(&mask), degree).unwrap()
    })
}

/// Members near the classical one: each free parameter moved from its default by up to 0.03.
fn member(design: &bcifs::Design, moves: &[f64]) -> Vec<(String, f64)> {
    let names = bcifs::solve(design).unwrap().parameter_names();
    names
        .into_iter()
        .zip(moves.iter().cycle())
        .map(|(name, m)| {
            let at = design.defaults().get(&name).copied().unwrap_or(0.0);
            (name, at + m)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, .. ProptestConfig::default() })]

    #[test]
    fn every_pattern_member_has_the_pattern_s_topology(
        p in pattern(),
        moves in prop::collection::vec(-0.03f64..0.03, 1..8),
        depth in 1usize..=3,
    ) {
        // As deep as a few thousand cells allow.
        let kept = p.keep.iter().filter(|k| **k).count();
        let depth = (1..=depth).rev().find(|&k| kept.pow(k as u32) <= 3000).unwrap_or(1);
        let design = p.design("oracle").unwrap();
        let params = member(&design, &moves);
        // Members that fold or do not converge say nothing about topology.
        if let Err(why) = check_pattern(&design, &p, &params, depth) {
            prop_assume!(false, "{}", why);
        }
    }
}

/// The pattern a shipped file was generated from, read off its first line
/// (`Generated by `bcifs new pattern --cell C --split S --keep M --degree D [--at A]``).
fn generated_from(text: &str) -> Option<Pattern> {
    let line = text.lines().next()?;
    let command = line.split('`').nth(1)?.strip_prefix("bcifs new pattern ")?;
    let words: Vec<&str> = command.split_whitespace().collect();
    let flag = |name: &str| words.iter().position(|w| *w == name).and_then(|i| words.get(i + 1)).copied();
    let cell = PatternCell::named(flag("--cell")?)?;
    let p = Pattern::parse(cell, flag("--split")?, flag("--keep"), flag("--degree")?.parse().ok()?).ok()?;
    match flag("--at") {
        Some(at) => p.with_at(at).ok(),
        None => Some(p),
    }
}

/// A shape bcifs writes for `design`, read back: its count against the
/// topology report, its closed pieces facing outward, its normals with
/// their faces.
fn check_written(design: &bcifs::Design, depth: usize) {
    let name = design.name().to_string();
    let dir = std::env::temp_dir().join(format!("bcifs-oracle-shipped-{}-{name}-{depth}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("shape.obj");
    bcifs::render::render(design, &bcifs::render::Options::default().with_depth(depth), &file).unwrap();
    let obj = read_obj(&file);
    std::fs::remove_dir_all(&dir).ok();
    let mesh = mesh_count(&obj);
    assert_eq!(normals_against_faces(&obj), 0, "{name} depth {depth}: vertex normals against a face they belong to");
    if mesh.edge_faces == (2, 2) && mesh.oriented {
        assert!(mesh.volume > 0.0, "{name} depth {depth}: a closed mesh facing inward (volume {})", mesh.volume);
    }
    let t = bcifs::render::topology_report(design, &[], depth).unwrap();
    if t.dimension < 3 && (!obj.faces.is_empty() || !obj.lines.is_empty()) {
        assert_eq!(
            (mesh.euler, mesh.pieces),
            (t.euler, t.components),
            "{name} depth {depth}: the file against the report"
        );
    }
}

#[test]
fn every_shipped_design_agrees_with_its_file_and_its_pattern_s_lattice() {
    let mut patterns = 0;
    for (name, text) in bcifs::BUILTIN_AUTOMATA {
        let design = bcifs::builtin_design(name).unwrap();
        let model = design.model().cloned().unwrap();
        let instance = bcifs::instantiate(&design, &[]).unwrap();
        let ev =
            bcifs::eval::Evaluator::new(&instance.automaton, &model, bcifs::eval::EvalSettings::default()).unwrap();
        if ev.polylines().is_none() && ev.cell_dimension() == 0 {
            continue; // points: a plain IFS has no cells to count
        }
        for depth in 1..=3usize {
            if ev.polygon_cells(depth).unwrap_or(0) > 20_000 || ev.estimate_bytes(depth) > 64 << 20 {
                break;
            }
            match generated_from(text) {
                Some(p) => {
                    let kept = p.keep.iter().filter(|k| **k).count();
                    if kept.pow(depth as u32) > 20_000 {
                        break;
                    }
                    check_pattern(&design, &p, &[], depth).unwrap();
                    patterns += usize::from(depth == 1);
                }
                None => check_written(&design, depth),
            }
        }
    }
    assert!(patterns >= 8, "the shipped patterns were read off their files: {patterns}");
    // The schemes' surfaces as IFS, closed or open.
    for name in ["bicubic", "box-spline", "box-spline-quad", "sqrt3-patch", "ternary5-surface", "ternary5-torus"] {
        let design = bcifs::render::ifs_preset(name, None, None).unwrap();
        for depth in [2, 3] {
            check_written(&design, depth);
        }
    }
}

/// A point of a Bézier curve of `points` at `t` (de Casteljau), `d` coordinates.
fn casteljau(points: &[Vec<f64>], t: f64) -> Vec<f64> {
    let mut p = points.to_vec();
    while p.len() > 1 {
        p = p.windows(2).map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| (1.0 - t) * a + t * b).collect()).collect();
    }
    p.remove(0)
}

/// A point of the root patch of a pattern's default model at `(u, v)`: its
/// `d × d` grid (index `d·row + col`) as a tensor Bézier patch, or its
/// triangle net (row by row from the first side) as a Bézier triangle at
/// the barycentric point `(1 − u − v, u, v)`.
fn root_patch(p: &Pattern, points: &[Vec<f64>], u: f64, v: f64) -> [f64; 3] {
    let d = p.degree;
    let q: Vec<f64> = match p.cell {
        PatternCell::Quad => {
            let rows: Vec<Vec<f64>> = (0..d).map(|r| casteljau(&points[r * d..(r + 1) * d], u)).collect();
            casteljau(&rows, v)
        }
        _ => {
            // De Casteljau on the net: each step a net one smaller, a point from three neighbours.
            let mut net: HashMap<(usize, usize), Vec<f64>> = HashMap::new();
            let mut i = 0;
            for b in 0..d {
                for a in 0..d - b {
                    net.insert((a, b), points[i].clone());
                    i += 1;
                }
            }
            for m in (1..d).rev() {
                let mut next = HashMap::new();
                for b in 0..m {
                    for a in 0..m - b {
                        let (o, x, y) = (&net[&(a, b)], &net[&(a + 1, b)], &net[&(a, b + 1)]);
                        next.insert((a, b), (0..o.len()).map(|c| (1.0 - u - v) * o[c] + u * x[c] + v * y[c]).collect());
                    }
                }
                net = next;
            }
            net.remove(&(0, 0)).unwrap()
        }
    };
    [q[0], q.get(1).copied().unwrap_or(0.0), q.get(2).copied().unwrap_or(0.0)]
}

/// `|S_u × S_v|` of the root patch at `(u, v)`, by central differences.
fn area_element(p: &Pattern, points: &[Vec<f64>], u: f64, v: f64) -> f64 {
    let h = 1e-6;
    let s = |u: f64, v: f64| root_patch(p, points, u, v);
    let (a, b, c, e) = (s(u + h, v), s(u - h, v), s(u, v + h), s(u, v - h));
    let su = [0, 1, 2].map(|x| (a[x] - b[x]) / (2.0 * h));
    let sv = [0, 1, 2].map(|x| (c[x] - e[x]) / (2.0 * h));
    let n = [su[1] * sv[2] - su[2] * sv[1], su[2] * sv[0] - su[0] * sv[2], su[0] * sv[1] - su[1] * sv[0]];
    n.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The area of the root patch over a cell of the parameter domain (its
/// corners `(u, v)`: a rectangle's four or a triangle's three): the midpoint
/// rule on `m × m` and `2m × 2m` splits of it, extrapolated (Richardson:
/// the rule's error is `O(h²)`, the extrapolation's `O(h⁴)`).
fn patch_area(p: &Pattern, points: &[Vec<f64>], corners: &[[f64; 2]], m: usize) -> f64 {
    (4.0 * midpoint_area(p, points, corners, 2 * m) - midpoint_area(p, points, corners, m)) / 3.0
}

/// [`patch_area`] by the midpoint rule on an `m × m` split.
fn midpoint_area(p: &Pattern, points: &[Vec<f64>], corners: &[[f64; 2]], m: usize) -> f64 {
    let mut sum = 0.0;
    if corners.len() == 4 {
        let (u0, v0, du, dv) =
            (corners[0][0], corners[0][1], corners[2][0] - corners[0][0], corners[2][1] - corners[0][1]);
        for j in 0..m {
            for i in 0..m {
                let (u, v) = (u0 + du * (i as f64 + 0.5) / m as f64, v0 + dv * (j as f64 + 0.5) / m as f64);
                sum += area_element(p, points, u, v) * (du * dv).abs() / (m * m) as f64;
            }
        }
        return sum;
    }
    // A triangle: its m² sub-triangles (upward and downward), each by its centroid.
    let [a, b, c] = [corners[0], corners[1], corners[2]];
    let at = |x: f64, y: f64| [0, 1].map(|k| a[k] + x / m as f64 * (b[k] - a[k]) + y / m as f64 * (c[k] - a[k]));
    let area = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() / 2.0 / (m * m) as f64;
    for y in 0..m {
        for x in 0..m - y {
            let centroids =
                [((x as f64) + 1.0 / 3.0, (y as f64) + 1.0 / 3.0), ((x as f64) + 2.0 / 3.0, (y as f64) + 2.0 / 3.0)];
            for (k, (cx, cy)) in centroids.into_iter().enumerate() {
                if k == 1 && x + y + 1 >= m {
                    continue;
                }
                let q = at(cx, cy);
                sum += area_element(p, points, q[0], q[1]) * area;
            }
        }
    }
    sum
}

/// A random quadrilateral or triangle pattern with a curved classical member.
fn surface_pattern() -> impl Strategy<Value = Pattern> {
    (prop_oneof![Just(PatternCell::Quad), Just(PatternCell::Triangle)], 2usize..=3, 2usize..=3, 2usize..=4)
        .prop_flat_map(|(cell, k, l, degree)| {
            let n = if cell == PatternCell::Quad { k * l } else { k * k };
            (Just((cell, k, l, degree)), prop::collection::vec(any::<bool>(), n))
        })
        .prop_filter("keeps a cell", |(_, keep)| keep.iter().any(|k| *k))
        .prop_map(|((cell, k, l, degree), keep)| {
            let split = if cell == PatternCell::Quad { format!("{k}x{l}") } else { k.to_string() };
            let mask: String = keep.iter().map(|&k| if k { '1' } else { '0' }).collect();
            Pattern::parse(cell, &split, Some(&mask), degree).unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, failure_persistence: None, .. ProptestConfig::default() })]

    /// The porosity of a curved lace's classical member is the share of its
    /// root patch's area its depth-k cells leave empty, integrated here on
    /// the patch's parameter domain (the cells are the patch over the pattern's
    /// sub-rectangles or sub-triangles).
    #[test]
    fn porosity_is_the_empty_share_of_the_curved_patch(p in surface_pattern(), depth in 1usize..=2) {
        let design = p.design("oracle").unwrap();
        let points = design.model().unwrap().points.clone();
        let place = Placements::of(&p);
        let scale = |x: usize| p.split[x.min(p.split.len() - 1)].pow(depth as u32) as f64;
        let unit: Vec<[f64; 2]> = match p.cell {
            PatternCell::Quad => vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            _ => vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        };
        let whole = patch_area(&p, &points, &unit, 48);
        let kept: f64 = place
            .cells(&p.split, depth)
            .iter()
            .map(|c| {
                let corners: Vec<[f64; 2]> = c.iter().map(|q| [q[0] as f64 / scale(0), q[1] as f64 / scale(1)]).collect();
                patch_area(&p, &points, &corners, 8)
            })
            .sum();
        let expected = 1.0 - kept / whole;
        let measured = *bcifs::report::porosity(&design, &[], depth).unwrap().last().unwrap();
        prop_assert!(
            (measured - expected).abs() < 1e-6,
            "{} {:?} {} degree {} depth {depth}: bcifs {measured} against the quadrature here {expected}",
            p.cell.name(), p.split, p.mask(), p.degree
        );
    }
}

#[test]
fn the_saddle_carpet_s_porosity_is_its_curved_area_s() {
    // The shipped carpet lies on a saddle (a twisted bilinear patch): its holes' share of the curved area.
    let carpet = bcifs::builtin_design("carpet").unwrap();
    let p = generated_from(bcifs::BUILTIN_AUTOMATA.iter().find(|(n, _)| *n == "carpet").unwrap().1).unwrap();
    let points = carpet.model().unwrap().points.clone();
    let whole = patch_area(&p, &points, &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 64);
    let measured = bcifs::report::porosity(&carpet, &[], 3).unwrap();
    let place = Placements::of(&p);
    for depth in 1..=3usize {
        let n = 3f64.powi(depth as i32);
        let kept: f64 = place
            .cells(&p.split, depth)
            .iter()
            .map(|c| {
                patch_area(
                    &p,
                    &points,
                    &[
                        [c[0][0] as f64 / n, c[0][1] as f64 / n],
                        [0.0; 2],
                        [c[2][0] as f64 / n, c[2][1] as f64 / n],
                        [0.0; 2],
                    ],
                    8,
                )
            })
            .sum();
        let expected = 1.0 - kept / whole;
        assert!(
            (measured[depth - 1] - expected).abs() < 1e-6,
            "depth {depth}: {} against {expected}",
            measured[depth - 1]
        );
    }
    // The figures: 0.1073, 0.2062, 0.2943 (the flat corner polygons gave 0.1615, 0.2596, 0.3424).
    for (m, e) in measured.iter().zip([0.1073, 0.2062, 0.2943]) {
        assert!((m - e).abs() < 5e-5, "{measured:?}");
    }
    // A pattern that keeps everything leaves nothing empty, on any patch.
    for (cell, split, degree) in
        [(PatternCell::Quad, "3x3", 4), (PatternCell::Triangle, "3", 4), (PatternCell::Segment, "4", 3)]
    {
        let all = Pattern::parse(cell, split, None, degree).unwrap().design("all").unwrap();
        for p in bcifs::report::porosity(&all, &[], 2).unwrap() {
            assert!(p.abs() < 1e-9, "{} keeps every cell: porosity {p}", cell.name());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, failure_persistence: None, .. ProptestConfig::default() })]

    /// Hexahedron patterns on the uniform B-spline (their matrices fixed:
    /// the tricubic volumes' members are the lattice's), counted as above.
    #[test]
    fn b_spline_solids_have_the_pattern_s_topology(
        split in prop::collection::vec(2usize..=3, 3),
        bits in prop::collection::vec(any::<bool>(), 27),
        degree in 3usize..=4,
        depth in 1usize..=2,
    ) {
        let n: usize = split.iter().product();
        let mask: String = bits[..n].iter().map(|&k| if k { '1' } else { '0' }).collect();
        prop_assume!(mask.contains('1'));
        let split_text = split.iter().map(ToString::to_string).collect::<Vec<_>>().join("x");
        let p = Pattern::parse_in(PatternCell::Hexahedron, &split_text, Some(&mask), degree, bcifs::schemes::Basis::BSpline);
        let Ok(p) = p else { return Ok(()) }; // over the size the fixed matrices may take
        let design = p.design("oracle").unwrap();
        if let Err(why) = check_pattern(&design, &p, &[], depth) {
            prop_assume!(false, "{}", why);
        }
    }
}
