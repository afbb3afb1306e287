//! The files bcifs writes, loaded by the programs users open them with
//! (MeshLab through pymeshlab, trimesh, Blender). A client that is not
//! installed is skipped with a printed reason; `.ci/run` installs them.

use std::process::Command;

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::export::ObjWriter;

use crate::load;

/// Runs a Python script with `module` importable; `None` (and a printed
/// reason) when Python or the module is missing.
pub(crate) fn python(module: &str, script: &str) -> Option<String> {
    let probe = Command::new("python3").args(["-c", &format!("import {module}")]).output();
    match probe {
        Ok(o) if o.status.success() => {}
        _ => {
            println!("skipped: python3 with `{module}` is not installed (pip install {module})");
            return None;
        }
    }
    let out = Command::new("python3").args(["-c", script]).output().expect("python3 runs");
    assert!(out.status.success(), "{module} failed: {}", String::from_utf8_lossy(&out.stderr));
    Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Where `.ci/run` installs the npm clients (`npm install --prefix`), or `$BCIFS_NPM_CLIENTS`.
fn npm_clients() -> std::path::PathBuf {
    std::env::var_os("BCIFS_NPM_CLIENTS")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/clients"))
}

/// The Khronos glTF validator's verdict on each file: `(errors, warnings,
/// messages)`; `None` (and a printed reason) when Node.js or the validator
/// is missing.
pub(crate) fn gltf_validator(files: &[&std::path::Path]) -> Option<Vec<(u64, u64, Vec<String>)>> {
    let modules = npm_clients().join("node_modules");
    if !modules.join("gltf-validator").is_dir() || Command::new("node").arg("--version").output().is_err() {
        println!(
            "skipped: the glTF validator is not installed (npm install --prefix {} gltf-validator)",
            npm_clients().display()
        );
        return None;
    }
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/clients/validate_gltf.js");
    let out = Command::new("node").env("NODE_PATH", &modules).arg(script).args(files).output().expect("node runs");
    assert!(out.status.success(), "the glTF validator failed: {}", String::from_utf8_lossy(&out.stderr));
    let lines = String::from_utf8_lossy(&out.stdout).lines().map(str::to_string).collect::<Vec<_>>();
    Some(
        lines
            .iter()
            .map(|l| {
                let v: serde_json::Value = serde_json::from_str(l).expect("the validator's JSON");
                let messages = v["messages"].as_array().unwrap().iter().map(|m| m.as_str().unwrap().to_string());
                (v["errors"].as_u64().unwrap(), v["warnings"].as_u64().unwrap(), messages.collect())
            })
            .collect(),
    )
}

fn streamed(name: &str, depth: usize, file: &str) -> std::path::PathBuf {
    let (a, model, _) = load(name, &[]);
    let path = std::env::temp_dir().join(format!("bcifs-client-{}-{file}", std::process::id()));
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(depth)).unwrap();
    let mut w = ObjWriter::create(&path).unwrap();
    ev.stream(&mut w).unwrap();
    w.finish().unwrap();
    path
}

/// Issue 15, item 1: a closed corner-cutting curve of 6 × 2^6 = 384 edges
/// arrives whole in MeshLab (long `l` records lost all but their first
/// segment). trimesh 5's OBJ reader ignores `l` records: it gets every
/// vertex, as a point cloud (the README's client table says so).
#[test]
fn curves_load_whole_in_meshlab_and_trimesh() {
    let path = streamed("corner_cutting", 6, "curve.obj");
    let p = path.display();
    if let Some(edges) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\nprint(ms.current_mesh().edge_number())"
        ),
    ) {
        assert_eq!(edges, "384", "pymeshlab edges");
    }
    if let Some(loaded) =
        python("trimesh", &format!("import trimesh\np = trimesh.load('{p}')\nprint(type(p).__name__, len(p.vertices))"))
    {
        assert_eq!(loaded, "PointCloud 384", "trimesh: every vertex");
    }
    std::fs::remove_file(&path).unwrap();
}

/// Issue 15, items 2 and 3: the closed tori (Doo-Sabin, ternary 5-point)
/// load as one watertight body with χ = 0 and positive volume (facing
/// outwards) in trimesh's default `load` and in MeshLab.
#[test]
fn closed_surfaces_load_watertight_and_outward() {
    let (a, model, _) = load("doo_sabin_torus", &[]);
    let torus = bcifs::schemes::ifs_preset("ternary5-torus", None, None).unwrap();
    let t5 = bcifs::instantiate(&torus, &[]).unwrap().automaton;
    for (name, automaton, model, depth) in
        [("doo_sabin_torus", a, model, 3), ("ternary5_torus", t5, torus.model().unwrap().clone(), 2)]
    {
        let path = std::env::temp_dir().join(format!("bcifs-client-{}-{name}.obj", std::process::id()));
        let ev = Evaluator::new(&automaton, &model, EvalSettings::default().with_depth(depth)).unwrap();
        let shape = ev.evaluate().unwrap();
        assert!(signed_volume(&shape) > 0.0, "{name}: outward in our own mesh");
        let mut w = ObjWriter::create(&path).unwrap();
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        watertight_in_clients(&path, shape.vertex_count(), 0, name);
        std::fs::remove_file(&path).unwrap();
    }
}

/// A closed OBJ of `vertices` vertices loads as one watertight body with
/// Euler characteristic `euler` and positive volume in trimesh, two-manifold
/// without border and of positive volume in MeshLab (each client skipped
/// when missing).
fn watertight_in_clients(path: &std::path::Path, vertices: usize, euler: i64, name: &str) {
    let p = path.display();
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\nm = trimesh.load('{p}')\nm.merge_vertices(merge_tex=True, merge_norm=True)\n\
             print(m.is_watertight, m.euler_number, m.volume > 0, len(m.vertices))"
        ),
    ) {
        assert_eq!(out, format!("True {euler} True {vertices}"), "{name} in trimesh");
    }
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\n\
             t = ms.get_topological_measures()\ng = ms.get_geometric_measures()\n\
             print(t['boundary_edges'], t['is_mesh_two_manifold'], g['mesh_volume'] > 0)"
        ),
    ) {
        assert_eq!(out, "0 True True", "{name} in MeshLab");
    }
}

/// The volume enclosed by a closed quad mesh (positive when it faces outwards).
fn signed_volume(shape: &bcifs::geometry::Shape) -> f64 {
    let p = |i: u32| shape.point(i as usize);
    shape
        .quads
        .iter()
        .map(|q| {
            let [a, b, c, d] = q.map(p);
            (det(a, b, c) + det(a, c, d)) / 6.0
        })
        .sum()
}

fn det(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Runs a Python script in headless Blender (`blender -b --factory-startup`)
/// and returns the lines it printed after `BCIFS `; `None` (and a printed
/// reason) when Blender is not installed.
pub(crate) fn blender(script: &str) -> Option<Vec<String>> {
    if Command::new("blender").arg("--version").output().is_err() {
        println!("skipped: blender is not installed (apt-get install blender)");
        return None;
    }
    let out = Command::new("blender")
        .args(["-b", "--factory-startup", "--python-exit-code", "1", "--python-expr", script])
        .output()
        .expect("blender runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "blender failed: {stdout}{}", String::from_utf8_lossy(&out.stderr));
    Some(stdout.lines().filter_map(|l| l.strip_prefix("BCIFS ")).map(str::to_string).collect())
}

/// Blender's script: imports `path` with the default OBJ importer of its
/// version (`wm.obj_import` in 3.4) and prints, in world coordinates,
/// `vertices edges faces signed_volume manifold dx dy dz`.
fn blender_import(path: &std::path::Path) -> String {
    format!(
        "import bpy, bmesh\n\
         bpy.ops.object.select_all(action='SELECT')\nbpy.ops.object.delete()\n\
         bpy.ops.wm.obj_import(filepath=r'{}')\n\
         bm = bmesh.new()\n\
         for o in bpy.context.scene.objects:\n    m = o.data.copy()\n    m.transform(o.matrix_world)\n    bm.from_mesh(m)\n\
         bm.verts.ensure_lookup_table()\n\
         d = [max(v.co[k] for v in bm.verts) - min(v.co[k] for v in bm.verts) for k in range(3)]\n\
         print('BCIFS', len(bm.verts), len(bm.edges), len(bm.faces), bm.calc_volume(signed=True), \
               all(e.is_manifold for e in bm.edges), *d)\n",
        path.display()
    )
}

/// Issue 15 in Blender 3.4 (Debian's), headless: a curve arrives with every
/// segment (384 edges, not 6), the closed Doo-Sabin torus as one closed
/// 2-manifold facing outwards, standing up (the model's z axis, the torus
/// axis, is Blender's z after its importer's Y-up conversion), and a point
/// cloud with every point.
#[test]
fn curves_and_surfaces_load_whole_and_upright_in_blender() {
    let curve = streamed("corner_cutting", 6, "blender-curve.obj");
    let Some(lines) = blender(&blender_import(&curve)) else { return };
    let f: Vec<&str> = lines[0].split(' ').collect();
    assert_eq!((f[0], f[1], f[2]), ("384", "384", "0"), "Blender: vertices, edges, faces of the curve");
    std::fs::remove_file(&curve).unwrap();

    let torus = streamed("doo_sabin_torus", 3, "blender-torus.obj");
    let (a, model, _) = load("doo_sabin_torus", &[]);
    let shape = Evaluator::new(&a, &model, EvalSettings::default().with_depth(3)).unwrap().evaluate().unwrap();
    let (lo, hi) = shape.bounds().unwrap();
    let lines = blender(&blender_import(&torus)).unwrap();
    let f: Vec<&str> = lines[0].split(' ').collect();
    let n = shape.vertex_count().to_string();
    assert_eq!((f[0], f[2]), (n.as_str(), shape.quads.len().to_string().as_str()), "Blender: vertices and faces");
    assert_eq!(f[4], "True", "Blender: every edge between two faces");
    let volume: f64 = f[3].parse().unwrap();
    assert!(volume > 0.0, "Blender: signed volume {volume}");
    // Blender holds single-precision coordinates: extents agree to 1e-5 relative.
    let dz: f64 = f[7].parse().unwrap();
    let model_z = hi[2] - lo[2];
    assert!((dz - model_z).abs() < 1e-5 * model_z.max(1.0), "Blender's height {dz} is the model's z extent {model_z}");
    std::fs::remove_file(&torus).unwrap();

    // A point cloud (the fern at depth 4: 4^4 leaves, 4 start points each): every point.
    let cloud = streamed("fern", 4, "blender-cloud.obj");
    let lines = blender(&blender_import(&cloud)).unwrap();
    assert_eq!(lines[0].split(' ').next(), Some("1024"), "Blender: every point of the cloud");
    std::fs::remove_file(&cloud).unwrap();
}

/// `bcifs surface` output (the library's streamed writer) in the clients: the
/// Catmull-Clark limit of the Blender-exported 12 × 6 torus loads watertight
/// and outward in trimesh and MeshLab, with every face in Blender; Suzanne's
/// Doo-Sabin net (n-gon faces, open) keeps every face in MeshLab.
#[test]
fn subdivided_meshes_load_in_the_clients() {
    use bcifs::mesh::{Scheme, read_mesh};
    use bcifs::render::{MeshJob, Options, render_mesh};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let write = |input: &str, scheme, depth, limit: bool, file: &str| {
        let mesh = read_mesh(&data.join(input)).unwrap();
        let path = std::env::temp_dir().join(format!("bcifs-client-{}-{file}", std::process::id()));
        let job = MeshJob { net: !limit, ..MeshJob::new(scheme, depth) };
        let written = render_mesh(&mesh, &job, &Options::default(), &path).unwrap();
        (path, written)
    };
    let (torus, w) = write("torus12.obj", Scheme::CatmullClark, 2, true, "torus-limit.obj");
    let p = torus.display();
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\nm = trimesh.load('{p}')\nm.merge_vertices(merge_tex=True, merge_norm=True)\n\
             print(m.is_watertight, m.euler_number, m.volume > 0, len(m.vertices))"
        ),
    ) {
        assert_eq!(out, format!("True 0 True {}", w.vertices), "trimesh");
    }
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\n\
             t = ms.get_topological_measures()\nprint(t['boundary_edges'], t['is_mesh_two_manifold'], ms.current_mesh().vertex_number())"
        ),
    ) {
        assert_eq!(out, format!("0 True {}", w.vertices), "MeshLab");
    }
    if let Some(lines) = blender(&blender_import(&torus)) {
        let f: Vec<&str> = lines[0].split(' ').collect();
        assert_eq!(
            (f[0], f[2], f[4]),
            (w.vertices.to_string().as_str(), w.faces.to_string().as_str(), "True"),
            "Blender"
        );
        assert!(f[3].parse::<f64>().unwrap() > 0.0, "Blender: outward");
    }
    std::fs::remove_file(&torus).unwrap();
    let (net, w) = write("suzanne.obj", Scheme::DooSabin, 1, false, "suzanne-net.obj");
    let p = net.display();
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\nprint(ms.current_mesh().vertex_number())"
        ),
    ) {
        assert_eq!(out, w.vertices.to_string(), "MeshLab vertices of the n-gon net");
    }
    std::fs::remove_file(&net).unwrap();
}

/// Issue 11's writers in the clients: the torus written in two passes,
/// formatted on two threads to 6 significant digits, loads as one
/// watertight outward body in trimesh and MeshLab (the rounding keeps
/// every welded vertex one vertex); the chaos game's streamed point cloud
/// arrives whole.
#[test]
fn rounded_parallel_and_streamed_obj_files_load_in_the_clients() {
    let (a, model, _) = load("doo_sabin_torus", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(4)).unwrap();
    let vertices = ev.evaluate().unwrap().vertex_count();
    let path = std::env::temp_dir().join(format!("bcifs-client-{}-rounded.obj", std::process::id()));
    let mut w = ObjWriter::create(&path).unwrap().with_threads(2).unwrap().with_precision(Some(6));
    bcifs::export::write_two_passes(&mut w, |sink| ev.stream(sink), None).unwrap();
    w.finish().unwrap();
    watertight_in_clients(&path, vertices, 0, "rounded torus");
    std::fs::remove_file(&path).unwrap();
    let design = bcifs::builtin_design("gasket").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let settings = bcifs::eval::RandomSettings::default().with_points(1000).with_threads(2);
    let game = bcifs::eval::ChaosGame::new(&inst.automaton, design.model().unwrap(), &settings).unwrap();
    let path = std::env::temp_dir().join(format!("bcifs-client-{}-cloud.obj", std::process::id()));
    let mut w = ObjWriter::create(&path).unwrap();
    bcifs::geometry::Sink::object(&mut w, "gasket").unwrap();
    game.stream(200_000, |xs| bcifs::geometry::Sink::vertices(&mut w, 2, xs, None)).unwrap();
    w.finish().unwrap();
    let p = path.display();
    if let Some(loaded) =
        python("trimesh", &format!("import trimesh\np = trimesh.load('{p}')\nprint(type(p).__name__, len(p.vertices))"))
    {
        assert_eq!(loaded, "PointCloud 200000", "trimesh: every point");
    }
    std::fs::remove_file(&path).unwrap();
}

/// A user's mesh as a generated automaton (`surface --print`), evaluated
/// (patches of several states welded as polygons) and written as OBJ: the
/// Blender torus under Doo-Sabin loads as one watertight outward body of
/// χ = 0, the icosahedron under Loop (triangles, valence 5) as a watertight
/// outward sphere (χ = 2), in trimesh and MeshLab.
#[test]
fn generated_mesh_automata_load_in_the_clients() {
    use bcifs::mesh::{PolyMesh, Scheme, read_mesh};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let torus = read_mesh(&data.join("torus12.obj")).unwrap();
    for (name, mesh, scheme, euler) in [
        ("torus-automaton", torus, Scheme::DooSabin, 0),
        ("icosahedron-automaton", PolyMesh::icosahedron(), Scheme::Loop, 2),
    ] {
        let design = bcifs::schemes::mesh_automaton(&mesh, scheme, None).unwrap();
        let automaton = bcifs::instantiate(&design, &[]).unwrap().automaton;
        let ev = Evaluator::new(&automaton, design.model().unwrap(), EvalSettings::default().with_depth(3)).unwrap();
        let vertices = ev.evaluate().unwrap().vertex_count();
        let path = std::env::temp_dir().join(format!("bcifs-client-{}-{name}.obj", std::process::id()));
        let mut w = ObjWriter::create(&path).unwrap();
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        watertight_in_clients(&path, vertices, euler, name);
        std::fs::remove_file(&path).unwrap();
    }
}

/// Issue 23, item 1: Doo-Sabin beside an interior vertex of valence 2 (the
/// cube with a vertex inserted in an edge; Suzanne has one) writes no face
/// with an index past the vertices, a repeated vertex or fewer than three
/// corners (the digon is a doubled edge, left out). The nets and limits of
/// depth 2 and 3 load in trimesh (the split cube watertight and outward),
/// MeshLab (two-manifold, every vertex) and Blender 3.4, which crashed on
/// the depth-3 net.
#[test]
fn doo_sabin_beside_a_valence_2_vertex_loads_in_the_clients() {
    use bcifs::mesh::{Scheme, read_mesh};
    use bcifs::render::{MeshJob, Options, render_mesh};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for input in ["split_cube.obj", "suzanne.obj"] {
        let mesh = read_mesh(&data.join(input)).unwrap();
        let closed = mesh.is_closed();
        for (depth, limit) in [(2, false), (2, true), (3, false), (3, true)] {
            let path =
                std::env::temp_dir().join(format!("bcifs-client-{}-ds-{depth}-{limit}-{input}", std::process::id()));
            let job = MeshJob { net: !limit, ..MeshJob::new(Scheme::DooSabin, depth) };
            let written = render_mesh(&mesh, &job, &Options::default(), &path).unwrap();
            let what = format!("{input} depth {depth} limit {limit}");
            // Our own reader checks every face (indices in range, three distinct corners, manifold).
            let back = read_mesh(&path).unwrap_or_else(|e| panic!("{what}: bcifs refuses its own file: {e}"));
            assert_eq!((back.positions.len(), back.face_count()), (written.vertices, written.faces), "{what}");
            assert_eq!(back.is_closed(), closed, "{what}: closed as the input");
            let p = path.display();
            if let Some(out) = python(
                "trimesh",
                &format!(
                    "import trimesh\nm = trimesh.load('{p}', process=False)\n\
                     print(len(m.vertices), int(m.faces.max()) < len(m.vertices), m.is_watertight, m.volume > 0)"
                ),
            ) {
                let expected = if closed { "True True" } else { "False" };
                assert!(
                    out.starts_with(&format!("{} True", written.vertices)) && out.contains(expected),
                    "{what} in trimesh: {out}"
                );
            }
            if let Some(out) = python(
                "pymeshlab",
                &format!(
                    "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\n\
                     t = ms.get_topological_measures()\n\
                     print(ms.current_mesh().vertex_number(), t['is_mesh_two_manifold'], t['boundary_edges'] == 0)"
                ),
            ) {
                assert_eq!(
                    out,
                    format!("{} True {}", written.vertices, if closed { "True" } else { "False" }),
                    "{what} in MeshLab"
                );
            }
            if let Some(lines) = blender(&blender_import(&path)) {
                let f: Vec<&str> = lines[0].split(' ').collect();
                assert_eq!(f[0], written.vertices.to_string(), "{what} in Blender: vertices");
                assert_eq!(f[2], written.faces.to_string(), "{what} in Blender: faces");
                if closed {
                    assert_eq!(f[4], "True", "{what} in Blender: every edge between two faces");
                }
            }
            std::fs::remove_file(&path).unwrap();
        }
    }
}

/// Issue 45: what a slicer is given is a valid solid in MeshLab too. The
/// sponge's boundary mesh and the carpet thickened into a shell (PLY): two-
/// manifold, no border, positive volume; trimesh sees them watertight with
/// the Euler characteristic of their genus. The shell has no face crossing
/// another (MeshLab's self-intersection selection is empty); on the sponge
/// MeshLab selects 8 faces at depth 2 (the mesh has no duplicate vertex or
/// face and every edge two faces: an open question of the notes, not asserted).
#[test]
fn solids_and_shells_are_valid_without_self_intersections_in_meshlab() {
    let dir = std::env::temp_dir().join(format!("bcifs-print-clients-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    };
    let sponge = dir.join("sponge.ply");
    let shell = dir.join("shell.ply");
    run(&["render", "menger", "--depth", "2", "-o", sponge.to_str().unwrap()]);
    run(&["render", "carpet", "--depth", "2", "--thickness", "0.01", "-o", shell.to_str().unwrap()]);
    // The sponge: genus 81, χ = −160; the shell of the carpet's 9 holes: χ = −16.
    for (path, euler) in [(&sponge, -160), (&shell, -16)] {
        let p = path.display();
        if let Some(out) = python(
            "trimesh",
            &format!(
                "import trimesh\nm = trimesh.load('{p}', process=False)\nprint(m.is_watertight, m.is_winding_consistent, m.euler_number, m.volume > 0)"
            ),
        ) {
            assert_eq!(out, format!("True True {euler} True"), "{p} in trimesh");
        }
        if let Some(out) = python(
            "pymeshlab",
            &format!(
                "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\n\
                 t = ms.get_topological_measures()\ng = ms.get_geometric_measures()\n\
                 ms.compute_selection_by_self_intersections_per_face()\n\
                 print(t['boundary_edges'], t['is_mesh_two_manifold'], g['mesh_volume'] > 0, ms.current_mesh().selected_face_number())"
            ),
        ) {
            let crossing = if path == &shell { " 0" } else { "" };
            assert!(out.starts_with("0 True True") && out.ends_with(crossing), "{p} in MeshLab: {out}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 45, item 5, in Blender 3.4 (Debian's): the sponge's STL (a triangle
/// soup, merged by position as a slicer merges it) and GLB import as one
/// closed 2-manifold of the sponge's volume (20/27)² with its 896 corners.
/// (Blender 3.4 has no 3MF importer: lib3mf, the Consortium's own library,
/// reads the 3MF in `python/tests`.)
#[test]
fn solids_import_closed_in_blender() {
    let dir = std::env::temp_dir().join(format!("bcifs-blender-solids-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (stl, glb) = (dir.join("sponge.stl"), dir.join("sponge.glb"));
    for path in [&stl, &glb] {
        let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["render", "menger", "--depth", "2", "-o"])
            .arg(path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    // Debian's Blender 3.4 glTF importer calls `numpy.bool` (see tests/eval/gltf.rs).
    let script = format!(
        "import bpy, bmesh, numpy\nnumpy.bool = bool\n\
         for path, kind in [(r'{}', 'stl'), (r'{}', 'glb')]:\n    \
             bpy.ops.object.select_all(action='SELECT')\n    bpy.ops.object.delete()\n    \
             bpy.ops.import_mesh.stl(filepath=path) if kind == 'stl' else bpy.ops.import_scene.gltf(filepath=path)\n    \
             bm = bmesh.new()\n    \
             for o in bpy.context.scene.objects:\n        \
                 if o.type == 'MESH':\n            m = o.data.copy()\n            m.transform(o.matrix_world)\n            bm.from_mesh(m)\n    \
             bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-6)\n    \
             print('BCIFS', kind, len(bm.verts), round(bm.calc_volume(signed=True), 6), all(e.is_manifold for e in bm.edges))\n",
        stl.display(),
        glb.display()
    );
    if let Some(lines) = blender(&script) {
        let volume = (20f64 / 27.0).powi(2);
        for (line, kind) in lines.iter().zip(["stl", "glb"]) {
            assert_eq!(line, &format!("{kind} 896 {volume:.6} True"), "{kind} in Blender");
        }
        assert_eq!(lines.len(), 2);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 46 §13: what a Blender user gets. The arch (`tricubic`, 3 long
/// along x, raised to 3.1 along the model's z) imports upright from STL (Z-up,
/// which Blender's STL importer keeps) and from OBJ (Y-up, which Blender's OBJ
/// importer turns); Blender 3.4's PLY importer keeps the file's axes, so a
/// default (Y-up) PLY lies on its back and `--up z` stands it up.
#[test]
fn files_stand_upright_in_blender_as_documented() {
    let dir = std::env::temp_dir().join(format!("bcifs-blender-up-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: Vec<(std::path::PathBuf, &str)> = vec![
        (dir.join("a.stl"), "auto"),
        (dir.join("a.obj"), "auto"),
        (dir.join("a.ply"), "auto"),
        (dir.join("z.ply"), "z"),
    ];
    for (path, up) in &files {
        let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["render", "tricubic", "--depth", "1", "--up", up, "-o"])
            .arg(path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let list: Vec<String> = files.iter().map(|(p, _)| format!("r'{}'", p.display())).collect();
    let script = format!(
        "import bpy\n\
         for path in [{}]:\n    \
             bpy.ops.object.select_all(action='SELECT')\n    bpy.ops.object.delete()\n    \
             ext = path.rsplit('.', 1)[1]\n    \
             {{'stl': bpy.ops.import_mesh.stl, 'obj': bpy.ops.wm.obj_import, 'ply': bpy.ops.import_mesh.ply}}[ext](filepath=path)\n    \
             o = bpy.context.selected_objects[0]\n    \
             zs = [(o.matrix_world @ v.co).z for v in o.data.vertices]\n    \
             print('BCIFS', round(min(zs), 3) + 0.0, round(max(zs), 3) + 0.0)\n",
        list.join(", ")
    );
    if let Some(lines) = blender(&script) {
        // Upright: z from 1.2 to 3.1 (the model's); on its back: the model's y, 0 to 1 (turned to −1 to 0).
        assert_eq!(lines, ["1.2 3.1", "1.2 3.1", "-1.0 0.0", "1.2 3.1"], "STL, OBJ, PLY, PLY --up z");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 46 §12: a coloured cloud of three objects (the gallery's
/// `contour-chaos`: 10, 50 and 300 points per map) groups its points in
/// OBJ with `p` records after each `o`, each object's vertices exactly;
/// MeshLab and trimesh read every point. Blender 3.4's OBJ importers (the
/// new one and the legacy add-on) put loose vertices in one object whatever
/// the grouping, so the GLB is the file that keeps the clouds apart there:
/// three objects of their own sizes.
#[test]
fn clouds_keep_their_objects_in_obj_and_in_blender() {
    use bcifs::geometry::{Shape, Sink as _};
    let dir = std::env::temp_dir().join(format!("bcifs-clouds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut shape = Shape::default();
    let sizes = [3usize, 20, 37];
    for (k, &n) in sizes.iter().enumerate() {
        shape.object(&format!("cloud {k}")).unwrap();
        shape.colours(&vec![[40 * k as u8, 200, 30]; n]).unwrap();
        let points: Vec<f64> = (0..n).flat_map(|i| [i as f64, k as f64, (i * i) as f64 / 7.0]).collect();
        shape.vertices(3, &points, None).unwrap();
    }
    let (obj, glb) = (dir.join("clouds.obj"), dir.join("clouds.glb"));
    bcifs::export::write_obj(&shape, "clouds", &obj).unwrap();
    let mut w = bcifs::export::GltfWriter::create(&glb).unwrap();
    shape.replay(&mut w).unwrap();
    w.finish().unwrap();

    // The records: `o cloud_k` followed by `p` lines naming its vertices, 1-based, in order.
    let text = std::fs::read_to_string(&obj).unwrap();
    let mut grouped: Vec<(String, Vec<usize>)> = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("o ") {
            grouped.push((name.to_string(), Vec::new()));
        } else if let Some(points) = line.strip_prefix("p ") {
            grouped.last_mut().expect("p after o").1.extend(points.split(' ').map(|v| v.parse::<usize>().unwrap()));
        }
    }
    let mut first = 1;
    for (k, (name, points)) in grouped.iter().enumerate() {
        assert_eq!(name, &format!("cloud_{k}"));
        assert_eq!(points, &(first..first + sizes[k]).collect::<Vec<_>>(), "{name}'s points");
        first += sizes[k];
    }
    assert_eq!(grouped.len(), 3);
    let total = sizes.iter().sum::<usize>().to_string();
    let p = obj.display();
    if let Some(n) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{p}')\nprint(ms.current_mesh().vertex_number())"
        ),
    ) {
        assert_eq!(n, total, "MeshLab: every point");
    }
    if let Some(n) = python("trimesh", &format!("import trimesh\nprint(len(trimesh.load('{p}').vertices))")) {
        assert_eq!(n, total, "trimesh: every point");
    }
    let script = format!(
        "import bpy, numpy\nnumpy.bool = bool\n\
         bpy.ops.object.select_all(action='SELECT')\nbpy.ops.object.delete()\n\
         bpy.ops.import_scene.gltf(filepath=r'{}')\n\
         for o in sorted(bpy.context.scene.objects, key=lambda o: o.name):\n    \
             print('BCIFS', o.name, len(o.data.vertices))\n",
        glb.display()
    );
    if let Some(lines) = blender(&script) {
        assert_eq!(lines, ["cloud 0 3", "cloud 1 20", "cloud 2 37"], "Blender: three clouds from the GLB");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
