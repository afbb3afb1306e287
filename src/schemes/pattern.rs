//! Subdivision patterns (issue 44): a cell split into a grid of sub-cells,
//! some kept and the others holes, makes its whole BC-IFS automaton — the
//! states, the subdivision and boundary arrows, and every incidence and
//! adjacency constraint the kept sub-cells imply, each with a comment
//! naming the sub-cells it glues. The user writes none of them.
//!
//! Cells carry Bézier-like control grids: a segment `D` control points, a
//! quadrilateral `D × D` (index `D·row + col`, rows along v), their ends
//! and corners one control point each, their sides the boundary row or
//! column. The classical member (the defaults) is the cell's polynomial
//! patch of degree `D − 1` subdivided at the uniform split points (de
//! Casteljau's matrices, exact): the Cantor set, the Sierpiński carpet on a
//! bicubic patch. Every other member moves the subdivision points: rough or
//! smooth laces of the same topology.

use num_rational::BigRational;
use num_traits::One;

use super::blossom::bezier_part;

use crate::algebra::Num;
use crate::design::{Design, DesignBuilder, Layout, Model};
use crate::space::{CellKind, Patch};

/// The cells a pattern splits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatternCell {
    /// A segment split into `k` parts.
    Segment,
    /// A quadrilateral split into `k × l` parts.
    Quad,
    /// A triangle split `n`-ary into `n²` triangles (upward and downward), a Bézier triangle of degree 1 to 3.
    Triangle,
    /// A hexahedron split into `k × l × m` parts.
    Hexahedron,
    /// A tetrahedron split into its four corner tetrahedra (`split` 2), corners only (degree 2).
    Tetrahedron,
}

impl PatternCell {
    /// Its name on the command line and in pattern files.
    pub fn name(self) -> &'static str {
        match self {
            PatternCell::Segment => "segment",
            PatternCell::Quad => "quad",
            PatternCell::Triangle => "triangle",
            PatternCell::Hexahedron => "hexahedron",
            PatternCell::Tetrahedron => "tetrahedron",
        }
    }

    /// The cell of this name.
    pub fn named(name: &str) -> Option<PatternCell> {
        [
            PatternCell::Segment,
            PatternCell::Quad,
            PatternCell::Triangle,
            PatternCell::Hexahedron,
            PatternCell::Tetrahedron,
        ]
        .into_iter()
        .find(|c| c.name() == name)
    }

    /// The number of split counts it takes.
    pub fn dimension(self) -> usize {
        match self {
            PatternCell::Segment | PatternCell::Triangle | PatternCell::Tetrahedron => 1,
            PatternCell::Quad => 2,
            PatternCell::Hexahedron => 3,
        }
    }

    /// Its sub-cells for a split.
    fn cells(self, split: &[usize]) -> usize {
        match self {
            PatternCell::Triangle => split[0] * split[0],
            PatternCell::Tetrahedron => 4,
            _ => split.iter().product(),
        }
    }
}

/// How a cell splits, which sub-cells are kept, and how many control points it carries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    /// The cell.
    pub cell: PatternCell,
    /// Parts along each direction (u, then v).
    pub split: Vec<usize>,
    /// One flag per sub-cell, u fastest, then v: kept (`true`) or a hole.
    pub keep: Vec<bool>,
    /// Control points along each direction, 2 to 4 (linear to cubic).
    pub degree: usize,
    /// Bézier grids and unknown matrices (a family), or a uniform B-spline's fixed matrices.
    pub basis: Basis,
    /// Where the classical member splits each direction (its `k − 1` inner
    /// points, increasing in `(0, 1)`); empty: uniformly (`1/k, 2/k, …`).
    /// One list serves every direction. Only the defaults change: the family
    /// is the same, its default member another (a Jerusalem-cube-like sponge
    /// splits at `2/5, 3/5`).
    pub at: Vec<BigRational>,
}

/// How a pattern's cells carry their control points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Basis {
    /// Bézier-like grids whose matrices are unknowns: the family of every
    /// member of the pattern's topology, the polynomial cell subdivided its
    /// classical member (the default).
    #[default]
    Bezier,
    /// The uniform B-spline of degree `degree − 1` along each direction: the
    /// matrices fixed, the tensor product of the curve's subdivision
    /// (Schaefer et al. 2005 §3.1, one dimension up); the shape is set by the
    /// control lattice alone, smooth across the cells' sides (hexahedra only:
    /// the tricubic B-spline volume with `degree` 4).
    BSpline,
}

impl Basis {
    /// Its name on the command line and in pattern files.
    pub fn name(self) -> &'static str {
        match self {
            Basis::Bezier => "bezier",
            Basis::BSpline => "bspline",
        }
    }

    /// The basis of this name.
    pub fn named(name: &str) -> Option<Basis> {
        [Basis::Bezier, Basis::BSpline].into_iter().find(|b| b.name() == name)
    }
}

/// Most exact entries of a pattern's fixed matrices (a cubic B-spline
/// Menger sponge has about 160,000).
const MAX_FIXED_ENTRIES: usize = 1_000_000;

/// A pattern that makes no automaton.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PatternError {
    /// A split that does not fit the cell.
    #[error("a {cell} splits along {dimension} direction(s): give {expected} (got {got:?}), each at least 2")]
    Split {
        /// The cell.
        cell: &'static str,
        /// Its dimension.
        dimension: usize,
        /// What is expected.
        expected: &'static str,
        /// What was given.
        got: Vec<usize>,
    },
    /// A mask of the wrong length, or not of 0s and 1s.
    #[error("the mask has {got} flag(s) for {expected} sub-cells ({split}): one 0 or 1 per sub-cell, u fastest")]
    Mask {
        /// Flags given.
        got: usize,
        /// Sub-cells.
        expected: usize,
        /// The split, as written.
        split: String,
    },
    /// A mask that is not of 0s and 1s.
    #[error("the mask `{0}` is not made of 0s and 1s")]
    MaskText(String),
    /// Nothing kept.
    #[error("the mask keeps no sub-cell: the attractor would be empty")]
    Empty,
    /// A degree that does not fit.
    #[error(
        "a degree of {0} control points per direction: expected 2, 3 or 4 (linear, quadratic, cubic); 2 for a tetrahedron (its corners)"
    )]
    Degree(usize),
    /// Too many unknowns for the exact solver.
    #[error(
        "this pattern has {unknowns} unknown matrix entries: the exact solver takes at most {max}; lower the degree or the split"
    )]
    TooLarge {
        /// Unknown entries.
        unknowns: usize,
        /// The limit.
        max: usize,
    },
    /// A basis that does not fit the pattern.
    #[error("{0}")]
    Basis(String),
    /// Split points that do not fit.
    #[error(
        "split points `{0}`: give the k − 1 inner points of a k-part split, increasing inside (0, 1), as numbers or fractions (`2/5,3/5`); every direction must have k parts; not for triangles or tetrahedra"
    )]
    At(String),
    /// A pattern file that does not read.
    #[error("{0}")]
    File(String),
    /// The generated automaton does not build or solve: a bug.
    #[error("internal error in the pattern generator (please report): {0}")]
    Internal(String),
}

fn internal(e: impl std::fmt::Display) -> PatternError {
    PatternError::Internal(e.to_string())
}

impl Pattern {
    /// A pattern from its parts as the command line gives them: a split
    /// `K[xL]` and a mask of 0s and 1s (`None`: every sub-cell kept).
    ///
    /// # Errors
    /// A split that does not fit the cell, a mask of the wrong length or
    /// keeping nothing, a degree other than 2, 3 or 4.
    pub fn parse(cell: PatternCell, split: &str, keep: Option<&str>, degree: usize) -> Result<Pattern, PatternError> {
        Pattern::parse_in(cell, split, keep, degree, Basis::Bezier)
    }

    /// [`Pattern::parse`] in `basis`.
    ///
    /// # Errors
    /// As [`Pattern::parse`]; a B-spline basis for another cell than a hexahedron.
    pub fn parse_in(
        cell: PatternCell,
        split: &str,
        keep: Option<&str>,
        degree: usize,
        basis: Basis,
    ) -> Result<Pattern, PatternError> {
        let parts: Vec<usize> = split.split('x').map(|t| t.trim().parse().unwrap_or(0)).collect();
        let keep = match keep {
            None => vec![true; cell.cells(&parts).max(1)],
            Some(bits) => bits
                .chars()
                .filter(|c| !c.is_whitespace() && *c != '_')
                .map(|c| match c {
                    '1' => Ok(true),
                    '0' => Ok(false),
                    _ => Err(PatternError::MaskText(bits.to_string())),
                })
                .collect::<Result<_, _>>()?,
        };
        let pattern = Pattern { cell, split: parts, keep, degree, basis, at: Vec::new() };
        pattern.check()?;
        Ok(pattern)
    }

    /// A pattern from a pattern file's text (TOML): `cell` (`segment`, `quad`,
    /// `triangle`), `split` (`"3x3"` or `[3, 3]`), `keep` (`"111101111"`, or
    /// rows of 0s and 1s listed u fastest: `["111", "101", "111"]`; all kept
    /// when left out), `degree` (2 when left out) and `name` (optional). The
    /// name is returned with the pattern (`"pattern"` when none).
    ///
    /// ```
    /// use bcifs::schemes::Pattern;
    /// let text = "cell = \"quad\"\nsplit = [3, 3]\nkeep = [\"111\", \"101\", \"111\"]\nname = \"carpet\"\n";
    /// let (pattern, name) = Pattern::from_toml(text, "carpet.toml")?;
    /// assert_eq!((pattern.mask().as_str(), name.as_str()), ("111101111", "carpet"));
    /// # Ok::<(), bcifs::schemes::PatternError>(())
    /// ```
    ///
    /// # Errors
    /// [`PatternError::File`] with `file:line:column` for text that is not
    /// such a file; then as [`Pattern::parse`].
    pub fn from_toml(text: &str, file: &str) -> Result<(Pattern, String), PatternError> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct PatternFile {
            cell: String,
            split: Split,
            keep: Option<Keep>,
            degree: Option<usize>,
            name: Option<String>,
            at: Option<String>,
            basis: Option<String>,
        }
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Split {
            Text(String),
            One(usize),
            Parts(Vec<usize>),
        }
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Keep {
            Text(String),
            Rows(Vec<String>),
        }
        let f: PatternFile = toml::from_str(text).map_err(|e| {
            let at = e.span().map(|s| crate::format::Source { file, text }.position(s.start));
            let place = at.map_or(String::new(), |(l, c)| format!(":{l}:{c}"));
            PatternError::File(format!("{file}{place}: {}", e.message()))
        })?;
        let cell = PatternCell::named(&f.cell).ok_or_else(|| {
            PatternError::File(format!(
                "{file}: cell `{}`: expected segment, quad, triangle, hexahedron or tetrahedron",
                f.cell
            ))
        })?;
        let split = match f.split {
            Split::Text(t) => t,
            Split::One(k) => k.to_string(),
            Split::Parts(ks) => ks.iter().map(ToString::to_string).collect::<Vec<_>>().join("x"),
        };
        let keep = f.keep.map(|k| match k {
            Keep::Text(t) => t,
            Keep::Rows(rows) => rows.concat(),
        });
        let basis = match &f.basis {
            None => Basis::Bezier,
            Some(basis) => Basis::named(basis)
                .ok_or_else(|| PatternError::File(format!("{file}: basis `{basis}`: expected bezier or bspline")))?,
        };
        let mut pattern = Pattern::parse_in(cell, &split, keep.as_deref(), f.degree.unwrap_or(2), basis)?;
        if let Some(at) = &f.at {
            pattern = pattern.with_at(at)?;
        }
        Ok((pattern, f.name.unwrap_or_else(|| "pattern".into())))
    }

    /// A pattern file read from `path` ([`Pattern::from_toml`]).
    ///
    /// # Errors
    /// A file that cannot be read (or is larger than a text file may be), then as [`Pattern::from_toml`].
    pub fn read(path: &std::path::Path) -> Result<(Pattern, String), PatternError> {
        let text = crate::input::read_text(path, crate::input::TEXT_FILE_LIMIT)
            .map_err(|e| PatternError::File(format!("cannot read {}: {e}", path.display())))?;
        Pattern::from_toml(&text, &path.display().to_string())
    }

    /// The pattern file of this pattern (what [`Pattern::from_toml`] reads).
    pub fn to_toml(&self, name: &str) -> String {
        let split = self.split.iter().map(ToString::to_string).collect::<Vec<_>>().join("x");
        let mut at = if self.at.is_empty() { String::new() } else { format!("at = {:?}\n", self.at_text()) };
        if self.basis != Basis::Bezier {
            at += &format!("basis = {:?}\n", self.basis.name());
        }
        format!(
            "# A subdivision pattern: `bcifs new pattern --from FILE` prints its automaton.\nname = {name:?}\ncell = {:?}\nsplit = {split:?}\nkeep = {:?}\ndegree = {}\n{at}",
            self.cell.name(),
            self.mask(),
            self.degree
        )
    }

    /// The split points as written (`2/5,3/5`).
    pub fn at_text(&self) -> String {
        self.at.iter().map(ToString::to_string).collect::<Vec<_>>().join(",")
    }

    /// The same pattern, its classical member split at the points `at`
    /// (`"2/5,3/5"`: the inner split points of every direction, exact).
    ///
    /// # Errors
    /// [`PatternError::At`]: not numbers, not increasing inside `(0, 1)`, not `k − 1` of them.
    pub fn with_at(mut self, at: &str) -> Result<Pattern, PatternError> {
        let bad = || PatternError::At(at.to_string());
        let points: Vec<BigRational> = at
            .split(',')
            .map(|t| t.trim().parse::<Num>().ok().and_then(|n| n.as_rational()).ok_or_else(bad))
            .collect::<Result<_, _>>()?;
        let zero = BigRational::from_integer(0.into());
        let inside = points.iter().all(|p| *p > zero && *p < BigRational::one());
        let increasing = points.windows(2).all(|w| w[0] < w[1]);
        let corners_only = matches!(self.cell, PatternCell::Triangle | PatternCell::Tetrahedron);
        if corners_only || !inside || !increasing || self.split.iter().any(|&k| k != points.len() + 1) {
            return Err(bad());
        }
        self.at = points;
        self.check()?;
        Ok(self)
    }

    /// Checks the pattern before anything is generated.
    ///
    /// # Errors
    /// As [`Pattern::parse`].
    pub fn check(&self) -> Result<(), PatternError> {
        let dimension = self.cell.dimension();
        if self.split.len() != dimension || self.split.iter().any(|&k| !(2..=64).contains(&k)) {
            let expected = ["K", "KxL", "KxLxM"][dimension - 1];
            return Err(PatternError::Split { cell: self.cell.name(), dimension, expected, got: self.split.clone() });
        }
        let cells = self.cell.cells(&self.split);
        if self.keep.len() != cells {
            let split = self.split.iter().map(ToString::to_string).collect::<Vec<_>>().join("x");
            return Err(PatternError::Mask { got: self.keep.len(), expected: cells, split });
        }
        if !self.keep.iter().any(|&k| k) {
            return Err(PatternError::Empty);
        }
        if !(2..=4).contains(&self.degree) || (self.cell == PatternCell::Tetrahedron && self.degree != 2) {
            return Err(PatternError::Degree(self.degree));
        }
        if self.cell == PatternCell::Tetrahedron && self.split != [2] {
            return Err(PatternError::Split {
                cell: "tetrahedron",
                dimension: 1,
                expected: "2",
                got: self.split.clone(),
            });
        }
        let d = self.degree;
        let kept = self.keep.iter().filter(|&&k| k).count();
        if self.basis == Basis::BSpline {
            return self.check_bspline();
        }
        let unknowns = match self.cell {
            // The kept volumes, the three faces' and edges' parts, the vertex.
            PatternCell::Hexahedron => {
                let [k, l, m] = [self.split[0], self.split[1], self.split[2]];
                kept * d.pow(6) + (k * l + k * m + l * m) * d.pow(4) + (k + l + m) * d * d + 1
            }
            PatternCell::Triangle => kept * (d * (d + 1) / 2).pow(2) + self.split[0] * d * d + 1,
            _ => kept * d.pow(2 * dimension as u32) + self.split.iter().sum::<usize>() * d * d + 1,
        };
        if unknowns > crate::design::MAX_UNKNOWNS {
            return Err(PatternError::TooLarge { unknowns, max: crate::design::MAX_UNKNOWNS });
        }
        Ok(())
    }

    /// A B-spline pattern: a hexahedron, uniform split points, its matrices' entries within bounds.
    fn check_bspline(&self) -> Result<(), PatternError> {
        if self.cell != PatternCell::Hexahedron {
            return Err(PatternError::Basis(format!(
                "a B-spline basis is for hexahedra (the {} pattern has Bézier grids; a bicubic B-spline surface is the `bicubic` preset)",
                self.cell.name()
            )));
        }
        if !self.at.is_empty() {
            return Err(PatternError::Basis(
                "a uniform B-spline splits at uniform points: split points (`at`) are for Bézier grids".into(),
            ));
        }
        let (d, kept) = (self.degree, self.keep.iter().filter(|&&k| k).count());
        let k = d - 1;
        let [a, b, c] = [self.split[0], self.split[1], self.split[2]];
        let side = |n: usize| n * d * d * k;
        let entries = kept * d.pow(6) + (a * b + a * c + b * c) * side(1).pow(2) + (a + b + c) * (d * k * k).pow(2);
        if entries > MAX_FIXED_ENTRIES {
            return Err(PatternError::Basis(format!(
                "this pattern's matrices have about {entries} entries: at most {MAX_FIXED_ENTRIES} are made; lower the degree or the split"
            )));
        }
        Ok(())
    }

    /// The kept sub-cells' grid positions `[i, j]` (j = 0 for a segment).
    pub fn kept(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        let k = self.split[0];
        self.keep.iter().enumerate().filter(|(_, kept)| **kept).map(move |(n, _)| [n % k, n / k])
    }

    fn is_kept(&self, i: usize, j: usize) -> bool {
        let k = self.split[0];
        let l = self.split.get(1).copied().unwrap_or(1);
        i < k && j < l && self.keep[j * k + i]
    }

    /// The mask as written (`111101111`).
    pub fn mask(&self) -> String {
        self.keep.iter().map(|&k| if k { '1' } else { '0' }).collect()
    }

    /// The automaton of the pattern, with a model on the unit cell.
    ///
    /// ```
    /// use bcifs::schemes::{Pattern, PatternCell, pattern_design};
    /// let cantor = Pattern::parse(PatternCell::Segment, "3", Some("101"), 2)?;
    /// let design = pattern_design(&cantor, "cantor")?;
    /// let family = bcifs::solve(&design).unwrap();
    /// assert_eq!(family.parameter_names(), ["a", "b"]); // where the two kept thirds end and start
    /// # Ok::<(), bcifs::schemes::PatternError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Pattern::check`]; [`PatternError::Internal`] for a bug.
    pub fn design(&self, name: &str) -> Result<Design, PatternError> {
        pattern_design(self, name)
    }
}

/// The name of the sub-cell at `[i, j]`'s subdivision arrow.
fn sub(cell: PatternCell, [i, j]: [usize; 2]) -> String {
    match cell {
        PatternCell::Segment => format!("T{i}"),
        PatternCell::Quad => format!("T{i}_{j}"),
        PatternCell::Triangle | PatternCell::Hexahedron | PatternCell::Tetrahedron => {
            super::pattern_triangle::cell_name([i, j])
        }
    }
}

/// The automaton of `pattern` named `name`: see [`Pattern::design`].
///
/// # Errors
/// As [`Pattern::check`].
pub fn pattern_design(pattern: &Pattern, name: &str) -> Result<Design, PatternError> {
    pattern.check()?;
    let mut b = Design::builder(name);
    let d = pattern.degree;
    let split = pattern.split.iter().map(ToString::to_string).collect::<Vec<_>>().join("x");
    let kept = pattern.kept().count();
    b.description(format!(
        "{} pattern {split}, mask {}, {d} control points per direction{} ({kept} of {} sub-cells kept)",
        pattern.cell.name(),
        pattern.mask(),
        match pattern.basis {
            Basis::Bezier => String::new(),
            Basis::BSpline => format!(", the uniform B-spline of degree {}", d - 1),
        },
        pattern.keep.len()
    ))
    .doc(format!(
        "Generated by {}: every state,\n\
         arrow and constraint below follows from the pattern (the sub-cells kept, {}).",
        command_line(pattern, &split),
        match pattern.cell {
            PatternCell::Segment => "left to right",
            PatternCell::Quad => "u fastest then v",
            PatternCell::Triangle => "row by row from side AB",
            PatternCell::Hexahedron => "u fastest, then v, then w",
            PatternCell::Tetrahedron => "one per corner",
        }
    ));
    match pattern.cell {
        PatternCell::Segment => segment(&mut b, pattern),
        PatternCell::Quad => quad(&mut b, pattern),
        PatternCell::Triangle => super::pattern_triangle::triangle(&mut b, pattern.split[0], &pattern.keep, d),
        PatternCell::Hexahedron => {
            let layers = match pattern.basis {
                Basis::Bezier => super::pattern_volume::Layers::bezier(d),
                Basis::BSpline => super::pattern_volume::Layers::bspline(d, &pattern.split).map_err(internal)?,
            };
            super::pattern_volume::hexahedron(&mut b, &pattern.split, &pattern.keep, &layers);
        }
        PatternCell::Tetrahedron => super::pattern_volume::tetrahedron(&mut b, &pattern.keep),
    }
    parameters(&mut b, pattern)?;
    b.build().map_err(internal)
}

/// The command that makes `pattern`'s automaton, quoted (`split` as written).
fn command_line(pattern: &Pattern, split: &str) -> String {
    let (cell, mask, d, at, basis) =
        (pattern.cell.name(), pattern.mask(), pattern.degree, pattern.at_text(), pattern.basis.name());
    match (at.is_empty(), pattern.basis) {
        (true, Basis::Bezier) => {
            format!("`bcifs new pattern --cell {cell} --split {split} --keep {mask} --degree {d}`")
        }
        (false, Basis::Bezier) => {
            format!("`bcifs new pattern --cell {cell} --split {split} --keep {mask} --degree {d} --at {at}`")
        }
        // A B-spline pattern splits uniformly: no split points.
        _ => format!("`bcifs new pattern --cell {cell} --split {split} --keep {mask} --degree {d} --basis {basis}`"),
    }
}

/// The states, arrows and constraints of a segment pattern.
fn segment(b: &mut DesignBuilder, p: &Pattern) {
    let (d, k) = (p.degree, p.split[0]);
    b.state("e", d, CellKind::Edge).patch(Patch::Bezier).doc(format!("The segment: {d} control points."));
    b.state("v", 1, CellKind::Vertex).doc("An end: one control point.");
    for [i, _] in p.kept() {
        b.unknown(sub(p.cell, [i, 0]), "e", "e").doc(format!("Part {i} of {k}, from the left."));
    }
    b.unknown("Tv", "v", "v").doc("Subdivision of an end.");
    b.select("b0", "e", "v", [0]).doc("The left end: the first control point.");
    b.select("b1", "e", "v", [d - 1]).doc("The right end: the last control point.");
    for i in 0..k.saturating_sub(1) {
        if p.is_kept(i, 0) && p.is_kept(i + 1, 0) {
            b.adjacency(format!("T{i} b1 = T{} b0", i + 1)).explain(format!("Parts {i} and {} share an end.", i + 1));
        }
    }
    if p.is_kept(0, 0) {
        b.incidence("T0 b0 = b0 Tv").explain("The first part starts where the segment starts.");
    }
    if p.is_kept(k - 1, 0) {
        b.incidence(format!("T{} b1 = b1 Tv", k - 1)).explain("The last part ends where the segment ends.");
    }
    let points: Vec<Vec<f64>> = (0..d).map(|i| vec![i as f64 / (d - 1) as f64, 0.0]).collect();
    b.model(Model::new("e", points).with_layout(Layout::Single)).doc("The unit segment.");
}

/// The states, arrows and constraints of a quadrilateral pattern.
fn quad(b: &mut DesignBuilder, p: &Pattern) {
    let (d, k, l) = (p.degree, p.split[0], p.split[1]);
    b.state("face", d * d, CellKind::Face)
        .patch(Patch::Bezier)
        .doc(format!("The quadrilateral: {d}×{d} control points, index {d}·row + col."));
    b.state("edge_u", d, CellKind::Edge).patch(Patch::Bezier).doc(format!("A side along u: {d} control points."));
    b.state("edge_v", d, CellKind::Edge).patch(Patch::Bezier).doc(format!("A side along v: {d} control points."));
    b.state("vertex", 1, CellKind::Vertex).doc("A corner: one control point.");
    for [i, j] in p.kept() {
        b.unknown(sub(p.cell, [i, j]), "face", "face").doc(format!("Sub-cell ({i}, {j}) of {k}×{l}."));
    }
    for i in 0..k {
        b.unknown(format!("U{i}"), "edge_u", "edge_u").doc(format!("Part {i} of {k} of a side along u."));
    }
    for j in 0..l {
        b.unknown(format!("V{j}"), "edge_v", "edge_v").doc(format!("Part {j} of {l} of a side along v."));
    }
    b.unknown("W", "vertex", "vertex").doc("Subdivision of a corner.");
    b.select("bottom", "face", "edge_u", (0..d).collect::<Vec<_>>()).doc("The bottom side: row 0.");
    b.select("top", "face", "edge_u", (0..d).map(|c| d * (d - 1) + c).collect::<Vec<_>>())
        .doc("The top side: the last row.");
    b.select("left", "face", "edge_v", (0..d).map(|r| d * r).collect::<Vec<_>>()).doc("The left side: column 0.");
    b.select("right", "face", "edge_v", (0..d).map(|r| d * r + d - 1).collect::<Vec<_>>())
        .doc("The right side: the last column.");
    b.select("u_start", "edge_u", "vertex", [0]).select("u_end", "edge_u", "vertex", [d - 1]);
    b.select("v_start", "edge_v", "vertex", [0]).select("v_end", "edge_v", "vertex", [d - 1]);
    b.doc("The ends of the sides: their first and last control points.");
    quad_constraints(b, p);
    // The unit square, its inner control points lifted: a curved patch.
    let points: Vec<Vec<f64>> = (0..d * d)
        .map(|n| {
            let (r, c) = (n / d, n % d);
            let (u, v) = (c as f64 / (d - 1) as f64, r as f64 / (d - 1) as f64);
            let inner = r > 0 && r < d - 1 && c > 0 && c < d - 1;
            vec![u, v, if inner { 0.5 } else { 0.0 }]
        })
        .collect();
    b.model(Model::new("face", points).with_layout(Layout::Single))
        .doc("The unit square, its inner control points raised: a curved patch.");
}

/// The constraints of a quadrilateral pattern: neighbours share sides (or,
/// touching only at a corner, that corner), the sides of the sub-cells on
/// the border are the subdivided sides, and the sides' parts share ends.
fn quad_constraints(b: &mut DesignBuilder, p: &Pattern) {
    let (k, l) = (p.split[0], p.split[1]);
    let t = |i, j| sub(p.cell, [i, j]);
    for [i, j] in p.kept() {
        if p.is_kept(i + 1, j) {
            b.adjacency(format!("{} right = {} left", t(i, j), t(i + 1, j)))
                .explain(format!("({i}, {j}) and ({}, {j}) share a side.", i + 1));
        }
        if p.is_kept(i, j + 1) {
            b.adjacency(format!("{} top = {} bottom", t(i, j), t(i, j + 1)))
                .explain(format!("({i}, {j}) and ({i}, {}) share a side.", j + 1));
        }
        // Diagonal neighbours with neither common neighbour kept touch at one corner: a pinch.
        if p.is_kept(i + 1, j + 1) && !p.is_kept(i + 1, j) && !p.is_kept(i, j + 1) {
            b.adjacency(format!("{} right v_end = {} left v_start", t(i, j), t(i + 1, j + 1))).explain(format!(
                "({i}, {j}) and ({}, {}) touch at one corner only (a pinch).",
                i + 1,
                j + 1
            ));
        }
        if i > 0 && p.is_kept(i - 1, j + 1) && !p.is_kept(i - 1, j) && !p.is_kept(i, j + 1) {
            b.adjacency(format!("{} left v_end = {} right v_start", t(i, j), t(i - 1, j + 1))).explain(format!(
                "({i}, {j}) and ({}, {}) touch at one corner only (a pinch).",
                i - 1,
                j + 1
            ));
        }
    }
    for [i, j] in p.kept() {
        if j == 0 {
            b.incidence(format!("{} bottom = bottom U{i}", t(i, j)))
                .explain(format!("({i}, 0) lies on the bottom side."));
        }
        if j == l - 1 {
            b.incidence(format!("{} top = top U{i}", t(i, j))).explain(format!("({i}, {j}) lies on the top side."));
        }
        if i == 0 {
            b.incidence(format!("{} left = left V{j}", t(i, j))).explain(format!("(0, {j}) lies on the left side."));
        }
        if i == k - 1 {
            b.incidence(format!("{} right = right V{j}", t(i, j)))
                .explain(format!("({i}, {j}) lies on the right side."));
        }
    }
    for i in 0..k - 1 {
        b.adjacency(format!("U{i} u_end = U{} u_start", i + 1));
    }
    for j in 0..l - 1 {
        b.adjacency(format!("V{j} v_end = V{} v_start", j + 1));
    }
    b.incidence("U0 u_start = u_start W").incidence(format!("U{} u_end = u_end W", k - 1));
    b.incidence("V0 v_start = v_start W").incidence(format!("V{} v_end = v_end W", l - 1));
    b.doc("The parts of a side share their ends; the first and last parts end at the subdivided corners.");
}

/// The free entries of the solved structure, named `a, b, …` (or `p1, p2, …`),
/// with the classical member's values as defaults.
fn parameters(b: &mut DesignBuilder, p: &Pattern) -> Result<(), PatternError> {
    let free = super::topology::free_entries(b).map_err(PatternError::Internal)?;
    if free.is_empty() {
        return Ok(());
    }
    for (name, arrow, r, c) in &free {
        b.name_entry(name.clone(), format!("{arrow}[{r}][{c}]"));
        b.default_value(name, Num::rational(classical(p, arrow, *r, *c)));
    }
    b.doc(format!(
        "{} free parameters (where the sub-cells' control points sit); the defaults are the classical\n\
         member: the polynomial cell of degree {} subdivided at the uniform split points.",
        free.len(),
        p.degree - 1
    ));
    Ok(())
}

/// The classical member's matrix of part `i` of `n` along a direction: at
/// the pattern's split points, or uniform.
fn part_at(p: &Pattern, n: usize, i: usize) -> Vec<Vec<BigRational>> {
    if p.at.len() + 1 != n {
        return bezier_part(p.degree, i, n);
    }
    let zero = BigRational::from_integer(0.into());
    let point = |k: usize| match k {
        0 => zero.clone(),
        k if k == n => BigRational::one(),
        k => p.at[k - 1].clone(),
    };
    super::blossom::bezier_between(p.degree, &point(i), &point(i + 1))
}

/// Entry `(r, c)` of the classical member's matrix of `arrow`: de Casteljau's
/// subdivision of the polynomial cell at the uniform split points.
fn classical(p: &Pattern, arrow: &str, r: usize, c: usize) -> BigRational {
    match p.cell {
        PatternCell::Triangle => return super::pattern_triangle::classical(p.split[0], p.degree, arrow, r, c),
        PatternCell::Hexahedron => {
            return super::pattern_volume::classical(&p.split, arrow, r, c, &|n, i| part_at(p, n, i));
        }
        PatternCell::Tetrahedron => return super::pattern_volume::corner_classical(arrow, r, c),
        _ => {}
    }
    let d = p.degree;
    let part = |n: usize, i: usize| part_at(p, n, i);
    let index = |text: &str| text.parse::<usize>().unwrap_or(0);
    if let Some(rest) = arrow.strip_prefix('U') {
        return part(p.split[0], index(rest))[r][c].clone();
    }
    if let Some(rest) = arrow.strip_prefix('V') {
        return part(p.split[p.split.len() - 1], index(rest))[r][c].clone();
    }
    let Some(rest) = arrow.strip_prefix('T').filter(|r| !r.is_empty() && *r != "v") else {
        return BigRational::one();
    };
    match p.cell {
        PatternCell::Segment | PatternCell::Triangle | PatternCell::Tetrahedron | PatternCell::Hexahedron => {
            part(p.split[0], index(rest))[r][c].clone()
        }
        PatternCell::Quad => {
            let (i, j) = rest.split_once('_').map_or((0, 0), |(i, j)| (index(i), index(j)));
            let (tu, tv) = (part(p.split[0], i), part(p.split[1], j));
            tv[r / d][c / d].clone() * tu[r % d][c % d].clone()
        }
    }
}
