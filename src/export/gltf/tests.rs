//! The glTF writer's unit tests.

use super::*;

/// The JSON and binary chunks of a `.glb`.
fn chunks(bytes: &[u8]) -> (Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!((&bytes[..4], word(8)), (&b"glTF"[..], bytes.len()));
    let json_len = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = bytes.get(28 + json_len..).unwrap_or_default().to_vec();
    (json, bin)
}

/// The `f32` or `u32` words of accessor `a`.
fn words(json: &Value, bin: &[u8], a: &Value) -> Vec<u32> {
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let (at, len) = (view["byteOffset"].as_u64().unwrap() as usize, view["byteLength"].as_u64().unwrap() as usize);
    bin[at..at + len].chunks_exact(4).map(|w| u32::from_le_bytes(w.try_into().unwrap())).collect()
}

/// Objects streamed through the side files come out whole: positions
/// as `f32` with their bounds, normals only when every vertex has one
/// (and normalised), each object's faces fanned and numbered from its
/// first vertex, groups as primitives; the side files are gone after.
#[test]
fn objects_stream_through_side_files() {
    let dir = std::env::temp_dir().join(format!("bcifs-glb-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("two.glb");
    let mut glb = GltfWriter::create(&path).unwrap().with_coordinates(Coordinates { up: Up::Z, ..Default::default() });
    let n = 3000;
    let points: Vec<f64> = (0..3 * n).map(|k| (k % 7) as f64 * 0.5 - (k % 11) as f64).collect();
    let normals: Vec<f64> = (0..3 * n).map(|k| 1.0 + (k % 5) as f64).collect();
    glb.object("a").unwrap();
    glb.vertices(3, &points[..3 * 1000], Some(&normals[..3 * 1000])).unwrap();
    glb.vertices(3, &points[3 * 1000..], Some(&normals[3 * 1000..])).unwrap();
    let quads: Vec<usize> = (0..n - 3).step_by(2).flat_map(|v| [v, v + 1, v + 3, v + 2]).collect();
    let starts: Vec<usize> = (0..=quads.len() / 4).map(|k| 4 * k).collect();
    glb.polygons(&starts[..11], &quads).unwrap();
    glb.group("rest").unwrap();
    glb.polygons(&starts[10..].iter().map(|s| s - 40).collect::<Vec<_>>(), &quads[40..]).unwrap();
    glb.object("b").unwrap();
    glb.vertices(3, &points[..9], Some(&normals[..9])).unwrap();
    glb.vertices(3, &points[9..12], None).unwrap();
    glb.triangles(&[[n, n + 1, n + 3]]).unwrap();
    glb.finish().unwrap();
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "side files left");
    let (json, bin) = chunks(&std::fs::read(&path).unwrap());
    let meshes = json["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 2);
    let [a, b] = [0, 1].map(|m| &meshes[m]["primitives"]);
    assert_eq!((a.as_array().unwrap().len(), a[1]["extras"]["group"].as_str()), (2, Some("rest")));
    let accessor = |k: &Value| &json["accessors"][k.as_u64().unwrap() as usize];
    let position = accessor(&a[0]["attributes"]["POSITION"]);
    let floats: Vec<f32> = words(&json, &bin, position).into_iter().map(f32::from_bits).collect();
    // Z-up input: the file's (x, y, z) is the model's (x, z, −y).
    let turned: Vec<f32> = points.chunks(3).flat_map(|p| [p[0] as f32, p[2] as f32, -p[1] as f32]).collect();
    assert_eq!(floats, turned);
    let lo: Vec<f32> =
        (0..3).map(|a| turned.iter().skip(a).step_by(3).copied().fold(f32::INFINITY, f32::min)).collect();
    assert_eq!(position["min"], json!(lo));
    let normal: Vec<f32> =
        words(&json, &bin, accessor(&a[0]["attributes"]["NORMAL"])).into_iter().map(f32::from_bits).collect();
    assert!(normal.chunks(3).all(|v| (v.iter().map(|x| x * x).sum::<f32>() - 1.0).abs() < 1e-6));
    let fans: Vec<u32> = quads.chunks(4).flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]]).map(|v| v as u32).collect();
    let mut indices = words(&json, &bin, accessor(&a[0]["indices"]));
    indices.extend(words(&json, &bin, accessor(&a[1]["indices"])));
    assert_eq!(indices, fans);
    assert!(b[0]["attributes"].get("NORMAL").is_none(), "b's last vertex has no normal");
    assert_eq!(words(&json, &bin, accessor(&b[0]["indices"])), [0, 1, 3]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A face or polyline naming a vertex of no object is refused when the
/// object ends, naming the first such vertex, and nothing is written.
#[test]
fn a_vertex_outside_its_object_is_refused() {
    let dir = std::env::temp_dir().join(format!("bcifs-glb-outside-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.glb");
    let mut glb = GltfWriter::create(&path).unwrap();
    glb.object("a").unwrap();
    glb.vertices(3, &[0.0; 9], None).unwrap();
    glb.triangles(&[[0, 1, 2], [0, 5, 4]]).unwrap();
    let e = glb.object("b").unwrap_err();
    assert!(e.to_string().contains("refers to vertex 5, outside its object (vertices 0 to 3)"), "{e}");
    drop(glb);
    // A polyline's too.
    let mut glb = GltfWriter::create(&path).unwrap();
    glb.object("a").unwrap();
    glb.vertices(3, &[0.0; 6], None).unwrap();
    glb.polyline(1, 2, false).unwrap();
    let e = glb.finish().unwrap_err();
    assert!(e.to_string().contains("refers to vertex 2, outside its object (vertices 0 to 2)"), "{e}");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}
