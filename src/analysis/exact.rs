//! The point query of a three-point curve ([`super::curve::curve_query`])
//! in exact arithmetic, for rational matrices (the corner cutting at
//! rational `a`, `b`).
//!
//! A column-stochastic `3 × 3` matrix has the eigenvalue 1, so its
//! characteristic polynomial is `(λ − 1)(λ² + pλ + q)` with `p = 1 − tr M`
//! and `q = det M`: the other two eigenvalues are `(−p ± √(p² − 4q))/2`,
//! rational or in the quadratic field `Q(√r)` of the discriminant `r`
//! (the corner cutting's `a`, `b`, `1 − a − b` are rational). Eigenvectors
//! are cross products of two rows of `M − λI` (no division), the
//! decomposition of `F(1) − F(0)` in an eigenbasis is Cramer's rule, and
//! every comparison the regions depend on (which eigenvalue dominates,
//! ties, signs, zero coordinates, collinearity at the junction) is exact.
//! Only the junction angle itself (an arccosine) is computed in floating
//! point, from the exact directions.

use std::cmp::Ordering;

use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::algebra::Surd;

/// `a + b√r` in the field of `r` (`r = 0`: the rationals, `b = 0`).
#[derive(Clone, Debug, PartialEq)]
struct Q2 {
    a: BigRational,
    b: BigRational,
}

impl Q2 {
    fn rational(a: BigRational) -> Q2 {
        Q2 { a, b: BigRational::zero() }
    }

    fn is_zero(&self) -> bool {
        self.a.is_zero() && self.b.is_zero()
    }
}

/// `Q(√r)`, `r` a positive rational that is not a square (or 0 for `Q`).
struct Field {
    r: BigRational,
}

impl Field {
    fn add(&self, x: &Q2, y: &Q2) -> Q2 {
        Q2 { a: &x.a + &y.a, b: &x.b + &y.b }
    }

    fn sub(&self, x: &Q2, y: &Q2) -> Q2 {
        Q2 { a: &x.a - &y.a, b: &x.b - &y.b }
    }

    fn mul(&self, x: &Q2, y: &Q2) -> Q2 {
        Q2 { a: &x.a * &y.a + &x.b * &y.b * &self.r, b: &x.a * &y.b + &x.b * &y.a }
    }

    fn inv(&self, x: &Q2) -> Option<Q2> {
        let norm = &x.a * &x.a - &x.b * &x.b * &self.r;
        (!norm.is_zero()).then(|| Q2 { a: &x.a / &norm, b: -&x.b / &norm })
    }

    /// The exact sign of `a + b√r`.
    fn sign(&self, x: &Q2) -> Ordering {
        let (sa, sb) = (x.a.cmp(&BigRational::zero()), x.b.cmp(&BigRational::zero()));
        if sb == Ordering::Equal || sa == sb {
            return if sa == Ordering::Equal { sb } else { sa };
        }
        if sa == Ordering::Equal {
            return sb;
        }
        // Opposite signs: the larger of a² and b²r wins.
        match (&x.a * &x.a).cmp(&(&x.b * &x.b * &self.r)) {
            Ordering::Greater => sa,
            Ordering::Less => sb,
            Ordering::Equal => Ordering::Equal,
        }
    }

    fn abs(&self, x: &Q2) -> Q2 {
        if self.sign(x) == Ordering::Less { Q2 { a: -&x.a, b: -&x.b } } else { x.clone() }
    }

    fn cmp(&self, x: &Q2, y: &Q2) -> Ordering {
        self.sign(&self.sub(x, y))
    }

    fn surd(&self, x: &Q2) -> Surd {
        let root = if x.b.is_zero() { Surd::zero() } else { Surd::sqrt_of(&self.r).unwrap_or_default() };
        Surd::rational(x.a.clone()).add(&root.scale(&x.b))
    }

    fn cross(&self, u: &[Q2; 3], v: &[Q2; 3]) -> [Q2; 3] {
        let c = |i: usize, j: usize| self.sub(&self.mul(&u[i], &v[j]), &self.mul(&u[j], &v[i]));
        [c(1, 2), c(2, 0), c(0, 1)]
    }

    fn dot(&self, u: &[Q2; 3], v: &[Q2; 3]) -> Q2 {
        (0..3).fold(Q2::rational(BigRational::zero()), |acc, i| self.add(&acc, &self.mul(&u[i], &v[i])))
    }
}

/// Whether `q` is the square of a rational.
fn is_square(q: &BigRational) -> Option<BigRational> {
    let (n, d) = (q.numer(), q.denom());
    if n.is_negative() {
        return None;
    }
    let (sn, sd) = (n.sqrt(), d.sqrt());
    (&sn * &sn == *n && &sd * &sd == *d).then(|| BigRational::new(sn, sd))
}

/// The exact eigen-decomposition of a rational column-stochastic `3 × 3`
/// matrix with real eigenvalues: its field, eigenvalues (decreasing) and
/// eigenvectors (first non-zero coordinate positive).
struct Eigen {
    field: Field,
    values: [Q2; 3],
    vectors: [[Q2; 3]; 3],
}

fn eigen(m: &[Vec<BigRational>]) -> Option<Eigen> {
    let e = |i: usize, j: usize| &m[i][j];
    let tr = e(0, 0) + e(1, 1) + e(2, 2);
    let minor = |i: usize, j: usize| e(i, i) * e(j, j) - e(i, j) * e(j, i);
    let c2 = minor(0, 1) + minor(0, 2) + minor(1, 2);
    let det = e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1)) - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
        + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0));
    let one = BigRational::one();
    let (p, q) = (&one - &tr, det);
    // (λ − 1)(λ² + pλ + q) = λ³ − tr λ² + c₂ λ − det needs q − p = c₂ (1 is an eigenvalue).
    if &q - &p != c2 {
        return None;
    }
    let disc = &p * &p - BigRational::from_integer(4.into()) * &q;
    if disc.is_negative() {
        return None;
    }
    let half = BigRational::new(1.into(), 2.into());
    let (field, plus, minus) = match is_square(&disc) {
        Some(s) => {
            (Field { r: BigRational::zero() }, Q2::rational((-&p + &s) * &half), Q2::rational((-&p - &s) * &half))
        }
        None => (Field { r: disc }, Q2 { a: -&p * &half, b: half.clone() }, Q2 { a: -&p * &half, b: -half.clone() }),
    };
    let mut values = [Q2::rational(one), plus, minus];
    values.sort_by(|x, y| field.cmp(y, x));
    let mut vectors: Vec<[Q2; 3]> = Vec::with_capacity(3);
    for l in &values {
        let row = |i: usize| -> [Q2; 3] {
            std::array::from_fn(|j| {
                let x = Q2::rational(m[i][j].clone());
                if i == j { field.sub(&x, l) } else { x }
            })
        };
        let v = [(0, 1), (0, 2), (1, 2)]
            .into_iter()
            .map(|(i, j)| field.cross(&row(i), &row(j)))
            .find(|v| v.iter().any(|x| !x.is_zero()))?;
        let first = v.iter().find(|x| !x.is_zero())?;
        let v = if field.sign(first) == Ordering::Less { v.map(|x| Q2 { a: -x.a, b: -x.b }) } else { v };
        vectors.push(v);
    }
    Some(Eigen { field, values, vectors: [vectors[0].clone(), vectors[1].clone(), vectors[2].clone()] })
}

impl Eigen {
    /// The fixed point, summing to 1 (rational: the eigenvector of 1).
    fn fixed_point(&self) -> Option<[BigRational; 3]> {
        let k = self.values.iter().position(|l| l.b.is_zero() && l.a.is_one())?;
        let v = &self.vectors[k];
        let sum = v.iter().fold(BigRational::zero(), |acc, x| acc + &x.a);
        (!sum.is_zero()).then(|| std::array::from_fn(|i| &v[i].a / &sum))
    }

    /// The component of `d` on the eigenvector of largest `|λ| < 1` that it
    /// has a component on: `(cᵢ vᵢ, λᵢ, cᵢ)`; `None` on a tie in modulus.
    fn leading(&self, d: &[BigRational; 3]) -> Option<([Q2; 3], Q2, Q2)> {
        let f = &self.field;
        let d: [Q2; 3] = std::array::from_fn(|i| Q2::rational(d[i].clone()));
        let v = &self.vectors;
        let det = f.dot(&v[0], &f.cross(&v[1], &v[2]));
        let inv = f.inv(&det)?;
        // Cramer: cᵢ = det(V with column i replaced by d) / det V.
        let coefficient = |i: usize| {
            let mut cols = v.clone();
            cols[i] = d.clone();
            f.mul(&f.dot(&cols[0], &f.cross(&cols[1], &cols[2])), &inv)
        };
        let mut best: Option<usize> = None;
        let mut tie = false;
        for i in 0..3 {
            let l = &self.values[i];
            if l.b.is_zero() && l.a.is_one() || coefficient(i).is_zero() {
                continue;
            }
            match best {
                None => best = Some(i),
                Some(b) => match f.cmp(&f.abs(l), &f.abs(&self.values[b])) {
                    Ordering::Greater => {
                        best = Some(i);
                        tie = false;
                    }
                    Ordering::Equal => tie = true,
                    Ordering::Less => {}
                },
            }
        }
        let i = best.filter(|_| !tie)?;
        let c = coefficient(i);
        Some((v[i].clone().map(|x| f.mul(&x, &c)), self.values[i].clone(), c))
    }

    /// The largest eigenvalue below 1 in modulus.
    fn subdominant(&self) -> Option<&Q2> {
        let f = &self.field;
        self.values.iter().filter(|l| !(l.b.is_zero() && l.a.is_one())).max_by(|x, y| f.cmp(&f.abs(x), &f.abs(y)))
    }
}

/// What [`curve_query_exact`] finds: as [`super::curve::CurveReport`], with
/// exact numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactCurveReport {
    /// The eigenvalues of `T0` and `T1`, decreasing.
    pub eigenvalues: [Vec<Surd>; 2],
    /// The largest eigenvalue below 1 in modulus of each.
    pub subdominant: [Option<Surd>; 2],
    /// Directions in which the curve leaves `F(0)` and arrives at `F(1)`
    /// (`α_L v_L⁰` and `β_R v_R¹`, unnormalised).
    pub half_tangents: Option<[Vec<Surd>; 2]>,
    /// The junction angle in degrees (floating point, from the exact directions).
    pub junction_angle_deg: Option<f64>,
    /// The half-tangents at the junction are collinear (exactly).
    pub c1_necessary: bool,
    /// The region of Sokolov et al. 2010 Fig. 8, decided exactly.
    pub region: Option<&'static str>,
}

/// The point query of [`super::curve::curve_query`] for rational `3 × 3`
/// halves `t0`, `t1` (rows of rationals), exactly; `None` when a matrix is
/// not `3 × 3` column-stochastic with real eigenvalues and an eigenbasis
/// (the floating-point query then answers alone).
///
/// # Example
/// ```
/// use num_rational::BigRational;
/// let q = |n: i64, d: i64| BigRational::new(n.into(), d.into());
/// // Chaikin (a = b = 1/4): eigenvalues (1, 1/2, 1/4), region 1.
/// let t0 = vec![vec![q(3, 4), q(1, 4), q(0, 1)], vec![q(1, 4), q(3, 4), q(3, 4)], vec![q(0, 1), q(0, 1), q(1, 4)]];
/// let t1 = vec![vec![q(1, 4), q(0, 1), q(0, 1)], vec![q(3, 4), q(3, 4), q(1, 4)], vec![q(0, 1), q(1, 4), q(3, 4)]];
/// let r = bcifs::analysis::curve_query_exact(&t0, &t1).unwrap();
/// assert_eq!(r.eigenvalues[0].iter().map(|x| x.to_string()).collect::<Vec<_>>(), ["1", "1/2", "1/4"]);
/// assert_eq!(r.region, Some("1"));
/// ```
pub fn curve_query_exact(t0: &[Vec<BigRational>], t1: &[Vec<BigRational>]) -> Option<ExactCurveReport> {
    let square = |m: &[Vec<BigRational>]| m.len() == 3 && m.iter().all(|r| r.len() == 3);
    if !square(t0) || !square(t1) {
        return None;
    }
    let (e0, e1) = (eigen(t0)?, eigen(t1)?);
    let surds = |e: &Eigen| e.values.iter().map(|x| e.field.surd(x)).collect::<Vec<_>>();
    let mut report = ExactCurveReport {
        eigenvalues: [surds(&e0), surds(&e1)],
        subdominant: [e0.subdominant().map(|x| e0.field.surd(x)), e1.subdominant().map(|x| e1.field.surd(x))],
        half_tangents: None,
        junction_angle_deg: None,
        c1_necessary: false,
        region: None,
    };
    let degenerate = e0.values.iter().chain(&e1.values).any(Q2::is_zero);
    let (Some(f0), Some(f1)) = (e0.fixed_point(), e1.fixed_point()) else { return Some(report) };
    let d: [BigRational; 3] = std::array::from_fn(|i| &f1[i] - &f0[i]);
    // A tie in modulus leaves no single direction: no half-tangent, no region.
    let (Some((start, lambda_l, alpha)), Some((end_back, lambda_r, _))) = (e0.leading(&d), e1.leading(&d)) else {
        return Some(report);
    };
    if degenerate {
        report.region = Some("degenerate");
    }
    let (g0, g1) = (&e0.field, &e1.field);
    let as_surds = |f: &Field, v: &[Q2; 3]| v.iter().map(|x| f.surd(x)).collect::<Vec<_>>();
    let (start_s, end_s) = (as_surds(g0, &start), as_surds(g1, &end_back));
    // d_in = T0 (β_R v_R¹) and d_out = T1 (α_L v_L⁰): rational matrices times surd vectors.
    let apply = |m: &[Vec<BigRational>], v: &[Surd]| -> Vec<Surd> {
        (0..3).map(|i| (0..3).fold(Surd::zero(), |acc, j| acc.add(&v[j].scale(&m[i][j])))).collect()
    };
    let (d_in, d_out) = (apply(t0, &end_s), apply(t1, &start_s));
    let cross_zero =
        [(1, 2), (2, 0), (0, 1)].iter().all(|&(i, j)| d_in[i].mul(&d_out[j]).sub(&d_in[j].mul(&d_out[i])).is_zero());
    let dot = (0..3).fold(Surd::zero(), |acc, i| acc.add(&d_in[i].mul(&d_out[i])));
    if g0.sign(&lambda_l) == Ordering::Greater && g1.sign(&lambda_r) == Ordering::Greater {
        let f = |v: &[Surd]| v.iter().map(Surd::to_f64).collect::<Vec<f64>>();
        let (a, b) = (f(&d_in), f(&d_out));
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cos = a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() / (norm(&a) * norm(&b));
        if cos.is_finite() {
            report.junction_angle_deg = Some(if cross_zero {
                if dot.is_negative() { 180.0 } else { 0.0 }
            } else {
                cos.clamp(-1.0, 1.0).acos().to_degrees()
            });
            report.c1_necessary = cross_zero;
        }
        report.half_tangents = Some([start_s, end_s]);
    }
    if degenerate {
        return Some(report);
    }
    let inner = |v: &[Q2; 3]| v.iter().any(Q2::is_zero);
    let smallest =
        e0.values.iter().filter(|l| !(l.b.is_zero() && l.a.is_one())).min_by(|x, y| g0.cmp(&g0.abs(x), &g0.abs(y)));
    report.region = Some(super::curve::region(
        [inner(&start), inner(&end_back)],
        report.c1_necessary && report.junction_angle_deg.is_some_and(|a| a < 90.0),
        g0.sign(&alpha) == Ordering::Less,
        smallest.is_some_and(|s| g0.sign(s) == Ordering::Less),
    ));
    Some(report)
}
