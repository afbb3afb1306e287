//! Differential behaviour of a BC-IFS curve at a parameter point (Sokolov et al. 2010
//! §4): eigenvalues, half-tangents, the junction angle, and the region of
//! the cartography (Fig. 8).
//!
//! The curve is `C(t) = P F(t)` with `F([0, 1/2]) = T0 F([0, 1])` and
//! `F([1/2, 1]) = T1 F([0, 1])`; `F(0)` and `F(1)` are the fixed points of
//! `T0` and `T1`. Near `t = 0`, `F(2⁻ᵏ t) − F(0) = T0ᵏ (F(t) − F(0))`, so the
//! direction of `F(t) − F(0)` is that of the component of `F(1) − F(0)` on
//! the eigenvector of `T0` with the largest eigenvalue below 1 in modulus
//! among those it has a component on (`α_L v_L⁰`, Property 1), provided that
//! eigenvalue is positive (negative: the direction alternates, no
//! half-tangent). Likewise `F(t) − F(1)` goes along `−β_R v_R¹` from the
//! decomposition `F(1) − F(0) = Σ βᵢ vᵢ¹` in `T1`'s eigenbasis. The paper
//! names these `t₋ = α_L v_L⁰` and `t₊ = β_R v_R¹` but calls them the
//! half-tangents at `F(1)` and `F(0)`: it is the other way round (see
//! `docs/errata.md`).
//!
//! At the junction `t = 1/2`, the left piece `T0 F` arrives along
//! `d_in = T0 (β_R v_R¹)` (the image of the direction in which `F` arrives at
//! `F(1)`) and the right piece `T1 F` leaves along `d_out = T1 (α_L v_L⁰)`;
//! the junction angle is the angle between them in barycentric coordinates
//! (0: a tangent, π: a cusp), as Sokolov et al. 2010 §6 measures roughness.
//!
//! Regions (§4.3, for three-point curves, the rule stated generally): a
//! half-tangent is *inner* when its eigenvector has a zero coordinate (it
//! depends on two control points only: `1 − a − b` sub-dominant for the
//! corner cutting). Both inner: region `1` when `d_in` and `d_out` point the
//! same way, else a cusp, `2` when `α_L < 0` and `2'` when `β_R < 0`. One
//! inner: `3` (at `F(0)`), `3'` (at `F(1)`). None: `4`, or `5` when the
//! smallest eigenvalue of `T0` in modulus (`1 − a − b`) is negative. An eigenvalue 0
//! besides the fixed point is `degenerate` (the corner cutting at `a = 0`,
//! `b = 0`, `a + b = 1`: piecewise linear). All of it is computed in
//! floating point from the instantiated matrices (ties within `1e-12`);
//! [`super::exact::curve_query_exact`] decides the same in exact arithmetic
//! for rational three-point curves, and `bcifs analyze curve` uses it there.

use nalgebra::{DMatrix, DVector};

/// Two eigenvalues closer than this are taken as equal, and a value this small as zero.
const TIE: f64 = 1e-12;

/// What the floating-point eigen-decomposition resolves: an eigenvalue
/// within this of 1 is the eigenvalue 1 of a column-stochastic matrix, an
/// imaginary part below it (relative) is rounding, a cosine within it of ±1
/// is parallel.
const ACCURACY: f64 = 1e-9;

/// What [`curve_query`] finds.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveReport {
    /// Real eigenvalues of `T0` and `T1`, decreasing (`None` when complex).
    pub eigenvalues: [Option<Vec<f64>>; 2],
    /// The largest eigenvalue below 1 in modulus of `T0` and `T1`.
    pub subdominant: [Option<f64>; 2],
    /// Directions (barycentric) in which the curve leaves `F(0)` and arrives at `F(1)`.
    pub half_tangents: Option<[Vec<f64>; 2]>,
    /// The junction angle in degrees.
    pub junction_angle_deg: Option<f64>,
    /// Half-tangents collinear at the junction (§4.2's necessary condition for C1).
    pub c1_necessary: bool,
    /// The region of Sokolov et al. 2010 Fig. 8 (before the convergence verdict is taken into account).
    pub region: Option<&'static str>,
}

/// Real eigen-decomposition `(λ, V)` of a matrix, or `None` when an
/// eigenvalue is complex or the eigenvectors are not a basis.
fn eigen(m: &DMatrix<f64>) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let n = m.nrows();
    let values = crate::algebra::eigenvalues(m)?;
    if values.iter().any(|z| z.im.abs() > ACCURACY * (1.0 + z.re.abs())) {
        return None;
    }
    let mut lambdas: Vec<f64> = values.iter().map(|z| z.re).collect();
    lambdas.sort_by(|a, b| b.partial_cmp(a).unwrap_or(std::cmp::Ordering::Equal));
    let mut vectors = DMatrix::zeros(n, n);
    for (k, &l) in lambdas.iter().enumerate() {
        let shifted = m - DMatrix::identity(n, n) * l;
        let mut v = null_vector(&shifted)?;
        // Sign: the first coordinate that is not 0 is positive (the paper's (1, −1, 0), (0, 1, −1)).
        if v.iter().find(|x| x.abs() > TIE).is_some_and(|x| *x < 0.0) {
            v = -v;
        }
        vectors.set_column(k, &v);
    }
    vectors.clone().try_inverse()?;
    Some((lambdas, vectors))
}

/// A unit vector of the null space of a singular matrix. For 3 × 3 of rank
/// 2 (the three-point curves of a map, pixel after pixel) the largest cross
/// product of two rows, which is orthogonal to every row; otherwise the
/// right singular vector of the smallest singular value.
fn null_vector(a: &DMatrix<f64>) -> Option<DVector<f64>> {
    if a.shape() == (3, 3) {
        let r = |i: usize| nalgebra::Vector3::new(a[(i, 0)], a[(i, 1)], a[(i, 2)]);
        let best = [(0, 1), (0, 2), (1, 2)]
            .map(|(i, j)| r(i).cross(&r(j)))
            .into_iter()
            .max_by(|x, y| x.norm().total_cmp(&y.norm()))?;
        // Rank 2 for sure when the cross product is far from rounding.
        if best.norm() > 1e-6 * a.norm_squared().max(1e-300) {
            let v = best.normalize();
            return Some(DVector::from_column_slice(v.as_slice()));
        }
    }
    let svd = crate::algebra::svd(a, true)?;
    let vt = svd.v_t?;
    let (i, _) = svd.singular_values.iter().enumerate().min_by(|x, y| x.1.total_cmp(y.1))?;
    Some(vt.row(i).transpose())
}

/// The fixed point (barycentric, summing to 1) of a column-stochastic matrix.
fn fixed_point(lambdas: &[f64], vectors: &DMatrix<f64>) -> Option<DVector<f64>> {
    let k = lambdas.iter().position(|l| (l - 1.0).abs() < ACCURACY)?;
    let v = vectors.column(k).into_owned();
    let s = v.sum();
    (s.abs() > TIE).then(|| v / s)
}

/// The direction of `d` along the eigenvector of largest modulus below 1
/// on which it has a component: `(coefficient · eigenvector, eigenvalue, coefficient)`.
fn leading_component(lambdas: &[f64], vectors: &DMatrix<f64>, d: &DVector<f64>) -> Option<(DVector<f64>, f64, f64)> {
    let coefficients = vectors.clone().try_inverse()? * d;
    let scale = d.norm().max(1e-300);
    let mut best: Option<usize> = None;
    for (i, l) in lambdas.iter().enumerate() {
        if (l - 1.0).abs() < ACCURACY || coefficients[i].abs() * vectors.column(i).norm() < ACCURACY * scale {
            continue;
        }
        match best {
            Some(b) if lambdas[b].abs() >= l.abs() - TIE => {
                if (lambdas[b].abs() - l.abs()).abs() < TIE {
                    return None; // two of the same modulus: no single direction
                }
            }
            _ => best = Some(i),
        }
    }
    let i = best?;
    Some((vectors.column(i) * coefficients[i], lambdas[i], coefficients[i]))
}

/// The differential behaviour of the curve whose halves are `t0` and `t1`
/// (square, column-stochastic).
pub fn curve_query(t0: &DMatrix<f64>, t1: &DMatrix<f64>) -> CurveReport {
    let (e0, e1) = (eigen(t0), eigen(t1));
    let subdominant = |e: &Option<(Vec<f64>, DMatrix<f64>)>| {
        e.as_ref().and_then(|(l, _)| {
            l.iter().copied().filter(|x| (x - 1.0).abs() > ACCURACY).max_by(|a, b| a.abs().total_cmp(&b.abs()))
        })
    };
    let mut report = CurveReport {
        eigenvalues: [e0.as_ref().map(|e| e.0.clone()), e1.as_ref().map(|e| e.0.clone())],
        subdominant: [subdominant(&e0), subdominant(&e1)],
        half_tangents: None,
        junction_angle_deg: None,
        c1_necessary: false,
        region: None,
    };
    let (Some((l0, v0)), Some((l1, v1))) = (e0, e1) else { return report };
    let degenerate = l0.iter().chain(&l1).any(|l| l.abs() < TIE);
    let (Some(f0), Some(f1)) = (fixed_point(&l0, &v0), fixed_point(&l1, &v1)) else { return report };
    let d = &f1 - &f0;
    let (Some((start, lambda_l, alpha)), Some((end_back, lambda_r, _))) =
        (leading_component(&l0, &v0, &d), leading_component(&l1, &v1, &d))
    else {
        return report;
    };
    if degenerate {
        report.region = Some("degenerate");
    }
    // Half-tangents exist when the leading eigenvalues are positive.
    if lambda_l > 0.0 && lambda_r > 0.0 {
        // F leaves F(0) along α_L v_L⁰ and arrives at F(1) along β_R v_R¹ (F(t) − F(1) ~ −β_R v_R¹).
        report.half_tangents = Some([start.iter().copied().collect(), end_back.iter().copied().collect()]);
        let d_in = t0 * &end_back;
        let d_out = t1 * &start;
        let cos = d_in.dot(&d_out) / (d_in.norm() * d_out.norm());
        if cos.is_finite() {
            report.junction_angle_deg = Some(cos.clamp(-1.0, 1.0).acos().to_degrees());
            report.c1_necessary = 1.0 - cos.abs() < ACCURACY;
        }
    }
    if degenerate || t0.nrows() != 3 {
        return report;
    }
    let inner = |v: &DVector<f64>| v.iter().any(|x| x.abs() < TIE * v.norm());
    // The sign of the smallest eigenvalue in modulus (1 − a − b for the corner cutting).
    let smallest = l0.iter().filter(|x| (*x - 1.0).abs() > ACCURACY).min_by(|a, b| a.abs().total_cmp(&b.abs()));
    report.region = Some(region(
        [inner(&start), inner(&end_back)],
        report.c1_necessary && report.junction_angle_deg.is_some_and(|a| a < 90.0),
        alpha < 0.0,
        smallest.is_some_and(|s| *s < 0.0),
    ));
    report
}

/// The region of §4.3 (see the module docs): `inner` says which half-tangents
/// depend on two control points only (at `F(0)`, at `F(1)`); `tangent`: the
/// junction is a tangent (collinear half-tangents, angle below 90°);
/// `alpha_negative`: `α_L < 0`; `smallest_negative`: the smallest eigenvalue
/// of `T0` in modulus is negative.
pub(crate) fn region(inner: [bool; 2], tangent: bool, alpha_negative: bool, smallest_negative: bool) -> &'static str {
    match inner {
        [true, true] if tangent => "1",
        [true, true] if alpha_negative => "2",
        [true, true] => "2'",
        [true, false] => "3",
        [false, true] => "3'",
        [false, false] if smallest_negative => "5",
        [false, false] => "4",
    }
}

/// The blending functions of a curve (Sokolov et al. 2010 §5, Fig. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct Blending {
    /// The natural parameters `t = j / 2^depth`, `0..=1`.
    pub t: Vec<f64>,
    /// `F(t)`: the barycentric coordinates of the curve point, one vector per `t`.
    pub f: Vec<Vec<f64>>,
    /// The parameters `tᵢ = i/(n − 1)` given to the control points.
    pub knots: Vec<f64>,
    /// The non-singular parameterization `u(t) = Σ tᵢ Fᵢ(t)`: the parameter
    /// values subdivided by the same matrices as the control points (Fig. 10).
    pub u: Vec<f64>,
}

/// The blending functions of the curve whose halves are `t0`, `t1` at the
/// dyadic parameters of `depth` (at most 20), and the non-singular
/// parameterization; `None` when a matrix has no fixed point.
pub fn blending(t0: &DMatrix<f64>, t1: &DMatrix<f64>, depth: usize) -> Option<Blending> {
    let (l0, v0) = eigen(t0)?;
    let (l1, v1) = eigen(t1)?;
    let (start, end) = (fixed_point(&l0, &v0)?, fixed_point(&l1, &v1)?);
    let n = t0.nrows();
    let depth = depth.min(20);
    // F(j / 2^k) = T_w F(0) for the word w of j: the leaves of the subdivision tree in order.
    let mut cells = vec![DMatrix::<f64>::identity(n, n)];
    for _ in 0..depth {
        cells = cells.iter().flat_map(|m| [m * t0, m * t1]).collect();
    }
    let mut f: Vec<Vec<f64>> = cells.iter().map(|m| (m * &start).iter().copied().collect()).collect();
    f.push(end.iter().copied().collect());
    let steps = f.len() - 1;
    let t = (0..=steps).map(|j| j as f64 / steps as f64).collect();
    let knots: Vec<f64> = (0..n).map(|i| i as f64 / (n.max(2) - 1) as f64).collect();
    let u = f.iter().map(|x| x.iter().zip(&knots).map(|(a, b)| a * b).sum()).collect();
    Some(Blending { t, f, knots, u })
}
