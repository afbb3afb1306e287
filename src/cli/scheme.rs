//! `bcifs scheme`: the papers' schemes, rendered or printed as automaton files.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Subcommand;

use super::render::{SchemeForm, normal_shape, print_report};
use crate::cli::common::keyword;
use bcifs::render::render;

#[derive(Subcommand)]
pub enum SchemeCommand {
    /// The p-ary normal-vector scheme of Li, Zheng, Peng and Zhou (Li et al. 2013, eq. 1).
    Normal(NormalArgs),
    /// Stationary schemes as IFS (Schaefer et al. 2005) and the ternary 5-point scheme (Siddiqi et al. 2014):
    /// bspline, bspline-end, bezier, bezier-union, four-point, koch-control,
    /// sierpinski-control, bicubic, box-spline, box-spline-gasket, box-spline-quad,
    /// sqrt3-patch, ternary5, ternary5-closed, ternary5-surface, ternary5-torus.
    Ifs(IfsArgs),
}

/// Where a generated scheme goes: its automaton file, or a picture or mesh.
#[derive(clap::Args)]
pub struct SchemeOutput {
    /// Print the automaton file (TOML) instead of rendering.
    #[arg(long)]
    print: bool,
    #[command(flatten)]
    picture: crate::cli::keys::KeyArgs<crate::cli::keys::PictureKeys>,
    /// Output file: .obj, .off, .ply, .stl, .glb, .svg or .png.
    #[arg(short, long, required_unless_present = "print")]
    output: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct IfsArgs {
    /// The scheme.
    name: String,
    /// Control points `x,y x,y ...` or `x,y,z ...` (default: the scheme's natural ones).
    #[arg(long, allow_hyphen_values = true)]
    points: Option<String>,
    /// Tension ω of the ternary schemes: a constant such as 3/50 or -1/20, or a
    /// name (`w`): ω free, a one-parameter family of curves (default 3/50) for
    /// `solve`, `check --param w=…` and `explore`.
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
                    .map(|x| {
                        x.trim()
                            .parse::<f64>()
                            .ok()
                            .filter(|v| v.is_finite())
                            .with_context(|| format!("--points `{p}`: `{}` is not a finite number", x.trim()))
                    })
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
    let name = args.name.replace('_', "-");
    let design = match args.omega.as_deref() {
        Some(w) if ["nan", "inf", "infinity", "-inf"].contains(&w.to_ascii_lowercase().as_str()) => {
            bail!("--omega {w}: a tension is a number (such as 1/16 or 0.06) or a parameter name, and `{w}` is neither")
        }
        Some(w) if w.starts_with(|c: char| c.is_alphabetic() || c == '_') && !w.starts_with("sqrt") => {
            bcifs::render::ternary_family(&name, points, w)?
        }
        omega => {
            let omega = omega.map(bcifs::render::Surd::parse).transpose()?;
            bcifs::render::ifs_preset(&name, points, omega.as_ref())?
        }
    };
    if args.out.print {
        out.push_str(&bcifs::render::write_design(&design));
        return Ok(0);
    }
    let output = args.out.output.context("give -o OUT (.png, .svg, .obj, .ply, .glb, ...)")?;
    crate::cli::common::check_output(&output, &crate::cli::common::render_formats(), &[])?;
    let mut options = crate::cli::render::options(&args.out.picture)?.with_depth(args.depth);
    options.sampling.dropped = args.drop;
    let started = std::time::Instant::now();
    print_report(&render(&design, &options, &output)?, design.description(), &output, started);
    Ok(0)
}

#[derive(clap::Args)]
pub struct NormalArgs {
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
    #[arg(long, value_enum)]
    normal: Option<Direction>,
    /// Sign pattern of β: constant, alternate ((−1)^i), level ((−1)^(k+1)), level-index ((−1)^(k+i)).
    #[arg(long)]
    sign: Option<String>,
    /// Initial polygon: segment, triangle or quad (the paper's unit shapes).
    #[arg(long, value_enum)]
    polygon: Option<Polygon>,
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
    #[arg(long, value_enum, default_value_t = SchemeForm::Auto)]
    form: SchemeForm,
    #[command(flatten)]
    out: SchemeOutput,
}

/// `--normal`: the direction of the normals.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum Direction {
    /// Counter-clockwise.
    Positive,
    /// Clockwise.
    Negative,
}

/// `--polygon`: the paper's unit shapes.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum Polygon {
    /// The unit segment (open).
    Segment,
    /// The unit triangle (closed).
    Triangle,
    /// The unit square (closed).
    Quad,
}

fn run_normal(out: &mut String, args: NormalArgs) -> Result<u8> {
    use bcifs::render::{NormalDirection, NormalPreset, NormalScheme, SignPattern, normal_preset};
    let mut preset = match &args.preset {
        Some(name) => normal_preset(name)?,
        None => NormalPreset {
            name: "normal",
            description: "normal-vector scheme",
            scheme: NormalScheme::parse(&["0", "1/2"], &["0", "1/2"])?,
            polygon: bcifs::render::unit_segment(),
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
    if let Some(n) = args.normal {
        preset.scheme = preset.scheme.with_normal(match n {
            Direction::Positive => NormalDirection::Positive,
            Direction::Negative => NormalDirection::Negative,
        });
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
    } else if let Some(poly) = args.polygon {
        (preset.polygon, preset.closed) = match poly {
            Polygon::Segment => (bcifs::render::unit_segment(), false),
            Polygon::Triangle => (bcifs::render::unit_triangle(), true),
            Polygon::Quad => (bcifs::render::unit_square(), true),
        };
    }
    if preset.polygon.len() < if preset.closed { 3 } else { 2 } {
        bail!("the initial polygon needs at least {} points", if preset.closed { 3 } else { 2 });
    }
    if args.out.print {
        out.push_str(&bcifs::render::write_design(&preset.design()?));
        return Ok(0);
    }
    let form = args.form;
    let depth = args.depth.unwrap_or(preset.depth);
    let output = args.out.output.context("give -o OUT (.png, .svg, .obj, .ply, .glb, ...)")?;
    crate::cli::common::check_output(&output, &crate::cli::common::render_formats(), &[])?;

    let started = std::time::Instant::now();
    let options = args.out.picture.options()?;
    let shape = normal_shape(&preset, depth, form, options.budget.memory)?;
    let raster = options.raster();
    let label = format!("{} ({}), depth {depth}", preset.name, preset.scheme);
    let comment = format!("{}; depth {depth}; size {}x{}", preset.scheme, raster.width, raster.height);
    let text = crate::cli::common::png_text(preset.name, &comment);
    let report = bcifs::render::write_shape_text(&shape, preset.name, &raster, &output, &text)?;
    print_report(&report, &label, &output, started);
    Ok(0)
}

/// Runs a `bcifs scheme` command.
pub fn run(out: &mut String, scheme: SchemeCommand) -> Result<u8> {
    match scheme {
        SchemeCommand::Normal(args) => run_normal(out, args),
        SchemeCommand::Ifs(args) => run_ifs(out, args),
    }
}
