//! Polygon meshes: reading, checks, subdivision against CGAL, limit surfaces.

mod automaton;
mod cgal;
#[path = "../common/hausdorff.rs"]
mod hausdorff;
mod meshes;
mod opensubdiv;
mod sources;

use bcifs::mesh::PolyMesh;

/// Test meshes: closed and open, with triangles, quads, pentagons, and
/// vertices of valence 2 to 5 (faces counter-clockwise seen from outside).
pub fn shapes() -> Vec<(&'static str, PolyMesh)> {
    let cube = cube();
    // A square pyramid: four triangles and a quad; apex of valence 4, base of valence 3.
    let pyramid = PolyMesh::new(
        vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [0.1, 0.2, 1.5]],
        vec![vec![0, 3, 2, 1], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]],
    )
    .unwrap();
    // A pentagonal prism: two pentagons, five quads, valence 3.
    let mut p = Vec::new();
    for z in [0.0, 1.3] {
        for k in 0..5 {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 5.0;
            p.push([a.cos(), a.sin(), z + 0.1 * k as f64]);
        }
    }
    let mut faces = vec![vec![4, 3, 2, 1, 0], vec![5, 6, 7, 8, 9]];
    faces.extend((0..5).map(|k| vec![k, (k + 1) % 5, 5 + (k + 1) % 5, 5 + k]));
    let prism = PolyMesh::new(p, faces).unwrap();
    // An icosahedron: triangles, valence 5.
    let icosahedron = icosahedron();
    // A cube without its top: open, a square boundary, corners of valence 2 on the border.
    let open_box = PolyMesh::new(
        cube.positions.clone(),
        cube.faces().filter(|f| f != &[4, 5, 6, 7]).map(<[usize]>::to_vec).collect(),
    )
    .unwrap();
    // A 3 × 2 sheet with a pentagon and a triangle.
    let sheet = PolyMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.1],
            [0.0, 1.0, 0.3],
            [1.0, 1.0, 0.5],
            [2.0, 1.0, 0.4],
            [3.0, 1.0, 0.0],
            [0.0, 2.0, 0.0],
            [1.5, 2.2, 0.2],
            [3.0, 2.0, 0.0],
        ],
        vec![vec![0, 1, 5, 4], vec![1, 2, 6, 5], vec![2, 3, 7, 6], vec![4, 5, 9, 8], vec![5, 6, 10, 9], vec![6, 7, 10]],
    )
    .unwrap();
    // The cube with a vertex inserted in an edge: two pentagons, an interior vertex of valence 2
    // (Doo-Sabin makes a digon of it, as CGAL does; Suzanne has one too).
    let mut positions = cube.positions.clone();
    positions.push([0.0, -1.0, -1.0]);
    let split_edge = PolyMesh::new(
        positions,
        vec![
            vec![0, 3, 2, 1, 8],
            vec![4, 5, 6, 7],
            vec![0, 8, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
    )
    .unwrap();
    vec![
        ("cube", cube),
        ("split_edge", split_edge),
        ("pyramid", pyramid),
        ("prism", prism),
        ("icosahedron", icosahedron),
        ("open_box", open_box),
        ("sheet", sheet),
    ]
}

/// Every test mesh with the polygon schemes, and split into triangles with
/// every scheme: `(name, mesh, scheme)`.
pub fn cases() -> Vec<(String, PolyMesh, bcifs::mesh::Scheme)> {
    use bcifs::mesh::Scheme;
    let mut out = Vec::new();
    for (name, mesh) in shapes() {
        for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
            out.push((name.to_string(), mesh.clone(), scheme));
        }
        let triangles = mesh.triangulated();
        for scheme in Scheme::ALL {
            out.push((format!("{name} (triangles)"), triangles.clone(), scheme));
        }
    }
    out
}

/// The cube [-1, 1]³.
pub fn cube() -> PolyMesh {
    PolyMesh::new(
        vec![
            [-1.0, -1.0, -1.0],
            [1.0, -1.0, -1.0],
            [1.0, 1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
            [1.0, -1.0, 1.0],
            [1.0, 1.0, 1.0],
            [-1.0, 1.0, 1.0],
        ],
        vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
    )
    .unwrap()
}

/// A regular icosahedron, faces outwards.
pub fn icosahedron() -> PolyMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let positions = vec![
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    PolyMesh::new(positions, faces.iter().map(|f| f.to_vec()).collect()).unwrap()
}

/// A scratch file path for this test process, tagged `tag`.
pub fn scratch(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("bcifs-mesh-{}-{tag}", std::process::id()))
}

/// A mesh written as OFF by the library's one OFF writer (in its own axes), as text.
pub fn off_text(mesh: &PolyMesh, tag: &str) -> String {
    let path = scratch(&format!("{tag}.off"));
    let coordinates = bcifs::export::Coordinates { y_up_input: true, ..Default::default() };
    let mut off = bcifs::export::OffWriter::create(&path).unwrap().with_coordinates(coordinates);
    mesh.push_into(&mut off).unwrap();
    off.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    text
}
