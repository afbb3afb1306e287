//! Joint spectral radius bounds of an automaton on its difference subspaces:
//! sound convergence verdicts for any (graph-directed) subdivision system.
//!
//! A column-stochastic matrix `M` (`λ_A = M λ_B`) maps the differences of
//! `B` (coordinates summing to 0) into those of `A`. The subdivision converges
//! when every long product of subdivision matrices along the automaton's
//! paths contracts those differences: when the joint spectral radius (JSR) of
//! the restricted matrices, over the admissible paths of each strongly
//! connected part of the automaton, is below 1. It diverges when some cycle's
//! product has a restricted spectral radius `ρ(P)^(1/length) ≥ 1`: its powers
//! do not shrink the differences. Per-matrix eigenvalues (Sokolov et al. 2010 §3) give a
//! necessary condition only.
//!
//! - **Lower bound**: `max ρ(P)^(1/|P|)` over the cycles of length up to
//!   [`JsrSettings::max_cycle`], with the cycle that attains it as the witness.
//! - **Upper bound**: in an ellipsoidal norm adapted to the system (the
//!   Perron eigenvector of `Y ↦ Σ Rᵀ Y R`, whose norm bounds every matrix by
//!   the "ρ₂" bound of Blondel and Nesterov), a branch and bound over paths:
//!   a path is closed once its norm is at most `γ^length`; when every path
//!   from every state closes, every infinite path is a chain of closed paths
//!   and `JSR ≤ γ`. Targets `γ` rise from just above the lower bound to 1
//!   until one closes within the budget.
//!
//! Every verdict is a theorem about the bounds beside it: `Converges` when
//! the upper bound is below 1, `Diverges` when the lower bound is at least 1
//! (less the rounding of an eigenvalue, [`ROUNDING`]), `Undecided` otherwise.

use std::fmt;

use nalgebra::DMatrix;
use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;
use rayon::prelude::*;

use crate::algebra::tolerance::{SLACK, STOCHASTIC};
use crate::automaton::{ArrowKind, Automaton};

/// Rounding allowed when a spectral radius is compared with 1: eigenvalues
/// of small products with entries of order 1 are backward stable to ~1e-15.
pub const ROUNDING: f64 = crate::algebra::tolerance::ROUNDING;

/// Factor matrices closer than this (relative to their size) are one map.
const SAME_MATRIX: f64 = 1e-14;

/// The identity's share added to each ellipsoid's form, which keeps it definite.
const DEFINITE: f64 = 1e-9;

/// The ellipsoids' iteration stops once no entry moves more than this.
const SETTLED: f64 = 1e-10;

/// How hard to look for the bounds. Work is counted in floating-point
/// operations of the products, eigenvalues and norms (about `n³` each for
/// `n × n` restricted matrices), so large surface patches get fewer products
/// than curves for the same time.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct JsrSettings {
    /// Longest cycle whose product's spectral radius is computed.
    pub max_cycle: usize,
    /// Work for the lower bound (cycles), in operations.
    pub cycle_work: f64,
    /// Work for the upper bound (adapted norm and branch and bound), in operations.
    pub norm_work: f64,
}

impl Default for JsrSettings {
    /// A fraction of a second on the largest shipped patches; milliseconds on curves.
    fn default() -> JsrSettings {
        JsrSettings { max_cycle: 10, cycle_work: 3e7, norm_work: 6e7 }
    }
}

impl JsrSettings {
    /// A small budget, to refuse a divergent system before evaluation: a
    /// few milliseconds.
    pub fn quick() -> JsrSettings {
        JsrSettings { max_cycle: 6, cycle_work: 2e6, norm_work: 2e6 }
    }
}

/// Operations left to spend.
struct Work(f64);

impl Work {
    /// Spends `ops`; false when the budget is exhausted.
    fn spend(&mut self, ops: f64) -> bool {
        self.0 -= ops;
        self.0 >= 0.0
    }
}

/// Operations of `a (r × k) · b (k × c)`, with the cost of a small
/// allocation counted as 500 operations.
fn product_ops(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    2.0 * (a.nrows() * a.ncols() * b.ncols()) as f64 + 500.0
}

/// Operations of an eigenvalue or singular value computation of `m`
/// (iterative: about `30 n³`, and a fixed cost).
fn decomposition_ops(m: &DMatrix<f64>) -> f64 {
    30.0 * (m.nrows().max(m.ncols()) as f64).powi(3) + 5000.0
}

/// What the bounds prove.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The upper bound is below 1: the subdivision converges.
    Converges,
    /// The lower bound is at least 1: the witness's powers do not contract.
    Diverges,
    /// The bounds straddle 1 within the budget.
    Undecided,
}

impl Verdict {
    /// `Some(true)`, `Some(false)` or `None` (undecided).
    pub fn converges(self) -> Option<bool> {
        match self {
            Verdict::Converges => Some(true),
            Verdict::Diverges => Some(false),
            Verdict::Undecided => None,
        }
    }
}

/// Bounds on the joint spectral radius of an automaton on its difference subspaces.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Jsr {
    /// `max ρ(P)^(1/|P|)` over the cycles tried.
    pub lower: f64,
    /// An upper bound (∞ when no norm bound was found).
    pub upper: f64,
    /// The cycle attaining the lower bound, arrow names in path order.
    pub witness: Vec<String>,
}

impl Jsr {
    /// What the bounds prove.
    pub fn verdict(&self) -> Verdict {
        if self.lower >= 1.0 - ROUNDING {
            Verdict::Diverges
        } else if self.upper < 1.0 {
            Verdict::Converges
        } else {
            Verdict::Undecided
        }
    }

    /// The witness as `T0 T1 T1 T1: ρ^(1/4) = 1.2601`.
    pub fn witness_text(&self) -> String {
        format!("{}: ρ^(1/{}) = {:.4}", self.witness.join(" "), self.witness.len(), self.lower)
    }
}

impl fmt::Display for Jsr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "JSR in [{:.6}, {:.6}]", self.lower, self.upper)?;
        if !self.witness.is_empty() {
            write!(f, " (lower bound by {})", self.witness_text())?;
        }
        Ok(())
    }
}

/// Why the bounds cannot be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum JsrError {
    /// A subdivision matrix whose columns do not sum to 1 does not keep the differences.
    #[error("arrow `{arrow}` is not column-stochastic (column {column} sums to {sum}): differences are not kept")]
    NotStochastic {
        /// The arrow.
        arrow: String,
        /// The column.
        column: usize,
        /// Its sum.
        sum: f64,
    },
}

/// An orthonormal basis of `{x ∈ R^n : Σ x = 0}` (Helmert): `n × (n − 1)`.
fn difference_basis(n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, n.saturating_sub(1), |i, k| {
        let k1 = (k + 1) as f64;
        let scale = 1.0 / (k1 * (k1 + 1.0)).sqrt();
        match i.cmp(&(k + 1)) {
            std::cmp::Ordering::Less => scale,
            std::cmp::Ordering::Equal => -k1 * scale,
            std::cmp::Ordering::Greater => 0.0,
        }
    })
}

/// An edge of a strongly connected part: its arrow's name, source and
/// target (indices in the part), and its restriction to the differences.
struct Edge {
    name: String,
    from: usize,
    to: usize,
    matrix: DMatrix<f64>,
    /// The arrow's matrix itself (for the Kronecker test).
    full: DMatrix<f64>,
}

/// The state of the cycle enumeration: where cycles start, the current
/// path (edge indices), the products left to form, the best cycle so far.
struct CycleSearch {
    start: usize,
    path: Vec<usize>,
    work: Work,
    best: (f64, Vec<usize>),
    stop_at_one: bool,
}

/// A strongly connected part of the automaton with at least one edge.
struct Part {
    dims: Vec<usize>,
    edges: Vec<Edge>,
}

fn spectral_radius(m: &DMatrix<f64>) -> f64 {
    match m.shape() {
        (0, _) => return 0.0,
        (1, 1) => return m[(0, 0)].abs(),
        (2, 2) => {
            // λ = t/2 ± √((a − d)²/4 + bc) (no cancellation for a scaled identity): a real
            // pair, or complex with |λ|² = det.
            let (t, det) = (m[(0, 0)] + m[(1, 1)], m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)]);
            let half = (m[(0, 0)] - m[(1, 1)]) / 2.0;
            let disc = half * half + m[(0, 1)] * m[(1, 0)];
            return if disc >= 0.0 { t.abs() / 2.0 + disc.sqrt() } else { det.sqrt() };
        }
        _ => {}
    }
    // Eigenvalues without Schur vectors first (thousands of cycles per part);
    // the Schur decomposition with its retries where that iteration stalls.
    match crate::algebra::hessenberg_eigenvalues(m).or_else(|| crate::algebra::eigenvalues(m)) {
        Some(eig) => eig.iter().map(|l| l.norm()).fold(0.0, f64::max),
        // A stalled eigenvalue iteration proves nothing: no lower bound from it.
        None => 0.0,
    }
}

fn spectral_norm(m: &DMatrix<f64>) -> f64 {
    match m.shape() {
        _ if m.is_empty() => return 0.0,
        (1, 1) => return m[(0, 0)].abs(),
        (2, 2) => {
            // σ² are the eigenvalues of MᵀM: (F ± √(F² − 4 det²)) / 2 with F = ‖M‖²_F.
            let f = m.norm_squared();
            let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
            return ((f + (f * f - 4.0 * det * det).max(0.0).sqrt()) / 2.0).sqrt();
        }
        _ => {}
    }
    // Not finite, or no convergence: no bound (infinite).
    crate::algebra::svd(m, false).map_or(f64::INFINITY, |s| s.singular_values.iter().copied().fold(0.0, f64::max))
}

/// The ∞-norm (largest absolute row sum): an operator norm, cheap.
fn infinity_norm(m: &DMatrix<f64>) -> f64 {
    m.row_iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// The 1-norm (largest absolute column sum).
fn one_norm(m: &DMatrix<f64>) -> f64 {
    m.column_iter().map(|c| c.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// A norm of the restricted matrices, with the matrices written in the
/// coordinates it is measured in.
struct Basis {
    matrices: Vec<DMatrix<f64>>,
    norm: fn(&DMatrix<f64>) -> f64,
    /// The norm needs a decomposition (the spectral norm), not a sum of entries.
    decomposes: bool,
}

/// From the orthonormal difference coordinates of [`difference_basis`] to
/// the coordinates of the differences of neighbours `e_i − e_{i+1}`, in
/// which the restricted matrices are the difference scheme's (the classic
/// convergence test bounds their ∞-norms): `(T, T⁻¹)`, `T = P B` with `P`
/// the partial sums (the left inverse of `D = [e_i − e_{i+1}]`), `T⁻¹ = Bᵀ D`.
fn to_neighbour_differences(n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let b = difference_basis(n);
    let partial = DMatrix::from_fn(n - 1, n, |i, j| if j <= i { 1.0 } else { 0.0 });
    let d = DMatrix::from_fn(n, n - 1, |i, k| match i {
        _ if i == k => 1.0,
        _ if i == k + 1 => -1.0,
        _ => 0.0,
    });
    (partial * &b, b.transpose() * d)
}

/// `M = A ⊗ B` with `A` `p × p` and `B` `q × q` (`p q` = the size of `M`),
/// both column-stochastic, when `M` is one (to `1e-12` of its largest
/// entry): the rank-one rearrangement of Van Loan and Pitsianis.
fn kronecker_factors(m: &DMatrix<f64>, p: usize, q: usize) -> Option<Factors> {
    if m.nrows() != p * q || m.ncols() != p * q {
        return None;
    }
    // R[(i1, j1), (i2, j2)] = M[i1 q + i2, j1 q + j2] = A[i1, j1] B[i2, j2].
    let r = |a: usize, b: usize| m[((a / p) * q + b / q, (a % p) * q + b % q)];
    let (mut best, mut at) = (0.0f64, (0, 0));
    for a in 0..p * p {
        for b in 0..q * q {
            if r(a, b).abs() > best {
                (best, at) = (r(a, b).abs(), (a, b));
            }
        }
    }
    if best == 0.0 {
        return None;
    }
    let pivot = r(at.0, at.1);
    let a = DMatrix::from_fn(p, p, |i, j| r(i * p + j, at.1));
    let b = DMatrix::from_fn(q, q, |i, j| r(at.0, i * q + j) / pivot);
    for x in 0..p * p {
        for y in 0..q * q {
            if (r(x, y) - a[(x / p, x % p)] * b[(y / q, y % q)]).abs() > ROUNDING * best {
                return None;
            }
        }
    }
    // Scaled so that A's columns sum to 1 (then B's do, M being column-stochastic).
    let sum = a.column(0).sum();
    if sum.abs() <= 1e-300 || sum.is_nan() {
        return None;
    }
    let (a, b) = (a / sum, b * sum);
    let stochastic = |x: &DMatrix<f64>| x.column_iter().all(|c| (c.sum() - 1.0).abs() < STOCHASTIC);
    (stochastic(&a) && stochastic(&b)).then_some((a, b))
}

/// The factors `(A, B)` of a map `A ⊗ B`.
type Factors = (DMatrix<f64>, DMatrix<f64>);

/// One state's part of single maps `A ⊗ B` (tensor-product surfaces): the
/// part of the `A`s and the part of the `B`s, each a one-state system.
fn kronecker_parts(part: &Part) -> Option<(Part, Part)> {
    let [n] = part.dims[..] else { return None };
    let factorizations = (2..n).filter(|p| n % p == 0 && n / p >= 2);
    for p in factorizations {
        let q = n / p;
        let factors: Option<Vec<Factors>> = part.edges.iter().map(|e| kronecker_factors(&e.full, p, q)).collect();
        let Some(factors) = factors else { continue };
        // Each factor's distinct matrices (T_i ⊗ T_j over all pairs repeats every T_i).
        let side = |k: usize, which: fn(&Factors) -> &DMatrix<f64>| {
            let b = difference_basis(k);
            let mut edges: Vec<Edge> = Vec::new();
            for (e, f) in part.edges.iter().zip(&factors) {
                let m = which(f);
                if edges.iter().any(|d| (&d.full - m).amax() <= SAME_MATRIX * m.amax().max(1.0)) {
                    continue;
                }
                let matrix = b.transpose() * m * &b;
                edges.push(Edge { name: e.name.clone(), from: 0, to: 0, matrix, full: m.clone() });
            }
            Part { dims: vec![k], edges }
        };
        return Some((side(p, |f| &f.0), side(q, |f| &f.1)));
    }
    None
}

/// Bounds on the JSR of the subdivision arrows of `automaton` restricted to
/// the difference subspaces, over the paths of each strongly connected part
/// (the largest over the parts).
///
/// Complexity: bounded by the work of [`JsrSettings`]: products, eigenvalues
/// and singular values of `(n − 1) × (n − 1)` restricted matrices.
///
/// # Errors
/// [`JsrError::NotStochastic`] for a subdivision arrow whose columns do not sum to 1.
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let chaikin = bcifs::instantiate(&design, &[("a".into(), 0.25), ("b".into(), 0.25)]).unwrap();
/// let jsr = bcifs::analysis::jsr(&chaikin.automaton, &Default::default()).unwrap();
/// assert!((jsr.lower - 0.5).abs() < 1e-12 && jsr.upper < 0.5 + 1e-3);
/// assert_eq!(jsr.verdict(), bcifs::analysis::Verdict::Converges);
/// ```
pub fn jsr(automaton: &Automaton<f64>, settings: &JsrSettings) -> Result<Jsr, JsrError> {
    // The parts are bounded independently (on the pool's threads), then combined in their order.
    let bounds: Vec<(f64, Vec<String>, f64)> = parts(automaton)?
        .par_iter()
        .map(|part| {
            let (lower, witness) = part.lower_bound(settings, false);
            let upper = if lower >= 1.0 - ROUNDING {
                part.norm_bound(settings)
            } else {
                // A tensor-product part is bounded by its factors' small systems first; the branch
                // and bound over its large matrices runs only when that does not prove convergence.
                let factors = part.kronecker_bound(settings);
                if factors < 1.0 { factors } else { part.upper_bound(lower, settings).min(factors) }
            };
            (lower, witness, upper)
        })
        .collect();
    Ok(combined(bounds))
}

/// The parts' bounds `(lower, witness, upper)` combined in their order. As
/// within a part, the first cycle that attains the lower bound within
/// rounding is the witness: parts that tie (the same patch rotated) do not
/// hand it on by their last bits.
fn combined(bounds: Vec<(f64, Vec<String>, f64)>) -> Jsr {
    let mut out = Jsr { lower: 0.0, upper: 0.0, witness: Vec::new() };
    for (lower, witness, upper) in bounds {
        if lower > out.lower + ROUNDING || out.witness.is_empty() && !witness.is_empty() {
            out.lower = out.lower.max(lower);
            out.witness = witness;
        }
        out.upper = out.upper.max(upper.max(lower));
    }
    out
}

/// The convergence verdict alone, as [`jsr`] would prove it but with early
/// exits: a part is settled as soon as the adapted norm bound is below 1, a
/// cycle reaches `ρ^(1/length) ≥ 1`, or the branch and bound closes for a
/// target just below 1 (the tight bounds are not needed for a verdict). For
/// maps over a parameter plane: each decision is a proof, as in [`jsr`], and
/// it can only be more decisive for the same budget.
///
/// # Errors
/// [`JsrError::NotStochastic`] for a subdivision arrow whose columns do not sum to 1.
pub fn jsr_verdict(automaton: &Automaton<f64>, settings: &JsrSettings) -> Result<Verdict, JsrError> {
    // Diverges if a part diverges, else Undecided if one is, else Converges: the parts are
    // settled independently, on the pool's threads.
    let verdicts: Vec<Verdict> = parts(automaton)?.par_iter().map(|part| part.verdict(settings)).collect();
    Ok(if verdicts.contains(&Verdict::Diverges) {
        Verdict::Diverges
    } else if verdicts.contains(&Verdict::Undecided) {
        Verdict::Undecided
    } else {
        Verdict::Converges
    })
}

/// The strongly connected parts with an edge, their matrices restricted.
fn parts(automaton: &Automaton<f64>) -> Result<Vec<Part>, JsrError> {
    let mut graph: DiGraph<usize, usize> = DiGraph::new();
    let mut node_of = std::collections::HashMap::new();
    for (id, state) in automaton.states() {
        node_of.insert(id, graph.add_node(state.dim));
    }
    let mut arrows = Vec::new();
    for (id, arrow) in automaton.arrows() {
        if arrow.kind != ArrowKind::Subdivision {
            continue;
        }
        for (column, col) in arrow.matrix.column_iter().enumerate() {
            let sum = col.sum();
            if !sum.is_finite() || (sum - 1.0).abs() > STOCHASTIC {
                return Err(JsrError::NotStochastic { arrow: arrow.name.clone(), column, sum });
            }
        }
        let (from, to) = automaton.arrow_ends(id);
        graph.add_edge(node_of[&from], node_of[&to], arrows.len());
        arrows.push((arrow.name.clone(), &arrow.matrix));
    }
    let mut out = Vec::new();
    for component in tarjan_scc(&graph) {
        let index = |n| component.iter().position(|c| *c == n);
        let dims: Vec<usize> = component.iter().map(|n| graph[*n]).collect();
        let mut edges = Vec::new();
        for e in graph.edge_indices() {
            let Some((a, b)) = graph.edge_endpoints(e) else { continue };
            if let (Some(from), Some(to)) = (index(a), index(b)) {
                let (name, m) = &arrows[graph[e]];
                let matrix = difference_basis(dims[from]).transpose() * *m * difference_basis(dims[to]);
                edges.push(Edge { name: name.clone(), from, to, matrix, full: (*m).clone() });
            }
        }
        if !edges.is_empty() && dims.iter().all(|d| *d >= 2) {
            out.push(Part { dims, edges });
        }
    }
    Ok(out)
}

impl Part {
    /// This part's verdict, for [`jsr_verdict`].
    fn verdict(&self, settings: &JsrSettings) -> Verdict {
        // Contracting in the Euclidean norm already settles it, without adapting the norm.
        if self.edges.iter().all(|e| spectral_norm(&e.matrix) < 1.0) {
            return Verdict::Converges;
        }
        if self.kronecker_bound(settings) < 1.0 {
            return Verdict::Converges;
        }
        let mut work = Work(settings.norm_work);
        let bases = self.bases(&mut work);
        let norms: Vec<Vec<f64>> = bases.iter().map(|b| b.matrices.iter().map(b.norm).collect()).collect();
        if norms.iter().any(|n| n.iter().all(|&x| x < 1.0)) {
            return Verdict::Converges;
        }
        let (lower, _) = self.lower_bound(settings, true);
        if lower >= 1.0 - ROUNDING {
            return Verdict::Diverges;
        }
        let gamma = 1.0 - SLACK;
        let share = work.0 / bases.len() as f64;
        let closed =
            gamma > lower && bases.iter().zip(&norms).any(|(basis, n)| self.closes(basis, n, gamma, &mut Work(share)));
        if closed { Verdict::Converges } else { Verdict::Undecided }
    }

    /// `max ρ(P)^(1/|P|)` over the cycles of length up to `max_cycle`, by a
    /// depth-first walk from every state; the cycle that attains it. With
    /// `stop_at_one`, the first cycle that proves divergence ends the search.
    fn lower_bound(&self, settings: &JsrSettings, stop_at_one: bool) -> (f64, Vec<String>) {
        let mut search = CycleSearch {
            start: 0,
            path: Vec::new(),
            work: Work(settings.cycle_work),
            best: (0.0, Vec::new()),
            stop_at_one,
        };
        for start in 0..self.dims.len() {
            let n = self.dims[start] - 1;
            search.start = start;
            self.cycles(start, &DMatrix::identity(n, n), settings.max_cycle, &mut search);
        }
        let (rho, path) = search.best;
        (rho, path.iter().map(|&e| self.edges[e].name.clone()).collect())
    }

    fn cycles(&self, at: usize, product: &DMatrix<f64>, left: usize, search: &mut CycleSearch) {
        if left == 0 || search.stop_at_one && search.best.0 >= 1.0 - ROUNDING {
            return;
        }
        for (k, e) in self.edges.iter().enumerate().filter(|(_, e)| e.from == at) {
            if !search.work.spend(product_ops(product, &e.matrix)) {
                return;
            }
            let p = product * &e.matrix;
            search.path.push(k);
            if e.to == search.start && search.work.spend(decomposition_ops(&p)) {
                let rho = spectral_radius(&p).powf(1.0 / search.path.len() as f64);
                if rho > search.best.0 + ROUNDING {
                    search.best = (rho, search.path.clone());
                }
            }
            self.cycles(e.to, &p, left - 1, search);
            search.path.pop();
        }
    }

    /// Ellipsoidal norms `‖x‖_s = |L_s x|` (`Y_s = L_sᵀ L_s`) from the Perron
    /// eigenvector of `Y_t ↦ Σ_{e: s → t} R_eᵀ Y_s R_e`: in them every
    /// matrix has norm at most the ρ₂ bound. The matrices in those norms.
    fn adapted(&self, work: &mut Work) -> Vec<DMatrix<f64>> {
        let m: Vec<usize> = self.dims.iter().map(|d| d - 1).collect();
        let mut y: Vec<DMatrix<f64>> = m.iter().map(|&k| DMatrix::identity(k, k)).collect();
        let round: f64 = self.edges.iter().map(|e| 2.0 * product_ops(&e.matrix, &e.matrix)).sum();
        for _ in 0..100 {
            if !work.spend(round) {
                break;
            }
            let mut next: Vec<DMatrix<f64>> = m.iter().map(|&k| DMatrix::zeros(k, k)).collect();
            for e in &self.edges {
                next[e.to] += e.matrix.transpose() * &y[e.from] * &e.matrix;
            }
            let scale = next.iter().map(|x| x.norm()).fold(0.0, f64::max);
            if !(scale > 0.0 && scale.is_finite()) {
                break;
            }
            let mut change: f64 = 0.0;
            for (x, n) in y.iter_mut().zip(next) {
                // A little of the identity keeps the norm definite.
                let n = n / scale + DMatrix::identity(x.nrows(), x.ncols()) * DEFINITE;
                change = change.max((&n - &*x).amax());
                *x = n;
            }
            if change < SETTLED {
                break;
            }
        }
        let factors: Vec<Option<(DMatrix<f64>, DMatrix<f64>)>> = y
            .into_iter()
            .map(|x| {
                let l = nalgebra::Cholesky::new(x)?.l().transpose();
                let inv = l.clone().try_inverse()?;
                Some((l, inv))
            })
            .collect();
        self.edges
            .iter()
            .map(|e| match (&factors[e.from], &factors[e.to]) {
                (Some((l, _)), Some((_, inv))) => l * &e.matrix * inv,
                _ => e.matrix.clone(),
            })
            .collect()
    }

    /// For maps `A_e ⊗ B_e` of one state (a tensor-product surface): the
    /// differences of the product space are `S_p ⊗ R^q + R^p ⊗ S_q` (`S`:
    /// the differences of a factor), two invariant subspaces, so the JSR on
    /// them is at most `max(ρ_A ρ⁺_B, ρ⁺_A ρ_B)`, with `ρ` the factors' JSR
    /// on differences and `ρ⁺ = max(1, ρ)` on the whole space (column-
    /// stochastic: the quotient by the differences is 1). Infinite when the
    /// maps are not such products.
    fn kronecker_bound(&self, settings: &JsrSettings) -> f64 {
        let Some((a, b)) = kronecker_parts(self) else { return f64::INFINITY };
        let bound = |part: &Part| {
            let (lower, _) = part.lower_bound(settings, false);
            part.upper_bound(lower, settings).max(lower)
        };
        let (ra, rb) = (bound(&a), bound(&b));
        (ra * rb.max(1.0)).max(ra.max(1.0) * rb)
    }

    /// The largest matrix norm in the adapted norms: an upper bound by itself.
    fn norm_bound(&self, settings: &JsrSettings) -> f64 {
        self.adapted(&mut Work(settings.norm_work)).iter().map(spectral_norm).fold(0.0, f64::max)
    }

    /// The norms the branch and bound tries: the adapted ellipsoidal norm
    /// (spectral norms), and the ∞- and 1-norms of the neighbour
    /// differences (a difference scheme contracting in the ∞-norm, as the
    /// classic test of a curve scheme, is decided there when the ellipsoid
    /// needs long products).
    fn bases(&self, work: &mut Work) -> Vec<Basis> {
        let adapted = self.adapted(work);
        let change: Vec<(DMatrix<f64>, DMatrix<f64>)> =
            self.dims.iter().map(|&n| to_neighbour_differences(n)).collect();
        let neighbours: Vec<DMatrix<f64>> =
            self.edges.iter().map(|e| &change[e.from].0 * &e.matrix * &change[e.to].1).collect();
        vec![
            Basis { matrices: adapted, norm: spectral_norm, decomposes: true },
            Basis { matrices: neighbours.clone(), norm: infinity_norm, decomposes: false },
            Basis { matrices: neighbours, norm: one_norm, decomposes: false },
        ]
    }

    /// The smallest target `γ` above `lower` whose branch and bound closes
    /// within the budget in one of the [`Part::bases`], or the smallest of
    /// their largest matrix norms; when that is not below 1 (undecided), the
    /// best bound the products of every length give
    /// ([`Part::fixed_length_bound`]), if smaller.
    fn upper_bound(&self, lower: f64, settings: &JsrSettings) -> f64 {
        let mut work = Work(settings.norm_work);
        let bases = self.bases(&mut work);
        let norms: Vec<Vec<f64>> = bases.iter().map(|b| b.matrices.iter().map(b.norm).collect()).collect();
        let single = norms.iter().map(|n| n.iter().copied().fold(0.0, f64::max)).fold(f64::INFINITY, f64::min);

        if single <= lower * (1.0 + SLACK) {
            return single;
        }
        // The loosest target first (it decides convergence, and smaller ones need
        // longer products), then tighter ones while they close.
        let mut best = single;
        for t in [0.99, 0.9, 0.7, 0.5, 0.3, 0.1, 0.03, 1e-2, 1e-3, 1e-4] {
            let gamma = lower + (single.min(1.0).max(lower) - lower) * t;
            if gamma >= best || gamma <= lower {
                continue;
            }
            // Each target gets half of what is left, shared by the norms.
            let budget = work.0 / 2.0;
            let mut closed = false;
            for (basis, n) in bases.iter().zip(&norms) {
                let mut share = Work(budget / bases.len() as f64);
                closed = self.closes(basis, n, gamma, &mut share);
                work.0 -= budget / bases.len() as f64 - share.0.max(0.0);
                if closed {
                    break;
                }
            }
            if !closed || work.0 <= 0.0 {
                break;
            }
            best = gamma;
        }
        if best < 1.0 {
            return best;
        }
        // Undecided: products of every length L (with a quarter of the work again, shared by the
        // norms) give the best bound found, which no target needed to close.
        let share = settings.norm_work / 4.0 / bases.len() as f64;
        bases.iter().map(|b| self.fixed_length_bound(b, &mut Work(share))).fold(best, f64::min)
    }

    /// The least, over lengths `L` while the work lasts (and 4096 products a
    /// length at most), of the largest norm (in `basis`) of a product of `L`
    /// maps along the automaton — every path of length `L` from every state —
    /// to the power `1/L`: an upper bound by itself (the norms are
    /// submultiplicative through the bases' changes of state), which no
    /// target of the branch and bound needs to close.
    fn fixed_length_bound(&self, basis: &Basis, work: &mut Work) -> f64 {
        let mut level: Vec<(usize, DMatrix<f64>)> =
            self.dims.iter().enumerate().map(|(s, &d)| (s, DMatrix::identity(d - 1, d - 1))).collect();
        let mut best = f64::INFINITY;
        for len in 1..=32 {
            let (mut next, mut worst) = (Vec::new(), 0.0f64);
            for (at, p) in &level {
                for (k, e) in self.edges.iter().enumerate().filter(|(_, e)| e.from == *at) {
                    let q = p * &basis.matrices[k];
                    let ops = if basis.decomposes { decomposition_ops(&q) } else { (q.nrows() * q.ncols()) as f64 };
                    if !work.spend(product_ops(p, &basis.matrices[k]) + ops) {
                        return best;
                    }
                    worst = worst.max((basis.norm)(&q));
                    next.push((e.to, q));
                }
            }
            if next.is_empty() {
                break;
            }
            best = best.min(worst.powf(1.0 / f64::from(len)));
            if next.len() > 4096 {
                break;
            }
            level = next;
        }
        best
    }

    /// Whether every path from every state reaches, within the budget, a
    /// prefix whose norm bound (in `basis`) is at most `γ^length`.
    fn closes(&self, basis: &Basis, norms: &[f64], gamma: f64, work: &mut Work) -> bool {
        // (end state, product, length, bound on its norm)
        let mut open: Vec<(usize, DMatrix<f64>, i32, f64)> = Vec::new();
        for (s, d) in self.dims.iter().enumerate() {
            open.push((s, DMatrix::identity(d - 1, d - 1), 0, 1.0));
        }
        while let Some((at, product, len, bound)) = open.pop() {
            for (k, e) in self.edges.iter().enumerate().filter(|(_, e)| e.from == at) {
                let p = &product * &basis.matrices[k];
                let ops = if basis.decomposes { decomposition_ops(&p) } else { (p.nrows() * p.ncols()) as f64 };
                if !work.spend(product_ops(&product, &basis.matrices[k]) + ops) {
                    return false;
                }
                let b = (bound * norms[k]).min((basis.norm)(&p));
                if b <= gamma.powi(len + 1) {
                    continue;
                }
                open.push((e.to, p, len + 1, b));
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 2 × 2 closed forms agree with the general decompositions (real,
    /// complex and double eigenvalues, singular and rotation matrices).
    #[test]
    fn closed_forms_of_two_by_two_agree_with_the_general_ones() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        let mut cases: Vec<DMatrix<f64>> = (0..200).map(|_| DMatrix::from_fn(2, 2, |_, _| next())).collect();
        cases.push(DMatrix::from_row_slice(2, 2, &[0.5, -0.5, 0.5, 0.5]));
        cases.push(DMatrix::from_row_slice(2, 2, &[0.3, 0.0, 0.0, 0.3]));
        cases.push(DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]));
        for m in cases {
            let rho = crate::algebra::eigenvalues(&m).unwrap().iter().map(|l| l.norm()).fold(0.0, f64::max);
            let sigma = m.clone().svd(false, false).singular_values.max();
            assert!((spectral_radius(&m) - rho).abs() < 1e-9 * (1.0 + rho), "{m}");
            assert!((spectral_norm(&m) - sigma).abs() < 1e-12 * (1.0 + sigma), "{m}");
        }
    }

    /// Parts whose lower bounds tie within rounding keep the first one's
    /// witness; a larger bound beyond rounding takes it; the upper bound is
    /// the largest.
    #[test]
    fn tied_parts_keep_the_first_witness() {
        let part = |lower: f64, name: &str, upper: f64| (lower, vec![name.to_string()], upper);
        let tie = combined(vec![part(0.5, "A", 0.6), part(0.5 + 4e-16, "B", 0.7), part(0.5 - 1e-16, "C", 0.5)]);
        assert_eq!((tie.witness, tie.upper), (vec!["A".to_string()], 0.7));
        let more = combined(vec![part(0.5, "A", 0.6), part(0.5 + 1e-9, "B", 0.6)]);
        assert_eq!((more.witness, more.lower), (vec!["B".to_string()], 0.5 + 1e-9));
        let first = combined(vec![(0.0, Vec::new(), 0.0), part(0.3, "D", 0.4)]);
        assert_eq!(first.witness, vec!["D".to_string()]);
    }

    #[test]
    fn the_difference_basis_is_orthonormal_and_sums_to_zero() {
        for n in 1..6 {
            let q = difference_basis(n);
            assert!((q.transpose() * &q - DMatrix::identity(n - 1, n - 1)).amax() < 1e-15);
            assert!(q.row_sum().amax() < 1e-15);
        }
    }
}
