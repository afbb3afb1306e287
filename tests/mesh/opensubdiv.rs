//! Texture coordinates through subdivision (issue 25) against OpenSubdiv
//! (Debian's libosd-dev, 3.5): Suzanne's UVs, face-varying with seams,
//! through Catmull-Clark and Loop. The peer (`benches/peers/osd_uv.cpp`)
//! refines with `FVAR_LINEAR_BOUNDARIES` (Blender's "Keep Boundaries") and
//! B-spline mesh borders; it is built once by g++, and the tests say
//! "skipped" and why without it (`.ci/run` installs libosd-dev).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use bcifs::mesh::{PolyMesh, Scheme, read_mesh, read_obj};

use crate::cgal::build_peer;

fn osd_peer() -> Option<&'static Path> {
    static PEER: OnceLock<Option<PathBuf>> = OnceLock::new();
    PEER.get_or_init(|| build_peer("osd_uv", "/usr/include/opensubdiv/version.h", "libosd-dev", &["-losdCPU"]))
        .as_deref()
}

/// Every face corner as `(x, y, z, u, v)`.
fn corners(mesh: &PolyMesh, texture: &PolyMesh) -> Vec<[f64; 5]> {
    mesh.faces()
        .zip(texture.faces())
        .flat_map(|(f, t)| {
            f.iter().zip(t).map(|(&v, &k)| {
                let (p, uv) = (mesh.positions[v], texture.positions[k]);
                [p[0], p[1], p[2], uv[0], uv[1]]
            })
        })
        .collect()
}

/// The OBJ text of a mesh with its texture coordinates (`f v/vt`).
fn textured_obj(mesh: &PolyMesh) -> String {
    let uv = mesh.texture().unwrap();
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    for t in &uv.positions {
        text += &format!("vt {:?} {:?}\n", t[0], t[1]);
    }
    for (f, t) in mesh.faces().zip(uv.faces()) {
        let c: Vec<String> = f.iter().zip(t).map(|(v, k)| format!("{}/{}", v + 1, k + 1)).collect();
        text += &format!("f {}\n", c.join(" "));
    }
    text
}

/// The largest distance from a corner of `a` to the nearest corner of `b`
/// in `(position, uv)` space, searched in cells of side `1e-6`.
fn worst_corner(a: &[[f64; 5]], b: &[[f64; 5]]) -> f64 {
    let cell = |c: &[f64; 5]| c.map(|x| (x * 1e6).round() as i64);
    let mut grid: HashMap<[i64; 5], Vec<usize>> = HashMap::new();
    for (i, c) in b.iter().enumerate() {
        grid.entry(cell(c)).or_default().push(i);
    }
    a.iter()
        .map(|c| {
            let k = cell(c);
            let mut best = f64::INFINITY;
            for step in 0..3i64.pow(5) {
                let mut key = k;
                let mut s = step;
                for x in &mut key {
                    *x += s % 3 - 1;
                    s /= 3;
                }
                for &i in grid.get(&key).into_iter().flatten() {
                    let d = (0..5).map(|j| (b[i][j] - c[j]).powi(2)).sum::<f64>().sqrt();
                    best = best.min(d);
                }
            }
            best
        })
        .fold(0.0, f64::max)
}

/// Suzanne (quads and triangles, 556 texture vertices for 507 vertices:
/// seams) after two steps of Catmull-Clark, and triangulated after two of
/// Loop: the same nets as OpenSubdiv's with the same texture coordinate at
/// every face corner, to 1e-12 (both in double precision); as many texture
/// vertices (seams stay seams: a seam vertex keeps one per side).
#[test]
fn suzannes_uvs_subdivide_as_opensubdiv_subdivides_them() {
    let Some(peer) = osd_peer() else { return };
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let suzanne = read_mesh(&data.join("suzanne.obj")).unwrap();
    assert_eq!(suzanne.name.as_deref(), Some("Suzanne"), "the file's `o` names the mesh");
    assert_eq!(suzanne.texture().map(|t| t.positions.len()), Some(556));
    for (scheme, mesh, name) in
        [(Scheme::CatmullClark, suzanne.clone(), "catmark"), (Scheme::Loop, suzanne.triangulated(), "loop")]
    {
        let depth = 2;
        let net = mesh.subdivide(scheme, depth).unwrap();
        let uv = mesh.texture_after(scheme, depth, None).expect("Catmull-Clark and Loop carry UVs");
        let dir = std::env::temp_dir();
        let input = dir.join(format!("bcifs-osd-{}-{name}-in.obj", std::process::id()));
        let output = dir.join(format!("bcifs-osd-{}-{name}-out.obj", std::process::id()));
        std::fs::write(&input, textured_obj(&mesh)).unwrap();
        let run = Command::new(peer).arg(name).arg(depth.to_string()).arg(&input).arg(&output).output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let theirs = read_obj(&std::fs::read_to_string(&output).unwrap(), "osd").unwrap();
        let their_uv = theirs.texture().unwrap();
        assert_eq!(
            (theirs.positions.len(), theirs.face_count(), their_uv.positions.len()),
            (net.positions.len(), net.face_count(), uv.positions.len()),
            "{name}: vertices, faces, texture vertices"
        );
        let (ours, osd) = (corners(&net, &uv), corners(&theirs, their_uv));
        let worst = worst_corner(&ours, &osd).max(worst_corner(&osd, &ours));
        assert!(worst < 1e-12, "{name}: {worst:e}");
        std::fs::remove_file(input).unwrap();
        std::fs::remove_file(output).unwrap();
    }
}

/// `--uv none` and the schemes that do not split faces: no texture
/// coordinates written; Catmull-Clark's limit keeps them (its faces are the
/// net's) in OBJ, and in glTF, where seams split vertices.
#[test]
fn texture_coordinates_are_written_where_asked_and_possible() {
    use bcifs::render::{MeshJob, Options, render_mesh};
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let suzanne = read_mesh(&data.join("suzanne.obj")).unwrap();
    let out = std::env::temp_dir().join(format!("bcifs-uv-{}.obj", std::process::id()));
    let vt = |job: &MeshJob| {
        let report = render_mesh(&suzanne, job, &Options::default(), &out).unwrap();
        let text = std::fs::read_to_string(&out).unwrap();
        (text.lines().filter(|l| l.starts_with("vt ")).count(), report)
    };
    let (limit, _) = vt(&MeshJob::new(Scheme::CatmullClark, 2));
    assert_eq!(limit, suzanne.texture_after(Scheme::CatmullClark, 2, None).unwrap().positions.len());
    assert_eq!(vt(&MeshJob { uv: false, ..MeshJob::new(Scheme::CatmullClark, 2) }).0, 0, "--uv none");
    let (doo_sabin, report) = vt(&MeshJob::new(Scheme::DooSabin, 2));
    assert_eq!(doo_sabin, 0);
    assert!(report.notes.iter().any(|n| n.contains("texture coordinates")), "{report:?}");
    std::fs::remove_file(&out).unwrap();
}

/// The input's `o` and `g` names carry through: the file's first name
/// names the output's object, and its groups of faces follow the faces
/// through Catmull-Clark (a quad per corner) and Loop (four triangles per
/// triangle), as `g` records in OBJ (read back: the same groups, each with
/// its faces' children) and as one named primitive each in glTF; Doo-Sabin
/// makes faces of edges and vertices too, and writes one object.
#[test]
fn object_and_group_names_carry_through() {
    use bcifs::render::{MeshJob, Options, render_mesh};
    let cube = "o box\ng top\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
                f 5 6 7 8\ng sides\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\ng bottom\nf 1 4 3 2\n";
    let mesh = read_obj(cube, "box.obj").unwrap();
    assert_eq!(mesh.name.as_deref(), Some("box"));
    let groups = |m: &PolyMesh| m.groups.iter().map(|(n, at)| format!("{n}@{at}")).collect::<Vec<_>>();
    assert_eq!(groups(&mesh), ["top@0", "sides@1", "bottom@5"], "`o box` then `g top` at the same face: top");
    let out = std::env::temp_dir().join(format!("bcifs-groups-{}.obj", std::process::id()));
    for (scheme, mesh, per_face) in [
        (Scheme::CatmullClark, mesh.clone(), 16),
        (Scheme::Loop, mesh.triangulated(), 32), // two triangles per square, 16 each after two steps
    ] {
        for net in [true, false] {
            let job = MeshJob { net, ..MeshJob::new(scheme, 2) };
            render_mesh(&mesh, &job, &Options::default(), &out).unwrap();
            let text = std::fs::read_to_string(&out).unwrap();
            assert!(text.contains("o box\n"), "{scheme:?}: the object is named as the file names it");
            let back = read_obj(&text, "back.obj").unwrap();
            let expected: Vec<String> = [("top", 0), ("sides", per_face), ("bottom", 5 * per_face)]
                .iter()
                .map(|(n, at)| format!("{n}@{at}"))
                .collect();
            assert_eq!(groups(&back), expected, "{scheme:?} net {net}");
        }
    }
    let doo_sabin = render_mesh(&mesh, &MeshJob::new(Scheme::DooSabin, 2), &Options::default(), &out).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(!text.contains("\ng "), "Doo-Sabin: no groups ({} faces in one object)", doo_sabin.faces);
    std::fs::remove_file(&out).unwrap();
}
