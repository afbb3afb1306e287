//! The files bcifs writes, loaded by the programs users open them with
//! (MeshLab through pymeshlab, trimesh). A client that is not installed is
//! skipped with a printed reason; `.ci/run` installs both.

use std::process::Command;

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::export::ObjWriter;

use crate::load;

/// Runs a Python script with `module` importable; `None` (and a printed
/// reason) when Python or the module is missing.
fn python(module: &str, script: &str) -> Option<String> {
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
        let p = path.display();
        if let Some(out) = python(
            "trimesh",
            &format!(
                "import trimesh\nm = trimesh.load('{p}')\nprint(m.is_watertight, m.euler_number, m.volume > 0, len(m.vertices))"
            ),
        ) {
            assert_eq!(out, format!("True 0 True {}", shape.vertex_count()), "{name} in trimesh");
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
        std::fs::remove_file(&path).unwrap();
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
