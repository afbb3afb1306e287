//! Subdivided meshes pushed into a sink as they are made: the net before
//! the last step is held in memory, the last step (the net, or Doo-Sabin's,
//! Catmull-Clark's and Loop's limits) goes straight to the sink, so a depth-10 cube (6.3 million faces)
//! written to a file needs the memory of depth 9 only. Loop's deep nets and
//! limits come from the net two steps before (depth 8 of 10), the net
//! between named ([`super::named::LoopChild`]). √3's limit points are a mask
//! on the last net: small ones are computed on it, large ones from the net
//! two steps before with both nets after it named ([`super::named::Sqrt3Child`]).

use super::emit::{Emit, Written};
use super::error::SubdivideError;
use super::polymesh::{PolyMesh, Scheme};
use super::subdivide::RuleWeights;
use crate::geometry::Sink;

/// Loop nets and limits of more faces than this before the last step are
/// written two steps from the net before them (at depth 10 on the
/// icosahedron: the 1.3 million faces of depth 8 held instead of the 5.2
/// million of depth 9).
pub(crate) const TWO_STEPS_FROM: u128 = 1 << 18;

/// √3 nets and limits whose made net (the last one for the limit, the one
/// before for the net) would have more faces than this are written from
/// the net two steps back, the nets after it named: made, they take about
/// 100 bytes a face (under 256 MiB up to here), named a fifth of that but
/// about 1.5 times the time (the last net's points are computed when asked).
pub(crate) const SQRT3_NAMED_FROM: u128 = 1 << 21;

/// A subdivision to run: the scheme, the steps, Doo-Sabin quad weights
/// (`None`: classic) and the in-memory limit in bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Subdivision {
    /// The scheme.
    pub scheme: Scheme,
    /// Steps.
    pub depth: usize,
    /// Doo-Sabin quad weights (`None`: classic).
    pub weights: Option<RuleWeights>,
    /// The most bytes the net before the last step may take.
    pub memory_limit: usize,
}

impl PolyMesh {
    /// Pushes the net after `job.depth` steps of `job.scheme` (or, with
    /// `limit`, the points of the limit surface at its vertices) into
    /// `sink`, holding only the net before the last step in memory: one
    /// object, vertices, then faces of any degree ([`Sink::polygons`]).
    ///
    /// # Errors
    /// That net over `memory_limit` (with the estimate), a Doo-Sabin limit
    /// of a mesh without interior vertex, or the sink's error.
    pub fn subdivide_into(
        &self,
        job: &Subdivision,
        limit: bool,
        name: &str,
        sink: &mut dyn Sink,
    ) -> Result<Written, SubdivideError> {
        let Subdivision { scheme, depth, weights, memory_limit } = *job;
        let depth = if limit { depth.max(1) } else { depth };
        if limit && scheme == Scheme::DooSabin && !self.has_interior_vertex() {
            return Err(SubdivideError::NoInteriorVertex);
        }
        let io = SubdivideError::Write;
        sink.object(name).map_err(io)?;
        let held = if limit { depth } else { depth.saturating_sub(1) };
        if scheme == Scheme::Sqrt3 && depth >= 2 && self.estimate(scheme, held).0 > SQRT3_NAMED_FROM {
            // The last two nets named from the one before them (a tenth of the memory), unless a
            // face of a border-splitting step has two border edges.
            let (net, t) = self.net_and_topology(scheme, depth - 2, weights, memory_limit)?;
            let mut out = Emit::into_sink(sink);
            if net.sqrt3_twice_into(&t, depth - 2, limit, &mut out).map_err(io)? {
                return out.flush().map_err(io);
            }
        }
        if limit && scheme == Scheme::Sqrt3 {
            // √3's limit points are a mask on the last net's rings: that net
            // in memory, its points and faces streamed (no copy of it made).
            let (net, t) = self.net_and_topology(scheme, depth, weights, memory_limit)?;
            let mut out = Emit::into_sink(sink);
            net.triangle_limit_into(&t, true, None, &mut out).map_err(io)?;
            return out.flush().map_err(io);
        }
        if depth == 0 {
            return self.push_into(sink).map_err(io);
        }
        let mut out = Emit::into_sink(sink);
        if self.two_loop_steps(scheme, depth) {
            // The last two steps (or the limit after them) from the net before them: a quarter of the memory.
            let (net, t) = self.net_and_topology(scheme, depth - 2, weights, memory_limit)?;
            let triangle = weights.and_then(RuleWeights::triangle);
            match limit {
                true => net.loop_limit_twice_into(&t, triangle, &mut out),
                false => net.loop_twice_into(&t, triangle, &mut out),
            }
            .map_err(io)?;
            return out.flush().map_err(io);
        }
        let (net, t) = self.net_and_topology(scheme, depth - 1, weights, memory_limit)?;
        if limit {
            // Limit points are a local mask on the next net: from the net before it, streamed.
            net.limit_step_into(&t, scheme, weights, &mut out)
        } else {
            net.step_into(scheme, depth - 1, &t, weights, &mut out)
        }
        .map_err(io)?;
        out.flush().map_err(io)
    }
}

impl PolyMesh {
    /// Whether the last two Loop steps of `depth` are made from the net
    /// before them ([`TWO_STEPS_FROM`]).
    fn two_loop_steps(&self, scheme: Scheme, depth: usize) -> bool {
        scheme == Scheme::Loop && depth >= 2 && self.estimate(scheme, depth - 1).0 > TWO_STEPS_FROM
    }

    /// The output of [`PolyMesh::subdivide_into`] in memory: the net after
    /// `job.depth` steps, or with `limit` the limit surface's points at the
    /// last net's vertices with its faces, in order (Doo-Sabin's: the dual's
    /// quads), within `job.memory_limit`.
    ///
    /// # Errors
    /// The output over `memory_limit` (with the estimate), or a Doo-Sabin
    /// limit of a mesh without interior vertex.
    pub fn subdivided(&self, job: &Subdivision, limit: bool) -> Result<PolyMesh, SubdivideError> {
        let Subdivision { scheme, depth, weights, memory_limit } = *job;
        if !limit {
            return self.subdivide_with(scheme, depth, weights, memory_limit);
        }
        match scheme {
            Scheme::CatmullClark | Scheme::Loop => {
                // Made from the net before the last step, as the streamed limit is
                // (the same numbers): the last net is never held beside the output.
                let depth = depth.max(1);
                self.check_size(scheme, depth, memory_limit)?;
                let two = self.two_loop_steps(scheme, depth);
                let (net, t) = self.net_and_topology(scheme, depth - 1 - usize::from(two), weights, memory_limit)?;
                let grow = if two { 4 } else { 1 };
                let (nv, nc) = (grow * net.positions.len(), grow * net.corner_count());
                let mut out = Emit::memory(nv + nc + grow * net.face_count(), 4 * nc);
                // Writing into memory fails only when cancelled.
                match two {
                    true => net.loop_limit_twice_into(&t, weights.and_then(RuleWeights::triangle), &mut out),
                    false => net.limit_step_into(&t, scheme, weights, &mut out),
                }
                .map_err(SubdivideError::Write)?;
                Ok(out.finish())
            }
            Scheme::Sqrt3 => {
                // The last net's points replaced by their limits, in place.
                let (mut net, t) = self.net_and_topology(scheme, depth.max(1), weights, memory_limit)?;
                let points = net.triangle_limit_points(&t, true, None);
                net.positions = points;
                Ok(net)
            }
            Scheme::DooSabin => self.doo_sabin_limit(depth, weights, memory_limit),
        }
    }

    /// Where the input's groups of faces start in the output of `depth`
    /// steps of `scheme` (`limit`: the limit surface's faces), in order:
    /// `None` for the faces before the first group; one entry, unnamed,
    /// when the output keeps no groups (fewer than two: the object is
    /// one; Doo-Sabin's limit, the dual's faces; Doo-Sabin's and √3's nets,
    /// whose faces come from edges and vertices too). A face number may be
    /// past the last face (an empty group).
    pub fn group_cuts(&self, scheme: Scheme, depth: usize, limit: bool) -> Vec<(Option<String>, usize)> {
        let steps = if limit { depth.max(1) } else { depth };
        let groups = self.groups_after(scheme, steps).filter(|g| g.len() > 1 && !(limit && scheme == Scheme::DooSabin));
        let mut cuts: Vec<(Option<String>, usize)> = match groups {
            Some(g) => g.into_iter().map(|(n, at)| (Some(n), at)).collect(),
            None => vec![(None, 0)],
        };
        if cuts.first().is_some_and(|c| c.1 > 0) {
            cuts.insert(0, (None, 0));
        }
        cuts
    }

    /// [`PolyMesh::subdivide_into`], with area-weighted vertex normals
    /// ([`crate::geometry::area_normals`]) and, when `texture` is asked and
    /// the mesh has texture coordinates, the texture mesh subdivided alike
    /// ([`PolyMesh::texture_after`]: Catmull-Clark and Loop) as
    /// [`Sink::textured_polygons`]. The whole output is made in memory
    /// first (the normals need every face around a vertex), so
    /// `job.memory_limit` bounds the output itself.
    ///
    /// # Errors
    /// The output over `memory_limit` (with the estimate), a Doo-Sabin limit
    /// of a mesh without interior vertex, or the sink's error.
    pub fn subdivide_smooth_into(
        &self,
        job: &Subdivision,
        limit: bool,
        texture: bool,
        name: &str,
        sink: &mut dyn Sink,
    ) -> Result<Written, SubdivideError> {
        let Subdivision { scheme, depth, weights, .. } = *job;
        let io = SubdivideError::Write;
        let PolyMesh { positions, starts, indices, .. } = self.subdivided(job, limit)?;
        let steps = if limit { depth.max(1) } else { depth };
        let uv = if texture { self.texture_after(scheme, steps, weights) } else { None };
        let uv = uv.filter(|t| t.indices.len() == indices.len());
        let faces = || starts.windows(2).map(|w| &indices[w[0]..w[1]]);
        let normals = crate::geometry::area_normals(&positions, faces());
        sink.object(name).map_err(io)?;
        sink.vertices(3, positions.as_flattened(), Some(normals.as_flattened())).map_err(io)?;
        if let Some(uv) = &uv {
            let flat: Vec<f64> = uv.positions.iter().flat_map(|t| [t[0], t[1]]).collect();
            sink.uvs(&flat).map_err(io)?;
        }
        sink.vertices_complete().map_err(io)?;
        let face_count = starts.len() - 1;
        let cuts: Vec<(Option<String>, usize)> =
            self.group_cuts(scheme, depth, limit).into_iter().map(|(g, at)| (g, at.min(face_count))).collect();
        for (k, (group, at)) in cuts.iter().enumerate() {
            let (at, end) = (*at, cuts.get(k + 1).map_or(face_count, |c| c.1));
            if let Some(group) = group {
                sink.group(group).map_err(io)?;
            }
            let range = &starts[at..=end.max(at)];
            match &uv {
                Some(uv) => sink.textured_polygons(range, &indices, &uv.indices).map_err(io)?,
                None => sink.polygons(range, &indices).map_err(io)?,
            }
        }
        Ok(Written { vertices: positions.len(), faces: faces().filter(|f| f.len() >= 3).count() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::LoopWeights;
    use crate::mesh::topology::{BORDER, Topology};

    /// The icosahedron without three of its faces (a border of valences 3 to 5).
    fn open_icosahedron() -> PolyMesh {
        let ico = PolyMesh::icosahedron();
        PolyMesh::new(ico.positions.clone(), ico.faces().skip(3).map(<[usize]>::to_vec).collect()).unwrap()
    }

    /// Triangle meshes with valences 3 to 6, closed and open.
    fn triangle_meshes() -> [PolyMesh; 4] {
        let open = open_icosahedron();
        let tet = PolyMesh::new(
            vec![[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]],
            vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]],
        )
        .unwrap();
        [PolyMesh::icosahedron(), open, tet, PolyMesh::cube().triangulated()]
    }

    /// A Loop net's topology read off the step before is the one searched for,
    /// array for array (twins, first corners, border flags): closed and open
    /// meshes, and an irregular mesh of 5,120 triangles with and without holes.
    #[test]
    fn loop_topology_read_off_the_step_before_is_the_one_searched_for() {
        let meshes = triangle_meshes().into_iter().map(|m| (m, 4)).chain(irregular_and_holes().map(|m| (m, 2)));
        assert_topology_read_off(Scheme::Loop, meshes);
    }

    /// The topology [`PolyMesh::net_and_topology`] hands on, at every depth up
    /// to each mesh's, is the one [`Topology::trusted`] searches for.
    fn assert_topology_read_off(scheme: Scheme, meshes: impl IntoIterator<Item = (PolyMesh, usize)>) {
        for (mesh, depth) in meshes {
            for d in 0..=depth {
                let (net, t) = mesh.net_and_topology(scheme, d, None, 1 << 30).unwrap();
                assert_eq!(t, Topology::trusted(&net), "{scheme:?} depth {d}");
            }
        }
    }

    /// The same for Catmull-Clark: quads, triangles and larger faces, closed
    /// and open, the irregular mesh with its holes.
    #[test]
    fn catmull_clark_topology_read_off_the_step_before_is_the_one_searched_for() {
        let mut meshes: Vec<(PolyMesh, usize)> = triangle_meshes().into_iter().map(|m| (m, 3)).collect();
        meshes.extend([(PolyMesh::cube(), 4), (open_mixed(), 3)]);
        meshes.extend(irregular_and_holes().map(|m| (m, 2)));
        assert_topology_read_off(Scheme::CatmullClark, meshes);
    }

    /// An open mesh of a pentagon and two triangles.
    fn open_mixed() -> PolyMesh {
        PolyMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.3],
                [3.0, 1.0, 0.0],
                [2.0, 2.0, 0.5],
                [0.0, 2.0, 0.0],
                [1.0, 3.0, 0.2],
                [-1.0, 1.0, 0.1],
            ],
            vec![vec![0, 1, 2, 3, 4], vec![4, 3, 5], vec![0, 4, 6]],
        )
        .unwrap()
    }

    /// An irregular mesh of 5,120 triangles (valences 4 to 16), and the same
    /// with the faces around four vertices far apart cut out (four border loops).
    fn irregular_and_holes() -> [PolyMesh; 2] {
        let irregular = crate::mesh::read_mesh(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/irregular5120.obj"
        )))
        .unwrap();
        let cut = [0, 700, 1400, 2100];
        let kept: Vec<Vec<usize>> =
            irregular.faces().filter(|f| !f.iter().any(|v| cut.contains(v))).map(<[usize]>::to_vec).collect();
        let holes = PolyMesh::new(irregular.positions.clone(), kept).unwrap();
        assert!(Topology::trusted(&holes).boundary_edges() > 20);
        [irregular, holes]
    }

    /// The limit streamed by [`PolyMesh::subdivide_into`] is [`PolyMesh::limit_with`]'s, bit for bit.
    fn assert_streamed_limit_is_in_memory(mesh: &PolyMesh, scheme: Scheme, weights: Option<RuleWeights>, depth: usize) {
        let job = Subdivision { scheme, depth, weights, memory_limit: 1 << 30 };
        let mut streamed = crate::geometry::Shape::default();
        mesh.subdivide_into(&job, true, "x", &mut streamed).unwrap();
        let memory = mesh.limit_with(scheme, depth, weights, 1 << 30).unwrap();
        assert_eq!(streamed.positions, memory.positions, "{scheme:?} depth {depth}");
        assert_eq!(streamed.quads, memory.quads, "{scheme:?} depth {depth}");
        assert_eq!(streamed.triangles, memory.triangles, "{scheme:?} depth {depth}");
        // And the limit made in memory as a mesh (what outputs with normals write).
        let made = mesh.subdivided(&job, true).unwrap();
        assert_eq!(made.positions.as_flattened(), memory.positions.as_slice(), "{scheme:?} depth {depth}");
        let quads = memory.quads.iter().map(|q| q.iter().map(|&v| v as usize).collect::<Vec<_>>());
        let faces: Vec<Vec<usize>> = quads.chain(memory.triangles.iter().map(|t| t.to_vec())).collect();
        assert_eq!(made.faces().map(<[usize]>::to_vec).collect::<Vec<_>>(), faces, "{scheme:?} depth {depth}");
    }

    /// Catmull-Clark's limit streamed from the net before the last step is
    /// the limit computed on the made net, bit for bit and face for face:
    /// closed and open meshes, quads, triangles and larger faces, an unused vertex.
    #[test]
    fn the_streamed_catmull_clark_limit_is_the_limit_in_memory() {
        let (ico, open) = (PolyMesh::icosahedron(), open_icosahedron());
        let mut unused = PolyMesh::cube().positions.clone();
        unused.push([5.0, 5.0, 5.0]);
        let lonely = PolyMesh::new(unused, PolyMesh::cube().faces().map(<[usize]>::to_vec).collect()).unwrap();
        for mesh in [PolyMesh::cube(), ico, open, lonely, open_mixed()] {
            for depth in 1..=3 {
                assert_streamed_limit_is_in_memory(&mesh, Scheme::CatmullClark, None, depth);
            }
        }
    }

    /// Loop's limit streamed from the net before the last step is the limit
    /// computed on the made net, bit for bit and face for face: closed and
    /// open meshes, Loop's and other weights.
    #[test]
    fn the_streamed_loop_limit_is_the_limit_in_memory() {
        for mesh in triangle_meshes() {
            for weights in [None, Some(LoopWeights { w: 0.3, sigma: 0.9 })] {
                for depth in 1..=3 {
                    assert_streamed_limit_is_in_memory(&mesh, Scheme::Loop, weights.map(Into::into), depth);
                }
            }
        }
    }

    /// Doo-Sabin's limit streamed, and made as a mesh, is the limit of
    /// [`PolyMesh::limit_with`]: closed and open meshes, depths 1 to 3.
    #[test]
    fn the_streamed_doo_sabin_limit_is_the_limit_in_memory() {
        for mesh in [PolyMesh::cube(), PolyMesh::icosahedron(), open_icosahedron()] {
            for depth in 1..=3 {
                assert_streamed_limit_is_in_memory(&mesh, Scheme::DooSabin, None, depth);
            }
        }
    }

    /// √3's limit streamed from the last net is the limit computed in
    /// memory, bit for bit and face for face: closed and open meshes
    /// (√3 refines the border every other step), odd and even depths.
    #[test]
    fn the_streamed_sqrt3_limit_is_the_limit_in_memory() {
        for mesh in triangle_meshes() {
            for depth in 1..=4 {
                assert_streamed_limit_is_in_memory(&mesh, Scheme::Sqrt3, None, depth);
            }
        }
    }

    /// A Loop net named from the net before it ([`LoopChild`]) is the made
    /// net, corner for corner and bit for bit: vertices, twins, first corners,
    /// border flags, edge numbers and points; closed and open meshes,
    /// valences 3 to 16, holes, Loop's and other weights.
    #[test]
    fn a_named_loop_net_is_the_made_one() {
        use crate::mesh::named::LoopChild;
        use crate::mesh::topology::Net;
        let meshes = triangle_meshes().into_iter().chain(irregular_and_holes());
        for (k, mesh) in meshes.enumerate() {
            for weights in [None, Some(LoopWeights { w: 0.3, sigma: 0.9 })] {
                let t = Topology::trusted(&mesh);
                let named = LoopChild::new(&mesh, &t, weights);
                let made = mesh.subdivide_with(Scheme::Loop, 1, weights.map(Into::into), 1 << 30).unwrap();
                let made_t = Topology::trusted(&made);
                let (edge_of, _) = made.edge_numbering(&made_t, &mut Emit::points(), |_, _| [0.0; 3]).unwrap();
                assert_eq!((named.vertex_count(), named.corner_count()), (made.positions.len(), made.corner_count()));
                for (x, &v) in made.indices.iter().enumerate() {
                    assert_eq!(named.vertex(x), v, "mesh {k} corner {x}");
                    assert_eq!(named.twin(x), made_t.twin(x), "mesh {k} corner {x}");
                    assert_eq!(named.edge(x), edge_of[x] as usize, "mesh {k} corner {x}");
                }
                for v in 0..made.positions.len() {
                    assert_eq!(named.first(v), made_t.first(v), "mesh {k} vertex {v}");
                    assert_eq!(named.on_border(v), made_t.on_border(v), "mesh {k} vertex {v}");
                    assert_eq!(named.point(v).map(f64::to_bits), made.positions[v].map(f64::to_bits));
                }
            }
        }
    }

    /// A named net is the made one: its corners, in the order of their
    /// numbers, are the made net's corners in order, with the same vertices
    /// and twins; its vertices' first corners, border flags and points are
    /// the made net's (points bit for bit).
    fn assert_named_is_made<N: crate::mesh::topology::Net>(named: &N, made: &PolyMesh, what: &str) {
        let t = Topology::trusted(made);
        let corners: Vec<usize> = (0..named.corner_count()).filter(|&x| named.is_corner(x)).collect();
        assert_eq!(corners.len(), made.corner_count(), "{what}");
        let mut real = std::collections::HashMap::new();
        real.insert(BORDER, BORDER);
        real.extend(corners.iter().enumerate().map(|(k, &x)| (x, k)));
        for (k, &x) in corners.iter().enumerate() {
            assert_eq!(named.vertex(x), made.indices[k], "{what}: corner {k}");
            assert_eq!(real.get(&named.twin(x)), Some(&t.twin(k)), "{what}: twin of corner {k}");
            assert_eq!(real[&named.next(x)], t.next(made, k), "{what}: next of corner {k}");
        }
        assert_eq!(named.vertex_count(), made.positions.len(), "{what}");
        for v in 0..made.positions.len() {
            assert_eq!(real.get(&named.first(v)), Some(&t.first(v)), "{what}: first corner of vertex {v}");
            assert_eq!(named.on_border(v), t.on_border(v), "{what}: vertex {v}");
            assert_eq!(named.point(v).map(f64::to_bits), made.positions[v].map(f64::to_bits), "{what}: vertex {v}");
        }
    }

    /// √3 steps named from the net before them, once and twice (the first
    /// kept points, the second computes them), are the made steps: closed
    /// and open meshes, holes, border-splitting steps and the others.
    #[test]
    fn named_sqrt3_steps_are_the_made_ones() {
        use crate::mesh::named::Sqrt3Child;
        use crate::mesh::topology::Made;
        let meshes = triangle_meshes().into_iter().chain(irregular_and_holes());
        let mut named = 0;
        for (k, mesh) in meshes.enumerate() {
            for d in 0..2 {
                let net = |d| mesh.net_and_topology(Scheme::Sqrt3, d, None, 1 << 30).unwrap();
                let (parent, t) = net(d);
                let made = Made { mesh: &parent, t: &t };
                let Some(once) = Sqrt3Child::new(&made, d % 2 == 1, true) else { continue };
                assert_named_is_made(&once, &net(d + 1).0, &format!("mesh {k}, step {d}"));
                let Some(twice) = Sqrt3Child::new(&once, d % 2 == 0, false) else { continue };
                assert_named_is_made(&twice, &net(d + 2).0, &format!("mesh {k}, steps {d} and {}", d + 1));
                named += 1;
            }
        }
        assert!(named >= 8, "{named} cases named twice");
        // A face with two border edges on a splitting step (CGAL's rule splits it twice): not
        // named, and the streamed limit is made from the last net, with nothing written before.
        let square = PolyMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            vec![vec![0, 1, 2], vec![0, 2, 3]],
        )
        .unwrap();
        let t = Topology::trusted(&square);
        assert!(Sqrt3Child::new(&Made { mesh: &square, t: &t }, true, true).is_none());
        let mut out = Emit::memory(0, 0);
        assert!(!square.sqrt3_twice_into(&t, 1, true, &mut out).unwrap());
        assert_eq!(out.finish().positions.len(), 0);
    }

    /// Two meshes made in memory are the same: points bit for bit, faces.
    fn assert_same_mesh(a: &PolyMesh, b: &PolyMesh, what: &str) {
        let bits = |m: &PolyMesh| m.positions.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b), "{what}");
        assert_eq!((&a.starts, &a.indices), (&b.starts, &b.indices), "{what}");
    }

    /// √3's limit and net two steps from a net (both nets between named)
    /// are the limit on the made net and the made net, bit for bit and face
    /// for face: closed and open meshes, holes, both parities of the
    /// border-splitting steps.
    #[test]
    fn sqrt3s_limit_and_net_two_steps_away_are_the_made_ones() {
        let meshes = triangle_meshes().into_iter().chain(irregular_and_holes());
        for (k, mesh) in meshes.enumerate() {
            for d in 0..3 {
                let net = |d| mesh.net_and_topology(Scheme::Sqrt3, d, None, 1 << 30).unwrap();
                let ((far, far_t), (last, last_t)) = (net(d), net(d + 2));
                let (mut two, mut made) = (Emit::memory(0, 0), Emit::memory(0, 0));
                assert!(far.sqrt3_twice_into(&far_t, d, true, &mut two).unwrap(), "mesh {k} depth {d}");
                last.triangle_limit_into(&last_t, true, None, &mut made).unwrap();
                assert_same_mesh(&two.finish(), &made.finish(), &format!("mesh {k} depth {d}"));
                // And the net itself.
                let mut two = Emit::memory(0, 0);
                assert!(far.sqrt3_twice_into(&far_t, d, false, &mut two).unwrap(), "mesh {k} depth {d}");
                let (before, before_t) = net(d + 1);
                let mut made = Emit::memory(0, 0);
                before.sqrt3_into(&before_t, d % 2 == 0, &mut made).unwrap();
                assert_same_mesh(&two.finish(), &made.finish(), &format!("mesh {k} net depth {}", d + 2));
            }
        }
    }

    /// Loop's limit two steps from a net (the step between named) is the
    /// limit one step from the made net between, bit for bit and face for
    /// face: closed and open meshes, holes, Loop's and other weights.
    #[test]
    fn loops_limit_two_steps_away_is_the_limit_one_step_away() {
        let meshes = triangle_meshes().into_iter().map(|m| (m, 3)).chain(irregular_and_holes().map(|m| (m, 2)));
        for (mesh, depth) in meshes {
            for weights in [None, Some(LoopWeights { w: 0.3, sigma: 0.9 })] {
                for d in 0..depth {
                    let net = |d| mesh.net_and_topology(Scheme::Loop, d, weights.map(Into::into), 1 << 30).unwrap();
                    let ((far, far_t), (near, near_t)) = (net(d), net(d + 1));
                    let (mut two, mut one) = (Emit::memory(0, 0), Emit::memory(0, 0));
                    far.loop_limit_twice_into(&far_t, weights, &mut two).unwrap();
                    near.loop_limit_into(&near_t, weights, &mut one).unwrap();
                    assert_same_mesh(&two.finish(), &one.finish(), &format!("depth {d}"));
                }
            }
        }
    }

    /// Loop's deep nets streamed (from two steps back, the net between
    /// named) are the net in memory bit for bit, numbering included.
    #[test]
    fn loop_nets_streamed_are_the_nets_in_memory() {
        let ico = PolyMesh::icosahedron();
        assert!(ico.two_loop_steps(Scheme::Loop, 8));
        let job = Subdivision { scheme: Scheme::Loop, depth: 8, weights: None, memory_limit: 1 << 30 };
        let made = ico.subdivided(&job, false).unwrap();
        let mut streamed = crate::geometry::Shape::default();
        let written = ico.subdivide_into(&job, false, "ico", &mut streamed).unwrap();
        assert_eq!((written.vertices, written.faces), (made.positions.len(), made.face_count()));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&streamed.positions), bits(made.positions.as_flattened()));
        let faces: Vec<[usize; 3]> = made.faces().map(|f| [f[0], f[1], f[2]]).collect();
        assert_eq!(streamed.triangles, faces);
    }

    /// Two Loop steps written at once are two steps in memory, vertex for
    /// vertex and bit for bit: closed and open meshes, valences 3 to 6,
    /// Loop's and other weights.
    #[test]
    fn two_loop_steps_at_once_are_two_steps() {
        for mesh in triangle_meshes() {
            for weights in [None, Some(LoopWeights { w: 0.3, sigma: 0.9 })] {
                let once = mesh.subdivide_with(Scheme::Loop, 1, weights.map(Into::into), 1 << 30).unwrap();
                let t = Topology::trusted(&once);
                let mut out = crate::mesh::emit::Emit::memory(0, 0);
                once.loop_twice_into(&t, weights, &mut out).unwrap();
                let ours = out.finish();
                let theirs = mesh.subdivide_with(Scheme::Loop, 3, weights.map(Into::into), 1 << 30).unwrap();
                assert_same_mesh(&ours, &theirs, &format!("{weights:?}"));
            }
        }
    }
}
