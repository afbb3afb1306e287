//! The topology of a union of volume cells (a porous solid at depth k): its
//! Betti numbers from the ranks of the boundary maps of its cell complex
//! (cells, their faces, edges and vertices, each once), over GF(2). For a
//! compact polyhedron in space these are the rational ones: its homology
//! has no torsion (Alexander duality).

use std::collections::HashMap;

/// What [`solid`] counts (the topology report's numbers for a solid).
pub(super) struct SolidCounts {
    pub cells: usize,
    pub vertices: usize,
    pub edges: usize,
    pub components: usize,
    pub euler: i64,
    pub betti: [i64; 3],
    pub pinches: usize,
}

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
fn pinches(c: &Complex) -> usize {
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
pub(super) fn solid(cells: &[Vec<Vec<usize>>]) -> SolidCounts {
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
    SolidCounts {
        cells: n,
        vertices: v,
        edges: e,
        components,
        euler,
        betti: [components as i64, (e - r1 - r2) as i64, (f - r2 - r3) as i64],
        pinches: pinches(&c),
    }
}
