//! A polygon mesh subdivided into a file: streamed (OBJ, OFF) or drawn
//! (PNG, SVG), in the input file's axes (a mesh file is Y-up).

use std::path::Path;

use super::checked::{Checked, FileWriter, WriteSettings, write_error};
use super::options::Options;
use super::output::{Format, RenderError, Report, check_disk};
use super::shape::write_shape_text;
use crate::analysis::{WeightsError, WeightsVerdict, check_loop_weights, check_quad_weights};
use crate::export::{NormalSpill, Replay};
use crate::geometry::Sink;
use crate::mesh::{LoopWeights, PolyMesh, QuadWeights, RuleWeights, Scheme, SubdivideError, Subdivision, Written};

/// A subdivision of a polygon mesh to render.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshJob {
    /// The scheme.
    pub scheme: Scheme,
    /// Steps.
    pub depth: usize,
    /// Rule weights (`None`: the classic rules); see [`rule_weights`].
    pub weights: Option<RuleWeights>,
    /// The control net after `depth` steps instead of the limit surface.
    pub net: bool,
    /// The object's name in the file (empty: the mesh's own, [`PolyMesh::name`], else `mesh`).
    pub name: String,
    /// Keep the input's texture coordinates (Catmull-Clark and Loop), face-varying.
    pub uv: bool,
}

impl MeshJob {
    /// The limit surface of `scheme` after `depth` steps, classic weights, named as the mesh is.
    pub fn new(scheme: Scheme, depth: usize) -> MeshJob {
        MeshJob { scheme, depth, weights: None, net: false, name: String::new(), uv: true }
    }
}

/// Bytes per face of a written mesh, for the size estimate: four indices and
/// about one vertex of three shortest round-trip coordinates (an upper bound
/// for quads, generous for triangles).
const BYTES_PER_FACE: u128 = 4 * 9 + 3 * 22 + 8;

/// Rule weights from named values (others: classic): `alpha`, `beta`,
/// `gamma` for Doo-Sabin's quad rule, `w`, `sigma` for Loop's; `None`
/// when no value is given.
///
/// # Errors
/// A name the scheme does not have (with the list), or a scheme without weights.
pub fn rule_weights(scheme: Scheme, params: &[(String, f64)]) -> Result<Option<RuleWeights>, RenderError> {
    if params.is_empty() {
        return Ok(None);
    }
    let unknown = |name: &str, names: &[&str]| {
        let list: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
        RenderError::Unsupported(format!(
            "`{name}` is not a parameter of {}: the parameters are {}",
            scheme.name(),
            list.join(", ")
        ))
    };
    let set = |slots: &mut [(&str, &mut f64)]| -> Result<(), RenderError> {
        for (name, value) in params {
            let names: Vec<&str> = slots.iter().map(|(n, _)| *n).collect();
            let Some((_, slot)) = slots.iter_mut().find(|(n, _)| n == name) else {
                return Err(unknown(name, &names));
            };
            **slot = *value;
        }
        Ok(())
    };
    match scheme {
        Scheme::DooSabin => {
            let mut w = QuadWeights::CLASSIC;
            set(&mut [("alpha", &mut w.alpha), ("beta", &mut w.beta), ("gamma", &mut w.gamma)])?;
            Ok(Some(w.into()))
        }
        Scheme::Loop => {
            let mut w = LoopWeights::CLASSIC;
            set(&mut [("w", &mut w.w), ("sigma", &mut w.sigma)])?;
            Ok(Some(w.into()))
        }
        _ => Err(RenderError::Unsupported(format!(
            "{} has no parameters (the weights are the classic rules)",
            scheme.name()
        ))),
    }
}

/// Checks rule weights on `mesh` before subdividing: `Some(why)` when
/// their convergence is undecided (a warning to show), `None` when proved
/// or classic.
///
/// # Errors
/// [`WeightsError`] when they diverge or are not finite.
pub fn check_weights(mesh: &PolyMesh, weights: Option<RuleWeights>) -> Result<Option<String>, WeightsError> {
    let verdict = match weights {
        Some(RuleWeights::Quad(w)) => check_quad_weights(&w)?,
        Some(RuleWeights::Loop(w)) => check_loop_weights(&w, &mesh.interior_valences())?,
        None => return Ok(None),
    };
    Ok(match verdict {
        WeightsVerdict::Undecided(why) => Some(why),
        WeightsVerdict::Converges => None,
    })
}

/// Outputs with vertex normals are made in memory up to this estimate
/// ([`PolyMesh::estimate`]: about two million faces, which take a third to a
/// half of it, under 200 MiB), larger ones streamed through side files
/// ([`NormalSpill`]): Catmull-Clark's and Doo-Sabin's depth 9 on the cube
/// are made, Loop's depth 9 on the icosahedron streamed.
const NORMALS_IN_MEMORY: u128 = 384 << 20;

/// Bytes per face of the side files of normals streamed: a vertex's position
/// (about one vertex a face), a face's area vector, its corners and their count.
const SPILL_PER_FACE: u128 = 24 + 24 + 4 * 5;

/// Bytes the normals streamed take once the mesh is made (a quarter for a
/// chunk of faces, the rest for the sums of a block of vertices: the
/// 10.5 million vertices of Loop's depth 10 on the icosahedron in three blocks).
const SPILL_BUDGET: usize = 128 << 20;

/// [`PolyMesh::subdivide_into`] through side files beside `out`,
/// then replayed into `sink` with vertex normals: the numbers and bytes
/// [`PolyMesh::subdivide_smooth_into`] gives, in bounded memory. The faces
/// written to the side files are reported as the first half of `total`.
fn spilled_into(
    mesh: &PolyMesh,
    job: &MeshJob,
    subdivision: &Subdivision,
    out: &Path,
    total: u64,
    options: &Options,
    sink: &mut dyn Sink,
) -> Result<Written, SubdivideError> {
    let io = SubdivideError::Write;
    let mut spill = NormalSpill::create(out).map_err(io)?;
    let mut checked = Checked::new(&mut spill, &options.cancel).with_progress(options.progress.as_ref(), 0, total);
    let written = mesh.subdivide_into(subdivision, !job.net, &job.name, &mut checked)?;
    let groups = mesh.group_cuts(job.scheme, job.depth, !job.net);
    let budget = SPILL_BUDGET.min(options.budget.memory / 2).max(1 << 20);
    spill.replay(Replay { sink, groups: &groups, cancel: &options.cancel, budget }).map_err(io)?;
    Ok(written)
}

/// The output of `job` on `mesh` in memory (what [`render_mesh`] writes,
/// as a mesh: the net, or the limit surface's points with the net's faces),
/// the rule weights checked first and [`Options`]' memory limit applied:
/// what front ends that want arrays, not files, call. With `job.uv` the
/// input's texture coordinates follow (Catmull-Clark and Loop, as the files
/// have them): the result's [`PolyMesh::texture`], face for face.
///
/// # Errors
/// Diverging weights, or an output over the memory limit.
pub fn subdivide_mesh(mesh: &PolyMesh, job: &MeshJob, options: &Options) -> Result<PolyMesh, RenderError> {
    // A closed mesh is subdivided facing outward, whatever the input's orientation.
    let turned = mesh.outward();
    let mesh = turned.as_ref().unwrap_or(mesh);
    check_weights(mesh, job.weights)?;
    let memory = options.budget.memory;
    let subdivision = Subdivision { scheme: job.scheme, depth: job.depth, weights: job.weights, memory_limit: memory };
    // The steps in memory look at the flag every few thousand faces (Ctrl-C within a tenth of a second).
    let mut out = options.cancel.scope(|| mesh.subdivided(&subdivision, !job.net)).map_err(|e| match e {
        SubdivideError::Write(_) if options.cancel.is_cancelled() => RenderError::Cancelled,
        other => other.into(),
    })?;
    if job.uv {
        let steps = if job.net { job.depth } else { job.depth.max(1) };
        let texture = mesh.texture_after(job.scheme, steps, job.weights);
        out.texture = texture.filter(|t| t.indices.len() == out.indices.len()).map(Box::new);
    }
    Ok(out)
}

/// For each face of [`subdivide_mesh`]'s output for `job`, the input face
/// it comes from ([`PolyMesh::face_sources`]: per-face data follows the
/// scheme as `data[sources[k]]`).
pub fn face_sources(mesh: &PolyMesh, job: &MeshJob) -> Vec<u32> {
    let turned = mesh.outward();
    let mesh = turned.as_ref().unwrap_or(mesh);
    let subdivision =
        Subdivision { scheme: job.scheme, depth: job.depth, weights: job.weights, memory_limit: usize::MAX };
    mesh.face_sources(&subdivision, !job.net)
}

/// Subdivides `mesh` as `job` says and writes it to `out`, the format
/// chosen by its extension: OBJ and OFF streamed (only the net before the
/// last step in memory; the size estimate checked against
/// [`Budget::output`](super::Budget::output) and the disk first), PNG and SVG drawn from
/// memory with [`Options::look`]. Files keep the input's axes (a mesh
/// file is Y-up, and so are the files written).
///
/// # Errors
/// Diverging weights, a net over the memory limit, an output over the size
/// limit, an I/O error or [`RenderError::Cancelled`]; nothing is left half-written.
pub fn render_mesh(mesh: &PolyMesh, job: &MeshJob, options: &Options, out: &Path) -> Result<Report, RenderError> {
    // The steps in memory look at the flag too, not only the writers.
    options.cancel.scope(|| render_mesh_in(mesh, job, options, out))
}

/// A subdivision's error as a render's: a write's (or the flag's) as [`write_error`] says.
fn subdivide_error(options: &Options, out: &Path) -> impl Fn(SubdivideError) -> RenderError {
    let write = write_error(options, out);
    move |e| match e {
        SubdivideError::Write(e) => write(e),
        other => other.into(),
    }
}

fn render_mesh_in(mesh: &PolyMesh, job: &MeshJob, options: &Options, out: &Path) -> Result<Report, RenderError> {
    let format = Format::of(out)?;
    let turned = mesh.outward();
    let mesh = turned.as_ref().unwrap_or(mesh);
    let named;
    let job = if job.name.is_empty() {
        named = MeshJob { name: mesh.name.clone().unwrap_or_else(|| "mesh".into()), ..job.clone() };
        &named
    } else {
        job
    };
    options.check_cancel()?;
    let mut report = Report { format: Some(format), depth: Some(job.depth), ..Report::default() };
    report.warnings.extend(check_weights(mesh, job.weights)?);
    if turned.is_some() {
        report.notes.push("the input's closed faces ran inward (a negative volume): subdivided turned outward".into());
    }
    let memory = options.budget.memory;
    let subdivision = Subdivision { scheme: job.scheme, depth: job.depth, weights: job.weights, memory_limit: memory };
    if matches!(format, Format::Png | Format::Svg) {
        let shape = mesh.subdivided(&subdivision, !job.net).map_err(subdivide_error(options, out))?;
        let shape = shape.to_shape(&job.name);
        options.check_cancel()?;
        let mut text = options.png_text(&job.name);
        if let Some((_, comment)) = text.iter_mut().find(|(key, _)| key == "Comment") {
            *comment = format!("{} depth {}{}", job.scheme.name(), job.depth, if job.net { ", net" } else { "" });
        }
        let written = write_shape_text(&shape, &job.name, &options.raster().with_y_up(true), out, &text)?;
        return Ok(Report { warnings: report.warnings, depth: report.depth, ..written });
    }
    let (faces, in_memory) = mesh.estimate(job.scheme, job.depth);
    // Vertex normals need every face around a vertex: small outputs are made in memory, large ones
    // streamed through side files (the same numbers); texture coordinates only in memory.
    let textured = job.uv && format.has_uvs() && mesh.texture().is_some();
    let follows = matches!(job.scheme, Scheme::CatmullClark | Scheme::Loop);
    let smooth = format.has_normals()
        && (in_memory <= NORMALS_IN_MEMORY.min(memory as u128) || textured && follows && in_memory <= memory as u128);
    let spilled = format.has_normals() && !smooth;
    let side = if spilled { faces.saturating_mul(SPILL_PER_FACE) } else { 0 };
    check_disk(out, faces.saturating_mul(BYTES_PER_FACE), side, options.budget.output)?;
    let coordinates = crate::export::Coordinates { y_up_input: true, ..options.file.coordinates };
    let (threads, raster) = (options.budget.thread_count(), options.raster());
    let settings = WriteSettings { coordinates, threads, raster: &raster, ascii: options.file.ascii };
    let mut writer = FileWriter::create(&crate::export::Target::from(out), format, &settings)?;
    // Progress: the faces written against the estimate (streamed normals: the side files' half, then the file's).
    let total = u64::try_from(faces).unwrap_or(u64::MAX);
    let (total, done) = if spilled { (total.saturating_mul(2), total) } else { (total, 0) };
    let mut sink = writer.checked(&options.cancel).with_progress(options.progress.as_ref(), done, total);
    if textured && !follows {
        report.notes.push(format!(
            "texture coordinates follow Catmull-Clark and Loop, whose faces split the input's; {}'s faces come from edges and vertices too: the output has none",
            job.scheme.name()
        ));
    } else if textured && !smooth {
        report.notes.push(format!(
            "texture coordinates are written by the output made in memory, which would take {:.1} GiB, over the in-memory limit of {:.1} GiB (the memory budget): this streamed output has none",
            in_memory as f64 / f64::from(1u32 << 30),
            memory as f64 / f64::from(1u32 << 30)
        ));
    }
    let written = if smooth {
        mesh.subdivide_smooth_into(&subdivision, !job.net, job.uv && format.has_uvs(), &job.name, &mut sink)
    } else if spilled {
        spilled_into(mesh, job, &subdivision, out, total, options, &mut sink)
    } else {
        mesh.subdivide_into(&subdivision, !job.net, &job.name, &mut sink)
    };
    let written = written.map_err(subdivide_error(options, out))?;
    report.vertices = written.vertices;
    report.faces = written.faces;
    report.bytes = writer.finish(&crate::export::Target::from(out))?;
    if let Some(progress) = &options.progress {
        // Done, whatever the estimate (digons are not counted).
        progress.report(total, total);
    }
    Ok(report)
}
