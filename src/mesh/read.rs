//! Reading polygon meshes: Wavefront OBJ (`v`, `vt` and `f` records;
//! texture coordinates kept when every corner has one, normal indices
//! skipped, negative indices, any face degree; the first `o` (else `g`)
//! names the mesh, and every `o` and `g` starts a group of faces; other
//! records are skipped) and OFF (with `#` comments, the counts on the header line or
//! the next, colours after the coordinates or indices ignored). Errors name
//! `file:line:column` and what was expected; the mesh is then checked like
//! [`PolyMesh::new`], naming the face's line.

use std::path::Path;

use super::error::{MeshCheckError, MeshReadError};
use super::polymesh::{Place, PolyMesh};

/// Reads a mesh, choosing the format by extension (`.obj`, `.off`).
///
/// # Errors
/// An unreadable or malformed file, or a mesh that fails the checks.
pub fn read_mesh(path: &Path) -> Result<PolyMesh, MeshReadError> {
    let name = path.display().to_string();
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let text = || {
        crate::input::read_text(path, crate::input::TEXT_FILE_LIMIT)
            .map_err(|e| MeshReadError::Io { file: name.clone(), source: e })
    };
    match ext.as_str() {
        "obj" => read_obj(&text()?, &name),
        "off" => read_off(&text()?, &name),
        other => Err(MeshReadError::Format(other.to_string())),
    }
}

fn syntax(file: &str, line: usize, column: usize, message: impl Into<String>) -> MeshReadError {
    MeshReadError::Syntax { file: file.to_string(), line, column, message: message.into() }
}

/// A coordinate: a finite number (NaN and infinities are named where they stand).
fn coordinate(tok: &str, file: &str, line: usize, column: usize) -> Result<f64, MeshReadError> {
    match tok.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(syntax(file, line, column, format!("expected a finite coordinate, found `{tok}`"))),
        Err(_) => Err(syntax(file, line, column, format!("expected a number, found `{tok}`"))),
    }
}

/// Checks the parsed mesh, naming faces by their lines.
fn finish(
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
    lines: &[usize],
    file: &str,
) -> Result<PolyMesh, MeshReadError> {
    let mut starts = Vec::with_capacity(faces.len() + 1);
    starts.push(0);
    for f in &faces {
        starts.push(starts[starts.len() - 1] + f.len());
    }
    let mesh = PolyMesh::from_flat(positions, starts, faces.concat());
    mesh.check(&|face| Place { file: Some(file.to_string()), line: lines.get(face).copied(), face })?;
    Ok(mesh)
}

/// Reads an OBJ file's text (`file` names it in errors).
///
/// # Errors
/// A malformed `v` or `f` record (`file:line:column`), or a mesh that
/// fails the checks.
pub fn read_obj(text: &str, file: &str) -> Result<PolyMesh, MeshReadError> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces = Vec::new();
    let mut lines = Vec::new();
    let (mut uvs, mut uv_corners, mut all_textured): (Vec<[f64; 2]>, Vec<usize>, bool) = (Vec::new(), Vec::new(), true);
    let (mut object, mut group): (Option<String>, Option<String>) = (None, None);
    let mut groups: Vec<(String, usize)> = Vec::new();
    let mut continued = String::new();
    let mut start_line = 0;
    for (i, raw) in text.lines().enumerate() {
        if continued.is_empty() {
            start_line = i + 1;
        }
        // A trailing backslash continues the record on the next line.
        if let Some(head) = raw.strip_suffix('\\') {
            continued.push_str(head);
            continued.push(' ');
            continue;
        }
        continued.push_str(raw);
        let line = std::mem::take(&mut continued);
        let content = line.split('#').next().unwrap_or("");
        let mut tokens = tokens(content);
        let Some((_, keyword)) = tokens.next() else { continue };
        match keyword {
            "v" => {
                let mut p = [0.0; 3];
                let mut last = keyword.len() + 1;
                for x in &mut p {
                    let (col, tok) =
                        tokens.next().ok_or_else(|| syntax(file, start_line, last + 1, "expected a coordinate"))?;
                    *x = coordinate(tok, file, start_line, col)?;
                    last = col + tok.len();
                }
                positions.push(p);
            }
            "vt" => {
                let mut t = [0.0; 2];
                let mut last = keyword.len() + 1;
                for x in &mut t {
                    let (col, tok) = tokens
                        .next()
                        .ok_or_else(|| syntax(file, start_line, last + 1, "expected a texture coordinate"))?;
                    *x = coordinate(tok, file, start_line, col)?;
                    last = col + tok.len();
                }
                uvs.push(t);
            }
            "o" | "g" => {
                let name = content.trim_start()[1..].trim();
                let slot = if keyword == "o" { &mut object } else { &mut group };
                if slot.is_none() && !name.is_empty() {
                    *slot = Some(name.to_string());
                }
                if !name.is_empty() {
                    // A group starts at the next face; one named twice in a row is the later name.
                    if groups.last().is_some_and(|(_, at)| *at == faces.len()) {
                        groups.pop();
                    }
                    groups.push((name.to_string(), faces.len()));
                }
            }
            "f" => {
                let mut face = Vec::new();
                for (col, tok) in tokens {
                    let mut parts = tok.split('/');
                    let index = parts.next().unwrap_or("");
                    // The texture index, resolved like the vertex index; any corner without one drops them
                    // all; one that names no texture coordinate is refused, as a vertex index is.
                    let texture = parts.next().filter(|t| !t.is_empty());
                    match texture.map(|t| t.parse::<i64>()) {
                        None => all_textured = false,
                        Some(Ok(k)) if k > 0 && (k as usize) <= uvs.len() => uv_corners.push(k as usize - 1),
                        Some(Ok(k)) if k < 0 && k.unsigned_abs() as usize <= uvs.len() => {
                            uv_corners.push(uvs.len() - k.unsigned_abs() as usize)
                        }
                        Some(_) => {
                            let t = texture.unwrap_or("");
                            let count = uvs.len();
                            return Err(syntax(
                                file,
                                start_line,
                                col + index.len() + 1,
                                format!(
                                    "texture index `{t}`: the file has {count} texture coordinates (`vt`) before this face"
                                ),
                            ));
                        }
                    }
                    let k: i64 = index.parse().map_err(|_| {
                        syntax(file, start_line, col, format!("expected a vertex index, found `{tok}`"))
                    })?;
                    let n = positions.len() as i64;
                    let resolved = if k > 0 { k - 1 } else { n + k };
                    if k == 0 || resolved < 0 || resolved >= n {
                        return Err(MeshCheckError::IndexOutOfRange {
                            place: Place { file: Some(file.to_string()), line: Some(start_line), face: faces.len() },
                            index: k,
                            count: positions.len(),
                        }
                        .into());
                    }
                    face.push(resolved as usize);
                }
                faces.push(face);
                lines.push(start_line);
            }
            _ => {}
        }
    }
    if !continued.is_empty() {
        let column = continued.trim_end().len();
        return Err(syntax(
            file,
            start_line,
            column,
            "the record ends with `\\` (continued on the next line), but the file ends there",
        ));
    }
    let mut mesh = finish(positions, faces, &lines, file)?;
    mesh.name = object.or(group);
    groups.retain(|(_, at)| *at < mesh.face_count());
    mesh.groups = groups;
    if all_textured && !uvs.is_empty() {
        mesh = mesh.with_texture(uvs, uv_corners)?;
    }
    Ok(mesh)
}

/// Whitespace-separated tokens with their 1-based columns.
fn tokens(line: &str) -> impl Iterator<Item = (usize, &str)> {
    line.split_ascii_whitespace().map(move |t| (t.as_ptr() as usize - line.as_ptr() as usize + 1, t))
}

/// Reads an OFF file's text (`file` names it in errors).
///
/// # Errors
/// A malformed header, count, coordinate or face (`file:line:column`), or
/// a mesh that fails the checks.
pub fn read_off(text: &str, file: &str) -> Result<PolyMesh, MeshReadError> {
    // Tokens with positions, comments removed, grouped by line.
    let mut lines_of_tokens: Vec<(usize, Vec<(usize, &str)>)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let content = raw.split('#').next().unwrap_or("");
        let t: Vec<(usize, &str)> = tokens(content).collect();
        if !t.is_empty() {
            lines_of_tokens.push((i + 1, t));
        }
    }
    let mut rows = lines_of_tokens.iter();
    let end = || syntax(file, text.lines().count().max(1), 1, "unexpected end of file");
    let (line, header) = rows.next().ok_or_else(end)?;
    let (col, keyword) = header[0];
    if !matches!(keyword, "OFF" | "COFF" | "NOFF" | "CNOFF" | "STOFF") {
        return Err(syntax(file, *line, col, format!("expected `OFF`, found `{keyword}`")));
    }
    let counts: Vec<(usize, usize, &str)> = if header.len() > 1 {
        header[1..].iter().map(|(c, t)| (*line, *c, *t)).collect()
    } else {
        let (l, t) = rows.next().ok_or_else(end)?;
        t.iter().map(|(c, tok)| (*l, *c, *tok)).collect()
    };
    if counts.len() < 2 {
        let (l, c, _) = counts.last().copied().unwrap_or((*line, 1, ""));
        return Err(syntax(file, l, c, "expected the counts: vertices faces [edges]"));
    }
    let count = |(l, c, t): (usize, usize, &str), what: &str| -> Result<usize, MeshReadError> {
        t.parse().map_err(|_| syntax(file, l, c, format!("expected the number of {what}, found `{t}`")))
    };
    let (nv, nf) = (count(counts[0], "vertices")?, count(counts[1], "faces")?);
    let mut positions = Vec::new();
    for _ in 0..nv {
        let (l, t) = rows.next().ok_or_else(end)?;
        if t.len() < 3 {
            let c = t.last().map_or(1, |(c, tok)| c + tok.len());
            return Err(syntax(file, *l, c, "expected three coordinates"));
        }
        let mut p = [0.0; 3];
        for (x, (c, tok)) in p.iter_mut().zip(t) {
            *x = coordinate(tok, file, *l, *c)?;
        }
        positions.push(p);
    }
    let mut faces = Vec::new();
    let mut lines = Vec::new();
    for _ in 0..nf {
        let (l, t) = rows.next().ok_or_else(end)?;
        let (c, tok) = t[0];
        let n: usize =
            tok.parse().map_err(|_| syntax(file, *l, c, format!("expected a vertex count, found `{tok}`")))?;
        // `n` may be any number the file says (2^64 - 1): compared without adding to it.
        if t.len() - 1 < n {
            return Err(syntax(file, *l, t[t.len() - 1].0, format!("expected {n} vertex indices")));
        }
        let mut face = Vec::with_capacity(n);
        for (c, tok) in &t[1..=n] {
            let k: i64 =
                tok.parse().map_err(|_| syntax(file, *l, *c, format!("expected a vertex index, found `{tok}`")))?;
            if k < 0 || k as usize >= positions.len() {
                return Err(MeshCheckError::IndexOutOfRange {
                    place: Place { file: Some(file.to_string()), line: Some(*l), face: faces.len() },
                    index: k,
                    count: positions.len(),
                }
                .into());
            }
            face.push(k as usize);
        }
        faces.push(face);
        lines.push(*l);
    }
    finish(positions, faces, &lines, file)
}
