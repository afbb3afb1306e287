//! glTF 2.0 binary (`.glb`: what web viewers, Blender's preferred importer
//! and game engines read): the one place glTF records are formatted.

use std::io::{self, BufReader, Read, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::Path;

use serde_json::{Value, json};

use super::atomic::{AtomicFile, Spool, Target};
use super::axes::{Coordinates, Up};
use crate::geometry::Sink;

/// The largest `.glb` (its length is a `u32`).
const GLB_LIMIT: u64 = u32::MAX as u64;
/// glTF's component types and buffer-view targets.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// Primitive modes.
const POINTS: u32 = 0;
const LINES: u32 = 1;
const TRIANGLES: u32 = 4;
/// No texture coordinate at this corner.
const NO_UV: u32 = u32::MAX;

/// A [`Sink`] that writes a glTF 2.0 binary file: one mesh and one node per
/// object (an object with no vertex gives none), its faces triangulated
/// (quads and larger faces as fans) in a `TRIANGLES` primitive, its
/// polylines as `LINES`, and a cloud (vertices with no element) as
/// `POINTS`. Vertices carry `POSITION` (with the `min`/`max` the
/// specification requires), and `NORMAL` (normalised), `COLOR_0` (RGBA,
/// linear as glTF 2.0 requires: the sRGB bytes bcifs colours with, decoded
/// by the sRGB curve, as normalised 16-bit numbers so that dark shades keep
/// their steps) and `TEXCOORD_0` when given. Texture coordinates are face-varying
/// in bcifs (a corner has a vertex and a texture vertex, as in OBJ) and
/// per-vertex in glTF: a vertex whose corners have different texture
/// vertices (a seam) is written once per texture vertex, and `v` is turned
/// to glTF's top-left origin (`1 − v`); textured surfaces get one plain
/// material (clients read texture coordinates of a material's primitives
/// only). Coordinates are `float`, Y-up as
/// glTF requires whatever [`Coordinates::up`] says.
///
/// The current object's positions, normals and triangles go to side files
/// as they come (glTF's arrays as they will be written: 28 bytes a vertex,
/// 12 a triangle; its colours, texture coordinates and lines are held, 4
/// bytes a vertex with colours), so a mesh of any size is written in
/// bounded memory; a textured object is read back into memory when it
/// ends, to split its seams. Finished objects go to another side file, and
/// the file is assembled at [`GltfWriter::finish`]. A `.glb` holds at most 4 GiB: larger output is
/// refused, nothing written.
///
/// ```
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-glb-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("square.glb");
/// let mut glb = bcifs::export::GltfWriter::create(&path)?;
/// glb.object("square")?;
/// glb.vertices(2, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], None)?;
/// glb.polygons(&[0, 4], &[0, 1, 2, 3])?;
/// glb.finish()?;
/// let bytes = std::fs::read(&path)?;
/// assert_eq!(&bytes[..4], b"glTF");
/// assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize, bytes.len());
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub struct GltfWriter {
    coordinates: Coordinates,
    main: Option<AtomicFile>,
    bin: Option<Spool>,
    /// Bytes in the binary chunk so far.
    bin_len: u64,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    /// A textured surface was written: the one material (which clients need to read texture coordinates) is used.
    material: bool,
    /// The object being written.
    current: Part,
    /// Its positions, normals (as given: normalised when written) and
    /// triangle corners' vertices, little-endian `f32` and `u32`.
    positions: Spool,
    normals: Spool,
    corners: Spool,
    /// Vertices of the objects before the current one.
    base: usize,
    /// Texture vertices of the objects before the current one.
    uv_base: usize,
    colours: Vec<[u8; 3]>,
}

/// One object until the next begins: its vertices and triangle corners in
/// the writer's side files (glTF's arrays as they are written), the rest in memory.
struct Part {
    name: String,
    /// Vertices.
    count: usize,
    /// The positions' bounds.
    lo: [f32; 3],
    hi: [f32; 3],
    /// Every vertex so far came with a normal.
    normals: bool,
    colours: Vec<[u8; 4]>,
    /// Texture vertices, `v` already turned.
    uvs: Vec<[f32; 2]>,
    /// Triangle corners.
    corners: usize,
    /// The largest vertex of a triangle corner.
    largest: Option<u32>,
    /// Each corner's texture vertex (or [`NO_UV`]), once a corner has one.
    corner_uvs: Vec<u32>,
    /// Named groups of triangles: each from its first corner on (a primitive each).
    groups: Vec<(String, usize)>,
    lines: Vec<u32>,
}

impl Default for Part {
    fn default() -> Part {
        Part {
            name: String::new(),
            count: 0,
            lo: [f32::INFINITY; 3],
            hi: [f32::NEG_INFINITY; 3],
            normals: true,
            colours: Vec::new(),
            uvs: Vec::new(),
            corners: 0,
            largest: None,
            corner_uvs: Vec::new(),
            groups: Vec::new(),
            lines: Vec::new(),
        }
    }
}

/// A textured object, in memory: glTF's texture coordinates are per vertex,
/// so the vertices at seams are split ([`Held::split_seams`]) before it is written.
#[derive(Default)]
struct Held {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    colours: Vec<[u8; 4]>,
    uvs: Vec<[f32; 2]>,
    /// Triangle corners: vertex and texture vertex (or [`NO_UV`]).
    corners: Vec<[u32; 2]>,
}

/// Where the bytes of a buffer view come from: memory, or a range of bytes
/// of a side file (`normalise`: `f32` triples made unit vectors on the way).
enum Bytes<'a> {
    Memory(&'a [u8]),
    Side { file: Side, from: u64, len: u64, normalise: bool },
}

/// The writer's side files.
#[derive(Clone, Copy)]
enum Side {
    Positions,
    Normals,
    Corners,
}

fn invalid(what: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, what)
}

impl GltfWriter {
    /// Starts writing `path`.
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create(path: &Path) -> io::Result<GltfWriter> {
        GltfWriter::create_in(&Target::from(path))
    }

    /// Starts writing `target`: a file, or a buffer ([`Target::Memory`]).
    ///
    /// # Errors
    /// The temporary files cannot be created.
    pub fn create_in(target: &Target) -> io::Result<GltfWriter> {
        Ok(GltfWriter {
            coordinates: Coordinates::default(),
            main: Some(AtomicFile::create_in(target)?),
            bin: Some(Spool::create(&target.beside(), "elements")?),
            bin_len: 0,
            buffer_views: Vec::new(),
            accessors: Vec::new(),
            meshes: Vec::new(),
            nodes: Vec::new(),
            material: false,
            current: Part::default(),
            positions: Spool::create(&target.beside(), "elements")?,
            normals: Spool::create(&target.beside(), "elements")?,
            corners: Spool::create(&target.beside(), "elements")?,
            base: 0,
            uv_base: 0,
            colours: Vec::new(),
        })
    }

    /// The same writer, with the input axes of `coordinates` (the file is
    /// Y-up whatever `coordinates.up` says; glTF has no digits: `float`).
    pub fn with_coordinates(mut self, coordinates: Coordinates) -> GltfWriter {
        self.coordinates = Coordinates { up: Up::Y, ..coordinates };
        self
    }

    /// Completes the file: the JSON chunk, then the binary chunk, renamed
    /// onto the target.
    ///
    /// # Errors
    /// The output exceeds 4 GiB, or an I/O error; the target is then left as it was.
    pub fn finish(mut self) -> io::Result<()> {
        self.end_object()?;
        let mut root = json!({
            "asset": { "version": "2.0", "generator": format!("bcifs {}", env!("CARGO_PKG_VERSION")) },
            "scene": 0,
            "scenes": [{ "nodes": (0..self.nodes.len()).collect::<Vec<_>>() }],
            "nodes": self.nodes,
        });
        if !self.meshes.is_empty() {
            root["meshes"] = Value::Array(std::mem::take(&mut self.meshes));
            root["accessors"] = Value::Array(std::mem::take(&mut self.accessors));
            root["bufferViews"] = Value::Array(std::mem::take(&mut self.buffer_views));
            root["buffers"] = json!([{ "byteLength": self.bin_len }]);
        }
        if self.material {
            // Plain grey, for the texture a user puts on it.
            root["materials"] = json!([{
                "name": "bcifs",
                "pbrMetallicRoughness": { "baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8 },
            }]);
        }
        let mut text = serde_json::to_vec(&root).map_err(io::Error::other)?;
        text.resize(text.len().next_multiple_of(4), b' ');
        let bin_chunk = if self.bin_len > 0 { 8 + self.bin_len } else { 0 };
        let total = 12 + 8 + text.len() as u64 + bin_chunk;
        if total > GLB_LIMIT {
            return Err(too_large(total));
        }
        let mut main = self.main.take().expect("finish once");
        let w = main.writer();
        w.write_all(b"glTF")?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&(total as u32).to_le_bytes())?;
        w.write_all(&(text.len() as u32).to_le_bytes())?;
        w.write_all(b"JSON")?;
        w.write_all(&text)?;
        if self.bin_len > 0 {
            w.write_all(&(self.bin_len as u32).to_le_bytes())?;
            w.write_all(b"BIN\0")?;
        }
        self.bin.take().expect("finish once").append_to(&mut main)?;
        main.commit()
    }

    /// Appends `bytes` (padded to 4) to the binary chunk as a buffer view; its index.
    fn view(&mut self, bytes: Bytes<'_>, target: u32) -> io::Result<usize> {
        let len = match &bytes {
            Bytes::Memory(b) => b.len() as u64,
            Bytes::Side { len, .. } => *len,
        };
        let padded = len.next_multiple_of(4);
        if self.bin_len + padded + 1024 > GLB_LIMIT {
            return Err(too_large(self.bin_len + padded));
        }
        let w = self.bin.as_mut().expect("not finished").writer();
        match bytes {
            Bytes::Memory(b) => w.write_all(b)?,
            Bytes::Side { file, from, len, normalise } => {
                let side = match file {
                    Side::Positions => &mut self.positions,
                    Side::Normals => &mut self.normals,
                    Side::Corners => &mut self.corners,
                };
                let mut reader = side.reader()?;
                reader.seek(SeekFrom::Start(from))?;
                let mut reader = BufReader::with_capacity(1 << 20, reader).take(len);
                if normalise {
                    let mut v = [0u8; 12];
                    for _ in 0..len / 12 {
                        reader.read_exact(&mut v)?;
                        let x = |k: usize| f32::from_le_bytes(v[4 * k..4 * k + 4].try_into().expect("4 bytes"));
                        w.write_all(&triple(unit([x(0), x(1), x(2)])))?;
                    }
                } else if io::copy(&mut reader, w)? != len {
                    return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "a glTF side file ended early"));
                }
            }
        }
        w.write_all(&[0; 3][..(padded - len) as usize])?;
        self.buffer_views.push(json!({
            "buffer": 0, "byteOffset": self.bin_len, "byteLength": len, "target": target,
        }));
        self.bin_len += padded;
        Ok(self.buffer_views.len() - 1)
    }

    /// An accessor over a new buffer view of `bytes`; its index.
    fn accessor(&mut self, bytes: Bytes<'_>, target: u32, mut description: Value) -> io::Result<usize> {
        description["bufferView"] = self.view(bytes, target)?.into();
        self.accessors.push(description);
        Ok(self.accessors.len() - 1)
    }

    /// Writes the current object as a mesh and a node, and starts the next
    /// (its side files emptied).
    fn end_object(&mut self) -> io::Result<()> {
        let part = std::mem::take(&mut self.current);
        let written = self.write_part(part);
        self.positions.clear()?;
        self.normals.clear()?;
        self.corners.clear()?;
        written
    }

    fn write_part(&mut self, part: Part) -> io::Result<()> {
        self.base += part.count;
        self.uv_base += part.uvs.len();
        if part.count == 0 {
            return Ok(());
        }
        let n = part.count;
        if part.largest.is_some_and(|v| v as usize >= n) || part.lines.iter().any(|&v| v as usize >= n) {
            let v = self.first_outside(&part)?;
            return Err(invalid(format!(
                "a glTF element refers to vertex {}, outside its object (vertices {} to {})",
                self.base - n + v as usize,
                self.base - n,
                self.base
            )));
        }
        if !part.uvs.is_empty() && part.corner_uvs.iter().any(|&t| t != NO_UV) {
            return self.write_held(part);
        }
        let mut attributes = serde_json::Map::new();
        let side = |file, len, normalise| Bytes::Side { file, from: 0, len, normalise };
        let position = self.accessor(
            side(Side::Positions, 12 * n as u64, false),
            ARRAY_BUFFER,
            json!({ "componentType": FLOAT, "count": n, "type": "VEC3", "min": part.lo, "max": part.hi }),
        )?;
        attributes.insert("POSITION".into(), position.into());
        if part.normals {
            let description = json!({ "componentType": FLOAT, "count": n, "type": "VEC3" });
            let normal = self.accessor(side(Side::Normals, 12 * n as u64, true), ARRAY_BUFFER, description)?;
            attributes.insert("NORMAL".into(), normal.into());
        }
        self.colour_accessor(&part.colours, n, &mut attributes)?;
        let pieces = triangle_pieces(&part.groups, part.corners)
            .map(|(range, group)| {
                let bytes = Bytes::Side {
                    file: Side::Corners,
                    from: 4 * range.start as u64,
                    len: 4 * range.len() as u64,
                    normalise: false,
                };
                (bytes, range.len(), TRIANGLES, group)
            })
            .collect();
        self.primitives(attributes, pieces, &part.lines, part.name)
    }

    /// The first vertex of a corner (else a line) of `part` outside it.
    fn first_outside(&mut self, part: &Part) -> io::Result<u32> {
        let mut corners = BufReader::with_capacity(1 << 20, self.corners.reader()?);
        let mut word = [0u8; 4];
        for _ in 0..part.corners {
            corners.read_exact(&mut word)?;
            let v = u32::from_le_bytes(word);
            if v as usize >= part.count {
                return Ok(v);
            }
        }
        Ok(part.lines.iter().copied().find(|&v| v as usize >= part.count).unwrap_or(u32::MAX))
    }

    /// A textured object: read back into memory, its seams split, written.
    fn write_held(&mut self, part: Part) -> io::Result<()> {
        let n = part.count;
        let read = |spool: &mut Spool, words: usize| -> io::Result<Vec<u32>> {
            let mut bytes = vec![0u8; 4 * words];
            spool.reader()?.read_exact(&mut bytes)?;
            Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes(w.try_into().expect("4 bytes"))).collect())
        };
        let triples = |words: Vec<u32>| -> Vec<[f32; 3]> {
            words.chunks_exact(3).map(|t| [t[0], t[1], t[2]].map(f32::from_bits)).collect()
        };
        let positions = triples(read(&mut self.positions, 3 * n)?);
        let normals = if part.normals { triples(read(&mut self.normals, 3 * n)?) } else { Vec::new() };
        let vertices = read(&mut self.corners, part.corners)?;
        let corners = vertices.iter().zip(&part.corner_uvs).map(|(&v, &t)| [v, t]).collect();
        let held = Held { positions, normals, colours: part.colours, uvs: part.uvs, corners }.split_seams();
        let n = held.positions.len();
        let mut attributes = serde_json::Map::new();
        let (lo, hi) = held.positions.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), p| {
            ([0, 1, 2].map(|a| lo[a].min(p[a])), [0, 1, 2].map(|a| hi[a].max(p[a])))
        });
        let position = self.accessor(
            Bytes::Memory(&floats(held.positions.iter().flatten().copied())),
            ARRAY_BUFFER,
            json!({ "componentType": FLOAT, "count": n, "type": "VEC3", "min": lo, "max": hi }),
        )?;
        attributes.insert("POSITION".into(), position.into());
        if held.normals.len() == n {
            let unit = held.normals.iter().flat_map(|v| unit(*v));
            let normal = self.accessor(
                Bytes::Memory(&floats(unit)),
                ARRAY_BUFFER,
                json!({ "componentType": FLOAT, "count": n, "type": "VEC3" }),
            )?;
            attributes.insert("NORMAL".into(), normal.into());
        }
        if held.uvs.len() == n {
            let uv = self.accessor(
                Bytes::Memory(&floats(held.uvs.iter().flatten().copied())),
                ARRAY_BUFFER,
                json!({ "componentType": FLOAT, "count": n, "type": "VEC2" }),
            )?;
            attributes.insert("TEXCOORD_0".into(), uv.into());
        }
        self.colour_accessor(&held.colours, n, &mut attributes)?;
        let triangles: Vec<u8> = held.corners.iter().flat_map(|c| c[0].to_le_bytes()).collect();
        let pieces = triangle_pieces(&part.groups, held.corners.len())
            .map(|(range, group)| {
                (Bytes::Memory(&triangles[4 * range.start..4 * range.end]), range.len(), TRIANGLES, group)
            })
            .collect();
        self.primitives(attributes, pieces, &part.lines, part.name)
    }

    /// The `COLOR_0` accessor (linear), when every one of the `n` vertices has a colour.
    fn colour_accessor(
        &mut self,
        colours: &[[u8; 4]],
        n: usize,
        attributes: &mut serde_json::Map<String, Value>,
    ) -> io::Result<()> {
        if colours.len() == n {
            // Linear values (glTF's COLOR_0 is linear; bcifs's colours are sRGB), one table for the 256 bytes.
            let linear: Vec<[u8; 2]> = (0..=255u8).map(|b| srgb_to_linear_u16(b).to_le_bytes()).collect();
            let bytes: Vec<u8> = colours
                .iter()
                .flat_map(|c| {
                    [linear[c[0] as usize], linear[c[1] as usize], linear[c[2] as usize], u16::MAX.to_le_bytes()]
                })
                .flatten()
                .collect();
            let colour = self.accessor(
                Bytes::Memory(&bytes),
                ARRAY_BUFFER,
                json!({ "componentType": UNSIGNED_SHORT, "normalized": true, "count": n, "type": "VEC4" }),
            )?;
            attributes.insert("COLOR_0".into(), colour.into());
        }
        Ok(())
    }

    /// The object's primitives (`pieces`: indices, their count, mode and
    /// group; then the lines), its mesh and its node.
    fn primitives(
        &mut self,
        attributes: serde_json::Map<String, Value>,
        pieces: Vec<(Bytes<'_>, usize, u32, Option<&str>)>,
        lines: &[u32],
        name: String,
    ) -> io::Result<()> {
        let line_bytes: Vec<u8> = lines.iter().flat_map(|i| i.to_le_bytes()).collect();
        let lines = (Bytes::Memory(&line_bytes), lines.len(), LINES, None);
        let mut primitives = Vec::new();
        for (indices, count, mode, group) in pieces.into_iter().chain([lines]) {
            if count == 0 {
                continue;
            }
            let accessor = self.accessor(
                indices,
                ELEMENT_ARRAY_BUFFER,
                json!({ "componentType": UNSIGNED_INT, "count": count, "type": "SCALAR" }),
            )?;
            let mut primitive = json!({ "attributes": attributes, "indices": accessor, "mode": mode });
            if mode == TRIANGLES && attributes.contains_key("TEXCOORD_0") {
                primitive["material"] = 0.into();
                self.material = true;
            }
            if let Some(group) = group {
                primitive["extras"] = json!({ "group": group });
            }
            primitives.push(primitive);
        }
        if primitives.is_empty() {
            primitives.push(json!({ "attributes": attributes, "mode": POINTS }));
        }
        let mut mesh = json!({ "primitives": primitives });
        let mut node = json!({ "mesh": self.meshes.len() });
        if !name.is_empty() {
            mesh["name"] = name.clone().into();
            node["name"] = name.into();
        }
        self.meshes.push(mesh);
        self.nodes.push(node);
        Ok(())
    }

    /// The current object's index of the global vertex `v` (which may come
    /// after the element: checked when the object ends).
    fn local(&self, v: usize) -> io::Result<u32> {
        match v.checked_sub(self.base).and_then(|i| u32::try_from(i).ok()).filter(|&i| i != NO_UV) {
            Some(i) => Ok(i),
            None => Err(invalid(format!(
                "a glTF element refers to vertex {v}, outside its object (which starts at vertex {})",
                self.base
            ))),
        }
    }

    /// Faces as fans of triangles, with their texture vertices if any.
    fn fans<'a>(&mut self, faces: impl Iterator<Item = (&'a [usize], Option<&'a [usize]>)>) -> io::Result<()> {
        for (face, uv) in faces.filter(|(f, _)| f.len() >= 3) {
            for k in 1..face.len() - 1 {
                for c in [0, k, k + 1] {
                    let v = self.local(face[c])?;
                    let t = match uv {
                        Some(uv) => {
                            let t = uv[c].checked_sub(self.uv_base).filter(|&t| t < self.current.uvs.len());
                            t.ok_or_else(|| {
                                invalid(format!("a glTF face refers to texture vertex {}, not written", uv[c]))
                            })? as u32
                        }
                        None => NO_UV,
                    };
                    self.corners.writer().write_all(&v.to_le_bytes())?;
                    let part = &mut self.current;
                    part.largest = part.largest.max(Some(v));
                    if t != NO_UV && part.corner_uvs.is_empty() {
                        part.corner_uvs.resize(part.corners, NO_UV);
                    }
                    if t != NO_UV || !part.corner_uvs.is_empty() {
                        part.corner_uvs.push(t);
                    }
                    part.corners += 1;
                }
            }
        }
        Ok(())
    }
}

impl Held {
    /// The same object with one vertex per (vertex, texture vertex) pair
    /// its triangles use, when it has texture coordinates (glTF's are per
    /// vertex): seams split, texture coordinates per vertex.
    fn split_seams(mut self) -> Held {
        if self.uvs.is_empty() || self.corners.iter().all(|c| c[1] == NO_UV) {
            self.uvs.clear();
            return self;
        }
        let n = self.positions.len();
        let mut seen = vec![false; n];
        let mut pairs: std::collections::HashMap<[u32; 2], u32> = std::collections::HashMap::new();
        let mut origin: Vec<u32> = (0..n as u32).collect();
        let mut uv_of: Vec<u32> = vec![NO_UV; n];
        for corner in &mut self.corners {
            let [v, t] = *corner;
            let new = if !seen[v as usize] {
                seen[v as usize] = true;
                uv_of[v as usize] = t;
                v
            } else if uv_of[v as usize] == t {
                v
            } else {
                *pairs.entry([v, t]).or_insert_with(|| {
                    origin.push(v);
                    uv_of.push(t);
                    (origin.len() - 1) as u32
                })
            };
            corner[0] = new;
        }
        let pick = |values: &[[f32; 3]]| -> Vec<[f32; 3]> {
            if values.len() == n { origin.iter().map(|&o| values[o as usize]).collect() } else { Vec::new() }
        };
        let positions = pick(&self.positions);
        let normals = pick(&self.normals);
        let colours = if self.colours.len() == n {
            origin.iter().map(|&o| self.colours[o as usize]).collect()
        } else {
            Vec::new()
        };
        let uvs = uv_of.iter().map(|&t| if t == NO_UV { [0.0, 0.0] } else { self.uvs[t as usize] }).collect();
        Held { positions, normals, colours, uvs, ..self }
    }
}

/// The triangles' corners by group: a range of corners and its group's
/// name (none for the corners before the first group), in order; a group
/// that starts where the next does is left out.
fn triangle_pieces(groups: &[(String, usize)], corners: usize) -> impl Iterator<Item = (Range<usize>, Option<&str>)> {
    let mut cuts: Vec<(Option<&str>, usize)> = vec![(None, 0)];
    for (name, at) in groups {
        if *at == cuts[cuts.len() - 1].1 {
            cuts.pop();
        }
        cuts.push((Some(name), *at));
    }
    (0..cuts.len()).map(move |k| {
        let (name, at) = cuts[k];
        let end = cuts.get(k + 1).map_or(corners, |c| c.1).min(corners);
        (at.min(end)..end, name)
    })
}

/// The little-endian bytes of `values`.
fn floats(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

/// The little-endian bytes of a vector.
fn triple(v: [f32; 3]) -> [u8; 12] {
    let mut bytes = [0u8; 12];
    for (k, x) in v.iter().enumerate() {
        bytes[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
    }
    bytes
}

/// `v` normalised (glTF requires unit normals); a zero or non-finite normal
/// (a vertex no face gives a direction) becomes the up axis.
fn unit(v: [f32; 3]) -> [f32; 3] {
    let len = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    if len > 0.0 && len.is_finite() { v.map(|x| x / len) } else { [0.0, 1.0, 0.0] }
}

fn too_large(bytes: u64) -> io::Error {
    invalid(format!(
        "a .glb file holds at most 4 GiB and this output needs {:.1} GiB: lower the depth, or write .ply",
        bytes as f64 / f64::from(1u32 << 30)
    ))
}

impl Sink for GltfWriter {
    fn object(&mut self, name: &str) -> io::Result<()> {
        self.end_object()?;
        self.current.name = name.to_string();
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        super::finite::finite_vertices(positions, normals)?;
        let dim = dim.max(1);
        let count = positions.len() / dim;
        let turn = self.coordinates.turn(dim);
        let before = self.current.count;
        let (part, w) = (&mut self.current, self.positions.writer());
        for p in positions.chunks_exact(dim) {
            let p = turn
                .apply([p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)])
                .map(|x| x as f32);
            (part.lo, part.hi) = ([0, 1, 2].map(|a| part.lo[a].min(p[a])), [0, 1, 2].map(|a| part.hi[a].max(p[a])));
            w.write_all(&triple(p))?;
        }
        part.count += count;
        // Normals and colours are kept only while every vertex of the object has them.
        match normals.filter(|n| n.len() >= 3 * count) {
            Some(n) if part.normals => {
                let w = self.normals.writer();
                for n in n.chunks_exact(3).take(count) {
                    w.write_all(&triple(turn.apply([n[0], n[1], n[2]]).map(|x| x as f32)))?;
                }
            }
            _ => part.normals = false,
        }
        let colours = std::mem::take(&mut self.colours);
        if colours.len() == count && part.colours.len() == before {
            part.colours.extend(colours.iter().map(|c| [c[0], c[1], c[2], 255]));
        } else {
            part.colours.clear();
        }
        Ok(())
    }

    fn colours(&mut self, rgb: &[[u8; 3]]) -> io::Result<()> {
        self.colours = rgb.to_vec();
        Ok(())
    }

    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        self.current.uvs.extend(uvs.chunks_exact(2).map(|t| [t[0] as f32, 1.0 - t[1] as f32]));
        Ok(())
    }

    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        let segments = if closed && count > 2 { count } else { count.saturating_sub(1) };
        for k in 0..segments {
            let (a, b) = (self.local(first + k)?, self.local(first + (k + 1) % count)?);
            self.current.lines.extend([a, b]);
        }
        Ok(())
    }

    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        match uvs {
            Some(uvs) => self.fans(quads.iter().zip(uvs).map(|(q, t)| (q.as_slice(), Some(t.as_slice())))),
            None => self.fans(quads.iter().map(|q| (q.as_slice(), None))),
        }
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.fans(triangles.iter().map(|t| (t.as_slice(), None)))
    }

    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        self.fans(starts.windows(2).map(|w| (&corners[w[0]..w[1]], None)))
    }

    fn group(&mut self, name: &str) -> io::Result<()> {
        self.current.groups.push((name.to_string(), self.current.corners));
        Ok(())
    }

    fn textured_polygons(&mut self, starts: &[usize], corners: &[usize], uv_corners: &[usize]) -> io::Result<()> {
        if uv_corners.len() != corners.len() {
            return self.polygons(starts, corners);
        }
        self.fans(starts.windows(2).map(|w| (&corners[w[0]..w[1]], Some(&uv_corners[w[0]..w[1]]))))
    }
}

#[cfg(test)]
mod tests;

/// An sRGB byte as a linear value, normalised to 16 bits (IEC 61966-2-1's curve).
pub fn srgb_to_linear_u16(b: u8) -> u16 {
    let c = f64::from(b) / 255.0;
    let linear = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    (linear * 65535.0).round() as u16
}
