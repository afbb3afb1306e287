//! Contour pieces as IFS (the Bézier-fractal contours paper §4): a line segment as two affine maps in
//! the paper's convention (homogeneous row vectors, `[x' y' 1] = [x y 1] F`).

/// A 3×3 matrix acting on homogeneous row vectors.
pub type RowMap = [[f64; 3]; 3];

fn mul(a: &RowMap, b: &RowMap) -> RowMap {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// The two maps whose attractor is the segment `p0 → p1` (eqs. 12–14):
/// `F1` halves towards the origin, `F2` halves towards `(1, 0)`, conjugated
/// by `D = S_s R_φ T_p0`, which takes the unit segment onto `p0 → p1`. The
/// angle is the segment's direction `φ = atan2(y1 − y0, x1 − x0)`; the
/// paper's `arctan((y1 − y0)/s)` misplaces the segment (`docs/errata.md`).
/// `F1` fixes `p0`, `F2` fixes `p1`, and both send the segment onto its halves.
///
/// ```
/// let [f1, f2] = bcifs::schemes::segment_ifs([0.0, 0.0], [3.0, 4.0]);
/// // [3 4 1] F2 = [3 4 1]: the end point is fixed.
/// let end: Vec<f64> = (0..3).map(|j| 3.0 * f2[0][j] + 4.0 * f2[1][j] + f2[2][j]).collect();
/// assert!((end[0] - 3.0).abs() < 1e-12 && (end[1] - 4.0).abs() < 1e-12);
/// ```
pub fn segment_ifs(p0: [f64; 2], p1: [f64; 2]) -> [RowMap; 2] {
    let (dx, dy) = (p1[0] - p0[0], p1[1] - p0[1]);
    segment_ifs_at(p0, dx.hypot(dy), dy.atan2(dx))
}

/// The maps of a segment from `p0` of length `s` at angle `phi`.
pub(crate) fn segment_ifs_at(p0: [f64; 2], s: f64, phi: f64) -> [RowMap; 2] {
    let (c, si) = (phi.cos(), phi.sin());
    let scale = [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, 1.0]];
    let rotate = [[c, si, 0.0], [-si, c, 0.0], [0.0, 0.0, 1.0]];
    let translate = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [p0[0], p0[1], 1.0]];
    let d = mul(&mul(&scale, &rotate), &translate);
    // D⁻¹ = T⁻¹ R⁻¹ S⁻¹ (s > 0).
    let inverse = mul(
        &mul(
            &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-p0[0], -p0[1], 1.0]],
            &[[c, -si, 0.0], [si, c, 0.0], [0.0, 0.0, 1.0]],
        ),
        &[[1.0 / s, 0.0, 0.0], [0.0, 1.0 / s, 0.0], [0.0, 0.0, 1.0]],
    );
    let f1 = [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]];
    let f2 = [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.5, 0.0, 1.0]];
    [mul(&mul(&inverse, &f1), &d), mul(&mul(&inverse, &f2), &d)]
}

/// The maps eq. 13 prints, with `φ = arctan((y1 − y0)/s)`: kept to show the erratum.
#[doc(hidden)]
pub fn segment_ifs_as_printed(p0: [f64; 2], p1: [f64; 2]) -> [RowMap; 2] {
    let (dx, dy) = (p1[0] - p0[0], p1[1] - p0[1]);
    let s = dx.hypot(dy);
    segment_ifs_at(p0, s, (dy / s).atan())
}
