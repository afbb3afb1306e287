//! Issue 46 §2: per-face data follows the schemes (`PolyMesh::face_sources`).

use bcifs::mesh::{DEFAULT_MESH_MEMORY, PolyMesh, Scheme, Subdivision};

/// An n × n grid of unit squares in the plane z = 0 (square `i + n j` at `[i, i + 1] × [j, j + 1]`).
fn grid(n: usize) -> PolyMesh {
    let positions = (0..=n).flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64, 0.0])).collect();
    let at = |i: usize, j: usize| i + (n + 1) * j;
    let faces = (0..n).flat_map(|j| (0..n).map(move |i| vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]));
    PolyMesh::new(positions, faces.collect()).unwrap()
}

/// The distance from `p` to the input face `f` (a square, or a triangle of a split square) in the plane.
fn distance(input: &PolyMesh, f: usize, p: [f64; 3]) -> f64 {
    let face = &input.corners()[input.offsets()[f]..input.offsets()[f + 1]];
    let corner = |k: usize| input.positions[face[k % face.len()]];
    // Outside the convex face by at most the largest distance past an edge (counter-clockwise).
    (0..face.len())
        .map(|k| {
            let (a, b) = (corner(k), corner(k + 1));
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            ((p[0] - a[0]) * ey - (p[1] - a[1]) * ex) / ex.hypot(ey)
        })
        .fold(0.0, f64::max)
}

/// Each face of a flat grid's subdivision lies in the input face it says it
/// comes from: Catmull-Clark's and Loop's faces inside it, Doo-Sabin's faces
/// of faces inside it and those of edges and vertices on its border (their
/// centroids are on the edge or at the vertex: the grid is regular), for the
/// nets and the limits at depths 1 to 3; √3's triangles across an edge
/// within 0.8 of a square of it (a third at each step, shrinking by √3). One source per face, digons included.
#[test]
fn every_face_lies_in_the_face_it_comes_from() {
    let quads = grid(4);
    let triangles = quads.triangulated();
    for scheme in [Scheme::CatmullClark, Scheme::DooSabin, Scheme::Loop, Scheme::Sqrt3] {
        let input = if matches!(scheme, Scheme::Loop | Scheme::Sqrt3) { &triangles } else { &quads };
        for depth in 1..=3 {
            for limit in [false, true] {
                let job = Subdivision { scheme, depth, weights: None, memory_limit: DEFAULT_MESH_MEMORY };
                let out = input.subdivided(&job, limit).unwrap();
                let sources = input.face_sources(&job, limit);
                assert_eq!(sources.len(), out.face_count(), "{scheme:?} depth {depth} limit {limit}");
                // √3's triangle across an edge reaches a third of a face past it, a third of the
                // (√3 times smaller) face past that at the next step...: at most (1/3)·√3/(√3 − 1) < 0.8.
                let bound = if scheme == Scheme::Sqrt3 { 0.8 } else { 1e-9 };
                for (k, w) in out.offsets().windows(2).enumerate() {
                    let face = &out.corners()[w[0]..w[1]];
                    let mut c = [0.0; 3];
                    face.iter().for_each(|&v| (0..3).for_each(|i| c[i] += out.positions[v][i] / face.len() as f64));
                    let d = distance(input, sources[k] as usize, c);
                    assert!(
                        d <= bound,
                        "{scheme:?} depth {depth} limit {limit}: face {k} at {c:?} is {d} from its source {}",
                        sources[k]
                    );
                }
            }
        }
    }
}

/// Catmull-Clark and Loop split their faces: each input face's children are
/// 4^depth faces (after Catmull-Clark's first step, one per corner), in
/// order; Doo-Sabin's and √3's faces of edges and vertices take the lowest
/// face they span, so every input face keeps its own faces and the counts
/// add up to the output's.
#[test]
fn split_faces_keep_their_count_and_order() {
    let cube = PolyMesh::cube();
    let job = |scheme, depth| Subdivision { scheme, depth, weights: None, memory_limit: DEFAULT_MESH_MEMORY };
    let cc = cube.face_sources(&job(Scheme::CatmullClark, 3), false);
    assert_eq!(cc, (0..6u32).flat_map(|f| std::iter::repeat_n(f, 64)).collect::<Vec<_>>());
    let ico = PolyMesh::icosahedron();
    let lp = ico.face_sources(&job(Scheme::Loop, 2), true);
    assert_eq!(lp, (0..20u32).flat_map(|f| std::iter::repeat_n(f, 16)).collect::<Vec<_>>());
    // Doo-Sabin on the cube: 6 faces, 12 edges, 8 vertices; an edge's face is
    // the lower of its two, a vertex's the lowest of its three.
    let ds = cube.face_sources(&job(Scheme::DooSabin, 1), false);
    assert_eq!(ds.len(), 26);
    assert_eq!(&ds[..6], &[0, 1, 2, 3, 4, 5]);
    let lowest = |v: usize| (0..6u32).find(|&f| cube.face(f as usize).contains(&v)).unwrap();
    let mut vertices: Vec<u32> = (0..8).map(lowest).collect();
    let mut got = ds[18..].to_vec();
    vertices.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, vertices, "each vertex's face: the lowest of its three");
}
