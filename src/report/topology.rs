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
    /// The cells of the union's top dimension: volumes, faces (quads and triangles), segments, or points.
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
        let c = super::homology::solid(&cells);
        return Ok(TopologyReport {
            depth,
            cells: c.cells,
            dimension: 3,
            vertices: c.vertices,
            edges: c.edges,
            components: c.components,
            euler: c.euler,
            betti: c.betti,
            pinches: c.pinches,
        });
    }
    let shape = ev.evaluate()?;
    Ok(topology_of(&shape, depth))
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
