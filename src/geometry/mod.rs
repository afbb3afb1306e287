//! Output geometry: the sink trait evaluators push into, and the in-memory
//! shape (polylines, quad meshes, point clouds) that is one such sink.

/// The largest coordinate of a control point or mesh vertex: its square,
/// summed over a million terms (a face's corners, a normal's cross
/// products, a distance's axes), stays finite in `f64`.
pub const MAX_COORDINATE: f64 = 1e150;

use std::io;
use std::ops::Range;

mod agree;
mod orient;
pub use agree::agreeing;
pub use orient::inward_faces;

/// Points per batch of [`PointBatches::fold`]: a chain of its own.
pub const BATCH: usize = 1 << 16;
/// Points per chunk handed to a visitor: few enough to stay in the first-level cache.
pub const CHUNK: usize = 512;

/// Random points drawn in batches and folded, never held (the chaos game,
/// [`crate::eval::ChaosGame`]): what density pictures receive.
pub trait PointBatches: Sync {
    /// Coordinates per point.
    fn dim(&self) -> usize;
    /// Folds `points` points: batches of [`BATCH`] points handed to `visit`
    /// in chunks of at most [`CHUNK`] points (`dim` coordinates each, with
    /// their colour coordinates in `[0, 1]` when `colour`, else an empty
    /// slice) into one accumulator per thread made by `init`, merged by
    /// `merge` (which must not depend on the order, like a sum of counts).
    fn fold<T: Send>(
        &self,
        points: usize,
        colour: bool,
        init: impl Fn() -> T + Sync + Send,
        visit: impl Fn(&mut T, &[f64], &[f32]) + Sync + Send,
        merge: impl Fn(T, T) -> T + Sync + Send,
    ) -> T;
}

/// A chaos game that is a plain IFS of the plane: one state, its arrows
/// affine maps of the modelling plane with their probabilities and colours
/// (what a `.flame` file holds; see [`crate::eval::ChaosGame::plain_ifs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PlainIfs {
    /// Per map: its arrow's name.
    pub names: Vec<String>,
    /// Per map: `[a, b, e, c, d, f]`, the map `(x, y) ↦ (a x + b y + e, c x + d y + f)`.
    pub maps: Vec<[f64; 6]>,
    /// Per map: its probability (they sum to 1).
    pub probabilities: Vec<f64>,
    /// Per map: its colour coordinate in `[0, 1]`.
    pub colours: Vec<f64>,
    /// How far each step moves the colour towards the map's ([`crate::eval::RandomSettings::colour_speed`]).
    pub colour_speed: f64,
}

/// Where evaluation output goes. Vertices are numbered from 0 in the order
/// they are pushed, across all objects; elements refer to those numbers.
///
/// Implemented by [`Shape`] (in memory) and by the streaming
/// [`crate::export::ObjWriter`], which is finished by its own consuming
/// `finish`. To re-evaluate into the buffers of an earlier shape, use
/// [`crate::eval::Evaluator::evaluate_into`].
pub trait Sink {
    /// Starts a named object (a piece of the model).
    fn object(&mut self, name: &str) -> io::Result<()>;
    /// Appends vertices: `positions` holds `dim` coordinates per vertex;
    /// `normals`, if any, 3 per vertex.
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()>;
    /// Appends texture coordinates, 2 per entry.
    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()>;
    /// A polyline through the vertices `first .. first + count`, closed or not.
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()>;
    /// Quads (vertex indices counter-clockwise), with texture indices if any.
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()>;
    /// Triangles (vertex indices counter-clockwise).
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()>;

    /// Faces of any degree, counter-clockwise: face `k` has the corners
    /// `corners[starts[k]..starts[k + 1]]` (`starts` holds one more entry
    /// than there are faces). A face of fewer than three corners (the digon
    /// Doo-Sabin makes at a vertex of valence 2) is a doubled edge that no
    /// file holds: writers leave it out.
    ///
    /// The default hands quads to [`Sink::faces`] and triangles, and larger
    /// faces as fans of triangles, to [`Sink::triangles`]; writers whose
    /// format has faces of any degree write them whole.
    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        let (mut quads, mut triangles) = (Vec::new(), Vec::new());
        for w in starts.windows(2) {
            match &corners[w[0]..w[1]] {
                &[a, b, c, d] => quads.push([a, b, c, d]),
                f => triangles.extend(fan(f, 0)),
            }
        }
        if !quads.is_empty() {
            self.faces(&quads, None)?;
        }
        if !triangles.is_empty() {
            self.triangles(&triangles)?;
        }
        Ok(())
    }

    /// The vertices `first .. first + count` are points of the current
    /// object on their own (a cloud: no element joins them), which OBJ
    /// groups with `p` records under the object's `o`. Formats whose clouds
    /// are their vertices ignore it (the default).
    fn cloud(&mut self, first: usize, count: usize) -> io::Result<()> {
        let _ = (first, count);
        Ok(())
    }

    /// Starts a named group of the current object's faces (OBJ's `g`): the
    /// faces that follow belong to it. Formats without groups ignore it (the default).
    fn group(&mut self, name: &str) -> io::Result<()> {
        let _ = name;
        Ok(())
    }

    /// Faces of any degree as [`Sink::polygons`], with a texture vertex
    /// (given by [`Sink::uvs`], numbered from 0 across the output) for each
    /// corner: `uv_corners[k]` belongs to `corners[k]`. Formats without
    /// texture coordinates drop them (the default).
    fn textured_polygons(&mut self, starts: &[usize], corners: &[usize], uv_corners: &[usize]) -> io::Result<()> {
        let _ = uv_corners;
        self.polygons(starts, corners)
    }

    /// Colours (RGB) of the vertices of the next [`Sink::vertices`] call,
    /// one per vertex. Formats without colours ignore them (the default).
    fn colours(&mut self, rgb: &[[u8; 3]]) -> io::Result<()> {
        let _ = rgb;
        Ok(())
    }

    /// No vertex nor texture coordinate follows: only elements (objects,
    /// groups, polylines, faces) come next. A writer that keeps elements
    /// apart until the end (OBJ's elements after every vertex) may then
    /// write them in place; vertices after this are an error there. The
    /// default does nothing.
    fn vertices_complete(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// The fan of triangles of a polygon from its corner `apex`: `[f[apex], f[apex + i], f[apex + i + 1]]`
/// for `i` in `1..n − 1` (indices mod `n`); none for fewer than three corners. The one fan every
/// writer, picture and front end splits polygons with.
///
/// ```
/// let fan: Vec<[u32; 3]> = bcifs::geometry::fan(&[7, 8, 9, 10], 1).collect();
/// assert_eq!(fan, [[8, 9, 10], [8, 10, 7]]);
/// ```
pub fn fan<T: Copy>(face: &[T], apex: usize) -> impl Iterator<Item = [T; 3]> + '_ {
    let n = face.len();
    (1..n.saturating_sub(1)).map(move |i| [face[apex % n], face[(apex + i) % n], face[(apex + i + 1) % n]])
}

/// Area-weighted unit vertex normals of the polygons `faces` over
/// `points`: each face adds its area vector (Newell's, exact for planar
/// faces, the mean of the fan's for skew ones) to its corners, and each sum
/// is normalised; a vertex no face of positive area touches gets zero.
///
/// ```
/// let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let square: &[usize] = &[0, 1, 2, 3];
/// let normals = bcifs::geometry::area_normals(&points, [square].into_iter());
/// assert_eq!(normals, vec![[0.0, 0.0, 1.0]; 4]);
/// ```
pub fn area_normals<'a>(points: &[[f64; 3]], faces: impl Iterator<Item = &'a [usize]>) -> Vec<[f64; 3]> {
    let mut sums = vec![[0.0f64; 3]; points.len()];
    for face in faces.filter(|f| f.len() >= 3) {
        let n = area_vector(face.len(), |k| points[face[k]]);
        for &a in face {
            (0..3).for_each(|c| sums[a][c] += n[c]);
        }
    }
    sums.iter_mut().for_each(|n| *n = unit_or_zero(*n));
    sums
}

/// The triangles through corner `k` of `face` that a client may split it
/// into: a quad's of both diagonals, a triangle itself.
fn corner_triangles(points: &[[f64; 3]], face: &[usize], k: usize) -> Vec<nalgebra::Vector3<f64>> {
    let p = |i: usize| nalgebra::Vector3::<f64>::from(points[face[i % face.len()]]);
    let tri = |a: usize, b: usize, c: usize| (p(b) - p(a)).cross(&(p(c) - p(a)));
    match face.len() {
        4 => vec![tri(k + 3, k, k + 1), tri(k, k + 1, k + 2), tri(k, k + 2, k + 3)],
        _ => vec![tri(k + face.len() - 1, k, k + 1)],
    }
}

/// Vertex normals of a mesh ([`area_normals`]'s area weighting)
/// that agree with every triangle a client may split the faces at each
/// vertex into: where the weighted sum points against one, [`agreeing`]'s
/// direction instead.
pub fn agreeing_normals<'a>(points: &[[f64; 3]], faces: impl Iterator<Item = &'a [usize]> + Clone) -> Vec<[f64; 3]> {
    let mut normals = area_normals(points, faces.clone());
    let mut against = vec![false; points.len()];
    for face in faces.clone().filter(|f| f.len() >= 3) {
        for (k, &v) in face.iter().enumerate() {
            let n = nalgebra::Vector3::<f64>::from(normals[v]);
            against[v] |= corner_triangles(points, face, k).iter().any(|t| t.dot(&n) <= 0.0 && t.norm() > 0.0);
        }
    }
    if !against.contains(&true) {
        return normals;
    }
    let mut sums: Vec<(nalgebra::Vector3<f64>, Vec<nalgebra::Vector3<f64>>)> =
        vec![(nalgebra::Vector3::zeros(), Vec::new()); points.len()];
    for face in faces.filter(|f| f.len() >= 3) {
        let area = nalgebra::Vector3::<f64>::from(area_vector(face.len(), |k| points[face[k]]));
        for (k, &v) in face.iter().enumerate().filter(|(_, v)| against[**v]) {
            sums[v].0 += area;
            sums[v].1.extend(corner_triangles(points, face, k));
        }
    }
    for (v, (sum, triangles)) in sums.iter().enumerate().filter(|(v, _)| against[*v]) {
        let n = agreeing(*sum, triangles);
        normals[v] = [n.x, n.y, n.z];
    }
    normals
}

/// The area vector (Newell's) of the polygon whose `k`-th corner is at
/// `corner(k)`, for `k` below `n`: the sum over its edges, in order from
/// the first corner, that [`area_normals`] gives each face.
#[inline]
pub fn area_vector(n: usize, corner: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
    let mut v = [0.0; 3];
    for k in 0..n {
        let (p, q) = (corner(k), corner((k + 1) % n));
        v[0] += (p[1] - q[1]) * (p[2] + q[2]);
        v[1] += (p[2] - q[2]) * (p[0] + q[0]);
        v[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    v
}

/// `n` divided by its length, or zero when that length is zero or not finite
/// (a vertex no face of positive area touches), as [`area_normals`] ends.
#[inline]
pub fn unit_or_zero(n: [f64; 3]) -> [f64; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() { n.map(|x| x / len) } else { [0.0; 3] }
}

/// A quad of an in-memory mesh: four vertex (or texture) indices, counter-clockwise.
pub type Quad = [u32; 4];

/// A named part of a [`Shape`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Vertices pushed while this object was current.
    pub vertices: Range<usize>,
    /// Polylines: `(first vertex, count, closed)`.
    pub polylines: Vec<(usize, usize, bool)>,
    /// Faces pushed while this object was current.
    pub faces: Range<usize>,
    /// Triangles pushed while this object was current (the last object also
    /// owns triangles stored without a [`Sink`] call, after its range).
    pub triangles: Range<usize>,
}

/// Evaluation output held in memory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shape {
    /// Coordinates per vertex (2 or 3).
    pub dim: usize,
    /// `dim` coordinates per vertex.
    pub positions: Vec<f64>,
    /// 3 coordinates per vertex, or empty.
    pub normals: Vec<f64>,
    /// 2 coordinates per texture vertex.
    pub uvs: Vec<f64>,
    /// RGB colour per vertex, or empty (written by the formats that hold colours).
    pub colours: Vec<[u8; 3]>,
    /// Quads, counter-clockwise (compact indices: a mesh in memory has fewer than 2^32 vertices).
    pub quads: Vec<Quad>,
    /// Texture indices of the quads, or empty.
    pub quad_uvs: Vec<Quad>,
    /// Triangles, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
    /// The objects, in order.
    pub objects: Vec<Object>,
}

impl Shape {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Vertex `i` as `[x, y, z]` (z = 0 in 2D).
    pub fn point(&self, i: usize) -> [f64; 3] {
        let p = &self.positions[i * self.dim..(i + 1) * self.dim];
        [p[0], p[1], if self.dim > 2 { p[2] } else { 0.0 }]
    }

    /// All vertices as `[x, y, z]`.
    pub fn points(&self) -> Vec<[f64; 3]> {
        (0..self.vertex_count()).map(|i| self.point(i)).collect()
    }

    /// Axis-aligned bounds `(min, max)`, or `None` when empty.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut it = (0..self.vertex_count()).map(|i| self.point(i));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| {
            ([lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])], [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])])
        }))
    }

    /// Drops the exact duplicates among the vertices of a point cloud (a
    /// shape without polylines, quads or triangles), keeping the first of
    /// each in order, and returns how many it dropped; `None`, and the
    /// shape untouched, when the shape has elements that refer to vertices.
    /// Points are equal when their coordinates are bit for bit (`0.0` and
    /// `-0.0` are distinct, as a file would print them).
    ///
    /// ```
    /// use bcifs::geometry::Shape;
    /// let mut cloud = Shape { dim: 2, positions: vec![0.0, 1.0, 2.0, 3.0, 0.0, 1.0], ..Shape::default() };
    /// assert_eq!(cloud.dedup_points(), Some(1));
    /// assert_eq!(cloud.positions, [0.0, 1.0, 2.0, 3.0]);
    /// ```
    pub fn dedup_points(&mut self) -> Option<usize> {
        if !self.quads.is_empty() || !self.triangles.is_empty() || self.polylines().next().is_some() {
            return None;
        }
        let (dim, n) = (self.dim.max(1), self.vertex_count());
        let mut seen = std::collections::HashSet::with_capacity(n);
        let mut keep = Vec::with_capacity(n);
        for i in 0..n {
            let key: Vec<u64> = self.positions[i * dim..(i + 1) * dim].iter().map(|x| x.to_bits()).collect();
            keep.push(seen.insert(key));
        }
        let dropped = keep.iter().filter(|k| !**k).count();
        if dropped == 0 {
            return Some(0);
        }
        let has_normals = self.normals.len() == 3 * n;
        let (mut w, mut new_index) = (0usize, Vec::with_capacity(n + 1));
        for (i, &k) in keep.iter().enumerate() {
            new_index.push(w);
            if k {
                self.positions.copy_within(i * dim..(i + 1) * dim, w * dim);
                if has_normals {
                    self.normals.copy_within(3 * i..3 * i + 3, 3 * w);
                }
                w += 1;
            }
        }
        new_index.push(w);
        if self.colours.len() == n {
            let mut k = keep.iter();
            self.colours.retain(|_| *k.next().unwrap_or(&false));
        }
        self.positions.truncate(w * dim);
        if has_normals {
            self.normals.truncate(3 * w);
        }
        for o in &mut self.objects {
            o.vertices = new_index[o.vertices.start.min(n)]..new_index[o.vertices.end.min(n)];
        }
        Some(dropped)
    }

    /// Sets the normals of a 3D shape with faces to the area-weighted
    /// normals of its quads and triangles ([`area_normals`]).
    pub fn set_area_normals(&mut self) {
        if self.dim != 3 || (self.quads.is_empty() && self.triangles.is_empty()) {
            return;
        }
        let points = self.points();
        let quads: Vec<[usize; 4]> = self.quads.iter().map(|q| q.map(|i| i as usize)).collect();
        let faces = quads.iter().map(|q| q.as_slice()).chain(self.triangles.iter().map(|t| t.as_slice()));
        self.normals = area_normals(&points, faces).into_iter().flatten().collect();
    }

    /// All polylines of all objects.
    pub fn polylines(&self) -> impl Iterator<Item = (usize, usize, bool)> + '_ {
        self.objects.iter().flat_map(|o| o.polylines.iter().copied())
    }

    /// Every edge of the quads as an unordered vertex pair, with multiplicity.
    pub fn edge_multiplicities(&self) -> std::collections::HashMap<(usize, usize), usize> {
        let mut m = std::collections::HashMap::new();
        for q in &self.quads {
            for k in 0..4 {
                let (a, b) = (q[k] as usize, q[(k + 1) % 4] as usize);
                *m.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        m
    }

    /// `V - E + F` of the quad mesh (vertices counted only if used by a quad).
    pub fn euler_characteristic(&self) -> i64 {
        let mut used = std::collections::HashSet::new();
        for q in &self.quads {
            used.extend(q.iter().map(|&i| i as usize));
        }
        used.len() as i64 - self.edge_multiplicities().len() as i64 + self.quads.len() as i64
    }

    /// A shape holding one polyline through `points` (each of `dim` coordinates).
    pub fn polyline(name: &str, dim: usize, points: &[f64], closed: bool) -> Shape {
        let mut shape = Shape::default();
        shape.add_polyline(name, dim, points, closed);
        shape
    }

    /// Adds an object holding one polyline through `points`.
    pub fn add_polyline(&mut self, name: &str, dim: usize, points: &[f64], closed: bool) {
        let first = self.vertex_count();
        let count = points.len() / dim.max(1);
        // Writing into memory cannot fail.
        let _ = self.object(name);
        let _ = self.vertices(dim, points, None);
        let _ = Sink::polyline(self, first, count, closed);
    }

    /// Pushes the whole shape into `sink` (objects, vertices, normals,
    /// texture coordinates, polylines, quads and triangles), without `finish`.
    ///
    /// # Errors
    /// The first write error of the sink.
    pub fn replay(&self, sink: &mut dyn Sink) -> io::Result<()> {
        let d = self.dim.max(1);
        if !self.uvs.is_empty() {
            sink.uvs(&self.uvs)?;
        }
        for (k, o) in self.objects.iter().enumerate() {
            sink.object(if o.name.is_empty() { "shape" } else { &o.name })?;
            let v = o.vertices.clone();
            if !v.is_empty() {
                if self.colours.len() == self.vertex_count() {
                    sink.colours(&self.colours[v.clone()])?;
                }
                let normals = (!self.normals.is_empty()).then(|| &self.normals[v.start * 3..v.end * 3]);
                sink.vertices(d, &self.positions[v.start * d..v.end * d], normals)?;
            }
            let end = if k + 1 == self.objects.len() { self.triangles.len() } else { o.triangles.end };
            let t = &self.triangles[o.triangles.start.min(end)..end];
            let cloud = o.polylines.is_empty() && o.faces.is_empty() && t.is_empty();
            if cloud && !v.is_empty() && self.objects.len() > 1 {
                sink.cloud(v.start, v.len())?;
            }
            for &(first, count, closed) in &o.polylines {
                sink.polyline(first, count, closed)?;
            }
            let f = o.faces.clone();
            if !f.is_empty() {
                let wide = |v: &[Quad]| -> Vec<[usize; 4]> { v.iter().map(|q| q.map(|i| i as usize)).collect() };
                let uvs = (!self.quad_uvs.is_empty()).then(|| wide(&self.quad_uvs[f.clone()]));
                sink.faces(&wide(&self.quads[f]), uvs.as_deref())?;
            }
            if !t.is_empty() {
                sink.triangles(t)?;
            }
        }
        Ok(())
    }

    /// Starts a mesh of `dim`-dimensional vertices that overwrites this
    /// shape, keeping its buffers' contents for reuse (the mesher resizes
    /// and overwrites them): one object called `name`.
    pub(crate) fn reuse_as_mesh(&mut self, dim: usize, name: &str) {
        self.dim = dim;
        self.triangles.clear();
        self.objects.clear();
        self.objects.push(Object { name: name.to_string(), ..Object::default() });
    }

    /// Ends a mesh started by [`Shape::reuse_as_mesh`]: its object holds every vertex and quad.
    pub(crate) fn close_mesh(&mut self) {
        let (v, f) = (self.vertex_count(), self.quads.len());
        let o = self.current();
        o.vertices = 0..v;
        o.faces = 0..f;
    }

    fn current(&mut self) -> &mut Object {
        if self.objects.is_empty() {
            self.objects.push(Object::default());
        }
        self.objects.last_mut().expect("just pushed")
    }
}

impl Sink for Shape {
    fn object(&mut self, name: &str) -> io::Result<()> {
        let (v, f, t) = (self.vertex_count(), self.quads.len(), self.triangles.len());
        self.objects.push(Object {
            name: name.to_string(),
            vertices: v..v,
            polylines: Vec::new(),
            faces: f..f,
            triangles: t..t,
        });
        Ok(())
    }

    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        if self.dim == 0 {
            self.dim = dim;
        }
        if dim != self.dim {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, "vertices of different dimensions in one shape"));
        }
        self.positions.extend_from_slice(positions);
        if let Some(n) = normals {
            self.normals.extend_from_slice(n);
        }
        let end = self.vertex_count();
        self.current().vertices.end = end;
        Ok(())
    }

    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        self.uvs.extend_from_slice(uvs);
        Ok(())
    }

    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        self.current().polylines.push((first, count, closed));
        Ok(())
    }

    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        let narrow = |q: &[usize; 4]| -> io::Result<Quad> {
            let mut out = [0u32; 4];
            for (o, &i) in out.iter_mut().zip(q) {
                *o = u32::try_from(i).map_err(|_| {
                    io::Error::new(io::ErrorKind::InvalidInput, "an in-memory mesh holds fewer than 2^32 vertices")
                })?;
            }
            Ok(out)
        };
        for q in quads {
            self.quads.push(narrow(q)?);
        }
        if let Some(t) = uvs {
            for q in t {
                self.quad_uvs.push(narrow(q)?);
            }
        }
        let end = self.quads.len();
        self.current().faces.end = end;
        Ok(())
    }

    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.triangles.extend_from_slice(triangles);
        let end = self.triangles.len();
        self.current().triangles.end = end;
        Ok(())
    }
}
