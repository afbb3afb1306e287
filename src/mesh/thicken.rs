//! Laces thickened into shells (issue 45, item 3): a surface with holes
//! written as a closed solid of a given thickness, for printing.

use rustc_hash::FxHashMap;

use crate::geometry::{Quad, Shape, Sink, area_normals};

/// Why a surface does not thicken into a shell.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ThickenError {
    /// Not a positive finite number.
    #[error("a thickness of {}: give a positive number (modelling units)", shown(*.0))]
    Thickness(f64),
    /// Nothing to thicken.
    #[error("only surfaces thicken into shells: this shape has no face")]
    NoFace,
    /// Walls would cross.
    #[error(
        "a thickness of {} is not smaller than the smallest side of a cell ({side:.3e}): the shell's walls would cross (lower the thickness or the depth)",
        shown(*thickness)
    )]
    TooThick {
        /// The thickness asked for.
        thickness: f64,
        /// The shortest edge of the surface.
        side: f64,
    },
    /// A closed surface (a solid's boundary): thickening it would make a hollow double wall.
    #[error(
        "this surface is closed (a solid's boundary, or a surface without border): a thickness makes a lace (a surface with a border and holes) into a shell, and would make this a hollow double wall; write the solid as it is"
    )]
    Closed,
    /// Cells touching at a point or along an edge only.
    #[error(
        "the surface's cells touch at single points or along edges only ({0} place(s), pinches): a shell around them is not a manifold there; thicken a lace without pinches (the carpet), or write the surface itself"
    )]
    Pinched(usize),
}

/// A number as written, in exponent form when very large or small.
fn shown(x: f64) -> String {
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) { x.to_string() } else { format!("{x:e}") }
}

/// `surface` (its quads and triangles, 3D) thickened into a closed shell of
/// thickness `thickness`: every vertex moved half of it each way along its
/// area-weighted normal, the faces twice (the lower copy turned over), and a
/// wall along every border edge (the outline and every hole's), all turned
/// outward. The shell is watertight and consistently oriented; its walls do
/// not cross when the thickness is below the smallest cell's side and the
/// surface bends less than that (checked: the side; refused: pinches, which
/// no shell of a lace's own faces can hold as a manifold).
///
/// # Errors
/// [`ThickenError`], before anything is made.
///
/// ```
/// use bcifs::{geometry::Shape, mesh::thicken};
/// // A unit square (one quad) 0.1 thick: a box of volume 0.1 with 6 faces.
/// let square = Shape { dim: 3, positions: vec![0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.], quads: vec![[0, 1, 2, 3]], ..Default::default() };
/// let shell = thicken(&square, 0.1)?;
/// assert_eq!((shell.vertex_count(), shell.quads.len()), (8, 6));
/// let r = bcifs::report::print_report_of(&shell);
/// assert!((r.volume - 0.1).abs() < 1e-15 && r.closed && r.oriented);
/// # Ok::<(), bcifs::mesh::ThickenError>(())
/// ```
pub fn thicken(surface: &Shape, thickness: f64) -> Result<Shape, ThickenError> {
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(ThickenError::Thickness(thickness));
    }
    let faces: Vec<Vec<usize>> = surface
        .quads
        .iter()
        .map(|q| q.iter().map(|&v| v as usize).collect())
        .chain(surface.triangles.iter().map(|t| t.to_vec()))
        .collect();
    if faces.is_empty() {
        return Err(ThickenError::NoFace);
    }
    let n = surface.vertex_count();
    let points: Vec<[f64; 3]> = (0..n).map(|v| surface.point(v)).collect();
    // Directed edges: the faces that run each; the border is run one way only.
    let mut directed: FxHashMap<(usize, usize), u32> = FxHashMap::default();
    let mut side = f64::INFINITY;
    for f in &faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *directed.entry((a, b)).or_insert(0) += 1;
            side = side.min((0..3).map(|x| (points[a][x] - points[b][x]).powi(2)).sum::<f64>().sqrt());
        }
    }
    let mut border_at = vec![0u32; n];
    let mut pinches = 0;
    let mut border: Vec<(usize, usize)> = Vec::new();
    for (&(a, b), &count) in &directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        if count + back > 2 || count > 1 {
            pinches += 1;
        } else if back == 0 {
            border.push((a, b));
            border_at[a] += 1;
        }
    }
    pinches += border_at.iter().filter(|&&c| c > 1).count();
    if pinches > 0 {
        return Err(ThickenError::Pinched(pinches));
    }
    if border.is_empty() {
        return Err(ThickenError::Closed);
    }
    if thickness >= side {
        return Err(ThickenError::TooThick { thickness, side });
    }
    border.sort_unstable();
    let normals = area_normals(&points, faces.iter().map(Vec::as_slice));
    let mut positions = Vec::with_capacity(6 * n);
    for sign in [0.5, -0.5] {
        for (p, m) in points.iter().zip(&normals) {
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt().max(f64::MIN_POSITIVE);
            positions.extend((0..3).map(|x| p[x] + sign * thickness * m[x] / len));
        }
    }
    let wide = |q: &Quad| q.map(|v| v as usize);
    let mut quads: Vec<[usize; 4]> = surface.quads.iter().map(wide).collect();
    // Turned over from the same corner: a fan splits both copies of a quad along the same diagonal.
    quads.extend(surface.quads.iter().map(|q| [q[0], q[3], q[2], q[1]].map(|v| v as usize + n)));
    quads.extend(border.iter().map(|&(a, b)| [b, a, a + n, b + n]));
    let mut triangles = surface.triangles.clone();
    triangles.extend(surface.triangles.iter().map(|t| [t[0] + n, t[2] + n, t[1] + n]));
    // Made through the sink, so that it replays as one object as the evaluated shapes do.
    let mut shell = Shape::default();
    let made = |s: &mut Shape| -> std::io::Result<()> {
        s.object("shell")?;
        s.vertices(3, &positions, None)?;
        s.faces(&quads, None)?;
        s.triangles(&triangles)
    };
    made(&mut shell).map_err(|_| ThickenError::NoFace)?;
    Ok(shell)
}
