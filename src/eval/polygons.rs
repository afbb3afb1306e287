//! Faces that are not a `p × p` split of one state — the patches of a
//! mesh's generated automaton: several states, triangles, n-gons, each
//! subdividing in its own orientation. Every face cell at depth `k` gives
//! its corner polygon; corners that neighbouring cells share (computed along
//! different paths, equal to rounding) are welded by position.

use rustc_hash::{FxHashMap, FxHashSet};

use super::prepared::Evaluator;
use super::settings::EvalError;
use crate::geometry::Sink;
use crate::space::CellKind;

impl Evaluator {
    /// Whether the faces are meshed as polygons: pieces that share control
    /// points (a mesh's patches), or a face that is not a lattice split.
    pub(super) fn polygon_faces(&self) -> bool {
        if self.pieces.shared {
            return true;
        }
        let mut seen = vec![false; self.plan.states.len()];
        let mut stack: Vec<usize> = self.pieces.pieces.iter().map(|p| p.state).collect();
        while let Some(s) = stack.pop() {
            if std::mem::replace(&mut seen[s], true) {
                continue;
            }
            let sp = self.plan.state(s);
            if (sp.kind == CellKind::Face && sp.split == 0 && !self.uses_start_set(s)) || !sp.faces.is_empty() {
                return true;
            }
            stack.extend(sp.children.iter().map(|c| c.1));
        }
        false
    }

    /// The corner polygons of the face cells `k` subdivisions below the
    /// pieces (a root that is not a face does not count as a subdivision),
    /// welded: each piece on its own, or all together when they share
    /// control points (a mesh's patches).
    pub(super) fn polygons(&self, k: usize, sink: &mut dyn Sink) -> Result<(), EvalError> {
        self.polygons_coloured(k, sink, None, None)
    }

    /// The volume cells `k` subdivisions below the pieces, each as its faces
    /// (cycles of welded vertex numbers, turned outward): the complex whose
    /// topology [`crate::report::topology_report`] measures.
    ///
    /// # Errors
    /// Over the memory limit; cancelled.
    pub fn volume_cells(&self, k: usize) -> Result<Vec<Vec<Vec<usize>>>, EvalError> {
        let mut cells = Vec::new();
        self.polygons_coloured(k, &mut crate::geometry::Shape::default(), None, Some(&mut cells))?;
        Ok(cells)
    }

    /// [`Evaluator::polygons`], recording the colour coordinate of every
    /// vertex (the first cell that makes it decides) when `colours` is given.
    pub(super) fn polygons_coloured(
        &self,
        k: usize,
        sink: &mut dyn Sink,
        mut colours: Option<&mut super::colour::CellColours<'_>>,
        mut record: Option<&mut Vec<Vec<Vec<usize>>>>,
    ) -> Result<(), EvalError> {
        let d = self.pieces.dim;
        // A grid solid: its boundary straight from the lattice, streamed (no inner face made).
        if let (None, None, [piece]) = (colours.as_deref(), record.as_deref(), &self.pieces.pieces[..]) {
            let sp = self.plan.state(piece.state);
            if let Some(grid) = super::lattice::SolidGrid::of(sp, piece.state) {
                sink.object(&piece.name)?;
                self.lattice_solid(&grid, piece.state, &piece.control, k, sink, 0)?;
                return Ok(());
            }
        }
        // Welding holds every corner: refuse what would not fit, with the estimate.
        let cells = self.pieces.pieces.iter().fold(0u128, |n, p| n.saturating_add(self.face_cells(p.state, k)));
        let estimate = cells.saturating_mul(4 * (8 * d as u128 + 64));
        if estimate > self.settings.memory_limit as u128 {
            return Err(EvalError::TooLarge { estimate, limit: self.settings.memory_limit });
        }
        let mut first = 0usize;
        let groups: Vec<&[super::pieces::Piece]> =
            // Pieces of one surface (a mesh's patches, a grid's or torus's windows) are welded together.
            if self.pieces.shared || self.pieces.grid.is_some() {
                vec![&self.pieces.pieces[..]]
            } else {
                self.pieces.pieces.chunks(1).collect()
            };
        for group in groups {
            let scale = group.iter().flat_map(|p| &p.control).fold(1.0f64, |m, x| m.max(x.abs()));
            let mut faces = Faces::new(crate::algebra::tolerance::SAME_POINT * scale, d, record.is_some());
            // Hexahedral cells of a lattice cut into pieces are checked not to be turned over.
            let folds =
                group.first().and_then(|p| super::lattice::Folds::of(self.plan.state(p.state), p.state, &p.control, d));
            // Per cell: state, control points, depth left, and its colour so far (see `CellColours`).
            let mut stack: Vec<(usize, Vec<f64>, usize, [f64; 2])> =
                group.iter().rev().map(|p| (p.state, p.control.clone(), k, [0.0, 1.0])).collect();
            let mut visited = 0usize;
            while let Some((s, c, r, colour)) = stack.pop() {
                visited += 1;
                if visited.is_multiple_of(4096) {
                    self.check_cancel()?;
                }
                let sp = self.plan.state(s);
                if r == 0 && (!sp.faces.is_empty() || sp.kind == CellKind::Face) {
                    if let Some(f) = &folds {
                        f.check(sp, s, &c, k)?;
                    }
                    faces.leaf(sp, &c, first);
                    if let Some(cc) = colours.as_deref_mut() {
                        // The vertices this cell adds take its colour.
                        let value = cc.leaf(s, colour);
                        cc.out.resize(first + faces.weld.positions.len() / d, value);
                    }
                    continue;
                }
                let step = self.step_of(s);
                if r < step {
                    continue;
                }
                for (e, t, m) in &sp.children {
                    let nt = self.plan.state(*t).dim;
                    let mut child = vec![0.0; d * nt];
                    super::prepared::mul_into(&c, d, sp.dim, m, nt, &mut child);
                    let colour = colours.as_deref().map_or(colour, |cc| cc.step(*e, colour));
                    stack.push((*t, child, r - step, colour));
                }
            }
            if let (Some(out), Some(cells)) = (record.as_deref_mut(), faces.cells.as_mut()) {
                out.append(cells);
            }
            sink.object(if group.len() > 1 { "surface" } else { &group[0].name })?;
            faces.write(sink, first, colours.as_deref_mut().map(|c| &mut c.out))?;
            first += faces.weld.positions.len() / d;
        }
        Ok(())
    }
}

/// The faces of a group of pieces being meshed: welded corners, quads and
/// triangles (numbered from the group's first vertex).
pub(super) struct Faces {
    weld: Weld,
    quads: Vec<[usize; 4]>,
    triangles: Vec<[usize; 3]>,
    /// Faces over start sets that two cells both make (overlapping copies of a patch) are kept once.
    made: FxHashSet<Poly>,
    /// Volumes' faces by their sorted corners: where in `side_list` they are.
    sides: FxHashMap<Poly, usize>,
    /// Volumes' faces, outward, in the order made, and how many cells made each: a face two kept
    /// cells share is inside the solid, and only the others are written.
    side_list: Vec<(Poly, usize, u32)>,
    /// Volume cells met so far (a face's cell is its number), and the cell of each quad and triangle.
    leaves: u32,
    quad_cells: Vec<u32>,
    triangle_cells: Vec<u32>,
    /// A leaf's welded corners, reused from leaf to leaf.
    scratch: Vec<usize>,
    /// Each leaf volume's faces, when asked for ([`Evaluator::volume_cells`]).
    cells: Option<Vec<Vec<Vec<usize>>>>,
}

impl Faces {
    /// No face yet: corners welded within `q`, `d` coordinates each; each cell's faces kept when `record`.
    fn new(q: f64, d: usize, record: bool) -> Faces {
        Faces {
            weld: Weld { q, d, index: FxHashMap::default(), positions: Vec::new() },
            quads: Vec::new(),
            triangles: Vec::new(),
            made: FxHashSet::default(),
            sides: FxHashMap::default(),
            side_list: Vec::new(),
            leaves: 0,
            quad_cells: Vec::new(),
            triangle_cells: Vec::new(),
            scratch: Vec::new(),
            cells: record.then(Vec::new),
        }
    }

    /// A leaf cell's polygons over its sample points (control points `c`):
    /// its start faces, or its corner polygon.
    fn leaf(&mut self, sp: &super::plan::StatePlan, c: &[f64], first: usize) {
        let (n, d) = (sp.dim, self.weld.d);
        let mut index = std::mem::take(&mut self.scratch);
        index.clear();
        let mut p = [0.0f64; 3];
        for b in &sp.samples {
            for (a, x) in p.iter_mut().enumerate().take(d) {
                *x = (0..n).map(|i| c[a * n + i] * b[i]).sum();
            }
            index.push(first + self.weld.index(&p[..d]));
        }
        if sp.kind == CellKind::Volume {
            self.volume(sp, &index, first);
            self.scratch = index;
            return;
        }
        let corner_polygon = [(0..index.len()).collect::<Vec<usize>>()];
        let start_faces = !sp.faces.is_empty();
        for face in if start_faces { &sp.faces[..] } else { &corner_polygon[..] } {
            let corners: Vec<usize> = face.iter().map(|&i| index[i]).collect();
            if start_faces {
                let key = Poly::sorted(&corners);
                if key.repeats() || !self.made.insert(key) {
                    continue;
                }
            }
            match corners.len() {
                4 => self.quads.push([corners[0], corners[1], corners[2], corners[3]]),
                _ => self.triangles.extend(crate::geometry::fan(&corners, 0)),
            }
        }
        self.scratch = index;
    }

    /// A leaf volume's faces (its corners welded at `index`), turned outward
    /// (their Newell normals away from the cell's centroid) and counted.
    fn volume(&mut self, sp: &super::plan::StatePlan, index: &[usize], first: usize) {
        let d = self.weld.d;
        let at = |v: usize| -> [f64; 3] {
            let p = &self.weld.positions[(v - first) * d..(v - first + 1) * d];
            [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)]
        };
        let mean = |vs: &[usize]| {
            let mut m = [0.0; 3];
            vs.iter().for_each(|&v| (0..3).for_each(|a| m[a] += at(v)[a] / vs.len() as f64));
            m
        };
        let centre = mean(index);
        let mut cell = Vec::new();
        for face in &sp.faces {
            let mut corners = Poly::mapped(face, |i| index[i]);
            let key = Poly::sorted(corners.as_slice());
            if key.repeats() {
                continue;
            }
            let cs = corners.as_slice();
            let (mid, mut normal) = (mean(cs), [0.0; 3]);
            for (k, &v) in cs.iter().enumerate() {
                let (p, q) = (at(v), at(cs[(k + 1) % cs.len()]));
                normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
                normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
                normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
            }
            if (0..3).map(|a| normal[a] * (mid[a] - centre[a])).sum::<f64>() < 0.0 {
                let mut turned: Vec<usize> = cs.to_vec();
                turned.reverse();
                corners = Poly::new(&turned);
            }
            if self.cells.is_some() {
                cell.push(corners.as_slice().to_vec());
            }
            match self.sides.get(&key) {
                Some(&at) => self.side_list[at].1 += 1,
                None => {
                    self.sides.insert(key, self.side_list.len());
                    self.side_list.push((corners, 1, self.leaves));
                }
            }
        }
        self.leaves += 1;
        if let Some(cells) = self.cells.as_mut() {
            cells.push(cell);
        }
    }

    /// The volumes' faces that one kept cell alone makes (the solid's
    /// boundary) into the quads and triangles.
    fn close_volumes(&mut self) -> bool {
        self.sides.clear();
        let volumes = !self.side_list.is_empty();
        for (corners, count, cell) in std::mem::take(&mut self.side_list) {
            match (corners.as_slice(), count) {
                (&[a, b, c, d], 1) => {
                    self.quads.push([a, b, c, d]);
                    self.quad_cells.push(cell);
                }
                (corners, 1) => {
                    self.triangles.extend(crate::geometry::fan(corners, 0));
                    self.triangle_cells.resize(self.triangles.len(), cell);
                }
                _ => {}
            }
        }
        volumes
    }

    /// Splits the vertices where a solid's cells touch at a point or along an
    /// edge only (pinches): around each vertex its boundary faces are joined
    /// through the edges they share (an edge of two faces; of four where two
    /// cells touch along it, then each cell's two), and every fan but the
    /// first gets its own copy of the vertex. The boundary becomes a
    /// 2-manifold, shells that touch without sharing a vertex (what a
    /// slicer and manifold3d take). Returns the vertices added.
    pub(super) fn split_pinches(&mut self, first: usize, colours: Option<&mut Vec<f32>>) -> usize {
        let d = self.weld.d;
        let n = self.weld.positions.len() / d;
        let nq = self.quads.len();
        let total = nq + self.triangles.len();
        let (quads, triangles) = (&self.quads, &self.triangles);
        let corners = |f: usize| -> &[usize] { if f < nq { &quads[f] } else { &triangles[f - nq] } };
        let cell = |f: usize| if f < nq { self.quad_cells[f] } else { self.triangle_cells[f - nq] };
        // The face corners at each vertex, gathered by counting.
        // The face corners at each vertex of six faces or more (one cell has at most three at a
        // corner: a pinch has at least six), gathered by counting.
        let mut count = vec![0u32; n];
        (0..total).flat_map(corners).for_each(|&v| count[v - first] += 1);
        let mut slot = vec![u32::MAX; n];
        let mut start = vec![0usize];
        for (v, &c) in count.iter().enumerate().filter(|(_, c)| **c >= 6) {
            slot[v] = (start.len() - 1) as u32;
            start.push(start[start.len() - 1] + c as usize);
        }
        drop(count);
        let mut fill = start.clone();
        let mut at = vec![(0usize, 0usize); start[start.len() - 1]];
        for f in 0..total {
            for (i, &v) in corners(f).iter().enumerate() {
                if let Some(k) = Some(slot[v - first] as usize).filter(|&k| k != u32::MAX as usize) {
                    at[fill[k]] = (f, i);
                    fill[k] += 1;
                }
            }
        }
        let mut renames: Vec<(usize, usize, usize)> = Vec::new();
        let mut added = 0;
        for k in 0..start.len() - 1 {
            let here = &at[start[k]..start[k + 1]];
            let mut parent = fans(here, &corners, &cell);
            let keep = fan_root(&mut parent, 0);
            let mut copies: Vec<(usize, usize)> = Vec::new();
            for (k, &(f, i)) in here.iter().enumerate() {
                let r = fan_root(&mut parent, k);
                if r == keep {
                    continue;
                }
                let copy = match copies.iter().find(|c| c.0 == r) {
                    Some(c) => c.1,
                    None => {
                        copies.push((r, n + added));
                        added += 1;
                        n + added - 1
                    }
                };
                renames.push((f, i, copy));
            }
        }
        let mut colours = colours;
        let mut origin = vec![0usize; added];
        for &(f, i, copy) in &renames {
            let v = corners(f)[i] - first;
            origin[copy - n] = v;
        }
        for &v in &origin {
            self.weld.positions.extend_from_within(v * d..(v + 1) * d);
            if let Some(c) = colours.as_deref_mut().filter(|c| c.len() > first + v) {
                c.push(c[first + v]);
            }
        }
        for (f, i, copy) in renames {
            if f < nq {
                self.quads[f][i] = first + copy;
            } else {
                self.triangles[f - nq][i] = first + copy;
            }
        }
        added
    }

    /// Turns every closed piece that encloses a negative volume (a member
    /// whose matrices list a cell's corners the other way round) outward.
    fn turn_outward(&mut self, first: usize) {
        let nq = self.quads.len();
        let n = first + self.weld.positions.len() / 3;
        let (quads, triangles, positions) = (&self.quads, &self.triangles, &self.weld.positions);
        let face = |f: usize| -> &[usize] { if f < nq { &quads[f] } else { &triangles[f - nq] } };
        let point = |v: usize| {
            let p = &positions[(v - first) * 3..(v - first) * 3 + 3];
            [p[0], p[1], p[2]]
        };
        let turn = crate::geometry::inward_faces(n, nq + triangles.len(), face, point);
        for (q, _) in self.quads.iter_mut().zip(&turn).filter(|(_, t)| **t) {
            q.swap(1, 3);
        }
        for (t, _) in self.triangles.iter_mut().zip(&turn[nq..]).filter(|(_, t)| **t) {
            t.swap(1, 2);
        }
    }

    /// Where two cells touch along an edge only and each end of it stays one
    /// vertex (the cells are joined around both ends through others: two
    /// slabs and two pillars touching along an edge between them), the
    /// split surface passes along that edge twice between the same two
    /// vertices — an edge of four faces however the vertices are split.
    /// Each cell's pass gets a vertex of its own at the edge's middle (its
    /// two faces there are cut into triangles through it), so that every
    /// edge of the mesh has two faces. Returns the vertices added.
    pub(super) fn split_doubled_edges(&mut self, first: usize, colours: Option<&mut Vec<f32>>) -> usize {
        let d = self.weld.d;
        let nq = self.quads.len();
        let total = nq + self.triangles.len();
        let corners =
            |f: usize| -> Vec<usize> { if f < nq { self.quads[f].to_vec() } else { self.triangles[f - nq].to_vec() } };
        let cell = |f: usize| if f < nq { self.quad_cells[f] } else { self.triangle_cells[f - nq] };
        // Per edge (its ends, sorted), the faces along it and where: `(face, corner it starts at)`.
        type Along = Vec<(usize, usize)>;
        let mut sides: FxHashMap<(usize, usize), Along> = FxHashMap::default();
        for f in 0..total {
            let c = corners(f);
            for i in 0..c.len() {
                let (a, b) = (c[i], c[(i + 1) % c.len()]);
                sides.entry((a.min(b), a.max(b))).or_default().push((f, i));
            }
        }
        // Per face, the sides cut and the vertex each is cut at.
        let mut cuts: FxHashMap<usize, Vec<(usize, usize)>> = FxHashMap::default();
        let mut doubled: Vec<((usize, usize), Along)> = sides.into_iter().filter(|(_, at)| at.len() > 2).collect();
        doubled.sort_unstable();
        let mut colours = colours;
        let mut added = 0;
        for ((a, b), at) in doubled {
            let mut cells: Vec<u32> = at.iter().map(|&(f, _)| cell(f)).collect();
            cells.sort_unstable();
            cells.dedup();
            for c in cells {
                let v = self.weld.positions.len() / d;
                for x in 0..d {
                    let mid =
                        (self.weld.positions[(a - first) * d + x] + self.weld.positions[(b - first) * d + x]) / 2.0;
                    self.weld.positions.push(mid);
                }
                if let Some(cs) = colours.as_deref_mut().filter(|cs| cs.len() > a) {
                    cs.push(cs[a]);
                }
                added += 1;
                for &(f, i) in at.iter().filter(|&&(f, _)| cell(f) == c) {
                    cuts.entry(f).or_default().push((i, first + v));
                }
            }
        }
        if cuts.is_empty() {
            return 0;
        }
        let mut cut: Vec<(usize, Vec<(usize, usize)>)> = cuts.into_iter().collect();
        cut.sort_unstable();
        let mut gone = vec![false; total];
        let (mut made, mut made_cells) = (Vec::new(), Vec::new());
        for (f, mut at) in cut {
            at.sort_unstable();
            let c = corners(f);
            // The polygon with the cut vertices in place, fanned from the first cut.
            let mut polygon = Vec::with_capacity(c.len() + at.len());
            for (i, &v) in c.iter().enumerate() {
                polygon.push(v);
                polygon.extend(at.iter().filter(|x| x.0 == i).map(|x| x.1));
            }
            let start = polygon.iter().position(|v| *v == at[0].1).unwrap_or(0);
            polygon.rotate_left(start);
            let tri = polygon.len() - 2;
            made.extend((0..tri).map(|k| [polygon[0], polygon[k + 1], polygon[k + 2]]));
            made_cells.extend(std::iter::repeat_n(cell(f), tri));
            gone[f] = true;
        }
        // The faces cut leave the quads and triangles they were (the new triangles, after them, stay).
        let quads = std::mem::take(&mut self.quads).into_iter().zip(std::mem::take(&mut self.quad_cells));
        (self.quads, self.quad_cells) = quads.enumerate().filter(|(f, _)| !gone[*f]).map(|(_, q)| q).unzip();
        let triangles = std::mem::take(&mut self.triangles).into_iter().zip(std::mem::take(&mut self.triangle_cells));
        (self.triangles, self.triangle_cells) =
            triangles.enumerate().filter(|(t, _)| !gone[nq + t]).map(|(_, t)| t).unzip();
        self.triangles.extend(made);
        self.triangle_cells.extend(made_cells);
        added
    }

    /// Drops the vertices no face uses (a solid's inner corners: its boundary
    /// is written, not its cells), renumbering the faces and the colours.
    fn compact(&mut self, first: usize, colours: Option<&mut Vec<f32>>) {
        let d = self.weld.d;
        let n = self.weld.positions.len() / d;
        let mut number = vec![usize::MAX; n];
        for v in self.quads.iter().flatten().chain(self.triangles.iter().flatten()) {
            number[v - first] = 0;
        }
        let mut kept = 0;
        for (i, slot) in number.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = first + kept;
                self.weld.positions.copy_within(i * d..(i + 1) * d, kept * d);
                kept += 1;
            }
        }
        if let Some(c) = colours {
            let mut at = 0;
            for i in 0..n.min(c.len().saturating_sub(first)) {
                if number[i] != usize::MAX {
                    c[first + at] = c[first + i];
                    at += 1;
                }
            }
            c.truncate(first + at);
        }
        self.weld.positions.truncate(kept * d);
        for v in self.quads.iter_mut().flatten().chain(self.triangles.iter_mut().flatten()) {
            *v = number[*v - first];
        }
    }

    /// Writes the welded vertices and the faces: a surface's shaded smooth
    /// (area-weighted normals that agree with every face at the vertex), a
    /// solid's boundary closed, outward, its pinches and doubled edges split,
    /// without normals (flat: its edges are sharp).
    pub(super) fn write(
        &mut self,
        sink: &mut dyn Sink,
        first: usize,
        colours: Option<&mut Vec<f32>>,
    ) -> Result<(), EvalError> {
        let mut colours = colours;
        let solid = self.close_volumes();
        if solid {
            self.split_pinches(first, colours.as_deref_mut());
            self.split_doubled_edges(first, colours.as_deref_mut());
            self.compact(first, colours);
        }
        let d = self.weld.d;
        if d == 3 {
            self.turn_outward(first);
        }
        // A solid's faces meet at sharp edges: written without vertex normals (clients shade
        // them flat, as glTF asks), not rounded over by averaged ones.
        let normals = (d == 3 && !solid).then(|| {
            let points: Vec<[f64; 3]> = self.weld.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
            let local = |v: &[usize]| v.iter().map(|i| i - first).collect::<Vec<_>>();
            let faces: Vec<Vec<usize>> =
                self.quads.iter().map(|q| local(q)).chain(self.triangles.iter().map(|t| local(t))).collect();
            crate::geometry::agreeing_normals(&points, faces.iter().map(Vec::as_slice)).concat()
        });
        sink.vertices(d, &self.weld.positions, normals.as_deref())?;
        sink.faces(&self.quads, None)?;
        sink.triangles(&self.triangles)?;
        Ok(())
    }
}

/// What [`Evaluator::for_each_cell`] calls with each cell: its plan and its control points.
pub type CellVisitor<'a> = dyn FnMut(&super::plan::StatePlan, &[f64]) -> Result<(), EvalError> + 'a;

impl Evaluator {
    /// Calls `visit` with every cell `k` subdivisions below the pieces (as
    /// [`Evaluator::polygons`] counts them: a root that only selects its
    /// patches is no subdivision) that is an edge, a face or a volume, with
    /// its plan and its control points (`d × n`, row-major). Nothing is
    /// held: memory stays that of one path down the tree.
    ///
    /// # Errors
    /// Cancelled; what `visit` returns.
    pub fn for_each_cell(&self, k: usize, visit: &mut CellVisitor<'_>) -> Result<(), EvalError> {
        let d = self.pieces.dim;
        let mut visited = 0usize;
        for piece in &self.pieces.pieces {
            let mut stack: Vec<(usize, Vec<f64>, usize)> = vec![(piece.state, piece.control.clone(), k)];
            while let Some((s, c, r)) = stack.pop() {
                visited += 1;
                if visited.is_multiple_of(4096) {
                    self.check_cancel()?;
                }
                let sp = self.plan.state(s);
                if r == 0 && matches!(sp.kind, CellKind::Edge | CellKind::Face | CellKind::Volume) {
                    visit(sp, &c)?;
                    continue;
                }
                let step = self.step_of(s);
                if r < step {
                    continue;
                }
                for (_, t, m) in sp.children.iter().rev() {
                    let nt = self.plan.state(*t).dim;
                    let mut child = vec![0.0; d * nt];
                    super::prepared::mul_into(&c, d, sp.dim, m, nt, &mut child);
                    stack.push((*t, child, r - step));
                }
            }
        }
        Ok(())
    }

    /// The face cells of the polygon mesh at depth `k` (saturating; a cell of
    /// more than four corners is written as a fan of triangles), or `None`
    /// when the output is not made of polygon cells.
    pub fn polygon_cells(&self, k: usize) -> Option<u128> {
        if !self.polygon_faces() {
            return None;
        }
        Some(self.pieces.pieces.iter().fold(0u128, |n, p| n.saturating_add(self.face_cells(p.state, k))))
    }

    /// Face cells `k` subdivisions below a cell of `state` (as [`Evaluator::polygons`] counts them), saturating.
    pub(super) fn face_cells(&self, state: usize, k: usize) -> u128 {
        let mut memo: Vec<Vec<Option<u128>>> = vec![vec![None; k + 1]; self.plan.states.len()];
        self.count_cells(state, k, &mut memo)
    }

    fn count_cells(&self, s: usize, r: usize, memo: &mut Vec<Vec<Option<u128>>>) -> u128 {
        if let Some(n) = memo[s][r] {
            return n;
        }
        let sp = self.plan.state(s);
        if (sp.kind == CellKind::Face || !sp.faces.is_empty()) && r == 0 {
            return 1;
        }
        let step = self.step_of(s);
        if r < step {
            return 0;
        }
        let n =
            sp.children.iter().map(|(_, t, _)| self.count_cells(*t, r - step, memo)).fold(0u128, u128::saturating_add);
        memo[s][r] = Some(n);
        n
    }

    /// Whether a cell of `s` counts as a subdivision: faces do, and states on
    /// a cycle (a root that selects its patches, taken once, does not).
    fn step_of(&self, s: usize) -> usize {
        let sp = self.plan.state(s);
        usize::from(sp.kind == CellKind::Face || sp.cyclic)
    }
}

/// The fans of boundary faces around one vertex (`here`: the faces and
/// corner positions there): a union-find over them, two faces joined when
/// they share an edge at the vertex that only they have, or that they have
/// with two faces of another cell (cells touching along it) and are of the same cell.
fn fans<'a>(
    here: &[(usize, usize)],
    corners: &impl Fn(usize) -> &'a [usize],
    cell: &impl Fn(usize) -> u32,
) -> Vec<usize> {
    let mut ends: Vec<(usize, usize)> = Vec::with_capacity(2 * here.len());
    for (k, &(f, i)) in here.iter().enumerate() {
        let c = corners(f);
        ends.push((c[(i + 1) % c.len()], k));
        ends.push((c[(i + c.len() - 1) % c.len()], k));
    }
    ends.sort_unstable();
    let mut parent: Vec<usize> = (0..here.len()).collect();
    for run in ends.chunk_by(|a, b| a.0 == b.0) {
        for (i, a) in run.iter().enumerate() {
            for b in &run[i + 1..] {
                if run.len() == 2 || cell(here[a.1].0) == cell(here[b.1].0) {
                    let (x, y) = (fan_root(&mut parent, a.1), fan_root(&mut parent, b.1));
                    parent[x] = y;
                }
            }
        }
    }
    parent
}

/// The representative of `x`'s fan.
fn fan_root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// A polygon's corners, held without an allocation up to four (every
/// volume pattern's faces): a face's key (its corners sorted) or its cycle.
#[derive(Clone, Debug, Hash, PartialEq, Eq)]
enum Poly {
    Short(u8, [usize; 4]),
    Long(Vec<usize>),
}

impl Poly {
    fn new(corners: &[usize]) -> Poly {
        Poly::mapped(corners, |v| v)
    }

    /// `face`'s corners through `f`, without an allocation up to four.
    fn mapped(face: &[usize], f: impl Fn(usize) -> usize) -> Poly {
        match face.len() {
            n @ 0..=4 => {
                let mut v = [usize::MAX; 4];
                face.iter().zip(&mut v).for_each(|(&i, x)| *x = f(i));
                Poly::Short(n as u8, v)
            }
            _ => Poly::Long(face.iter().map(|&i| f(i)).collect()),
        }
    }

    fn sorted(corners: &[usize]) -> Poly {
        let mut p = Poly::new(corners);
        match &mut p {
            Poly::Short(n, v) => v[..*n as usize].sort_unstable(),
            Poly::Long(v) => v.sort_unstable(),
        }
        p
    }

    fn as_slice(&self) -> &[usize] {
        match self {
            Poly::Short(n, v) => &v[..*n as usize],
            Poly::Long(v) => v,
        }
    }

    /// Whether a corner repeats (sorted keys only): a degenerate face.
    fn repeats(&self) -> bool {
        self.as_slice().windows(2).any(|w| w[0] == w[1])
    }
}

/// Points numbered once each: equal up to a fraction of `q` (a grid of
/// cells of side `q`; a point near a cell's side also looks in the cell
/// across, so that copies of one point rounded apart are found).
struct Weld {
    q: f64,
    d: usize,
    index: FxHashMap<[i64; 3], usize>,
    positions: Vec<f64>,
}

impl Weld {
    fn index(&mut self, p: &[f64]) -> usize {
        let mut key = [0i64; 3];
        let mut across = [0i64; 3];
        for (a, x) in p.iter().take(3).enumerate() {
            let scaled = x / self.q;
            key[a] = scaled.round() as i64;
            let frac = scaled - key[a] as f64;
            across[a] = if frac > 0.25 {
                1
            } else if frac < -0.25 {
                -1
            } else {
                0
            };
        }
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        // The cells across the near sides (usually none): every non-empty subset of them.
        let near: Vec<usize> = (0..3).filter(|&a| across[a] != 0).collect();
        for subset in 1..1usize << near.len() {
            let mut k = key;
            for (bit, &a) in near.iter().enumerate() {
                if subset >> bit & 1 == 1 {
                    k[a] += across[a];
                }
            }
            if let Some(&i) = self.index.get(&k) {
                return i;
            }
        }
        let i = self.positions.len() / self.d;
        self.index.insert(key, i);
        self.positions.extend_from_slice(p);
        i
    }
}
