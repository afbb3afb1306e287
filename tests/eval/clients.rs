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
