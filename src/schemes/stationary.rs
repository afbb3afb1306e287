//! Stationary subdivision schemes as IFS (Schaefer, Levin, Goldman,
//! *Subdivision schemes and attractors*, Schaefer et al. 2005).
//!
//! A scheme refines control points `p^k → p^{k+1}` by fixed rules; the rows
//! of its subdivision matrix `S` that depend on `n` consecutive control points
//! only are cut into square blocks `S_1, …, S_p` (overlapping rows allowed,
//! §2) whose products of length `k` applied to the control points converge
//! to the limit curve. In bcifs the blocks become barycentric subdivision
//! matrices `T_i = S_iᵀ` (DESIGN §4): `C_child = C · T_i` for control points
//! held as columns. The lifted ordinary IFS of eq. (2), `f_i(X) = X P⁻¹ S_i P`,
//! is in [`LiftedIfs`].
//!
//! Three ways to get blocks:
//! - [`Rules`]: a uniform scheme given by its rules (masks), e.g. the cubic
//!   B-spline rules of eq. (4), the four-point scheme (§2.3), the ternary
//!   5-point scheme of Siddiqi et al. 2014;
//! - [`BSpline`]: a B-spline of any degree over a knot sequence that is
//!   self-similar under p-adic refinement (uniform, end-interpolating,
//!   Bézier), by blossoming, exactly over the rationals;
//! - explicit matrices ([`koch_blocks`], [`sierpinski_blocks`]: §4).
//!
//! [`ifs_file`] writes any of them as an automaton: an `edge` bounded by
//! `vertex` states when the blocks have the structure of a curve (found
//! automatically: §"vertex support" below), a `free` state otherwise.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

use crate::algebra::Surd;
use crate::design::{BuildError, Design, Model};
use crate::space::CellKind;

/// An exact matrix, row by row.
pub type ExactMatrix = Vec<Vec<Surd>>;

/// Why blocks cannot be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum StationaryError {
    /// The rules do not give `p` square blocks on `n` control points.
    #[error(
        "with {n} control points the {arity}-ary rules determine {run} consecutive new points; \
         {arity} square blocks need {n} + a positive multiple of {} of them (try more control points)", arity - 1
    )]
    Window {
        /// Control points.
        n: usize,
        /// Arity.
        arity: usize,
        /// Length of the longest run of new points determined by the `n` control points.
        run: usize,
    },
    /// A knot sequence that is not self-similar, or too short.
    #[error("{0}")]
    Knots(String),
    /// Rules with no point, or of an arity below 2.
    #[error("a scheme needs arity ≥ 2 and one non-empty rule per residue")]
    Rules,
    /// The generated design does not build: its model does not fit the
    /// automaton (a user's control points), or a bug (anything else).
    #[error("{0}")]
    Design(String),
}

/// A uniform stationary scheme: new point `p·i + r` is `Σ w · p_{i+o}` over
/// the `(o, w)` of rule `r` (`r = 0 … p-1`).
#[derive(Clone, Debug, PartialEq)]
pub struct Rules {
    /// `p`.
    pub arity: usize,
    /// One rule per residue: `(offset, weight)` pairs.
    pub rules: Vec<Vec<(i64, Surd)>>,
}

fn q(n: i64, d: i64) -> Surd {
    Surd::frac(n, d)
}

impl Rules {
    /// A scheme from its rules.
    ///
    /// # Errors
    /// [`StationaryError::Rules`] for an arity below 2 or an empty rule.
    pub fn new(rules: Vec<Vec<(i64, Surd)>>) -> Result<Rules, StationaryError> {
        if rules.len() < 2 || rules.iter().any(|r| r.iter().all(|(_, w)| w.is_zero())) {
            return Err(StationaryError::Rules);
        }
        Ok(Rules { arity: rules.len(), rules })
    }

    /// Uniform cubic B-spline, eq. (4): `p_{2i} = (p_{i-1} + 6 p_i + p_{i+1})/8`, `p_{2i+1} = (p_i + p_{i+1})/2`.
    pub fn cubic_bspline() -> Rules {
        Rules {
            arity: 2,
            rules: vec![vec![(-1, q(1, 8)), (0, q(3, 4)), (1, q(1, 8))], vec![(0, q(1, 2)), (1, q(1, 2))]],
        }
    }

    /// The interpolatory four-point scheme (§2.3): `p_{2i} = p_i`,
    /// `p_{2i+1} = (-p_{i-1} + 9 p_i + 9 p_{i+1} - p_{i+2})/16`.
    pub fn four_point() -> Rules {
        Rules {
            arity: 2,
            rules: vec![vec![(0, Surd::int(1))], vec![(-1, q(-1, 16)), (0, q(9, 16)), (1, q(9, 16)), (2, q(-1, 16))]],
        }
    }

    /// Chaikin's corner cutting: `p_{2i} = (3 p_i + p_{i+1})/4`, `p_{2i+1} = (p_i + 3 p_{i+1})/4`.
    pub fn chaikin() -> Rules {
        Rules { arity: 2, rules: vec![vec![(0, q(3, 4)), (1, q(1, 4))], vec![(0, q(1, 4)), (1, q(3, 4))]] }
    }

    /// The rows of new points `f` determined by control points `0 … n-1`
    /// (`None` when a rule needs a point outside).
    fn row(&self, f: i64, n: usize) -> Option<Vec<Surd>> {
        let p = self.arity as i64;
        let (i, r) = (f.div_euclid(p), f.rem_euclid(p));
        let mut row = vec![Surd::zero(); n];
        for (o, w) in &self.rules[r as usize] {
            if w.is_zero() {
                continue;
            }
            let j = i + o;
            if j < 0 || j >= n as i64 {
                return None;
            }
            row[j as usize] = row[j as usize].add(w);
        }
        Some(row)
    }

    /// The longest run of consecutive new points that `n` control points determine.
    fn run(&self, n: usize) -> Vec<Vec<Surd>> {
        let p = self.arity as i64;
        let mut best: Vec<Vec<Surd>> = Vec::new();
        let mut current: Vec<Vec<Surd>> = Vec::new();
        let reach = self.rules.iter().flatten().map(|(o, _)| o.abs()).max().unwrap_or(0) + 1;
        for f in -p * reach..p * (n as i64 + reach) {
            match self.row(f, n) {
                Some(r) => current.push(r),
                None => {
                    if current.len() > best.len() {
                        best = std::mem::take(&mut current);
                    }
                    current.clear();
                }
            }
        }
        if current.len() > best.len() {
            best = current;
        }
        best
    }

    /// The `p` square blocks `S_0 … S_{p-1}` (`n × n`) on `n` control points:
    /// the longest run of new points the `n` points determine, cut into `p`
    /// windows of `n` rows with equal overlaps (§2, e.g. the 5×5 blocks of the
    /// cubic B-spline and the 7×7 blocks of the four-point scheme).
    ///
    /// # Errors
    /// [`StationaryError::Window`] when the run does not split into `p` windows.
    pub fn blocks(&self, n: usize) -> Result<Vec<ExactMatrix>, StationaryError> {
        let run = self.run(n);
        let p = self.arity;
        let err = StationaryError::Window { n, arity: p, run: run.len() };
        if run.len() <= n || !(run.len() - n).is_multiple_of(p - 1) {
            return Err(err);
        }
        let shift = (run.len() - n) / (p - 1);
        Ok((0..p).map(|l| run[l * shift..l * shift + n].to_vec()).collect())
    }

    /// The smallest number of control points whose blocks make a curve (an
    /// edge with vertex support), up to 64.
    pub fn smallest_window(&self) -> Option<usize> {
        (2..=64).find(|&n| self.blocks(n).is_ok_and(|b| curve_structure(&b).is_some()))
    }

    /// One refinement step of the control polygon (`d` coordinates per point):
    /// on a closed polygon every new point; on an open one the longest run of
    /// new points that the polygon determines.
    pub fn refine(&self, points: &[Vec<f64>], closed: bool) -> Vec<Vec<f64>> {
        let n = points.len();
        let d = points.first().map_or(0, Vec::len);
        let combine = |row: &[(usize, f64)]| -> Vec<f64> {
            (0..d).map(|a| row.iter().map(|(j, w)| w * points[*j][a]).sum()).collect()
        };
        if closed {
            let flat: Vec<f64> = points.iter().flatten().copied().collect();
            return self.refine_closed_flat(&flat, d).chunks_exact(d.max(1)).map(<[f64]>::to_vec).collect();
        }
        self.run(n)
            .iter()
            .map(|row| {
                let row: Vec<(usize, f64)> = row.iter().enumerate().map(|(j, w)| (j, w.to_f64())).collect();
                combine(&row)
            })
            .collect()
    }

    /// One refinement step of a closed polygon held flat (`d` coordinates per
    /// point, `p · n` points out): the hot path of length measurements.
    pub fn refine_closed_flat(&self, points: &[f64], d: usize) -> Vec<f64> {
        let n = (points.len() / d.max(1)) as i64;
        let weights: Vec<Vec<(i64, f64)>> =
            self.rules.iter().map(|r| r.iter().map(|(o, w)| (*o, w.to_f64())).collect()).collect();
        let mut out = Vec::with_capacity(points.len() * self.arity);
        for i in 0..n {
            for rule in &weights {
                let at = out.len();
                out.resize(at + d, 0.0);
                for (o, w) in rule {
                    let j = (i + o).rem_euclid(n) as usize;
                    for (x, y) in out[at..].iter_mut().zip(&points[j * d..(j + 1) * d]) {
                        *x += w * y;
                    }
                }
            }
        }
        out
    }

    /// The control polygon after `depth` refinements.
    pub fn polygon(&self, points: &[Vec<f64>], closed: bool, depth: usize) -> Vec<Vec<f64>> {
        let mut pts = points.to_vec();
        for _ in 0..depth {
            pts = self.refine(&pts, closed);
        }
        pts
    }
}

/// A B-spline curve of degree `d` over a knot sequence in the blossoming
/// convention (`n + d - 1` knots for `n` control points; control point `i`
/// is the blossom at `t_i … t_{i+d-1}`), e.g. `{0,1,2,3,4,5,6}` for the
/// uniform cubic with 5 control points and `{0,0,0,1,2,2,2}` for the
/// end-interpolating one (§2.1), `{0,0,1,1}` for a quadratic Bézier curve.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    /// Degree.
    pub degree: usize,
    /// Knots, non-decreasing.
    pub knots: Vec<BigRational>,
}

impl BSpline {
    /// A B-spline of degree `degree` over integer knots.
    ///
    /// # Errors
    /// [`StationaryError::Knots`] unless the knots are non-decreasing, at
    /// least `degree` of them, with a non-empty domain `[t_{d-1}, t_{n-1}]`.
    pub fn new(degree: usize, knots: &[i64]) -> Result<BSpline, StationaryError> {
        let knots: Vec<BigRational> = knots.iter().map(|k| BigRational::from_integer(BigInt::from(*k))).collect();
        let spline = BSpline { degree, knots };
        spline.validate()?;
        Ok(spline)
    }

    /// The uniform B-spline of degree `d` with `n` control points.
    ///
    /// # Errors
    /// As [`BSpline::new`] (`n > d` is needed).
    pub fn uniform(degree: usize, n: usize) -> Result<BSpline, StationaryError> {
        BSpline::new(degree, &(0..(n + degree) as i64 - 1).collect::<Vec<_>>())
    }

    /// The Bézier curve of degree `d` (`d + 1` control points).
    pub fn bezier(degree: usize) -> BSpline {
        let knots: Vec<i64> = (0..2 * degree).map(|i| i64::from(i >= degree)).collect();
        BSpline::new(degree, &knots).expect("Bézier knots are valid")
    }

    fn validate(&self) -> Result<(), StationaryError> {
        let d = self.degree;
        let m = self.knots.len();
        if d == 0 || m < d || self.knots.windows(2).any(|w| w[0] > w[1]) {
            return Err(StationaryError::Knots(format!(
                "degree {d} needs at least {d} non-decreasing knots (got {m})"
            )));
        }
        let n = m + 1 - d;
        if n <= d || self.knots[d - 1] >= self.knots[n - 1] {
            return Err(StationaryError::Knots("the domain [t_(d-1), t_(n-1)] is empty".into()));
        }
        Ok(())
    }

    /// Number of control points.
    pub fn control_points(&self) -> usize {
        self.knots.len() + 1 - self.degree
    }

    /// The blossom of the polynomial piece on `[t_k, t_{k+1}]` at `u`, as
    /// weights of the control points (de Boor's algorithm with one argument
    /// per level).
    fn blossom(&self, k: usize, u: &[BigRational]) -> Vec<BigRational> {
        let (d, n, t) = (self.degree, self.control_points(), &self.knots);
        let mut pts: Vec<Vec<BigRational>> = (k + 1 - d..=k + 1)
            .map(|i| (0..n).map(|j| if i == j { BigRational::one() } else { BigRational::zero() }).collect())
            .collect();
        for r in 1..=d {
            // pts[s] stands for control point i = k + 1 - d + s.
            for s in (r..=d).rev() {
                let i = k + 1 - d + s;
                let (lo, hi) = (&t[i - 1], &t[i + d - r]);
                let den = hi - lo;
                let (a, b) = ((hi - &u[r - 1]) / &den, (&u[r - 1] - lo) / &den);
                pts[s] = pts[s - 1].iter().zip(&pts[s]).map(|(x, y)| &a * x + &b * y).collect();
            }
        }
        pts.pop().expect("d + 1 points")
    }

    /// The `p` blocks `S_0 … S_{p-1}` of the p-adic split of the domain: row `i`
    /// of `S_l` is control point `i` of the `l`-th part, the blossom at the
    /// knots mapped affinely into that part (Ramshaw's blossoming, §2.1).
    ///
    /// # Errors
    /// [`StationaryError::Knots`] when the mapped knots would straddle an
    /// original knot (the sequence is not self-similar under the split).
    pub fn blocks(&self, arity: usize) -> Result<Vec<ExactMatrix>, StationaryError> {
        let (d, n, t) = (self.degree, self.control_points(), &self.knots);
        let (lo, hi) = (&t[d - 1], &t[n - 1]);
        let p = BigRational::from_integer(BigInt::from(arity));
        let mut blocks = Vec::with_capacity(arity);
        for l in 0..arity {
            let offset = lo + (hi - lo) * BigRational::from_integer(BigInt::from(l)) / &p;
            let phi = |x: &BigRational| &offset + (x - lo) / &p;
            let mapped: Vec<BigRational> = t.iter().map(phi).collect();
            let mut rows = Vec::with_capacity(n);
            for i in 0..n {
                // A piece of part l that uses control point i, then the original piece containing it.
                let (a, b) = (mapped[d - 1].clone(), mapped[n - 1].clone());
                let kk = (i.saturating_sub(1)..=(i + d - 1).min(n - 2))
                    .find(|&k| k >= d - 1 && mapped[k] < mapped[k + 1])
                    .ok_or_else(|| StationaryError::Knots(format!("no piece of part {l} uses control point {i}")))?;
                let (s, e) = (mapped[kk].clone().max(a), mapped[kk + 1].clone().min(b));
                let k = (d - 1..=n - 2).find(|&k| t[k] <= s && e <= t[k + 1] && t[k] < t[k + 1]).ok_or_else(|| {
                    StationaryError::Knots(format!(
                        "the knots are not self-similar under a {arity}-adic split: [{s}, {e}] straddles a knot"
                    ))
                })?;
                let weights = self.blossom(k, &mapped[i..i + d]);
                rows.push(weights.into_iter().map(Surd::rational).collect());
            }
            blocks.push(rows);
        }
        Ok(blocks)
    }
}

/// The Koch curve with five control points, §4.1 (the printed `S_1 … S_4`):
/// natural control points `(0,0), (1/3,0), (1/2,√3/6), (2/3,0), (1,0)`.
pub fn koch_blocks() -> Vec<ExactMatrix> {
    let m = |rows: [[(i64, i64); 5]; 5]| -> ExactMatrix {
        rows.iter().map(|r| r.iter().map(|(a, b)| Surd::frac(*a, *b)).collect()).collect()
    };
    let (z, o, t1, t2) = ((0, 1), (1, 1), (1, 3), (2, 3));
    vec![
        m([[o, z, z, z, z], [t2, t1, z, z, z], [t2, z, t1, z, z], [t1, t2, z, z, z], [z, o, z, z, z]]),
        m([[z, o, z, z, z], [z, t2, t1, z, z], [t1, z, t2, z, z], [z, t1, t2, z, z], [z, z, o, z, z]]),
        m([[z, z, o, z, z], [z, z, t2, t1, z], [z, z, t2, z, t1], [z, z, t1, t2, z], [z, z, z, o, z]]),
        m([[z, z, z, o, z], [z, z, z, t2, t1], [z, z, t1, z, t2], [z, z, z, t1, t2], [z, z, z, z, o]]),
    ]
}

/// The Sierpinski gasket with six control points, §4.2 (the printed
/// `S_1 … S_3`): corners 0, 2, 4 and edge points 1, 3, 5; the outer edges
/// are quadratic (Lagrange), the inner edges linear.
pub fn sierpinski_blocks() -> Vec<ExactMatrix> {
    let m = |rows: [[(i64, i64); 6]; 6]| -> ExactMatrix {
        rows.iter().map(|r| r.iter().map(|(a, b)| Surd::frac(*a, *b)).collect()).collect()
    };
    let (z, o, h) = ((0, 1), (1, 1), (1, 2));
    let (a, b, c) = ((3, 8), (3, 4), (-1, 8));
    vec![
        m([
            [o, z, z, z, z, z],
            [a, b, c, z, z, z],
            [z, o, z, z, z, z],
            [z, h, z, z, z, h],
            [z, z, z, z, z, o],
            [a, z, z, z, c, b],
        ]),
        m([
            [z, o, z, z, z, z],
            [c, b, a, z, z, z],
            [z, z, o, z, z, z],
            [z, z, a, b, c, z],
            [z, z, z, o, z, z],
            [z, h, z, h, z, z],
        ]),
        m([
            [z, z, z, z, z, o],
            [z, z, z, h, z, h],
            [z, z, z, o, z, z],
            [z, z, c, b, a, z],
            [z, z, z, z, o, z],
            [c, z, z, z, a, b],
        ]),
    ]
}

/// How blocks make a curve: the control points of the start vertex
/// (`start .. start + k`), of the end vertex (`end .. end + k`), and the
/// vertex rules at both ends (`k × k`, in the blocks' row convention).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveStructure {
    /// First control point of the start vertex.
    pub start: usize,
    /// First control point of the end vertex.
    pub end: usize,
    /// Vertex support: control points per vertex.
    pub support: usize,
    /// Rule of the start vertex: rows `start..start+k`, columns `start..start+k` of `S_0`.
    pub start_rule: ExactMatrix,
    /// Rule of the end vertex: the same block of `S_{p-1}` at `end`.
    pub end_rule: ExactMatrix,
}

/// Finds the smallest vertex support `k` such that the first block maps the
/// start window `[a, a+k)` into itself, the last block the end window
/// `[b, b+k)` into itself, and consecutive blocks agree where they meet
/// (`S_l` rows `[b, b+k)` = `S_{l+1}` rows `[a, a+k)`): the adjacency and
/// incidence constraints of a BC-IFS curve. `None` when there is none (a
/// set that is not a curve, such as the gasket).
pub fn curve_structure(blocks: &[ExactMatrix]) -> Option<CurveStructure> {
    let n = blocks.first()?.len();
    let p = blocks.len();
    let closed = |m: &ExactMatrix, a: usize, k: usize| {
        (a..a + k).all(|r| m[r].iter().enumerate().all(|(c, x)| x.is_zero() || (a..a + k).contains(&c)))
    };
    let sub =
        |m: &ExactMatrix, a: usize, k: usize| -> ExactMatrix { (a..a + k).map(|r| m[r][a..a + k].to_vec()).collect() };
    for k in 1..n {
        for a in 0..=n - k {
            if !closed(&blocks[0], a, k) {
                continue;
            }
            for b in (0..=n - k).rev() {
                if b == a || !closed(&blocks[p - 1], b, k) {
                    continue;
                }
                if (0..p - 1).all(|l| (0..k).all(|r| blocks[l][b + r] == blocks[l + 1][a + r])) {
                    return Some(CurveStructure {
                        start: a,
                        end: b,
                        support: k,
                        start_rule: sub(&blocks[0], a, k),
                        end_rule: sub(&blocks[p - 1], b, k),
                    });
                }
            }
        }
    }
    None
}

/// `Mᵀ`, row by row.
pub(super) fn transposed(m: &ExactMatrix) -> Vec<Vec<Surd>> {
    let n = m.first().map_or(0, Vec::len);
    (0..n).map(|c| m.iter().map(|row| row[c].clone()).collect()).collect()
}

/// The model of a generated design and the comment above it. The roots are
/// set by the generator (`e` for curves, `face` for surfaces).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSpec {
    /// Control points, layout, grid and step.
    pub model: Model,
    /// Comment above the model when the design is printed.
    pub comment: String,
}

fn internal(e: BuildError) -> StationaryError {
    match e.at() {
        crate::design::Locus::Model { .. } => StationaryError::Design(e.to_string()),
        _ => StationaryError::Design(format!("internal error in a scheme generator (please report): {e}")),
    }
}

/// The design of the IFS with blocks `S_i` (`T_i = S_iᵀ`): an edge with one
/// or two vertex states when [`curve_structure`] finds one (two when the
/// rules at the two ends differ), a free state otherwise.
///
/// # Errors
/// [`StationaryError::Design`]: a model that does not fit (too few control
/// points for its layout), or a bug.
pub fn ifs_design(
    name: &str,
    description: &str,
    comment: &str,
    blocks: &[ExactMatrix],
    model: &ModelSpec,
) -> Result<Design, StationaryError> {
    let n = blocks.first().map_or(0, Vec::len);
    let p = blocks.len();
    let mut b = Design::builder(name);
    b.description(description).doc(comment);
    let structure = curve_structure(blocks);
    let kind = if structure.is_some() { CellKind::Edge } else { CellKind::Free };
    b.state("e", n, kind).doc(format!("The attractor's space: {n} control points, BI^{n}."));
    let (v0, v1) = match &structure {
        Some(s) if s.start_rule == s.end_rule => ("v", "v"),
        Some(_) => ("v0", "v1"),
        None => ("", ""),
    };
    if let Some(s) = &structure {
        if v0 == v1 {
            b.state("v", s.support, CellKind::Vertex)
                .doc(format!("An end of the curve: {} control points.", s.support));
        } else {
            b.state("v0", s.support, CellKind::Vertex).doc("The start of the curve.");
            b.state("v1", s.support, CellKind::Vertex).doc("The end of the curve.");
        }
    }
    for (i, s) in blocks.iter().enumerate() {
        b.matrix(format!("T{i}"), "e", "e", transposed(s)).doc(format!(
            "Part {} of {p}: the transpose of the block S_{}.",
            i + 1,
            i + 1
        ));
    }
    if let Some(s) = &structure {
        let k = s.support;
        let (r0, r1) = if v0 == v1 { ("Tv", "Tv") } else { ("Tv0", "Tv1") };
        b.matrix(r0, v0, v0, transposed(&s.start_rule)).doc("Subdivision of the start vertex.");
        b.select("b0", "e", v0, s.start..s.start + k).doc("Start of the curve.");
        if v1 != v0 {
            b.matrix(r1, v1, v1, transposed(&s.end_rule)).doc("Subdivision of the end vertex.");
        }
        b.select("b1", "e", v1, s.end..s.end + k).doc("End of the curve.");
        for i in 0..p - 1 {
            b.adjacency(format!("T{i} b1 = T{} b0", i + 1)).doc("Consecutive parts meet.");
        }
        b.incidence(format!("T0 b0 = b0 {r0}")).incidence(format!("T{} b1 = b1 {r1}", p - 1));
        b.doc("The ends of the curve are fixed points of the vertex rules.");
    }
    b.model(model.model.clone().with_roots(vec!["e".into()])).doc(model.comment.clone());
    b.build().map_err(internal)
}

/// `A ⊗ B` (row-major pair indices: `(i, j) ↦ i · rows(B) + j`).
pub(super) fn kron(a: &ExactMatrix, b: &ExactMatrix) -> ExactMatrix {
    let (ra, ca) = (a.len(), a.first().map_or(0, Vec::len));
    let (rb, cb) = (b.len(), b.first().map_or(0, Vec::len));
    (0..ra * rb).map(|r| (0..ca * cb).map(|c| a[r / rb][c / cb].mul(&b[r % rb][c % cb])).collect()).collect()
}

/// The design of the tensor product of a curve IFS with itself: a face
/// with an `n × n` control grid (index `n · row + col`, rows along v) split
/// into `p × p` sub-faces `T{u}{v}` (matrix `(S_v ⊗ S_u)ᵀ`), edges along u
/// (`k` rows of `n`) and along v (`n` rows of `k`), and a `k × k` vertex,
/// with every adjacency and incidence constraint (Schaefer et al. 2005 §3.1 for the
/// bicubic patch; the ternary 5-point surfaces of Siddiqi et al. 2014).
///
/// # Errors
/// [`StationaryError::Rules`] when the blocks are not a curve with the same
/// vertex rule at both ends.
pub fn tensor_design(
    name: &str,
    description: &str,
    comment: &str,
    blocks: &[ExactMatrix],
    model: &ModelSpec,
) -> Result<Design, StationaryError> {
    let s = curve_structure(blocks).filter(|s| s.start_rule == s.end_rule).ok_or(StationaryError::Rules)?;
    let n = blocks[0].len();
    let p = blocks.len();
    let (a, e, k) = (s.start, s.end, s.support);
    let rule = &s.start_rule;
    let mut b = Design::builder(name);
    b.description(description).doc(comment);
    b.state("face", n * n, CellKind::Face)
        .doc(format!("The patch: {n}×{n} control grid (index {n}*row + col, rows along v)."));
    b.state("edge_u", k * n, CellKind::Edge).doc(format!("An edge along u: {k} rows of {n} (index {n}*row + col)."));
    b.state("edge_v", n * k, CellKind::Edge).doc(format!("An edge along v: {n} rows of {k} (index {k}*row + col)."));
    b.state("vertex", k * k, CellKind::Vertex).doc(format!("A corner: {k}×{k} control points (index {k}*row + col)."));
    let t = |u: usize, v: usize| format!("T{u}{v}");
    for v in 0..p {
        for u in 0..p {
            b.matrix(t(u, v), "face", "face", transposed(&kron(&blocks[v], &blocks[u])))
                .doc(format!("Sub-face ({u}, {v}): (S_{v} ⊗ S_{u})ᵀ."));
        }
    }
    for (i, block) in blocks.iter().enumerate() {
        b.matrix(format!("U{i}"), "edge_u", "edge_u", transposed(&kron(rule, block)))
            .doc(format!("Part {i} of an edge along u."));
    }
    for (j, block) in blocks.iter().enumerate() {
        b.matrix(format!("V{j}"), "edge_v", "edge_v", transposed(&kron(block, rule)))
            .doc(format!("Part {j} of an edge along v."));
    }
    b.matrix("W", "vertex", "vertex", transposed(&kron(rule, rule))).doc("The vertex rule.");
    let grid = |cols: usize, rows: std::ops::Range<usize>, columns: std::ops::Range<usize>| -> Vec<usize> {
        rows.flat_map(|r| columns.clone().map(move |c| r * cols + c)).collect()
    };
    b.select("bottom", "face", "edge_u", grid(n, a..a + k, 0..n)).doc("Bottom edge.");
    b.select("top", "face", "edge_u", grid(n, e..e + k, 0..n)).doc("Top edge.");
    b.select("left", "face", "edge_v", grid(n, 0..n, a..a + k)).doc("Left edge.");
    b.select("right", "face", "edge_v", grid(n, 0..n, e..e + k)).doc("Right edge.");
    b.select("u_start", "edge_u", "vertex", grid(n, 0..k, a..a + k)).doc("Start of an edge along u.");
    b.select("u_end", "edge_u", "vertex", grid(n, 0..k, e..e + k)).doc("End of an edge along u.");
    b.select("v_start", "edge_v", "vertex", grid(k, a..a + k, 0..k)).doc("Start of an edge along v.");
    b.select("v_end", "edge_v", "vertex", grid(k, e..e + k, 0..k)).doc("End of an edge along v.");
    for v in 0..p {
        for u in 0..p {
            if u + 1 < p {
                b.adjacency(format!("{} right = {} left", t(u, v), t(u + 1, v)));
            }
            if v + 1 < p {
                b.adjacency(format!("{} top = {} bottom", t(u, v), t(u, v + 1)));
            }
        }
    }
    for i in 0..p - 1 {
        b.adjacency(format!("U{i} u_end = U{} u_start", i + 1));
        b.adjacency(format!("V{i} v_end = V{} v_start", i + 1));
    }
    b.doc("Neighbouring sub-cells share their common boundary.");
    for i in 0..p {
        b.incidence(format!("{} bottom = bottom U{i}", t(i, 0)));
        b.incidence(format!("{} top = top U{i}", t(i, p - 1)));
        b.incidence(format!("{} left = left V{i}", t(0, i)));
        b.incidence(format!("{} right = right V{i}", t(p - 1, i)));
    }
    b.incidence("U0 u_start = u_start W").incidence(format!("U{} u_end = u_end W", p - 1));
    b.incidence("V0 v_start = v_start W").incidence(format!("V{} v_end = v_end W", p - 1));
    b.doc("The boundary of a sub-cell is the subdivided boundary.");
    b.model(model.model.clone().with_roots(vec!["face".into()])).doc(model.comment.clone());
    b.build().map_err(internal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(m: &ExactMatrix) -> Vec<Vec<String>> {
        m.iter().map(|r| r.iter().map(Surd::to_string).collect()).collect()
    }

    fn parse(rows: &[&str]) -> Vec<Vec<String>> {
        rows.iter().map(|r| r.split_whitespace().map(str::to_string).collect()).collect()
    }

    /// The printed 5×5 blocks of the uniform cubic B-spline (§2.1).
    const CUBIC_S1: [&str; 5] =
        ["1/2 1/2 0 0 0", "1/8 3/4 1/8 0 0", "0 1/2 1/2 0 0", "0 1/8 3/4 1/8 0", "0 0 1/2 1/2 0"];
    const CUBIC_S2: [&str; 5] =
        ["0 1/2 1/2 0 0", "0 1/8 3/4 1/8 0", "0 0 1/2 1/2 0", "0 0 1/8 3/4 1/8", "0 0 0 1/2 1/2"];

    #[test]
    fn cubic_bspline_blocks_from_rules_and_from_knots_are_the_printed_ones() {
        let rules = Rules::cubic_bspline().blocks(5).unwrap();
        assert_eq!(text(&rules[0]), parse(&CUBIC_S1));
        assert_eq!(text(&rules[1]), parse(&CUBIC_S2));
        let knots = BSpline::uniform(3, 5).unwrap().blocks(2).unwrap();
        assert_eq!(knots, rules);
    }

    #[test]
    fn end_interpolating_bspline_blocks_are_the_printed_ones() {
        let b = BSpline::new(3, &[0, 0, 0, 1, 2, 2, 2]).unwrap().blocks(2).unwrap();
        assert_eq!(
            text(&b[0]),
            parse(&["1 0 0 0 0", "1/2 1/2 0 0 0", "0 3/4 1/4 0 0", "0 3/8 1/2 1/8 0", "0 1/4 1/2 1/4 0"])
        );
        assert_eq!(
            text(&b[1]),
            parse(&["0 1/4 1/2 1/4 0", "0 1/8 1/2 3/8 0", "0 0 1/4 3/4 0", "0 0 0 1/2 1/2", "0 0 0 0 1"])
        );
    }

    #[test]
    fn quadratic_bezier_blocks_are_de_casteljau() {
        let b = BSpline::bezier(2).blocks(2).unwrap();
        assert_eq!(text(&b[0]), parse(&["1 0 0", "1/2 1/2 0", "1/4 1/2 1/4"]));
        assert_eq!(text(&b[1]), parse(&["1/4 1/2 1/4", "0 1/2 1/2", "0 0 1"]));
    }

    #[test]
    fn four_point_blocks_are_the_printed_ones() {
        let b = Rules::four_point().blocks(7).unwrap();
        let e = |i: usize| (0..7).map(|j| if i == j { "1" } else { "0" }).collect::<Vec<_>>().join(" ");
        let r = |i: usize| {
            (0..7)
                .map(|j| match j as i64 - i as i64 {
                    -1 | 2 => "-1/16",
                    0 | 1 => "9/16",
                    _ => "0",
                })
                .collect::<Vec<_>>()
                .join(" ")
        };
        let s1 = [e(1), r(1), e(2), r(2), e(3), r(3), e(4)];
        let s2 = [e(2), r(2), e(3), r(3), e(4), r(4), e(5)];
        assert_eq!(text(&b[0]), parse(&s1.iter().map(String::as_str).collect::<Vec<_>>()));
        assert_eq!(text(&b[1]), parse(&s2.iter().map(String::as_str).collect::<Vec<_>>()));
    }

    #[test]
    fn curve_structures() {
        let s = curve_structure(&Rules::cubic_bspline().blocks(5).unwrap()).unwrap();
        assert_eq!((s.start, s.end, s.support), (0, 2, 3));
        let s = curve_structure(&Rules::four_point().blocks(7).unwrap()).unwrap();
        assert_eq!((s.start, s.end, s.support), (2, 4, 1));
        let s = curve_structure(&koch_blocks()).unwrap();
        assert_eq!((s.start, s.end, s.support), (0, 4, 1));
        assert!(curve_structure(&sierpinski_blocks()).is_none());
        assert_eq!(Rules::cubic_bspline().smallest_window(), Some(4));
        assert_eq!(Rules::four_point().smallest_window(), Some(6));
    }

    #[test]
    fn bad_knots_are_refused() {
        assert!(BSpline::new(3, &[0, 1, 0, 2]).is_err());
        assert!(BSpline::new(3, &[0, 0, 0]).is_err());
        // Not self-similar: the split point 3/2 is not where a 2-adic copy of the knots puts one.
        assert!(matches!(BSpline::new(2, &[0, 0, 1, 3, 3]).unwrap().blocks(2), Err(StationaryError::Knots(_))));
    }
}
