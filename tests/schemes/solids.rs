//! Volume patterns (issue 44): hexahedra and tetrahedra split into kept
//! sub-cells make porous solids whose depth-k cells have the topology the
//! pattern implies, checked against counts made here on the pattern's own
//! voxel grid (not by the library's code), and whose boundary mesh is closed.

use std::collections::{HashMap, HashSet};

use bcifs::render::topology_report;
use bcifs::schemes::{Pattern, PatternCell, PatternError, pattern_design};

/// The Menger sponge's mask: a cell is kept unless two of its coordinates are the middle one.
const MENGER: &str = "111101111101000101111101111";

/// The voxels of a hexahedron pattern's depth-`k` cells on the grid of `split^k` a side (3 × 3 × 3 splits).
pub(crate) fn voxels(mask: &str, k: u32) -> (usize, HashSet<[usize; 3]>) {
    let keep: Vec<bool> = mask.chars().map(|c| c == '1').collect();
    let side = 3usize.pow(k);
    let mut out = HashSet::new();
    for z in 0..side {
        for y in 0..side {
            for x in 0..side {
                let (mut a, mut b, mut c, mut kept) = (x, y, z, true);
                for _ in 0..k {
                    kept &= keep[(c % 3) * 9 + (b % 3) * 3 + a % 3];
                    (a, b, c) = (a / 3, b / 3, c / 3);
                }
                if kept {
                    out.insert([x, y, z]);
                }
            }
        }
    }
    (side, out)
}

/// The Euler characteristic of a union of closed unit cubes (its distinct
/// vertices, edges, squares and cubes), its components (cubes touching at
/// least at a corner), and its cavities (the complement's components that do
/// not reach the outside): the Betti numbers follow, `b1 = b0 + b2 − χ`.
pub(crate) fn cube_topology(side: usize, cubes: &HashSet<[usize; 3]>) -> (i64, [i64; 3]) {
    // Cells of the cubical complex by doubled coordinates: a vertex has all even, a cube all odd.
    let mut cells: HashSet<[usize; 3]> = HashSet::new();
    for c in cubes {
        for dz in 0..3 {
            for dy in 0..3 {
                for dx in 0..3 {
                    cells.insert([2 * c[0] + dx, 2 * c[1] + dy, 2 * c[2] + dz]);
                }
            }
        }
    }
    let euler: i64 =
        cells.iter().map(|p| if p.iter().filter(|&&x| x % 2 == 1).count() % 2 == 0 { 1 } else { -1 }).sum();
    let flood = |start: Vec<[isize; 3]>, inside: &dyn Fn([isize; 3]) -> bool, seen: &mut HashSet<[isize; 3]>| {
        let mut stack = start;
        while let Some(p) = stack.pop() {
            if !inside(p) || !seen.insert(p) {
                continue;
            }
            for a in 0..3 {
                for s in [-1, 1] {
                    let mut q = p;
                    q[a] += s;
                    stack.push(q);
                }
            }
        }
    };
    // Components: cubes touching at a corner are joined (26-neighbours).
    let mut parts = 0;
    let mut seen: HashSet<[usize; 3]> = HashSet::new();
    for c in cubes {
        if seen.contains(c) {
            continue;
        }
        parts += 1;
        let mut stack = vec![*c];
        while let Some(p) = stack.pop() {
            if !seen.insert(p) {
                continue;
            }
            for d in 0..27usize {
                let q = [p[0] + d % 3, p[1] + d / 3 % 3, p[2] + d / 9].map(|x| x.wrapping_sub(1));
                if cubes.contains(&q) {
                    stack.push(q);
                }
            }
        }
    }
    // Cavities: empty voxels (face-neighbours) not reached from a padding layer around the box.
    let n = side as isize;
    let empty = |p: [isize; 3]| {
        p.iter().all(|&x| (-1..=n).contains(&x))
            && !(p.iter().all(|&x| (0..n).contains(&x)) && cubes.contains(&p.map(|x| x as usize)))
    };
    let mut outside = HashSet::new();
    flood(vec![[-1, -1, -1]], &empty, &mut outside);
    let mut cavities = 0;
    let mut inner = HashSet::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = [x, y, z];
                if empty(p) && !outside.contains(&p) && !inner.contains(&p) {
                    cavities += 1;
                    flood(vec![p], &empty, &mut inner);
                }
            }
        }
    }
    (euler, [parts, parts + cavities - euler, cavities])
}

/// The volume a closed outward mesh encloses (the divergence theorem).
fn enclosed_volume(shape: &bcifs::geometry::Shape) -> f64 {
    let tri = shape.quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
    tri.chain(shape.triangles.iter().map(|t| t.map(|v| v as u32)))
        .map(|t| {
            let [a, b, c] = t.map(|v| shape.point(v as usize));
            a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum::<f64>()
        / 6.0
}

/// Every edge of a mesh has two faces, used once in each direction (closed and consistently oriented).
fn closed_and_oriented(shape: &bcifs::geometry::Shape) -> bool {
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    let faces =
        shape.quads.iter().map(|q| q.map(|v| v as usize).to_vec()).chain(shape.triangles.iter().map(|t| t.to_vec()));
    for f in faces {
        for k in 0..f.len() {
            *directed.entry((f[k], f[(k + 1) % f.len()])).or_default() += 1;
        }
    }
    directed.iter().all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
}

#[test]
fn the_menger_sponge_has_20_to_the_k_cubes_and_the_genus_its_voxels_give() {
    let menger = bcifs::builtin_design("menger").unwrap();
    let family = bcifs::solve(&menger).unwrap();
    assert!(!family.parameters.is_empty(), "the split points are free");
    for k in 1..=3u32 {
        let t = topology_report(&menger, &[], k as usize).unwrap();
        let (side, cubes) = voxels(MENGER, k);
        assert_eq!(t.cells, 20usize.pow(k), "depth {k}");
        assert_eq!(cubes.len(), t.cells);
        let (euler, betti) = cube_topology(side, &cubes);
        assert_eq!((t.euler, t.betti), (euler, betti), "depth {k}");
        assert_eq!(t.pinches, 0);
        // The boundary mesh is closed, oriented outward, and holds (20/27)^k of the cube.
        let shape = crate::evaluate(&menger, k as usize);
        assert!(closed_and_oriented(&shape), "depth {k}");
        let volume = enclosed_volume(&shape);
        assert!((volume - (20.0f64 / 27.0).powi(k as i32)).abs() < 1e-12, "depth {k}: {volume}");
        // A closed surface of genus g bounds a solid of χ = 1 − g: χ(surface) = 2χ(solid).
        let faces = shape.quads.len() as i64;
        let mut edges = HashSet::new();
        for q in &shape.quads {
            for i in 0..4 {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        let used: HashSet<u32> = shape.quads.iter().flatten().copied().collect();
        assert_eq!(used.len() as i64 - edges.len() as i64 + faces, 2 * euler, "depth {k}");
    }
    assert_eq!(topology_report(&menger, &[], 1).unwrap().betti, [1, 5, 0], "the level-1 sponge has genus 5");
    // Depth 4: 160,000 cubes, genus 26,433, as the voxels say.
    let t = topology_report(&menger, &[], 4).unwrap();
    let (side, cubes) = voxels(MENGER, 4);
    assert_eq!((t.cells, (t.euler, t.betti)), (160_000, cube_topology(side, &cubes)));
    assert_eq!(t.betti, [1, 26_433, 0]);
    // Its similarity dimension is log 20 / log 3, and it converges.
    let d = bcifs::render::dimension_report(&menger, &[]).unwrap();
    assert!((d.similarity.unwrap() - 20f64.ln() / 3f64.ln()).abs() < 1e-9, "{:?}", d.similarity);
    assert_eq!(bcifs::render::check_report(&menger, &[]).unwrap().converges, Some(true));
}

#[test]
fn the_jerusalem_like_sponge_is_the_menger_pattern_split_at_two_fifths() {
    // Its default member is affine: each depth keeps 8·(2/5)³ + 12·(2/5)²·(1/5) = 0.896 of the volume.
    let jerusalem = bcifs::builtin_design("jerusalem").unwrap();
    let text = bcifs::write_design(&jerusalem);
    assert!(text.contains(r#"entry = "U1[1][0]", default = "2/5""#), "{text}");
    for k in 1..=3 {
        let shape = crate::evaluate(&jerusalem, k);
        assert!(closed_and_oriented(&shape), "depth {k}");
        assert!((enclosed_volume(&shape) - 0.896f64.powi(k as i32)).abs() < 1e-12, "depth {k}");
        let (side, cubes) = voxels(MENGER, k as u32);
        assert_eq!(topology_report(&jerusalem, &[], k).unwrap().betti, cube_topology(side, &cubes).1);
    }
    // The same family as the sponge: only the defaults differ.
    let menger = bcifs::builtin_design("menger").unwrap();
    assert_eq!(bcifs::solve(&jerusalem).unwrap().parameter_names(), bcifs::solve(&menger).unwrap().parameter_names());
    // Split points that do not fit are refused.
    let p = Pattern::parse(PatternCell::Hexahedron, "3x3x3", None, 2).unwrap();
    for bad in ["3/5,2/5", "0,1/2", "1/2", "a,b"] {
        assert!(matches!(p.clone().with_at(bad), Err(PatternError::At(_))), "{bad}");
    }
}

#[test]
fn other_members_move_the_holes_and_keep_the_topology() {
    // Any member of the family (the split points moved: a Jerusalem-cube-like sponge with bigger
    // corners, or a rough one) has the topology of the pattern: the constraints, not the numbers, make it.
    let menger = bcifs::builtin_design("menger").unwrap();
    let family = bcifs::solve(&menger).unwrap();
    let defaults = family.parameter_values(&[]).unwrap();
    let moved: Vec<(String, f64)> = family
        .parameter_names()
        .iter()
        .zip(&defaults)
        .enumerate()
        .map(|(i, (n, v))| (n.to_string(), v + 0.02 * ((i * 7919 % 13) as f64 / 13.0 - 0.5)))
        .collect();
    for k in 1..=2 {
        let t = topology_report(&menger, &moved, k).unwrap();
        let (side, cubes) = voxels(MENGER, k as u32);
        assert_eq!((t.euler, t.betti), cube_topology(side, &cubes), "depth {k}");
    }
    let d = topology_report(&menger, &moved, 1).unwrap();
    assert_eq!(d.betti, [1, 5, 0]);
}

#[test]
fn the_sierpinski_tetrahedron_touches_at_points_and_cantor_dust_falls_apart() {
    let tetra = bcifs::builtin_design("sierpinski_tetrahedron").unwrap();
    for k in 1..=4usize {
        let t = topology_report(&tetra, &[], k).unwrap();
        let n = 4i64.pow(k as u32);
        // 4^k tetrahedra glued at 2(4^k − 1) points, each shared by two: a graph of loops.
        let contacts = 2 * (n - 1);
        assert_eq!(t.cells as i64, n, "depth {k}");
        assert_eq!(t.pinches as i64, contacts, "depth {k}: every contact is a pinch");
        assert_eq!(t.betti, [1, contacts - (n - 1), 0], "depth {k}");
    }
    // The classical member: the corners of the depth-1 cells are the tetrahedron's edge midpoints.
    let shape = crate::evaluate(&tetra, 1);
    let model = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 3f64.sqrt() / 2.0, 0.0],
        [0.5, 3f64.sqrt() / 6.0, (2.0f64 / 3.0).sqrt()],
    ];
    for i in 0..4 {
        for j in i + 1..4 {
            let mid: Vec<f64> = (0..3).map(|a| (model[i][a] + model[j][a]) / 2.0).collect();
            assert!(
                (0..shape.vertex_count()).any(|v| (0..3).all(|a| (shape.point(v)[a] - mid[a]).abs() < 1e-12)),
                "the middle of edge {i}{j}"
            );
        }
    }
    let dust = bcifs::builtin_design("cantor_dust").unwrap();
    for k in 1..=4usize {
        let t = topology_report(&dust, &[], k).unwrap();
        let n = 8i64.pow(k as u32);
        assert_eq!((t.components as i64, t.betti), (n, [n, 0, 0]), "depth {k}: separate cubes");
        if k < 4 {
            assert!(closed_and_oriented(&crate::evaluate(&dust, k)));
        }
    }
}

#[test]
fn contacts_along_an_edge_or_at_a_corner_are_generated_and_said() {
    // Two cubes of a 2×2×2 split touching along an edge only, and two touching at a corner only.
    for (mask, what) in [("10000010", "along an edge only"), ("10000001", "at a corner only")] {
        let pattern = Pattern::parse(PatternCell::Hexahedron, "2x2x2", Some(mask), 2).unwrap();
        let design = pattern_design(&pattern, "touching").unwrap();
        let text = bcifs::write_design(&design);
        assert!(text.contains(&format!("touch {what} (a pinch)")), "{mask}: {text}");
        bcifs::solve(&design).unwrap();
        let t = topology_report(&design, &[], 1).unwrap();
        assert_eq!((t.cells, t.components, t.betti), (2, 1, [1, 0, 0]), "{mask}");
        assert!(t.pinches >= 1, "{mask}: {t:?}");
        // The cells really share the contact at every depth: still one piece at depth 2.
        assert_eq!(topology_report(&design, &[], 2).unwrap().components, 1, "{mask}");
    }
    // A full 2×2×2 split is the cube: no pinch, no hole; its boundary encloses the unit cube.
    let full = pattern_design(&Pattern::parse(PatternCell::Hexahedron, "2x2x3", None, 3).unwrap(), "full").unwrap();
    let t = topology_report(&full, &[], 2).unwrap();
    assert_eq!((t.cells, t.betti, t.pinches), (144, [1, 0, 0], 0));
    assert!((enclosed_volume(&crate::evaluate(&full, 2)) - 1.0).abs() < 1e-12);
}

#[test]
fn volume_patterns_refuse_what_does_not_fit() {
    let e = Pattern::parse(PatternCell::Hexahedron, "3x3", None, 2).unwrap_err();
    assert!(matches!(e, PatternError::Split { .. }) && e.to_string().contains("KxLxM"), "{e}");
    let e = Pattern::parse(PatternCell::Hexahedron, "3x3x3", Some("1111"), 2).unwrap_err();
    assert!(matches!(e, PatternError::Mask { expected: 27, .. }), "{e}");
    let e = Pattern::parse(PatternCell::Tetrahedron, "3", None, 2).unwrap_err();
    assert!(matches!(e, PatternError::Split { .. }), "{e}");
    let e = Pattern::parse(PatternCell::Tetrahedron, "2", None, 3).unwrap_err();
    assert!(matches!(e, PatternError::Degree(3)), "{e}");
    let e = Pattern::parse(PatternCell::Hexahedron, "3x3x3", Some(&"0".repeat(27)), 2).unwrap_err();
    assert!(matches!(e, PatternError::Empty), "{e}");
}

#[test]
fn solids_are_porous_by_their_volume() {
    let l = bcifs::render::lacunarity_report(&bcifs::builtin_design("menger").unwrap(), &[], 3).unwrap();
    assert_eq!(l.dimension, 3);
    for (k, p) in l.porosity.iter().enumerate() {
        assert!((p - (1.0 - (20.0f64 / 27.0).powi(k as i32 + 1))).abs() < 1e-12, "depth {}: {p}", k + 1);
    }
    // Λ(1) is one over the filled fraction, sampled in 81³ voxels (a sampling error of well under 1%).
    let expected = (27.0f64 / 20.0).powi(3);
    assert!((l.lacunarity[0][1] / expected - 1.0).abs() < 0.01, "{:?}", l.lacunarity);
    assert!((l.lacunarity.last().unwrap()[1] - 1.0).abs() < 1e-12);
    assert_eq!(bcifs::render::lacunarity_depth(&bcifs::builtin_design("menger").unwrap()), 4);
    // A depth whose cells would not fit memory is refused at once, before the shallower depths are made.
    let e = bcifs::render::lacunarity_report(&bcifs::builtin_design("menger").unwrap(), &[], 9).unwrap_err();
    assert!(e.to_string().contains("in-memory limit"), "{e}");
}

/// The similarity dimension of a solid's default member and Moran's open set
/// condition for it (issue 44, item 6): the Menger sponge's twenty maps of
/// ratio 1/3 give log 20 / log 3, Cantor dust's eight log 8 / log 3, the
/// Sierpiński tetrahedron's four of ratio 1/2 exactly 2, each the Hausdorff
/// dimension since the images of the cube (the tetrahedron) meet only on
/// their boundaries; a sponge of degree 3 (27 control points, not a simplex)
/// the same. The Jerusalem-like member's beams are not similarities: no
/// such dimension; the whole cube kept, 27 maps tiling it, gives 3.
#[test]
fn solids_have_their_moran_dimension_with_the_open_set_condition() {
    let moran = |design: &bcifs::Design| {
        let instance = bcifs::instantiate(design, &[]).unwrap();
        let model = design.model().unwrap();
        let ev = bcifs::eval::Evaluator::new(&instance.automaton, model, bcifs::eval::EvalSettings::default()).unwrap();
        let piece = &ev.pieces().pieces[0];
        let root = bcifs::petgraph::graph::NodeIndex::new(piece.state);
        let dim = ev.pieces().dim;
        let s = bcifs::analysis::similarity_dimension(&instance.automaton, root, &piece.control, dim)?;
        let osc = bcifs::analysis::open_set_condition(&instance.automaton, root, &piece.control, dim, s);
        Some((s, osc.holds))
    };
    let sponge3 =
        pattern_design(&Pattern::parse(PatternCell::Hexahedron, "3x3x3", Some(MENGER), 3).unwrap(), "m3").unwrap();
    for (design, expected) in [
        (bcifs::builtin_design("menger").unwrap(), 20f64.ln() / 3f64.ln()),
        (sponge3, 20f64.ln() / 3f64.ln()),
        (bcifs::builtin_design("cantor_dust").unwrap(), 8f64.ln() / 3f64.ln()),
        (bcifs::builtin_design("sierpinski_tetrahedron").unwrap(), 2.0),
    ] {
        let (s, holds) = moran(&design).unwrap_or_else(|| panic!("{}: no similarity dimension", design.name()));
        assert!((s - expected).abs() < 1e-9, "{}: {s}", design.name());
        assert_eq!(holds, Some(true), "{}", design.name());
    }
    assert_eq!(moran(&bcifs::builtin_design("jerusalem").unwrap()), None);
    let full = pattern_design(&Pattern::parse(PatternCell::Hexahedron, "3x3x3", None, 2).unwrap(), "cube").unwrap();
    let (s, holds) = moran(&full).unwrap();
    assert!((s - 3.0).abs() < 1e-9 && holds == Some(true), "{s} {holds:?}");
    // The dimension report coarsens a solid's resolution to its memory budget (it refused the
    // tetrahedron and the Jerusalem cube over 2.4 GiB, as a surface is not refused).
    let cancel = bcifs::Cancel::new();
    for name in ["sierpinski_tetrahedron", "jerusalem", "menger"] {
        let design = bcifs::builtin_design(name).unwrap();
        let report = bcifs::render::dimension_within(&design, &[], 64 << 20, &cancel);
        assert!(report.is_ok(), "{name}: {report:?}");
    }
}

/// Issue 45: a solid written for printing. The 3MF package holds the three
/// parts a slicer looks for, its model the mesh written (every vertex and
/// triangle, in millimetres); the print report measures the boundary mesh:
/// the sponge's volume (20/27)^k, area, box, one closed oriented piece of
/// the genus its voxels give, and no vertex inside the solid.
#[test]
fn solids_are_written_for_printing_with_their_print_report() {
    use std::io::Read;
    let menger = bcifs::builtin_design("menger").unwrap();
    let dir = std::env::temp_dir().join(format!("bcifs-print-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for k in 1..=3usize {
        let options = bcifs::render::Options::default().with_depth(k);
        let path = dir.join(format!("menger{k}.3mf"));
        let written = bcifs::render::render(&menger, &options, &path).unwrap();
        let r = bcifs::render::print_report(&menger, &options).unwrap();
        assert!((r.volume - (20f64 / 27.0).powi(k as i32)).abs() < 1e-12, "depth {k}: {}", r.volume);
        let (side, cubes) = voxels(MENGER, k as u32);
        let (_, betti) = cube_topology(side, &cubes);
        assert_eq!((r.closed, r.oriented, r.components, r.genus), (true, true, 1, Some(betti[1])), "depth {k}");
        assert_eq!(r.bbox, [[0.0; 3], [1.0; 3]]);
        // Every vertex written is on the boundary (a face uses it).
        assert_eq!((written.vertices, r.triangles), (r.vertices, 2 * written.faces));
        // The area: each unit-cube face of the voxels on the boundary, 1/3^k a side.
        let mut boundary = 0usize;
        for c in &cubes {
            for axis in 0..3 {
                for step in [-1i64, 1] {
                    let mut n = c.map(|x| x as i64);
                    n[axis] += step;
                    let inside = n.iter().all(|&x| (0..side as i64).contains(&x));
                    if !inside || !cubes.contains(&n.map(|x| x as usize)) {
                        boundary += 1;
                    }
                }
            }
        }
        assert!((r.area - boundary as f64 / 9f64.powi(k as i32)).abs() < 1e-9, "depth {k}: {}", r.area);
        // The package: a ZIP whose central directory names the content types, the relationships and
        // the model; the model (deflated) holds the vertices and triangles counted above.
        let bytes = std::fs::read(&path).unwrap();
        let end = bytes.len() - 22;
        assert_eq!(&bytes[end..end + 4], b"PK\x05\x06");
        assert_eq!(u16::from_le_bytes([bytes[end + 10], bytes[end + 11]]), 3);
        let find = |name: &str| bytes.windows(name.len()).position(|w| w == name.as_bytes());
        for name in ["[Content_Types].xml", "_rels/.rels", "3D/3dmodel.model"] {
            assert!(find(name).is_some(), "{name}");
        }
        // The model's data follows its local header's name.
        let at = find("3D/3dmodel.model").unwrap() + "3D/3dmodel.model".len();
        let mut model = String::new();
        flate2::read::DeflateDecoder::new(&bytes[at..]).read_to_string(&mut model).unwrap();
        assert!(model.contains("unit=\"millimeter\""));
        assert_eq!(model.matches("<vertex ").count(), r.vertices);
        assert_eq!(model.matches("<triangle ").count(), r.triangles);
    }
    // A curve has no print report, and no 3MF.
    let cantor = bcifs::builtin_design("cantor").unwrap();
    let options = bcifs::render::Options::default().with_depth(2);
    assert!(bcifs::render::print_report(&cantor, &options).is_err());
    let e = bcifs::render::render(&cantor, &options, &dir.join("cantor.3mf")).unwrap_err();
    assert!(e.to_string().contains("print file holds solids"), "{e}");
    assert!(!dir.join("cantor.3mf").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 45, item 2: cells that touch only at a point or along an edge are
/// written as shells that touch without sharing a vertex (the pinch split),
/// so that every print file is a 2-manifold: the Sierpiński tetrahedron's
/// 4^k cells are 4^k closed, oriented pieces of genus 0 with half the volume
/// at every depth; two cubes of a 2×2×2 split touching along an edge are two.
#[test]
fn pinches_are_split_so_that_solids_print_as_manifolds() {
    let tetra = bcifs::builtin_design("sierpinski_tetrahedron").unwrap();
    let whole = 2f64.sqrt() / 12.0; // the regular tetrahedron of side 1
    for k in 1..=3usize {
        let r = bcifs::render::print_report(&tetra, &bcifs::render::Options::default().with_depth(k)).unwrap();
        let cells = 4usize.pow(k as u32);
        assert_eq!((r.components, r.closed, r.oriented, r.genus), (cells, true, true, Some(0)), "depth {k}");
        assert_eq!(r.vertices, 4 * cells, "depth {k}: each cell's corners its own");
        assert!((r.volume - whole / 2f64.powi(k as i32)).abs() < 1e-12, "depth {k}");
        // The topology of the cells themselves is unchanged: they touch, one component.
        assert_eq!(topology_report(&tetra, &[], k).unwrap().components, 1);
    }
    // Cells (0,0,0) and (1,1,0) of a 2×2×2 split share an edge and nothing else.
    let edge =
        pattern_design(&Pattern::parse(PatternCell::Hexahedron, "2x2x2", Some("10010000"), 2).unwrap(), "e").unwrap();
    let r = bcifs::render::print_report(&edge, &bcifs::render::Options::default().with_depth(1)).unwrap();
    assert_eq!((r.components, r.closed, r.oriented, r.vertices, r.genus), (2, true, true, 16, Some(0)));
    assert!((r.volume - 0.25).abs() < 1e-12);
    // Without a pinch nothing is split: the sponge's boundary keeps its one piece.
    let menger = bcifs::builtin_design("menger").unwrap();
    let r = bcifs::render::print_report(&menger, &bcifs::render::Options::default().with_depth(2)).unwrap();
    assert_eq!((r.components, r.genus), (1, Some(81)));
}

/// Issue 45, item 3: a lace written as a closed shell of a given thickness.
/// The carpet on its curved patch at depth k thickened: one closed,
/// consistently oriented piece whose genus is the carpet's number of holes
/// ((8^k − 1)/7), its volume the thickness times the sheet's area to first
/// order; a thickness at or over the smallest cell, a pinched lace (the
/// gasket's corners) and a curve are refused before anything is written.
#[test]
fn laces_thicken_into_closed_shells_of_the_carpets_genus() {
    let carpet = bcifs::builtin_design("carpet").unwrap();
    let t = 0.004;
    for k in 1..=3usize {
        let options = bcifs::render::Options::default().with_depth(k);
        let sheet = bcifs::render::evaluate_design(&carpet, &options, &mut Vec::new()).unwrap();
        let area = bcifs::render::print_report_of(&sheet).area;
        let shell = bcifs::mesh::thicken(&sheet, t).unwrap();
        let r = bcifs::render::print_report_of(&shell);
        let holes = (8i64.pow(k as u32) - 1) / 7;
        assert_eq!((r.closed, r.oriented, r.components, r.genus), (true, true, 1, Some(holes)), "depth {k}");
        // The sheet bends gently: the shell's volume is t·area within t² times its extent.
        assert!((r.volume - t * area).abs() < 10.0 * t * t, "depth {k}: {} vs {}", r.volume, t * area);
        // Through the options: the same shell, to a file.
        let mut thick = options.clone();
        thick.file.thickness = Some(t);
        // Its figures; a print report says too what a slicer will not like (here: a print 1 mm across).
        let mut printed = bcifs::render::print_report(&carpet, &thick).unwrap();
        assert!(printed.warnings.iter().any(|w| w.contains("too small to slice")), "{:?}", printed.warnings);
        (printed.warnings, printed.bed_contact) = (r.warnings.clone(), r.bed_contact);
        assert_eq!(printed, r);
    }
    let sheet =
        bcifs::render::evaluate_design(&carpet, &bcifs::render::Options::default().with_depth(2), &mut Vec::new())
            .unwrap();
    assert!(matches!(bcifs::mesh::thicken(&sheet, 0.2), Err(bcifs::mesh::ThickenError::TooThick { .. })));
    assert!(matches!(bcifs::mesh::thicken(&sheet, -1.0), Err(bcifs::mesh::ThickenError::Thickness(_))));
    let gasket = bcifs::builtin_design("gasket_lace").unwrap();
    let g = bcifs::render::evaluate_design(&gasket, &bcifs::render::Options::default().with_depth(2), &mut Vec::new())
        .unwrap();
    assert!(matches!(bcifs::mesh::thicken(&g, 0.001), Err(bcifs::mesh::ThickenError::Pinched(_))));
    // A solid's boundary is closed: no hollow double wall is made of it.
    let menger = bcifs::builtin_design("menger").unwrap();
    let m = bcifs::render::evaluate_design(&menger, &bcifs::render::Options::default().with_depth(1), &mut Vec::new())
        .unwrap();
    assert!(matches!(bcifs::mesh::thicken(&m, 0.01), Err(bcifs::mesh::ThickenError::Closed)));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["render", "cantor", "--depth", "2", "--thickness", "0.01", "-o"])
        .arg(std::env::temp_dir().join(format!("bcifs-cantor-{}.stl", std::process::id())))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("only surfaces thicken"), "{err}");
}
