//! The render API, as the command line, the Python module and the explorer
//! call it: a design rendered to OBJ and PNG, a polygon mesh subdivided to
//! OBJ, with a progress callback and a cancellation flag.
//!
//! `cargo run --release --example render_api -- [OUT_DIR]`

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use bcifs::mesh::{PolyMesh, Scheme};
use bcifs::render::{MeshJob, Options, RenderError, render, render_mesh};
use bcifs::{Cancel, Progress};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).map_or_else(std::env::temp_dir, PathBuf::from);
    std::fs::create_dir_all(&dir)?;

    // Progress: the library reports (done, total); here, the furthest fraction seen.
    let seen = Arc::new(AtomicU64::new(0));
    let s = seen.clone();
    let progress = Progress::new(move |done, total| {
        s.fetch_max(done * 100 / total.max(1), Ordering::Relaxed);
    });
    // Cancellation: a web server sets the flag when the request goes away, the CLI on Ctrl-C.
    let cancel = Cancel::new();

    // A design (the Doo-Sabin torus, a shipped automaton) to OBJ and PNG.
    let design = bcifs::builtin_design("doo_sabin_torus").ok_or("doo_sabin_torus is shipped")?;
    let options =
        Options::default().with_depth(4).with_size(400, 400).with_progress(progress).with_cancel(cancel.clone());
    for file in ["torus.obj", "torus.png"] {
        let report = render(&design, &options, &dir.join(file))?;
        println!(
            "{file}: {} vertices, {} faces, {} bytes, depth {:?}",
            report.vertices, report.faces, report.bytes, report.depth
        );
    }
    println!("progress reached {}%", seen.load(Ordering::Relaxed));

    // A polygon mesh (a cube) subdivided by Catmull-Clark, its limit surface to OBJ.
    let job = MeshJob::new(Scheme::CatmullClark, 5);
    let report = render_mesh(&PolyMesh::cube(), &job, &options, &dir.join("cube.obj"))?;
    println!("cube.obj: {} vertices, {} faces", report.vertices, report.faces);

    // Once the flag is set, the next render stops before it writes anything.
    cancel.cancel();
    match render(&design, &options, &dir.join("never.obj")) {
        Err(RenderError::Cancelled) => println!("cancelled: never.obj was not written"),
        other => return Err(format!("expected a cancelled render, got {other:?}").into()),
    }
    Ok(())
}
