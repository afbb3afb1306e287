//! `bcifs surface`: a user's polygon mesh subdivided by Doo-Sabin,
//! Catmull-Clark, Loop or √3: the limit surface, or with `--net` the
//! control mesh.

use std::path::PathBuf;

use anyhow::bail;
use bcifs::render::mesh_automaton;
use bcifs::render::write_atomic;
use bcifs::render::{MeshJob, render_mesh, rule_weights};
use bcifs::render::{PolyMesh, Scheme, read_mesh};

use super::render::print_report;
use crate::cli::common::parse_params;

/// The arguments of `bcifs surface`.
#[derive(clap::Args)]
pub struct SurfaceArgs {
    /// The control mesh: an OBJ or OFF file (faces of any degree, closed or with boundary).
    pub mesh: PathBuf,
    /// The scheme: doo-sabin, catmull-clark (any polygons), loop or sqrt3 (triangles).
    #[arg(long, value_enum)]
    pub scheme: Scheme,
    /// Split faces of more than three vertices into fans of triangles first (for loop and sqrt3).
    #[arg(long)]
    pub triangulate: bool,
    /// Rule weights, NAME=VALUE. Doo-Sabin: alpha (the corner), beta (the next), gamma (the previous),
    /// defaults 9/16, 3/16, 3/16 (the opposite corner gets the rest). Loop: w (each end of an edge,
    /// default 3/8) and sigma (the vertex eigenvalue relative to Loop's, default 1).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Subdivision steps.
    #[arg(long, default_value_t = 4)]
    pub depth: usize,
    /// Write the control mesh after DEPTH steps (as CGAL's Subdivision_method_3 makes it) instead of the limit surface.
    #[arg(long)]
    pub net: bool,
    /// Write the mesh as a generated BC-IFS automaton (states, exact matrices in the weights, constraints)
    /// to -o FILE.toml or to standard output; `bcifs solve` and `bcifs check` read it.
    #[arg(long, conflicts_with = "net")]
    pub print: bool,
    /// Output file: .obj, .off, .ply, .stl, .glb, .png or .svg (in the input file's axes, glTF Y-up; pictures seen from --view); with --print, .toml.
    #[arg(short, long, required_unless_present = "print")]
    pub output: Option<PathBuf>,
    /// The options of pictures and files.
    #[command(flatten)]
    pub keys: crate::cli::keys::KeyArgs<crate::cli::keys::MeshKeys>,
    /// The input's texture coordinates: `keep` them, subdivided face-varying with linear seams
    /// (Catmull-Clark and Loop, into OBJ and glTF), or `none`.
    #[arg(long, value_enum, default_value_t = UvMode::Keep)]
    pub uv: UvMode,
}

/// What happens to the input's texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum UvMode {
    /// Subdivided with the surface.
    Keep,
    /// Dropped.
    None,
}

/// `bcifs surface`.
pub fn run(out: &mut String, args: SurfaceArgs) -> anyhow::Result<u8> {
    let started = std::time::Instant::now();
    let scheme = args.scheme;
    let weights = rule_weights(scheme, &parse_params(&args.params)?)?;
    let mut mesh = read_mesh(&args.mesh)?;
    if args.triangulate {
        mesh = mesh.triangulated();
    }
    // The file's own name for its object (`o`, else `g`), else the file's.
    let stem = || args.mesh.file_stem().map_or("mesh".into(), |s| s.to_string_lossy().to_string());
    let name = mesh.name.clone().unwrap_or_else(stem);
    let job = MeshJob { scheme, depth: args.depth, weights, net: args.net, name, uv: args.uv == UvMode::Keep };
    if args.print {
        return print_automaton(out, &args, &mesh, &job, started);
    }
    let Some(output) = args.output.clone() else { bail!("give the output file with -o") };
    crate::cli::common::check_output(&output, &crate::cli::common::render_formats(), &[&args.mesh])?;
    let options = crate::cli::render::options(&args.keys)?;
    let report = render_mesh(&mesh, &job, &options, &output)?;
    let label =
        format!("{} ({}, depth {}{})", job.name, scheme.name(), args.depth, if args.net { ", net" } else { "" });
    print_report(&report, &label, &output, started);
    Ok(0)
}

/// `--print`: the mesh as a generated automaton, to `-o FILE.toml` or
/// standard output (`out`, written by the caller, which takes a closed pipe calmly).
fn print_automaton(
    out: &mut String,
    args: &SurfaceArgs,
    mesh: &PolyMesh,
    job: &MeshJob,
    started: std::time::Instant,
) -> anyhow::Result<u8> {
    if let Some(why) = bcifs::render::check_weights(mesh, job.weights)? {
        eprintln!("warning: {why}");
    }
    let design = mesh_automaton(mesh, job.scheme, job.weights)?;
    let text = bcifs::render::write_design(&design);
    let Some(output) = &args.output else {
        out.push_str(&text);
        return Ok(0);
    };
    let ext = output.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if ext != "toml" {
        bail!("--print writes an automaton file: give -o FILE.toml (or no -o for standard output), not .{ext}");
    }
    write_atomic(output, text.as_bytes()).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", output.display()))?;
    eprintln!(
        "{}: {} states, {} arrows, {} constraints, {} weights → {} ({:.2} s)",
        design.name(),
        design.automaton().states().count(),
        design.automaton().arrows().count(),
        design.automaton().constraints().len(),
        design.declared().len(),
        output.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(0)
}
