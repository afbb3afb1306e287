//! Lacunar polygons whose topology is read from a polyhedron (issue 44,
//! the way of the 2025 Computer Aided Geometric Design paper on multi-scale
//! lacunar polygons from polyhedral crystallographic circle packings).
//!
//! Kontorovich and Nakamura's packing of a polyhedron `Π` puts one circle
//! on each vertex of `Π` (two touch where an edge joins their vertices) and
//! one dual circle on each face (through the points where the circles of
//! the face's vertices touch); reflections in the dual circles fill the
//! gaps. The gap of face `F` is a curvilinear `|F|`-gon `R_F`: its corners
//! are the touching points of the edges of `F`, its sides arcs of the
//! circles of the vertices of `F`. The reflection in `F`'s dual circle
//! maps everything outside into `R_F`, so that
//!
//! - `R_F` is the union of one copy of `R_G` for every other face `G` (the
//!   polygon's pieces), and a hole for every vertex not on `F`;
//! - the side of `R_F` on the circle of vertex `x` (valence `d`) is made of
//!   the sides on that circle of the copies of the `d − 1` other faces
//!   around `x`, in their order around `x` and each reversed (a reflection
//!   turns the plane over);
//! - copies of faces `G` and `H` that share an edge touch at one point,
//!   where that edge's circles touch.
//!
//! That is the whole BC-IFS topology: one state per face, one per vertex
//! valence for the sides, subdivision arrows `S{F}_{G}`, and the
//! incidence and adjacency constraints above, each with a comment. The
//! geometry is free (BC-IFS replaces the circles' reflections by the
//! solved family's matrices): the default member places every touching
//! point of a copy where Tutte's barycentric embedding of the packing's
//! contact graph puts it, exactly, with the sides split evenly.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

use crate::algebra::Num;
use crate::design::{Design, DesignBuilder, Layout, Model};
use crate::space::{CellKind, Patch};

/// The polyhedra known by name (their faces counter-clockwise seen from outside).
pub const POLYHEDRON_NAMES: [&str; 7] =
    ["tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron", "prism", "pyramid"];

/// A polyhedron's combinatorics: its faces as cycles of vertex numbers,
/// oriented alike, making a closed surface of genus 0 whose faces meet as a
/// convex polyhedron's do (checked by [`Polyhedron::from_faces`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Polyhedron {
    name: String,
    vertices: usize,
    faces: Vec<Vec<usize>>,
    /// The numbers the vertices were given (those of `faces` are `0..vertices`, in that order).
    labels: Vec<usize>,
}

/// A polyhedron that makes no lacunar polygon.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PolyhedronError {
    /// Neither a known name nor a file.
    #[error(
        "`{0}` is neither a file nor a polyhedron bcifs knows (tetrahedron, cube, octahedron, dodecahedron, icosahedron, prism, pyramid)"
    )]
    Unknown(String),
    /// A file that does not read.
    #[error("{0}")]
    Read(String),
    /// Faces that do not make a polyhedron, and why.
    #[error("not a polyhedron: {0}")]
    Invalid(String),
    /// A root face that does not exist.
    #[error("face {face}: the polyhedron has faces 0 to {last}")]
    Face {
        /// The face asked for.
        face: usize,
        /// The last face.
        last: usize,
    },
    /// Too many unknowns for the exact solver.
    #[error(
        "this polyhedron's lacunar polygon has {unknowns} unknown matrix entries (one copy of every face in every face): the exact solver takes at most {max}; use a polyhedron with fewer edges"
    )]
    TooLarge {
        /// Unknown entries.
        unknowns: usize,
        /// The limit.
        max: usize,
    },
    /// The generated automaton does not build or solve: a bug.
    #[error("internal error in the polyhedron generator (please report): {0}")]
    Internal(String),
}

fn invalid(text: String) -> PolyhedronError {
    PolyhedronError::Invalid(text)
}

/// Where each directed edge `(a, b)` is: the face and the position of `a` in it (`b` follows).
type Directed = HashMap<(usize, usize), (usize, usize)>;

impl Polyhedron {
    /// The polyhedron called `name` (see [`POLYHEDRON_NAMES`]).
    pub fn named(name: &str) -> Option<Polyhedron> {
        let faces: Vec<Vec<usize>> = match name {
            "tetrahedron" => vec![vec![0, 1, 2], vec![0, 3, 1], vec![1, 3, 2], vec![2, 3, 0]],
            "cube" => crate::mesh::PolyMesh::cube().faces().map(<[usize]>::to_vec).collect(),
            "octahedron" => Polyhedron::named("cube")?.dual(),
            "icosahedron" => crate::mesh::PolyMesh::icosahedron().faces().map(<[usize]>::to_vec).collect(),
            "dodecahedron" => Polyhedron::named("icosahedron")?.dual(),
            "prism" => vec![vec![0, 2, 1], vec![3, 4, 5], vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![2, 0, 3, 5]],
            "pyramid" => vec![vec![0, 3, 2, 1], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]],
            _ => return None,
        };
        let mut p = Polyhedron::from_faces(faces).ok()?;
        p.name = name.to_string();
        Some(p)
    }

    /// A known polyhedron's name, else an OBJ or OFF file's path (its faces; positions are not used).
    ///
    /// # Errors
    /// [`PolyhedronError::Unknown`], a file that does not read, faces that are not a polyhedron's.
    pub fn named_or_read(what: &str) -> Result<Polyhedron, PolyhedronError> {
        if let Some(p) = Polyhedron::named(what) {
            return Ok(p);
        }
        let path = Path::new(what);
        if !path.is_file() {
            return Err(PolyhedronError::Unknown(what.to_string()));
        }
        let mesh = crate::mesh::read_mesh(path).map_err(|e| PolyhedronError::Read(e.to_string()))?;
        let mut p = Polyhedron::from_faces(mesh.faces().map(<[usize]>::to_vec).collect()).map_err(|e| {
            PolyhedronError::Invalid(format!("{what}: {}", e.to_string().trim_start_matches("not a polyhedron: ")))
        })?;
        p.name = path.file_stem().map_or_else(|| "polyhedron".into(), |s| s.to_string_lossy().into_owned());
        Ok(p)
    }

    /// The polyhedron of `faces` (vertex numbers; vertices no face uses are
    /// dropped, messages name the others by their numbers here).
    ///
    /// # Errors
    /// [`PolyhedronError::Invalid`], saying what fails: a face of fewer than
    /// three vertices; an edge that is not between exactly two faces run in
    /// opposite directions (an open or inconsistently oriented surface); a
    /// vertex whose faces do not make one fan; a vertex of valence below
    /// three; a surface that is not a sphere (`V − E + F ≠ 2`); a graph that
    /// two vertices cut in two (not 3-connected: by Steinitz's theorem not a
    /// convex polyhedron's, and without a packing); [`PolyhedronError::TooLarge`]
    /// when its lace would have more unknowns than the exact solver takes.
    pub fn from_faces(faces: Vec<Vec<usize>>) -> Result<Polyhedron, PolyhedronError> {
        let mut labels: Vec<usize> = faces.iter().flatten().copied().collect();
        labels.sort_unstable();
        labels.dedup();
        let faces: Vec<Vec<usize>> =
            faces.into_iter().map(|f| f.into_iter().map(|v| labels.binary_search(&v).unwrap_or(0)).collect()).collect();
        let p = Polyhedron { name: "polyhedron".into(), vertices: labels.len(), faces, labels };
        p.check()?;
        Ok(p)
    }

    fn check(&self) -> Result<(), PolyhedronError> {
        // The lace holds a copy of every face in every face: refused before any quadratic check.
        let corners: usize = self.faces.iter().map(Vec::len).sum();
        if corners.saturating_mul(corners) > crate::design::MAX_UNKNOWNS {
            return Err(PolyhedronError::TooLarge {
                unknowns: corners.saturating_mul(corners),
                max: crate::design::MAX_UNKNOWNS,
            });
        }
        for (i, f) in self.faces.iter().enumerate() {
            let mut sorted = f.clone();
            sorted.sort_unstable();
            sorted.dedup();
            if sorted.len() < 3 || sorted.len() != f.len() {
                return Err(invalid(format!(
                    "face {i} has {} distinct vertices of {}: a face needs at least 3, each once",
                    sorted.len(),
                    f.len()
                )));
            }
        }
        let mut directed: Directed = HashMap::new();
        for (i, f) in self.faces.iter().enumerate() {
            for (p, &a) in f.iter().enumerate() {
                let b = f[(p + 1) % f.len()];
                if let Some((g, _)) = directed.insert((a, b), (i, p)) {
                    let (a, b) = (self.labels[a], self.labels[b]);
                    return Err(invalid(format!(
                        "faces {g} and {i} both run from vertex {a} to vertex {b}: the faces are not oriented alike, or three faces meet at that edge"
                    )));
                }
            }
        }
        if let Some((a, b)) = directed.keys().find(|(a, b)| !directed.contains_key(&(*b, *a))) {
            let (a, b) = (self.labels[*a], self.labels[*b]);
            return Err(invalid(format!(
                "the edge from vertex {a} to vertex {b} has a face on one side only: the surface is open there"
            )));
        }
        let edges = directed.len() / 2;
        for x in 0..self.vertices {
            let valence = directed.keys().filter(|(a, _)| *a == x).count();
            let (f, p) = self.first_at(x);
            let fan = self.around(&directed, f, p).len() + 1;
            let label = self.labels[x];
            if valence < 3 {
                return Err(invalid(format!(
                    "vertex {label} has valence {valence}: a polyhedron's vertices join at least 3 edges"
                )));
            }
            if fan != valence {
                return Err(invalid(format!(
                    "the faces at vertex {label} make more than one fan (two cones meet there)"
                )));
            }
        }
        let euler = self.vertices as i64 - edges as i64 + self.faces.len() as i64;
        if euler != 2 {
            return Err(invalid(format!(
                "V − E + F = {} − {edges} + {} = {euler}: a packing's polyhedron is a sphere (2), connected and without handles",
                self.vertices,
                self.faces.len()
            )));
        }
        if let Some((a, b)) = self.two_cut(&directed) {
            let (a, b) = (self.labels[a], self.labels[b]);
            return Err(invalid(format!(
                "removing vertices {a} and {b} cuts its graph in two: it is not 3-connected (Steinitz: not a convex polyhedron's), and has no packing"
            )));
        }
        Ok(())
    }

    /// Two vertices whose removal disconnects the graph, if any.
    fn two_cut(&self, directed: &Directed) -> Option<(usize, usize)> {
        let mut next: Vec<Vec<usize>> = vec![Vec::new(); self.vertices];
        for &(a, b) in directed.keys() {
            next[a].push(b);
        }
        for a in 0..self.vertices {
            for b in a + 1..self.vertices {
                let start = (0..self.vertices).find(|&v| v != a && v != b)?;
                let mut seen = vec![false; self.vertices];
                seen[a] = true;
                seen[b] = true;
                seen[start] = true;
                let mut stack = vec![start];
                let mut reached = 1;
                while let Some(v) = stack.pop() {
                    for &w in &next[v] {
                        if !std::mem::replace(&mut seen[w], true) {
                            reached += 1;
                            stack.push(w);
                        }
                    }
                }
                if reached + 2 < self.vertices {
                    return Some((a, b));
                }
            }
        }
        None
    }

    /// Its name (a known polyhedron's, or the file's stem).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its faces, each a cycle of vertex numbers.
    pub fn faces(&self) -> &[Vec<usize>] {
        &self.faces
    }

    /// Its number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices
    }

    fn directed(&self) -> Directed {
        let mut out = HashMap::new();
        for (i, f) in self.faces.iter().enumerate() {
            for (p, &a) in f.iter().enumerate() {
                out.insert((a, f[(p + 1) % f.len()]), (i, p));
            }
        }
        out
    }

    /// The other faces around the vertex at position `p` of face `f`, each
    /// with that vertex's position in it, starting with the face across the
    /// edge that ends at the vertex in `f`, turning until back at `f`.
    fn around(&self, directed: &Directed, f: usize, p: usize) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        let (mut face, mut at) = (f, p);
        loop {
            let cycle = &self.faces[face];
            let (x, before) = (cycle[at], cycle[(at + cycle.len() - 1) % cycle.len()]);
            let Some(&(next, q)) = directed.get(&(x, before)) else { return out };
            if next == f || out.len() > self.faces.len() {
                return out;
            }
            out.push((next, q));
            (face, at) = (next, q);
        }
    }

    /// The first face at vertex `x`, and `x`'s position in it.
    fn first_at(&self, x: usize) -> (usize, usize) {
        self.faces
            .iter()
            .enumerate()
            .find_map(|(i, f)| f.iter().position(|&v| v == x).map(|p| (i, p)))
            .unwrap_or((0, 0))
    }

    /// The dual's faces: around each vertex, the faces in turning order.
    fn dual(&self) -> Vec<Vec<usize>> {
        let directed = self.directed();
        (0..self.vertices)
            .map(|x| {
                let (f, p) = self.first_at(x);
                std::iter::once(f).chain(self.around(&directed, f, p).into_iter().map(|(g, _)| g)).collect()
            })
            .collect()
    }
}

/// Barycentric coordinates over a face's corners, exact.
type Coords = Vec<BigRational>;

fn ratio(p: usize, q: usize) -> BigRational {
    BigRational::new(BigInt::from(p), BigInt::from(q))
}

/// Where the copies of the other faces touch inside face `f` (one point per
/// edge of the polyhedron), in the barycentric coordinates of `f`'s
/// corners: `f`'s own edges at its corners, the edges at a vertex of `f`
/// evenly along the side on its circle, the others where Tutte's embedding
/// puts them (each the average of the four points it is joined to in the
/// faces on both sides of it), solved exactly.
fn touching_points(
    p: &Polyhedron,
    directed: &Directed,
    edge_id: &HashMap<(usize, usize), usize>,
    f: usize,
) -> Vec<Coords> {
    let face = &p.faces[f];
    let k = face.len();
    let unit =
        |j: usize| (0..k).map(|i| if i == j { BigRational::one() } else { BigRational::zero() }).collect::<Coords>();
    let mut known: Vec<Option<Coords>> = vec![None; edge_id.len()];
    for j in 0..k {
        known[edge_id[&(face[j], face[(j + 1) % k])]] = Some(unit(j));
    }
    for j in 0..k {
        let parts = p.around(directed, f, (j + 1) % k);
        let d = parts.len() + 1;
        for (i, &(g, q)) in parts.iter().enumerate().skip(1) {
            // Between parts i − 1 and i: the edge of g after the vertex (g turned from part i − 1 across it).
            let cycle = &p.faces[g];
            let t = ratio(i, d - 1);
            let point = (0..k)
                .map(|c| match c {
                    c if c == j => BigRational::one() - &t,
                    c if c == (j + 1) % k => t.clone(),
                    _ => BigRational::zero(),
                })
                .collect();
            known[edge_id[&(cycle[q], cycle[(q + 1) % cycle.len()])]] = Some(point);
        }
    }
    // The interior points: 4 x_e − Σ x_n (unknown n) = Σ x_n (known n).
    let inner: Vec<usize> = (0..known.len()).filter(|&e| known[e].is_none()).collect();
    let index: HashMap<usize, usize> = inner.iter().enumerate().map(|(i, &e)| (e, i)).collect();
    let n = inner.len();
    let mut rows: Vec<Vec<BigRational>> = vec![vec![BigRational::zero(); n + k]; n];
    for (&(a, b), &(g, q)) in directed {
        let e = edge_id[&(a, b)];
        let Some(&row) = index.get(&e) else { continue };
        let cycle = &p.faces[g];
        let m = cycle.len();
        rows[row][row] += BigRational::from_integer(2.into());
        for (x, y) in [(cycle[(q + m - 1) % m], a), (b, cycle[(q + 2) % m])] {
            let neighbour = edge_id[&(x, y)];
            match (&known[neighbour], index.get(&neighbour)) {
                (Some(c), _) => (0..k).for_each(|i| rows[row][n + i] += &c[i]),
                (None, Some(&col)) => rows[row][col] -= BigRational::one(),
                (None, None) => {}
            }
        }
    }
    let solved = gauss_jordan(rows, n);
    for (i, &e) in inner.iter().enumerate() {
        known[e] = Some(solved[i].clone());
    }
    known.into_iter().map(Option::unwrap_or_default).collect()
}

/// The solutions of the `n × n` system whose rows carry their right-hand
/// sides after column `n` (nonsingular: Tutte's system, diagonally dominant).
fn gauss_jordan(mut rows: Vec<Vec<BigRational>>, n: usize) -> Vec<Coords> {
    for c in 0..n {
        let Some(pivot) = (c..n).find(|&r| !rows[r][c].is_zero()) else { continue };
        rows.swap(c, pivot);
        let lead = rows[c][c].clone();
        rows[c].iter_mut().for_each(|x| *x /= &lead);
        let top = rows[c].clone();
        for (r, row) in rows.iter_mut().enumerate() {
            if r != c && !row[c].is_zero() {
                let factor = row[c].clone();
                row.iter_mut().zip(&top).for_each(|(x, t)| *x -= &factor * t);
            }
        }
    }
    rows.into_iter().map(|r| r[n..].to_vec()).collect()
}

/// The lacunar polygon of face `face` of `p`: see the module's text.
///
/// ```
/// use bcifs::schemes::{Polyhedron, polyhedral_lace};
/// // The tetrahedron's packing is Apollonian: a triangle made of three triangles, one hole.
/// let design = polyhedral_lace(&Polyhedron::named("tetrahedron").unwrap(), 0, "apollonian")?;
/// let family = bcifs::solve(&design).unwrap();
/// assert_eq!(family.parameter_names().len(), 1); // where the sides split: no touching point is inside
/// # Ok::<(), bcifs::schemes::PolyhedronError>(())
/// ```
///
/// # Errors
/// [`PolyhedronError::Face`].
pub fn polyhedral_lace(p: &Polyhedron, face: usize, name: &str) -> Result<Design, PolyhedronError> {
    if face >= p.faces.len() {
        return Err(PolyhedronError::Face { face, last: p.faces.len() - 1 });
    }
    let directed = p.directed();
    let mut edge_id: HashMap<(usize, usize), usize> = HashMap::new();
    for &(a, b) in directed.keys() {
        if a < b {
            let n = edge_id.len() / 2;
            edge_id.insert((a, b), n);
            edge_id.insert((b, a), n);
        }
    }
    let mut b = Design::builder(name);
    let faces = p.faces.len();
    b.description(format!(
        "lacunar {}-gon from the {}'s packing: {} pieces (the other faces), {} holes (the vertices off face {face})",
        p.faces[face].len(),
        p.name,
        faces - 1,
        p.vertices - p.faces[face].len()
    ))
    .doc(format!(
        "Generated by `bcifs new polyhedron {} --face {face}`: the topology of the {}'s crystallographic\n\
         circle packing (a circle on each vertex, a gap on each face), read from its {} faces and {} vertices.\n\
         Every state, arrow and constraint below follows from the polyhedron.",
        p.name, p.name, faces, p.vertices
    ));
    states(&mut b, p);
    constraints(&mut b, p, &directed);
    let points: Vec<Vec<Coords>> = (0..faces).map(|f| touching_points(p, &directed, &edge_id, f)).collect();
    parameters(&mut b, p, &edge_id, &points)?;
    let k = p.faces[face].len();
    let corner = |j: usize| {
        let a = std::f64::consts::TAU * (j as f64 + 0.5) / k as f64 - std::f64::consts::FRAC_PI_2;
        vec![a.cos(), a.sin()]
    };
    b.model(Model::new(format!("f{face}"), (0..k).map(corner).collect()).with_layout(Layout::Single))
        .doc(format!("The regular {k}-gon (face {face}'s gap): its corners are the control points."));
    b.build().map_err(|e| PolyhedronError::Internal(e.to_string()))
}

/// The valences of the vertices, sorted, each once.
fn valences(p: &Polyhedron, directed: &Directed) -> Vec<usize> {
    let mut out: Vec<usize> = (0..p.vertices).map(|x| directed.keys().filter(|(a, _)| *a == x).count()).collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The valence of the vertex at position `q` of face `f`.
fn valence_at(p: &Polyhedron, directed: &Directed, f: usize, q: usize) -> usize {
    p.around(directed, f, q).len() + 1
}

/// The states and arrows: a state per face and per valence, a copy of
/// every other face in every face, the sides' parts.
fn states(b: &mut DesignBuilder, p: &Polyhedron) {
    let directed = p.directed();
    for (f, cycle) in p.faces.iter().enumerate() {
        let list = cycle.iter().map(|&v| p.labels[v].to_string()).collect::<Vec<_>>().join(", ");
        b.state(format!("f{f}"), cycle.len(), CellKind::Face).patch(Patch::Polygon).doc(format!(
            "The gap of face {f} (vertices {list}): a {}-gon, corner j where the circles of vertices j and j + 1 touch.",
            cycle.len()
        ));
    }
    let valences = valences(p, &directed);
    for &d in &valences {
        b.state(format!("arc{d}"), 2, CellKind::Edge)
            .doc(format!("A side on the circle of a vertex of valence {d}: its two ends."));
    }
    b.state("point", 1, CellKind::Vertex).doc("A touching point: one control point.");
    for (f, cycle) in p.faces.iter().enumerate() {
        for g in (0..p.faces.len()).filter(|&g| g != f) {
            b.unknown(format!("S{f}_{g}"), format!("f{f}"), format!("f{g}"))
                .doc(format!("The copy of face {g}'s gap in face {f}'s."));
        }
        for j in 0..cycle.len() {
            let d = valence_at(p, &directed, f, (j + 1) % cycle.len());
            b.select(format!("side{f}_{j}"), format!("f{f}"), format!("arc{d}"), [j, (j + 1) % cycle.len()]).doc(
                format!("Side {j} of face {f}: on the circle of vertex {}.", p.labels[cycle[(j + 1) % cycle.len()]]),
            );
        }
    }
    for &d in &valences {
        for i in 0..d - 1 {
            b.unknown(format!("P{d}_{i}"), format!("arc{d}"), format!("arc{d}"))
                .doc(format!("Part {i} of {} of a side of valence {d}, reversed.", d - 1));
        }
        b.select(format!("start{d}"), format!("arc{d}"), "point", [0]).doc("The start of a side.");
        b.select(format!("end{d}"), format!("arc{d}"), "point", [1]).doc("The end of a side.");
    }
    b.unknown("W", "point", "point").doc("Subdivision of a touching point.");
}

/// The constraints: the copies on a side make it, copies of faces that
/// share an edge touch, a side's parts share their ends.
fn constraints(b: &mut DesignBuilder, p: &Polyhedron, directed: &Directed) {
    for (f, cycle) in p.faces.iter().enumerate() {
        let k = cycle.len();
        for j in 0..k {
            let x = p.labels[cycle[(j + 1) % k]];
            let parts = p.around(directed, f, (j + 1) % k);
            let d = parts.len() + 1;
            for (i, &(g, q)) in parts.iter().enumerate() {
                let m = p.faces[g].len();
                b.incidence(format!("S{f}_{g} side{g}_{} = side{f}_{j} P{d}_{i}", (q + m - 1) % m)).explain(format!(
                    "Part {i} of face {f}'s side on vertex {x}'s circle is face {g}'s side there, turned over."
                ));
            }
        }
        // Copies of faces that share an edge off f touch where its circles do.
        let mut touching: Vec<(usize, usize, usize, usize, usize, usize)> = Vec::new();
        for (&(a, c), &(g, q)) in directed {
            let (h, r) = directed[&(c, a)];
            if a < c && !cycle.contains(&a) && !cycle.contains(&c) {
                touching.push((g.min(h), g.max(h), a, c, if g < h { q } else { r }, if g < h { r } else { q }));
            }
        }
        touching.sort_unstable();
        for (g, h, a, c, q, r) in touching {
            let corner = |face: usize, at: usize| {
                let cycle = &p.faces[face];
                format!("side{face}_{at} start{}", valence_at(p, directed, face, (at + 1) % cycle.len()))
            };
            b.adjacency(format!("S{f}_{g} {} = S{f}_{h} {}", corner(g, q), corner(h, r))).explain(format!(
                "In face {f}, the copies of faces {g} and {h} touch where edge {}–{} does.",
                p.labels[a], p.labels[c]
            ));
        }
    }
    for d in valences(p, directed) {
        b.incidence(format!("P{d}_0 end{d} = start{d} W")).incidence(format!("P{d}_{} start{d} = end{d} W", d - 2));
        for i in 0..d - 2 {
            b.adjacency(format!("P{d}_{i} start{d} = P{d}_{} end{d}", i + 1));
        }
        b.doc(format!("The parts of a side of valence {d} share their ends, turned over: the first ends at its start, the last starts at its end."));
    }
}

/// The free entries named `a, b, …` with the default member's values.
fn parameters(
    b: &mut DesignBuilder,
    p: &Polyhedron,
    edge_id: &HashMap<(usize, usize), usize>,
    points: &[Vec<Coords>],
) -> Result<(), PolyhedronError> {
    let free = super::topology::free_entries(b).map_err(PolyhedronError::Internal)?;
    for (name, arrow, r, c) in &free {
        b.name_entry(name.clone(), format!("{arrow}[{r}][{c}]"));
        b.default_value(name, Num::rational(default_entry(p, edge_id, points, arrow, *r, *c)));
    }
    let mut text =
        format!("{} free parameters (where the copies touch, where the sides split); the defaults", free.len());
    let _ = write!(text, " place them by Tutte's\nembedding of the contact graph, the sides split evenly.");
    b.doc(text);
    Ok(())
}

/// Entry `(r, c)` of the default member's matrix of `arrow`.
fn default_entry(
    p: &Polyhedron,
    edge_id: &HashMap<(usize, usize), usize>,
    points: &[Vec<Coords>],
    arrow: &str,
    r: usize,
    c: usize,
) -> BigRational {
    let number = |t: &str| t.parse::<usize>().unwrap_or(0);
    let split = |rest: &str| rest.split_once('_').map_or((0, 0), |(a, b)| (number(a), number(b)));
    if let Some((f, g)) = arrow.strip_prefix('S').map(split) {
        let cycle = &p.faces[g];
        let e = edge_id[&(cycle[c], cycle[(c + 1) % cycle.len()])];
        return points[f][e][r].clone();
    }
    if let Some((d, i)) = arrow.strip_prefix('P').map(split) {
        // Column 0, the image of the start, is the part's far end (i + 1)/(d − 1); column 1 its near end.
        let t = ratio(if c == 0 { i + 1 } else { i }, d - 1);
        return if r == 0 { BigRational::one() - t } else { t };
    }
    BigRational::one()
}
