//! Rendering a design to a file chosen by its extension (`.obj` streamed,
//! `.svg`, `.png`), and the curves of the normal-vector presets.

use std::path::{Path, PathBuf};

use anyhow::bail;
use bcifs::render::EvalError;
use bcifs::render::Shape;
use bcifs::render::{Options, RenderError, Report, control_net, evaluate_design, model_of};

use crate::cli::common::{load, progress_bar};
use crate::cli::keys::{AllKeys, KeyArgs};

/// The arguments of `bcifs render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The automaton file (TOML), or the name of a shipped automaton.
    pub file: String,
    /// Output file: .obj, .off, .ply, .stl, .3mf (streamed), .glb, .svg, .png, or .flame (a plain IFS of the plane).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write the model's control net instead of the attractor (the control polygon of a
    /// curve, the control grid of a surface as quads), to show next to the attractor.
    #[arg(long)]
    pub control: bool,
    /// Print a JSON report on stdout: what was written, and for meshes the print report
    /// (volume, area, bbox, components, genus, closed, oriented, smallest wall and hole).
    #[arg(long)]
    pub json: bool,
    /// The options: what is sampled, the budget, the look, the file's style.
    #[command(flatten)]
    pub keys: KeyArgs<AllKeys>,
}

/// `bcifs render`: evaluates a design with its model and writes the file.
pub fn run(args: RenderArgs) -> anyhow::Result<u8> {
    crate::cli::common::check_output(
        &args.output,
        &crate::cli::common::render_formats(),
        &[std::path::Path::new(&args.file)],
    )?;
    let design = load(&args.file)?;
    let started = std::time::Instant::now();
    let options = options(&args.keys)?;
    if args.control {
        if args.keys.has("samples") {
            bail!("--control draws the control net: --random (the chaos game) does not apply to it");
        }
        let model = model_of(&design)?;
        let raster = options.raster();
        let text = crate::cli::common::png_text(
            design.name(),
            &format!("control net; size {}x{}", raster.width, raster.height),
        );
        let report =
            bcifs::render::write_shape_text(&control_net(&model), design.name(), &raster, &args.output, &text)?;
        print_report(&report, &format!("{} (control net)", design.name()), &args.output, started);
        return Ok(0);
    }
    let report = bcifs::render::render(&design, &options, &args.output)?;
    print_report(&report, design.name(), &args.output, started);
    if args.json {
        let mut json = serde_json::json!({
            "automaton": design.name(),
            "output": args.output,
            "format": report.format.map(|f| f.extension()),
            "vertices": report.vertices,
            "faces": report.faces,
            "bytes": report.bytes,
            "depth": report.depth,
            "warnings": report.warnings,
        });
        if report.faces > 0 {
            // A print file's report was made with it; another mesh's is made here.
            let print = match &report.print {
                Some(p) => p.clone(),
                None => bcifs::render::print_report(&design, &options)?,
            };
            if let (Some(out), Ok(serde_json::Value::Object(mut fields))) =
                (json.as_object_mut(), serde_json::to_value(print))
            {
                // One list of warnings: the render's (a print file's hold its print report's).
                let extra = fields.remove("warnings");
                if report.print.is_none()
                    && let (Some(serde_json::Value::Array(w)), Some(serde_json::Value::Array(more))) =
                        (out.get_mut("warnings"), extra)
                {
                    w.extend(more);
                }
                out.extend(fields);
            }
        }
        println!("{}", serde_json::to_string_pretty(&json)?);
    }
    Ok(0)
}

/// The render options the flags ask for, checked by the library, with the
/// command line's progress bar, Ctrl-C and provenance.
pub fn options<S: crate::cli::keys::KeySet>(keys: &KeyArgs<S>) -> anyhow::Result<Options> {
    let mut options = keys.options()?;
    options.progress = progress_bar();
    options.cancel = crate::cli::common::interrupt().clone();
    options.provenance = Some(crate::cli::common::command_line());
    Ok(options)
}

/// Tells stderr a render's warnings and notes.
pub fn warn(report: &Report) {
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    for n in &report.notes {
        eprintln!("note: {n}");
    }
}

/// Tells stderr what a render did: its warnings and notes, then
/// `label: N vertices, M faces → OUT (T s)`.
pub fn print_report(report: &Report, label: &str, output: &Path, started: std::time::Instant) {
    warn(report);
    eprintln!(
        "{label}: {} vertices{}{} → {} ({:.2} s)",
        report.vertices,
        if report.faces > 0 { format!(", {} faces", report.faces) } else { String::new() },
        report.duplicates.map_or(String::new(), |n| format!(" ({n} exact duplicates dropped)")),
        output.display(),
        started.elapsed().as_secs_f64()
    );
}

/// Which form of a scheme to evaluate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SchemeForm {
    /// The automaton when the scheme has one, the direct polyline form otherwise.
    Auto,
    /// The direct polyline form (the paper's refinement rules).
    Direct,
    /// The automaton (BC-IFS) form.
    Automaton,
}

/// The curve of a normal-vector scheme on its initial polygon after `depth`
/// steps, in the requested form (both forms give the same points).
///
/// # Errors
/// A non-interpolatory scheme asked for in automaton form, or an evaluation error.
pub fn normal_shape(
    preset: &bcifs::render::NormalPreset,
    depth: usize,
    form: SchemeForm,
    memory_limit: usize,
) -> Result<Shape, RenderError> {
    let scheme = &preset.scheme;
    if preset.polygon.iter().flatten().any(|x| !x.is_finite()) {
        return Err(RenderError::Scheme(bcifs::render::NormalSchemeError::NotFinite));
    }
    let automaton = match form {
        SchemeForm::Auto => scheme.is_interpolatory(),
        SchemeForm::Direct => false,
        SchemeForm::Automaton => true,
    };
    if automaton {
        let design = scheme.design(preset.name, &preset.polygon, preset.closed).map_err(RenderError::Scheme)?;
        let mut options = Options::default().with_depth(depth);
        options.budget.memory = memory_limit;
        return evaluate_design(&design, &options, &mut Vec::new());
    }
    let segments = if preset.closed { preset.polygon.len() } else { preset.polygon.len().saturating_sub(1) };
    let points = (segments as u128 * (scheme.arity() as u128).pow(depth.min(64) as u32) + 1) * 2 * 8;
    if points > memory_limit as u128 {
        return Err(RenderError::Eval(EvalError::TooLarge { estimate: points, limit: memory_limit }));
    }
    let pts = scheme.polygon(&preset.polygon, preset.closed, depth);
    let flat: Vec<f64> = pts.iter().flatten().copied().collect();
    Ok(Shape::polyline(preset.name, 2, &flat, preset.closed))
}
