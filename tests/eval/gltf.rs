//! glTF 2.0 binary files (issue 25) in the clients that read them: the
//! Khronos glTF validator (no error, no warning), trimesh and Blender 3.4's
//! importer.

use std::path::{Path, PathBuf};

use bcifs::geometry::{Shape, Sink};
use bcifs::mesh::{Scheme, read_mesh};
use bcifs::render::{MeshJob, Options, Report, render, render_mesh, write_shape};

use crate::clients::{blender, gltf_validator, python};

fn scratch(file: &str) -> PathBuf {
    std::env::temp_dir().join(format!("bcifs-glb-{}-{file}", std::process::id()))
}

fn design(name: &str, options: &Options, file: &str) -> (PathBuf, Report) {
    let path = scratch(file);
    let report = render(&bcifs::builtin_design(name).unwrap(), options, &path).unwrap();
    (path, report)
}

/// Blender's glTF importer, headless: per object of each file, `name
/// vertices faces edges dx dy dz smooth_faces colour_attributes uv_layers`.
/// Debian's Blender 3.4 importer calls `numpy.bool`, which its NumPy (1.24)
/// no longer has: the alias is put back before importing.
fn blender_glb(files: &[&Path]) -> Option<Vec<String>> {
    let list: Vec<String> = files.iter().map(|f| format!("r'{}'", f.display())).collect();
    blender(&format!(
        "import bpy, numpy\nnumpy.bool = bool\n\
         for f in [{}]:\n    bpy.ops.wm.read_factory_settings(use_empty=True)\n    \
         bpy.ops.import_scene.gltf(filepath=f)\n    \
         for o in sorted(bpy.data.objects, key=lambda o: o.name):\n        m = o.data\n        \
         print('BCIFS', o.name.replace(' ', '_'), len(m.vertices), len(m.polygons), len(m.edges), \
               *[round(x, 3) for x in o.dimensions], sum(p.use_smooth for p in m.polygons), \
               len(m.color_attributes), len(m.uv_layers))\n",
        list.join(", ")
    ))
}

/// The closed Doo-Sabin torus, a curve, a coloured cloud and an open sheet
/// as `.glb`: valid for the Khronos validator; in trimesh a watertight outward mesh
/// (quads as two triangles), a path and a coloured point cloud with every
/// vertex; in Blender the same counts, smooth-shaded (the normals are
/// there), the colours an attribute, and the torus standing as it was
/// modelled (the model's z, its axis, is glTF's y and Blender's z again).
#[test]
fn surfaces_curves_and_clouds_load_whole_from_glb() {
    let (torus, report) = design("doo_sabin_torus", &Options::default().with_depth(4), "torus.glb");
    let (curve, curve_report) = design("corner_cutting", &Options::default().with_depth(5), "curve.glb");
    let coloured = Options::from_values([("samples", 20_000.into()), ("palette", "rainbow".into())]).unwrap();
    let (cloud, _) = design("gasket", &coloured, "cloud.glb");
    // An open sheet streams its far row and column after its quads: they refer to vertices still to come.
    let (sheet, _) = design("doo_sabin_quad", &Options::default().with_depth(3), "sheet.glb");
    let files = [torus.as_path(), curve.as_path(), cloud.as_path()];
    if let Some(verdicts) = gltf_validator(&[&torus, &curve, &cloud, &sheet]) {
        for (file, (errors, warnings, messages)) in [&torus, &curve, &cloud, &sheet].iter().zip(verdicts) {
            assert_eq!((errors, warnings), (0, 0), "{}: {messages:?}", file.display());
        }
    }
    std::fs::remove_file(sheet).unwrap();
    let [t, c, p] = files.map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\n\
             t = trimesh.load('{t}', force='mesh'); t.merge_vertices()\n\
             print(len(t.faces), t.is_watertight, t.volume > 0, t.extents.argmin())\n\
             c = trimesh.load('{c}', force='scene'); g = list(c.geometry.values())[0]\n\
             print(type(g).__name__, len(g.vertices))\n\
             p = trimesh.load('{p}', force='scene'); g = list(p.geometry.values())[0]\n\
             print(type(g).__name__, len(g.vertices), len(g.colors), len(set(map(tuple, g.colors.tolist()))) > 50)"
        ),
    ) {
        let lines: Vec<&str> = out.lines().collect();
        // The torus axis (model z) is the file's y.
        assert_eq!(lines[0], format!("{} True True 1", 2 * report.faces), "trimesh torus");
        assert_eq!(lines[1], format!("Path3D {}", curve_report.vertices), "trimesh curve");
        assert_eq!(lines[2], "PointCloud 20000 20000 True", "trimesh cloud");
    }
    if let Some(out) = python(
        "pymeshlab",
        &format!(
            "import pymeshlab\nfor f in ['{t}', '{p}']:\n    ms = pymeshlab.MeshSet(); ms.load_new_mesh(f)\n    \
             m = ms.current_mesh(); print(m.vertex_number(), m.face_number(), m.has_vertex_color())"
        ),
    ) {
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], format!("{} {} False", report.vertices, 2 * report.faces), "MeshLab torus (no colours)");
        assert_eq!(lines[1], "20000 0 True", "MeshLab coloured cloud");
    }
    if let Some(lines) = blender_glb(&files) {
        let torus_line: Vec<&str> = lines[0].split(' ').collect();
        assert_eq!(torus_line[1..4], [report.vertices, 2 * report.faces, 3 * report.faces].map(|n| n.to_string()));
        let (dx, dz): (f64, f64) = (torus_line[4].parse().unwrap(), torus_line[6].parse().unwrap());
        assert!(dz < dx / 2.0, "the torus stands on its axis in Blender: {}", lines[0]);
        assert_eq!(torus_line[7], (2 * report.faces).to_string(), "smooth: every face has its vertex normals");
        let curve_line: Vec<&str> = lines[1].split(' ').collect();
        // A closed curve: as many segments as vertices.
        assert_eq!(curve_line[1..4], [curve_report.vertices, 0, curve_report.vertices].map(|n| n.to_string()));
        let cloud_line: Vec<&str> = lines[2].split(' ').collect();
        assert_eq!((cloud_line[1], cloud_line[8]), ("20000", "1"), "Blender cloud: {}", lines[2]);
    }
    for p in [torus, curve, cloud] {
        std::fs::remove_file(p).unwrap();
    }
}

/// One node per object, named as the objects are: a shape of a surface
/// (quads), a triangle, a polyline and a cloud gives four meshes in every
/// client; faces of any degree (Suzanne's Doo-Sabin net) are fanned into
/// triangles, every one of them there.
#[test]
fn objects_are_nodes_and_polygons_are_fanned() {
    let mut shape = Shape::default();
    shape.object("quads").unwrap();
    shape.vertices(3, &[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 1., 0., 1.], None).unwrap();
    shape.faces(&[[0, 1, 2, 3], [0, 4, 5, 1]], None).unwrap();
    shape.object("triangle").unwrap();
    shape.vertices(3, &[2., 0., 0., 3., 0., 0., 2., 1., 0.], None).unwrap();
    shape.triangles(&[[6, 7, 8]]).unwrap();
    shape.object("polyline").unwrap();
    shape.vertices(3, &[4., 0., 0., 5., 0., 0., 5., 1., 1.], None).unwrap();
    shape.polyline(9, 3, false).unwrap();
    shape.object("cloud").unwrap();
    shape.vertices(3, &[6., 0., 0., 7., 0., 0.], None).unwrap();
    let objects = scratch("objects.glb");
    write_shape(&shape, "objects", &Default::default(), &objects).unwrap();

    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let net = scratch("suzanne.glb");
    let job = MeshJob { net: true, ..MeshJob::new(Scheme::DooSabin, 1) };
    let mesh = read_mesh(&data.join("suzanne.obj")).unwrap();
    let report = render_mesh(&mesh, &job, &Options::default(), &net).unwrap();
    let subdivided = mesh.subdivide(Scheme::DooSabin, 1).unwrap();
    let triangles: usize = subdivided.written_faces().map(|f| f.len() - 2).sum();

    if let Some(verdicts) = gltf_validator(&[&objects, &net]) {
        for (errors, warnings, messages) in verdicts {
            assert_eq!((errors, warnings), (0, 0), "{messages:?}");
        }
    }
    let [o, n] = [&objects, &net].map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh\ns = trimesh.load('{o}', force='scene')\n\
             print(' '.join(f'{{k}}:{{type(g).__name__}}:{{len(g.vertices)}}' for k, g in sorted(s.geometry.items())))\n\
             m = trimesh.load('{n}', force='mesh')\nprint(len(m.vertices), len(m.faces))"
        ),
    ) {
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], "cloud:PointCloud:2 polyline:Path3D:3 quads:Trimesh:6 triangle:Trimesh:3");
        assert_eq!(lines[1], format!("{} {triangles}", report.vertices), "Suzanne's net, fanned");
    }
    if let Some(lines) = blender_glb(&[&objects, &net]) {
        let names: Vec<&str> = lines[..4].iter().map(|l| l.split(' ').next().unwrap()).collect();
        assert_eq!(names, ["cloud", "polyline", "quads", "triangle"]);
        assert!(lines[2].starts_with("quads 6 4 "), "{}", lines[2]);
        assert!(lines[1].starts_with("polyline 3 0 2 "), "{}", lines[1]);
        let counts: Vec<usize> = lines[4].split(' ').skip(1).take(2).map(|x| x.parse().unwrap()).collect();
        assert_eq!(counts, [report.vertices, triangles], "Blender: Suzanne's net");
    }
    for p in [objects, net] {
        std::fs::remove_file(p).unwrap();
    }
}

/// A textured mesh through Catmull-Clark into glTF: texture coordinates
/// per vertex (glTF has no face-varying attribute), so a seam vertex is
/// written once per side: valid for the validator, one UV map in Blender,
/// every corner with the texture coordinate the OBJ gives it (OBJ's `v` up,
/// glTF's down: `1 − v`; compared to 5 decimals: glTF is `float`).
#[test]
fn textured_meshes_keep_their_uvs_in_glb() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let suzanne = read_mesh(&data.join("suzanne.obj")).unwrap();
    let (glb, obj) = (scratch("suzanne-uv.glb"), scratch("suzanne-uv.obj"));
    let job = MeshJob::new(Scheme::CatmullClark, 1);
    let report = render_mesh(&suzanne, &job, &Options::default(), &glb).unwrap();
    render_mesh(&suzanne, &job, &Options::default(), &obj).unwrap();
    if let Some(verdicts) = gltf_validator(&[&glb]) {
        assert_eq!((verdicts[0].0, verdicts[0].1), (0, 0), "{:?}", verdicts[0].2);
    }
    let [g, o] = [&glb, &obj].map(|p| p.display().to_string());
    if let Some(out) = python(
        "trimesh",
        &format!(
            "import trimesh, numpy as np\n\
             g = trimesh.load('{g}', force='mesh', process=False)\n\
             o = trimesh.load('{o}', force='mesh', process=False)\n\
             def corners(m):\n    c = np.hstack([m.vertices[m.faces].reshape(-1, 3), m.visual.uv[m.faces].reshape(-1, 2)])\n    \
             return c[np.lexsort(np.round(c, 3).T[::-1])]\n\
             a, b = corners(g), corners(o)\n\
             print(len(g.visual.uv) == len(g.vertices), a.shape == b.shape and np.abs(a - b).max() < 1e-5)"
        ),
    ) {
        assert_eq!(out, "True True", "trimesh: the same texture coordinate at every corner");
    }
    if let Some(lines) = blender_glb(&[&glb]) {
        let fields: Vec<&str> = lines[0].split(' ').collect();
        assert_eq!(fields[0], "Suzanne");
        assert_eq!(fields[2], (report.faces * 2).to_string(), "quads as two triangles");
        assert_eq!(fields[9], "1", "one UV map");
    }
    std::fs::remove_file(glb).unwrap();
    std::fs::remove_file(obj).unwrap();
}

/// Groups of faces (OBJ's `g`) through Catmull-Clark into glTF: one
/// primitive per group, named in its `extras`, with its faces' children
/// (16 quads, 32 triangles, per input quad after two steps); the node is
/// named as the file names its object; valid for the validator.
#[test]
fn groups_are_primitives_in_glb() {
    let cube = "o box\ng top\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
                f 5 6 7 8\ng sides\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\ng bottom\nf 1 4 3 2\n";
    let mesh = bcifs::mesh::read_obj(cube, "box.obj").unwrap();
    let out = scratch("groups.glb");
    render_mesh(&mesh, &MeshJob::new(Scheme::CatmullClark, 2), &Options::default(), &out).unwrap();
    let bytes = std::fs::read(&out).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    let primitives: Vec<(String, u64)> = json["meshes"][0]["primitives"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let count = json["accessors"][p["indices"].as_u64().unwrap() as usize]["count"].as_u64().unwrap();
            (p["extras"]["group"].as_str().unwrap().to_string(), count)
        })
        .collect();
    let expected = [("top", 96), ("sides", 4 * 96), ("bottom", 96)].map(|(g, n)| (g.to_string(), n));
    assert_eq!(primitives, expected);
    assert_eq!(json["nodes"][0]["name"], "box");
    if let Some(verdicts) = gltf_validator(&[&out]) {
        assert_eq!((verdicts[0].0, verdicts[0].1), (0, 0), "{:?}", verdicts[0].2);
    }
    std::fs::remove_file(out).unwrap();
}

/// Issue 46 §10: glTF's `COLOR_0` is linear (glTF 2.0, §3.7.2.1), bcifs's
/// colours sRGB: the GLB holds each colour of the PLY (sRGB bytes, as PNG
/// and PLY readers expect) decoded by the sRGB curve, vertex for vertex,
/// to 16-bit rounding — read here from the file's own bytes.
#[test]
fn glb_colours_are_linear_and_ply_colours_srgb() {
    use bcifs::eval::Colouring;
    let mut options = Options::default().with_depth(3);
    options.look.colour = Some(Colouring::Level);
    let design = bcifs::schemes::ifs_preset("box-spline", None, None).unwrap();
    let (glb, ply) = (scratch("levels.glb"), scratch("levels.ply"));
    render(&design, &options, &glb).unwrap();
    let ascii = Options { file: bcifs::render::FileStyle { ascii: true, ..options.file }, ..options.clone() };
    render(&design, &ascii, &ply).unwrap();
    // The PLY's sRGB bytes: the last three numbers of each vertex line.
    let text = std::fs::read_to_string(&ply).unwrap();
    let count: usize = text.lines().find_map(|l| l.strip_prefix("element vertex ")).unwrap().parse().unwrap();
    let body = text.split("end_header\n").nth(1).unwrap();
    let srgb: Vec<[u8; 3]> = body
        .lines()
        .take(count)
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            [0, 1, 2].map(|k| w[w.len() - 3 + k].parse().unwrap())
        })
        .collect();
    // The GLB's COLOR_0: its accessor, view and bytes.
    let bytes = std::fs::read(&glb).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let gltf: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    let bin = &bytes[20 + length + 8..];
    let accessor =
        &gltf["accessors"][gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].as_u64().unwrap() as usize];
    assert_eq!((accessor["componentType"].as_u64(), accessor["normalized"].as_bool()), (Some(5123), Some(true)));
    let view = &gltf["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let at = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    assert_eq!(accessor["count"].as_u64(), Some(count as u64));
    let decode = |b: u8| {
        let c = f64::from(b) / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    let mut distinct = std::collections::HashSet::new();
    for (v, c) in srgb.iter().enumerate() {
        for k in 0..4 {
            let o = at + 8 * v + 2 * k;
            let stored = f64::from(u16::from_le_bytes([bin[o], bin[o + 1]])) / 65535.0;
            let expected = if k == 3 { 1.0 } else { decode(c[k]) };
            assert!(
                (stored - expected).abs() <= 0.5 / 65535.0 + 1e-12,
                "vertex {v} channel {k}: {stored} vs {expected}"
            );
        }
        distinct.insert(*c);
    }
    assert!(distinct.len() >= 4, "the levels' colours: {distinct:?}");
    if let Some(verdicts) = gltf_validator(&[&glb]) {
        assert_eq!((verdicts[0].0, verdicts[0].1), (0, 0), "{:?}", verdicts[0].2);
    }
    for p in [glb, ply] {
        std::fs::remove_file(p).ok();
    }
}
