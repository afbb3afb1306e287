//! The gallery: every shipped automaton and scheme preset rendered into a
//! directory, with an `index.html`.

use std::fmt::Write as _;
use std::path::Path;

use bcifs::render::Shape;
use bcifs::render::mesh_automaton;
use bcifs::render::{CellKind, Design, Layout, Progress, instantiate};
use bcifs::render::{Depth, RandomSettings};
use bcifs::render::{RasterSettings, write_atomic};

use super::render::{SchemeForm, normal_shape, warn};
use crate::cli::common::progress_bar;
use bcifs::render::{Options as RenderOptions, Profile, RenderError, Report as RenderSummary, model_of, write_shape};

/// Renders with the library, its warnings and notes told on stderr.
fn render(design: &Design, options: &RenderOptions, out: &Path) -> Result<RenderSummary, RenderError> {
    let report = bcifs::render::render(design, options, out)?;
    warn(&report);
    Ok(report)
}

/// The output budget of a gallery entry's files (`gallery --full`: [`Profile::GalleryFull`]).
fn files_budget(full: bool) -> u128 {
    if full { Profile::GalleryFull } else { Profile::Gallery }.budget().output
}
/// The in-memory budget of a plain IFS's picture (its points, evaluated within half a pixel).
fn picture_budget() -> u128 {
    Profile::GalleryPicture.budget().output
}

/// One rendered gallery entry.
#[derive(Clone, Debug)]
pub struct GalleryEntry {
    /// Automaton name.
    pub name: String,
    /// Description.
    pub description: String,
    /// Depth or tolerance used.
    pub depth: Depth,
    /// Files written, relative to the gallery directory.
    pub files: Vec<String>,
    /// Vertices and quads of the picture.
    pub summary: RenderSummary,
    /// The depth or tolerance of the geometry files where it is not the picture's
    /// (a plain IFS's picture is finer than its files).
    pub geometry_depth: Option<Depth>,
}

/// `depth 8` or `tolerance 0.028`.
/// How an entry was made and its vertices: `depth 6, 4225 vertices`, or
/// `the chaos game` for pictures of samples (the density sheet) that have none.
fn made(e: &GalleryEntry) -> String {
    match e.summary.vertices {
        0 => "the chaos game".into(),
        n => format!("{}, {n} vertices", describe(e.depth)),
    }
}

fn describe(depth: Depth) -> String {
    match depth {
        Depth::Fixed(k) => format!("depth {k}"),
        Depth::Tolerance(eps) => format!("tolerance {eps:.3}"),
    }
}

/// Laces made from patterns (issue 44): the carpet on a bicubic patch and a lace of four holes on
/// a biquadratic one, as `bcifs new pattern` writes them.
fn laces() -> Vec<(String, String, GallerySource)> {
    use bcifs::render::{Pattern, PatternCell};
    LACES
        .iter()
        .filter_map(|&(name, split, keep, degree, what)| {
            let design = Pattern::parse(PatternCell::Quad, split, Some(keep), degree).ok()?.design(name).ok()?;
            Some((name.to_string(), what.to_string(), GallerySource::Design(Box::new(design), None)))
        })
        .collect()
}

/// The gallery's laces: `(name, split, mask, degree, description)`.
const LACES: [(&str, &str, &str, usize, &str); 2] = [
    ("lace-carpet-bicubic", "3x3", "111101111", 4, "the Sierpiński carpet as a lace on a bicubic patch"),
    (
        "lace-four-holes",
        "5x5",
        "1111110101111111010111111",
        3,
        "a lace of four holes (a 5×5 mask) on a biquadratic patch",
    ),
];

/// Depth of the cube textures.
const CUBE_DEPTH: usize = 5;
/// Depth of the icosahedron textures.
const ICOSAHEDRON_DEPTH: usize = 5;

/// Geometric textures of a mesh: one entry per weight set (its limit
/// surface), and a first one with all of them side by side (3 × 2, 3.5 units apart).
fn mesh_textures(
    mesh: &bcifs::render::PolyMesh,
    scheme: bcifs::render::Scheme,
    depth: usize,
    textures: &[(bcifs::render::RuleWeights, String)],
    (name, what): (&str, &str),
) -> Vec<(String, String, GallerySource)> {
    use bcifs::render::Sink as _;
    let mut items = Vec::new();
    let mut all = Shape::default();
    for (i, (w, label)) in textures.iter().enumerate() {
        let Ok(shape) = mesh.limit_with(scheme, depth, Some(*w), files_budget(true) as usize) else {
            continue;
        };
        let (dx, dy) = (3.5 * (i % 3) as f64, -3.5 * (i / 3) as f64);
        let first = all.vertex_count();
        let moved: Vec<f64> = shape.positions.chunks_exact(3).flat_map(|p| [p[0] + dx, p[1] + dy, p[2]]).collect();
        let quads: Vec<[usize; 4]> = shape.quads.iter().map(|q| q.map(|v| first + v as usize)).collect();
        let triangles: Vec<[usize; 3]> = shape.triangles.iter().map(|t| t.map(|v| first + v)).collect();
        let _ = all.object(label);
        let _ = all.vertices(3, &moved, None);
        let _ = all.faces(&quads, None);
        let _ = all.triangles(&triangles);
        items.push((
            format!("{name}-texture-{}", i + 1),
            format!("{what}, weights {label} (Sokolov et al. 2010 Fig. 12)"),
            GallerySource::Shape(Box::new(shape), depth),
        ));
    }
    items.insert(
        0,
        (
            format!("{name}-textures"),
            format!("six geometric textures of {what}: weight sets of the family (Sokolov et al. 2010 Fig. 12)"),
            GallerySource::Shape(Box::new(all), depth),
        ),
    );
    items
}

/// The six cube textures (Doo-Sabin-like weight triples) and the six
/// icosahedron textures (Loop-like weights).
fn textures() -> Vec<(String, String, GallerySource)> {
    use bcifs::render::{LoopWeights, PolyMesh, QuadWeights, Scheme};
    let cube: Vec<_> = QuadWeights::TEXTURES
        .iter()
        .map(|w| ((*w).into(), format!("α = {}, β = {}, γ = {}", w.alpha, w.beta, w.gamma)))
        .collect();
    let ico: Vec<_> =
        LoopWeights::TEXTURES.iter().map(|w| ((*w).into(), format!("w = {}, σ = {}", w.w, w.sigma))).collect();
    let mut items =
        mesh_textures(&PolyMesh::cube(), Scheme::DooSabin, CUBE_DEPTH, &cube, ("cube", "the cube, Doo-Sabin-like"));
    items.extend(mesh_textures(
        &PolyMesh::icosahedron(),
        Scheme::Loop,
        ICOSAHEDRON_DEPTH,
        &ico,
        ("icosahedron", "the icosahedron, Loop-like"),
    ));
    items
}

/// The cube as its generated Doo-Sabin automaton (`surface --print`), with
/// a weight the mesh code does not have: the rule of the triangles the
/// cube's corners become (`a3_0 = a3_2 = 0.45`: a twist at every corner).
fn mesh_automata() -> Vec<(String, String, GallerySource)> {
    use bcifs::render::{PolyMesh, Scheme};
    let Ok(design) = mesh_automaton(&PolyMesh::cube(), Scheme::DooSabin, None) else { return Vec::new() };
    let mut b = design.to_builder();
    b.default_value("a3_0", 0.45).default_value("a3_2", 0.45);
    let Ok(design) = b.build() else { return Vec::new() };
    let what = "the cube as a generated Doo-Sabin automaton, its corner triangles' rule a3 = (0.45, 0.1, 0.45): twisted corners";
    vec![("cube-corners".into(), what.into(), GallerySource::Design(Box::new(design), Some(CUBE_DEPTH)))]
}

/// The silhouette the contour example fits (drawn by a test: `docs/silhouette.png`).
const SILHOUETTE: &[u8] = include_bytes!("../../docs/silhouette.png");

/// the Bézier-fractal contours paper's pipeline on the shipped silhouette: the fitted contour's
/// automaton, the iterations 0, 3, 6, 9 of its maps from a rectangle (Figs.
/// 5–6) and the chaos game after 10, 50, 300 points per map (Fig. 7), side
/// by side. Pixel coordinates are turned y-up for the pictures.
fn contour_example() -> Vec<(String, String, GallerySource)> {
    use bcifs::render::Sink as _;
    let Ok(picture) = image::load_from_memory(SILHOUETTE) else { return Vec::new() };
    let grey = picture.to_luma8();
    let (w, h) = (grey.width() as usize, grey.height() as usize);
    let Ok(fit) = bcifs::render::fit_contour(grey.as_raw(), w, h, &Default::default()) else { return Vec::new() };
    let segments: Vec<bcifs::render::Segment> = fit
        .segments
        .iter()
        .map(|s| bcifs::render::Segment { points: s.points.iter().map(|p| [p[0], -p[1]]).collect() })
        .collect();
    let mut items = Vec::new();
    if let Ok(design) = bcifs::render::contour_design("contour-fitted", &segments) {
        let arcs = segments.iter().filter(|s| s.is_arc()).count();
        let what = format!(
            "a silhouette fitted by {arcs} quadratic Bézier arcs and {} line segments (the Bézier-fractal contours paper §6)",
            segments.len() - arcs
        );
        items.push(("contour-fitted".to_string(), what, GallerySource::Design(Box::new(design), Some(8))));
    }
    let (x0, x1) = (0.0, w as f64);
    let (y0, y1) = (-(h as f64), 0.0);
    let rectangle = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let gap = 1.15 * w as f64;
    let mut iterations = Shape::default();
    for (panel, depth) in [0usize, 3, 6, 9].into_iter().enumerate() {
        let _ = iterations.object(&format!("iteration {depth}"));
        for poly in bcifs::render::iterate_polygon(&segments, &rectangle, depth) {
            let first = iterations.vertex_count();
            let flat: Vec<f64> = poly.iter().flat_map(|p| [p[0] + panel as f64 * gap, p[1]]).collect();
            let _ = iterations.vertices(2, &flat, None);
            let _ = iterations.polyline(first, poly.len(), true);
        }
    }
    items.push((
        "contour-iterations".into(),
        "iterations 0, 3, 6, 9 of the fitted contour's maps from a rectangle (the Bézier-fractal contours paper Figs. 5–6)".into(),
        GallerySource::Shape(Box::new(iterations), 9),
    ));
    let mut chaos = Shape::default();
    for (panel, per_map) in [10usize, 50, 300].into_iter().enumerate() {
        let _ = chaos.object(&format!("{per_map} points per map"));
        let flat: Vec<f64> = bcifs::render::chaos_points(&segments, per_map, 7)
            .iter()
            .flat_map(|p| [p[0] + panel as f64 * gap, p[1]])
            .collect();
        let _ = chaos.vertices(2, &flat, None);
    }
    items.push((
        "contour-chaos".into(),
        "the chaos game of the fitted contour after 10, 50 and 300 points per map, p ∝ |det| (the Bézier-fractal contours paper Fig. 7)".into(),
        GallerySource::Shape(Box::new(chaos), 1),
    ));
    items
}

/// A gallery entry to make: its name, its description and what it is made from.
pub type GalleryItem = (String, String, GallerySource);

/// What a gallery entry is made from.
#[derive(Clone, Debug)]
pub enum GallerySource {
    /// An automaton with a model, evaluated to the deepest depth within the budget
    /// (or to the given depth).
    Design(Box<Design>, Option<usize>),
    /// A shape computed directly (a scheme's polyline form), with its depth.
    Shape(Box<Shape>, usize),
}

/// The gallery: every shipped automaton with a model, every normal-vector
/// preset of Li et al. 2013 at the paper's depth, every scheme of the catalogue
/// (Schaefer et al. 2005 and Siddiqi et al. 2014): `(name, description, source)`.
pub fn gallery_items() -> Vec<(String, String, GallerySource)> {
    let mut items: Vec<(String, String, GallerySource)> = bcifs::render::BUILTIN_AUTOMATA
        .iter()
        .filter_map(|(n, _)| bcifs::render::builtin_design(n))
        .filter(|d| d.model().is_some())
        .map(|d| (d.name().to_string(), d.description().to_string(), GallerySource::Design(Box::new(d), None)))
        .collect();
    for name in bcifs::render::PRESET_NAMES {
        let Ok(preset) = bcifs::render::normal_preset(name) else { continue };
        let entry = format!("normal-{name}");
        let description = format!("{} (normal-vector scheme, Li et al. 2013)", preset.description);
        let source = match preset.scheme.design(&entry, &preset.polygon, preset.closed) {
            Ok(design) => GallerySource::Design(Box::new(design), Some(preset.depth)),
            Err(_) => match normal_shape(&preset, preset.depth, SchemeForm::Direct, files_budget(true) as usize) {
                Ok(shape) => GallerySource::Shape(Box::new(shape), preset.depth),
                Err(_) => continue,
            },
        };
        items.push((entry, description, source));
    }
    items.extend(textures());
    items.extend(mesh_automata());
    items.extend(contour_example());
    items.extend(laces());
    for name in bcifs::render::IFS_NAMES {
        if let Ok(g) = bcifs::render::ifs_preset(name, None, None) {
            items.push((g.name().to_string(), g.description().to_string(), GallerySource::Design(Box::new(g), None)));
        }
    }
    items
}

/// Renders the gallery's `items` ([`gallery_items`]) into `dir`, telling
/// `entry` each one's name as it starts: a PNG and an OBJ each
/// (plus a chaos-game picture for plain IFS), and an `index.html`.
///
/// # Errors
/// The first entry that fails, or an I/O error.
pub fn gallery(
    dir: &Path,
    formats: &[String],
    budget: u128,
    progress: Option<&Progress>,
    items: Vec<GalleryItem>,
    entry: &dyn Fn(&str),
) -> Result<Vec<GalleryEntry>, RenderError> {
    check_gallery_dir(dir)?;
    let mut entries = Vec::new();
    let total = items.len() as u64;
    for (done, (name, description, source)) in items.into_iter().enumerate() {
        if let Some(p) = progress {
            p.report(done as u64, total);
        }
        entry(&name);
        let png = format!("{name}.png");
        let (depth, summary, files, geometry_depth) = match source {
            GallerySource::Shape(shape, depth) => {
                let summary = write_shape(&shape, &name, &RasterSettings::default(), &dir.join(&png))?;
                let mut files = vec![png];
                for ext in formats {
                    let file = format!("{name}.{ext}");
                    write_shape(&shape, &name, &RasterSettings::default(), &dir.join(&file))?;
                    files.push(file);
                }
                (Depth::Fixed(depth), summary, files, None)
            }
            GallerySource::Design(design, fixed) => design_entry(dir, &name, &design, (fixed, budget), formats)?,
        };
        entries.push(GalleryEntry { name, description, depth, files, summary, geometry_depth });
    }
    entries.push(density_page(dir)?);
    if let Some(p) = progress {
        p.report(total, total);
    }
    write_index(dir, &entries)?;
    Ok(entries)
}

/// Before any work: no output of the gallery may land on a directory.
fn check_gallery_dir(dir: &Path) -> Result<(), RenderError> {
    std::fs::create_dir_all(dir).map_err(|e| RenderError::Io(dir.to_path_buf(), e))?;
    let entries = std::fs::read_dir(dir).map_err(|e| RenderError::Io(dir.to_path_buf(), e))?;
    for entry in entries.flatten() {
        let path = entry.path();
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
        if path.is_dir() && ["png", "obj", "ply", "glb", "html"].contains(&ext.as_str()) {
            let why =
                std::io::Error::new(std::io::ErrorKind::IsADirectory, "a directory where the gallery writes a file");
            return Err(RenderError::Io(path, why));
        }
    }
    Ok(())
}

/// A design's gallery entry: its PNG and OBJ at the depth (or Hausdorff
/// tolerance) that fits, and a chaos-game picture of plain IFS.
fn design_entry(
    dir: &Path,
    name: &str,
    design: &Design,
    (fixed, budget): (Option<usize>, u128),
    formats: &[String],
) -> Result<(Depth, RenderSummary, Vec<String>, Option<Depth>), RenderError> {
    let depth = match fixed {
        Some(d) => d,
        None => bcifs::render::depth_within(design, budget, Profile::Gallery.budget().max_depth)?,
    };
    let mut options = RenderOptions::default().with_depth(depth);
    let model = model_of(design)?;
    let root = design.automaton().state_id(model.root(0)).map(|r| design.automaton().state(r));
    let plain_ifs = model.layout == Layout::Single && root.is_some_and(|r| r.kind == CellKind::Free);
    // Affine maps (d + 1 control points) get a Hausdorff tolerance; larger
    // free states (subdivision patches as IFS) keep the deepest depth that fits.
    let affine = root.is_some_and(|r| r.dim <= model.points[0].len() + 1);
    // The picture of an affine IFS is drawn within half a pixel wherever its points fit the
    // picture's budget (Barnsley's fern: 646,000 points, 0.3 s; depth 6 was a faint scatter, its
    // stem's map contracts by 0.16 and its leaves' by 0.85); its geometry files keep the file budget.
    let mut picture = options.clone();
    // The files' budget is the smaller: it is tried only when the picture's fits.
    if plain_ifs
        && affine
        && let Some(eps) = bcifs::render::tolerance_within(design, picture_budget())?
    {
        picture.sampling.depth = Depth::Tolerance(eps);
        if bcifs::render::tolerance_within(design, budget)?.is_some() {
            options.sampling.depth = Depth::Tolerance(eps);
        }
    }
    let png = format!("{name}.png");
    let summary = render(design, &picture, &dir.join(&png))?;
    let mut files = vec![png];
    for ext in formats {
        let file = format!("{name}.{ext}");
        render(design, &options, &dir.join(&file))?;
        files.push(file);
    }
    if plain_ifs {
        let mut random = options.clone();
        random = random.with_chaos(2_000_000);
        let png = format!("{name}-chaos.png");
        render(design, &random, &dir.join(&png))?;
        files.push(png);
    }
    let (files_depth, picture_depth) = (options.sampling.depth, picture.sampling.depth);
    let geometry = (files_depth != picture_depth && !formats.is_empty()).then_some(files_depth);
    Ok((picture_depth, summary, files, geometry))
}

/// The gallery's `index.html`: a figure per entry.
fn write_index(dir: &Path, entries: &[GalleryEntry]) -> Result<(), RenderError> {
    let mut html = String::from(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>bcifs gallery</title>\n<style>body{font-family:sans-serif;margin:2em;background:#f6f7f9}figure{display:inline-block;margin:1em;background:white;padding:1em;box-shadow:0 1px 3px #0002;vertical-align:top}img{width:360px;height:360px;object-fit:contain}figcaption{max-width:360px}</style></head><body>\n<h1>bcifs gallery</h1>\n",
    );
    for e in entries {
        let _ = write!(html, "<figure>");
        for f in e.files.iter().filter(|f| f.ends_with(".png")) {
            let _ = write!(html, "<img src=\"{f}\" alt=\"{}\">", e.name);
        }
        let obj: Vec<String> =
            e.files.iter().filter(|f| !f.ends_with(".png")).map(|f| format!("<a href=\"{f}\">{f}</a>")).collect();
        let obj = match e.geometry_depth {
            Some(d) if !obj.is_empty() => format!("{} ({})", obj.join(" "), describe(d)),
            _ => obj.join(" "),
        };
        let (command, paper) = caption(&e.name, e.depth);
        let _ = writeln!(
            html,
            "<figcaption><b>{}</b> — {}<br>{}{}; {}<br><i>From:</i> {paper}<br><code>{}</code></figcaption></figure>",
            e.name,
            e.description,
            made(e),
            if e.summary.faces > 0 { format!(", {} faces", e.summary.faces) } else { String::new() },
            obj,
            command.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
        );
    }
    html.push_str("</body></html>\n");
    write_atomic(&dir.join("index.html"), html.as_bytes()).map_err(|e| RenderError::Io(dir.join("index.html"), e))
}

/// The command that makes an entry's picture, and the paper and figure it reproduces.
fn caption(name: &str, depth: Depth) -> (String, String) {
    let how = match depth {
        Depth::Fixed(k) => format!("--depth {k}"),
        Depth::Tolerance(eps) => format!("--tolerance {eps:.4}"),
    };
    let texture = |scheme: &str, mesh: &str, params: String| {
        format!("bcifs surface tests/data/{mesh} --scheme {scheme} {params}{how} -o {name}.png")
    };
    let numbered = |prefix: &str| name.strip_prefix(prefix).and_then(|k| k.parse::<usize>().ok()).filter(|k| *k >= 1);
    let command = if let Some(k) = numbered("cube-texture-") {
        let w = bcifs::render::QuadWeights::TEXTURES[(k - 1).min(5)];
        texture(
            "doo-sabin",
            "cube.off",
            format!("--param alpha={} --param beta={} --param gamma={} ", w.alpha, w.beta, w.gamma),
        )
    } else if let Some(k) = numbered("icosahedron-texture-") {
        let w = bcifs::render::LoopWeights::TEXTURES[(k - 1).min(5)];
        texture("loop", "icosahedron.off", format!("--param w={} --param sigma={} ", w.w, w.sigma))
    } else if let Some(preset) = name.strip_prefix("normal-") {
        format!(
            "bcifs scheme normal --preset {preset} --depth {} -o {name}.png",
            match depth {
                Depth::Fixed(k) => k,
                _ => 6,
            }
        )
    } else if name == "cube-corners" {
        format!(
            "bcifs surface tests/data/cube.off --scheme doo-sabin --print -o cube.toml && bcifs render cube.toml --param a3_0=0.45 --param a3_2=0.45 {how} -o {name}.png"
        )
    } else if name == "contour-fitted" {
        format!(
            "bcifs contour fit docs/silhouette.png -o s.toml && bcifs contour automaton s.toml > c.toml && bcifs render c.toml {how} -o {name}.png (the gallery turns the picture's y up)"
        )
    } else if let Some(&(_, split, keep, degree, _)) = LACES.iter().find(|l| l.0 == name) {
        format!(
            "bcifs new pattern --cell quad --split {split} --keep {keep} --degree {degree} --name {name} > {name}.toml && bcifs render {name}.toml {how} -o {name}.png"
        )
    } else if name.ends_with("-textures") || name.starts_with("contour-") || name == "density" {
        "made by the gallery from the entries beside it (bcifs gallery)".to_string()
    } else {
        format!("bcifs render {name} {how} -o {name}.png")
    };
    let paper = match name {
        "corner_cutting" => "Sokolov et al. 2010, §3 (the corner-cutting family)",
        "curve_4_3" => "Sokolov et al. 2010, §2 (a BC-IFS curve of 4 control points)",
        "doo_sabin_quad" | "doo_sabin_torus" => "Sokolov et al. 2010, §5 (Doo-Sabin-like patches)",
        "fern_sierpinski" => "Sokolov et al. 2010, §2 (a controlled IFS of two states)",
        "fern" | "gasket" => "a classic IFS (Barnsley's fern, Sierpinski's gasket)",
        "koch" => "Li et al. 2013, Fig. 6a (Koch curve, scheme (5))",
        "levy" => "Li et al. 2013, Fig. 2 (Lévy C curve, scheme (2))",
        n if n.starts_with("normal-") => "Li et al. 2013 (the figure is in the description)",
        n if n.starts_with("cube-") || n.starts_with("icosahedron-") => {
            "Sokolov et al. 2010, Fig. 12 (geometric textures)"
        }
        n if n.starts_with("contour-") => "the Bézier-fractal contours paper (figure in the description)",
        n if n.starts_with("ternary5") => "Siddiqi et al. 2014",
        "density" => "the chaos game as density images (flame renderers' tone mapping)",
        "cantor" | "carpet" | "gasket_lace" => {
            "Sokolov, Gentil, Bensoudane 2010 (lacunar cells) and Gentil et al. 2021 (laces from a subdivision pattern)"
        }
        n if n.starts_with("lace-") => "Gentil et al. 2021 (laces: surfaces with holes from a subdivision pattern)",
        _ => "Schaefer et al. 2005 (section and figure in the description)",
    };
    (command, paper.to_string())
}

/// Sample counts of the density page.
pub const DENSITY_SAMPLES: [usize; 3] = [100_000, 1_000_000, 100_000_000];

/// The density page (issue 11): the fern, the gasket and the fern with a
/// Sierpinski branch by the chaos game, as dots (a pixel inked by any
/// sample) and as density images (log-density ink), at 1e5, 1e6 and 1e8
/// samples, and coloured by their maps at 1e8 (the fire palette, a light
/// blur): `density-NAME-KIND-N.png` tiles, `density.png` (all of them, a
/// row per shape) and `density.html`.
fn density_page(dir: &Path) -> Result<GalleryEntry, RenderError> {
    use bcifs::render::{Palette, Tone, density_counts as density, write_png_text};
    let tile = 240u32;
    let raster = RasterSettings::default().with_size(tile, tile);
    let shapes = ["fern", "gasket", "fern_sierpinski"];
    let columns = DENSITY_SAMPLES.len() * 2 + 1;
    let mut sheet =
        image::RgbImage::from_pixel(tile * columns as u32, tile * shapes.len() as u32, image::Rgb([255; 3]));
    let files = vec!["density.png".to_string(), "density.html".to_string()];
    let mut rows = String::new();
    let io = |p: &Path, e| RenderError::Io(p.to_path_buf(), e);
    let fire = Palette::named("fire").expect("shipped palette");
    for (row, name) in shapes.iter().enumerate() {
        let design = bcifs::render::builtin_design(name).expect("shipped automaton");
        let instance = instantiate(&design, &[])?;
        let model = model_of(&design)?;
        let game =
            bcifs::render::ChaosGame::new(&instance.automaton, &model, &RandomSettings::default().with_points(1))?;
        let mut tiles = Vec::new();
        let mut dots = Vec::new();
        for &n in &DENSITY_SAMPLES {
            let counts = density(&game, n, &raster, 1, None)?;
            dots.push((format!("dots-{n}"), counts.dots()));
            tiles.push((format!("density-{n}"), counts.image(&Tone::default())));
        }
        let n = DENSITY_SAMPLES[DENSITY_SAMPLES.len() - 1];
        let flame = density(&game, n, &raster, 1, Some(&fire))?.image(&Tone { blur: 2.0, ..Tone::default() });
        let all: Vec<(String, image::RgbImage)> =
            dots.into_iter().chain(tiles).chain([(format!("colour-{n}"), flame)]).collect();
        let _ = write!(rows, "<tr><th>{name}</th>");
        for (col, (kind, img)) in all.iter().enumerate() {
            let file = format!("density-{name}-{kind}.png");
            let text = super::common::png_text(name, &format!("gallery density sheet: {kind}"));
            write_png_text(&dir.join(&file), img, &text).map_err(|e| io(&dir.join(&file), e))?;
            image::imageops::replace(&mut sheet, img, i64::from(tile) * col as i64, i64::from(tile) * row as i64);
            let _ = write!(rows, "<td><img src=\"{file}\" alt=\"{name} {kind}\"></td>");
        }
        rows.push_str("</tr>\n");
    }
    let columns: Vec<String> = ["dots", "density"]
        .iter()
        .flat_map(|k| DENSITY_SAMPLES.iter().map(move |n| format!("{k}, {n:.0e} samples")))
        .chain([format!("by the maps, {:.0e}", DENSITY_SAMPLES[2])])
        .collect();
    let names: Vec<String> = shapes.iter().map(|s| s.to_string()).collect();
    let sheet = super::plot::labelled_sheet(&sheet, tile, &columns, &names)
        .map_err(|e| io(&dir.join("density.png"), std::io::Error::other(e.to_string())))?;
    let text = super::common::png_text("density", "gallery: dots and density pictures of the chaos game");
    write_png_text(&dir.join("density.png"), &sheet, &text).map_err(|e| io(&dir.join("density.png"), e))?;
    let head: String = ["dots", "density"]
        .iter()
        .flat_map(|k| DENSITY_SAMPLES.iter().map(move |n| format!("<th>{k}, {n:.0e} samples</th>")))
        .chain([format!("<th>coloured by the maps, {:.0e}</th>", DENSITY_SAMPLES[2])])
        .collect();
    let html = format!(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>bcifs: dots and density</title></head><body>\n<h1>The chaos game as dots and as density images</h1>\n<p>Dots ink a pixel hit by any sample: past a million samples the attractor is a solid silhouette. Density images ink by the log of the count (flame renderers' tone mapping), so they keep improving with the samples; the last column colours each sample by the maps it went through.</p>\n<table><tr><th></th>{head}</tr>\n{rows}</table></body></html>\n"
    );
    write_atomic(&dir.join("density.html"), html.as_bytes()).map_err(|e| io(&dir.join("density.html"), e))?;
    Ok(GalleryEntry {
        name: "density".into(),
        description: "the fern, the gasket and fern∘Sierpinski by the chaos game: dots and density images at 1e5, 1e6 and 1e8 samples, coloured by the maps at 1e8".into(),
        depth: Depth::Fixed(0),
        files,
        summary: RenderSummary::default(),
        geometry_depth: None,
    })
}

/// `bcifs gallery DIR`: renders the gallery and lists what it wrote.
pub fn run(out: &mut String, dir: &Path, formats: &[String], full: bool) -> anyhow::Result<u8> {
    let started = std::time::Instant::now();
    let budget = files_budget(full);
    let items = gallery_items();
    let count = items.len() + 1;
    // What it will write, before it starts (measured: the default gallery is about 70 MB, --full 330 MB).
    let (size, other) = if full { ("330", "") } else { ("70", "; --full: the deep versions, about 330 MB") };
    eprintln!(
        "bcifs gallery: {count} entries into {}: a PNG and {} each and index.html, about {size} MB{other}",
        dir.display(),
        formats.iter().map(|f| f.to_uppercase()).collect::<Vec<_>>().join(", ")
    );
    let bar = progress_bar();
    let done = std::cell::Cell::new(0usize);
    let terminal = bar.is_some();
    // Written into a staging folder beside DIR, its files moved into DIR at the end: an
    // interrupted or failed gallery leaves DIR as it was (and no staging folder).
    check_gallery_dir(dir)?;
    let staging = staging_dir(dir);
    let written = gallery(&staging, formats, budget, bar.as_ref(), items, &|name| {
        done.set(done.get() + 1);
        if terminal {
            eprintln!("  [{}/{count}] {name}", done.get());
        }
    });
    let entries = match written.map_err(anyhow::Error::from).and_then(|e| move_into(&staging, dir).map(|()| e)) {
        Ok(entries) => entries,
        Err(e) => {
            remove_staging();
            return Err(e);
        }
    };
    remove_staging();
    let mut bytes = 0u64;
    for e in &entries {
        let size: u64 = e.files.iter().filter_map(|f| std::fs::metadata(dir.join(f)).ok()).map(|m| m.len()).sum();
        bytes += size;
        writeln!(out, "{:<20} {:<35} {:>7.1} MB  {}", e.name, made(e), size as f64 / 1e6, e.files.join(", "))?;
    }
    writeln!(
        out,
        "{} entries, {:.0} MB → {} ({:.1} s)",
        entries.len(),
        bytes as f64 / 1e6,
        dir.join("index.html").display(),
        started.elapsed().as_secs_f64()
    )?;
    Ok(0)
}

/// The staging folders of galleries being written (removed when interrupted).
static STAGING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// A fresh staging folder beside `dir`, registered for [`remove_staging`].
fn staging_dir(dir: &Path) -> std::path::PathBuf {
    let name = dir.file_name().map_or("gallery".into(), |n| n.to_string_lossy().into_owned());
    let staging = dir.with_file_name(format!(".{name}.partial.{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&staging);
    STAGING.lock().unwrap_or_else(std::sync::PoisonError::into_inner).push(staging.clone());
    staging
}

/// Removes the staging folders of this process: an interrupted gallery
/// leaves its folder as it was.
pub fn remove_staging() {
    for dir in STAGING.lock().unwrap_or_else(std::sync::PoisonError::into_inner).drain(..) {
        // A writer still finishing may put a file back while the folder is emptied: again, briefly.
        for _ in 0..40 {
            if std::fs::remove_dir_all(&dir).is_ok() || !dir.exists() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }
}

/// Moves every file of `staging` into `dir` (a rename each: each file is
/// whole, old or new), after the whole gallery was written.
fn move_into(staging: &Path, dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("cannot create {}: {e}", dir.display()))?;
    for entry in std::fs::read_dir(staging)? {
        let from = entry?.path();
        let to = dir.join(from.file_name().unwrap_or_default());
        std::fs::rename(&from, &to)
            .map_err(|e| anyhow::anyhow!("cannot move {} to {}: {e}", from.display(), to.display()))?;
    }
    Ok(())
}
