//! The colours of parameter maps, the one palette every front end draws
//! with (`analyze map`, the explorer's maps, the Blender add-on's through
//! the Python module): verdicts, the regions of Sokolov et al. 2010 Fig. 8,
//! junction angles (Fig. 11) and dimensions, as sRGB bytes.

use super::sweep::{REGIONS, SweepKind, SweepValues};

/// The colour of a verdict code.
pub fn verdict_colour(code: i8) -> [u8; 3] {
    match code {
        1 => [150, 205, 150],
        -1 => [215, 60, 60],
        -2 => [228, 228, 228],
        _ => [240, 200, 80],
    }
}

/// A dimension's colour: 1 dark blue to 2 yellow (viridis-like), NaN grey.
pub fn dimension_colour(d: f64) -> [u8; 3] {
    if d.is_nan() {
        return [228, 228, 228];
    }
    let stops =
        [[68.0, 1.0, 84.0], [59.0, 82.0, 139.0], [33.0, 145.0, 140.0], [94.0, 201.0, 98.0], [253.0, 231.0, 37.0]];
    let t = (d - 1.0).clamp(0.0, 1.0) * 4.0;
    let (k, f) = ((t.floor() as usize).min(3), t - t.floor().min(3.0));
    [0, 1, 2].map(|c| (stops[k][c] + (stops[k + 1][c] - stops[k][c]) * f).round() as u8)
}

/// A junction angle's colour: 0° red to 180° violet through the hues, as Fig. 11.
pub fn angle_colour(degrees: f64) -> [u8; 3] {
    let h = (degrees / 180.0).clamp(0.0, 1.0) * 0.8;
    let f = |n: f64| {
        let k = (n + h * 6.0) % 6.0;
        (255.0 * (1.0 - k.min(4.0 - k).clamp(0.0, 1.0))) as u8
    };
    [f(5.0), f(3.0), f(1.0)]
}

/// The colour of a region of Sokolov et al. 2010 Fig. 8 (and of the verdicts around them).
pub fn region_colour(region: Option<&str>) -> [u8; 3] {
    match region {
        Some("1") => [40, 150, 70],
        Some("2") => [150, 60, 200],
        Some("2'") => [200, 110, 230],
        Some("3") => [40, 110, 200],
        Some("3'") => [110, 170, 235],
        Some("4") => [240, 170, 40],
        Some("5") => [230, 90, 40],
        Some("divergent") => [200, 30, 30],
        Some("degenerate") => [20, 20, 20],
        Some(_) => [255, 0, 255],
        None => [245, 230, 120],
    }
}

/// The colour of a sweep's pixel value; a value that is none of the kind's
/// (NaN, a code out of range) takes the grey of "nothing here".
pub fn sweep_colour(kind: SweepKind, v: f64) -> [u8; 3] {
    const NOTHING: [u8; 3] = [228, 228, 228];
    let code = (v.is_finite() && v.fract() == 0.0).then_some(v);
    match kind {
        SweepKind::Verdict => code.filter(|c| (-2.0..=1.0).contains(c)).map_or(NOTHING, |c| verdict_colour(c as i8)),
        SweepKind::Region => match code.and_then(|c| REGIONS.get(usize::try_from(c as i64).ok()?)) {
            Some(&"undecided") => region_colour(None),
            Some(r) => region_colour(Some(r)),
            None => NOTHING,
        },
        SweepKind::Angle if v.is_nan() => NOTHING,
        SweepKind::Angle => angle_colour(v),
        SweepKind::Dimension => dimension_colour(v),
        // The dimension's palette over [0, 1]: porosity as is, lacunarity as 1 − 1/Λ.
        SweepKind::Porosity => dimension_colour(1.0 + v),
        SweepKind::Lacunarity => dimension_colour(2.0 - 1.0 / v),
    }
}

/// A square sweep of `size` pixels a side as a picture (row 0 at the top), unframed.
pub fn sweep_image(kind: SweepKind, values: &SweepValues, size: usize) -> image::RgbImage {
    let numbers = values.to_f64();
    image::RgbImage::from_fn(size as u32, size as u32, |i, j| {
        image::Rgb(sweep_colour(kind, numbers[j as usize * size + i as usize]))
    })
}
