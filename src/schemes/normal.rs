//! The multi-control p-ary subdivision scheme based on normal vectors of
//! Li, Zheng, Peng and Zhou (*Normal vector based subdivision scheme to
//! generate fractal curves*, Li et al. 2013), in two forms that agree:
//!
//! - the **direct polyline form** of eq. (1): every segment `P_i P_{i+1}` of
//!   level `k` is replaced by the `p` points
//!   `P_{pi+j} = (1 - α_j) P_i + α_j P_{i+1} + β_j d_i`, with
//!   `d_i = |P_i P_{i+1}| n_i` and `n_i` the unit normal obtained by rotating
//!   the segment counter-clockwise (positive) or clockwise (negative);
//! - the **automaton form** for interpolatory parameter sets
//!   (`α_0 = β_0 = 0`): a segment with its rotated frame point
//!   `Q_i = P_i + R90(P_{i+1} - P_i)` is a 3-point barycentric cell, since
//!   `d_i = ±(Q_i - P_i)` is affine in `(P_i, P_{i+1}, Q_i)`. New point `j` has
//!   barycentric coordinates `(1 - α_j - σβ_j, α_j, σβ_j)` (`σ = ±1`, the
//!   normal direction times the sign pattern), and sub-segment `j` is the
//!   frame of points `j` and `j + 1`. The ends of a segment are vertices of
//!   dimension 1.
//!
//! The sign patterns of the paper make β depend on the level `k` and the
//! index `i` of the segment: `(−1)^i` (dragon, Fig. 3), `(−1)^(k+i)`
//! (Sierpinski gasket, eq. 3), `(−1)^(k+1)` (human-like curve, Fig. 8b).
//! The sign of a segment is a function of `(k mod 2, i mod 2)`, and its
//! children's are a function of the same pair, so the pattern is a finite
//! automaton over these four pairs; bcifs minimises it (Moore's partition
//! refinement) into the fewest states: one for a constant sign, two for
//! the paper's patterns (four for `(−1)^(k+i)` with an even `p`).

use std::collections::HashMap;
use std::fmt;

use crate::algebra::{Surd, SurdError};
use crate::design::{Design, Layout, Model};
use crate::space::CellKind;

/// A point of the plane.
pub type Point2 = [f64; 2];

/// The direction of the unit normals `n_i`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NormalDirection {
    /// The segment rotated counter-clockwise.
    Positive,
    /// The segment rotated clockwise.
    Negative,
}

impl NormalDirection {
    fn sign(self) -> i64 {
        match self {
            NormalDirection::Positive => 1,
            NormalDirection::Negative => -1,
        }
    }
}

/// How the sign of the β's varies with the level `k` and the index `i` of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SignPattern {
    /// β as given.
    Constant,
    /// `(−1)^i β`: the dragon curves (Fig. 3).
    Alternate,
    /// `(−1)^(k+1) β`: the human-like curve (Fig. 8b).
    Level,
    /// `(−1)^(k+i) β`: the Sierpinski gasket, eq. (3).
    LevelIndex,
}

impl SignPattern {
    /// All patterns.
    pub const ALL: [SignPattern; 4] =
        [SignPattern::Constant, SignPattern::Alternate, SignPattern::Level, SignPattern::LevelIndex];

    /// The keyword of the command line.
    pub fn keyword(self) -> &'static str {
        match self {
            SignPattern::Constant => "constant",
            SignPattern::Alternate => "alternate",
            SignPattern::Level => "level",
            SignPattern::LevelIndex => "level-index",
        }
    }

    /// `±1` for a segment of index `i` at level `k`.
    pub fn sign(self, k: usize, i: usize) -> i64 {
        let odd = match self {
            SignPattern::Constant => false,
            SignPattern::Alternate => i % 2 == 1,
            SignPattern::Level => (k + 1) % 2 == 1,
            SignPattern::LevelIndex => (k + i) % 2 == 1,
        };
        if odd { -1 } else { 1 }
    }

    fn formula(self) -> &'static str {
        match self {
            SignPattern::Constant => "β_j",
            SignPattern::Alternate => "(−1)^i β_j",
            SignPattern::Level => "(−1)^(k+1) β_j",
            SignPattern::LevelIndex => "(−1)^(k+i) β_j",
        }
    }
}

/// Why a normal-vector scheme cannot be built or turned into an automaton.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NormalSchemeError {
    /// `p < 2` or α, β of different lengths.
    #[error("a p-ary scheme needs p ≥ 2 and p values of α and of β (got {alpha} α and {beta} β)")]
    Arity {
        /// Number of α.
        alpha: usize,
        /// Number of β.
        beta: usize,
    },
    /// A parameter is not an exact constant.
    #[error(transparent)]
    Value(#[from] SurdError),
    /// The automaton form needs `α_0 = β_0 = 0`.
    #[error(
        "the automaton form needs an interpolatory scheme (α_0 = β_0 = 0, here α_0 = {alpha0}, β_0 = {beta0}): \
         a sub-segment would straddle two segments. Use the direct polyline form."
    )]
    NotInterpolatory {
        /// α_0.
        alpha0: String,
        /// β_0.
        beta0: String,
    },
    /// A coordinate of the initial polygon is infinite or not a number.
    #[error("the initial polygon has a coordinate that is not a finite number")]
    NotFinite,
    /// The generated automaton does not build: a bug.
    #[error("internal error in the normal-vector generator (please report): {0}")]
    Internal(String),
    /// An initial polygon that has no segment.
    #[error("the initial polygon needs at least 2 points (3 when closed), not {0}")]
    Polygon(usize),
    /// No preset of that name.
    #[error("no preset named `{name}`{}; presets: {}", .suggestion.as_ref().map(|s| format!(" (did you mean `{s}`?)")).unwrap_or_default(), PRESET_NAMES.join(", "))]
    UnknownPreset {
        /// The name asked for.
        name: String,
        /// The closest preset name.
        suggestion: Option<String>,
    },
}

/// A multi-control p-ary normal-vector scheme, eq. (1) of Li et al. 2013.
///
/// ```
/// use bcifs::schemes::{NormalScheme, normal_preset};
/// let koch = normal_preset("koch").unwrap();
/// // Eq. (5): four sub-segments of length 1/3, so the length grows by 4/3 a level.
/// let pts = koch.scheme.polygon(&koch.polygon, false, 3);
/// assert_eq!(pts.len(), 4usize.pow(3) + 1);
/// let len: f64 = pts.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt()).sum();
/// assert!((len - (4.0f64 / 3.0).powi(3)).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct NormalScheme {
    /// α_0 … α_{p-1}: positions of the assistant points along the segment.
    pub alpha: Vec<Surd>,
    /// β_0 … β_{p-1}: displacements along the normal, in units of the segment length.
    pub beta: Vec<Surd>,
    /// Direction of the normals.
    pub normal: NormalDirection,
    /// How the sign of β varies with level and index.
    pub sign: SignPattern,
}

impl NormalScheme {
    /// The scheme with these α and β, positive normals and constant sign.
    ///
    /// # Errors
    /// [`NormalSchemeError::Arity`] unless both have the same length `p ≥ 2`.
    pub fn new(alpha: Vec<Surd>, beta: Vec<Surd>) -> Result<NormalScheme, NormalSchemeError> {
        if alpha.len() < 2 || alpha.len() != beta.len() {
            return Err(NormalSchemeError::Arity { alpha: alpha.len(), beta: beta.len() });
        }
        Ok(NormalScheme { alpha, beta, normal: NormalDirection::Positive, sign: SignPattern::Constant })
    }

    /// Parses α and β from constant expressions (`"1/3"`, `"sqrt(3)/6"`).
    ///
    /// # Errors
    /// See [`NormalScheme::new`] and [`Surd::parse`].
    pub fn parse(alpha: &[&str], beta: &[&str]) -> Result<NormalScheme, NormalSchemeError> {
        let parse = |v: &[&str]| v.iter().map(|s| Surd::parse(s)).collect::<Result<Vec<_>, _>>();
        NormalScheme::new(parse(alpha)?, parse(beta)?)
    }

    /// With the given normal direction.
    pub fn with_normal(mut self, normal: NormalDirection) -> Self {
        self.normal = normal;
        self
    }

    /// With the given sign pattern.
    pub fn with_sign(mut self, sign: SignPattern) -> Self {
        self.sign = sign;
        self
    }

    /// `p`: the number of new points per segment.
    pub fn arity(&self) -> usize {
        self.alpha.len()
    }

    /// Whether `α_0 = β_0 = 0`: every old point is kept.
    pub fn is_interpolatory(&self) -> bool {
        self.alpha[0].is_zero() && self.beta[0].is_zero()
    }

    /// One step of eq. (1) on the polygon of level `k`: `p` points per segment
    /// (segments `P_i P_{i+1}`, and `P_{n-1} P_0` when `closed`).
    ///
    /// An open polygon keeps its last point: the paper's rule `j = 0` at
    /// `i = p^k n` needs a point after the last one, which does not exist
    /// (for interpolatory schemes it is the last point itself).
    pub fn step(&self, points: &[Point2], closed: bool, k: usize) -> Vec<Point2> {
        let n = points.len();
        let segments = if closed { n } else { n.saturating_sub(1) };
        let p = self.arity();
        let alpha: Vec<f64> = self.alpha.iter().map(Surd::to_f64).collect();
        let beta: Vec<f64> = self.beta.iter().map(Surd::to_f64).collect();
        let mut out = Vec::with_capacity(segments * p + 1);
        for i in 0..segments {
            let (a, b) = (points[i], points[(i + 1) % n]);
            let sigma = (self.normal.sign() * self.sign.sign(k, i)) as f64;
            // d_i = |P_i P_{i+1}| n_i = ±R90(P_{i+1} - P_i).
            let d = [-(b[1] - a[1]) * sigma, (b[0] - a[0]) * sigma];
            for j in 0..p {
                let (al, be) = (alpha[j], beta[j]);
                out.push([(1.0 - al) * a[0] + al * b[0] + be * d[0], (1.0 - al) * a[1] + al * b[1] + be * d[1]]);
            }
        }
        if !closed && let Some(last) = points.last() {
            out.push(*last);
        }
        out
    }

    /// The polygon after `depth` steps of eq. (1).
    pub fn polygon(&self, points: &[Point2], closed: bool, depth: usize) -> Vec<Point2> {
        let mut pts = points.to_vec();
        for k in 0..depth {
            pts = self.step(&pts, closed, k);
        }
        pts
    }

    /// Sign classes of the pattern automaton: `(class of each raw state
    /// (k mod 2, i mod 2), sign of each class, child classes of each class)`,
    /// classes numbered in order of first appearance from the roots.
    fn sign_automaton(&self) -> (Vec<usize>, Vec<i64>, Vec<Vec<usize>>) {
        let p = self.arity();
        let raw_sign = |s: usize| self.normal.sign() * self.sign.sign(s / 2, s % 2);
        let child = |s: usize, j: usize| (((s / 2) + 1) % 2) * 2 + (p * (s % 2) + j) % 2;
        // Moore: start from the sign partition, refine by the children's classes.
        let mut class: Vec<usize> = (0..4).map(|s| usize::from(raw_sign(s) < 0)).collect();
        loop {
            let mut keys: Vec<(usize, Vec<usize>)> = Vec::new();
            let next: Vec<usize> = (0..4)
                .map(|s| {
                    let key = (class[s], (0..p).map(|j| class[child(s, j)]).collect::<Vec<_>>());
                    keys.iter().position(|k| *k == key).unwrap_or_else(|| {
                        keys.push(key);
                        keys.len() - 1
                    })
                })
                .collect();
            let stable = next.iter().collect::<std::collections::HashSet<_>>().len()
                == class.iter().collect::<std::collections::HashSet<_>>().len();
            class = next;
            if stable {
                break;
            }
        }
        // Renumber the classes reachable from the roots (0,0), (0,1) in order of appearance.
        let mut order: Vec<usize> = Vec::new();
        let mut queue = vec![0usize, 1];
        let mut seen_raw = [false; 4];
        while let Some(s) = queue.first().copied() {
            queue.remove(0);
            if seen_raw[s] {
                continue;
            }
            seen_raw[s] = true;
            if !order.contains(&class[s]) {
                order.push(class[s]);
            }
            queue.extend((0..p).map(|j| child(s, j)));
        }
        let renumber: HashMap<usize, usize> = order.iter().enumerate().map(|(new, old)| (*old, new)).collect();
        let of_raw: Vec<usize> = (0..4).map(|s| renumber.get(&class[s]).copied().unwrap_or(usize::MAX)).collect();
        let mut signs = vec![0; order.len()];
        let mut children = vec![Vec::new(); order.len()];
        for s in 0..4 {
            let c = of_raw[s];
            if c == usize::MAX || !children[c].is_empty() {
                continue;
            }
            signs[c] = raw_sign(s);
            children[c] = (0..p).map(|j| of_raw[child(s, j)]).collect();
        }
        (of_raw, signs, children)
    }

    /// The 3×3 matrix of sub-segment `j` in frame coordinates for normal sign `sigma`:
    /// columns are the start, the end and the rotated frame point of the sub-segment.
    pub fn frame_matrix(&self, j: usize, sigma: i64) -> [[Surd; 3]; 3] {
        let p = self.arity();
        let s = Surd::int(sigma);
        let point = |j: usize| -> [Surd; 3] {
            if j == p {
                return [Surd::zero(), Surd::int(1), Surd::zero()];
            }
            let b = self.beta[j].mul(&s);
            [Surd::int(1).sub(&self.alpha[j]).sub(&b), self.alpha[j].clone(), b]
        };
        let (a, e) = (point(j), point(j + 1));
        let delta: Vec<Surd> = (0..3).map(|r| e[r].sub(&a[r])).collect();
        // R90 in frame coordinates: x1 (P1 - P0) + x2 (Q - P0) ↦ x1 (Q - P0) + x2 (P0 - P1).
        let f = [a[0].add(&delta[2]).sub(&delta[1]), a[1].sub(&delta[2]), a[2].add(&delta[1])];
        let col = [a, e, f];
        std::array::from_fn(|r| std::array::from_fn(|c| col[c][r].clone()))
    }

    /// The comment above a generated automaton: the scheme and its frame cells.
    fn header_doc(&self, sign_classes: usize) -> String {
        let list = |v: &[Surd]| v.iter().map(Surd::to_string).collect::<Vec<_>>().join(", ");
        format!(
            "The {p}-ary normal-vector scheme of Li, Zheng, Peng and Zhou (Li et al. 2013, eq. 1) as a BC-IFS\n\
             (generated by bcifs). P_(pi+j) = (1 - α_j) P_i + α_j P_(i+1) + {} |P_i P_(i+1)| n_i with\n\
             α = ({}), β = ({}), {} normals.\n\
             \n\
             A segment with its rotated frame point Q = P_i + R90(P_(i+1) - P_i) is a 3-point barycentric cell\n\
             (P_i, P_(i+1), Q): new point j is (1 - α_j - σβ_j, α_j, σβ_j), σ = ±1 the sign of the normal.\n\
             Sub-segment j has columns (start, end, start + R90(end - start)), where R90 acts on frame\n\
             coordinates as x1 (P1 - P0) + x2 (Q - P0) -> x1 (Q - P0) + x2 (P0 - P1).\n\
             {}",
            self.sign.formula(),
            list(&self.alpha),
            list(&self.beta),
            match self.normal {
                NormalDirection::Positive => "positive (counter-clockwise)",
                NormalDirection::Negative => "negative (clockwise)",
            },
            if sign_classes > 1 {
                format!(
                    "The sign pattern {} is a finite automaton: {sign_classes} edge states, one per sign class.",
                    self.sign.formula()
                )
            } else {
                String::new()
            },
            p = self.arity()
        )
    }

    /// The design of an interpolatory scheme on an initial polygon: one
    /// edge state per sign class (the fewest the pattern allows), a vertex
    /// of dimension 1, the adjacency and incidence constraints, and a
    /// `frames` model. `bcifs check` passes on it; [`crate::write_design`]
    /// prints it as a commented automaton file.
    ///
    /// # Errors
    /// [`NormalSchemeError::NotInterpolatory`], or a polygon without segment.
    pub fn design(&self, name: &str, polygon: &[Point2], closed: bool) -> Result<Design, NormalSchemeError> {
        self.described_design(name, &format!("normal-vector scheme `{name}`"), polygon, closed)
    }

    fn described_design(
        &self,
        name: &str,
        description: &str,
        polygon: &[Point2],
        closed: bool,
    ) -> Result<Design, NormalSchemeError> {
        if !self.is_interpolatory() {
            return Err(NormalSchemeError::NotInterpolatory {
                alpha0: self.alpha[0].to_string(),
                beta0: self.beta[0].to_string(),
            });
        }
        if polygon.len() < if closed { 3 } else { 2 } {
            return Err(NormalSchemeError::Polygon(polygon.len()));
        }
        if polygon.iter().flatten().any(|x| !x.is_finite()) {
            return Err(NormalSchemeError::NotFinite);
        }
        let p = self.arity();
        let (of_raw, signs, children) = self.sign_automaton();
        let many = signs.len() > 1;
        let state = |c: usize| if many { format!("e{c}") } else { "e".to_string() };
        let arrow = |base: &str, c: usize| if many { format!("{base}_e{c}") } else { base.to_string() };
        let mut b = Design::builder(name);
        b.description(description).doc(self.header_doc(signs.len()));
        for (c, sigma) in signs.iter().enumerate() {
            b.state(state(c), 3, CellKind::Edge)
                .doc(format!("A segment with its frame point, normal sign σ = {sigma:+}: BI^3."));
        }
        b.state("v", 1, CellKind::Vertex).doc("An end point of a segment: BI^1.");
        for (c, sigma) in signs.iter().enumerate() {
            for (j, &target) in children[c].iter().enumerate() {
                let m = self.frame_matrix(j, *sigma);
                b.matrix(arrow(&format!("T{j}"), c), state(c), state(target), m.iter().map(|r| r.iter())).doc(format!(
                    "Sub-segment {j} of {p}{}.",
                    if many { format!(", a segment of state {}", state(target)) } else { String::new() }
                ));
            }
            b.select(arrow("b0", c), state(c), "v", [0]).doc("Start point of the segment: P_i.");
            b.select(arrow("b1", c), state(c), "v", [1]).doc("End point of the segment: P_(i+1).");
            for j in 0..p - 1 {
                let (t, next) = (arrow(&format!("T{j}"), c), arrow(&format!("T{}", j + 1), c));
                let (end, start) = (arrow("b1", children[c][j]), arrow("b0", children[c][j + 1]));
                b.adjacency(format!("{t} {end} = {next} {start}")).doc("Consecutive sub-segments meet.");
            }
            let (first, last) = (arrow("T0", c), arrow(&format!("T{}", p - 1), c));
            b.incidence(format!("{first} {} = {} Tv", arrow("b0", children[c][0]), arrow("b0", c)));
            b.incidence(format!("{last} {} = {} Tv", arrow("b1", children[c][p - 1]), arrow("b1", c)))
                .doc("The scheme is interpolatory: the ends of a segment stay.");
        }
        b.matrix("Tv", "v", "v", [[1]]).doc("An end point stays (interpolatory).");
        let mut roots: Vec<String> = vec![state(of_raw[0])];
        if polygon.len() > 2 && of_raw[1] != of_raw[0] {
            roots.push(state(of_raw[1]));
        }
        let points: Vec<Vec<f64>> = polygon.iter().map(|p| p.to_vec()).collect();
        let layout = if closed { Layout::ClosedFrames } else { Layout::Frames };
        b.model(Model::new("", points).with_roots(roots).with_layout(layout)).doc(
            "The initial polygon: the frames layout adds to each segment its frame point P_i + R90(P_(i+1) - P_i);\n\
             segment i at level 0 is a cell of the i-th root (taken in turn).",
        );
        b.build().map_err(|e| NormalSchemeError::Internal(e.to_string()))
    }
}

impl fmt::Display for NormalScheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let list = |v: &[Surd]| v.iter().map(Surd::to_string).collect::<Vec<_>>().join(", ");
        write!(
            f,
            "p = {}, α = ({}), β = ({}), {:?} normals, sign {}",
            self.arity(),
            list(&self.alpha),
            list(&self.beta),
            self.normal,
            self.sign.formula()
        )
    }
}

/// A figure of Li et al. 2013: a scheme, an initial polygon and the paper's depth.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalPreset {
    /// Preset name (`koch`, `snowflake`, ...).
    pub name: &'static str,
    /// What it is and where the paper shows it.
    pub description: &'static str,
    /// The scheme.
    pub scheme: NormalScheme,
    /// The initial polygon.
    pub polygon: Vec<Point2>,
    /// Whether the polygon is closed.
    pub closed: bool,
    /// The number of subdivision steps of the paper's figure.
    pub depth: usize,
}

impl NormalPreset {
    /// The automaton form of the preset on its polygon, described as the
    /// paper's figure (see [`NormalScheme::design`]).
    ///
    /// # Errors
    /// [`NormalSchemeError::NotInterpolatory`] for the approximating preset.
    pub fn design(&self) -> Result<Design, NormalSchemeError> {
        self.scheme.described_design(self.name, self.description, &self.polygon, self.closed)
    }
}

/// The names of the presets, in the paper's order.
pub const PRESET_NAMES: [&str; 16] = [
    "levy",
    "dragon",
    "dragon-triangle",
    "dragon-quad",
    "sierpinski",
    "sierpinski-triangle",
    "sierpinski-quad",
    "koch",
    "koch-triangle",
    "koch-quad",
    "snowflake",
    "tigerhead",
    "human",
    "approximating",
    "crown",
    "minkowski",
];

/// The unit segment from (0,0) to (1,0) (Fig. 3a).
pub fn unit_segment() -> Vec<Point2> {
    vec![[0.0, 0.0], [1.0, 0.0]]
}

/// The equilateral triangle of side 1 on the unit segment, counter-clockwise (Fig. 3b).
pub fn unit_triangle() -> Vec<Point2> {
    vec![[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]]
}

/// The unit square, counter-clockwise (the quadrilateral of Fig. 3c).
pub fn unit_square() -> Vec<Point2> {
    vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
}

/// The preset called `name` (see [`PRESET_NAMES`]).
///
/// # Errors
/// [`NormalSchemeError::UnknownPreset`], with the closest name.
pub fn normal_preset(name: &str) -> Result<NormalPreset, NormalSchemeError> {
    curve_figure(name).or_else(|| shape_figure(name)).ok_or_else(|| NormalSchemeError::UnknownPreset {
        name: name.to_string(),
        suggestion: crate::names::suggest(name, PRESET_NAMES),
    })
}

/// A preset scheme: `α` and `β` as exact constants, the normals' direction and β's signs.
fn preset_scheme(a: &[&str], b: &[&str], normal: NormalDirection, sign: SignPattern) -> NormalScheme {
    NormalScheme::parse(a, b).expect("preset parameters are exact").with_normal(normal).with_sign(sign)
}

/// A preset of a figure.
fn preset(
    name: &'static str,
    description: &'static str,
    scheme: NormalScheme,
    polygon: &[Point2],
    closed: bool,
    depth: usize,
) -> NormalPreset {
    NormalPreset { name, description, scheme, polygon: polygon.to_vec(), closed, depth }
}

/// The classic fractal curves of the paper (Figs. 2–7) on its unit shapes.
fn curve_figure(name: &str) -> Option<NormalPreset> {
    use NormalDirection::{Negative, Positive};
    use SignPattern::{Alternate, Constant, LevelIndex};
    let scheme = preset_scheme;
    let levy = || scheme(&["0", "1/2"], &["0", "1/2"], Positive, Constant);
    let dragon = || scheme(&["0", "1/2"], &["0", "1/2"], Positive, Alternate);
    let sierpinski = || scheme(&["0", "1/4", "3/4"], &["0", "sqrt(3)/4", "sqrt(3)/4"], Positive, LevelIndex);
    let koch = |normal| scheme(&["0", "1/3", "1/2", "2/3"], &["0", "0", "sqrt(3)/6", "0"], normal, Constant);
    let (seg, tri, quad) = (unit_segment(), unit_triangle(), unit_square());
    Some(match name {
        "levy" => preset("levy", "Lévy C curve, scheme (2), Fig. 2", levy(), &seg, false, 11),
        "dragon" => preset("dragon", "dragon curve, β_1 = (−1)^i/2, Fig. 3a", dragon(), &seg, false, 10),
        "dragon-triangle" => {
            preset("dragon-triangle", "dragon curves on a triangle, Fig. 3b", dragon(), &tri, true, 10)
        }
        "dragon-quad" => preset("dragon-quad", "dragon curves on a quadrilateral, Fig. 3c", dragon(), &quad, true, 10),
        "sierpinski" => preset("sierpinski", "Sierpinski gasket, scheme (3), Fig. 4", sierpinski(), &seg, false, 7),
        "sierpinski-triangle" => preset(
            "sierpinski-triangle",
            "Sierpinski gasket-like curve on a triangle, scheme (3), Fig. 5a",
            sierpinski(),
            &tri,
            true,
            7,
        ),
        "sierpinski-quad" => preset(
            "sierpinski-quad",
            "Sierpinski gasket-like curve on a quadrilateral, scheme (3), Fig. 5b",
            sierpinski(),
            &quad,
            true,
            7,
        ),
        "koch" => preset("koch", "Koch curve, scheme (5), Fig. 6a", koch(Positive), &seg, false, 5),
        "koch-triangle" => {
            preset("koch-triangle", "Koch-type curve on a triangle, Fig. 6b", koch(Positive), &tri, true, 5)
        }
        "koch-quad" => {
            preset("koch-quad", "Koch-type curve on a quadrilateral, Fig. 6c", koch(Positive), &quad, true, 5)
        }
        "snowflake" => preset("snowflake", "Koch snowflake, negative normals, Fig. 7b", koch(Negative), &tri, true, 5),
        _ => return None,
    })
}

/// The other shapes of the paper (Figs. 8–9).
fn shape_figure(name: &str) -> Option<NormalPreset> {
    use NormalDirection::{Negative, Positive};
    use SignPattern::{Constant, Level};
    let scheme = preset_scheme;
    let (seg, quad) = (unit_segment(), unit_square());
    Some(match name {
        "tigerhead" => preset(
            "tigerhead",
            "tiger-head-like curve, Fig. 8a",
            scheme(&["0", "-1/4", "1/2", "5/4"], &["0", "1/3", "1/2", "1/3"], Positive, Constant),
            &seg,
            false,
            6,
        ),
        "human" => preset(
            "human",
            "human-like curve, β = (−1)^(k+1)(0, 1/3, 1/2, 1/3), Fig. 8b",
            scheme(&["0", "5/9", "1/2", "4/9"], &["0", "1/3", "1/2", "1/3"], Positive, Level),
            &seg,
            false,
            7,
        ),
        "approximating" => preset(
            "approximating",
            "approximating curve on a quadrilateral, negative normals, Fig. 8c",
            scheme(&["-1/2", "-1/4", "1/4", "1/2"], &["0", "1/5", "1/5", "0"], Negative, Constant),
            &quad,
            true,
            5,
        ),
        "crown" => preset(
            "crown",
            "crown-like curve, 6-ary, Fig. 9a",
            scheme(
                &["0", "1/3", "1/3", "1/2", "2/3", "2/3"],
                &["0", "-sqrt(3)/9", "sqrt(3)/9", "-sqrt(3)/18", "sqrt(3)/9", "-sqrt(3)/9"],
                Positive,
                Constant,
            ),
            &seg,
            false,
            4,
        ),
        "minkowski" => preset(
            "minkowski",
            "\"Minkowski curve\", 7-ary, Fig. 9b (dimension log 3/log 2 ≈ 1.585, not the Minkowski curve's 1.5: docs/errata.md)",
            scheme(
                &["0", "1/4", "1/4", "1/2", "1/2", "3/4", "3/4"],
                &["0", "0", "1/4", "1/4", "-1/4", "-1/4", "0"],
                Positive,
                Constant,
            ),
            &seg,
            false,
            5,
        ),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_automata_have_the_fewest_states() {
        let count = |p: usize, sign| {
            let s = NormalScheme::new(vec![Surd::zero(); p], vec![Surd::zero(); p]).unwrap().with_sign(sign);
            s.sign_automaton().1.len()
        };
        for p in 2..6 {
            assert_eq!(count(p, SignPattern::Constant), 1);
            assert_eq!(count(p, SignPattern::Alternate), 2);
            assert_eq!(count(p, SignPattern::Level), 2);
            assert_eq!(count(p, SignPattern::LevelIndex), if p % 2 == 1 { 2 } else { 4 });
        }
    }

    #[test]
    fn levy_frame_matrices_are_those_of_the_shipped_file() {
        let levy = normal_preset("levy").unwrap().scheme;
        let t0 = levy.frame_matrix(0, 1);
        let text: Vec<Vec<String>> = t0.iter().map(|r| r.iter().map(Surd::to_string).collect()).collect();
        assert_eq!(text, [["1", "0", "1"], ["0", "1/2", "-1/2"], ["0", "1/2", "1/2"]]);
    }
}
