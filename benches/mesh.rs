//! Polygon-mesh subdivision throughput: the cube at depth 8 (393k faces),
//! Doo-Sabin and Catmull-Clark, the net and the limit surface written as
//! OBJ files through the render API (what `bcifs surface` does), and the
//! in-memory net alone; Loop on the
//! icosahedron at depths 7 and 8 written as OBJ files; Loop's and √3's
//! limits streamed from named nets (OFF); faces of 3,000 and
//! 30,000 corners (linear in a face's size). The peers
//! (CGAL, OpenSubdiv) are measured side by side, end to end, by
//! `benches/peers/compare.sh`.

use std::hint::black_box;

use bcifs::mesh::{PolyMesh, Scheme};
use bcifs::render::{MeshJob, Options, render_mesh};

/// A scratch OBJ file for this run.
fn scratch(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("bcifs-bench-{}-{name}.obj", std::process::id()))
}
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn subdivision(c: &mut Criterion) {
    let cube = PolyMesh::cube();
    let mut g = c.benchmark_group("cube_depth8");
    g.sample_size(10);
    for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
        let faces = cube.subdivide(scheme, 8).expect("fits").face_count();
        g.throughput(Throughput::Elements(faces as u64));
        g.bench_function(BenchmarkId::new("net_in_memory", scheme.name()), |b| {
            b.iter(|| black_box(cube.subdivide(scheme, 8).expect("fits")))
        });
        for (what, net) in [("net_obj", true), ("limit_obj", false)] {
            let job = MeshJob { net, ..MeshJob::new(scheme, 8) };
            let path = scratch(what);
            g.bench_function(BenchmarkId::new(what, scheme.name()), |b| {
                b.iter(|| black_box(render_mesh(&cube, &job, &Options::default(), &path).expect("writes")))
            });
            let _ = std::fs::remove_file(&path);
        }
    }
    g.finish();
}

/// Loop on the icosahedron at depths 7 and 8 (328k and 1.3M triangles) as
/// OBJ files through the render API (the rows of `compare.sh` against
/// CGAL), against the in-memory net of depth 8 alone.
fn loop_obj(c: &mut Criterion) {
    let ico = PolyMesh::icosahedron();
    let mut g = c.benchmark_group("icosahedron_loop");
    g.sample_size(10);
    g.throughput(Throughput::Elements(20 * 4u64.pow(8)));
    g.bench_function("net_in_memory_depth8", |b| b.iter(|| black_box(ico.subdivide(Scheme::Loop, 8).expect("fits"))));
    for depth in [7, 8] {
        g.throughput(Throughput::Elements(20 * 4u64.pow(depth as u32)));
        let job = MeshJob { net: true, ..MeshJob::new(Scheme::Loop, depth) };
        let path = scratch("loop");
        g.bench_function(BenchmarkId::new("net_obj_depth", depth), |b| {
            b.iter(|| black_box(render_mesh(&ico, &job, &Options::default(), &path).expect("writes")))
        });
        let _ = std::fs::remove_file(&path);
    }
    g.finish();
}

/// The limits streamed from the net two steps back, the nets between named
/// (OFF, no normals: nothing of the output held): Loop on the icosahedron at
/// depth 8 (1.3M triangles) and √3 at depth 11 (3.5M triangles).
fn named_limits(c: &mut Criterion) {
    let ico = PolyMesh::icosahedron();
    let mut g = c.benchmark_group("icosahedron_limit_off");
    g.sample_size(10);
    for (scheme, depth, faces) in [(Scheme::Loop, 8, 20 * 4u64.pow(8)), (Scheme::Sqrt3, 11, 20 * 3u64.pow(11))] {
        g.throughput(Throughput::Elements(faces));
        let job = MeshJob::new(scheme, depth);
        let path = scratch(scheme.name()).with_extension("off");
        g.bench_function(BenchmarkId::new(scheme.name(), depth), |b| {
            b.iter(|| black_box(render_mesh(&ico, &job, &Options::default(), &path).expect("writes")))
        });
        let _ = std::fs::remove_file(&path);
    }
    g.finish();
}

/// Vertex normals made in memory against streamed through side files (a
/// 64 MiB memory limit: the same bytes), Loop's limit on the icosahedron at
/// depth 8 into OBJ (1.3M triangles, 0.65M vertices): the cost of bounded memory.
fn normals_streamed(c: &mut Criterion) {
    let ico = PolyMesh::icosahedron();
    let mut g = c.benchmark_group("icosahedron_loop8_obj_normals");
    g.sample_size(10);
    g.throughput(Throughput::Elements(20 * 4u64.pow(8)));
    let job = MeshJob::new(Scheme::Loop, 8);
    let path = scratch("normals").with_extension("obj");
    let mut streamed = Options::default();
    streamed.budget.memory = 64 << 20;
    for (name, options) in [("in_memory", Options::default()), ("streamed", streamed)] {
        g.bench_function(name, |b| b.iter(|| black_box(render_mesh(&ico, &job, &options, &path).expect("writes"))));
    }
    let _ = std::fs::remove_file(&path);
    g.finish();
}

/// A prism over an `n`-gon: two `n`-gon faces and `n` quads.
fn prism(n: usize) -> PolyMesh {
    let mut positions = Vec::with_capacity(2 * n);
    for z in [0.0, 1.0] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            positions.push([a.cos(), a.sin(), z]);
        }
    }
    let mut faces = vec![(0..n).rev().collect::<Vec<usize>>(), (n..2 * n).collect()];
    faces.extend((0..n).map(|k| vec![k, (k + 1) % n, n + (k + 1) % n, n + k]));
    PolyMesh::new(positions, faces).expect("a closed prism")
}

/// Issue 23, item 7: a face of n corners costs O(n). Prisms over a 3,000-
/// and a 30,000-gon, two steps of each scheme in memory (Loop and √3 on
/// the fan-triangulated prism, whose apex has valence n): per element the
/// times are alike at both sizes (they were 10× apart, quadratic).
fn large_faces(c: &mut Criterion) {
    let mut g = c.benchmark_group("large_face_depth2");
    g.sample_size(10);
    for n in [3_000, 30_000] {
        let (mesh, triangles) = (prism(n), prism(n).triangulated());
        for scheme in Scheme::ALL {
            let input = if scheme.triangles_only() { &triangles } else { &mesh };
            g.throughput(Throughput::Elements(input.corner_count() as u64));
            g.bench_function(BenchmarkId::new(scheme.name(), n), |b| {
                b.iter(|| black_box(input.subdivide(scheme, 2).expect("fits")))
            });
        }
    }
    g.finish();
    // Issue 42, item 10: the limit surfaces too (Catmull-Clark's limit points of the net, Loop's
    // of the triangulated prism): a 100,000-gon's depth 2 did not finish in 90 s.
    let mut g = c.benchmark_group("large_face_limit_depth2");
    g.sample_size(10);
    for n in [3_000, 30_000] {
        let (mesh, triangles) = (prism(n), prism(n).triangulated());
        for (scheme, input) in [(Scheme::CatmullClark, &mesh), (Scheme::Loop, &triangles)] {
            g.throughput(Throughput::Elements(input.corner_count() as u64));
            g.bench_function(BenchmarkId::new(scheme.name(), n), |b| {
                b.iter(|| black_box(input.limit_with(scheme, 2, None, 1 << 32).expect("fits")))
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = subdivision, loop_obj, named_limits, normals_streamed, large_faces
}
criterion_main!(benches);
