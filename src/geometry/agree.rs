//! Vertex normals that agree with every face at the vertex: on a rough
//! surface the area-weighted sum of the faces' normals can point against
//! one of them (a client then shades that face from behind).

use nalgebra::Vector3;

type DVec3 = Vector3<f64>;

fn unit(v: DVec3) -> Option<DVec3> {
    let r = 1.0 / v.norm();
    (r.is_finite() && r > 0.0).then(|| v * r)
}

/// The direction `n` with `n·u = n·v = n·w = 1` for unit `u, v, w` (the
/// rows of `M`, `n = M⁻¹ (1, 1, 1)`), or `None` when they are nearly
/// coplanar (`|det M| ≤ 1e-12`). Cofactors over the determinant, in this
/// order of operations.
fn equidistant(u: &DVec3, v: &DVec3, w: &DVec3) -> Option<DVec3> {
    // The columns of M.
    let x = DVec3::new(u.x, v.x, w.x);
    let y = DVec3::new(u.y, v.y, w.y);
    let z = DVec3::new(u.z, v.z, w.z);
    let rows = [y.cross(&z), z.cross(&x), x.cross(&y)];
    let det = x.dot(&rows[0]);
    if det.abs() <= crate::algebra::tolerance::DEGENERATE {
        return None;
    }
    let r = 1.0 / det;
    let [a, b, c] = rows.map(|t| t.x * r + t.y * r + t.z * r);
    Some(DVec3::new(a, b, c))
}

/// The unit normal of a vertex from `sum`, the area vectors of its faces
/// summed (area weighting), and `triangles`, the normals of the triangles
/// at the vertex a client may split its faces into: `sum` itself unless it
/// points against one of them; then the centre of the smallest cap of the
/// sphere holding their unit normals (spanned by one, two or three of
/// them), which agrees with every one whenever any direction does. `+z`
/// when all are degenerate.
///
/// ```
/// use nalgebra::Vector3;
/// // Three faces whose sum leans against the third.
/// let t = [Vector3::new(1.0, 0.0, 0.2), Vector3::new(1.0, 0.1, 0.0), Vector3::new(-0.2, 0.0, 0.05)];
/// let n = bcifs::geometry::agreeing(t.iter().sum(), &t);
/// assert!(t.iter().all(|f| f.dot(&n) > 0.0));
/// ```
pub fn agreeing(sum: DVec3, triangles: &[DVec3]) -> DVec3 {
    let triangles = || triangles.iter().copied();
    // The common case: the sum agrees with every (non-degenerate) triangle.
    if triangles().all(|f| f.dot(&sum) > 0.0 || unit(f).is_none())
        && let Some(n) = unit(sum)
    {
        return n;
    }
    let units: Vec<DVec3> = triangles().filter_map(unit).collect();
    let worst = |n: &DVec3| units.iter().map(|u| u.dot(n)).fold(f64::INFINITY, f64::min);
    let best = |c: Vec<DVec3>| c.into_iter().map(|n| (worst(&n), n)).max_by(|a, b| a.0.total_cmp(&b.0));
    // Caps spanned by one or two normals first: cheap, and enough almost always.
    let mut candidates: Vec<DVec3> = units.clone();
    candidates.extend(unit(sum));
    for (a, u) in units.iter().enumerate() {
        candidates.extend(units[a + 1..].iter().filter_map(|v| unit(u + v)));
    }
    let two = best(candidates);
    if let Some((w, n)) = two
        && w > 0.0
    {
        return n;
    }
    let mut candidates = Vec::new();
    for (a, u) in units.iter().enumerate() {
        for (b, v) in units.iter().enumerate().skip(a + 1) {
            for w in &units[b + 1..] {
                // Equidistant from u, v, w: n·u = n·v = n·w.
                candidates.extend(equidistant(u, v, w).and_then(unit));
            }
        }
    }
    let three = best(candidates);
    match (two, three) {
        (Some(a), Some(b)) => {
            if b.0 > a.0 {
                b.1
            } else {
                a.1
            }
        }
        (Some((_, n)), None) | (None, Some((_, n))) => n,
        (None, None) => DVec3::z(),
    }
}
