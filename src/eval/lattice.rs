//! Solids whose volume splits into a grid of copies of itself (every
//! hexahedron pattern: the Menger sponge, the Jerusalem cube): their leaf
//! cells sit on a lattice, so a face is on the boundary exactly when the
//! cell across it is not kept (read off the pattern's digits), and corners
//! are numbered by their lattice point. No face of the solid's inside is
//! ever made or hashed, and only the boundary's corners are kept.

use rustc_hash::FxHashMap;

use super::plan::StatePlan;
use super::prepared::Evaluator;
use super::settings::EvalError;
use crate::space::CellKind;

/// Where the boundary of a grid solid goes (the polygon mesher's faces).
pub(super) trait Boundary {
    /// Coordinates per point.
    fn dim(&self) -> usize;
    /// A new cell: its number, for the faces it makes.
    fn next_cell(&mut self) -> u32;
    /// A new vertex at `p`: its local number.
    fn add_vertex(&mut self, p: &[f64]) -> usize;
    /// A boundary quad `ids` (at `points`) of cell `cell` (corners `at`), to be turned outward.
    fn add_quad(&mut self, ids: [usize; 4], points: &[[f64; 3]], at: &[[f64; 3]; 8], cell: u32);
}

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
        // The children's corners by lattice point: one weight vector each (`m · b`).
        let mut key_of: FxHashMap<u64, usize> = FxHashMap::default();
        let (mut points, mut point_of) = (Vec::new(), Vec::new());
        for ((_, _, m), p) in sp.children.iter().zip(&place) {
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
        let by_code = [0, 1, 2, 3, 4, 5, 6, 7].map(|i| code([i & 1, i >> 1 & 1, i >> 2 & 1]).unwrap_or(0));
        Some(SolidGrid { dims, place, kept, corner, side, points, point_of, by_code })
    }

    /// The corner Jacobians of a cell (corners `at`): per corner of the unit
    /// cube, the determinant of the cell's three edges through it, and the
    /// product of their lengths (its scale).
    fn jacobians(&self, at: &[[f64; 3]; 8]) -> [(f64, f64); 8] {
        [0, 1, 2, 3, 4, 5, 6, 7].map(|c: usize| {
            let e = [1, 2, 4].map(|bit| {
                let (lo, hi) = (at[self.by_code[c & !bit]], at[self.by_code[c | bit]]);
                [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]]
            });
            let det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
            let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            (det, len(e[0]) * len(e[1]) * len(e[2]))
        })
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

/// A grid solid's walk to its leaves: where its corners are numbered.
struct Walk<'a> {
    grid: &'a SolidGrid,
    sp: &'a StatePlan,
    k: usize,
    /// Lattice points per direction at depth `k`.
    side: [u64; 3],
    first: usize,
    number: FxHashMap<u64, usize>,
    /// The root's orientation (the sign of its corner Jacobians), 0 when unknown (not 3D, flat).
    sign: f64,
}

impl Walk<'_> {
    /// A leaf at lattice place `p`, its corners at `at`: checked not turned
    /// over, and its faces whose cell across is not kept, made.
    fn leaf(&mut self, at: &[[f64; 3]; 8], p: [u64; 3], faces: &mut dyn Boundary) -> Result<(), EvalError> {
        if self.sign != 0.0 {
            for (c, (det, scale)) in self.grid.jacobians(at).into_iter().enumerate() {
                if det * self.sign < -1e-9 * scale {
                    let corner = at[self.grid.by_code[c]];
                    return Err(EvalError::Folded { at: corner, depth: self.k, jacobian: det / scale });
                }
            }
        }
        let (grid, d) = (self.grid, faces.dim());
        let cell = faces.next_cell();
        for (f, face) in self.sp.faces.iter().enumerate() {
            let (axis, end) = grid.side[f];
            let mut across = p;
            if end == 1 {
                across[axis] += 1;
            } else if across[axis] == 0 {
                across[axis] = u64::MAX;
            } else {
                across[axis] -= 1;
            }
            if across[axis] != u64::MAX && grid.kept_at(across, self.k) {
                continue;
            }
            let mut ids = [0usize; 4];
            for (slot, &j) in ids.iter_mut().zip(face) {
                let q = [0, 1, 2].map(|x| p[x] + grid.corner[j][x]);
                let key = q[0] + self.side[0] * (q[1] + self.side[1] * q[2]);
                *slot = *self.number.entry(key).or_insert_with(|| self.first + faces.add_vertex(&at[j][..d]));
            }
            let points = [face[0], face[1], face[2], face[3]].map(|j| at[j]);
            faces.add_quad(ids, &points, at, cell);
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
    /// `control` (state `s`), into `faces`: corners numbered by lattice
    /// point, a face made when the cell across it is not kept. The last
    /// level's corners are computed once per lattice point of their parent.
    ///
    /// # Errors
    /// A cell turned over ([`EvalError::Folded`]); cancelled.
    pub(super) fn lattice_solid(
        &self,
        grid: &SolidGrid,
        s: usize,
        control: &[f64],
        k: usize,
        faces: &mut dyn Boundary,
        first: usize,
    ) -> Result<(), EvalError> {
        let d = faces.dim();
        let sp = self.plan.state(s);
        let n = sp.dim;
        let root = corners_of(control, d, n, &sp.samples);
        let total: f64 = grid.jacobians(&root).iter().map(|j| j.0).sum();
        let scale: f64 = grid.jacobians(&root).iter().map(|j| j.1).sum();
        let sign = if d == 3 && total.abs() > 1e-9 * scale { total.signum() } else { 0.0 };
        let side = [0, 1, 2].map(|x| grid.dims[x].pow(k as u32) + 1);
        let mut walk = Walk { grid, sp, k, side, first, number: FxHashMap::default(), sign };
        if k == 0 {
            return walk.leaf(&root, [0, 0, 0], faces);
        }
        let mut stack: Vec<(Vec<f64>, usize, [u64; 3])> = vec![(control.to_vec(), k, [0, 0, 0])];
        let mut table = vec![[0.0f64; 3]; grid.points.len()];
        let mut visited = 0usize;
        while let Some((c, r, p)) = stack.pop() {
            visited += 1;
            if visited.is_multiple_of(256) {
                self.check_cancel()?;
            }
            let below = [0, 1, 2].map(|x| p[x] * grid.dims[x]);
            if r > 1 {
                for ((_, _, m), place) in sp.children.iter().zip(&grid.place) {
                    let mut child = vec![0.0; d * n];
                    super::prepared::mul_into(&c, d, n, m, n, &mut child);
                    stack.push((child, r - 1, [0, 1, 2].map(|x| below[x] + place[x])));
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
                walk.leaf(&at, [0, 1, 2].map(|x| below[x] + place[x]), faces)?;
            }
        }
        Ok(())
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
}
