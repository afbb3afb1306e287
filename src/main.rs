//! The `bcifs` command line: parses arguments, calls the library, prints.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use serde_json::json;

use bcifs::analysis::{DEFAULT_CHECK_TOLERANCE, check};
use bcifs::schemes::{curve, quad_patch};
use bcifs::{Design, SolveError, read_design, solve};

#[derive(Parser)]
#[command(name = "bcifs", version, about = "Iterative geometric modelling with Boundary Controlled IFS")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve the constraints of an automaton file into its admissible family.
    Solve {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Instantiate an automaton and verify constraints, column sums and spectra.
    Check {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable; defaults come from the file).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate an automaton with its model and write OBJ, SVG or PNG.
    Render {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Subdivision depth.
        #[arg(long, conflicts_with = "tolerance")]
        depth: Option<usize>,
        /// Subdivide until every cell's control polygon is smaller than this (modelling units).
        #[arg(long)]
        tolerance: Option<f64>,
        /// Chaos game with this many points instead of deterministic evaluation.
        #[arg(long, value_name = "N")]
        random: Option<usize>,
        /// Seed of the chaos game.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Probability of an arrow in the chaos game, ARROW=P (repeatable; default ∝ |det|).
        #[arg(long = "prob", value_name = "ARROW=P")]
        probs: Vec<String>,
        /// Leave out a subdivision arrow (repeatable): a subset of the attractor.
        #[arg(long = "drop", value_name = "ARROW")]
        drop: Vec<String>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// In-memory limit in MiB for PNG/SVG output.
        #[arg(long, default_value_t = 4096)]
        memory_mib: usize,
        /// Picture size in pixels, WIDTHxHEIGHT.
        #[arg(long, default_value = "800x800")]
        size: String,
        /// View of 3D shapes: YAW,PITCH in degrees.
        #[arg(long, default_value = "30,35", allow_hyphen_values = true)]
        view: String,
        /// Output file: .obj (streamed), .svg or .png.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Render every shipped automaton (PNG, OBJ) and an index.html into DIR.
    Gallery {
        /// Output directory.
        #[arg(default_value = "gallery")]
        dir: PathBuf,
    },
    /// Generate the seeds' subdivision schemes: render them or print their automaton.
    Scheme {
        #[command(subcommand)]
        scheme: SchemeCommand,
    },
    /// Analyse a scheme over a parameter range: continuity and fractal ranges.
    Analyze {
        #[command(subcommand)]
        what: AnalyzeCommand,
    },
    /// Print a commented automaton file for a BC-IFS topology.
    New {
        #[command(subcommand)]
        topology: Topology,
    },
}

#[derive(Subcommand)]
enum SchemeCommand {
    /// The p-ary normal-vector scheme of Li, Zheng, Peng and Zhou (seed 000, eq. 1).
    Normal(NormalArgs),
    /// Stationary schemes as IFS (seed 001) and the ternary 5-point scheme (seed 003):
    /// bspline, bspline-end, bezier, bezier-union, four-point, koch-control,
    /// sierpinski-control, bicubic, ternary5, ternary5-closed, ternary5-surface, ternary5-torus.
    Ifs(IfsArgs),
}

/// Where a generated scheme goes: its automaton file, or a picture or mesh.
#[derive(clap::Args)]
struct SchemeOutput {
    /// Print the automaton file (TOML) instead of rendering.
    #[arg(long)]
    print: bool,
    /// Picture size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800")]
    size: String,
    /// Output file: .obj, .svg or .png.
    #[arg(short, long, required_unless_present = "print")]
    output: Option<PathBuf>,
}

#[derive(clap::Args)]
struct IfsArgs {
    /// The scheme.
    name: String,
    /// Control points `x,y x,y ...` or `x,y,z ...` (default: the scheme's natural ones).
    #[arg(long, allow_hyphen_values = true)]
    points: Option<String>,
    /// Tension ω of the ternary schemes, a constant such as 3/50 or -1/20.
    #[arg(long, allow_hyphen_values = true)]
    omega: Option<String>,
    /// Subdivision depth.
    #[arg(long, default_value_t = 6)]
    depth: usize,
    /// Leave out a subdivision arrow (repeatable): a fractal subset of the attractor.
    #[arg(long = "drop", value_name = "ARROW")]
    drop: Vec<String>,
    #[command(flatten)]
    out: SchemeOutput,
}

fn run_ifs(out: &mut String, args: IfsArgs) -> Result<u8> {
    let points = match &args.points {
        None => None,
        Some(text) => {
            let mut pts = Vec::new();
            for p in text.split_whitespace() {
                let coords: Vec<f64> = p
                    .split(',')
                    .map(|x| x.trim().parse::<f64>().with_context(|| format!("--points `{p}`: expected numbers")))
                    .collect::<Result<_>>()?;
                pts.push(coords);
            }
            let d = pts.first().map_or(0, Vec::len);
            if !(2..=3).contains(&d) || pts.iter().any(|p| p.len() != d) {
                bail!("--points: all points need 2 or all 3 coordinates");
            }
            Some(pts)
        }
    };
    let omega = args.omega.as_deref().map(bcifs::Surd::parse).transpose()?;
    let design = bcifs::schemes::ifs_preset(&args.name, points, omega.as_ref())?;
    if args.out.print {
        out.push_str(&bcifs::write_design(&design));
        return Ok(0);
    }
    let output = args.out.output.context("give -o OUT.{png,svg,obj}")?;
    let (w, h) = parse_size(&args.out.size)?;
    let mut options = bcifs::RenderOptions::default();
    options.eval.depth = bcifs::eval::Depth::Fixed(args.depth);
    options.eval.dropped = args.drop;
    options.eval.progress = true;
    options.raster = options.raster.with_size(w, h);
    let started = std::time::Instant::now();
    let summary = bcifs::render(&design, &options, &output)?;
    eprintln!(
        "{}: {} vertices{} → {} ({:.2} s)",
        design.description(),
        summary.vertices,
        if summary.quads > 0 { format!(", {} quads", summary.quads) } else { String::new() },
        output.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(0)
}

#[derive(Subcommand)]
enum AnalyzeCommand {
    /// The ternary 5-point scheme with tension ω (seed 003): C0/C1/C2 bounds,
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
    },
}

fn run_ternary5(out: &mut String, from: f64, to: f64, steps: usize, output: &std::path::Path) -> Result<u8> {
    use bcifs::analysis::ternary::{PAPER_RANGES, boundary, intervals, omegas, ternary5_rows};
    if from >= to || !from.is_finite() || !to.is_finite() {
        bail!("--omega-range A B needs finite A < B");
    }
    if steps == 0 || steps > 10_000 {
        bail!("--steps must be between 1 and 10000");
    }
    // In chunks, with a progress bar on a terminal.
    let all = omegas(from, to, steps);
    let bar =
        std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| indicatif::ProgressBar::new(all.len() as u64));
    let mut rows = Vec::with_capacity(all.len());
    for chunk in all.chunks(32) {
        rows.extend(ternary5_rows(chunk));
        if let Some(b) = &bar {
            b.inc(chunk.len() as u64);
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    writeln!(out, "ternary 5-point scheme (seed 003, eq. 1), ω from {from} to {to}")?;
    writeln!(
        out,
        "{:>10}  {:>8}  {:>8}  {:>8}  {:>8}  {:>8}  verdict",
        "omega", "C0 bound", "JSR low", "C1 bound", "C2 bound", "growth"
    )?;
    for r in &rows {
        writeln!(
            out,
            "{:>10.5}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}  {}",
            r.omega,
            r.c0,
            r.c0_lower,
            r.c1,
            r.c2,
            r.growth,
            r.verdict()
        )?;
    }
    writeln!(
        out,
        "
C0 bound: min over L ≤ 8 of ‖S_b^L‖∞^(1/L) for the difference scheme b = a/(1+z+z²) (< 1 proves C0);"
    )?;
    writeln!(out, "JSR low: max over block products of length ≤ 4 of ρ^(1/len) (≥ 1 proves divergence);")?;
    writeln!(
        out,
        "C1/C2 bounds: the same for 3a/σ² and 9a/σ³; growth: polygon length ratio per step after 10 steps.
"
    )?;
    let step = (to - from) / steps as f64;
    let refine = |ranges: Vec<(f64, f64)>, pred: &dyn Fn(&bcifs::analysis::ternary::TernaryRow) -> bool| {
        ranges
            .into_iter()
            .map(|(a, b)| {
                let lo = if a > from { boundary(a - step, a, 1e-6, pred) } else { a };
                let hi = if b < to { boundary(b, b + step, 1e-6, pred) } else { b };
                (lo, hi)
            })
            .collect::<Vec<_>>()
    };
    let show = |v: &[(f64, f64)]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.iter().map(|(a, b)| format!("({a:.5}, {b:.5})")).collect::<Vec<_>>().join(" ∪ ")
        }
    };
    let paper = |i: usize| format!("paper: ({:.5}, {:.5})", PAPER_RANGES[i].1, PAPER_RANGES[i].2);
    let c0 = refine(intervals(&rows, |r| r.converges()), &|r| r.converges());
    writeln!(out, "C0 proven on       {}   [{}]", show(&c0), paper(0))?;
    let fails = refine(intervals(&rows, |r| r.fails()), &|r| r.fails());
    writeln!(out, "not C0 (proven) on {}", show(&fails))?;
    let c1 = refine(intervals(&rows, |r| r.c1 < 1.0), &|r| r.c1 < 1.0);
    writeln!(out, "C1 proven on       {}   [{}]", show(&c1), paper(1))?;
    let c2 = refine(intervals(&rows, |r| r.c2 < 1.0), &|r| r.c2 < 1.0);
    writeln!(out, "C2 proven on       {}   [{}]", show(&c2), paper(2))?;
    let fractal = refine(intervals(&rows, |r| r.fractal()), &|r| r.fractal());
    writeln!(out, "fractal (C0 and length growth > 1.001) on {}", show(&fractal))?;
    let img = bcifs::ternary5_plot(&rows).render(900, 600);
    bcifs::export::write_png(output, &img).with_context(|| format!("cannot write {}", output.display()))?;
    writeln!(out, "plot → {}", output.display())?;
    Ok(0)
}

#[derive(clap::Args)]
struct NormalArgs {
    /// A figure of the paper: levy, dragon, dragon-triangle, dragon-quad, sierpinski,
    /// sierpinski-triangle, sierpinski-quad, koch, koch-triangle, koch-quad, snowflake,
    /// tigerhead, human, approximating, crown, minkowski.
    #[arg(long)]
    preset: Option<String>,
    /// Arity p (checked against the number of α and β).
    #[arg(long = "p")]
    arity: Option<usize>,
    /// α_0, …, α_{p-1}, comma-separated constants (`0,1/3,1/2,2/3`).
    #[arg(long, allow_hyphen_values = true)]
    alpha: Option<String>,
    /// β_0, …, β_{p-1}, comma-separated constants (`0,0,sqrt(3)/6,0`).
    #[arg(long, allow_hyphen_values = true)]
    beta: Option<String>,
    /// Direction of the normals: positive (counter-clockwise) or negative.
    #[arg(long)]
    normal: Option<String>,
    /// Sign pattern of β: constant, alternate ((−1)^i), level ((−1)^(k+1)), level-index ((−1)^(k+i)).
    #[arg(long)]
    sign: Option<String>,
    /// Initial polygon: segment, triangle or quad (the paper's unit shapes).
    #[arg(long)]
    polygon: Option<String>,
    /// Initial polygon as points `x,y x,y ...` (overrides --polygon).
    #[arg(long, allow_hyphen_values = true)]
    points: Option<String>,
    /// Close the polygon given by --points.
    #[arg(long)]
    closed: bool,
    /// Subdivision steps (default: the paper's figure).
    #[arg(long)]
    depth: Option<usize>,
    /// auto (automaton when interpolatory), direct (eq. 1 on the polygon) or automaton.
    #[arg(long, default_value = "auto")]
    form: String,
    #[command(flatten)]
    out: SchemeOutput,
}

fn keyword<T: Copy>(what: &str, value: &str, options: &[(&str, T)]) -> Result<T> {
    options.iter().find(|(k, _)| *k == value).map(|(_, v)| *v).with_context(|| {
        let names: Vec<&str> = options.iter().map(|(k, _)| *k).collect();
        match bcifs::suggest(value, names.iter().copied()) {
            Some(s) => format!("unknown {what} `{value}` (did you mean `{s}`?); expected {}", names.join(", ")),
            None => format!("unknown {what} `{value}`; expected {}", names.join(", ")),
        }
    })
}

fn parse_size(size: &str) -> Result<(u32, u32)> {
    let (w, h) = size.split_once('x').with_context(|| format!("--size `{size}`: expected WIDTHxHEIGHT"))?;
    Ok((w.trim().parse().context("--size width")?, h.trim().parse().context("--size height")?))
}

fn run_normal(out: &mut String, args: NormalArgs) -> Result<u8> {
    use bcifs::schemes::{NormalDirection, NormalPreset, NormalScheme, SignPattern, normal_preset};
    let mut preset = match &args.preset {
        Some(name) => normal_preset(name)?,
        None => NormalPreset {
            name: "normal",
            description: "normal-vector scheme",
            scheme: NormalScheme::parse(&["0", "1/2"], &["0", "1/2"])?,
            polygon: bcifs::schemes::unit_segment(),
            closed: false,
            depth: 8,
        },
    };
    match (&args.alpha, &args.beta) {
        (Some(a), Some(b)) => {
            let a: Vec<&str> = a.split(',').map(str::trim).collect();
            let b: Vec<&str> = b.split(',').map(str::trim).collect();
            let scheme = NormalScheme::parse(&a, &b)?;
            preset.scheme = scheme.with_normal(preset.scheme.normal).with_sign(preset.scheme.sign);
        }
        (None, None) => {}
        _ => bail!("give both --alpha and --beta"),
    }
    if let Some(p) = args.arity
        && p != preset.scheme.arity()
    {
        bail!("--p {p} but {} values of α and β", preset.scheme.arity());
    }
    if let Some(n) = &args.normal {
        let n = keyword(
            "normal direction",
            n,
            &[("positive", NormalDirection::Positive), ("negative", NormalDirection::Negative)],
        )?;
        preset.scheme = preset.scheme.with_normal(n);
    }
    if let Some(sgn) = &args.sign {
        let options: Vec<(&str, SignPattern)> = SignPattern::ALL.iter().map(|p| (p.keyword(), *p)).collect();
        preset.scheme = preset.scheme.with_sign(keyword("sign pattern", sgn, &options)?);
    }
    if let Some(text) = &args.points {
        let mut pts = Vec::new();
        for p in text.split_whitespace() {
            let (x, y) = p.split_once(',').with_context(|| format!("--points `{p}`: expected x,y"))?;
            pts.push([x.trim().parse().context("--points x")?, y.trim().parse().context("--points y")?]);
        }
        preset.polygon = pts;
        preset.closed = args.closed;
    } else if let Some(poly) = &args.polygon {
        type Shape = fn() -> Vec<bcifs::schemes::Point2>;
        let options: [(&str, (Shape, bool)); 3] = [
            ("segment", (bcifs::schemes::unit_segment, false)),
            ("triangle", (bcifs::schemes::unit_triangle, true)),
            ("quad", (bcifs::schemes::unit_square, true)),
        ];
        let (make, closed) = keyword("polygon", poly, &options)?;
        preset.polygon = make();
        preset.closed = closed;
    }
    if preset.polygon.len() < if preset.closed { 3 } else { 2 } {
        bail!("the initial polygon needs at least {} points", if preset.closed { 3 } else { 2 });
    }
    if args.out.print {
        out.push_str(&bcifs::write_design(&preset.design()?));
        return Ok(0);
    }
    let form = keyword(
        "form",
        &args.form,
        &[
            ("auto", bcifs::SchemeForm::Auto),
            ("direct", bcifs::SchemeForm::Direct),
            ("automaton", bcifs::SchemeForm::Automaton),
        ],
    )?;
    let depth = args.depth.unwrap_or(preset.depth);
    let output = args.out.output.context("give -o OUT.{png,svg,obj}")?;
    let (w, h) = parse_size(&args.out.size)?;
    let started = std::time::Instant::now();
    let shape = bcifs::normal_shape(&preset, depth, form, bcifs::eval::DEFAULT_MEMORY_LIMIT)?;
    let raster = bcifs::export::RasterSettings::default().with_size(w, h);
    let summary = bcifs::write_shape(&shape, preset.name, &raster, &output)?;
    eprintln!(
        "{} ({}), depth {depth}: {} vertices → {} ({:.2} s)",
        preset.name,
        preset.scheme,
        summary.vertices,
        output.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(0)
}

#[derive(Subcommand)]
enum Topology {
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
}

/// Reads a file, or a shipped automaton by name when no such file exists.
fn load(file: &str) -> Result<Design> {
    let path = PathBuf::from(file);
    if !path.exists()
        && let Some(d) = bcifs::builtin_design(file.trim_end_matches(".toml"))
    {
        return Ok(d);
    }
    Ok(read_design(&path)?)
}

fn parse_params(params: &[String]) -> Result<Vec<(String, f64)>> {
    params
        .iter()
        .map(|p| {
            let (name, value) = p.split_once('=').with_context(|| format!("`{p}`: expected NAME=VALUE"))?;
            let value: f64 = match value.trim().parse() {
                Ok(v) => v,
                Err(_) => {
                    let e = bcifs::Expr::parse(value.trim()).map_err(|e| anyhow::anyhow!("`{p}`: {e}"))?;
                    struct NoNames;
                    impl bcifs::Env<f64> for NoNames {
                        fn param(&self, _: &str) -> Option<f64> {
                            None
                        }
                        fn entry(&self, _: &str, _: usize, _: usize) -> Option<f64> {
                            None
                        }
                    }
                    e.eval(&NoNames).map_err(|e| anyhow::anyhow!("`{p}`: {e}"))?
                }
            };
            Ok((name.trim().to_string(), value))
        })
        .collect()
}

fn run_solve(out: &mut String, file: &str, as_json: bool) -> Result<u8> {
    let design = load(file)?;
    let name = design.name().to_string();
    match solve(&design) {
        Ok(family) => {
            let matrices = family.matrices_text();
            if as_json {
                let m: serde_json::Map<String, serde_json::Value> =
                    matrices.iter().map(|(n, rows)| (n.clone(), json!(rows))).collect();
                writeln!(
                    out,
                    "{}",
                    serde_json::to_string_pretty(&json!({
                        "automaton": name, "consistent": true, "dof": family.dof(),
                        "parameters": family.parameter_names(), "matrices": m,
                    }))?
                )?;
            } else {
                writeln!(out, "{name}: {} free parameter(s): {}", family.dof(), family.parameter_names().join(", "))?;
                writeln!(out, "({} scalar equations, rank {})", family.equations, family.rank)?;
                for (n, rows) in &matrices {
                    let width = rows.iter().flatten().map(String::len).max().unwrap_or(1);
                    writeln!(out, "\n{n} =")?;
                    for row in rows {
                        let cells: Vec<String> = row.iter().map(|c| format!("{c:>width$}")).collect();
                        writeln!(out, "  [ {} ]", cells.join("  "))?;
                    }
                }
            }
            Ok(0)
        }
        Err(SolveError::Inconsistent { conflicts }) => {
            if as_json {
                writeln!(
                    out,
                    "{}",
                    serde_json::to_string_pretty(
                        &json!({"automaton": name, "consistent": false, "conflicts": conflicts})
                    )?
                )?;
            } else {
                writeln!(out, "{name}: the constraints are inconsistent; these equations conflict:")?;
                for c in &conflicts {
                    writeln!(out, "  {c}")?;
                }
            }
            Ok(1)
        }
        Err(e) => bail!("{name}: {e}"),
    }
}

fn run_check(out: &mut String, file: &str, params: &[String], as_json: bool) -> Result<u8> {
    let design = load(file)?;
    let values = parse_params(params)?;
    let instance = bcifs::instantiate(&design, &values).map_err(|e| anyhow::anyhow!("{}: {e}", design.name()))?;
    let report = check(&instance.automaton, &instance.values, DEFAULT_CHECK_TOLERANCE)?;
    if as_json {
        let params: serde_json::Map<String, serde_json::Value> =
            instance.parameters.iter().map(|(n, v)| (n.clone(), json!(v))).collect();
        let spectra: serde_json::Map<String, serde_json::Value> = report
            .spectra
            .iter()
            .map(|(n, eig)| (n.clone(), json!(eig.iter().map(|l| [l.re, l.im]).collect::<Vec<_>>())))
            .collect();
        let constraints: Vec<_> =
            report.constraints.iter().map(|(e, r)| json!({"equation": e, "max_abs_residual": r})).collect();
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&json!({
                "automaton": design.name(), "ok": report.ok, "parameters": params,
                "constraints": constraints, "max_column_sum_error": report.max_column_sum_error,
                "spectra": spectra, "contractive": report.contractive,
            }))?
        )?;
    } else {
        let p: Vec<String> = instance.parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        writeln!(out, "{}: {}", design.name(), if p.is_empty() { "no free parameter".into() } else { p.join(", ") })?;
        for (e, r) in &report.constraints {
            let mark = if *r <= DEFAULT_CHECK_TOLERANCE { "ok  " } else { "FAIL" };
            writeln!(out, "  {mark} {e}   (residual {r:.3e})")?;
        }
        writeln!(out, "  column sums: max error {:.3e}", report.max_column_sum_error)?;
        for (n, eig) in &report.spectra {
            let list: Vec<String> = eig
                .iter()
                .map(|l| if l.im.abs() < 1e-12 { format!("{:.6}", l.re) } else { format!("{:.6}{:+.6}i", l.re, l.im) })
                .collect();
            writeln!(out, "  spectrum of {n}: {}", list.join(", "))?;
        }
        writeln!(out, "  contractive: {}", if report.contractive { "yes" } else { "no" })?;
        writeln!(out, "{}", if report.ok { "ok" } else { "FAILED: some constraints do not hold" })?;
    }
    Ok(if report.ok { 0 } else { 1 })
}

fn run(out: &mut String, cli: Cli) -> Result<u8> {
    match cli.command {
        Command::Solve { file, json } => run_solve(out, &file, json),
        Command::Check { file, params, json } => run_check(out, &file, &params, json),
        Command::Render {
            file,
            params,
            depth,
            tolerance,
            random,
            seed,
            probs,
            drop,
            threads,
            memory_mib,
            size,
            view,
            output,
        } => {
            let design = load(&file)?;
            let mut options = bcifs::RenderOptions::default();
            options.params = parse_params(&params)?;
            options.eval.depth = match (depth, tolerance) {
                (_, Some(eps)) if eps > 0.0 => bcifs::eval::Depth::Tolerance(eps),
                (_, Some(eps)) => bail!("the tolerance must be positive, not {eps}"),
                (Some(k), None) => bcifs::eval::Depth::Fixed(k),
                (None, None) => bcifs::eval::Depth::Fixed(bcifs::eval::DEFAULT_DEPTH),
            };
            options.eval.threads = threads;
            options.eval.memory_limit = memory_mib.saturating_mul(1 << 20);
            options.eval.dropped = drop;
            options.eval.progress = true;
            if let Some(n) = random {
                let mut r = bcifs::eval::RandomSettings::default().with_points(n).with_seed(seed);
                r.threads = threads;
                r.probabilities = parse_params(&probs)?;
                options.random = Some(r);
            }
            let (w, h) = size.split_once('x').with_context(|| format!("--size `{size}`: expected WIDTHxHEIGHT"))?;
            let (yaw, pitch) = view.split_once(',').with_context(|| format!("--view `{view}`: expected YAW,PITCH"))?;
            options.raster = options
                .raster
                .with_size(w.trim().parse().context("--size width")?, h.trim().parse().context("--size height")?)
                .with_view(yaw.trim().parse().context("--view yaw")?, pitch.trim().parse().context("--view pitch")?);
            let started = std::time::Instant::now();
            let summary = bcifs::render(&design, &options, &output)?;
            eprintln!(
                "{}: {} vertices{} → {} ({:.2} s)",
                design.name(),
                summary.vertices,
                if summary.quads > 0 { format!(", {} quads", summary.quads) } else { String::new() },
                output.display(),
                started.elapsed().as_secs_f64()
            );
            Ok(0)
        }
        Command::Gallery { dir } => {
            let started = std::time::Instant::now();
            let entries = bcifs::gallery(&dir, true)?;
            for e in &entries {
                writeln!(
                    out,
                    "{:<20} depth {:>2}  {:>9} vertices  {}",
                    e.name,
                    e.depth.unwrap_or(0),
                    e.summary.vertices,
                    e.files.join(", ")
                )?;
            }
            writeln!(
                out,
                "{} automata → {} ({:.1} s)",
                entries.len(),
                dir.join("index.html").display(),
                started.elapsed().as_secs_f64()
            )?;
            Ok(0)
        }
        Command::Analyze { what } => match what {
            AnalyzeCommand::Ternary5 { omega_range, steps, output } => {
                run_ternary5(out, omega_range[0], omega_range[1], steps, &output)
            }
        },
        Command::Scheme { scheme } => match scheme {
            SchemeCommand::Normal(args) => run_normal(out, args),
            SchemeCommand::Ifs(args) => run_ifs(out, args),
        },
        Command::New { topology } => {
            let text = match topology {
                Topology::Curve { points, vertex, arity } => curve(points, vertex, arity)?,
                Topology::QuadPatch { symmetric } => quad_patch(symmetric)?,
            };
            out.push_str(&bcifs::write_design(&text));
            Ok(0)
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut out = String::new();
    let code = match run(&mut out, cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            2
        }
    };
    // A closed pipe (`bcifs solve x | head`) is the reader's choice, not an error.
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(out.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: cannot write the output: {e}");
            ExitCode::from(2)
        }
        _ => ExitCode::from(code),
    }
}
