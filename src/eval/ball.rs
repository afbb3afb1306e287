//! Balls that hold the attractor of a plain (or graph-directed) IFS
//! piece, so that adaptive evaluation can promise a Hausdorff distance.
//!
//! A piece whose reachable states all have `d + 1` control points, with
//! affinely independent control points `P`, is a graph-directed IFS of
//! affine maps of modelling space: arrow `M` is `f(x) = P M λ(x)` whatever
//! its states (`λ`: barycentric coordinates relative to `P`), with linear
//! part `L = D(PM) D(P)⁻¹` (`D(X)`: the columns `x_j − x_0`). When every
//! `L` contracts the Euclidean norm (`‖L‖₂ = ρ < 1`), balls `B(c_s, R_s)`
//! with `R_s ≥ |f(c_t) − c_s| + ρ R_t` for every arrow `s → t` are mapped
//! into each other, so `B(c_s, R_s)` holds the attractor `A_s` of state `s`.
//! A covering pass then tightens each: `A_s ⊂ ⋃ f_w(B_t)` over the leaves
//! `w` of a coarse subdivision from `s`, so `A_s` lies in the ball about the
//! centre `c'` of the points `f_w(c_t)` with radius
//! `max (|f_w(c_t) − c'| + ‖L_w‖ R_t)`.
//!
//! A cell `w` at state `s` of the evaluation then holds
//! `f_w(A_s) ⊂ f_w(B_s)`, of diameter at most `2 R_s ‖L_w‖`: stopping when
//! that is below `ε` and emitting `f_w(c_s)` gives a point set within `ε`
//! of the attractor in Hausdorff distance, both ways.

use nalgebra::DMatrix;

use super::plan::Plan;
use super::prepared::{mul_into, project_into};

/// Depth of the covering pass that tightens the ball.
const COVER_DEPTH: usize = 24;
/// The covering pass stops a branch when its image of the first ball is this fraction of it.
const COVER_FRACTION: f64 = 0.05;
/// Most leaves the covering pass visits.
const COVER_LEAVES: usize = 1 << 16;

/// Balls holding the attractors of the states of a piece, in modelling units.
#[derive(Clone, Debug)]
pub(super) struct Balls {
    /// Per state: barycentric coordinates of the centre relative to the piece's
    /// control points, and the radius (`None`: not reachable from the piece).
    balls: Vec<Option<(Vec<f64>, f64)>>,
    /// `D(P)⁻¹`, `d × d` row-major.
    inverse: Vec<f64>,
}

/// An arrow as a map of modelling space: from state, to state, the images
/// of the control points (`d × (d + 1)`), and the norm of its linear part.
struct Map {
    from: usize,
    to: usize,
    image: Vec<f64>,
    rho: f64,
}

/// The columns `x_j − x_0` of control points `c` (`d × (d + 1)`, row-major), as a matrix.
fn differences(c: &[f64], d: usize) -> DMatrix<f64> {
    let n = d + 1;
    DMatrix::from_fn(d, d, |a, j| c[a * n + j + 1] - c[a * n])
}

/// The spectral norm of a `d × d` row-major matrix: exact in 2D, the
/// Frobenius norm (an upper bound) otherwise.
fn norm(l: &[f64], d: usize) -> f64 {
    let f2: f64 = l.iter().map(|x| x * x).sum();
    if d == 2 {
        let det = l[0] * l[3] - l[1] * l[2];
        ((f2 + (f2 * f2 - 4.0 * det * det).max(0.0).sqrt()) / 2.0).sqrt()
    } else {
        f2.sqrt()
    }
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt()
}

impl Balls {
    /// The balls of the piece with control points `control` (`d × n`,
    /// row-major) at `root`, or `None` when the piece is not an IFS of
    /// Euclidean contractions of `d + 1` affinely independent points.
    pub fn of(plan: &Plan, root: usize, control: &[f64], d: usize) -> Option<Balls> {
        let n = d + 1;
        // Fewer (or more) control points than d + 1 (a Cantor set on a segment of the plane): no affine frame.
        if control.len() != d * n {
            return None;
        }
        let inv = differences(control, d).try_inverse()?;
        if !inv.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut balls =
            Balls { balls: vec![None; plan.states.len()], inverse: (0..d * d).map(|k| inv[(k / d, k % d)]).collect() };
        // The reachable states, all with d + 1 points and subdivision arrows.
        let mut reach = vec![root];
        let mut seen = vec![false; plan.states.len()];
        seen[root] = true;
        let mut maps = Vec::new();
        while let Some(s) = reach.pop() {
            let sp = plan.state(s);
            if sp.dim != n || sp.children.is_empty() {
                return None;
            }
            for (_, t, m) in &sp.children {
                let mut image = vec![0.0; d * n];
                mul_into(control, d, n, m, n, &mut image);
                let rho = norm(&balls.linear_part(&image, d), d);
                if rho.is_nan() || rho >= 1.0 {
                    return None;
                }
                maps.push(Map { from: s, to: *t, image, rho });
                if !seen[*t] {
                    seen[*t] = true;
                    reach.push(*t);
                }
            }
        }
        let states = plan.states.len();
        let centres = balls.centres(&maps, states, control, d);
        let radii = balls.radii(&maps, &centres, control, d)?;
        for s in (0..states).filter(|&s| seen[s]) {
            let beta = balls.barycentric(control, &centres[s], d);
            balls.balls[s] = Some((beta, radii[s]));
        }
        let tight: Vec<Option<(Vec<f64>, f64)>> =
            (0..states).map(|s| if seen[s] { balls.tightened(plan, s, control, d) } else { None }).collect();
        for (ball, t) in balls.balls.iter_mut().zip(tight) {
            if let (Some(b), Some(t)) = (ball.as_mut(), t)
                && t.1 < b.1
            {
                *b = t;
            }
        }
        Some(balls)
    }

    /// Centres: the images of the centres averaged, to their fixed point.
    fn centres(&self, maps: &[Map], states: usize, control: &[f64], d: usize) -> Vec<Vec<f64>> {
        let mut centres = vec![vec![0.0; d]; states];
        for _ in 0..200 {
            let mut next = vec![vec![0.0; d]; states];
            let mut counts = vec![0usize; states];
            for map in maps {
                let x = self.apply(map, &centres[map.to], control, d);
                next[map.from].iter_mut().zip(&x).for_each(|(a, b)| *a += b);
                counts[map.from] += 1;
            }
            for (c, k) in next.iter_mut().zip(&counts) {
                c.iter_mut().for_each(|x| *x /= (*k).max(1) as f64);
            }
            centres = next;
        }
        centres
    }

    /// Radii: the least solution of `R_s = max (|f(c_t) − c_s| + ρ R_t)`,
    /// inflated until it holds; `None` when it cannot be made to.
    fn radii(&self, maps: &[Map], centres: &[Vec<f64>], control: &[f64], d: usize) -> Option<Vec<f64>> {
        let gaps: Vec<f64> =
            maps.iter().map(|m| distance(&self.apply(m, &centres[m.to], control, d), &centres[m.from])).collect();
        let mut radii = vec![0.0f64; centres.len()];
        for _ in 0..10_000 {
            let mut next = vec![0.0f64; centres.len()];
            for (m, g) in maps.iter().zip(&gaps) {
                next[m.from] = next[m.from].max(g + m.rho * radii[m.to]);
            }
            let done = next.iter().zip(&radii).all(|(a, b)| a - b <= crate::algebra::tolerance::ROUNDING * a.abs());
            radii = next;
            if done {
                break;
            }
        }
        let holds = |r: &[f64]| maps.iter().zip(&gaps).all(|(m, g)| g + m.rho * r[m.to] <= r[m.from]);
        let mut tries = 0;
        while !holds(&radii) {
            radii.iter_mut().for_each(|r| *r = *r * 1.001 + 1e-300);
            tries += 1;
            if tries > 1000 || !radii.iter().all(|r| r.is_finite()) {
                return None;
            }
        }
        Some(radii)
    }

    /// `f(x)` for the map `m`.
    fn apply(&self, m: &Map, x: &[f64], control: &[f64], d: usize) -> Vec<f64> {
        let beta = self.barycentric(control, x, d);
        let mut y = vec![0.0; d];
        project_into(&m.image, d, d + 1, &beta, &mut y);
        y
    }

    /// Barycentric coordinates of the point `x` relative to the control points.
    fn barycentric(&self, control: &[f64], x: &[f64], d: usize) -> Vec<f64> {
        let n = d + 1;
        // λ_1.. = D(P)⁻¹ (x − p_0), λ_0 = 1 − Σ.
        let rel: Vec<f64> = (0..d).map(|a| x[a] - control[a * n]).collect();
        let mut beta = vec![0.0; n];
        for j in 0..d {
            beta[j + 1] = (0..d).map(|a| self.inverse[j * d + a] * rel[a]).sum();
        }
        beta[0] = 1.0 - beta[1..].iter().sum::<f64>();
        beta
    }

    /// The linear part `D(C) D(P)⁻¹` of the map taking the piece to the cell `c`.
    fn linear_part(&self, c: &[f64], d: usize) -> Vec<f64> {
        let dc = differences(c, d);
        let inv = DMatrix::from_row_slice(d, d, &self.inverse);
        let l = dc * inv;
        (0..d * d).map(|k| l[(k / d, k % d)]).collect()
    }

    /// The centre (barycentric) of the ball of `state`.
    pub fn centre(&self, state: usize) -> &[f64] {
        self.balls[state].as_ref().map_or(&[], |b| &b.0)
    }

    /// An upper bound of the diameter of the attractor's part in the cell
    /// at `state` with control points `c`.
    pub fn cell_diameter(&self, state: usize, c: &[f64], d: usize) -> f64 {
        let radius = self.balls[state].as_ref().map_or(f64::INFINITY, |b| b.1);
        2.0 * radius * norm(&self.linear_part(c, d), d)
    }

    /// A smaller ball of `state`: about the centre of a coarse covering.
    fn tightened(&self, plan: &Plan, state: usize, control: &[f64], d: usize) -> Option<(Vec<f64>, f64)> {
        let n = d + 1;
        let mut leaves: Vec<(Vec<f64>, f64)> = Vec::new(); // (image of the centre, ‖L_w‖ R_t)
        let mut stack = vec![(state, control.to_vec(), 0usize)];
        while let Some((s, c, level)) = stack.pop() {
            let rho = norm(&self.linear_part(&c, d), d);
            if rho < COVER_FRACTION || level >= COVER_DEPTH || leaves.len() + stack.len() >= COVER_LEAVES {
                let (beta, radius) = self.balls[s].as_ref()?;
                let mut x = vec![0.0; d];
                project_into(&c, d, n, beta, &mut x);
                leaves.push((x, rho * radius));
                continue;
            }
            for (_, t, m) in &plan.state(s).children {
                let mut child = vec![0.0; d * n];
                mul_into(&c, d, n, m, n, &mut child);
                stack.push((*t, child, level + 1));
            }
        }
        let mut lo = vec![f64::INFINITY; d];
        let mut hi = vec![f64::NEG_INFINITY; d];
        for (x, _) in &leaves {
            for a in 0..d {
                lo[a] = lo[a].min(x[a]);
                hi[a] = hi[a].max(x[a]);
            }
        }
        let centre: Vec<f64> = lo.iter().zip(&hi).map(|(l, h)| (l + h) / 2.0).collect();
        let radius = leaves.iter().map(|(x, r)| distance(x, &centre) + r).fold(0.0, f64::max);
        radius.is_finite().then(|| (self.barycentric(control, &centre, d), radius))
    }
}
