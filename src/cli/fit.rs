//! `bcifs fit`: a family's free parameters fitted to a target.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;

use super::common::{check_output, interrupt, load, progress_bar};

/// `bcifs fit DESIGN --to FILE | --dimension D | --angle DEG | --porosity P`.
#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// The automaton file (TOML), or the name of a shipped automaton.
    pub design: String,
    /// Points or a mesh the shape should pass near (OBJ, OFF, PLY: their vertices), or a picture
    /// (PNG: its largest shape's outline, placed over the default member's bounding box).
    #[arg(long = "to", value_name = "FILE")]
    pub to: Option<PathBuf>,
    /// The attractor's dimension to reach (its similarity dimension; box-counting where it has none).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub dimension: Option<f64>,
    /// A curve's junction angle to reach, in degrees (`analyze curve`).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub angle: Option<f64>,
    /// The porosity to reach: the share of the start cell left empty at the fit's depth (at most 4).
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    pub porosity: Option<f64>,
    /// The depth of the shape's points (default: the one whose vertices are as many as the target's).
    #[arg(long)]
    pub depth: Option<usize>,
    /// Fit the model's control points too (written to `-o` with the parameters).
    #[arg(long)]
    pub control_points: bool,
    /// Starts run to the end: the defaults, then the best of a sample of the convergence ranges.
    #[arg(long, default_value_t = 4)]
    pub starts: usize,
    /// Write the fitted design (its parameters as defaults) to this automaton file (.toml).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Print the report as JSON: parameters, residual, converges…
    #[arg(long)]
    pub json: bool,
}

/// Runs `bcifs fit`.
pub fn run(out: &mut String, args: FitArgs) -> Result<u8> {
    let design = load(&args.design)?;
    if let Some(o) = &args.output {
        let inputs: Vec<&Path> = [Path::new(&args.design)].into_iter().chain(args.to.as_deref()).collect();
        check_output(o, &["toml"], &inputs)?;
    }
    let points = match &args.to {
        Some(path) => bcifs::render::read_target(path, &design)?,
        None => Vec::new(),
    };
    let free_pose = args.to.as_deref().is_some_and(|p| bcifs::render::is_picture(&p.to_string_lossy()));
    let target = bcifs::render::FitTarget {
        points,
        dimension: args.dimension,
        angle: args.angle,
        porosity: args.porosity,
        free_pose,
    };
    let settings = bcifs::render::FitOptions {
        depth: args.depth,
        starts: args.starts,
        control_points: args.control_points,
        cancel: interrupt().clone(),
        progress: progress_bar(),
        ..Default::default()
    };
    let report = bcifs::render::fit(&design, &target, &settings)?;
    if let Some(o) = &args.output {
        let fitted = bcifs::render::fitted_design(&design, &report)?;
        bcifs::render::write_atomic(o, bcifs::render::write_design(&fitted).as_bytes())
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", o.display()))?;
    }
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&report.to_json())?)?;
        return Ok(0);
    }
    let values: Vec<String> = report.parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
    writeln!(out, "{}: {}", report.automaton, values.join(", "))?;
    let distance = report.distance.map(|d| format!(", points {d:.3e} apart (RMS, both ways)")).unwrap_or_default();
    writeln!(out, "  residual {:.3e}{distance}, depth {}", report.residual, report.depth)?;
    for n in &report.numbers {
        let within = if n.within > 0.0 { format!(", good to ±{}", n.within) } else { String::new() };
        let reached = if n.reached { "met" } else { "missed" };
        writeln!(out, "  {}: {} (asked {}{within}: {reached})", n.name, n.value, n.target)?;
    }
    let verdict = if report.converges { "converges (proven)" } else { "not proven to converge" };
    writeln!(out, "  {verdict}: JSR upper bound {:.4}", report.jsr_upper)?;
    writeln!(
        out,
        "  {} iterations from {} start(s){}",
        report.iterations,
        report.starts,
        if report.interrupted { ", interrupted: the best so far" } else { "" }
    )?;
    if let Some((scale, shift)) = &report.pose {
        writeln!(
            out,
            "  pose: the member scaled by {scale:.6} after a shift of {shift:?} lies on the picture's outline"
        )?;
    }
    if let Some(why) = &report.reason {
        writeln!(out, "  note: {why}")?;
    }
    Ok(0)
}
