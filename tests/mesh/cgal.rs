//! `--net` against CGAL's Subdivision_method_3 (Debian's libcgal-dev, 5.5):
//! the same vertex positions to 1e-12 and the same faces with the same
//! orientation, up to numbering, on closed and open meshes with triangles,
//! quads and pentagons and vertices of valence 2 to 5. The peer
//! (`benches/peers/cgal_subdivide.cpp`) is built once by g++; without g++ or
//! CGAL the tests say "skipped" and why (`.ci/run` installs libcgal-dev).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use bcifs::mesh::{PolyMesh, Scheme};

/// The CGAL peer, built on first use into `target/peers/`.
pub fn cgal_peer() -> Option<&'static Path> {
    static PEER: OnceLock<Option<PathBuf>> = OnceLock::new();
    PEER.get_or_init(|| {
        build_peer("cgal_subdivide", "/usr/include/CGAL/subdivision_method_3.h", "libcgal-dev", &["-lgmp", "-lmpfr"])
    })
    .as_deref()
}

/// A C++ peer of `benches/peers/NAME.cpp`, built by g++ into
/// `target/peers/NAME` when missing or older than its source; `None` (and
/// a printed reason) when `header` of its library (Debian's `package`) or
/// g++ is missing.
pub fn build_peer(name: &str, header: &str, package: &str, libs: &[&str]) -> Option<PathBuf> {
    if !Path::new(header).exists() {
        println!("skipped: {header} is not installed (apt-get install {package})");
        return None;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let source = root.join(format!("benches/peers/{name}.cpp"));
    let dir = root.join("target/peers");
    std::fs::create_dir_all(&dir).unwrap();
    let exe = dir.join(name);
    let fresh = |p: &Path| p.metadata().and_then(|m| m.modified()).ok();
    if fresh(&exe).is_none() || fresh(&exe) < fresh(&source) {
        let tmp = dir.join(format!("{name}.{}.tmp", std::process::id()));
        let out = Command::new("g++").args(["-O2", "-std=c++17"]).arg(&source).arg("-o").arg(&tmp).args(libs).output();
        match out {
            Ok(o) if o.status.success() => std::fs::rename(&tmp, &exe).unwrap(),
            Ok(o) => panic!("the peer {name} does not build: {}", String::from_utf8_lossy(&o.stderr)),
            Err(e) => {
                println!("skipped: g++ cannot run ({e})");
                return None;
            }
        }
    }
    Some(exe)
}

/// A mesh as CGAL wrote it: positions and faces, digons (two-sided faces,
/// which our reader refuses) included.
pub struct Peer {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Faces.
    pub faces: Vec<Vec<usize>>,
}

/// The OFF text CGAL's peer writes, read without the checks of our reader.
fn parse_peer_off(text: &str) -> Peer {
    let mut words = text.split_whitespace();
    assert_eq!(words.next(), Some("OFF"));
    let mut number = || words.next().expect("CGAL's OFF ends early").parse::<f64>().unwrap();
    let (nv, nf) = (number() as usize, number() as usize);
    number();
    let positions = (0..nv).map(|_| [number(), number(), number()]).collect();
    let faces = (0..nf)
        .map(|_| {
            let k = number() as usize;
            (0..k).map(|_| number() as usize).collect()
        })
        .collect();
    Peer { positions, faces }
}

/// CGAL's mesh after `depth` steps of `scheme` on `mesh`.
pub fn cgal(peer: &Path, mesh: &PolyMesh, scheme: Scheme, depth: usize, tag: &str) -> Peer {
    let dir = std::env::temp_dir();
    let (input, output) = (
        dir.join(format!("bcifs-cgal-{}-{tag}-in.off", std::process::id())),
        dir.join(format!("bcifs-cgal-{}-{tag}-out.off", std::process::id())),
    );
    std::fs::write(&input, crate::off_text(mesh, tag)).unwrap();
    let out = Command::new(peer).arg(scheme.name()).arg(depth.to_string()).arg(&input).arg(&output).output().unwrap();
    assert!(out.status.success(), "CGAL failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&output).unwrap();
    std::fs::remove_file(&input).unwrap();
    std::fs::remove_file(&output).unwrap();
    parse_peer_off(&text)
}

/// Asserts the two meshes are equal up to numbering: a bijection of the
/// vertices within `tol`, and the same faces with the same orientation.
pub fn assert_same_mesh(ours: &PolyMesh, theirs: &Peer, tol: f64, what: &str) {
    assert_eq!(ours.face_count(), theirs.faces.len(), "{what}: faces");
    let mut used: Vec<usize> = theirs.faces.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    assert_eq!(ours.used_vertices(), used.len(), "{what}: vertices");
    // Match vertices through a grid of cells of size 1e-6 (points closer than tol share or neighbour a cell).
    let key = |p: [f64; 3]| p.map(|x| (x * 1e6).round() as i64);
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in theirs.positions.iter().enumerate() {
        cells.entry(key(*p)).or_default().push(i);
    }
    let mut map = vec![usize::MAX; ours.positions.len()];
    for (i, p) in ours.positions.iter().enumerate() {
        let k = key(*p);
        let mut best = (f64::INFINITY, usize::MAX);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]).into_iter().flatten() {
                        let q = theirs.positions[j];
                        let d = (0..3).map(|a| (p[a] - q[a]).abs()).fold(0.0, f64::max);
                        if d < best.0 {
                            best = (d, j);
                        }
                    }
                }
            }
        }
        map[i] = best.1;
        if ours.faces().any(|f| f.contains(&i)) {
            assert!(best.0 <= tol, "{what}: our vertex {i} at {p:?} is {} from CGAL's nearest", best.0);
        }
    }
    let canonical = |f: Vec<usize>| {
        let m = (0..f.len()).min_by_key(|&i| f[i]).unwrap();
        let mut g = f[m..].to_vec();
        g.extend_from_slice(&f[..m]);
        g
    };
    let mut a: Vec<Vec<usize>> = ours.faces().map(|f| canonical(f.iter().map(|&v| map[v]).collect())).collect();
    let mut b: Vec<Vec<usize>> = theirs.faces.iter().map(|f| canonical(f.clone())).collect();
    a.sort();
    b.sort();
    assert!(
        a == b,
        "{what}: the faces differ (same count {}, first difference {:?})",
        a.len(),
        a.iter().zip(&b).find(|(x, y)| x != y)
    );
}

#[test]
fn net_is_cgal_subdivision() {
    let Some(peer) = cgal_peer() else { return };
    for (name, mesh) in crate::shapes() {
        for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
            for depth in 1..=3 {
                let ours = mesh.subdivide(scheme, depth).unwrap();
                let theirs = cgal(peer, &mesh, scheme, depth, &format!("{name}-{}-{depth}", scheme.name()));
                // A few roundings per step on coordinates of size ~1.
                assert_same_mesh(&ours, &theirs, 1e-12, &format!("{name}, {}, depth {depth}", scheme.name()));
            }
        }
    }
}

/// The comparison can fail: other quad weights, or the faces reversed, are not CGAL's mesh.
#[test]
fn the_comparison_sees_a_difference() {
    let Some(peer) = cgal_peer() else { return };
    let cube = crate::cube();
    let theirs = cgal(peer, &cube, Scheme::DooSabin, 1, "diff");
    let weights = bcifs::mesh::QuadWeights { alpha: 0.5, beta: 0.25, gamma: 0.125 };
    let other = cube.subdivide_with(Scheme::DooSabin, 1, Some(weights.into()), 1 << 30).unwrap();
    let moved = std::panic::catch_unwind(|| assert_same_mesh(&other, &theirs, 1e-12, "other weights"));
    assert!(moved.is_err(), "other weights matched CGAL");
    let ours = cube.subdivide(Scheme::DooSabin, 1).unwrap();
    let flipped =
        PolyMesh::new(ours.positions.clone(), ours.faces().map(|f| f.iter().rev().copied().collect()).collect())
            .unwrap();
    let reversed = std::panic::catch_unwind(|| assert_same_mesh(&flipped, &theirs, 1e-12, "reversed quads"));
    assert!(reversed.is_err(), "reversed faces matched CGAL");
}

/// Loop and √3 against CGAL on triangle meshes: closed ones with vertices of
/// valence 3 to 6 and more (the icosahedron; the pyramid, the cube and the
/// prism split into fans), and open ones (the box without its top, the
/// sheet), where √3 refines the border on even steps.
#[test]
fn triangle_nets_are_cgal_subdivision() {
    let Some(peer) = cgal_peer() else { return };
    for (name, mesh) in crate::shapes() {
        let mesh = mesh.triangulated();
        for scheme in [Scheme::Loop, Scheme::Sqrt3] {
            for depth in 1..=3 {
                let ours = mesh.subdivide(scheme, depth).unwrap();
                let theirs = cgal(peer, &mesh, scheme, depth, &format!("{name}-{}-{depth}", scheme.name()));
                assert_same_mesh(&ours, &theirs, 1e-12, &format!("{name}, {}, depth {depth}", scheme.name()));
            }
        }
    }
}

/// Suzanne (exported by Blender: n-gons, open, an interior vertex of valence
/// 2) under Doo-Sabin and Catmull-Clark: CGAL's mesh, digons included.
#[test]
fn suzanne_nets_are_cgal_subdivision() {
    let Some(peer) = cgal_peer() else { return };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/suzanne.obj");
    let mesh = bcifs::mesh::read_mesh(&path).unwrap();
    for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
        for depth in 1..=3 {
            let ours = mesh.subdivide(scheme, depth).unwrap();
            let theirs = cgal(peer, &mesh, scheme, depth, &format!("suzanne-{}-{depth}", scheme.name()));
            assert_same_mesh(&ours, &theirs, 1e-12, &format!("suzanne, {}, depth {depth}", scheme.name()));
        }
    }
    let digons = mesh.subdivide(Scheme::DooSabin, 1).unwrap().faces().filter(|f| f.len() == 2).count();
    assert!(digons > 0, "Suzanne has an interior vertex of valence 2");
}

/// CGAL's self-intersection check (exact predicates, `benches/peers/cgal_self_intersect.cpp`),
/// built on first use.
fn cgal_self_intersect() -> Option<&'static Path> {
    static PEER: OnceLock<Option<PathBuf>> = OnceLock::new();
    PEER.get_or_init(|| {
        build_peer(
            "cgal_self_intersect",
            "/usr/include/CGAL/Polygon_mesh_processing/self_intersections.h",
            "libcgal-dev",
            &["-lgmp", "-lmpfr"],
        )
    })
    .as_deref()
}

/// Issue 45: no face of a solid's boundary or of a thickened lace crosses
/// another, by CGAL's exact `self_intersections` (MeshLab's filter flags a
/// few coplanar neighbours of the sponge, which CGAL's exact predicates
/// clear): the sponges at depths 2 and 3, the twisted tricubic sponge, the
/// bent bar, Cantor dust's separate cubes and the carpet's shell. Only the
/// Sierpiński tetrahedron's shells meet, at the points where they touch.
#[test]
fn solids_and_shells_do_not_intersect_themselves_for_cgal() {
    let Some(peer) = cgal_self_intersect() else { return };
    let dir = std::env::temp_dir().join(format!("bcifs-cgal-solids-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pairs = |name: &str, depth: usize, thickness: Option<f64>| -> (usize, bool) {
        let design = bcifs::render::load(name).unwrap();
        let mut options = bcifs::render::Options::default().with_depth(depth);
        options.file.thickness = thickness;
        let path = dir.join(format!("{name}-{depth}.off"));
        bcifs::render::render(&design, &options, &path).unwrap();
        let out = Command::new(peer).arg(&path).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let words: Vec<&str> = text.split_whitespace().collect();
        assert!(out.status.success() && words.len() == 6, "{name}: {text} {}", String::from_utf8_lossy(&out.stderr));
        (words[3].parse().unwrap(), words[5] == "1")
    };
    for (name, depth, thickness) in [
        ("menger", 2, None),
        ("menger", 3, None),
        ("tricubic-sponge", 2, None),
        ("tricubic", 3, None),
        ("cantor_dust", 2, None),
        ("carpet", 2, Some(0.01)),
    ] {
        assert_eq!(pairs(name, depth, thickness), (0, true), "{name} at depth {depth}");
    }
    let (touching, closed) = pairs("sierpinski_tetrahedron", 2, None);
    assert!(touching > 0 && closed, "the tetrahedra touch at points: {touching}");
    std::fs::remove_dir_all(&dir).ok();
}
