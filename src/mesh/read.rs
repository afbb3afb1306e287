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
    let mut obj = ObjReader { file, ..ObjReader::default() };
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
        obj.record(&line, start_line)?;
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
    obj.finish()
}

/// What [`read_obj`] has read so far.
#[derive(Default)]
struct ObjReader<'f> {
    file: &'f str,
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
    /// The line of each face.
    lines: Vec<usize>,
    uvs: Vec<[f64; 2]>,
    /// Each corner's texture coordinate, while every corner has one.
    uv_corners: Vec<usize>,
    /// Some corner has no texture index: the texture is dropped.
    untextured: bool,
    object: Option<String>,
    group: Option<String>,
    groups: Vec<(String, usize)>,
}

impl ObjReader<'_> {
    /// One record (a line, its continuations joined) starting on line `line`.
    fn record(&mut self, record: &str, line: usize) -> Result<(), MeshReadError> {
        let content = record.split('#').next().unwrap_or("");
        let mut tokens = tokens(content);
        let Some((_, keyword)) = tokens.next() else { return Ok(()) };
        match keyword {
            "v" => {
                let p = self.numbers::<3>(&mut tokens, line, keyword.len(), "a coordinate")?;
                self.positions.push(p);
            }
            "vt" => {
                let t = self.numbers::<2>(&mut tokens, line, keyword.len(), "a texture coordinate")?;
                self.uvs.push(t);
            }
            "o" | "g" => self.name(keyword, content.trim_start()[1..].trim()),
            "f" => {
                let face = tokens.map(|(col, tok)| self.corner(tok, line, col)).collect::<Result<_, _>>()?;
                self.faces.push(face);
                self.lines.push(line);
            }
            _ => {}
        }
        Ok(())
    }

    /// `N` numbers after a keyword `after` characters long.
    fn numbers<'t, const N: usize>(
        &self,
        tokens: &mut impl Iterator<Item = (usize, &'t str)>,
        line: usize,
        after: usize,
        what: &str,
    ) -> Result<[f64; N], MeshReadError> {
        let mut out = [0.0; N];
        let mut last = after + 1;
        for x in &mut out {
            let (col, tok) =
                tokens.next().ok_or_else(|| syntax(self.file, line, last + 1, format!("expected {what}")))?;
            *x = coordinate(tok, self.file, line, col)?;
            last = col + tok.len();
        }
        Ok(out)
    }

    /// An object's (`o`) or a group's (`g`) name: the mesh's name is the
    /// first object's, else the first group's; a group starts at the next face.
    fn name(&mut self, keyword: &str, name: &str) {
        if name.is_empty() {
            return;
        }
        let slot = if keyword == "o" { &mut self.object } else { &mut self.group };
        if slot.is_none() {
            *slot = Some(name.to_string());
        }
        // One named twice in a row is the later name.
        if self.groups.last().is_some_and(|(_, at)| *at == self.faces.len()) {
            self.groups.pop();
        }
        self.groups.push((name.to_string(), self.faces.len()));
    }

    /// A face corner `v`, `v/t`, `v/t/n` or `v//n` at column `col`: its
    /// vertex (1-based, or negative from the end), its texture index noted.
    fn corner(&mut self, tok: &str, line: usize, col: usize) -> Result<usize, MeshReadError> {
        let mut parts = tok.split('/');
        let index = parts.next().unwrap_or("");
        // The texture index, resolved like the vertex index; any corner without one drops them
        // all; one that names no texture coordinate is refused, as a vertex index is.
        let texture = parts.next().filter(|t| !t.is_empty());
        let count = self.uvs.len();
        match texture.map(|t| t.parse::<i64>()) {
            None => self.untextured = true,
            Some(Ok(k)) if k > 0 && (k as usize) <= count => self.uv_corners.push(k as usize - 1),
            Some(Ok(k)) if k < 0 && k.unsigned_abs() as usize <= count => {
                self.uv_corners.push(count - k.unsigned_abs() as usize)
            }
            Some(_) => {
                let t = texture.unwrap_or("");
                return Err(syntax(
                    self.file,
                    line,
                    col + index.len() + 1,
                    format!("texture index `{t}`: the file has {count} texture coordinates (`vt`) before this face"),
                ));
            }
        }
        let k: i64 = index
            .parse()
            .map_err(|_| syntax(self.file, line, col, format!("expected a vertex index, found `{tok}`")))?;
        let n = self.positions.len() as i64;
        let resolved = if k > 0 { k - 1 } else { n + k };
        if k == 0 || resolved < 0 || resolved >= n {
            return Err(MeshCheckError::IndexOutOfRange {
                place: Place { file: Some(self.file.to_string()), line: Some(line), face: self.faces.len() },
                index: k,
                count: self.positions.len(),
            }
            .into());
        }
        Ok(resolved as usize)
    }

    /// The mesh read: checked, named, its groups and texture kept.
    fn finish(self) -> Result<PolyMesh, MeshReadError> {
        let mut mesh = finish(self.positions, self.faces, &self.lines, self.file)?;
        mesh.name = self.object.or(self.group);
        let mut groups = self.groups;
        groups.retain(|(_, at)| *at < mesh.face_count());
        mesh.groups = groups;
        if !self.untextured && !self.uvs.is_empty() {
            mesh = mesh.with_texture(self.uvs, self.uv_corners)?;
        }
        Ok(mesh)
    }
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
