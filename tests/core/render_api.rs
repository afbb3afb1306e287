//! The library's render API (issue 24): the calls the command line makes,
//! their formats, reports, progress and cancellation.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use bcifs::mesh::{PolyMesh, Scheme, read_mesh, read_off};
use bcifs::render::{Format, MeshJob, Options, RenderError, render, render_mesh};
use bcifs::{Cancel, Progress};

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bcifs-api-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn bcifs(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().expect("run bcifs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into())
}

/// No temporary file is left in `dir`.
fn no_temporaries(dir: &Path) {
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// The CLI is a shell over the API: the same design, depth and format give
/// the same bytes, for a surface (OBJ, OFF) and a curve (OBJ).
#[test]
fn the_cli_makes_the_api_calls() {
    let dir = scratch("same");
    for (name, ext) in [("doo_sabin_torus", "obj"), ("doo_sabin_torus", "off"), ("corner_cutting", "obj")] {
        let design = bcifs::builtin_design(name).unwrap();
        let api = dir.join(format!("{name}-api.{ext}"));
        let cli = dir.join(format!("{name}-cli.{ext}"));
        let report = render(&design, &Options::default().with_depth(3), &api).unwrap();
        let (code, err) = bcifs(&["render", name, "--depth", "3", "-o", cli.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        let bytes = std::fs::read(&api).unwrap();
        assert_eq!(bytes, std::fs::read(&cli).unwrap(), "{name}.{ext}");
        assert_eq!(report.bytes, bytes.len() as u64);
        assert_eq!(report.depth, Some(3));
        assert_eq!(report.format, Some(Format::of(&api).unwrap()));
    }
    // An OFF surface reads back with the counts the report gives (a closed torus: V − E + F = 0).
    let off = read_off(&std::fs::read_to_string(dir.join("doo_sabin_torus-api.off")).unwrap(), "t.off").unwrap();
    let report = render(
        &bcifs::builtin_design("doo_sabin_torus").unwrap(),
        &Options::default().with_depth(3),
        &dir.join("again.off"),
    )
    .unwrap();
    assert_eq!((off.positions.len(), off.face_count()), (report.vertices, report.faces));
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Formats by extension: unknown ones and curves to OFF are refused with
/// the reason, and nothing is written.
#[test]
fn formats_are_chosen_by_extension() {
    let dir = scratch("formats");
    assert_eq!(Format::of(Path::new("a/B.OBJ")).unwrap(), Format::Obj);
    assert!(matches!(Format::of(Path::new("x.stp")), Err(RenderError::Format(e)) if e == "stp"));
    let curve = bcifs::builtin_design("corner_cutting").unwrap();
    let off = dir.join("curve.off");
    let e = render(&curve, &Options::default().with_depth(3), &off).unwrap_err();
    assert!(e.to_string().contains("not curves"), "{e}");
    assert!(!off.exists());
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A flag set while the file is streamed stops the render at its next
/// batch: `Cancelled`, the target not created, no temporary file left; the
/// same for a mesh subdivision. Progress is reported to the callback.
#[test]
fn cancellation_stops_a_streamed_render() {
    let dir = scratch("cancel");
    let cancel = Cancel::new();
    let reports = Arc::new(AtomicU64::new(0));
    let (flag, count) = (cancel.clone(), reports.clone());
    let progress = Progress::new(move |done, total| {
        count.fetch_add(1, Ordering::Relaxed);
        if done > 0 && done < total {
            flag.cancel();
        }
    });
    let design = bcifs::builtin_design("doo_sabin_torus").unwrap();
    let options = Options::default().with_depth(7).with_progress(progress).with_cancel(cancel.clone());
    let out = dir.join("torus.obj");
    assert!(matches!(render(&design, &options, &out), Err(RenderError::Cancelled)));
    assert!(reports.load(Ordering::Relaxed) > 0, "progress was reported");
    assert!(!out.exists());
    // A mesh: the flag already set stops it before any work; set during the write, at the next batch.
    let mesh = PolyMesh::cube();
    let job = MeshJob::new(Scheme::CatmullClark, 6);
    assert!(matches!(render_mesh(&mesh, &job, &options, &dir.join("cube.obj")), Err(RenderError::Cancelled)));
    assert!(!dir.join("cube.obj").exists());
    no_temporaries(&dir);
    // A density picture of the chaos game: the walk stops taking batches once the flag is set.
    let cancel = Cancel::new();
    let flag = cancel.clone();
    let progress = Progress::new(move |done, total| {
        if done > 0 && done < total {
            flag.cancel();
        }
    });
    let mut options = Options::default().with_progress(progress).with_cancel(cancel).with_size(64, 64);
    options.random = Some(bcifs::eval::RandomSettings::default().with_points(1 << 24));
    let fern = bcifs::builtin_design("fern").unwrap();
    assert!(matches!(render(&fern, &options, &dir.join("fern.png")), Err(RenderError::Cancelled)));
    assert!(!dir.join("fern.png").exists());
    // Without the flag the same calls write their files.
    let fresh = Options::default().with_depth(3);
    render(&design, &fresh, &out).unwrap();
    let report = render_mesh(&mesh, &job, &fresh, &dir.join("cube.obj")).unwrap();
    assert_eq!(report.faces, 6 * 4usize.pow(6));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A mesh through the API: OBJ and OFF of the same job are the same mesh,
/// in the input's axes, with the counts of the report; the estimate over
/// the size limit is refused before writing.
#[test]
fn meshes_render_to_every_format() {
    let dir = scratch("mesh");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mesh = read_mesh(&data.join("suzanne.obj")).unwrap();
    for scheme in Scheme::ALL {
        let mesh = if matches!(scheme, Scheme::Loop | Scheme::Sqrt3) { mesh.triangulated() } else { mesh.clone() };
        for net in [false, true] {
            let job = MeshJob { net, ..MeshJob::new(scheme, 2) };
            let (obj, off) = (dir.join("s.obj"), dir.join("s.off"));
            let a = render_mesh(&mesh, &job, &Options::default(), &obj).unwrap();
            let b = render_mesh(&mesh, &job, &Options::default(), &off).unwrap();
            assert_eq!((a.vertices, a.faces), (b.vertices, b.faces));
            let (m1, m2) = (read_mesh(&obj).unwrap(), read_mesh(&off).unwrap());
            assert_eq!(m1.clone().without_texture(), m2, "{scheme:?} net {net}: OFF has no texture coordinates");
            assert_eq!((m1.positions.len(), m1.face_count()), (a.vertices, a.faces));
            // Suzanne stands: her height (file y) is her input's y, untouched.
            let span = |m: &PolyMesh, k: usize| {
                let v = m.positions.iter().map(|p| p[k]);
                v.clone().fold(f64::MIN, f64::max) - v.fold(f64::MAX, f64::min)
            };
            assert!((span(&m1, 1) - span(&mesh, 1)).abs() < 0.2 * span(&mesh, 1), "{scheme:?}");
            render_mesh(&mesh, &job, &Options::default().with_size(64, 64), &dir.join("s.png")).unwrap();
        }
    }
    let options = Options { max_output: 1 << 20, ..Options::default() };
    let e = render_mesh(&mesh, &MeshJob::new(Scheme::CatmullClark, 6), &options, &dir.join("big.obj")).unwrap_err();
    assert!(matches!(e, RenderError::TooBig(_)), "{e}");
    assert!(!dir.join("big.obj").exists());
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}
