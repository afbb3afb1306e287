//! Solids whose volume splits into a grid of copies of itself (every
//! hexahedron pattern: the Menger sponge, the Jerusalem cube): their leaf
//! cells sit on a lattice, so a face is on the boundary exactly when the
//! cell across it is not kept (read off the pattern's digits), and corners
//! are numbered by their lattice point. No face of the solid's inside is
//! ever made or hashed, and only the boundary's corners are kept.

use rustc_hash::FxHashMap;

use super::plan::StatePlan;
use super::prepared::Evaluator;
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
        Some(SolidGrid { dims, place, kept, corner, side })
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

impl Evaluator {
    /// The boundary of the depth-`k` cells of a grid solid rooted at
    /// `control` (state `s`), into `faces`: corners numbered by lattice
    /// point, a face made when the cell across it is not kept.
    pub(super) fn lattice_solid(
        &self,
        grid: &SolidGrid,
        s: usize,
        control: &[f64],
        k: usize,
        faces: &mut dyn Boundary,
        first: usize,
    ) -> Result<(), super::settings::EvalError> {
        let d = faces.dim();
        let sp = self.plan.state(s);
        let n = sp.dim;
        let side = [0, 1, 2].map(|x| grid.dims[x].pow(k as u32) + 1);
        let mut number: FxHashMap<u64, usize> = FxHashMap::default();
        let mut stack: Vec<(Vec<f64>, usize, [u64; 3])> = vec![(control.to_vec(), k, [0, 0, 0])];
        let mut visited = 0usize;
        let mut at = [[0.0f64; 3]; 8];
        while let Some((c, r, p)) = stack.pop() {
            visited += 1;
            if visited.is_multiple_of(4096) {
                self.check_cancel()?;
            }
            if r > 0 {
                for ((_, _, m), place) in sp.children.iter().zip(&grid.place) {
                    let mut child = vec![0.0; d * n];
                    super::prepared::mul_into(&c, d, n, m, n, &mut child);
                    stack.push((child, r - 1, [0, 1, 2].map(|x| p[x] * grid.dims[x] + place[x])));
                }
                continue;
            }
            for (j, b) in sp.samples.iter().enumerate() {
                for a in 0..d {
                    at[j][a] = (0..n).map(|i| c[a * n + i] * b[i]).sum();
                }
            }
            let cell = faces.next_cell();
            for (f, face) in sp.faces.iter().enumerate() {
                let (axis, end) = grid.side[f];
                let mut across = p;
                if end == 1 {
                    across[axis] += 1;
                } else if across[axis] == 0 {
                    across[axis] = u64::MAX;
                } else {
                    across[axis] -= 1;
                }
                if across[axis] != u64::MAX && grid.kept_at(across, k) {
                    continue;
                }
                let mut ids = [0usize; 4];
                for (slot, &j) in ids.iter_mut().zip(face) {
                    let q = [0, 1, 2].map(|x| p[x] + grid.corner[j][x]);
                    let key = q[0] + side[0] * (q[1] + side[1] * q[2]);
                    *slot = *number.entry(key).or_insert_with(|| first + faces.add_vertex(&at[j][..d]));
                }
                let points = [face[0], face[1], face[2], face[3]].map(|j| at[j]);
                faces.add_quad(ids, &points, &at, cell);
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
