//! A design rendered to a file: the route by format and options.

use std::path::Path;

use super::checked::{FileWriter, WriteSettings, write_error};
use super::job::{Job, Route, route};
use super::options::Options;
use super::output::{Format, RenderError, Report, check_room};
use super::picture::deterministic_image;
use super::shape::write_shape_text;
use crate::design::Design;
use crate::eval::{Depth, EvalError, RandomSettings};
use crate::geometry::{Shape, Sink};

/// Evaluates a design in memory (deterministic or random, as the options
/// say; a surface thickened into a shell when they give a thickness);
/// warnings (undecided convergence) go to `warnings`.
///
/// # Errors
/// See [`RenderError`].
pub fn evaluate_design(design: &Design, options: &Options, warnings: &mut Vec<String>) -> Result<Shape, RenderError> {
    shaped(&Job::new(design, options)?, warnings)
}

/// The job's output in memory: its shell, its colours, or the plain evaluation.
fn shaped(job: &Job, warnings: &mut Vec<String>) -> Result<Shape, RenderError> {
    if let Some(shell) = shell(job, warnings)? {
        return Ok(shell);
    }
    // Coloured by state, level or map: the colours the files get, on the shape.
    if job.options.look.colour.is_some() && job.options.sampling.samples.is_none() {
        return coloured_shape(job, warnings);
    }
    job.evaluate(warnings)
}

/// The job's mesh for printing, its print report ([`crate::report::printed`]:
/// millimetres, what a slicer will not like) and the mesh scaled to it; a
/// mesh that is not a closed 2-manifold refused unless the options allow it.
fn printed(job: &Job, warnings: &mut Vec<String>) -> Result<(Shape, crate::report::PrintReport), RenderError> {
    let mut shape = shaped(job, warnings)?;
    if shape.quads.is_empty() && shape.triangles.is_empty() {
        return Err(RenderError::Unsupported(format!(
            "{}: a print file holds solids (closed surfaces), not curves or points, which this design makes",
            job.name()
        )));
    }
    // The printed file is Z-up: a Y-up mesh file's model stands on its y.
    let up = if job.options.file.coordinates.y_up_input { 1 } else { 2 };
    let style = &job.options.file.print;
    let report = crate::report::printed(&shape, style, up);
    if !report.manifold && !style.allow_non_manifold {
        return Err(RenderError::Unsupported(format!(
            "{}: not a closed, oriented 2-manifold ({}), which a slicer would have to repair; allow non-manifold \
             meshes to write it anyway, or write it as .obj, .ply or .glb",
            job.name(),
            report.warnings.first().map_or("", String::as_str)
        )));
    }
    if report.scale != 1.0 {
        shape.positions.iter_mut().for_each(|x| *x *= report.scale);
    }
    Ok((shape, report))
}

/// A print file: the mesh in memory, checked and sized ([`printed`]); a
/// mesh over the memory budget streamed as it is (a lattice solid's
/// boundary is closed by construction), with a note that it was not checked.
fn print_file(job: &Job, format: Format, out: &Path, report: &mut Report) -> Result<(), RenderError> {
    let options = &job.options;
    let plain = options.file.thickness.is_none() && options.look.colour.is_none();
    if let (true, Depth::Fixed(k)) = (plain, options.sampling.depth) {
        let ev = job.evaluator(&mut Vec::new())?;
        if ev.estimate_bytes(k) > options.budget.memory as u128 {
            if options.file.print.size.is_some() || options.file.print.scale.is_some_and(|s| s != 1.0) {
                return Err(RenderError::TooBig(format!(
                    "{}: sizing a print holds its mesh in memory, over the memory budget at depth {k}: raise the budget or lower the depth",
                    job.name()
                )));
            }
            report.notes.push(
                "streamed over the memory budget: the print checks (pieces, bed, walls) were not made; a model unit is a millimetre".into(),
            );
            return stream_file(job, format, &out.into(), report);
        }
    }
    let (shape, print) = printed(job, &mut report.warnings)?;
    let written = super::shape::write_shape_options(&shape, job.name(), options, out)?;
    report.vertices = written.vertices;
    report.faces = written.faces;
    report.bytes = written.bytes;
    report.warnings.extend(print.warnings.iter().cloned());
    report.print = Some(print);
    Ok(())
}

/// Renders a design to `out`, the format chosen by its extension: `.obj`
/// and `.off` are streamed (any depth, any number of points), `.png` is
/// drawn while curves, points and chaos games are evaluated (surfaces from
/// memory, at the depth whose quads are below a pixel), `.svg` from memory.
///
/// # Errors
/// See [`RenderError`]; nothing is left half-written.
pub fn render(design: &Design, options: &Options, out: &Path) -> Result<Report, RenderError> {
    let format = Format::of(out)?;
    let job = &Job::new(design, options)?;
    let options = &job.options;
    let mut report = Report { format: Some(format), ..Report::default() };
    warn_unused(options, format, &mut report.warnings);
    match route(format, options) {
        Route::Print => print_file(job, format, out, &mut report)?,
        Route::Shell => shell_file(job, out, &mut report)?,
        Route::Coloured => coloured_file(job, format, out, &mut report)?,
        Route::Flame => flame_file(job, out, &mut report)?,
        Route::Stream => stream_file(job, format, &out.into(), &mut report)?,
        Route::Picture => {
            let png = png_file(job, crate::export::Compression::Small, &mut report)?;
            crate::export::write_atomic(out, &png).map_err(write_error(options, out))?;
            report.bytes = png.len() as u64;
        }
        Route::Memory => {
            let mut shape = job.evaluate(&mut report.warnings)?;
            let duplicates = dedup(&mut shape, options, &mut report.warnings);
            options.check_cancel()?;
            let written = write_shape_text(&shape, job.name(), &options.raster(), out, &options.png_text(job.name()))?;
            report.vertices = written.vertices;
            report.faces = written.faces;
            report.bytes = written.bytes;
            report.duplicates = duplicates;
        }
    }
    Ok(finished(options, report))
}

/// The depth and the empty-output warning every report gives.
fn finished(options: &Options, mut report: Report) -> Report {
    if let (None, Depth::Fixed(k), None) = (options.sampling.samples, options.sampling.depth, report.depth) {
        report.depth = Some(k);
    }
    if report.vertices == 0 {
        report.warnings.push("the output is empty (every arrow dropped, or nothing to draw)".into());
    }
    report
}

/// Renders a design in `format` in memory: the bytes [`render`] writes to
/// a file of that format, for a page or a notebook that wants them, not a
/// file. Meshes, curves and point clouds (OBJ, OFF, PLY, STL, glTF) are
/// streamed into the buffer as into a file (its side files, where a format
/// needs them, in the temporary directory); PNG is [`picture_png`]'s.
/// Coloured and deduplicated clouds, SVG and flam3 go to files only.
///
/// ```
/// use bcifs::render::{Format, Options, render, render_bytes};
/// let design = bcifs::builtin_design("doo_sabin_torus").unwrap();
/// let options = Options::default().with_depth(3);
/// let (report, glb) = render_bytes(&design, &options, Format::Glb)?;
/// assert!(glb.starts_with(b"glTF") && report.bytes as usize == glb.len());
/// let file = std::env::temp_dir().join(format!("bcifs-bytes-doc-{}.glb", std::process::id()));
/// render(&design, &options, &file)?;
/// assert_eq!(std::fs::read(&file)?, glb);
/// # std::fs::remove_file(&file)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`render`]; [`RenderError::Unsupported`] for the outputs made in files only.
pub fn render_bytes(design: &Design, options: &Options, format: Format) -> Result<(Report, Vec<u8>), RenderError> {
    match route(format, options) {
        Route::Picture => picture_png(design, options, crate::export::Compression::Small),
        Route::Stream => {
            let job = &Job::new(design, options)?;
            let mut report = Report { format: Some(format), ..Report::default() };
            warn_unused(&job.options, format, &mut report.warnings);
            let buffer = crate::export::MemoryFile::new();
            stream_file(job, format, &crate::export::Target::Memory(buffer.clone()), &mut report)?;
            Ok((finished(&job.options, report), buffer.take()))
        }
        Route::Print => {
            let job = &Job::new(design, options)?;
            let mut report = Report { format: Some(format), ..Report::default() };
            let (shape, print) = printed(job, &mut report.warnings)?;
            let buffer = crate::export::MemoryFile::new();
            let raster = job.options.raster();
            let settings = WriteSettings {
                coordinates: job.options.file.coordinates,
                threads: 1,
                raster: &raster,
                ascii: job.options.file.ascii,
            };
            let target = crate::export::Target::Memory(buffer.clone());
            let io = write_error(&job.options, target.path());
            report.bytes = super::shape::write_geometry(&shape, job.name(), &settings, format, &target, &io)?;
            (report.vertices, report.faces) = (shape.vertex_count(), shape.quads.len() + shape.triangles.len());
            report.warnings.extend(print.warnings.iter().cloned());
            report.print = Some(print);
            Ok((finished(&job.options, report), buffer.take()))
        }
        _ => Err(RenderError::Unsupported(format!(
            "a .{} output is written to a file (render), not made in memory",
            format.extension()
        ))),
    }
}

/// Options given that this output does not use, as warnings.
fn warn_unused(options: &Options, format: Format, warnings: &mut Vec<String>) {
    let ext = format.extension();
    let (look, chaos) = (&options.look, options.sampling.samples.is_some());
    let colours = look.palette.is_some() || chaos && !look.arrow_colours.is_empty();
    let tone = look.tone.blur > 0.0 || look.tone.vibrancy != 1.0 || look.tone.background.is_some();
    let picture = matches!(format, Format::Png | Format::Flame);
    if (colours || tone) && !chaos && format != Format::Flame {
        warnings.push("the palette, the arrows' colours, the blur, the vibrancy and the background shape chaos-game pictures (samples); this render ignores them".into());
    } else if tone && !picture {
        warnings.push(format!(
            "the blur, the vibrancy and the background shape density pictures (.png); the .{ext} file ignores them"
        ));
    } else if colours && !picture && !format.has_colours() {
        warnings.push(format!("the palette and the arrows' colours colour density pictures (.png) and the points of .obj, .ply and .glb files; the .{ext} file ignores them"));
    }
    if options.file.uv && !format.has_uvs() {
        warnings
            .push(format!("texture coordinates (uv) are written into OBJ and glTF files; the .{ext} output has none"));
    }
    if options.file.coordinates.precision.is_some() && !format.has_digits() {
        warnings.push(format!("the precision sets the digits of text coordinates; the .{ext} output ignores it"));
    }
}

/// Drops the exact duplicate points of `shape` when the options ask for
/// it: how many, or `None` (not asked, or not a point cloud: a warning).
fn dedup(shape: &mut Shape, options: &Options, warnings: &mut Vec<String>) -> Option<usize> {
    if !options.file.dedup {
        return None;
    }
    let dropped = shape.dedup_points();
    if dropped.is_none() {
        warnings.push("deduplication applies to point clouds; this output has lines or faces, kept as is".into());
    }
    dropped
}

/// OBJ or OFF, streamed: the chaos game a few chains at a time, a
/// deterministic evaluation in two passes (vertices, then elements), or a
/// cloud to deduplicate from memory.
fn stream_file(job: &Job, format: Format, out: &crate::export::Target, report: &mut Report) -> Result<(), RenderError> {
    let (options, name) = (&job.options, job.name());
    let (threads, raster) = (options.budget.thread_count(), options.raster());
    let io = write_error(options, out.path());
    let settings =
        WriteSettings { coordinates: options.file.coordinates, threads, raster: &raster, ascii: options.file.ascii };
    let mut writer = FileWriter::create(out, format, &settings)?;
    if let (Some(random), false) = (options.random_settings(), options.file.dedup) {
        let game = job.game(&random)?;
        check_room(out, random.points as u128 * (3 + 22 * game.dim() as u128), 0, options.budget.output)?;
        let mut sink = writer.checked(&options.cancel);
        sink.object(name).map_err(&io)?;
        match &options.look.palette {
            // Each point coloured as the density pictures colour it, in the formats that hold colours.
            Some(palette) if format.has_colours() => game
                .stream_coloured(random.points, |xs, cs| {
                    sink.colours(&cs.iter().map(|c| palette.colour(*c)).collect::<Vec<_>>())?;
                    sink.vertices(game.dim(), xs, None)
                })
                .map_err(&io)?,
            _ => game.stream(random.points, |xs| sink.vertices(game.dim(), xs, None)).map_err(&io)?,
        }
        report.vertices = random.points;
    } else if options.sampling.samples.is_some() || options.file.dedup {
        let mut shape = job.evaluate(&mut report.warnings)?;
        report.duplicates = dedup(&mut shape, options, &mut report.warnings);
        let mut sink = writer.checked(&options.cancel);
        if shape.objects.is_empty() {
            sink.object(name).map_err(&io)?;
        }
        shape.replay(&mut sink).map_err(&io)?;
        report.vertices = shape.vertex_count();
        report.faces = shape.quads.len() + shape.triangles.len();
    } else {
        let ev = job.evaluator(&mut report.warnings)?;
        if options.file.uv && ev.polylines().is_some() {
            report
                .warnings
                .push("texture coordinates (uv) are given to surfaces; this curve or point set has none".into());
        }
        if let Depth::Fixed(k) = options.sampling.depth {
            check_room(out, ev.estimate_obj_bytes(k), 0, options.budget.output)?;
        }
        let eval_error = |e: EvalError| match e {
            EvalError::Io(e) => io(e),
            other => other.into(),
        };
        (report.vertices, report.faces) = match &mut writer {
            // Vertices, then elements: two streamed passes, no side file of elements.
            FileWriter::Obj(w) => {
                crate::export::write_two_passes(w, |sink| ev.stream(sink), Some(&options.cancel)).map_err(eval_error)?
            }
            _ => {
                let mut sink = writer.checked(&options.cancel);
                ev.stream(&mut sink).map_err(eval_error)?;
                (sink.vertices, sink.faces)
            }
        };
    }
    report.bytes = writer.finish(out)?;
    Ok(())
}

/// The print report ([`PrintReport`](crate::report::PrintReport)) of the
/// mesh [`render`] writes for `design` with `options` (evaluated in memory,
/// within the options' memory budget): its volume, area, box, pieces,
/// genus, and whether it is closed and oriented.
///
/// # Errors
/// As [`render`]'s evaluation; a design that makes no face.
pub fn print_report(design: &Design, options: &Options) -> Result<crate::report::PrintReport, RenderError> {
    let job = Job::new(design, options)?;
    let allowed = Job {
        options: Options {
            file: super::options::FileStyle {
                print: crate::report::PrintStyle { allow_non_manifold: true, ..job.options.file.print },
                ..job.options.file
            },
            ..job.options.clone()
        },
        ..job
    };
    Ok(printed(&allowed, &mut Vec::new())?.1)
}

/// The surface evaluated in memory, thickened into a shell of the options'
/// thickness ([`crate::mesh::thicken`]).
fn shell(job: &Job, warnings: &mut Vec<String>) -> Result<Option<Shape>, RenderError> {
    let Some(t) = job.options.file.thickness else { return Ok(None) };
    let shape = job.evaluate(warnings)?;
    job.options.check_cancel()?;
    crate::mesh::thicken(&shape, t).map(Some).map_err(|e| RenderError::Unsupported(format!("{}: {e}", job.name())))
}

/// A surface written as a shell of the options' thickness.
fn shell_file(job: &Job, out: &Path, report: &mut Report) -> Result<(), RenderError> {
    let Some(shell) = shell(job, &mut report.warnings)? else { return Ok(()) };
    let written = super::shape::write_shape_options(&shell, job.name(), &job.options, out)?;
    report.vertices = written.vertices;
    report.faces = written.faces;
    report.bytes = written.bytes;
    Ok(())
}

/// A deterministic evaluation coloured by state, level or map
/// ([`Look::colour`](super::Look::colour)), evaluated in memory and written with its colours.
fn coloured_file(job: &Job, format: Format, out: &Path, report: &mut Report) -> Result<(), RenderError> {
    let options = &job.options;
    if options.look.colour.is_none() {
        return Ok(());
    }
    if !format.has_colours() {
        report.warnings.push(format!(
            "vertex colours are written into .obj, .ply and .glb files; the .{} file has none",
            format.extension()
        ));
    }
    let shape = coloured_shape(job, &mut report.warnings)?;
    let written = super::shape::write_shape_options(&shape, job.name(), options, out)?;
    report.vertices = written.vertices;
    report.faces = written.faces;
    report.bytes = written.bytes;
    Ok(())
}

/// The deterministic evaluation coloured by state, level or map
/// ([`Look::colour`](super::Look::colour)) in memory, its vertices' colours
/// from the palette (rainbow by default).
fn coloured_shape(job: &Job, warnings: &mut Vec<String>) -> Result<Shape, RenderError> {
    let options = &job.options;
    let mut ev = job.evaluator(warnings)?;
    let Some(mode) = options.look.colour else { return job.evaluate(warnings) };
    let random = options.colour_settings(0);
    let (mut shape, coordinates) = ev.evaluate_coloured(&job.automaton, mode, &random)?;
    options.check_cancel()?;
    let rainbow = crate::export::Palette::named("rainbow");
    let palette = options.look.palette.as_ref().or(rainbow.as_ref());
    shape.colours = match palette {
        Some(p) => coordinates.iter().map(|&c| p.colour(c)).collect(),
        None => Vec::new(),
    };
    Ok(shape)
}

/// A `.flame` file of the chaos game (its settings, or the defaults), framed as its density picture.
fn flame_file(job: &Job, out: &Path, report: &mut Report) -> Result<(), RenderError> {
    let (options, design) = (&job.options, job.design);
    let mut random = options.random_settings().unwrap_or_default();
    random.progress = None;
    let game = job.game(&random)?;
    let (palette, raster) = (options.look.palette.as_ref(), options.raster());
    let ifs = game.plain_ifs().map_err(|why| RenderError::Unsupported(format!("{}: {why}", design.name())))?;
    let frame = crate::export::picture_frame(&game, random.points, &raster);
    let look = (&raster, &options.look.tone, palette);
    crate::export::write_flame(out, design.name(), &ifs, frame, look, random.points).map_err(|e| match e {
        crate::export::FlameError::NotPlain(why) => RenderError::Unsupported(format!("{}: {why}", design.name())),
        crate::export::FlameError::Io(path, e) => RenderError::Io(path, e),
    })?;
    report.vertices = random.points;
    report.bytes = std::fs::metadata(out).map_or(0, |m| m.len());
    Ok(())
}

/// The picture that [`render`] writes to a `.png`, in memory and RGB (the
/// same pixels as the file without `--transparent`): a chaos game's density
/// picture when `options.sampling.samples` asks for one, the deterministic evaluation
/// drawn otherwise. For front ends that show pixels (the explorer encodes
/// them for the browser itself).
///
/// # Errors
/// As [`render`]; per-point colours (`options.colour`) and deduplicated
/// clouds are written by [`render`] only.
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("koch").unwrap();
/// let options = bcifs::render::Options::default();
/// let img = bcifs::render::picture(&design, &options.clone().with_size(64, 48)).unwrap();
/// assert_eq!(img.dimensions(), (64, 48));
/// assert!(img.pixels().any(|p| p.0 != [255, 255, 255]));
/// ```
pub fn picture(design: &Design, options: &Options) -> Result<image::RgbImage, RenderError> {
    Ok(png_image(&picture_job(design, options)?, &mut Report::default())?.0)
}

/// The job of a picture made in memory; coloured and deduplicated clouds
/// are drawn into files only.
fn picture_job<'a>(design: &'a Design, options: &Options) -> Result<Job<'a>, RenderError> {
    if route(Format::Png, options) != Route::Picture {
        return Err(RenderError::Unsupported(
            "coloured and deduplicated clouds are drawn by render() into a .png file".into(),
        ));
    }
    Job::new(design, options)
}

/// The density picture of the chaos game that [`render`] writes to a PNG
/// (`options.sampling.samples` samples, `options.look`), in
/// memory: for front ends that want pixels, not a file.
///
/// # Errors
/// No chaos game asked (`options.sampling.samples` is `None`), parameters, a system
/// that does not converge, a picture over the memory limit, or
/// [`RenderError::Cancelled`].
pub fn density(design: &Design, options: &Options) -> Result<image::RgbImage, RenderError> {
    let random = options.random_settings().ok_or_else(|| {
        RenderError::Unsupported("a density picture needs chaos-game samples (the samples option)".into())
    })?;
    density_with(&Job::new(design, options)?, &random)
}

/// [`density`] of a job with the chaos game's settings given.
fn density_with(job: &Job, random: &RandomSettings) -> Result<image::RgbImage, RenderError> {
    let (game, options) = (job.game(random)?, &job.options);
    let look = &options.look;
    let img = crate::export::density_image(&game, random.points, &options.raster(), &look.tone, look.palette.as_ref())?;
    // A cancelled fold stops early: its partial picture is not returned.
    options.check_cancel()?;
    Ok(img)
}

/// The PNG [`render`] writes into a `.png` file (a deterministic picture, or
/// the chaos game's density when `options.sampling.samples` is set: its text chunks,
/// its matte when transparent), in memory: for a page or a notebook that
/// wants the file's bytes, not a file. Coloured and deduplicated clouds are
/// written by [`render`] only.
///
/// ```
/// use bcifs::export::Compression;
/// let design = bcifs::builtin_design("koch").unwrap();
/// let options = bcifs::render::Options::default().with_size(64, 48);
/// let (report, png) = bcifs::render::picture_png(&design, &options, Compression::Fast)?;
/// assert_eq!(report.bytes as usize, png.len());
/// let img = image::load_from_memory(&png)?.to_rgb8();
/// assert_eq!(img, bcifs::render::picture(&design, &options)?);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`picture`].
pub fn picture_png(
    design: &Design,
    options: &Options,
    compression: crate::export::Compression,
) -> Result<(Report, Vec<u8>), RenderError> {
    let job = &picture_job(design, options)?;
    let mut report = Report { format: Some(Format::Png), ..Report::default() };
    warn_unused(&job.options, Format::Png, &mut report.warnings);
    let png = png_file(job, compression, &mut report)?;
    report.bytes = png.len() as u64;
    Ok((finished(&job.options, report), png))
}

/// The bytes of a job's `.png`: its pixels, text chunks and matte, encoded.
fn png_file(job: &Job, compression: crate::export::Compression, report: &mut Report) -> Result<Vec<u8>, RenderError> {
    let (img, matte) = png_image(job, report)?;
    crate::export::png_bytes(&img, &job.options.png_text(job.name()), matte, compression)
        .map_err(|e| RenderError::Unsupported(format!("cannot encode the picture: {e}")))
}

/// The pixels of a `.png` output and its matte (a transparent picture's):
/// the chaos game's density (the samples counted per pixel, never stored),
/// or a deterministic picture.
fn png_image(job: &Job, report: &mut Report) -> Result<(image::RgbImage, Option<crate::export::Matte>), RenderError> {
    let look = &job.options.look;
    match job.options.random_settings() {
        Some(random) => {
            let img = density_with(job, &random)?;
            let matte = look.transparent.then(|| look.tone.matte(look.palette.is_some()));
            report.vertices = random.points;
            Ok((img, matte))
        }
        None => deterministic_image(job, report),
    }
}
