//! The one check that no file holds a non-finite number.

/// Refuses vertices with a coordinate or normal that is not finite: no file
/// bcifs writes holds NaN or an infinity, which every client refuses or
/// draws wrong (a design's control points so large that its sums overflow
/// `f64`). The atomic writers then leave the target as it was.
pub fn finite_vertices(positions: &[f64], normals: Option<&[f64]>) -> std::io::Result<()> {
    let bad = |xs: &[f64]| xs.iter().any(|x| !x.is_finite());
    if bad(positions) || normals.is_some_and(bad) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "a vertex has a coordinate or normal that is not a finite number (the evaluation overflowed f64: \
             scale the control points or mesh below ±1e150); nothing is written",
        ));
    }
    Ok(())
}
