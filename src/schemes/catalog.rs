//! The papers' subdivision schemes as ready-made automata with natural
//! control points: the curves and fractals of Schaefer et al. 2005 (B-splines, Bézier
//! curves and their union, the four-point scheme, Koch and Sierpinski with
//! control points, the bicubic patch) and the ternary 5-point curves and
//! surfaces of Siddiqi et al. 2014.

use super::stationary::{
    BSpline, ExactMatrix, ModelSpec, Rules, ifs_design, koch_blocks, sierpinski_blocks, tensor_design,
};
use super::ternary::ternary_five_point;
use crate::algebra::Surd;
use crate::design::{Design, Layout, Model};

/// Why a preset cannot be generated.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CatalogError {
    /// No such preset.
    #[error("no scheme named `{name}`{}; schemes: {}", .suggestion.as_ref().map(|s| format!(" (did you mean `{s}`?)")).unwrap_or_default(), IFS_NAMES.join(", "))]
    Unknown {
        /// The name asked for.
        name: String,
        /// The closest name.
        suggestion: Option<String>,
    },
    /// Control points that do not fit the scheme.
    #[error("{0}")]
    Points(String),
}

/// The names of the presets.
pub const IFS_NAMES: [&str; 18] = [
    "bspline",
    "bspline-end",
    "bezier",
    "bezier-union",
    "four-point",
    "koch-control",
    "sierpinski-control",
    "bicubic",
    "box-spline",
    "box-spline-gasket",
    "box-spline-quad",
    "sqrt3-patch",
    "ternary5",
    "ternary5-closed",
    "ternary5-surface",
    "ternary5-torus",
    "tricubic",
    "tricubic-sponge",
];

/// Default tension of the ternary presets: in the positive fractal range.
pub const DEFAULT_OMEGA: (i64, i64) = (3, 50);

fn pts(v: &[[f64; 2]]) -> Vec<Vec<f64>> {
    v.iter().map(|p| p.to_vec()).collect()
}

fn spec(points: Vec<Vec<f64>>, layout: Layout, grid: Option<(usize, usize)>, comment: &str) -> ModelSpec {
    let mut model = Model::new("e", points).with_layout(layout);
    model.grid = grid;
    ModelSpec { model, comment: comment.into() }
}

fn grid_points(rows: usize, cols: usize, height: impl Fn(f64, f64) -> f64) -> Vec<Vec<f64>> {
    (0..rows * cols)
        .map(|k| {
            let (r, c) = ((k / cols) as f64, (k % cols) as f64);
            vec![c, r, (height(c, r) * 1e6).round() / 1e6]
        })
        .collect()
}

fn torus_points(rows: usize, cols: usize) -> Vec<Vec<f64>> {
    (0..rows * cols)
        .map(|k| {
            let (u, v) = (
                std::f64::consts::TAU * (k % cols) as f64 / cols as f64,
                std::f64::consts::TAU * (k / cols) as f64 / rows as f64,
            );
            let r = 3.0 + 1.2 * v.cos();
            [r * u.cos(), r * u.sin(), 1.2 * v.sin()].iter().map(|x| (x * 1e6).round() / 1e6).collect()
        })
        .collect()
}

/// The preset called `name` as a design, with the given control points (or
/// the natural ones) and, for the ternary presets, tension `omega` (default
/// 3/50). Its description says what it is and where the seed shows it;
/// [`crate::write_design`] prints it as a commented automaton file.
///
/// # Errors
/// An unknown name (with the closest one), or control points that do not fit.
pub fn ifs_preset(name: &str, points: Option<Vec<Vec<f64>>>, omega: Option<&Surd>) -> Result<Design, CatalogError> {
    let request = Request { name, points };
    match name {
        "ternary5" | "ternary5-closed" | "ternary5-surface" | "ternary5-torus" => {
            let omega = omega.cloned().unwrap_or_else(|| Surd::frac(DEFAULT_OMEGA.0, DEFAULT_OMEGA.1));
            ternary_preset(&request, &omega)
        }
        _ => seed1_preset(&request),
    }
}

/// A ternary 5-point curve preset (`ternary5`, `ternary5-closed`) whose
/// tension ω is the free parameter `parameter` (default 3/50): every entry
/// of eq. (1) is affine in ω, so one design holds the whole family, and
/// `solve`, `analyze map` and `explore` walk it like any other. (The
/// surfaces' blocks are tensor products, quadratic in ω: a known matrix
/// holds affine entries only, so they are refused with that reason.)
///
/// # Errors
/// A preset without a tension, a surface, a parameter name that is not a
/// name, or control points that do not fit.
///
/// # Example
/// ```
/// let family = bcifs::schemes::ternary_family("ternary5", None, "w").unwrap();
/// assert_eq!(family.declared(), ["w"]);
/// let at = |w: f64| bcifs::instantiate(&family, &[("w".into(), w)]).unwrap();
/// let fixed = bcifs::schemes::ifs_preset("ternary5", None, Some(&bcifs::algebra::Surd::frac(1, 20))).unwrap();
/// let fixed = bcifs::instantiate(&fixed, &[]).unwrap();
/// for ((_, a), (_, b)) in at(0.05).automaton.arrows().zip(fixed.automaton.arrows()) {
///     assert!((&a.matrix - &b.matrix).amax() < 1e-15);
/// }
/// ```
pub fn ternary_family(name: &str, points: Option<Vec<Vec<f64>>>, parameter: &str) -> Result<Design, CatalogError> {
    if !name.starts_with("ternary5") {
        return Err(CatalogError::Points(format!("`{name}` has no tension: a free ω is for the ternary5 presets")));
    }
    let valid = parameter.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && parameter.chars().all(|c| c.is_alphanumeric() || c == '_')
        && parameter != "sqrt";
    if !valid {
        return Err(CatalogError::Points(format!("`{parameter}`: a parameter is a name (letters, digits, _)")));
    }
    // Two generic tensions one apart (ω = 0 would drop entries and change the ends' supports).
    let origin = Surd::frac(DEFAULT_OMEGA.0, DEFAULT_OMEGA.1);
    let at = |k: i64| ifs_preset(name, points.clone(), Some(&origin.add(&Surd::int(k)))).map(|d| d.to_builder());
    let (base, next, third) = (at(0)?, at(1)?, at(2)?);
    let mut builder = base
        .affine_in([&next, &third], parameter, &crate::algebra::Num::from(origin.clone()))
        .map_err(|e| CatalogError::Points(format!("{name} with a free tension: {e}")))?;
    let description = builder.description_text().replace(&format!("ω = {origin}"), &format!("ω = {parameter} (free)"));
    builder.description(description).default_value(parameter, &origin);
    builder.build().map_err(|e| CatalogError::Points(e.to_string()))
}

/// A preset asked for: its name and the user's control points, if any.
struct Request<'a> {
    name: &'a str,
    points: Option<Vec<Vec<f64>>>,
}

impl Request<'_> {
    /// The user's control points, or the preset's.
    fn with(&self, default: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        self.points.clone().unwrap_or(default)
    }

    /// At least `min` finite control points, all of 2 or all of 3 coordinates.
    fn check(&self, model: &ModelSpec, min: usize) -> Result<(), CatalogError> {
        let model = &model.model;
        if model.points.len() < min {
            return Err(CatalogError::Points(format!("`{}` needs at least {min} control points", self.name)));
        }
        if model.points.iter().flatten().any(|x| !x.is_finite()) {
            return Err(CatalogError::Points("control point coordinates must be finite numbers".into()));
        }
        let d = model.points.first().map_or(0, Vec::len);
        if !(2..=3).contains(&d) || model.points.iter().any(|p| p.len() != d) {
            return Err(CatalogError::Points("control points need 2 or 3 coordinates, all the same".into()));
        }
        Ok(())
    }

    /// The curve (or fractal) IFS of `blocks`.
    fn curve(
        &self,
        blocks: Vec<ExactMatrix>,
        description: &str,
        comment: &str,
        model: ModelSpec,
    ) -> Result<Design, CatalogError> {
        ifs_design(self.name, description, comment, &blocks, &model).map_err(|e| CatalogError::Points(e.to_string()))
    }
}

/// The presets of Schaefer et al. 2005: B-splines, Bézier curves, the four-point
/// scheme, Koch and Sierpinski with control points, the bicubic patch.
fn seed1_preset(request: &Request<'_>) -> Result<Design, CatalogError> {
    match request.name {
        "bicubic" => bicubic_preset(request),
        "tricubic" | "tricubic-sponge" => tricubic_preset(request),
        "box-spline" | "box-spline-gasket" | "box-spline-quad" | "sqrt3-patch" => triangle_preset(request),
        name => match seed1_curve(name) {
            Some(curve) => curve.design(request),
            None => Err(CatalogError::Unknown {
                name: name.to_string(),
                suggestion: crate::names::suggest(name, IFS_NAMES),
            }),
        },
    }
}

/// The reference of Schaefer et al. 2005.
const SEED1: &str = "Schaefer, Levin, Goldman, Subdivision schemes and attractors (Schaefer et al. 2005)";

/// A curve of Schaefer et al. 2005: its blocks, default control points and layout,
/// the points it needs, and what the automaton file says about it.
struct Seed1Curve {
    blocks: Vec<ExactMatrix>,
    points: Vec<Vec<f64>>,
    layout: Layout,
    about_points: &'static str,
    min: usize,
    description: &'static str,
    comment: &'static str,
}

impl Seed1Curve {
    fn new(
        blocks: Vec<ExactMatrix>,
        points: Vec<Vec<f64>>,
        layout: Layout,
        about_points: &'static str,
        min: usize,
        description: &'static str,
        comment: &'static str,
    ) -> Seed1Curve {
        Seed1Curve { blocks, points, layout, about_points, min, description, comment }
    }

    fn design(self, request: &Request<'_>) -> Result<Design, CatalogError> {
        let model = spec(request.with(self.points), self.layout, None, self.about_points);
        request.check(&model, self.min)?;
        request.curve(self.blocks, self.description, &format!("{}\n{SEED1}.", self.comment), model)
    }
}

/// The curves of Schaefer et al. 2005 by name.
fn seed1_curve(name: &str) -> Option<Seed1Curve> {
    seed1_spline(name).or_else(|| seed1_fractal(name))
}

/// The spline curves of Schaefer et al. 2005 (§2).
fn seed1_spline(name: &str) -> Option<Seed1Curve> {
    let wave = || pts(&[[0.0, 0.0], [1.0, 2.0], [2.5, 2.2], [3.5, 0.4], [5.0, 1.2]]);
    let curve = Seed1Curve::new;
    Some(match name {
        "bspline" => {
            let b = BSpline::uniform(3, 5).expect("valid").blocks(2).expect("self-similar");
            let n = b[0].len();
            curve(
                b,
                wave(),
                Layout::Open,
                "An open control polygon: windows of 5 points sliding by 2.",
                n,
                "uniform cubic B-spline, 5 control points, Schaefer et al. 2005 §2.1 (Fig. 2)",
                "The uniform cubic B-spline as an IFS: S_1, S_2 are the 5×5 blocks of rules (4).",
            )
        }
        "bspline-end" => curve(
            BSpline::new(3, &[0, 0, 0, 1, 2, 2, 2]).expect("valid").blocks(2).expect("self-similar"),
            wave(),
            Layout::Single,
            "Five control points; the curve interpolates the first and last.",
            5,
            "end-interpolating cubic B-spline, knots {0,0,0,1,2,2,2}, Schaefer et al. 2005 §2.1 (Fig. 3)",
            "Knot insertion by blossoming gives the printed S_1, S_2.",
        ),
        "bezier" => curve(
            BSpline::bezier(2).blocks(2).expect("self-similar"),
            pts(&[[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]]),
            Layout::Single,
            "Three control points.",
            3,
            "quadratic Bézier curve: de Casteljau at u = 1/2, Schaefer et al. 2005 §2.2",
            "Goldman's IFS of a Bézier curve.",
        ),
        "bezier-union" => curve(
            BSpline::bezier(2).blocks(2).expect("self-similar"),
            pts(&[[0.0, 0.0], [1.0, 2.0], [2.0, 0.0], [2.5, 0.5], [3.0, 2.5], [4.5, 1.5]]),
            Layout::Union,
            "Two Bézier curves: points 0-2 and 3-5, drawn apart.",
            6,
            "union of two quadratic Bézier curves, Schaefer et al. 2005 §2.2 (Fig. 4)",
            "The union of attractors: one piece per control triangle (the paper's block-diagonal IFS).",
        ),
        _ => return None,
    })
}

/// The four-point scheme and the fractals with control points of Schaefer et al. 2005 (§2.3, §4).
fn seed1_fractal(name: &str) -> Option<Seed1Curve> {
    let (s, h) = (3f64.sqrt() / 6.0, 3f64.sqrt() / 2.0);
    let curve = Seed1Curve::new;
    Some(match name {
        "four-point" => curve(
            Rules::four_point().blocks(7).expect("7 points give blocks"),
            pts(&[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.5], [4.0, 0.0], [5.0, 1.0], [6.0, 0.0]]),
            Layout::Single,
            "Seven control points: the attractor runs from P2 to P4.",
            7,
            "interpolatory four-point scheme, 7×7 blocks, Schaefer et al. 2005 §2.3 (Fig. 5)",
            "The printed 7×7 blocks S_1, S_2 of the four-point rules.",
        ),
        "koch-control" => curve(
            koch_blocks(),
            pts(&[[0.0, 0.0], [1.0 / 3.0, 0.0], [0.5, s], [2.0 / 3.0, 0.0], [1.0, 0.0]]),
            Layout::Single,
            "The natural control points of the Koch curve (move them to deform it).",
            5,
            "Koch curve with 5 control points, Schaefer et al. 2005 §4.1 (Fig. 10)",
            "The printed S_1 … S_4: barycentric coordinates w.r.t. the closest control points.",
        ),
        "sierpinski-control" => curve(
            sierpinski_blocks(),
            pts(&[[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [0.75, h / 2.0], [0.5, h], [0.25, h / 2.0]]),
            Layout::Single,
            "Corners 0, 2, 4 and edge points 1, 3, 5 (quadratic outer edges).",
            6,
            "Sierpinski gasket with 6 control points, Schaefer et al. 2005 §4.2 (Fig. 11)",
            "The printed S_1 … S_3: outer edges by Lagrange interpolation, inner edges linear.",
        ),
        _ => return None,
    })
}

/// Schaefer et al. 2005's bicubic B-spline patches (Fig. 6).
fn bicubic_preset(request: &Request<'_>) -> Result<Design, CatalogError> {
    let b = BSpline::uniform(3, 4).expect("valid").blocks(2).expect("self-similar");
    let default =
        grid_points(6, 6, |c, r| if (1.0..=4.0).contains(&c) && (1.0..=4.0).contains(&r) { 1.2 } else { 0.0 });
    let model =
        spec(request.with(default), Layout::Grid, Some((6, 6)), "A 6×6 control grid: 3×3 bicubic patches, welded.");
    request.check(&model, 16)?;
    let description = "bicubic B-spline patches: tensor product of the cubic IFS, Schaefer et al. 2005 §3.1 (Fig. 6)";
    tensor_design(
        request.name,
        description,
        &format!("Four maps (S_v ⊗ S_u)ᵀ on a 4×4 control grid.\n{SEED1}."),
        &b,
        &model,
    )
    .map_err(|e| CatalogError::Points(e.to_string()))
}

/// The tricubic B-spline volume as an IFS (the tensor product of three cubic
/// curve IFS: Schaefer et al. 2005 §3.1 one dimension up) on a 4×4×4
/// control lattice: `tricubic` split 2×2×2, every part kept (the volume), a
/// bar bent into an arch; `tricubic-sponge` split 3×3×3 with the Menger
/// sponge's mask, twisted a third of a turn about its axis: a smooth porous
/// solid bent along its lattice.
fn tricubic_preset(request: &Request<'_>) -> Result<Design, CatalogError> {
    use super::pattern::{Basis, Pattern, PatternCell, pattern_design};
    let sponge = request.name == "tricubic-sponge";
    let (split, keep) = if sponge { ("3x3x3", Some("111101111101000101111101111")) } else { ("2x2x2", None) };
    let pattern = Pattern::parse_in(PatternCell::Hexahedron, split, keep, 4, Basis::BSpline)
        .map_err(|e| CatalogError::Points(e.to_string()))?;
    let design = pattern_design(&pattern, request.name).map_err(|e| CatalogError::Points(e.to_string()))?;
    // The lattice at the Greville points (−1, 0, 1, 2 along each direction: the unit cube), bent.
    let mut default = Vec::with_capacity(64);
    for w in 0..4 {
        for v in 0..4 {
            for u in 0..4 {
                let [x, y, z] = [u, v, w].map(|i| f64::from(i) - 1.0);
                default.push(if sponge {
                    let turn = std::f64::consts::FRAC_PI_3 * (z - 0.5);
                    let (dx, dy) = (x - 0.5, y - 0.5);
                    vec![0.5 + dx * turn.cos() - dy * turn.sin(), 0.5 + dx * turn.sin() + dy * turn.cos(), z]
                } else {
                    vec![3.0 * x, y, z + 0.4 * (3.0 * x - 1.5).powi(2)]
                });
            }
        }
    }
    let comment = if sponge {
        "A 4×4×4 control lattice (index 16·w + 4·v + u): the unit cube's Greville points, each layer turned\nby 60° per unit of height about the axis x = y = 0.5."
    } else {
        "A 4×4×4 control lattice (index 16·w + 4·v + u): a 3×1×1 bar's Greville points, raised\nby 0.4 (x − 1.5)²: an arch."
    };
    let model = spec(request.with(default), Layout::Single, None, comment);
    request.check(&model, 64)?;
    let points = model.model.points;
    // n × n × n points: (n − 3)³ cells, each the 4 × 4 × 4 window at its corner, welded where they meet.
    let n = (1..=64).find(|n| n * n * n >= points.len()).unwrap_or(0);
    if n < 4 || n * n * n != points.len() || points[0].len() != 3 {
        return Err(CatalogError::Points(format!(
            "`{}` takes an n × n × n control lattice (n ≥ 4, 3 coordinates each, index n²·w + n·v + u): {} points are not one",
            request.name,
            points.len()
        )));
    }
    let lattice = if n == 4 {
        Model::new("volume", points).with_layout(Layout::Single)
    } else {
        let mut windows = Vec::new();
        for (a, b, c) in (0..n - 3).flat_map(|c| (0..n - 3).flat_map(move |b| (0..n - 3).map(move |a| (a, b, c)))) {
            let at = |i: usize| (c + i / 16) * n * n + (b + i / 4 % 4) * n + a + i % 4;
            windows.push((0..64).map(at).collect());
        }
        Model::new("volume", points).with_patches(vec!["volume".into()], windows)
    };
    let mut b = design.to_builder();
    let description = if sponge {
        "Menger sponge on a tricubic B-spline lattice: the tensor product of three cubic curve IFS, 20 of 27 parts kept, twisted"
    } else {
        "tricubic B-spline volume: the tensor product of three cubic curve IFS (Schaefer et al. 2005 §3.1, one dimension up), a bent bar"
    };
    b.description(description);
    b.model(lattice).doc(model.comment);
    b.build().map_err(|e| CatalogError::Points(e.to_string()))
}

/// The triangle schemes of Schaefer et al. 2005 §3.2–3.3 as IFS on lattice cells
/// ([`super::lattice`]): the box-spline's hexagon (six maps), the same
/// with two maps left out, its parallelogram (four maps), and √3's
/// triangle (nine maps of a ternary split).
fn triangle_preset(request: &Request<'_>) -> Result<Design, CatalogError> {
    use super::lattice::{LatticeScheme, hexagon_parts, lattice_ifs, parallelogram_parts, ternary_triangle_parts};
    let seed1 = "Schaefer, Levin, Goldman, Subdivision schemes and attractors (Schaefer et al. 2005)";
    let (scheme, parts, corners, description, comment) = match request.name {
        "box-spline" => (
            LatticeScheme::BoxSpline,
            hexagon_parts(),
            vec![(0, 0)],
            "three-direction quartic box-spline (Loop) hexagonal patch, six maps, Schaefer et al. 2005 §3.2 (Fig. 7)",
            "Loop's rules on the regular lattice: the six half-size hexagons around the centre.\n\
             19 control points (two rings around the centre); the attractor is the limit surface over\n\
             the hexagon of the first ring.",
        ),
        "box-spline-gasket" => (
            LatticeScheme::BoxSpline,
            hexagon_parts(),
            vec![(0, 0)],
            "box-spline patch with two of its six maps left out: a fractal on the surface, Schaefer et al. 2005 §3.2 (Fig. 9)",
            "The box-spline IFS without the sub-hexagons towards (0,-1) and (1,-1): G ⊂ F, so every point\n\
             lies on the box-spline surface of the same control points (which two the paper drops is not\n\
             printed; these four leave the largest holes).",
        ),
        "box-spline-quad" => (
            LatticeScheme::BoxSpline,
            parallelogram_parts(),
            vec![(0, 0), (1, 0), (0, 1), (1, 1)],
            "box-spline patch over a lattice parallelogram, four maps, Schaefer et al. 2005 §3.2",
            "The four-map split the seed mentions: the parallelogram (0,0), (1,0), (1,1), (0,1) into four\n\
             half-size copies; 14 control points. Its attractor looks rectangular.",
        ),
        _ => (
            LatticeScheme::Sqrt3,
            ternary_triangle_parts(),
            vec![(0, 0), (1, 0), (0, 1)],
            "Kobbelt's √3 scheme on one triangle: two steps are a ternary split, nine maps, Schaefer et al. 2005 §3.3 (Fig. 8)",
            "Two rounds of √3 (valence-6 rules, α = 1/3) split the triangle (0,0), (1,0), (0,1) into six\n\
             upright and three half-turned thirds; 27 control points.",
        ),
    };
    let mut ifs = lattice_ifs(scheme, &parts, &corners).map_err(|e| CatalogError::Points(e.to_string()))?;
    if request.name == "box-spline-gasket" {
        // The same IFS on the same control points, two maps left out.
        ifs.blocks =
            ifs.blocks.into_iter().enumerate().filter(|(i, _)| !GASKET_DROPPED.contains(i)).map(|(_, b)| b).collect();
    }
    let default = ifs
        .control
        .iter()
        .map(|&p| {
            let [x, y] = super::lattice::position(p);
            let z = 0.9 * (-(x * x + y * y) / 2.5).exp() + 0.2 * x - 0.1 * y * y;
            [x, y, z].iter().map(|c| (c * 1e6).round() / 1e6).collect()
        })
        .collect();
    let mut model = spec(
        request.with(default),
        Layout::Single,
        None,
        "Control points on the triangular lattice (axial (i, j) at (i + j/2, j√3/2)), sorted by row, lifted to a hill;\n\
         the net is the lattice's triangles.",
    );
    model.model.net = super::lattice::lattice_triangles(&ifs.control);
    // The cell triangulated: its lattice triangles over the limit points of its vertices (a surface, not a cloud).
    let (start, faces) = super::lattice::cell_mesh(&ifs.control, &cell_triangles(request.name))
        .map_err(|e| CatalogError::Points(e.to_string()))?;
    model.model.start.push(("e".into(), start));
    model.model.start_faces.push(("e".into(), faces));
    request.check(&model, ifs.control.len())?;
    let lattice: Vec<String> = ifs.control.iter().map(|(i, j)| format!("({i},{j})")).collect();
    let comment = format!("{comment}\nLattice points in order: {}.\n{seed1}.", lattice.join(" "));
    request.curve(ifs.blocks, description, &comment, model)
}

/// The lattice triangles of the cell of a triangle preset, counter-clockwise:
/// the hexagon's six around its centre, the parallelogram's two, the triangle.
fn cell_triangles(name: &str) -> Vec<[super::lattice::Axial; 3]> {
    use super::lattice::DIRECTIONS;
    match name {
        "box-spline" | "box-spline-gasket" => {
            (0..6).map(|i| [(0, 0), DIRECTIONS[i], DIRECTIONS[(i + 1) % 6]]).collect()
        }
        "box-spline-quad" => vec![[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]],
        _ => vec![[(0, 0), (1, 0), (0, 1)]],
    }
}

/// Which of the box-spline's six sub-hexagons (counter-clockwise from the
/// one towards `(1, 0)`) the gasket preset leaves out.
pub const GASKET_DROPPED: [usize; 2] = [4, 5];

/// The ternary 5-point presets of Siddiqi et al. 2014: open and closed curves, a
/// sheet and a torus, with tension `omega`.
fn ternary_preset(request: &Request<'_>, omega: &Surd) -> Result<Design, CatalogError> {
    let name = request.name;
    let with = |default| request.with(default);
    let check = |model: &ModelSpec, min| request.check(model, min);
    let rules = ternary_five_point(omega);
    let b = rules.blocks(super::ternary::TERNARY_WINDOW).expect("7 points give blocks");
    let seed3 = format!(
        "The ternary 5-point scheme of Siddiqi, Siddiqui and Ahmad (Siddiqi et al. 2014, eq. 1) with tension ω = {omega}:\n\
         three 7×7 blocks; the attractor of one window is the curve around its middle point."
    );
    match name {
        "ternary5" | "ternary5-closed" => {
            let closed = name == "ternary5-closed";
            let default: Vec<Vec<f64>> = if closed {
                (0..9)
                    .map(|i| {
                        let t = std::f64::consts::TAU * i as f64 / 9.0;
                        let r = if i % 3 == 0 { 1.3 } else { 1.0 };
                        vec![(r * t.cos() * 1e6).round() / 1e6, (r * t.sin() * 1e6).round() / 1e6]
                    })
                    .collect()
            } else {
                (0..12).map(|i| vec![i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }]).collect()
            };
            let model = spec(
                with(default),
                if closed { Layout::Closed } else { Layout::Open },
                None,
                "Windows of 7 control points sliding by 1.",
            );
            check(&model, 7)?;
            request.curve(b, &format!("ternary 5-point curve, ω = {omega}, Siddiqi et al. 2014"), &seed3, model)
        }
        _ => {
            let torus = name == "ternary5-torus";
            let model = if torus {
                spec(with(torus_points(8, 12)), Layout::Torus, Some((8, 12)), "A closed 8×12 control grid on a torus.")
            } else {
                let default =
                    grid_points(9, 9, |c, r| ((c - 4.0).powi(2) + (r - 4.0).powi(2) < 5.0) as u8 as f64 * 1.5);
                spec(with(default), Layout::Grid, Some((9, 9)), "A 9×9 control grid: 3×3 patches of 7×7 windows.")
            };
            check(&model, 49)?;
            let description = format!("ternary 5-point tensor-product surface, ω = {omega}, Siddiqi et al. 2014");
            tensor_design(name, &description, &seed3, &b, &model).map_err(|e| CatalogError::Points(e.to_string()))
        }
    }
}
