//! `bcifs solve`, `check` and `new`: families, verification, generated topologies.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use clap::Subcommand;

use bcifs::render::SolveError;
use bcifs::render::{DEFAULT_CHECK_TOLERANCE, check};
use bcifs::render::{curve, quad_patch};

use crate::cli::common::{load, parse_params};

#[derive(Subcommand)]
pub enum Topology {
    /// An edge bounded by two vertices.
    Curve {
        /// Control points of the edge.
        #[arg(long, default_value_t = 3)]
        points: usize,
        /// Control points of a vertex (the first/last points of the edge).
        #[arg(long, default_value_t = 2)]
        vertex: usize,
        /// Number of sub-edges.
        #[arg(long, default_value_t = 2)]
        arity: usize,
    },
    /// The quad patch: 3×3 face, 2×2 sub-faces, edges along u and v, 2×2 vertex.
    QuadPatch {
        /// Use the rotationally symmetric vertex rule (3 parameters).
        #[arg(long)]
        symmetric: bool,
    },
    /// A subdivision pattern: a cell split into a grid, some sub-cells kept and the others holes
    /// (the Cantor set, laces such as the Sierpiński carpet); every state, arrow and constraint generated
    Pattern {
        /// A pattern file (TOML: cell, split, keep, degree, name) instead of the flags below.
        #[arg(long, conflicts_with_all = ["cell", "split", "keep", "degree", "name", "at", "basis"])]
        from: Option<std::path::PathBuf>,
        /// Print the pattern file of the flags instead of the automaton.
        #[arg(long)]
        file: bool,
        /// The cell: segment, quad, triangle, hexahedron or tetrahedron.
        #[arg(long, default_value = "quad")]
        cell: String,
        /// Parts along each direction: K for a segment or a triangle (K-ary: K² triangles), KxL for a quad,
        /// KxLxM for a hexahedron, 2 for a tetrahedron (its four corner tetrahedra).
        #[arg(long, default_value = "3x3")]
        split: String,
        /// One 0 or 1 per sub-cell, u fastest, then v, then w (default: all kept); the carpet is 111101111.
        #[arg(long)]
        keep: Option<String>,
        /// Control points per direction: 2 (linear), 3 (quadratic) or 4 (cubic).
        #[arg(long, default_value_t = 2)]
        degree: usize,
        /// Where the default member splits each direction: its K − 1 inner points (default uniform);
        /// `2/5,3/5` with the Menger mask makes a Jerusalem-cube-like sponge.
        #[arg(long, value_name = "POINTS")]
        at: Option<String>,
        /// How the cells carry their control points: bezier (grids whose matrices are unknowns: a
        /// family) or bspline (a hexahedron's uniform B-spline: fixed matrices, the shape set by the
        /// control lattice; `--degree 4` is the tricubic B-spline volume).
        #[arg(long, default_value = "bezier")]
        basis: String,
        /// The design's name.
        #[arg(long, default_value = "pattern")]
        name: String,
    },
    /// A lacunar polygon whose topology is a polyhedron's circle packing (the 2025 CAGD paper's way):
    /// the gap of one face made of copies of every other face's, a hole for every vertex off it
    Polyhedron {
        /// A polyhedron: tetrahedron, cube, octahedron, dodecahedron, icosahedron, prism, pyramid,
        /// or an OBJ or OFF file (its faces, oriented alike, a sphere).
        polyhedron: String,
        /// The face whose gap is the polygon.
        #[arg(long, default_value_t = 0)]
        face: usize,
        /// The design's name (default: the polyhedron's, `_lace` added).
        #[arg(long)]
        name: Option<String>,
    },
}

/// A design the command uses until it ends: its memory (each matrix as
/// written and as affine forms, and its solved family) goes back to the
/// system with the process instead of entry by entry (14 ms of `check`'s
/// 0.33 s on Suzanne's 430,000 entries).
fn kept_to_the_end(design: bcifs::render::Design) -> std::mem::ManuallyDrop<bcifs::render::Design> {
    std::mem::ManuallyDrop::new(design)
}

pub fn run_solve(out: &mut String, file: &str, as_json: bool) -> Result<u8> {
    let design = kept_to_the_end(load(file)?);
    let name = design.name().to_string();
    if as_json {
        let report = bcifs::render::solve_report(&design).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        writeln!(out, "{}", serde_json::to_string_pretty(&report)?)?;
        return Ok(if report.consistent { 0 } else { 1 });
    }
    match bcifs::render::solution(&design).as_ref() {
        Ok(family) => {
            writeln!(out, "{name}: {}", free_parameters(&family.parameter_names()))?;
            writeln!(out, "({})", system_summary(family))?;
            out.push_str(&family.matrices_report());
            Ok(0)
        }
        Err(SolveError::Inconsistent { conflicts }) => {
            writeln!(out, "{name}: the constraints are inconsistent; these equations conflict:")?;
            for c in conflicts {
                writeln!(out, "  {c}")?;
            }
            Ok(1)
        }
        Err(e) => bail!("{name}: {e}"),
    }
}

/// `no free parameter`, `1 free parameter: a`, `2 free parameters: a, b`.
fn free_parameters(names: &[String]) -> String {
    match names.len() {
        0 => "no free parameter (every entry is fixed)".into(),
        1 => format!("1 free parameter: {}", names[0]),
        n => format!("{n} free parameters: {}", names.join(", ")),
    }
}

/// What the solver was given and kept: `3 constraints: 26 scalar equations, rank 20; 4 more hold
/// whatever the parameters` (column sums included).
fn system_summary(family: &bcifs::render::Family) -> String {
    let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let constraints = plural(family.constraints, "constraint", "constraints");
    if family.equations == 0 {
        return format!(
            "{constraints} and the column sums: all {} hold whatever the parameters; nothing to solve",
            plural(family.identities, "scalar equation", "scalar equations")
        );
    }
    let mut s = format!(
        "{constraints} and the column sums: {}, rank {}",
        plural(family.equations, "scalar equation", "scalar equations"),
        family.rank
    );
    if family.identities > 0 {
        s += &format!("; {} more hold whatever the parameters", family.identities);
    }
    s
}

pub fn run_check(out: &mut String, file: &str, params: &[String], as_json: bool) -> Result<u8> {
    let design = kept_to_the_end(load(file)?);
    let values = parse_params(params)?;
    let instance =
        bcifs::render::instantiate(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    let report = check(&instance.automaton, &instance.values, DEFAULT_CHECK_TOLERANCE)?;
    if as_json {
        let json =
            bcifs::render::check_report(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
        writeln!(out, "{}", serde_json::to_string_pretty(&json)?)?;
    } else {
        let p: Vec<String> = instance.parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        writeln!(out, "{}: {}", design.name(), if p.is_empty() { "no free parameter".into() } else { p.join(", ") })?;
        for (e, r) in &report.constraints {
            let mark = if *r <= DEFAULT_CHECK_TOLERANCE { "ok  " } else { "FAIL" };
            writeln!(out, "  {mark} {e}   (residual {r:.3e})")?;
        }
        let rounding = report.rounding.as_ref().map(|(arrow, column, magnitude)| {
            format!(
                "arrow `{arrow}`, column {column}: entries of magnitude {magnitude:e}, whose sum of 1 is lost to rounding in floating point"
            )
        });
        match &rounding {
            None => writeln!(out, "  column sums: max error {:.3e}", report.max_column_sum_error)?,
            Some(why) => writeln!(out, "  column sums: not decided ({why})")?,
        }
        for (n, eig) in &report.spectra {
            if eig.is_empty() || eig.iter().any(|l| !(l.re.is_finite() && l.im.is_finite())) {
                writeln!(out, "  spectrum of {n}: not computed (the entries overflow floating point)")?;
                continue;
            }
            let list: Vec<String> = eig
                .iter()
                .map(|l| {
                    // Six decimals, or six significant digits past a million.
                    let x = |v: f64| if v.abs() < 1e6 { format!("{v:.6}") } else { format!("{v:.6e}") };
                    if l.im.abs() < bcifs::render::DEGENERATE {
                        x(l.re)
                    } else {
                        format!("{}{}{}i", x(l.re), if l.im < 0.0 { "-" } else { "+" }, x(l.im.abs()))
                    }
                })
                .collect();
            writeln!(out, "  spectrum of {n}: {}", list.join(", "))?;
        }
        writeln!(
            out,
            "  per-matrix condition (Sokolov et al. 2010 §3, necessary only): {}",
            if report.contractive { "holds" } else { "fails" }
        )?;
        match &report.jsr {
            Some(j) => writeln!(out, "  {j}")?,
            None => writeln!(out, "  JSR: not defined (a subdivision matrix is not column-stochastic)")?,
        }
        let verdict = match (report.converges, &report.jsr) {
            (Some(true), _) => "converges (the upper bound is below 1)",
            (Some(false), _) => "DIVERGES (the lower bound is at least 1)",
            (None, Some(_)) => "undecided (the bounds straddle 1)",
            (None, None) => "not decided (no JSR bounds without column-stochastic matrices)",
        };
        writeln!(out, "  convergence: {verdict}")?;
        match (&rounding, report.ok) {
            (Some(why), _) => writeln!(out, "FAILED: these parameters cannot be evaluated in floating point ({why})")?,
            (None, true) => writeln!(out, "ok")?,
            (None, false) => writeln!(out, "FAILED: some constraints do not hold")?,
        }
    }
    Ok(if report.ok && report.rounding.is_none() && report.converges != Some(false) { 0 } else { 1 })
}

/// Prints the automaton file of a generated topology.
pub fn run_new(out: &mut String, topology: Topology) -> Result<u8> {
    let design = match topology {
        Topology::Curve { points, vertex, arity } => curve(points, vertex, arity)?,
        Topology::QuadPatch { symmetric } => quad_patch(symmetric)?,
        Topology::Pattern { from, file, cell, split, keep, degree, name, at, basis } => {
            let (pattern, name) = match from {
                Some(path) => bcifs::render::Pattern::read(&path)?,
                None => {
                    let cell = bcifs::render::PatternCell::named(&cell).ok_or_else(|| {
                        anyhow::anyhow!("--cell `{cell}`: expected segment, quad, triangle, hexahedron or tetrahedron")
                    })?;
                    let named = bcifs::render::Basis::named(&basis)
                        .ok_or_else(|| anyhow::anyhow!("--basis `{basis}`: expected bezier or bspline"))?;
                    let pattern = bcifs::render::Pattern::parse_in(cell, &split, keep.as_deref(), degree, named)?;
                    (if let Some(at) = &at { pattern.with_at(at)? } else { pattern }, name)
                }
            };
            if file {
                out.push_str(&pattern.to_toml(&name));
                return Ok(0);
            }
            let design = pattern.design(&name)?;
            pattern_warnings(&design);
            design
        }
        Topology::Polyhedron { polyhedron, face, name } => {
            let p = bcifs::render::Polyhedron::named_or_read(&polyhedron)?;
            let name = name.unwrap_or_else(|| format!("{}_lace", p.name()));
            let design = bcifs::render::polyhedral_lace(&p, face, &name)?;
            pattern_warnings(&design);
            design
        }
    };
    out.push_str(&bcifs::render::write_design(&design));
    Ok(0)
}

/// What is legal but surprising in a pattern, said on stderr: kept sub-cells
/// that make separate pieces (the attractor not connected), or that touch at a corner only (a pinch).
fn pattern_warnings(design: &bcifs::render::Design) {
    let Ok(t) = bcifs::render::topology_report(design, &[], 1) else { return };
    if t.components > 1 {
        // The pieces are counted on the welded cells: parts that share an end, a side or a corner are one.
        let deeper = bcifs::render::topology_report(design, &[], 2)
            .map_or(String::new(), |t| format!(" ({} at depth 2)", t.components));
        eprintln!(
            "warning: the kept sub-cells make {} separate pieces{deeper}: the attractor is not connected",
            t.components
        );
    }
    if t.pinches > 0 {
        eprintln!(
            "warning: {} place(s) where kept sub-cells touch at a corner or along an edge only (a pinch): the union is not a manifold there; the meshes of solids bcifs writes split it (shells that touch without sharing a vertex)",
            t.pinches
        );
    }
}

/// `bcifs list`: the shipped automata, then the scheme presets.
pub fn run_list(out: &mut String) -> Result<u8> {
    writeln!(out, "shipped automata (bcifs render NAME, bcifs show NAME):")?;
    for (name, _) in bcifs::render::BUILTIN_AUTOMATA {
        let d = bcifs::render::builtin_design(name)
            .ok_or_else(|| anyhow::anyhow!("internal error: `{name}` does not parse"))?;
        writeln!(out, "  {name:<22} {}", d.description())?;
    }
    writeln!(out, "normal-vector presets (bcifs scheme normal --preset NAME):")?;
    for name in bcifs::render::PRESET_NAMES {
        let p = bcifs::render::normal_preset(name)?;
        writeln!(out, "  {name:<22} {}", p.description)?;
    }
    writeln!(out, "subdivision schemes as IFS (bcifs scheme ifs NAME):")?;
    for name in bcifs::render::IFS_NAMES {
        let d = bcifs::render::ifs_preset(name, None, None)?;
        writeln!(out, "  {name:<22} {}", d.description())?;
    }
    Ok(0)
}

/// `bcifs show NAME`: the embedded file of a shipped automaton, or a
/// preset's automaton printed as a file.
pub fn run_show(out: &mut String, name: &str) -> Result<u8> {
    // A shipped file as written (with its comments); a preset or figure as the library makes it.
    if let Some((_, text)) = bcifs::render::BUILTIN_AUTOMATA.iter().find(|(n, _)| *n == name) {
        out.push_str(text);
        return Ok(0);
    }
    if std::path::Path::new(name).exists() {
        bail!("`bcifs show` prints a shipped automaton or preset by name; `{name}` is a file (read it as it is)");
    }
    out.push_str(&bcifs::render::write_design(&bcifs::render::load(name)?));
    Ok(0)
}
