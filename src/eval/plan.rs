//! What evaluation needs to know about an automaton, computed once: vertex
//! fixed points, edge end points, face corners and sub-face layout, and
//! tables of the last levels of the subdivision tree.

use petgraph::stable_graph::{EdgeIndex, NodeIndex};

use crate::algebra::tolerance::{CONTRACTIVE, SAME_POINT, STOCHASTIC};
use crate::automaton::{ArrowKind, Automaton};
use crate::space::CellKind;

/// Why an automaton cannot be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// A column of a matrix does not sum to 1.
    #[error("arrow `{arrow}` is not stochastic: column {column} sums to {sum} (every column must sum to 1)")]
    NotStochastic {
        /// Arrow name.
        arrow: String,
        /// Column.
        column: usize,
        /// Its sum.
        sum: f64,
    },
    /// A column whose entries are so large (or not finite) that floating
    /// point cannot tell whether it sums to 1: the rounding of entries of
    /// `magnitude` is larger than 1.
    #[error(
        "arrow `{arrow}` cannot be evaluated in floating point: column {column} has entries of magnitude {magnitude:e}, whose sum of 1 is lost to rounding (such parameters make no contractive system)"
    )]
    Unrepresentable {
        /// Arrow name.
        arrow: String,
        /// Column.
        column: usize,
        /// The largest absolute entry (infinite or NaN when one is not finite).
        magnitude: f64,
    },
    /// A subdivision arrow has an eigenvalue of modulus ≥ 1 besides the eigenvalue 1.
    #[error(
        "arrow `{arrow}` is not contractive: eigenvalue of modulus {modulus:.6} besides the eigenvalue 1 (the attractor would not exist)"
    )]
    NotContractive {
        /// Arrow name.
        arrow: String,
        /// The largest modulus besides 1.
        modulus: f64,
    },
    /// The eigenvalue computation did not converge.
    #[error(
        "the eigenvalues of arrow `{0}` could not be computed (the Schur iteration stalled): contractivity is unknown"
    )]
    Spectrum(String),
    /// A vertex state without a subdivision arrow to itself (or one rule to another vertex state).
    #[error(
        "vertex state `{0}` needs a subdivision arrow to itself (its fixed point is the vertex), or one arrow to a vertex state that has one"
    )]
    NoVertexRule(String),
    /// An edge state without two boundary arrows to vertices.
    #[error("edge state `{0}` needs two boundary arrows to vertex states (its start and its end)")]
    NoEnds(String),
    /// A face whose boundary does not close into a polygon of corners.
    #[error("face state `{0}`: {1}")]
    BadFace(String, String),
    /// A volume whose boundary cells do not give it corners.
    #[error(
        "volume state `{0}` needs boundary arrows to faces (or edges) whose corners span it: it has {1} corner(s), at least 4 are needed"
    )]
    BadVolume(String, usize),
    /// A state with no subdivision arrow: its attractor is empty.
    #[error("state `{0}` has no subdivision arrow: nothing to evaluate")]
    Empty(String),
}

/// The evaluation plan of one state.
#[derive(Clone, Debug)]
pub struct StatePlan {
    /// Name.
    pub name: String,
    /// Dimension (control points).
    pub dim: usize,
    /// Kind.
    pub kind: CellKind,
    /// Subdivision arrows: `(arrow, target state index, matrix row-major dim × dim(target))`.
    pub children: Vec<(EdgeIndex, usize, Vec<f64>)>,
    /// Barycentric points emitted by a leaf cell (edge: its start; free: its
    /// sample points; face: its corners in cyclic order).
    pub samples: Vec<Vec<f64>>,
    /// Edges: barycentric end point (emitted once, after the last leaf).
    pub end: Option<Vec<f64>>,
    /// Faces: lattice offset `(du, dv)` of each child in a `split × split` grid.
    pub quadrants: Vec<(usize, usize)>,
    /// Faces: sub-faces per side (2 for a 2×2 split, 3 for a ternary scheme's 3×3).
    pub split: usize,
    /// Whether the state lies on a cycle of subdivision arrows (its cells are iterated).
    pub cyclic: bool,
    /// Faces over `samples` ([`crate::Model::start_faces`]): a leaf cell is meshed by them.
    pub faces: Vec<Vec<usize>>,
    /// Edges whose sub-edges do not chain end to start (a lacunar curve,
    /// the Cantor set's): a leaf emits both its ends, a segment of its own.
    pub gapped: bool,
    /// The patch its control points make, when the design says ([`crate::space::Patch`]).
    pub patch: Option<crate::space::Patch>,
}

/// The evaluation plan of an automaton.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Per state, indexed by `NodeIndex::index()`.
    pub states: Vec<Option<StatePlan>>,
}

fn fixed_point(m: &nalgebra::DMatrix<f64>) -> Option<Vec<f64>> {
    // Solve (M - I) λ = 0 with Σ λ = 1: replace the last equation by the sum.
    let n = m.nrows();
    let mut a = m - nalgebra::DMatrix::identity(n, n);
    let mut rhs = nalgebra::DVector::zeros(n);
    for j in 0..n {
        a[(n - 1, j)] = 1.0;
    }
    rhs[n - 1] = 1.0;
    a.lu().solve(&rhs).map(|v| v.iter().copied().collect())
}

fn mat_vec(m: &[f64], rows: usize, cols: usize, v: &[f64]) -> Vec<f64> {
    (0..rows).map(|i| (0..cols).map(|j| m[i * cols + j] * v[j]).sum()).collect()
}

/// Whether the sub-edges of an edge chain from its start `a` to its end
/// `b`, each starting where the one before ends (their ends from `ends`).
fn chains(plan: &StatePlan, a: &[f64], b: &[f64], ends: &dyn Fn(NodeIndex) -> Option<(Vec<f64>, Vec<f64>)>) -> bool {
    let mut at = a.to_vec();
    for (_, t, m) in &plan.children {
        let Some((ta, tb)) = ends(NodeIndex::new(*t)) else { return true };
        let lift = |v: &[f64]| -> Vec<f64> {
            (0..plan.dim).map(|i| (0..v.len()).map(|j| m[i * v.len() + j] * v[j]).sum()).collect()
        };
        if !close(&lift(&ta), &at) {
            return false;
        }
        at = lift(&tb);
    }
    plan.children.is_empty() || close(&at, b)
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < SAME_POINT)
}

impl Plan {
    /// Verifies that `automaton` is stochastic and contractive (every square
    /// subdivision loop), then computes what evaluation needs.
    ///
    /// # Errors
    /// A non-stochastic or non-contractive arrow, or a topology that cannot
    /// be evaluated (a vertex without rule, an edge without ends, a face
    /// that is not a 2×2 split in grid orientation).
    pub fn new(automaton: &Automaton<f64>, start_sets: &[(String, Vec<Vec<f64>>)]) -> Result<Plan, PlanError> {
        check_arrows(automaton)?;
        let vertex_point = vertex_points(automaton)?;
        // Barycentric ends of an edge state: b · v* for its first two boundary arrows.
        let ends = |edge: NodeIndex| -> Option<(Vec<f64>, Vec<f64>)> {
            let b: Vec<Vec<f64>> = automaton
                .outgoing(edge, ArrowKind::Boundary)
                .into_iter()
                .filter_map(|e| {
                    let to = automaton.arrow_ends(e).1;
                    let v = vertex_point[to.index()].as_ref()?;
                    let m = &automaton.arrow(e).matrix;
                    Some((0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)] * v[j]).sum()).collect())
                })
                .collect();
            (b.len() >= 2).then(|| (b[0].clone(), b[1].clone()))
        };
        let mut states = vec![None; vertex_point.len()];
        for (id, s) in automaton.states() {
            let children: Vec<(EdgeIndex, usize, Vec<f64>)> = automaton
                .outgoing(id, ArrowKind::Subdivision)
                .into_iter()
                .map(|e| {
                    let to = automaton.arrow_ends(e).1;
                    let m = &automaton.arrow(e).matrix;
                    let row_major = (0..m.nrows()).flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)])).collect();
                    (e, to.index(), row_major)
                })
                .collect();
            let mut plan = StatePlan {
                name: s.name.clone(),
                dim: s.dim,
                kind: s.kind,
                children,
                samples: Vec::new(),
                end: None,
                quadrants: Vec::new(),
                split: 0,
                cyclic: automaton.outgoing(id, ArrowKind::Subdivision).into_iter().any(|e| automaton.on_cycle(e)),
                faces: Vec::new(),
                gapped: false,
                patch: s.patch,
            };
            match s.kind {
                CellKind::Vertex => plan.samples = vertex_point[id.index()].iter().cloned().collect(),
                CellKind::Free => plan.samples = vec![vec![1.0 / s.dim as f64; s.dim]],
                CellKind::Edge => {
                    let (a, b) = ends(id).ok_or_else(|| PlanError::NoEnds(s.name.clone()))?;
                    if chains(&plan, &a, &b, &ends) {
                        plan.samples = vec![a];
                        plan.end = Some(b);
                    } else {
                        plan.samples = vec![a, b];
                        plan.gapped = true;
                    }
                }
                CellKind::Face => face_plan(automaton, id, &ends, &mut plan)?,
                CellKind::Volume => {
                    plan.samples = corners(automaton, id, &vertex_point, 3);
                    if plan.samples.len() < 4 {
                        return Err(PlanError::BadVolume(s.name.clone(), plan.samples.len()));
                    }
                }
            }
            if let Some((_, set)) = start_sets.iter().find(|(n, _)| *n == s.name) {
                plan.samples = set.clone();
                plan.end = None;
            }
            states[id.index()] = Some(plan);
        }
        volume_faces(automaton, start_sets, &mut states);
        Ok(Plan { states })
    }

    /// The plan of state `i`.
    pub fn state(&self, i: usize) -> &StatePlan {
        self.states[i].as_ref().expect("state index from this automaton")
    }
}

/// Every column of every arrow sums to 1, and every square subdivision
/// arrow has one eigenvalue 1 and all others of modulus < 1.
fn check_arrows(automaton: &Automaton<f64>) -> Result<(), PlanError> {
    for (id, arrow) in automaton.arrows() {
        for (j, col) in arrow.matrix.column_iter().enumerate() {
            let sum = col.sum();
            if (sum - 1.0).abs() > STOCHASTIC {
                let magnitude = col.iter().map(|x| if x.is_nan() { f64::NAN } else { x.abs() }).fold(0.0, f64::max);
                // A sum of n entries of this size is only known to within n ε magnitude.
                if !magnitude.is_finite() || magnitude * col.len() as f64 * f64::EPSILON > STOCHASTIC {
                    return Err(PlanError::Unrepresentable { arrow: arrow.name.clone(), column: j, magnitude });
                }
                return Err(PlanError::NotStochastic { arrow: arrow.name.clone(), column: j, sum });
            }
        }
        if arrow.kind == ArrowKind::Subdivision
            && arrow.matrix.is_square()
            && automaton.on_cycle(id)
            && !crate::algebra::contracts_by_norm(&arrow.matrix, CONTRACTIVE)
        {
            let eig =
                crate::algebra::eigenvalues(&arrow.matrix).ok_or_else(|| PlanError::Spectrum(arrow.name.clone()))?;
            if !crate::algebra::contractive_spectrum(&eig, CONTRACTIVE) {
                // The largest modulus once the eigenvalue nearest 1 is set aside.
                let one = (0..eig.len()).min_by(|&a, &b| (eig[a] - 1.0).norm().total_cmp(&(eig[b] - 1.0).norm()));
                let modulus = (0..eig.len())
                    .filter(|&i| Some(i) != one || eig.len() == 1)
                    .map(|i| eig[i].norm())
                    .fold(0.0, f64::max);
                return Err(PlanError::NotContractive { arrow: arrow.name.clone(), modulus });
            }
        }
    }
    Ok(())
}

/// The fixed point of each vertex state's own rule (indexed by state), `None`
/// for other states. A vertex state whose one rule leads to another vertex
/// state (a mesh vertex whose faces become quads after a step) has the image
/// of that state's point.
fn vertex_points(automaton: &Automaton<f64>) -> Result<Vec<Option<Vec<f64>>>, PlanError> {
    let size = automaton.states().map(|(i, _)| i.index() + 1).max().unwrap_or(0);
    let mut vertex_point: Vec<Option<Vec<f64>>> = vec![None; size];
    let mut chained = Vec::new();
    for (id, s) in automaton.states() {
        if s.kind == CellKind::Vertex {
            let rules = automaton.outgoing(id, ArrowKind::Subdivision);
            match rules.iter().find(|e| automaton.arrow_ends(**e).1 == id) {
                Some(rule) => vertex_point[id.index()] = fixed_point(&automaton.arrow(*rule).matrix),
                None if rules.len() == 1 => chained.push((id, rules[0])),
                None => return Err(PlanError::NoVertexRule(s.name.clone())),
            }
        }
    }
    // Follow the chains (each pass settles at least one state, or none can be).
    while !chained.is_empty() {
        let before = chained.len();
        chained.retain(|&(id, e)| {
            let to = automaton.arrow_ends(e).1;
            let Some(v) = vertex_point[to.index()].clone() else { return true };
            let m = &automaton.arrow(e).matrix;
            vertex_point[id.index()] =
                Some((0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)] * v[j]).sum()).collect());
            false
        });
        if chained.len() == before {
            return Err(PlanError::NoVertexRule(automaton.state(chained[0].0).name.clone()));
        }
    }
    Ok(vertex_point)
}

/// The faces of each volume (without start sets): its boundary faces'
/// corner cycles, lifted into the volume and numbered as its corners, so a
/// leaf volume is meshed by its boundary (see [`StatePlan::faces`]).
fn volume_faces(automaton: &Automaton<f64>, start_sets: &[(String, Vec<Vec<f64>>)], states: &mut [Option<StatePlan>]) {
    for (id, s) in automaton.states() {
        if s.kind != CellKind::Volume || start_sets.iter().any(|(n, _)| *n == s.name) {
            continue;
        }
        let mut faces = Vec::new();
        for e in automaton.outgoing(id, ArrowKind::Boundary) {
            let to = automaton.arrow_ends(e).1;
            let Some(face) = states[to.index()].as_ref().filter(|f| f.kind == CellKind::Face) else { continue };
            let m = &automaton.arrow(e).matrix;
            let Some(plan) = states[id.index()].as_ref() else { continue };
            let cycle: Option<Vec<usize>> = face
                .samples
                .iter()
                .map(|c| {
                    let lifted: Vec<f64> =
                        (0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)] * c[j]).sum()).collect();
                    plan.samples.iter().position(|x| close(x, &lifted))
                })
                .collect();
            if let Some(cycle) = cycle.filter(|c| c.len() >= 3) {
                faces.push(cycle);
            }
        }
        if let Some(plan) = states[id.index()].as_mut() {
            plan.faces = faces;
        }
    }
}

/// The corners of a cell: its vertices' points lifted through the boundary
/// arrows down to them (`levels` at most), each once: a volume's are its
/// faces' corners.
fn corners(
    automaton: &Automaton<f64>,
    id: NodeIndex,
    vertex_point: &[Option<Vec<f64>>],
    levels: usize,
) -> Vec<Vec<f64>> {
    if let Some(v) = &vertex_point[id.index()] {
        return vec![v.clone()];
    }
    let mut out: Vec<Vec<f64>> = Vec::new();
    if levels == 0 {
        return out;
    }
    for e in automaton.outgoing(id, ArrowKind::Boundary) {
        let to = automaton.arrow_ends(e).1;
        let m = &automaton.arrow(e).matrix;
        for c in corners(automaton, to, vertex_point, levels - 1) {
            let lifted: Vec<f64> = (0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)] * c[j]).sum()).collect();
            if !out.iter().any(|x| close(x, &lifted)) {
                out.push(lifted);
            }
        }
    }
    out
}

/// The corners of a face (its boundary edges' ends, walked as a cycle),
/// then the placement of its sub-faces.
fn face_plan(
    automaton: &Automaton<f64>,
    id: NodeIndex,
    ends: &dyn Fn(NodeIndex) -> Option<(Vec<f64>, Vec<f64>)>,
    plan: &mut StatePlan,
) -> Result<(), PlanError> {
    let bad = |why: &str| PlanError::BadFace(plan.name.clone(), why.to_string());
    // Corner pairs of each boundary edge, in face coordinates.
    let mut sides: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    for e in automaton.outgoing(id, ArrowKind::Boundary) {
        let to = automaton.arrow_ends(e).1;
        let (a, b) = ends(to).ok_or_else(|| bad("every boundary arrow must lead to an edge with two ends"))?;
        let m = &automaton.arrow(e).matrix;
        let lift = |v: &[f64]| -> Vec<f64> {
            (0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)] * v[j]).sum()).collect()
        };
        sides.push((lift(&a), lift(&b)));
    }
    let mut corners: Vec<Vec<f64>> = Vec::new();
    for (a, b) in &sides {
        for c in [a, b] {
            if !corners.iter().any(|x| close(x, c)) {
                corners.push(c.clone());
            }
        }
    }
    let index = |c: &[f64]| corners.iter().position(|x| close(x, c)).expect("collected");
    // Walk the cycle of corners along the sides.
    let mut cycle = vec![0usize];
    let mut used = vec![false; sides.len()];
    loop {
        let here = *cycle.last().expect("non-empty");
        let next = sides.iter().enumerate().find_map(|(k, (a, b))| {
            if used[k] {
                return None;
            }
            let (ia, ib) = (index(a), index(b));
            if ia == here {
                Some((k, ib))
            } else if ib == here {
                Some((k, ia))
            } else {
                None
            }
        });
        match next {
            Some((k, c)) => {
                used[k] = true;
                if c == cycle[0] {
                    break;
                }
                cycle.push(c);
            }
            None => return Err(bad("its boundary edges do not close into a cycle of corners")),
        }
    }
    // Two corners make a lens (Doo-Sabin's patch of a vertex of valence 2): its two sides end at
    // the same corners, its neighbours meet along them, and its corner polygon has no face.
    if cycle.len() < 2 || cycle.len() != corners.len() {
        return Err(bad(&format!("its {} corners do not make one polygon", corners.len())));
    }
    plan.samples = cycle.iter().map(|&i| corners[i].clone()).collect();
    // A 2 × 2 (p × p) split of one state is meshed as a lattice; other faces
    // (several states, triangles, n-gons: a mesh's generated automaton) as
    // their corner polygons (`split` 0).
    if cycle.len() == 4 && place_sub_faces(id, plan).is_ok() {
        return Ok(());
    }
    plan.quadrants.clear();
    plan.split = 0;
    Ok(())
}

/// Places the sub-faces of a face as a `p × p` grid keeping its orientation
/// (`plan.quadrants`, `plan.split`), from its corners (`plan.samples`).
fn place_sub_faces(id: NodeIndex, plan: &mut StatePlan) -> Result<(), PlanError> {
    let bad = |why: &str| PlanError::BadFace(plan.name.clone(), why.to_string());
    // Sub-faces tile the face as a p × p grid and keep its orientation: sub-face
    // corner c is the lattice corner (du, dv) + OFFSETS[c]. The one whose corner 0
    // is the face's corner 0 sits at (0, 0); the right neighbour's corner 0 is
    // this one's corner 1, the upper neighbour's corner 0 this one's corner 3.
    const OFFSETS: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
    let count = plan.children.len();
    let p = (count as f64).sqrt().round() as usize;
    if p < 2 || p * p != count {
        return Err(bad(&format!("faces are meshed as p × p splits; {count} sub-faces is not a square ≥ 4")));
    }
    for (_, target, _) in &plan.children {
        if *target != id.index() {
            return Err(bad("a face must subdivide into faces of the same state"));
        }
    }
    let image =
        |child: usize, corner: usize| mat_vec(&plan.children[child].2, plan.dim, plan.dim, &plan.samples[corner]);
    let starting_at = |point: &[f64]| (0..count).find(|&c| close(&image(c, 0), point));
    let mut place: Vec<Option<(usize, usize)>> = vec![None; count];
    let first = starting_at(&plan.samples[0]).ok_or_else(|| bad("no sub-face starts at the face's first corner"))?;
    place[first] = Some((0, 0));
    let mut queue = vec![first];
    while let Some(c) = queue.pop() {
        let (du, dv) = place[c].expect("placed");
        for (corner, (nu, nv)) in [(1, (du + 1, dv)), (3, (du, dv + 1))] {
            if nu >= p || nv >= p {
                continue;
            }
            let Some(next) = starting_at(&image(c, corner)) else { continue };
            match place[next] {
                None => {
                    place[next] = Some((nu, nv));
                    queue.push(next);
                }
                Some(at) if at == (nu, nv) => {}
                Some(_) => return Err(bad("the sub-faces do not tile the face as a grid")),
            }
        }
    }
    plan.quadrants = place
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| bad("the sub-faces do not tile the face as a p × p grid keeping its orientation"))?;
    for (c, &(du, dv)) in plan.quadrants.iter().enumerate() {
        // Every corner of every sub-face is where the grid puts it (checked against the face's corners).
        for (k, &(ou, ov)) in OFFSETS.iter().enumerate() {
            let (u, v) = (du + ou, dv + ov);
            if let Some(fc) = OFFSETS.iter().position(|&o| (o.0 * p, o.1 * p) == (u, v))
                && !close(&image(c, k), &plan.samples[fc])
            {
                return Err(bad("a sub-face at a corner of the face does not share that corner"));
            }
        }
    }
    let mut q = plan.quadrants.clone();
    q.sort_unstable();
    q.dedup();
    if q.len() != count {
        return Err(bad("two sub-faces at the same place: not a p × p split"));
    }
    plan.split = p;
    Ok(())
}
