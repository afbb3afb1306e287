//! The true measure of a cell: the length, area or volume of the patch its
//! control points make ([`Patch`]), integrated on the patch itself by
//! Gauss–Legendre quadrature — `|S′|` along a curve, `|S_u × S_v|` over a
//! patch, `|det J|` through a volume — not the flat polygon of its corners.
//! Cells that are affine images of one another have constant Jacobians,
//! integrated exactly; the polynomial Jacobian of a trilinear or tricubic
//! volume is integrated exactly as well (enough points for its degree).

use crate::eval::StatePlan;
use crate::space::{CellKind, Patch};

/// Why a cell has no measure bcifs knows.
pub(super) fn no_patch(sp: &StatePlan) -> String {
    format!(
        "state `{}` ({} control points) does not say how its control points make a patch (`patch = \"bezier\"`, \
         \"bspline\" or \"polygon\" on the state), and they are not only its corners: its cells have no length, \
         area or volume to measure",
        sp.name, sp.dim
    )
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on `[0, 1]`.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            // Newton from Tricomi's estimate of the i-th root of P_n on [-1, 1].
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                let p = if n == 0 { 1.0 } else { p1 };
                derivative = n as f64 * (x * p - p0) / (x * x - 1.0);
                let step = p / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * derivative * derivative);
            ((1.0 - x) / 2.0, w / 2.0)
        })
        .collect()
}

/// The binomial coefficient.
fn choose(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

/// `x^e` with `0^0 = 1`.
fn power(x: f64, e: usize) -> f64 {
    x.powi(e as i32)
}

/// The `n` functions of one direction at `t` and their derivatives: the
/// Bernstein polynomials of degree `n − 1`, or the uniform B-spline's over one span.
fn basis(patch: Patch, n: usize, t: f64) -> (Vec<f64>, Vec<f64>) {
    let m = n - 1;
    match patch {
        Patch::BSpline => {
            let b = |d: usize, x: f64| crate::schemes::cardinal_bspline(d, x);
            let values = (0..n).map(|i| b(m, t + (m - i) as f64)).collect();
            let slopes = (0..n)
                .map(|i| if m == 0 { 0.0 } else { b(m - 1, t + (m - i) as f64) - b(m - 1, t + (m - i) as f64 - 1.0) })
                .collect();
            (values, slopes)
        }
        _ => {
            let values = (0..n).map(|i| choose(m, i) * power(t, i) * power(1.0 - t, m - i)).collect();
            let slopes = (0..n)
                .map(|i| {
                    let up = if i > 0 { choose(m - 1, i - 1) * power(t, i - 1) * power(1.0 - t, m - i) } else { 0.0 };
                    let down = if i < m { choose(m - 1, i) * power(t, i) * power(1.0 - t, m - 1 - i) } else { 0.0 };
                    m as f64 * (up - down)
                })
                .collect();
            (values, slopes)
        }
    }
}

/// `Σ_i w_i P_i` over the control points `c` (`d × n`, row-major), as 3D.
fn combine(c: &[f64], d: usize, n: usize, w: &[f64]) -> [f64; 3] {
    let mut p = [0.0; 3];
    for (a, x) in p.iter_mut().enumerate().take(d) {
        *x = (0..n).map(|i| c[a * n + i] * w[i]).sum();
    }
    p
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The side `D` of a grid of `n = D^k` points, if it is one.
fn side(n: usize, k: u32) -> Option<usize> {
    (2..=n).find(|&s| s.pow(k) >= n).filter(|&s| s.pow(k) == n)
}

/// The measure of a cell of `sp` on the control points `c` (`d`
/// coordinates, row-major): its patch's length (edges), area (faces) or
/// volume (volumes).
///
/// # Errors
/// A cell whose control points make no patch bcifs knows (see [`no_patch`]).
pub(super) fn cell_measure(sp: &StatePlan, c: &[f64], d: usize) -> Result<f64, String> {
    let n = sp.dim;
    let corners_only = match sp.kind {
        CellKind::Edge => n == 2,
        CellKind::Face | CellKind::Volume => n == sp.samples.len(),
        _ => false,
    };
    let patch = match sp.patch {
        Some(p) => p,
        None if corners_only => Patch::Polygon,
        None => return Err(no_patch(sp)),
    };
    match (sp.kind, patch) {
        (_, Patch::Polygon) => Ok(polygon(sp, c, d)),
        (CellKind::Edge, p) => {
            let rule = gauss_legendre(16);
            Ok(rule.iter().map(|&(t, w)| w * norm(combine(c, d, n, &basis(p, n, t).1))).sum())
        }
        (CellKind::Face, p) => match side(n, 2) {
            Some(s) => Ok(tensor_area(p, s, c, d)),
            None if p == Patch::Bezier => {
                let s = (1..=n).find(|s| s * (s + 1) / 2 == n).ok_or_else(|| no_patch(sp))?;
                Ok(triangle_area(s, c, d))
            }
            None => Err(no_patch(sp)),
        },
        (CellKind::Volume, p) => match side(n, 3) {
            Some(s) => Ok(tensor_volume(p, s, c, d)),
            // A linear tetrahedron.
            None if n == 4 && p == Patch::Bezier => {
                let at = |i: usize| combine(c, d, n, &(0..4).map(|j| f64::from(u8::from(i == j))).collect::<Vec<_>>());
                let (o, a, b, e) = (at(0), at(1), at(2), at(3));
                let r = |p: [f64; 3]| [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
                let (a, b, e) = (r(a), r(b), r(e));
                let x = cross(a, b);
                Ok((x[0] * e[0] + x[1] * e[1] + x[2] * e[2]).abs() / 6.0)
            }
            None => Err(no_patch(sp)),
        },
        _ => Err(no_patch(sp)),
    }
}

/// The area of a `s × s` tensor patch (index `s·row + col`, rows along v).
fn tensor_area(patch: Patch, s: usize, c: &[f64], d: usize) -> f64 {
    let rule = gauss_legendre(12);
    let mut area = 0.0;
    for &(v, wv) in &rule {
        let (bv, dv) = basis(patch, s, v);
        for &(u, wu) in &rule {
            let (bu, du) = basis(patch, s, u);
            let along_u: Vec<f64> = (0..s * s).map(|i| bv[i / s] * du[i % s]).collect();
            let along_v: Vec<f64> = (0..s * s).map(|i| dv[i / s] * bu[i % s]).collect();
            let (su, sv) = (combine(c, d, s * s, &along_u), combine(c, d, s * s, &along_v));
            area += wu * wv * norm(cross(su, sv));
        }
    }
    area
}

/// The area of a Bézier triangle of `s` points a side (its net row by row
/// from the first side), over the collapsed square `u = x, v = (1 − x) y`.
fn triangle_area(s: usize, c: &[f64], d: usize) -> f64 {
    let net = crate::schemes::triangle_net(s);
    let m = s - 1;
    let rule = gauss_legendre(12);
    let mut area = 0.0;
    for &(x, wx) in &rule {
        for &(y, wy) in &rule {
            let (u, v) = (x, (1.0 - x) * y);
            let l = 1.0 - u - v;
            let (mut du, mut dv) = (Vec::with_capacity(net.len()), Vec::with_capacity(net.len()));
            for &(a, b) in &net {
                let i = m - a - b;
                let coef = (1..=m).product::<usize>() as f64
                    / ((1..=i).product::<usize>() * (1..=a).product::<usize>() * (1..=b).product::<usize>()) as f64;
                let term = |ea: usize, eb: usize, el: usize| power(u, ea) * power(v, eb) * power(l, el);
                let dl = if i > 0 { i as f64 * term(a, b, i - 1) } else { 0.0 };
                du.push(coef * (if a > 0 { a as f64 * term(a - 1, b, i) } else { 0.0 } - dl));
                dv.push(coef * (if b > 0 { b as f64 * term(a, b - 1, i) } else { 0.0 } - dl));
            }
            let (su, sv) = (combine(c, d, net.len(), &du), combine(c, d, net.len(), &dv));
            area += wx * wy * (1.0 - x) * norm(cross(su, sv));
        }
    }
    area
}

/// The volume of a `s × s × s` tensor volume (index `s²·w + s·v + u`): its
/// Jacobian is a polynomial of degree `3(s − 1) − 1` along each direction,
/// integrated exactly by `⌈3(s − 1)/2⌉` points.
fn tensor_volume(patch: Patch, s: usize, c: &[f64], d: usize) -> f64 {
    let rule = gauss_legendre((3 * (s - 1)).div_ceil(2).max(1) + 1);
    let n = s * s * s;
    let mut volume = 0.0;
    for &(w, ww) in &rule {
        let (bw, dw) = basis(patch, s, w);
        for &(v, wv) in &rule {
            let (bv, dv) = basis(patch, s, v);
            for &(u, wu) in &rule {
                let (bu, du) = basis(patch, s, u);
                let weights = |f: &dyn Fn(usize, usize, usize) -> f64| -> Vec<f64> {
                    (0..n).map(|i| f(i % s, i / s % s, i / (s * s))).collect()
                };
                let ju = combine(c, d, n, &weights(&|i, j, k| du[i] * bv[j] * bw[k]));
                let jv = combine(c, d, n, &weights(&|i, j, k| bu[i] * dv[j] * bw[k]));
                let jw = combine(c, d, n, &weights(&|i, j, k| bu[i] * bv[j] * dw[k]));
                let x = cross(ju, jv);
                volume += wu * wv * ww * (x[0] * jw[0] + x[1] * jw[1] + x[2] * jw[2]).abs();
            }
        }
    }
    volume
}

/// The flat measure of a cell's corners: a segment's length, a polygon's
/// (Newell) area, a polyhedron's volume through its faces.
fn polygon(sp: &StatePlan, c: &[f64], d: usize) -> f64 {
    let n = sp.dim;
    let at = |b: &[f64]| combine(c, d, n, b);
    match sp.kind {
        CellKind::Edge => {
            let a = at(&sp.samples[0]);
            let b = sp.end.as_deref().or(sp.samples.get(1).map(Vec::as_slice)).map_or(a, at);
            norm([b[0] - a[0], b[1] - a[1], b[2] - a[2]])
        }
        CellKind::Face => {
            let corners: Vec<[f64; 3]> = sp.samples.iter().map(|s| at(s)).collect();
            norm(crate::geometry::area_vector(corners.len(), |k| corners[k]))
        }
        _ => {
            let corners: Vec<[f64; 3]> = sp.samples.iter().map(|s| at(s)).collect();
            let o = corners[0];
            let r = |p: [f64; 3]| [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
            let mut volume = 0.0;
            for face in &sp.faces {
                for t in crate::geometry::fan(face, 0) {
                    let [a, b, e] = t.map(|i| r(corners[i]));
                    let x = cross(b, e);
                    volume += (a[0] * x[0] + a[1] * x[1] + a[2] * x[2]) / 6.0;
                }
            }
            volume.abs()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for n in [2usize, 5, 12, 16] {
            let rule = gauss_legendre(n);
            assert!((rule.iter().map(|r| r.1).sum::<f64>() - 1.0).abs() < 1e-14);
            let degree = 2 * n - 1;
            let integral: f64 = rule.iter().map(|&(x, w)| w * x.powi(degree as i32)).sum();
            assert!((integral - 1.0 / (degree + 1) as f64).abs() < 1e-14, "n = {n}: {integral}");
        }
    }

    #[test]
    fn bases_are_partitions_of_unity_with_derivatives_summing_to_zero() {
        for patch in [Patch::Bezier, Patch::BSpline] {
            for n in 2..=4 {
                let (v, s) = basis(patch, n, 0.37);
                assert!((v.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{patch:?} {n}");
                assert!(s.iter().sum::<f64>().abs() < 1e-13, "{patch:?} {n}");
                // The derivative against a difference.
                let (a, b) = (basis(patch, n, 0.37 + 1e-6).0, basis(patch, n, 0.37 - 1e-6).0);
                for i in 0..n {
                    assert!(((a[i] - b[i]) / 2e-6 - s[i]).abs() < 1e-6, "{patch:?} {n} {i}");
                }
            }
        }
    }
}
