//! PLY and STL files (issue 25, on issue 24's pipeline) in the
//! clients that read them: trimesh, MeshLab and Blender 3.4.

use std::path::{Path, PathBuf};

use bcifs::mesh::{Scheme, read_mesh};
use bcifs::render::{MeshJob, Options, Report, render, render_mesh};

use crate::clients::{blender, python};

fn scratch(file: &str) -> PathBuf {
    std::env::temp_dir().join(format!("bcifs-ply-{}-{file}", std::process::id()))
}

fn design(name: &str, options: &Options, file: &str) -> (PathBuf, Report) {
    let path = scratch(file);
    let report = render(&bcifs::builtin_design(name).unwrap(), options, &path).unwrap();
    (path, report)
}

/// The closed Doo-Sabin torus as binary, ASCII and single-precision PLY:
/// trimesh reads it watertight and outward with every vertex, the binary
/// file's vertices are the OBJ file's to the bit, the `float` ones to 6
/// digits, MeshLab reads the ASCII file whole.
#[test]
fn surfaces_load_whole_from_ply() {
    let options = Options::default().with_depth(4);
    let (binary, report) = design("doo_sabin_torus", &options, "t.ply");
    let (ascii, _) = design(
        "doo_sabin_torus",
        &Options { file: bcifs::render::FileStyle { ascii: true, ..options.file }, ..options.clone() },
        "ta.ply",
    );
    let mut six = options.clone();
    six.set("precision", bcifs::render::Value::from(6)).unwrap();
    let (single, _) = design("doo_sabin_torus", &six, "t32.ply");
    let (obj, _) = design("doo_sabin_torus", &options, "t.obj");
    let head = std::fs::read(&binary).unwrap();
    assert!(head.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
    let [b, a, s, o] = [&binary, &ascii, &single, &obj].map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh, numpy as np\n\
             b = trimesh.load('{b}', process=False); a = trimesh.load('{a}', process=False)\n\
             s = trimesh.load('{s}', process=False); o = trimesh.load('{o}', process=False)\n\
             print(b.is_watertight, b.volume > 0, len(b.vertices), len(b.faces), \
                   np.array_equal(b.vertices, o.vertices), np.array_equal(a.vertices, o.vertices), \
                   np.abs(s.vertices - o.vertices).max() <= 1e-5 * np.abs(o.vertices).max())"
        ),
    ) {
        // Quads are split in two by trimesh.
        assert_eq!(out, format!("True True {} {} True True True", report.vertices, 2 * report.faces), "trimesh");
    }
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nms = pymeshlab.MeshSet()\nms.load_new_mesh('{a}')\nm = ms.current_mesh()\n\
             print(m.vertex_number(), m.face_number())"
        ),
    ) {
        assert_eq!(out, format!("{} {}", report.vertices, 2 * report.faces), "MeshLab");
    }
    for p in [binary, ascii, single, obj] {
        std::fs::remove_file(p).unwrap();
    }
}

/// Faces of any degree (Suzanne's Doo-Sabin net: n-gons beside quads) keep
/// their degree in Blender and are all there in MeshLab (which triangulates
/// them); a curve's segments are edges in both, a chaos-game cloud is every
/// point. trimesh's binary reader assumes faces of one degree (it refuses
/// the mixed file), so it is given the others.
#[test]
fn polygons_curves_and_clouds_load_whole_from_ply() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mesh = read_mesh(&data.join("suzanne.obj")).unwrap();
    let net = scratch("s.ply");
    let job = MeshJob { net: true, ..MeshJob::new(Scheme::DooSabin, 2) };
    let report = render_mesh(&mesh, &job, &Options::default(), &net).unwrap();
    let (curve, curve_report) = design("corner_cutting", &Options::default().with_depth(5), "c.ply");
    let random = Options::default().with_chaos(10_000);
    let (cloud, _) = design("fern", &random, "f.ply");
    let [n, c, f] = [&net, &curve, &cloud].map(|p| p.display().to_string());
    let corner_cutting_segments = curve_report.vertices; // a closed curve: as many segments as vertices
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nfor f in ['{n}', '{c}', '{f}']:\n    ms = pymeshlab.MeshSet(); ms.load_new_mesh(f)\n    \
             m = ms.current_mesh(); print(m.vertex_number(), m.face_number() > 0, m.edge_number())"
        ),
    ) {
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], format!("{} True 0", report.vertices), "MeshLab net");
        assert_eq!(lines[1], format!("{} False {corner_cutting_segments}", curve_report.vertices), "MeshLab curve");
        assert_eq!(lines[2], "10000 False 0", "MeshLab cloud");
    }
    if let Some(out) =
        python("trimesh", &format!("import trimesh\nm = trimesh.load('{f}')\nprint(type(m).__name__, len(m.vertices))"))
    {
        assert_eq!(out, "PointCloud 10000", "trimesh cloud");
    }
    let script = format!(
        "import bpy\n\
         for f in [r'{n}', r'{c}']:\n    bpy.ops.object.select_all(action='SELECT'); bpy.ops.object.delete()\n    \
         bpy.ops.import_mesh.ply(filepath=f)\n    o = bpy.context.selected_objects[0]\n    \
         print('BCIFS', len(o.data.vertices), len(o.data.polygons), len(o.data.edges))\n"
    );
    if let Some(lines) = blender(&script) {
        let net_line: Vec<usize> = lines[0].split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!((net_line[0], net_line[1]), (report.vertices, report.faces), "Blender keeps every n-gon");
        assert_eq!(lines[1], format!("{} 0 {corner_cutting_segments}", curve_report.vertices), "Blender curve");
    }
    for p in [net, curve, cloud] {
        std::fs::remove_file(p).unwrap();
    }
}

/// Binary STL for 3D printing: closed surfaces (the Doo-Sabin torus, the
/// Catmull-Clark cube, Doo-Sabin beside a valence-2 vertex) arrive
/// watertight and outward in trimesh once merged by position (a slicer's
/// sense), every face as triangles; a curve and a point cloud are refused
/// with the reason, and nothing is written.
#[test]
fn closed_surfaces_arrive_watertight_in_stl() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let (torus, report) = design("doo_sabin_torus", &Options::default().with_depth(4), "t.stl");
    assert_eq!(std::fs::metadata(&torus).unwrap().len(), 84 + 50 * 2 * report.faces as u64);
    let cube = scratch("cube.stl");
    let cc = render_mesh(
        &read_mesh(&data.join("cube.off")).unwrap(),
        &MeshJob::new(Scheme::CatmullClark, 3),
        &Options::default(),
        &cube,
    )
    .unwrap();
    let split = scratch("split.stl");
    let job = MeshJob::new(Scheme::DooSabin, 2);
    render_mesh(&read_mesh(&data.join("split_cube.obj")).unwrap(), &job, &Options::default(), &split).unwrap();
    let [t, c, s] = [&torus, &cube, &split].map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\nfor f in ['{t}', '{c}', '{s}']:\n    m = trimesh.load(f); m.merge_vertices()\n    \
             print(len(m.faces), m.is_watertight, m.is_winding_consistent, m.volume > 0)"
        ),
    ) {
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], format!("{} True True True", 2 * report.faces), "torus");
        assert_eq!(lines[1], format!("{} True True True", 2 * cc.faces), "cube");
        assert!(lines[2].ends_with("True True True"), "split cube: {}", lines[2]);
    }
    for (name, options, why) in [
        ("corner_cutting", Options::default().with_depth(4), "not curves"),
        ("fern", Options::default().with_chaos(1000), "no face"),
    ] {
        let out = scratch(&format!("{name}.stl"));
        let e = render(&bcifs::builtin_design(name).unwrap(), &options, &out).unwrap_err();
        assert!(e.to_string().contains(why), "{name}: {e}");
        assert!(!out.exists(), "{name}: nothing is written");
    }
    for p in [torus, cube, split] {
        std::fs::remove_file(p).unwrap();
    }
}

/// PNG pictures carry their settings in `tEXt` chunks (as flam3 records
/// its genome): the program, the design, the parameters and depth or the
/// chaos game, the size and view, and what asked for them; the pixels are
/// the same as without.
#[test]
fn png_pictures_carry_their_settings() {
    let text_of = |path: &Path| -> Vec<(String, String)> {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let reader = decoder.read_info().unwrap();
        reader.info().uncompressed_latin1_text.iter().map(|t| (t.keyword.clone(), t.text.clone())).collect()
    };
    let mut options = Options::default().with_depth(5).with_size(120, 90);
    options.params = vec![("a".into(), 0.25), ("b".into(), 0.125)];
    options.provenance = Some("a test of the render API".into());
    let (curve, _) = design("corner_cutting", &options, "cc.png");
    let text = text_of(&curve);
    let get = |k: &str| text.iter().find(|(key, _)| key == k).map(|(_, v)| v.as_str()).unwrap_or("");
    assert!(get("Software").starts_with("bcifs "), "{text:?}");
    assert_eq!(get("Title"), "corner_cutting");
    assert_eq!(get("Comment"), "params a=0.25 b=0.125; depth 5; size 120x90; view 30,35");
    assert_eq!(get("Description"), "a test of the render API");
    // The same pixels as the picture without chunks.
    let img = image::open(&curve).unwrap().to_rgb8();
    let plain = scratch("plain.png");
    bcifs::export::write_png(&plain, &img).unwrap();
    assert_eq!(image::open(&plain).unwrap().to_rgb8(), img);
    assert!(text_of(&plain).is_empty());
    // A chaos-game picture records the walk.
    let random =
        Options::from_values([("samples", 20_000.into()), ("seed", 7.into()), ("size", "64x64".into())]).unwrap();
    let (fern, _) = design("fern", &random, "fern.png");
    assert!(text_of(&fern).iter().any(|(k, v)| k == "Comment" && v.starts_with("random 20000 seed 7")));
    for p in [curve, plain, fern] {
        std::fs::remove_file(p).unwrap();
    }
}

/// A chaos game with `--palette` to OBJ and PLY: every point carries the
/// colour the density pictures give it (MeshLab's `v x y z r g b` in OBJ,
/// `uchar` RGB in PLY): as many colours as vertices, and many of them.
#[test]
fn coloured_clouds_carry_their_colours() {
    let options = Options::from_values([("samples", 20_000.into()), ("palette", "rainbow".into())]).unwrap();
    let (ply, _) = design("gasket", &options, "g.ply");
    let (obj, _) = design("gasket", &options, "g.obj");
    let [p, o] = [&ply, &obj].map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\nm = trimesh.load('{p}')\n\
             print(len(m.vertices), len(m.colors), len(set(map(tuple, m.colors[:, :3].tolist()))) > 50)"
        ),
    ) {
        assert_eq!(out, "20000 20000 True", "trimesh");
    }
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nfor f in ['{p}', '{o}']:\n    ms = pymeshlab.MeshSet(); ms.load_new_mesh(f)\n    \
             m = ms.current_mesh(); print(m.vertex_number(), m.has_vertex_color(), len(set(map(tuple, m.vertex_color_matrix().round(3).tolist()))) > 50)"
        ),
    ) {
        assert_eq!(out, "20000 True True\n20000 True True", "MeshLab");
    }

    for p in [ply, obj] {
        std::fs::remove_file(p).unwrap();
    }
}

/// `--transparent` pictures are RGBA whose background is transparent:
/// composited over the paper of the opaque picture they give it back (to
/// the rounding of 8-bit channels), and exactly the paper's pixels are
/// fully transparent: a curve, a shaded surface, a one-ink and a palette
/// density picture.
#[test]
fn transparent_pictures_composite_back_to_the_opaque_ones() {
    let random = |palette: Option<&str>| {
        let mut options = Options::default().with_chaos(50_000).with_size(160, 160);
        options.look.palette = palette.map(|p| bcifs::export::Palette::parse(p).unwrap());
        options
    };
    let cases = [
        ("koch", Options::default().with_depth(6).with_size(160, 120), [255u8; 3]),
        ("doo_sabin_torus", Options::default().with_depth(4).with_size(160, 120), [255; 3]),
        ("fern", random(None), [255; 3]),
        ("fern", random(Some("fire")), [0; 3]),
    ];
    for (k, (name, options, paper)) in cases.into_iter().enumerate() {
        let (opaque, _) = design(name, &options, &format!("opaque{k}.png"));
        let mut clear = options.clone();
        clear.look.transparent = true;
        let (transparent, _) = design(name, &clear, &format!("clear{k}.png"));
        let (o, t) = (image::open(&opaque).unwrap(), image::open(&transparent).unwrap());
        assert_eq!(t.color(), image::ColorType::Rgba8, "{name}");
        let (o, t) = (o.to_rgb8(), t.to_rgba8());
        let mut worst = 0u8;
        for (po, pt) in o.pixels().zip(t.pixels()) {
            let a = f64::from(pt[3]) / 255.0;
            for c in 0..3 {
                let over = (f64::from(pt[c]) * a + f64::from(paper[c]) * (1.0 - a)).round() as u8;
                worst = worst.max(over.abs_diff(po[c]));
            }
            assert_eq!(pt[3] == 0, po.0 == paper, "{name}: the paper, and only it, is clear");
        }
        // Alpha is rounded to 1/255: an ink's channel moves by at most its distance to the paper over 255, twice.
        assert!(worst <= 2, "{name} ({k}): composited back within {worst} levels");
        std::fs::remove_file(opaque).unwrap();
        std::fs::remove_file(transparent).unwrap();
    }
}

/// `surface` output carries area-weighted vertex normals in every format
/// that has them (OBJ `vn`, PLY `nx ny nz`, glTF `NORMAL`): in trimesh each
/// vertex has one, unit, pointing out of the closed Catmull-Clark cube and
/// within a few degrees of the normal trimesh computes from the faces (its
/// own weighting differs; the surface is smooth, so both are close).
#[test]
fn subdivided_surfaces_carry_vertex_normals() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let cube = read_mesh(&data.join("cube.off")).unwrap();
    let mut files = Vec::new();
    let mut vertices = 0;
    for (ext, net) in [("obj", false), ("ply", false), ("glb", true)] {
        let path = scratch(&format!("normals.{ext}"));
        let job = MeshJob { net, ..MeshJob::new(Scheme::CatmullClark, 3) };
        vertices = render_mesh(&cube, &job, &Options::default(), &path).unwrap().vertices;
        files.push(path);
    }
    let list: Vec<String> = files.iter().map(|p| format!("'{}'", p.display())).collect();
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh, numpy as np\nfor f in [{}]:\n    \
             m = trimesh.load(f, force='mesh', process=False)\n    n = np.asarray(m.vertex_normals)\n    \
             own = trimesh.Trimesh(vertices=m.vertices, faces=m.faces, process=False).vertex_normals\n    \
             out = ((m.vertices - m.vertices.mean(axis=0)) * n).sum(axis=1)\n    \
             angle = np.degrees(np.arccos(np.clip((n * own).sum(axis=1), -1, 1))).max()\n    \
             print(len(n), np.abs(np.linalg.norm(n, axis=1) - 1).max() < 1e-6, (out > 0).all(), angle < 5)",
            list.join(", ")
        ),
    ) {
        for (line, file) in out.lines().zip(&files) {
            assert_eq!(line, format!("{vertices} True True True"), "{}", file.display());
        }
    }
    for p in files {
        std::fs::remove_file(p).unwrap();
    }
}

/// `.flame` files (flam3's XML) of the plain IFS: flam3-render draws the
/// picture bcifs draws, framed alike and standing alike (the inked pixels
/// of the two pictures overlap to 90% at least: their tone mappings and
/// filters differ, the shape and its frame do not), with one ink or the
/// fire palette; a graph-directed automaton is refused with the reason.
#[test]
fn flame_files_render_the_same_picture_in_flam3() {
    let probe = std::process::Command::new("flam3-render").stdin(std::process::Stdio::null()).output();
    for (name, palette) in [("fern", None), ("gasket", Some("fire")), ("levy", None)] {
        let mut options = Options::default().with_chaos(1_000_000).with_size(200, 160);
        options.look.palette = palette.map(|p| bcifs::export::Palette::parse(p).unwrap());
        let (flame, _) = design(name, &options, &format!("{name}.flame"));
        let (ours, _) = design(name, &options, &format!("{name}.png"));
        let text = std::fs::read_to_string(&flame).unwrap();
        assert!(text.contains("<flame ") && text.contains("linear=\"1\""), "{text}");
        if probe.is_err() {
            println!("skipped: flam3-render is not installed (apt-get install flam3-utils)");
        } else {
            let prefix = scratch(&format!("{name}-flam3-"));
            let rendered = std::process::Command::new("flam3-render")
                .env("prefix", &prefix)
                .env("format", "png")
                .stdin(std::fs::File::open(&flame).unwrap())
                .output()
                .unwrap();
            assert!(rendered.status.success(), "{}", String::from_utf8_lossy(&rendered.stderr));
            assert!(!String::from_utf8_lossy(&rendered.stderr).contains("Warning"), "flam3 takes every attribute");
            let theirs = PathBuf::from(format!("{}00000.png", prefix.display()));
            let inked = |path: &Path| -> Vec<bool> {
                let img = image::open(path).unwrap().to_rgb8();
                let paper = *img.get_pixel(0, 0);
                img.pixels().map(|p| (0..3).any(|k| p[k].abs_diff(paper[k]) > 8)).collect()
            };
            let (a, b) = (inked(&theirs), inked(&ours));
            assert_eq!(a.len(), b.len(), "{name}: same size");
            let both = a.iter().zip(&b).filter(|(x, y)| **x && **y).count() as f64;
            let either = a.iter().zip(&b).filter(|(x, y)| **x || **y).count() as f64;
            assert!(both / either > 0.9, "{name}: flam3 and bcifs ink the same pixels ({:.3})", both / either);
            std::fs::remove_file(theirs).unwrap();
        }
        std::fs::remove_file(flame).unwrap();
        std::fs::remove_file(ours).unwrap();
    }
    let out = scratch("cc.flame");
    let e = render(&bcifs::builtin_design("corner_cutting").unwrap(), &Options::default(), &out).unwrap_err();
    assert!(e.to_string().contains("graph-directed"), "{e}");
    assert!(!out.exists());
}

/// `--colour level|state|map` (issue 25) on deterministic evaluations, in
/// the files that hold colours:
/// - level: the box-spline patch at depth 3 has 7 vertices already at level
///   0 (the hexagon's), then 12, 42 and 156 new ones (`3R(R + 1) + 1`
///   lattice points for `R = 2^j`): one colour per level, in those counts;
/// - state: the graph-directed fern-with-Sierpinski's points of the fern
///   state are the points left when the one arrow into the other state
///   (`T2`) is dropped, and the others are the rest;
/// - map: the Koch curve at depth 1 gives each of its four pieces
///   `s c_q + (1 − s)/2` with `c_q = q/(n − 1)` (`n` subdivision arrows)
///   and `s = 1/2`, the end point its last piece's;
///
/// trimesh reads a colour per vertex.
#[test]
fn vertices_are_coloured_by_level_state_and_map() {
    use bcifs::eval::Colouring;
    let count = |path: &Path| -> Vec<usize> {
        let p = path.display();
        let out = python(
            "trimesh",
            &format!(
                "import trimesh, collections\nm = trimesh.load('{p}', process=False)\n\
                 c = m.visual.vertex_colors if hasattr(m, 'visual') else m.colors\n\
                 assert len(c) == len(m.vertices)\nprint(*sorted(collections.Counter(map(tuple, c.tolist())).values()))"
            ),
        );
        out.map(|o| o.split(' ').map(|x| x.parse().unwrap()).collect()).unwrap_or_default()
    };
    let coloured = |mode| {
        let mut options = Options::default().with_depth(3);
        options.look.colour = Some(mode);
        options
    };
    let patch = scratch("levels.ply");
    let box_spline = bcifs::schemes::ifs_preset("box-spline", None, None).unwrap();
    let report = render(&box_spline, &coloured(Colouring::Level), &patch).unwrap();
    assert_eq!(report.vertices, 217);
    let levels = count(&patch);
    assert!(levels.is_empty() || levels == [7, 12, 42, 156], "{levels:?}");
    // Blender 3.4's PLY importer keeps colours on faces' corners (a cloud's are dropped): the patch's arrive.
    let script = format!(
        "import bpy\nbpy.ops.object.select_all(action='SELECT'); bpy.ops.object.delete()\n\
         bpy.ops.import_mesh.ply(filepath=r'{}')\no = bpy.context.selected_objects[0]\n\
         print('BCIFS', len(o.data.vertices), len(o.data.color_attributes))\n",
        patch.display()
    );
    if let Some(lines) = crate::clients::blender(&script) {
        assert_eq!(lines[0], "217 1", "Blender: every vertex, one colour attribute");
    }

    let states = Options::from_values([("colour", "state".into()), ("depth", 5.into())]).unwrap();
    let (fs, all) = design("fern_sierpinski", &states, "states.ply");
    let mut fern_only = Options::default().with_depth(5);
    fern_only.sampling.dropped = vec!["T2".into()];
    let (fern, only) = design("fern_sierpinski", &fern_only, "fern.ply");
    let per_state = count(&fs);
    if !per_state.is_empty() {
        let mut expected = vec![only.vertices, all.vertices - only.vertices];
        expected.sort_unstable();
        assert_eq!(per_state, expected, "fern state and Sierpinski state");
    }

    let design_koch = bcifs::builtin_design("koch").unwrap();
    let instance = bcifs::instantiate(&design_koch, &[]).unwrap();
    let model = design_koch.model().unwrap();
    let mut ev =
        bcifs::eval::Evaluator::new(&instance.automaton, model, bcifs::eval::EvalSettings::default().with_depth(1))
            .unwrap();
    let (shape, coordinates) =
        ev.evaluate_coloured(&instance.automaton, Colouring::Map, &bcifs::eval::RandomSettings::default()).unwrap();
    assert_eq!(shape.vertex_count(), 5);
    // Arrow colours are spread over all subdivision arrows (the end vertex's own arrow too).
    let arrows = instance.automaton.arrows().filter(|(_, a)| a.kind == bcifs::ArrowKind::Subdivision).count() as f64;
    let expected: Vec<f32> =
        [0.0, 1.0, 2.0, 3.0, 3.0].iter().map(|q: &f64| (0.5 * q / (arrows - 1.0) + 0.25) as f32).collect();
    for (c, e) in coordinates.iter().zip(&expected) {
        assert!((c - e).abs() < 1e-6, "{coordinates:?} against {expected:?}");
    }
    for p in [patch, fs, fern] {
        std::fs::remove_file(p).unwrap();
    }
}

/// The triangles of a binary STL file: their count and total area.
fn stl_area(path: &Path) -> (usize, f64) {
    let bytes = std::fs::read(path).unwrap();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let f = |at: usize| f64::from(f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()));
    let area = (0..count)
        .map(|t| {
            let p = |k: usize| [0, 1, 2].map(|a| f(84 + 50 * t + 12 + 12 * k + 4 * a));
            let (a, b, c) = (p(0), p(1), p(2));
            let (u, v) = ([0, 1, 2].map(|i| b[i] - a[i]), [0, 1, 2].map(|i| c[i] - a[i]));
            let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            n.iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0
        })
        .sum();
    (count, area)
}

/// Surfaces streamed a block at a time send a block's faces before its
/// vertices: STL, which needs positions to write a triangle, refused them
/// ("a face refers to a vertex not written before it"). Every surface the
/// OBJ writer takes, STL takes, with the same triangles (their area to f32).
#[test]
fn every_surface_written_as_obj_is_written_as_stl() {
    for (name, depth) in [("doo_sabin_quad", 3), ("bicubic", 4), ("ternary5-surface", 2), ("doo_sabin_torus", 3)] {
        let design = bcifs::render::load(name).unwrap();
        let mut options = Options::default().with_depth(depth);
        // Open sheets are no solids: a print file of them is asked for.
        options.file.print.allow_non_manifold = true;
        let (stl, obj) = (scratch(&format!("{name}.stl")), scratch(&format!("{name}.obj")));
        let report = render(&design, &options, &stl).unwrap_or_else(|e| panic!("{name}: {e}"));
        render(&design, &options, &obj).unwrap();
        let (triangles, area) = stl_area(&stl);
        let (models, _) = tobj::load_obj(&obj, &tobj::LoadOptions { triangulate: true, ..Default::default() }).unwrap();
        let mut obj_area = 0.0;
        let mut obj_triangles = 0;
        for m in &models {
            let p = |i: u32| [0, 1, 2].map(|a| m.mesh.positions[3 * i as usize + a]);
            for t in m.mesh.indices.chunks_exact(3) {
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                let (u, v) = ([0, 1, 2].map(|i| b[i] - a[i]), [0, 1, 2].map(|i| c[i] - a[i]));
                let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
                obj_area += n.iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0;
                obj_triangles += 1;
            }
        }
        assert_eq!(triangles, obj_triangles, "{name}");
        assert!(triangles >= report.faces, "{name}");
        // f32 coordinates: relative error of an area below 1e-6 a triangle, summed.
        assert!((area - obj_area).abs() <= 1e-5 * obj_area, "{name}: {area} against {obj_area}");
        std::fs::remove_file(stl).unwrap();
        std::fs::remove_file(obj).unwrap();
    }
}

/// Issue 46 §11: every picture the command line writes carries `Software`,
/// `Title`, `Comment` and `Description` (`scheme ifs`, `scheme normal`, whose
/// Greek letters go in `iTXt`, `analyze map`, `surface`, `render --control`),
/// and a picture is the same file whatever `--threads` (the command line
/// recorded leaves the thread count out).
#[test]
fn every_picture_carries_its_settings_and_threads_change_no_byte() {
    let keys_of = |path: &Path| -> Vec<String> {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let reader = decoder.read_info().unwrap();
        let info = reader.info();
        let mut keys: Vec<String> = info.uncompressed_latin1_text.iter().map(|t| t.keyword.clone()).collect();
        keys.extend(info.utf8_text.iter().map(|t| t.keyword.clone()));
        keys.sort();
        keys
    };
    let out = scratch("picture.png");
    let o = out.display().to_string();
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cube.off").display().to_string();
    let runs: [Vec<&str>; 6] = [
        vec!["scheme", "ifs", "bspline", "-o", &o],
        vec!["scheme", "normal", "--preset", "snowflake", "-o", &o],
        vec!["analyze", "map", "corner_cutting", "--x", "a=-1:1", "--y", "b=-1:1", "--size", "24", "-o", &o],
        vec!["surface", &cube, "--scheme", "catmull-clark", "--depth", "2", "-o", &o],
        vec!["render", "gasket", "--control", "-o", &o],
        vec!["render", "fern", "--random", "20000", "-o", &o],
    ];
    let bcifs = env!("CARGO_BIN_EXE_bcifs");
    for args in &runs {
        let run = std::process::Command::new(bcifs).args(args).output().unwrap();
        assert!(run.status.success(), "{args:?}: {}", String::from_utf8_lossy(&run.stderr));
        assert_eq!(keys_of(&out), ["Comment", "Description", "Software", "Title"], "{args:?}");
    }
    let with_threads = |n: &str| {
        let args = ["render", "fern", "--random", "20000", "--threads", n, "-o", &o];
        assert!(std::process::Command::new(bcifs).args(args).output().unwrap().status.success());
        std::fs::read(&out).unwrap()
    };
    assert!(with_threads("1") == with_threads("2"), "the same picture whatever --threads");
    std::fs::remove_file(out).unwrap();
}
