//! `bcifs analyze`: continuity and fractal ranges of a scheme family.

use bcifs::render::{angle_colour, dimension_colour, region_colour, sweep_image, verdict_colour};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Subcommand;

use bcifs::render::{CurveCell, Verdict};

use super::plot::{Plot, Series};

mod ternary;
use ternary::run_ternary5;

#[derive(Subcommand)]
pub enum AnalyzeCommand {
    /// A curve's differential behaviour at a parameter point (Sokolov et al. 2010 §4):
    /// convergence verdict, eigenvalues, half-tangents, junction angle, region.
    Curve {
        /// The automaton file (TOML), or the name of a shipped automaton; its
        /// model's root is an edge state with two subdivision arrows.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// A map instead of a point: regions (Fig. 8), roughness (the junction angle, Fig. 11
        /// left) or smooth (angle below --threshold, Fig. 11 right), over --x and --y.
        #[arg(long, requires_all = ["x", "y", "output"])]
        map: Option<String>,
        /// The parameter along x and its range, NAME=FROM:TO.
        #[arg(long, allow_hyphen_values = true)]
        x: Option<String>,
        /// The parameter along y and its range, NAME=FROM:TO.
        #[arg(long, allow_hyphen_values = true)]
        y: Option<String>,
        /// Pixels on a side.
        #[arg(long, default_value_t = 512)]
        size: usize,
        /// The smooth map's angle threshold in degrees.
        #[arg(long, default_value_t = 5.0)]
        threshold: f64,
        /// The map: .png, or .csv for the raw grid (x, y, verdict, region, angle).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// The blending functions F(t) of a curve in the natural parameterization, the
    /// non-singular parameterization u(t) and F in it: three panels (Sokolov et al. 2010 Fig. 9).
    Blend {
        /// The automaton file (TOML), or the name of a shipped automaton (a curve root with T0, T1).
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Subdivision depth of the samples (2^DEPTH + 1 of them).
        #[arg(long, default_value_t = 10)]
        depth: usize,
        /// The picture (PNG).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// The fractal dimension of an automaton's attractor: box counting on a
    /// deterministic evaluation (within 1/1024 of its extent), and the
    /// similarity dimension (Moran, Mauldin–Williams) when its maps are similarities.
    Dimension {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON: box_dimension, fit (r2, scales), similarity_dimension.
        #[arg(long)]
        json: bool,
    },
    /// The topology of the depth-K cells: how many, their connected components, Euler
    /// characteristic and Betti numbers (b0 components, b1 holes or loops, b2 voids), and pinches
    /// (cells meeting at a point only), on the welded cells bcifs writes.
    Topology {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Subdivision depth.
        #[arg(long, default_value_t = 3)]
        depth: usize,
        /// Print JSON: cells, dimension, vertices, edges, components, euler, betti, pinches.
        #[arg(long)]
        json: bool,
    },
    /// Porosity (the fraction of the cell the depth-k cells leave empty, per depth) and the
    /// gliding-box lacunarity curve Λ(r) (Allain & Cloitre 1991) of the depth-K cells.
    Lacunarity {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// The deepest depth (porosity at depths 1 to K, lacunarity at K); default 5, 4 for a solid.
        #[arg(long)]
        depth: Option<usize>,
        /// Print JSON: dimension, porosity (one value per depth from 1), grid, lacunarity ([r, Λ(r)] pairs).
        #[arg(long)]
        json: bool,
    },
    /// The ternary 5-point scheme with tension ω (Siddiqi et al. 2014): C0/C1/C2 bounds,
    /// polygon length growth, fractal ranges; a table and a PNG plot.
    Ternary5 {
        /// The ω interval, A B.
        #[arg(long, num_args = 2, value_names = ["A", "B"], allow_hyphen_values = true, default_values_t = [-0.1, 0.17])]
        omega_range: Vec<f64>,
        /// Number of intervals (the table has STEPS + 1 rows).
        #[arg(long, default_value_t = 54)]
        steps: usize,
        /// The plot (PNG).
        #[arg(short, long, default_value = "ternary5.png")]
        output: PathBuf,
        /// Print JSON: one object per row (omega, the bounds, the verdict), and the proven ranges.
        #[arg(long)]
        json: bool,
    },
    /// The convergence verdict over a plane of two free parameters of a
    /// family (the others at their defaults): a PNG map of where the joint
    /// spectral radius bounds prove convergence, prove divergence inside the
    /// per-matrix domain of Sokolov et al. 2010 §3, or leave it undecided.
    Map {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// The parameter along x and its range, NAME=FROM:TO.
        #[arg(long, allow_hyphen_values = true)]
        x: String,
        /// The parameter along y and its range, NAME=FROM:TO.
        #[arg(long, allow_hyphen_values = true)]
        y: String,
        /// Pixels on a side.
        #[arg(long, default_value_t = 256)]
        size: usize,
        /// What each pixel shows: verdict, region or angle (curve families:
        /// Sokolov et al. 2010 Fig. 8 and Fig. 11), dimension (box counting where it converges),
        /// porosity or lacunarity (of the depth-4 cells, where it converges).
        #[arg(long, default_value = "verdict")]
        what: String,
        /// Search the bounds with the full budget at every pixel (slower, fewer undecided pixels).
        #[arg(long)]
        thorough: bool,
        /// The map: .png, or .csv for the raw grid (x, y, value, label; the array `bcifs.sweep` returns).
        #[arg(short, long, default_value = "map.png")]
        output: PathBuf,
    },
}

/// `NAME=FROM:TO`.
fn axis(text: &str) -> Result<(String, f64, f64)> {
    let bad = || anyhow::anyhow!("`{text}`: expected NAME=FROM:TO, such as a=-1:2");
    let (name, range) = text.split_once('=').ok_or_else(bad)?;
    let (from, to) = range.split_once(':').ok_or_else(bad)?;
    let (from, to): (f64, f64) = (from.trim().parse().map_err(|_| bad())?, to.trim().parse().map_err(|_| bad())?);
    // The width too: the axes' ticks and the pixels' steps divide it.
    if !(from.is_finite() && to.is_finite() && from < to && (to - from).is_finite()) {
        bail!("`{text}`: the range needs finite FROM < TO, and TO - FROM finite");
    }
    Ok((name.trim().to_string(), from, to))
}

/// The parameter plane of two axes `NAME=FROM:TO` (two different names) and `size` pixels a side.
fn plane((x, y): (&str, &str), size: usize) -> Result<bcifs::render::ParameterPlane> {
    let (x, y) = (axis(x)?, axis(y)?);
    if x.0 == y.0 {
        bail!("--x and --y both vary `{}`: a map needs two different parameters", x.0);
    }
    Ok(bcifs::render::ParameterPlane { x, y, size: (size, size) })
}

/// Writes a map of `plane` framed with its title, axes and legend.
fn write_framed_map(
    output: &std::path::Path,
    title: &str,
    plane: &bcifs::render::ParameterPlane,
    img: &image::RgbImage,
    legend: &[([u8; 3], String)],
) -> Result<()> {
    let (x, y) = (&plane.x, &plane.y);
    let framed = super::plot::framed_map(title, (&x.0, x.1, x.2), (&y.0, y.1, y.2), img, legend)?;
    let comment = format!("{title}; {} from {} to {}; {} from {} to {}", x.0, x.1, x.2, y.0, y.1, y.2);
    let text = crate::cli::common::png_text(title, &comment);
    bcifs::render::write_png_text(output, &framed, &text).with_context(|| format!("cannot write {}", output.display()))
}

/// `bcifs analyze map`: a sweep as a picture (or CSV), and its counts.
fn run_map(
    out: &mut String,
    file: &str,
    (x, y): (&str, &str),
    size: usize,
    (what, thorough): (&str, bool),
    output: &std::path::Path,
) -> Result<u8> {
    use bcifs::render::SweepKind;
    if size == 0 || size > 4096 {
        bail!("--size must be between 1 and 4096");
    }
    let kind: SweepKind = what.parse()?;
    let design = crate::cli::common::load(file)?;
    let plane = plane((x, y), size)?;
    let started = std::time::Instant::now();
    let values = bcifs::render::sweep(&design, &plane, kind, thorough, 0..size)?;
    let ext = output.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let numbers = values.to_f64();
    let count = |code: i8| numbers.iter().filter(|&&v| v == f64::from(code)).count();
    let (title, legend) = map_legend(kind, &count);
    if ext == "csv" {
        let text = bcifs::render::sweep_csv(&plane, kind, &values);
        bcifs::render::write_atomic(output, text.as_bytes())
            .with_context(|| format!("cannot write {}", output.display()))?;
    } else {
        let img = sweep_image(kind, &values, size);
        write_framed_map(output, &format!("{}: {title}", design.name()), &plane, &img, &legend)?;
    }
    writeln!(
        out,
        "{}: {} ∈ [{}, {}] (x) × {} ∈ [{}, {}] (y), {size}×{size} pixels in {:.2} s",
        design.name(),
        plane.x.0,
        plane.x.1,
        plane.x.2,
        plane.y.0,
        plane.y.1,
        plane.y.2,
        started.elapsed().as_secs_f64()
    )?;
    map_summary(out, kind, &values, &count)?;
    writeln!(out, "map → {}", output.display())?;
    Ok(0)
}

/// A map's title and legend (a colour and its label, with the pixel counts of the verdicts).
fn map_legend(kind: bcifs::render::SweepKind, count: &dyn Fn(i8) -> usize) -> (&'static str, Vec<([u8; 3], String)>) {
    use bcifs::render::SweepKind;
    match kind {
        SweepKind::Verdict => (
            "convergence verdicts (JSR bounds)",
            vec![
                (verdict_colour(1), format!("converges ({})", count(1))),
                (verdict_colour(-1), format!("diverges, JSR ≥ 1 ({})", count(-1))),
                (verdict_colour(-2), format!("a matrix fails, §3 ({})", count(-2))),
                (verdict_colour(0), format!("undecided ({})", count(0))),
            ],
        ),
        SweepKind::Region => ("regions", curve_map_legend("regions", 0.0)),
        SweepKind::Angle => (
            "junction angle, where the halves have half-tangents",
            [0.0, 45.0, 90.0, 135.0, 180.0]
                .iter()
                .map(|a: &f64| (angle_colour(*a), format!("angle {a}°")))
                .chain([([228, 228, 228], "no half-tangents".to_string())])
                .collect(),
        ),
        SweepKind::Dimension => (
            "box-counting dimension",
            [1.0, 1.25, 1.5, 1.75, 2.0]
                .iter()
                .map(|d| (dimension_colour(*d), format!("dimension {d}")))
                .chain([(dimension_colour(f64::NAN), "not convergent".to_string())])
                .collect(),
        ),
        SweepKind::Porosity => (
            "porosity (area or length left empty at depth 4)",
            [0.0, 0.25, 0.5, 0.75, 1.0]
                .iter()
                .map(|p| (dimension_colour(1.0 + p), format!("porosity {p}")))
                .chain([(dimension_colour(f64::NAN), "not convergent".to_string())])
                .collect(),
        ),
        SweepKind::Lacunarity => (
            "lacunarity Λ(9) at depth 4",
            [1.0, 1.5, 2.0, 4.0, 8.0]
                .iter()
                .map(|l: &f64| (dimension_colour(2.0 - 1.0 / l), format!("Λ {l}")))
                .chain([(dimension_colour(f64::NAN), "not convergent".to_string())])
                .collect(),
        ),
    }
}

/// The lines under a map: its verdicts' or regions' counts, or its values' range.
fn map_summary(
    out: &mut String,
    kind: bcifs::render::SweepKind,
    values: &bcifs::render::SweepValues,
    count: &dyn Fn(i8) -> usize,
) -> Result<()> {
    use bcifs::render::{REGIONS, SweepKind, SweepValues};
    match values {
        SweepValues::Codes(_) if kind == SweepKind::Verdict => {
            writeln!(out, "  converges (green):                          {}", count(1))?;
            writeln!(out, "  diverges although each matrix passes (red):  {}", count(-1))?;
            writeln!(out, "  diverges, a matrix fails (grey):            {}", count(-2))?;
            writeln!(out, "  undecided (yellow):                         {}", count(0))?;
        }
        SweepValues::Codes(_) => {
            for (code, region) in REGIONS.iter().enumerate() {
                let n = count(code as i8);
                if n > 0 {
                    writeln!(out, "  region {region:<10} {n}")?;
                }
            }
        }
        SweepValues::Values(v) => {
            let defined: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
            let (lo, hi) = defined.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            if defined.is_empty() {
                writeln!(out, "  no pixel has a {}", kind.name())?;
            } else {
                writeln!(out, "  {} pixels with a {}, from {lo:.4} to {hi:.4}", defined.len(), kind.name())?;
            }
        }
    }
    Ok(())
}

/// Runs a `bcifs analyze` command.
pub fn run(out: &mut String, what: AnalyzeCommand) -> Result<u8> {
    match &what {
        AnalyzeCommand::Ternary5 { output, .. } => crate::cli::common::check_output(output, &["png"], &[])?,
        AnalyzeCommand::Blend { output, file, .. } => {
            crate::cli::common::check_output(output, &["png"], &[Path::new(file)])?
        }
        AnalyzeCommand::Map { output, file, .. } => {
            crate::cli::common::check_output(output, &["png", "csv"], &[Path::new(file)])?
        }
        AnalyzeCommand::Curve { output: Some(output), file, .. } => {
            crate::cli::common::check_output(output, &["png", "csv"], &[Path::new(file)])?;
        }
        _ => {}
    }
    match what {
        AnalyzeCommand::Ternary5 { omega_range, steps, output, json } => {
            run_ternary5(out, (omega_range[0], omega_range[1]), steps, &output, json)
        }
        AnalyzeCommand::Map { file, x, y, size, what, thorough, output } => {
            run_map(out, &file, (&x, &y), size, (&what, thorough), &output)
        }
        AnalyzeCommand::Dimension { file, params, json } => run_dimension(out, &file, &params, json),
        AnalyzeCommand::Topology { file, params, depth, json } => run_topology(out, &file, &params, depth, json),
        AnalyzeCommand::Lacunarity { file, params, depth, json } => run_lacunarity(out, &file, &params, depth, json),
        AnalyzeCommand::Blend { file, params, depth, output } => run_blend(out, &file, &params, depth, &output),
        AnalyzeCommand::Curve { file, params, json, map: None, .. } => run_curve(out, &file, &params, json),
        AnalyzeCommand::Curve { file, params, map: Some(kind), x, y, size, threshold, output, .. } => {
            let (x, y, output) = (x.unwrap_or_default(), y.unwrap_or_default(), output.unwrap_or_default());
            let marker = crate::cli::common::parse_params(&params)?;
            run_curve_map(out, &file, &kind, (&x, &y), (size, threshold, &marker), &output)
        }
    }
}

/// A design loaded by name or path, and a report on it at the parameters
/// `NAME=VALUE` (its errors named after the design).
fn report_on<R>(
    file: &str,
    params: &[String],
    report: impl FnOnce(&bcifs::render::Design, &[(String, f64)]) -> Result<R, bcifs::render::ReportError>,
) -> Result<(bcifs::render::Design, R)> {
    let design = crate::cli::common::load(file)?;
    let values = crate::cli::common::parse_params(params)?;
    let r = report(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    Ok((design, r))
}

/// `bcifs analyze lacunarity`.
fn run_lacunarity(out: &mut String, file: &str, params: &[String], depth: Option<usize>, as_json: bool) -> Result<u8> {
    let mut used = 0;
    let (design, l) = report_on(file, params, |d, v| {
        used = depth.unwrap_or_else(|| bcifs::render::lacunarity_depth(d));
        bcifs::render::lacunarity_report(d, v, used)
    })?;
    let depth = used;
    if as_json {
        writeln!(out, "{}", serde_json::to_string_pretty(&l)?)?;
        return Ok(0);
    }
    let what = ["length", "length", "area", "volume"][l.dimension.min(3)];
    writeln!(out, "{}: porosity (the {what} the depth-k cells leave empty)", design.name())?;
    for (k, p) in l.porosity.iter().enumerate() {
        writeln!(out, "  depth {}: {p:.6}", k + 1)?;
    }
    writeln!(out, "  lacunarity Λ(r) at depth {depth}, on a grid of {} cells a side:", l.grid)?;
    for [r, lambda] in &l.lacunarity {
        writeln!(out, "    r = {r}: {lambda:.6}")?;
    }
    Ok(0)
}

/// `bcifs analyze topology`.
fn run_topology(out: &mut String, file: &str, params: &[String], depth: usize, as_json: bool) -> Result<u8> {
    let (design, t) = report_on(file, params, |d, v| bcifs::render::topology_report(d, v, depth))?;
    if as_json {
        writeln!(out, "{}", serde_json::to_string_pretty(&t)?)?;
        return Ok(0);
    }
    let kind = ["points", "segments", "faces", "volumes"][t.dimension.min(3)];
    writeln!(
        out,
        "{} at depth {}: {} {kind}, {} vertices, {} edges",
        design.name(),
        depth,
        t.cells,
        t.vertices,
        t.edges
    )?;
    writeln!(out, "  components {}, Euler characteristic {}, Betti numbers {:?}", t.components, t.euler, t.betti)?;
    if t.pinches > 0 {
        writeln!(
            out,
            "  {} pinch(es): cells meet at a point or along an edge only there (the union is not a manifold there: a solid's mesh is written with it split, a surface's keeps the contact)",
            t.pinches
        )?;
    }
    Ok(0)
}

/// `bcifs analyze dimension`.
fn run_dimension(out: &mut String, file: &str, params: &[String], as_json: bool) -> Result<u8> {
    let (design, report) = report_on(file, params, bcifs::render::dimension_report)?;
    if as_json {
        writeln!(out, "{}", serde_json::to_string_pretty(&report.to_json())?)?;
        return Ok(0);
    }
    let bcifs::render::DimensionReport { fit, similarity, open_set, resolution, points, .. } = report;
    writeln!(out, "{}: {points} points within {resolution:.3e}", design.name())?;
    match &fit {
        Some(f) => writeln!(
            out,
            "  box-counting dimension {:.4} (r² = {:.5}, {} scales from {:.3e} to {:.3e})",
            f.dimension,
            f.r2,
            f.scales.len(),
            f.scales[0].0,
            f.scales[f.scales.len() - 1].0
        )?,
        None => writeln!(out, "  box-counting dimension: not enough scales")?,
    }
    match (similarity, &open_set) {
        (Some(s), Some(o)) if o.holds == Some(true) => {
            writeln!(out, "  similarity dimension {s:.6}: the Hausdorff dimension (open set condition: {})", o.reason)?;
        }
        (Some(s), Some(o)) => {
            let status = if o.holds == Some(false) { "fails" } else { "not known to hold" };
            writeln!(out, "  similarity dimension {s:.6}: only an upper bound of the Hausdorff dimension")?;
            writeln!(out, "  open set condition {status}: {}", o.reason)?;
        }
        (Some(s), None) => writeln!(out, "  similarity dimension {s:.6}")?,
        (None, _) => writeln!(out, "  similarity dimension: none (a map is not a similarity of modelling space)")?,
    }
    Ok(0)
}

/// `bcifs analyze curve`.
fn run_curve(out: &mut String, file: &str, params: &[String], as_json: bool) -> Result<u8> {
    let design = crate::cli::common::load(file)?;
    let values = crate::cli::common::parse_exact_params(params)?;
    let analysis =
        bcifs::render::curve_analysis(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    if as_json {
        writeln!(out, "{}", serde_json::to_string_pretty(&analysis.to_json())?)?;
    } else {
        curve_text(out, &analysis)?;
    }
    Ok(0)
}

/// `analyze curve` as text.
fn curve_text(out: &mut String, analysis: &bcifs::render::CurveAnalysis) -> Result<()> {
    let (names, report) = (&analysis.names, &analysis.report);
    let p: Vec<String> = analysis.parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
    writeln!(out, "{}: {}", analysis.automaton, p.join(", "))?;
    writeln!(out, "  converges: {}", analysis.converges.map_or("undecided".to_string(), |c| c.to_string()))?;
    for (k, name) in names.iter().enumerate() {
        let eigenvalues = match &report.eigenvalues[k] {
            Some(values) => values.iter().map(|x| format!("{x:.6}")).collect::<Vec<_>>().join(", "),
            None => "not computed (complex, or no basis of eigenvectors)".to_string(),
        };
        let subdominant = report.subdominant[k].map_or("none".to_string(), |x| format!("{x:.6}"));
        writeln!(out, "  {name}: eigenvalues {eigenvalues}; sub-dominant {subdominant}")?;
    }
    let v = |x: &[f64]| format!("({})", x.iter().map(|c| format!("{c:.6}")).collect::<Vec<_>>().join(", "));
    match (&report.half_tangents, report.junction_angle_deg) {
        (Some([s, e]), Some(angle)) => {
            if let Some([ds, de]) = &analysis.directions {
                writeln!(
                    out,
                    "  half-tangents in the model (unit directions): at the start {}, at the end {}",
                    v(ds),
                    v(de)
                )?;
                writeln!(out, "  (as barycentric weights of the control points: start {}, end {})", v(s), v(e))?;
            } else {
                writeln!(out, "  half-tangents (barycentric weights): at the start {}, at the end {}", v(s), v(e))?;
            }
            writeln!(
                out,
                "  junction angle between the halves ({} arriving, {} leaving): {angle:.4}°",
                names[0], names[1]
            )?;
        }
        _ => writeln!(out, "  no half-tangents (a leading eigenvalue is negative or tied)")?,
    }
    let region = analysis.region.unwrap_or("undecided");
    writeln!(
        out,
        "  C1 necessary condition (collinear half-tangents, Sokolov et al. 2010 §4): {}",
        report.c1_necessary
    )?;
    writeln!(
        out,
        "  region {region} of Sokolov et al. 2010 Fig. 8: {} (see the guide's curve-family tutorial)",
        bcifs::render::region_meaning(region)
    )?;
    match &analysis.exact {
        Some(e) => {
            for (k, name) in names.iter().enumerate() {
                let values: Vec<String> = e.eigenvalues[k].iter().map(ToString::to_string).collect();
                writeln!(out, "  exact {name}: eigenvalues {}", values.join(", "))?;
            }
            writeln!(out, "  (regions, ties and collinearity decided in exact arithmetic)")?;
        }
        None => writeln!(
            out,
            "  (floating point: the exact analysis needs 3×3 matrices with the eigenvalue 1 and two more real ones, at rational parameters)"
        )?,
    }
    Ok(())
}

/// The curve map as CSV: a row per cell.
fn curve_map_csv(
    plane: &bcifs::render::ParameterPlane,
    cells: &[CurveCell],
    size: usize,
    output: &std::path::Path,
) -> Result<()> {
    let mut text = format!("{},{},verdict,per_matrix,region,junction_angle_deg\n", plane.x.0, plane.y.0);
    for (i, c) in cells.iter().enumerate() {
        let (px, py) = plane.at(i % size, i / size);
        let verdict = match c.verdict {
            Verdict::Converges => "converges",
            Verdict::Diverges => "diverges",
            Verdict::Undecided => "undecided",
        };
        writeln!(
            text,
            "{px},{py},{verdict},{},{},{}",
            c.per_matrix,
            c.region().unwrap_or(""),
            c.angle().map_or(String::new(), |a| a.to_string())
        )?;
    }
    bcifs::render::write_atomic(output, text.as_bytes()).with_context(|| format!("cannot write {}", output.display()))
}

/// The colour of a curve-map cell for the map `kind`; outside the per-matrix domain grey.
fn curve_map_colour(c: &CurveCell, kind: &str, threshold: f64) -> [u8; 3] {
    if !c.per_matrix && c.verdict != Verdict::Converges {
        return [228, 228, 228];
    }
    match kind {
        "regions" => region_colour(c.region()),
        _ => match (c.verdict, c.angle()) {
            (Verdict::Diverges, _) => [200, 30, 30],
            (Verdict::Converges, Some(a)) if kind == "smooth" => {
                if a < threshold {
                    [20, 20, 20]
                } else {
                    [255, 255, 255]
                }
            }
            (Verdict::Converges, Some(a)) => angle_colour(a),
            _ => [245, 230, 120],
        },
    }
}

/// The point given with `--param` (both coordinates of the plane), as a black cross.
fn mark_point(
    img: &mut image::RgbImage,
    plane: &bcifs::render::ParameterPlane,
    marker: &[(String, f64)],
) -> Result<()> {
    let size = img.width() as usize;
    let value = |name: &str| marker.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
    let (Some(px), Some(py)) = (value(&plane.x.0), value(&plane.y.0)) else {
        if !marker.is_empty() {
            bail!("--param with --map marks a point: give both {} and {}", plane.x.0, plane.y.0);
        }
        return Ok(());
    };
    let col = ((px - plane.x.1) / (plane.x.2 - plane.x.1) * size as f64).floor();
    let row = ((plane.y.2 - py) / (plane.y.2 - plane.y.1) * size as f64).floor();
    let arm = (size as f64 / 64.0).max(2.0);
    for d in -(arm as i64)..=(arm as i64) {
        for (c, r) in [(col + d as f64, row), (col, row + d as f64)] {
            if c >= 0.0 && r >= 0.0 && (c as usize) < size && (r as usize) < size {
                img.put_pixel(c as u32, r as u32, image::Rgb([0, 0, 0]));
            }
        }
    }
    Ok(())
}

/// The legend of a curve map of `kind`.
fn curve_map_legend(kind: &str, threshold: f64) -> Vec<([u8; 3], String)> {
    let mut legend: Vec<([u8; 3], String)> = match kind {
        "regions" => [
            ("1", "1: C1 candidates (tangent)"),
            ("2", "2: cusp (α < 0)"),
            ("2'", "2': cusp (β < 0)"),
            ("3", "3: inner tangent at start"),
            ("3'", "3': inner tangent at end"),
            ("4", "4: no inner tangent"),
            ("5", "5: oscillating (1−a−b < 0)"),
            ("degenerate", "degenerate"),
        ]
        .iter()
        .map(|(r, l)| (region_colour(Some(r)), l.to_string()))
        .collect(),
        "smooth" => vec![([20, 20, 20], format!("angle < {threshold}°")), ([255, 255, 255], "rougher".into())],
        _ => [0.0, 45.0, 90.0, 135.0, 180.0].iter().map(|a: &f64| (angle_colour(*a), format!("angle {a}°"))).collect(),
    };
    legend.extend([
        ([200, 30, 30], "diverges (JSR ≥ 1)".to_string()),
        ([245, 230, 120], "undecided".to_string()),
        ([228, 228, 228], "a matrix fails (§3)".to_string()),
    ]);
    legend
}

/// `bcifs analyze curve --map`.
fn run_curve_map(
    out: &mut String,
    file: &str,
    kind: &str,
    (x, y): (&str, &str),
    (size, threshold, marker): (usize, f64, &[(String, f64)]),
    output: &std::path::Path,
) -> Result<u8> {
    use bcifs::render::{JsrSettings, curve_map};
    if size == 0 || size > 4096 {
        bail!("--size must be between 1 and 4096");
    }
    if !matches!(kind, "regions" | "roughness" | "smooth") {
        bail!("--map {kind}: expected regions, roughness or smooth");
    }
    if !(threshold.is_finite() && threshold > 0.0) {
        bail!("--threshold {threshold}: expected a positive angle in degrees");
    }
    let design = crate::cli::common::load(file)?;
    let root = design.model().map(|m| m.root(0).to_string()).context("the design has no [model] naming its root")?;
    let family = bcifs::render::solve(&design).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    let plane = plane((x, y), size)?;
    let started = std::time::Instant::now();
    let cells = curve_map(&family, &plane, &JsrSettings::quick(), &root)?;
    let ext = output.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if ext == "csv" {
        curve_map_csv(&plane, &cells, size, output)?;
    } else {
        let colour = |c: &CurveCell| curve_map_colour(c, kind, threshold);
        let mut img = image::RgbImage::from_fn(size as u32, size as u32, |i, j| {
            image::Rgb(colour(&cells[j as usize * size + i as usize]))
        });
        mark_point(&mut img, &plane, marker)?;
        let legend = curve_map_legend(kind, threshold);
        write_framed_map(output, &format!("{}: {kind}", design.name()), &plane, &img, &legend)?;
    }
    let mut counts: std::collections::BTreeMap<&str, usize> = std::collections::BTreeMap::new();
    for c in &cells {
        *counts.entry(c.region().unwrap_or("undecided")).or_default() += 1;
    }
    writeln!(
        out,
        "{}: {kind} map, {size}×{size} pixels in {:.2} s → {}",
        design.name(),
        started.elapsed().as_secs_f64(),
        output.display()
    )?;
    for (r, n) in counts {
        writeln!(out, "  region {r:<10} {n}")?;
    }
    Ok(0)
}

/// `bcifs analyze blend`.
fn run_blend(out: &mut String, file: &str, params: &[String], depth: usize, output: &std::path::Path) -> Result<u8> {
    if depth == 0 || depth > 16 {
        bail!("--depth must be between 1 and 16");
    }
    let design = crate::cli::common::load(file)?;
    let values = crate::cli::common::parse_params(params)?;
    let instance =
        bcifs::render::instantiate(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    let [e0, e1] =
        bcifs::render::curve_halves(&design, &instance).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    let a = &instance.automaton;
    let b = bcifs::render::blending(&a.arrow(e0).matrix, &a.arrow(e1).matrix, depth)
        .context("a subdivision matrix has no fixed point")?;
    let colours = [[200, 40, 40], [40, 140, 60], [40, 80, 200], [200, 140, 20], [130, 60, 170], [20, 150, 160]];
    let components = |xs: &[f64]| -> Vec<Series> {
        (0..b.knots.len())
            .map(|i| Series {
                label: format!("F{i}"),
                points: xs.iter().zip(&b.f).map(|(x, f)| (*x, f[i])).collect(),
                color: colours[i % colours.len()],
            })
            .collect()
    };
    let p: Vec<String> = instance.parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
    let panels = [
        Plot {
            title: "F(t), natural parameterization".into(),
            x_label: "t".into(),
            y_label: "F".into(),
            series: components(&b.t),
            ..Plot::default()
        },
        Plot {
            title: "u(t) = Σ tᵢ Fᵢ(t)".into(),
            x_label: "t".into(),
            y_label: "u".into(),
            series: vec![Series {
                label: "u".into(),
                points: b.t.iter().copied().zip(b.u.iter().copied()).collect(),
                color: [30, 30, 30],
            }],
            ..Plot::default()
        },
        Plot {
            title: "F(u), non-singular parameterization".into(),
            x_label: "u".into(),
            y_label: "F".into(),
            series: components(&b.u),
            ..Plot::default()
        },
    ];
    let (w, h) = (520u32, 420u32);
    let mut img = image::RgbImage::from_pixel(3 * w, h, image::Rgb([255, 255, 255]));
    for (k, panel) in panels.iter().enumerate() {
        let pic = panel.render(w, h)?;
        image::imageops::replace(&mut img, &pic, i64::from(k as u32 * w), 0);
    }
    let text = crate::cli::common::png_text(design.name(), &format!("blending functions; depth {depth}"));
    bcifs::render::write_png_text(output, &img, &text).with_context(|| format!("cannot write {}", output.display()))?;
    let monotone = b.u.windows(2).all(|x| x[1] > x[0]);
    writeln!(
        out,
        "{} ({}): {} samples; u(t) {} → {}",
        design.name(),
        p.join(", "),
        b.t.len(),
        if monotone { "increasing" } else { "NOT increasing (no reparameterization)" },
        output.display()
    )?;
    Ok(0)
}
