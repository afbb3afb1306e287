//! `bcifs contour`: contours as Bézier fractals (the Bézier-fractal contours paper).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Subcommand;

/// What to do with a contour.
#[derive(Subcommand)]
pub enum ContourCommand {
    /// Fit the outer contour of the largest shape of a PNG or JPEG picture with line segments
    /// and quadratic Bézier arcs (threshold, contour tracing, IPAN99 corners, least squares).
    Fit {
        /// The picture.
        image: PathBuf,
        /// The segments file to write (pixels: pixel (c, r)'s centre at (c, r), so the picture's
        /// top-left corner at (-0.5, -0.5); y down).
        #[arg(short, long)]
        output: PathBuf,
        /// Grey level 0-255 between shape and background (default: Otsu's).
        #[arg(long)]
        threshold: Option<u8>,
        /// Largest distance in pixels from the traced contour to its fitted piece.
        #[arg(long, default_value_t = 1.0)]
        tolerance: f64,
        /// IPAN99: shortest triangle side in pixels.
        #[arg(long, default_value_t = 7.0)]
        d_min: f64,
        /// IPAN99: longest triangle side in pixels.
        #[arg(long, default_value_t = 9.0)]
        d_max: f64,
        /// IPAN99: widest corner angle in degrees.
        #[arg(long, default_value_t = 150.0)]
        alpha_max: f64,
        /// Print JSON: corners, segments and the largest distance from the contour to the fit.
        #[arg(long)]
        json: bool,
    },
    /// Print the maps of every segment in the paper's convention (homogeneous row
    /// vectors, [x' y' 1] = [x y 1] F): L, M for arcs (eq. 10), F1, F2 for line segments (eqs. 12–14).
    Ifs {
        /// The segments file (TOML: [[segment]] points = [[x, y], ...], 2 or 3 points each).
        segments: PathBuf,
        /// Print JSON: {"maps": [{"segment", "name", "matrix"}, ...]}.
        #[arg(long)]
        json: bool,
    },
    /// Print the automaton (with its model) of the whole contour: arcs and line segments chained
    /// into one curve; `bcifs render`, `check` and `--random` work on it.
    Automaton {
        /// The segments file.
        segments: PathBuf,
    },
}

/// Runs a contour command.
pub fn run(out: &mut String, command: ContourCommand) -> Result<u8> {
    match command {
        ContourCommand::Fit { image, output, threshold, tolerance, d_min, d_max, alpha_max, json } => {
            let settings = bcifs::render::FitSettings {
                threshold,
                ipan: bcifs::render::Ipan { d_min, d_max, alpha_max },
                tolerance,
            };
            run_fit(out, &image, &output, &settings, json)
        }
        ContourCommand::Ifs { segments, json } => run_ifs(out, &segments, json),
        ContourCommand::Automaton { segments } => {
            let pieces = bcifs::render::read_segments(&segments)?;
            let name = segments.file_stem().map_or("contour".into(), |s| s.to_string_lossy().to_string());
            let design = bcifs::render::contour_design(&name, &pieces)?;
            out.push_str(&bcifs::render::write_design(&design));
            Ok(0)
        }
    }
}

/// `contour fit`: the contour of a picture as arcs and segments, to a segments file.
fn run_fit(
    out: &mut String,
    image: &std::path::Path,
    output: &std::path::Path,
    settings: &bcifs::render::FitSettings,
    json: bool,
) -> Result<u8> {
    let (tolerance, bcifs::render::Ipan { d_min, d_max, alpha_max }) = (settings.tolerance, settings.ipan);
    // The fit is a segments file (TOML): a picture's extension would hold text.
    crate::cli::common::check_output(output, &["toml"], &[image])?;
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        anyhow::bail!("--tolerance {tolerance}: expected a positive number of pixels");
    }
    if !(d_min > 0.0 && d_min <= d_max && d_max.is_finite() && (0.0..=180.0).contains(&alpha_max)) {
        anyhow::bail!("IPAN99 needs 0 < d_min ≤ d_max and 0 ≤ alpha_max ≤ 180");
    }
    let picture = image::open(image)
        .map_err(|e| anyhow::anyhow!("{}: not a readable PNG or JPEG picture: {e}", image.display()))?
        .to_luma8();
    let (w, h) = (picture.width() as usize, picture.height() as usize);
    let fit = bcifs::render::fit_contour(picture.as_raw(), w, h, settings)
        .map_err(|e| anyhow::anyhow!("{}: {e}", image.display()))?;
    let text = bcifs::render::write_segments(&fit.segments);
    bcifs::render::write_atomic(output, text.as_bytes())
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", output.display()))?;
    let arcs = fit.segments.iter().filter(|s| s.is_arc()).count();
    if json {
        let segments: Vec<&Vec<[f64; 2]>> = fit.segments.iter().map(|s| &s.points).collect();
        let value = serde_json::json!({
            "image": image.display().to_string(), "threshold": fit.threshold, "components": fit.components,
            "contour_points": fit.contour.len(), "corners": fit.corners, "segments": segments,
            "max_distance": fit.max_distance,
            "cut_corners": fit.cut_corners.iter().map(|(at, radius)| serde_json::json!({"at": at, "radius": radius})).collect::<Vec<_>>(),
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&value)?)?;
    } else {
        writeln!(
            out,
            "{}: threshold {}, {} contour points, {} corners → {} arcs and {} line segments \
             (within {:.3} px) → {}",
            image.display(),
            fit.threshold,
            fit.contour.len(),
            fit.corners.len(),
            arcs,
            fit.segments.len() - arcs,
            fit.max_distance,
            output.display()
        )?;
        if fit.components > 1 {
            writeln!(out, "  {} shapes: the largest is traced", fit.components)?;
        }
    }
    Ok(0)
}

/// `contour ifs`: the two maps of each segment.
fn run_ifs(out: &mut String, segments: &std::path::Path, json: bool) -> Result<u8> {
    let pieces = bcifs::render::read_segments(segments)?;
    let mut maps = Vec::new();
    for (k, s) in pieces.iter().enumerate() {
        let pair = s.maps().map_err(|e| anyhow::anyhow!("{}: segment {k}: {e}", segments.display()))?;
        for (name, m) in pair {
            maps.push((k, name, m));
        }
    }
    if json {
        let list: Vec<serde_json::Value> =
            maps.iter().map(|(k, name, m)| serde_json::json!({"segment": k, "name": name, "matrix": m})).collect();
        writeln!(out, "{}", serde_json::to_string_pretty(&serde_json::json!({ "maps": list }))?)?;
    } else {
        for (k, name, m) in &maps {
            writeln!(out, "segment {k} {name}:")?;
            for row in m {
                writeln!(out, "  [{:>10.6} {:>10.6} {:>10.6}]", row[0], row[1], row[2])?;
            }
        }
    }
    Ok(0)
}
