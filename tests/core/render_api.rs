//! The library's render API (issue 24): the calls the command line makes,
//! their formats, reports, progress and cancellation.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use bcifs::mesh::{PolyMesh, Scheme, read_mesh, read_off};
use bcifs::render::{FileStyle, Format, Look, MeshJob, Options, RenderError, Sampling, render, render_mesh};
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
    options = options.with_chaos(1 << 24);
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
    let mut options = Options::default();
    options.budget.output = 1 << 20;
    let e = render_mesh(&mesh, &MeshJob::new(Scheme::CatmullClark, 6), &options, &dir.join("big.obj")).unwrap_err();
    assert!(matches!(e, RenderError::TooBig(_)), "{e}");
    assert!(!dir.join("big.obj").exists());
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Outputs with vertex normals too large to make in memory (here: over a
/// 2 MiB memory limit) are streamed through side files with the normals
/// computed a block at a time: the same bytes as made in memory, for OBJ,
/// PLY (binary and text) and glTF, every scheme, limit and net, faces of
/// any degree (Doo-Sabin's net keeps the split cube's pentagons and makes
/// digons, which files leave out), groups of faces; no side file is left.
/// Texture coordinates stay with the output made in memory: streamed, the
/// output has none, and says so.
#[test]
fn normals_streamed_are_the_normals_made_in_memory() {
    let dir = scratch("normals");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let suzanne = read_mesh(&data.join("suzanne.obj")).unwrap().without_texture();
    let split = read_mesh(&data.join("split_cube.obj")).unwrap();
    let grouped_text = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
        f 1 4 3 2\ng sides\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\ng top\nf 3 4 8 7\nf 4 1 5 8\n";
    std::fs::write(dir.join("grouped.obj"), grouped_text).unwrap();
    let grouped = read_mesh(&dir.join("grouped.obj")).unwrap();
    assert_eq!(grouped.groups.len(), 2);
    let small = |ascii: bool| {
        let mut o = Options::default();
        o.file.ascii = ascii;
        o.budget.memory = 2 << 20;
        o
    };
    // √3's limit holds its last net: over the limit here, it is tested in the library.
    let cases = [
        (&suzanne, Scheme::CatmullClark, 3, [false, true].as_slice()),
        (&suzanne.triangulated(), Scheme::Loop, 2, &[false, true]),
        (&suzanne.triangulated(), Scheme::Sqrt3, 3, &[true]),
        (&split, Scheme::DooSabin, 6, &[false, true]),
        (&grouped, Scheme::CatmullClark, 6, &[false, true]),
        (&grouped.triangulated(), Scheme::Loop, 5, &[false, true]),
    ];
    for (mesh, scheme, depth, nets) in cases {
        assert!(mesh.estimate(scheme, depth).1 > 2 << 20, "{scheme:?}: would not be streamed");
        for &net in nets {
            let job = MeshJob { net, ..MeshJob::new(scheme, depth) };
            for (ext, ascii) in [("obj", false), ("ply", false), ("ply", true), ("glb", false)] {
                let (a, b) = (dir.join(format!("a.{ext}")), dir.join(format!("b.{ext}")));
                let made = render_mesh(
                    mesh,
                    &job,
                    &Options { file: FileStyle { ascii, ..FileStyle::default() }, ..Options::default() },
                    &a,
                )
                .unwrap();
                let streamed = render_mesh(mesh, &job, &small(ascii), &b).unwrap();
                let what = format!("{scheme:?} depth {depth} net {net} .{ext} ascii {ascii}");
                assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(), "{what}: the files differ");
                assert_eq!(
                    (made.vertices, made.faces, &made.notes),
                    (streamed.vertices, streamed.faces, &streamed.notes)
                );
                assert!(made.notes.is_empty(), "{what}: {:?}", made.notes);
            }
        }
    }
    let text = std::fs::read_to_string(dir.join("a.obj")).unwrap();
    assert!(text.contains("\ng sides\n") && text.contains("\ng top\n"));
    // Texture coordinates: in memory within the limit, streamed without them beyond it.
    let textured = read_mesh(&data.join("suzanne.obj")).unwrap();
    let job = MeshJob::new(Scheme::CatmullClark, 3);
    let streamed = render_mesh(&textured, &job, &small(false), &dir.join("t.obj")).unwrap();
    assert!(streamed.notes.iter().any(|n| n.contains("texture coordinates")), "{:?}", streamed.notes);
    let text = std::fs::read_to_string(dir.join("t.obj")).unwrap();
    assert!(text.contains("\nvn ") && !text.contains("\nvt "));
    render_mesh(&textured, &job, &Options::default(), &dir.join("t.obj")).unwrap();
    assert!(std::fs::read_to_string(dir.join("t.obj")).unwrap().contains("\nvt "));
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A mesh render reports the faces it has written against the estimate,
/// never backwards, and ends with the whole: streamed (OFF), with normals
/// made in memory (OBJ), with normals streamed through side files (OBJ over a
/// 2 MiB memory limit: the side files' half, then the file's).
#[test]
fn mesh_renders_report_progress() {
    let dir = scratch("progress");
    let mesh = PolyMesh::cube();
    let job = MeshJob::new(Scheme::CatmullClark, 6);
    for (file, memory) in [("c.off", 4 << 30), ("c.obj", 4 << 30), ("s.obj", 2 << 20)] {
        let seen = Arc::new(std::sync::Mutex::new(Vec::new()));
        let log = seen.clone();
        let mut options = Options::default().with_progress(Progress::new(move |done, total| {
            log.lock().unwrap().push((done, total));
        }));
        options.budget.memory = memory;
        render_mesh(&mesh, &job, &options, &dir.join(file)).unwrap();
        let seen = seen.lock().unwrap();
        assert!(seen.len() > 1, "{file}: {seen:?}");
        assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0 && w[0].1 == w[1].1), "{file}: {seen:?}");
        let (done, total) = *seen.last().unwrap();
        assert_eq!(done, total, "{file}");
        if memory < 1 << 30 {
            assert!(seen.iter().any(|&(d, t)| d > 0 && d <= t / 2), "{file}: the side files' half");
        }
    }
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 43 §3: a picture made in memory is the file `render` writes, byte
/// for byte (its text chunks, its matte when transparent; a curve, a
/// surface, a chaos game's density), through the one PNG encoder; a page's
/// fast compression decodes to the same pixels.
#[test]
fn pictures_in_memory_are_the_files() {
    use bcifs::render::{Compression, picture_png};
    let dir = scratch("in-memory");
    let cases = [
        ("koch", Options::default().with_size(120, 90)),
        ("doo_sabin_torus", Options::default().with_size(96, 96)),
        (
            "fern",
            Options {
                sampling: Sampling { samples: Some(20_000), ..Sampling::default() },
                ..Options::default().with_size(80, 80)
            },
        ),
        ("gasket", Options { look: Look { transparent: true, ..Look::default() }, ..Options::default() }),
    ];
    for (name, options) in cases {
        let design = bcifs::render::load(name).unwrap();
        let file = dir.join(format!("{name}.png"));
        let written = render(&design, &options, &file).unwrap();
        let (report, png) = picture_png(&design, &options, Compression::Small).unwrap();
        assert_eq!(std::fs::read(&file).unwrap(), png, "{name}");
        assert_eq!((report.bytes, report.vertices), (written.bytes, written.vertices), "{name}");
        let (_, fast) = picture_png(&design, &options, Compression::Fast).unwrap();
        let decode = |bytes: &[u8]| image::load_from_memory(bytes).unwrap().to_rgba8();
        assert_eq!(decode(&fast), decode(&png), "{name}: the same pixels");
    }
    let coloured = Options { file: FileStyle { dedup: true, ..FileStyle::default() }, ..Options::default() };
    assert!(picture_png(&bcifs::render::load("fern").unwrap(), &coloured, Compression::Small).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 43 §3: every streamed output made in memory is the file `render`
/// writes, byte for byte: a curve, a surface (its normals and, in glTF, its
/// binary chunk), a chaos-game cloud and a deduplicated one, in each format
/// the explorer exports and the others streamed; nothing is left in the
/// temporary directory; the outputs made in files only say so.
#[test]
fn outputs_in_memory_are_the_files() {
    use bcifs::render::render_bytes;
    let dir = scratch("bytes");
    let cloud = Options::default().with_chaos(5_000);
    let cases = [
        ("corner_cutting", Options::default().with_depth(6), vec![Format::Obj, Format::Ply, Format::Glb]),
        (
            "doo_sabin_torus",
            Options::default().with_depth(3),
            vec![Format::Obj, Format::Off, Format::Ply, Format::Stl, Format::Glb],
        ),
        ("fern", cloud.clone(), vec![Format::Obj, Format::Ply, Format::Glb]),
        (
            "gasket",
            Options { file: FileStyle { dedup: true, ..FileStyle::default() }, ..Options::default().with_depth(5) },
            vec![Format::Obj, Format::Ply],
        ),
        ("koch", Options::default().with_size(90, 60), vec![Format::Png]),
    ];
    let temporaries = || {
        std::fs::read_dir(std::env::temp_dir())
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().contains(&format!(".{}.", std::process::id())))
            .count()
    };
    for (name, options, formats) in cases {
        let design = bcifs::render::load(name).unwrap();
        for format in formats {
            let file = dir.join(format!("{name}.{}", format.extension()));
            let written = render(&design, &options, &file).unwrap();
            let (report, bytes) = render_bytes(&design, &options, format).unwrap();
            assert_eq!(std::fs::read(&file).unwrap(), bytes, "{name} .{}", format.extension());
            assert_eq!(
                (report.bytes, report.vertices, report.faces),
                (written.bytes, written.vertices, written.faces),
                "{name} .{}",
                format.extension()
            );
        }
    }
    assert_eq!(temporaries(), 0, "side files of outputs in memory are removed");
    let design = bcifs::render::load("koch").unwrap();
    for format in [Format::Svg, Format::Flame] {
        let e = render_bytes(&design, &cloud, format).unwrap_err().to_string();
        assert!(e.contains("written to a file"), "{e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
