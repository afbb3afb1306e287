//! The topology of a design's depth-k cells (issue 44 §4): the cells kept,
//! the connected components, the Euler characteristic and the Betti numbers
//! of their union, computed on the welded cells bcifs writes (vertices
//! shared through the constraints, not merged by distance).

use std::collections::{BTreeSet, HashMap};

use super::error::ReportError;
use crate::design::Design;
use crate::family::instantiate;
use crate::geometry::Shape;

/// What the depth-k cells of a design make.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TopologyReport {
    /// The depth.
    pub depth: usize,
    /// The cells of the union's top dimension: volumes, faces (polygons), segments, or points.
    pub cells: usize,
    /// The dimension of those cells: 3, 2, 1 or 0.
    pub dimension: usize,
    /// Distinct vertices.
    pub vertices: usize,
    /// Distinct edges (for faces: sides; for curves: segments).
    pub edges: usize,
    /// Connected components (`b0`).
    pub components: usize,
    /// `V − E + F` (`− C` for volumes).
    pub euler: i64,
    /// `[b0, b1, b2]`: components, independent loops (holes of a lace, tunnels of a
    /// solid), enclosed voids (closed surfaces: `b2` is the number of components every
    /// edge of which has two faces; solids: the ranks of their complex's boundary maps).
    pub betti: [i64; 3],
    /// Vertices where the cells meet at a single point (a pinch), the union not a manifold there.
    pub pinches: usize,
}

/// The topology of `design`'s cells at depth `depth` (parameters `params`).
///
/// ```
/// let carpet = bcifs::builtin_design("carpet").unwrap();
/// let t = bcifs::report::topology_report(&carpet, &[], 2)?;
/// assert_eq!((t.cells, t.components, t.euler, t.betti), (64, 1, 1 - 9, [1, 9, 0]));
/// # Ok::<(), bcifs::report::ReportError>(())
/// ```
///
/// # Errors
/// No model, parameters, evaluation (a depth whose cells would not fit memory is refused).
pub fn topology_report(design: &Design, params: &[(String, f64)], depth: usize) -> Result<TopologyReport, ReportError> {
    use crate::eval::{EvalSettings, Evaluator};
    let instance = instantiate(design, params)?;
    let model = super::error::model_of(design)?;
    let ev = Evaluator::new(&instance.automaton, &model, EvalSettings::default().with_depth(depth))?;
    let cells = ev.volume_cells(depth)?;
    if !cells.is_empty() {
        return Ok(solid(&cells, depth));
    }
    let shape = ev.evaluate()?;
    let mut report = topology_of(&shape, depth);
    // Cells of more than four corners are written as fans: count them once, without their diagonals.
    if let Some(cells) = ev.polygon_cells(depth).and_then(|c| usize::try_from(c).ok())
        && cells < report.cells
    {
        report.edges -= report.cells - cells;
        report.cells = cells;
    }
    Ok(report)
}

/// The topology of an evaluated shape (its faces, else its polylines, else its points).
pub fn topology_of(shape: &Shape, depth: usize) -> TopologyReport {
    let mut faces: Vec<Vec<usize>> = shape.quads.iter().map(|q| q.iter().map(|&v| v as usize).collect()).collect();
    faces.extend(shape.triangles.iter().map(|t| t.to_vec()));
    if !faces.is_empty() {
        return surface(&faces, depth);
    }
    let segments: Vec<[usize; 2]> = shape
        .polylines()
        .flat_map(|(first, count, closed)| {
            let open = (first..first + count.saturating_sub(1)).map(|i| [i, i + 1]);
            open.chain((closed && count > 2).then_some([first + count - 1, first]))
        })
        .collect();
    if !segments.is_empty() {
        return curve(&segments, depth);
    }
    let n = shape.vertex_count();
    TopologyReport {
        depth,
        cells: n,
        dimension: 0,
        vertices: n,
        edges: 0,
        components: n,
        euler: n as i64,
        betti: [n as i64, 0, 0],
        pinches: 0,
    }
}

/// Union-find over vertex numbers.
struct Components(HashMap<usize, usize>);

impl Components {
    fn root(&mut self, v: usize) -> usize {
        let p = *self.0.entry(v).or_insert(v);
        if p == v {
            return v;
        }
        let r = self.root(p);
        self.0.insert(v, r);
        r
    }
    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        self.0.insert(ra, rb);
    }
}

fn curve(segments: &[[usize; 2]], depth: usize) -> TopologyReport {
    let mut parts = Components(HashMap::new());
    let mut edges = BTreeSet::new();
    let mut degree: HashMap<usize, usize> = HashMap::new();
    for &[a, b] in segments {
        parts.join(a, b);
        if edges.insert((a.min(b), a.max(b))) {
            *degree.entry(a).or_default() += 1;
            *degree.entry(b).or_default() += 1;
        }
    }
    let vertices: Vec<usize> = degree.keys().copied().collect();
    let components = vertices.iter().map(|&v| parts.root(v)).collect::<BTreeSet<_>>().len();
    let euler = vertices.len() as i64 - edges.len() as i64;
    TopologyReport {
        depth,
        cells: edges.len(),
        dimension: 1,
        vertices: vertices.len(),
        edges: edges.len(),
        components,
        euler,
        betti: [components as i64, components as i64 - euler, 0],
        pinches: degree.values().filter(|&&d| d > 2).count(),
    }
}

fn surface(faces: &[Vec<usize>], depth: usize) -> TopologyReport {
    let mut parts = Components(HashMap::new());
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    let mut corners: HashMap<usize, Vec<usize>> = HashMap::new();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            parts.join(a, b);
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            corners.entry(a).or_default().push(f);
        }
    }
    let vertices: Vec<usize> = corners.keys().copied().collect();
    let mut roots: HashMap<usize, bool> = HashMap::new();
    for &v in &vertices {
        roots.insert(parts.root(v), true);
    }
    // A component is closed when every one of its edges has two faces.
    for (&(a, _), &n) in &edges {
        if n != 2 {
            let r = parts.root(a);
            roots.insert(r, false);
        }
    }
    let components = roots.len();
    let closed = roots.values().filter(|&&c| c).count();
    let euler = vertices.len() as i64 - edges.len() as i64 + faces.len() as i64;
    TopologyReport {
        depth,
        cells: faces.len(),
        dimension: 2,
        vertices: vertices.len(),
        edges: edges.len(),
        components,
        euler,
        betti: [components as i64, components as i64 + closed as i64 - euler, closed as i64],
        pinches: pinches(faces, &corners),
    }
}

/// Vertices whose faces do not make one fan joined through shared sides:
/// the cells meet there at a point only.
fn pinches(faces: &[Vec<usize>], corners: &HashMap<usize, Vec<usize>>) -> usize {
    let side = |f: usize, v: usize| -> [usize; 2] {
        let face = &faces[f];
        let k = face.iter().position(|&x| x == v).unwrap_or(0);
        [face[(k + face.len() - 1) % face.len()], face[(k + 1) % face.len()]]
    };
    corners
        .iter()
        .filter(|(v, fs)| {
            // The faces around v joined when they share a side through v.
            let mut around = Components(HashMap::new());
            for (i, &f) in fs.iter().enumerate() {
                around.root(f);
                for &g in &fs[i + 1..] {
                    if side(f, **v).iter().any(|n| side(g, **v).contains(n)) {
                        around.join(f, g);
                    }
                }
            }
            fs.iter().map(|&f| around.root(f)).collect::<BTreeSet<_>>().len() > 1
        })
        .count()
}

// Solids: the Betti numbers of a union of volume cells (a porous solid at
// depth k) from the ranks of the boundary maps of its cell complex (cells,
// faces, edges, vertices, each once), over GF(2). For a compact polyhedron
// in space these are the rational ones: its homology has no torsion
// (Alexander duality).

/// The complex of volume cells, each given by its faces (cycles of vertex numbers).
struct Complex {
    vertices: usize,
    /// Each edge's two vertices (numbered here).
    edges: Vec<[u32; 2]>,
    /// Each face's edges, sorted.
    faces: Vec<Vec<u32>>,
    /// Each cell's faces, sorted.
    cells: Vec<Vec<u32>>,
}

impl Complex {
    fn of(cells: &[Vec<Vec<usize>>]) -> Complex {
        let mut vertex: HashMap<usize, u32> = HashMap::new();
        let mut edge: HashMap<(u32, u32), u32> = HashMap::new();
        let mut face: HashMap<Vec<u32>, u32> = HashMap::new();
        let (mut edges, mut faces, mut out) = (Vec::new(), Vec::new(), Vec::new());
        for cell in cells {
            let mut mine = Vec::new();
            for cycle in cell {
                let vs: Vec<u32> = cycle
                    .iter()
                    .map(|v| {
                        let n = vertex.len() as u32;
                        *vertex.entry(*v).or_insert(n)
                    })
                    .collect();
                let mut key = vs.clone();
                key.sort_unstable();
                let next = face.len() as u32;
                let f = *face.entry(key).or_insert_with(|| {
                    let mut sides: Vec<u32> = (0..vs.len())
                        .map(|k| {
                            let (a, b) = (vs[k], vs[(k + 1) % vs.len()]);
                            let n = edge.len() as u32;
                            *edge.entry((a.min(b), a.max(b))).or_insert_with(|| {
                                edges.push([a.min(b), a.max(b)]);
                                n
                            })
                        })
                        .collect();
                    sides.sort_unstable();
                    faces.push(sides);
                    next
                });
                mine.push(f);
            }
            mine.sort_unstable();
            out.push(mine);
        }
        Complex { vertices: vertex.len(), edges, faces, cells: out }
    }
}

/// The rank over GF(2) of the matrix of `columns` (each its sorted rows),
/// the columns with `skip` left out (known to reduce to zero), and the row
/// each reduced column ends at (its pivot).
fn rank(columns: &[Vec<u32>], rows: usize, skip: &[bool]) -> (usize, Vec<u32>) {
    let mut owner: Vec<Option<usize>> = vec![None; rows];
    let mut reduced: Vec<Vec<u32>> = Vec::with_capacity(columns.len());
    let mut pivots = Vec::new();
    for (j, column) in columns.iter().enumerate() {
        let mut col = if skip.get(j).copied().unwrap_or(false) { Vec::new() } else { column.clone() };
        while let Some(&low) = col.last() {
            match owner[low as usize] {
                Some(k) => col = xor(&col, &reduced[k]),
                None => {
                    owner[low as usize] = Some(j);
                    pivots.push(low);
                    break;
                }
            }
        }
        reduced.push(col);
    }
    (pivots.len(), pivots)
}

/// The symmetric difference of two sorted lists.
fn xor(a: &[u32], b: &[u32]) -> Vec<u32> {
    let (mut i, mut j, mut out) = (0, 0, Vec::with_capacity(a.len() + b.len()));
    while i < a.len() || j < b.len() {
        match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x == y => (i, j) = (i + 1, j + 1),
            (Some(x), Some(y)) if x < y => {
                out.push(*x);
                i += 1;
            }
            (Some(_), Some(y)) | (None, Some(y)) => {
                out.push(*y);
                j += 1;
            }
            (Some(x), None) => {
                out.push(*x);
                i += 1;
            }
            (None, None) => break,
        }
    }
    out
}

/// Union-find over numbers.
fn root(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        parent[v as usize] = parent[parent[v as usize] as usize];
        v = parent[v as usize];
    }
    v
}

/// Places where cells meet but are not joined around it: a vertex whose
/// cells do not make one group through shared edges, an edge whose cells
/// do not through shared faces (the union is not a manifold there).
fn solid_pinches(c: &Complex) -> usize {
    // Cells around each vertex and each edge, and the faces and edges each cell has.
    let mut at_vertex: Vec<Vec<u32>> = vec![Vec::new(); c.vertices];
    let mut at_edge: Vec<Vec<u32>> = vec![Vec::new(); c.edges.len()];
    let cell_edges: Vec<Vec<u32>> = c
        .cells
        .iter()
        .map(|fs| {
            let mut es: Vec<u32> = fs.iter().flat_map(|&f| c.faces[f as usize].iter().copied()).collect();
            es.sort_unstable();
            es.dedup();
            es
        })
        .collect();
    for (k, es) in cell_edges.iter().enumerate() {
        let mut vs: Vec<u32> = es.iter().flat_map(|&e| c.edges[e as usize]).collect();
        vs.sort_unstable();
        vs.dedup();
        vs.iter().for_each(|&v| at_vertex[v as usize].push(k as u32));
        es.iter().for_each(|&e| at_edge[e as usize].push(k as u32));
    }
    let joined = |cells: &[u32], shared: &dyn Fn(u32, u32) -> bool| {
        let mut parent: Vec<u32> = (0..cells.len() as u32).collect();
        for a in 0..cells.len() {
            for b in a + 1..cells.len() {
                if shared(cells[a], cells[b]) {
                    let (ra, rb) = (root(&mut parent, a as u32), root(&mut parent, b as u32));
                    parent[ra as usize] = rb;
                }
            }
        }
        (0..cells.len() as u32).all(|a| root(&mut parent, a) == root(&mut parent, 0))
    };
    let common = |x: &[u32], y: &[u32]| x.iter().any(|e| y.binary_search(e).is_ok());
    let by_edges = |a: u32, b: u32| common(&cell_edges[a as usize], &cell_edges[b as usize]);
    let by_faces = |a: u32, b: u32| common(&c.cells[a as usize], &c.cells[b as usize]);
    at_vertex.iter().filter(|cells| !joined(cells, &by_edges)).count()
        + at_edge.iter().filter(|cells| !joined(cells, &by_faces)).count()
}

/// The topology of the union of volume `cells` (each its faces, cycles of
/// vertex numbers shared where the cells are welded).
fn solid(cells: &[Vec<Vec<usize>>], depth: usize) -> TopologyReport {
    let c = Complex::of(cells);
    let (v, e, f, n) = (c.vertices, c.edges.len(), c.faces.len(), c.cells.len());
    let mut parent: Vec<u32> = (0..v as u32).collect();
    for &[a, b] in &c.edges {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        parent[ra as usize] = rb;
    }
    let components = (0..v as u32).filter(|&x| root(&mut parent, x) == x).count();
    let r1 = v - components;
    // Cells first: the faces their reduced columns end at are boundaries, whose columns of
    // the next map reduce to zero (the clearing of persistent homology's algorithms).
    let (r3, pivots) = rank(&c.cells, f, &[]);
    let mut skip = vec![false; f];
    pivots.iter().for_each(|&p| skip[p as usize] = true);
    let (r2, _) = rank(&c.faces, e, &skip);
    let euler = v as i64 - e as i64 + f as i64 - n as i64;
    TopologyReport {
        depth,
        cells: n,
        dimension: 3,
        vertices: v,
        edges: e,
        components,
        euler,
        betti: [components as i64, (e - r1 - r2) as i64, (f - r2 - r3) as i64],
        pinches: solid_pinches(&c),
    }
}
