//! Fit targets read from files: the vertices of a mesh or point cloud
//! (OBJ, OFF, PLY, as other tools write them) and a picture's silhouette.

use std::path::Path;

use super::types::FitError;
use crate::design::Design;

/// The points of a target file, by extension: the vertices of an OBJ
/// (`v` lines), OFF or PLY (ASCII or binary) file — faces, edges, normals
/// and colours are not needed — read as Y-up (as bcifs writes these files
/// and Blender exports them: turned back into a Z-up model's axes), or,
/// for a PNG, the outline of its largest shape placed over the design's
/// default member ([`picture_points`]).
///
/// # Errors
/// An unreadable or malformed file (with its line), an unknown extension, no point.
pub fn read_target(path: &Path, design: &Design) -> Result<Vec<[f64; 3]>, FitError> {
    let name = path.display().to_string();
    let size = std::fs::metadata(path).map_err(|e| FitError::Target(format!("{name}: {e}")))?.len();
    if size > crate::input::TEXT_FILE_LIMIT {
        return Err(FitError::Target(format!(
            "{name}: {size} bytes, over the limit of {} bytes",
            crate::input::TEXT_FILE_LIMIT
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| FitError::Target(format!("{name}: {e}")))?;
    read_target_bytes(&name, &bytes, design)
}

/// [`read_target`] of a file's bytes (an upload), its format from `name`'s extension.
///
/// # Errors
/// As [`read_target`].
pub fn read_target_bytes(name: &str, bytes: &[u8], design: &Design) -> Result<Vec<[f64; 3]>, FitError> {
    let ext = Path::new(name).extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let bad = |line: usize, what: &str| FitError::Target(format!("{name}:{line}: {what}"));
    let points = match ext.as_str() {
        "png" => {
            let picture = image::load_from_memory(bytes).map_err(|e| FitError::Target(format!("{name}: {e}")))?;
            return picture_points(&picture, name, design);
        }
        "ply" => ply_vertices(bytes).map_err(|(line, what)| bad(line, &what))?,
        "obj" | "off" => {
            let text = std::str::from_utf8(bytes).map_err(|e| FitError::Target(format!("{name}: not text: {e}")))?;
            let parsed = if ext == "obj" { obj_vertices(text) } else { off_vertices(text) };
            parsed.map_err(|(line, what)| bad(line, &what))?
        }
        other => {
            return Err(FitError::Target(format!(
                "{name}: a target is an OBJ, OFF or PLY file (points or a mesh) or a PNG picture, not `.{other}`"
            )));
        }
    };
    if points.is_empty() {
        return Err(FitError::Target(format!("{name}: no vertex")));
    }
    // Mesh files are Y-up (as bcifs writes them, and Blender and most tools export them): a
    // Z-up model's points are turned back, (x, y, z) ↦ (x, −z, y).
    let model = crate::report::model_of(design).map_err(|e| FitError::Design(e.to_string()))?;
    let space = model.points.first().is_some_and(|p| p.len() == 3);
    Ok(if space && !model.y_up { points.into_iter().map(|[x, y, z]| [x, -z, y]).collect() } else { points })
}

/// Whether a target file is a picture (`.png`), whose outline has no model units: its size and
/// place are fitted with the parameters ([`crate::fit::FitTarget::free_pose`]).
pub fn is_picture(name: &str) -> bool {
    Path::new(name).extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// Three coordinates (a missing third one is 0) from words, or what is wrong.
fn coordinates<'a>(words: impl Iterator<Item = &'a str>) -> Result<[f64; 3], String> {
    let mut p = [0.0; 3];
    let mut n = 0;
    for (k, w) in words.take(3).enumerate() {
        p[k] = w.parse().map_err(|_| format!("expected a number, found `{w}`"))?;
        n = k + 1;
    }
    if n < 2 { Err("expected at least two coordinates".into()) } else { Ok(p) }
}

fn obj_vertices(text: &str) -> Result<Vec<[f64; 3]>, (usize, String)> {
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() == Some("v") {
            out.push(coordinates(words).map_err(|e| (k + 1, e))?);
        }
    }
    Ok(out)
}

fn off_vertices(text: &str) -> Result<Vec<[f64; 3]>, (usize, String)> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (k, head) = lines.next().ok_or((1, "expected `OFF`".to_string()))?;
    let mut words: Vec<&str> = head.split_whitespace().collect();
    if !words.first().is_some_and(|w| w.ends_with("OFF")) {
        return Err((k + 1, format!("expected `OFF`, found `{head}`")));
    }
    words.remove(0);
    let (k, counts) =
        if words.is_empty() { lines.next().ok_or((k + 1, "expected the counts".to_string()))? } else { (k, head) };
    let first = counts.split_whitespace().find(|w| !w.ends_with("OFF"));
    let n: usize =
        first.and_then(|w| w.parse().ok()).ok_or((k + 1, format!("expected the vertex count, found `{counts}`")))?;
    let mut out = Vec::with_capacity(n.min(1 << 24));
    for _ in 0..n {
        let (k, line) = lines.next().ok_or((k + 1, format!("expected {n} vertices")))?;
        out.push(coordinates(line.split_whitespace()).map_err(|e| (k + 1, e))?);
    }
    Ok(out)
}

/// A PLY element: its name, count and properties (type, name; `list` for a list).
type Element = (String, usize, Vec<(String, String)>);

/// The vertices of a PLY file: its `vertex` element's `x`, `y`, `z`, in ASCII or binary.
fn ply_vertices(bytes: &[u8]) -> Result<Vec<[f64; 3]>, (usize, String)> {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .ok_or((1, "expected a PLY header ending in `end_header`".to_string()))?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    let body = &bytes[end + 11..];
    let (mut format, mut elements): (&str, Vec<Element>) = ("", Vec::new());
    for (k, line) in header.lines().enumerate() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", f, ..] => format = f,
            ["element", name, count] => {
                let count = count.parse().map_err(|_| (k + 1, format!("expected a count, found `{count}`")))?;
                elements.push((name.to_string(), count, Vec::new()));
            }
            ["property", "list", ..] => {
                elements
                    .last_mut()
                    .ok_or((k + 1, "a property before any element".to_string()))?
                    .2
                    .push(("list".into(), String::new()));
            }
            ["property", ty, name] => {
                elements
                    .last_mut()
                    .ok_or((k + 1, "a property before any element".to_string()))?
                    .2
                    .push((ty.to_string(), name.to_string()));
            }
            _ => {}
        }
    }
    let (_, count, props) =
        elements.first().filter(|e| e.0 == "vertex").ok_or((1, "expected the `vertex` element first".to_string()))?;
    let axis = |n: &str| props.iter().position(|p| p.1 == n);
    let (x, y, z) = (
        axis("x").ok_or((1, "the vertices have no `x`".to_string()))?,
        axis("y").ok_or((1, "the vertices have no `y`".to_string()))?,
        axis("z"),
    );
    let mut out = Vec::with_capacity((*count).min(1 << 24));
    if format == "ascii" {
        let text = String::from_utf8_lossy(body);
        for (k, line) in text.lines().take(*count).enumerate() {
            let w: Vec<f64> = line.split_whitespace().map(|s| s.parse().unwrap_or(f64::NAN)).collect();
            let at = |i: usize| {
                w.get(i).copied().ok_or((header.lines().count() + 2 + k, "a vertex line too short".to_string()))
            };
            out.push([at(x)?, at(y)?, z.map_or(Ok(0.0), at)?]);
        }
        return Ok(out);
    }
    let big = match format {
        "binary_little_endian" => false,
        "binary_big_endian" => true,
        other => return Err((1, format!("expected an ascii or binary PLY format, found `{other}`"))),
    };
    binary_vertices(body, *count, props, big, [x, y], z)
}

/// The `count` vertices of a binary PLY body, their coordinates at properties `xy` and `z`.
fn binary_vertices(
    mut body: &[u8],
    count: usize,
    props: &[(String, String)],
    big: bool,
    [x, y]: [usize; 2],
    z: Option<usize>,
) -> Result<Vec<[f64; 3]>, (usize, String)> {
    let size = |ty: &str| match ty {
        "char" | "uchar" | "int8" | "uint8" => Some(1),
        "short" | "ushort" | "int16" | "uint16" => Some(2),
        "int" | "uint" | "float" | "int32" | "uint32" | "float32" => Some(4),
        "double" | "float64" => Some(8),
        _ => None,
    };
    let mut out = Vec::with_capacity(count.min(1 << 24));
    for _ in 0..count {
        let mut values = Vec::with_capacity(props.len());
        for (ty, _) in props {
            let n = size(ty).ok_or((1, format!("a vertex property of type `{ty}` is not read here")))?;
            if body.len() < n {
                return Err((1, "the file ends before its vertices".into()));
            }
            let (v, rest) = body.split_at(n);
            body = rest;
            let mut b = [0u8; 8];
            b[..n].copy_from_slice(v);
            if big {
                b[..n].reverse();
            }
            values.push(match ty.as_str() {
                "float" | "float32" => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                "double" | "float64" => f64::from_le_bytes(b),
                _ => f64::NAN,
            });
        }
        out.push([values[x], values[y], z.map_or(0.0, |z| values[z])]);
    }
    Ok(out)
}

/// The outline of a picture's largest shape (traced as the contour fit
/// traces it: half a pixel outside its border pixels' centres, the picture's
/// y axis turned up), scaled and moved so that its bounding box's centre and
/// diagonal are those of the design's default member: a silhouette fixes the
/// shape, not its size or place.
///
/// # Errors
/// A picture with no shape (`name` says which), a design that does not evaluate.
pub fn picture_points(picture: &image::DynamicImage, name: &str, design: &Design) -> Result<Vec<[f64; 3]>, FitError> {
    let grey = picture.to_luma8();
    let (w, h) = (grey.width() as usize, grey.height() as usize);
    let traced = crate::contour::fit_contour(grey.as_raw(), w, h, &crate::contour::FitSettings::default())
        .map_err(|e| FitError::Target(format!("{name}: {e}")))?;
    let outline: Vec<[f64; 3]> = traced.contour.iter().map(|p| [p[0], -p[1], 0.0]).collect();
    let family = crate::family::instantiate(design, &[]).map_err(|e| FitError::Design(e.to_string()))?;
    let model = crate::report::model_of(design).map_err(|e| FitError::Design(e.to_string()))?;
    let ev = crate::eval::Evaluator::new(&family.automaton, &model, crate::eval::EvalSettings::default().with_depth(4))
        .map_err(|e| FitError::Design(e.to_string()))?;
    let shape = ev.evaluate().map_err(|e| FitError::Design(e.to_string()))?;
    let ((lo, hi), (a, b)) = (bounds(&shape.points()), bounds(&outline));
    let diagonal = |lo: [f64; 3], hi: [f64; 3]| (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    let scale = diagonal(lo, hi) / diagonal(a, b).max(f64::MIN_POSITIVE);
    let centre = |lo: [f64; 3], hi: [f64; 3]| [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    let (to, from) = (centre(lo, hi), centre(a, b));
    Ok(outline
        .iter()
        .map(|p| [0, 1, 2].map(|k| if k == 2 { to[2] } else { to[k] + (p[k] - from[k]) * scale }))
        .collect())
}

fn bounds(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        (0..3).for_each(|k| (lo[k], hi[k]) = (lo[k].min(p[k]), hi[k].max(p[k])));
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    /// The three formats' vertices, and their errors with a line.
    #[test]
    fn vertices_are_read_from_obj_off_and_ply() {
        assert_eq!(
            super::obj_vertices("# c\nv 1 2 3\nvn 0 0 1\nv 4 5\nf 1 2 3\n").unwrap(),
            [[1.0, 2.0, 3.0], [4.0, 5.0, 0.0]]
        );
        assert_eq!(super::obj_vertices("v 1 x 3\n").unwrap_err(), (1, "expected a number, found `x`".into()));
        assert_eq!(super::off_vertices("OFF\n2 0 0\n0 0 0\n1 2 3\n").unwrap(), [[0.0; 3], [1.0, 2.0, 3.0]]);
        assert!(super::off_vertices("OFF\n3 0 0\n0 0 0\n").unwrap_err().1.contains("3 vertices"));
        let ascii = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nend_header\n1 2 3 255\n4 5 6 0\n";
        assert_eq!(super::ply_vertices(ascii).unwrap(), [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\nproperty double y\nproperty double z\nend_header\n".to_vec();
        [0.5f64, -1.0, 2.0].iter().for_each(|x| binary.extend(x.to_le_bytes()));
        assert_eq!(super::ply_vertices(&binary).unwrap(), [[0.5, -1.0, 2.0]]);
    }
}
