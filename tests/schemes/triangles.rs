//! The triangle schemes as IFS (Schaefer et al. 2005 §3.2–3.3): every point of the
//! attractor is a point of the limit surface of Loop's (box-spline) or
//! Kobbelt's √3 subdivision of the same control points, computed by the
//! mesh subdivision (itself checked against CGAL in the mesh tests).

use bcifs::mesh::{PolyMesh, Scheme};
use bcifs::schemes::{
    Axial, LatticeIfs, LatticeScheme, hexagon_parts, ifs_preset, lattice_ifs, lattice_triangles, parallelogram_parts,
    ternary_triangle_parts, to_f64,
};
use nalgebra::{DMatrix, DVector};

/// Heights from a fixed linear congruential sequence in [-1, 1].
fn heights(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        })
        .collect()
}

fn xy((i, j): Axial) -> [f64; 2] {
    [i as f64 + 0.5 * j as f64, j as f64 * 3f64.sqrt() / 2.0]
}

/// The lattice inside the hexagon of radius `r`, lifted by random heights:
/// a triangle mesh, and the height of each lattice point.
fn lattice_mesh(r: i64, seed: u64) -> (PolyMesh, std::collections::HashMap<Axial, [f64; 3]>) {
    let points: Vec<Axial> = (-r..=r)
        .flat_map(|i| (-r..=r).map(move |j| (i, j)))
        .filter(|&(i, j)| i.abs().max(j.abs()).max((i + j).abs()) <= r)
        .collect();
    let z = heights(points.len(), seed);
    let positions: Vec<[f64; 3]> = points.iter().zip(&z).map(|(&p, &h)| [xy(p)[0], xy(p)[1], h]).collect();
    let mesh = PolyMesh::new(positions.clone(), lattice_triangles(&points)).expect("a valid lattice mesh");
    (mesh, points.into_iter().zip(positions).collect())
}

/// The points `vᵀ S_{w_k} ⋯ S_{w_1} C` of the IFS for every word `w` of
/// length `depth` and every fixed point `v` of the maps `fixed`: points of
/// the attractor, exactly.
fn attractor_points(ifs: &LatticeIfs, control: &DMatrix<f64>, depth: usize, fixed: &[usize]) -> Vec<[f64; 3]> {
    let blocks: Vec<DMatrix<f64>> = ifs.blocks.iter().map(to_f64).collect();
    let n = control.nrows();
    let fixed_points: Vec<DVector<f64>> = fixed
        .iter()
        .map(|&j| {
            let t = blocks[j].transpose();
            let mut v = DVector::from_element(n, 1.0 / n as f64);
            for _ in 0..400 {
                v = &t * v;
            }
            v
        })
        .collect();
    let mut nets = vec![control.clone()];
    for _ in 0..depth {
        nets = nets.iter().flat_map(|c| blocks.iter().map(move |s| s * c)).collect();
    }
    nets.iter()
        .flat_map(|c| fixed_points.iter().map(move |v| (v.transpose() * c).transpose()))
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// The largest distance from an attractor point to the limit vertex below it
/// (the limit vertices of the mesh after `steps` steps).
fn worst_distance(points: &[[f64; 3]], mesh: &PolyMesh, scheme: Scheme, steps: usize) -> f64 {
    let limit = mesh.limit(scheme, steps).unwrap().points();
    points
        .iter()
        .map(|p| {
            let below = limit
                .iter()
                .min_by(|a, b| {
                    let d = |q: &&[f64; 3]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
                    d(a).total_cmp(&d(b))
                })
                .unwrap();
            (0..3).map(|a| (below[a] - p[a]).powi(2)).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max)
}

fn control_of(ifs: &LatticeIfs, lattice: &std::collections::HashMap<Axial, [f64; 3]>) -> DMatrix<f64> {
    DMatrix::from_fn(ifs.control.len(), 3, |k, a| lattice[&ifs.control[k]][a])
}

/// Fig. 7: the six-map box-spline IFS on 19 control points. Its fixed
/// points and their images under all words of length 3 (1296 points, on the
/// lattice of level 3) are Loop limit points of the same control points,
/// to 1e-12 (products of 4 dyadic matrices: rounding ~1e-15); the heights
/// outside the two rings are random and do not matter.
#[test]
fn box_spline_attractor_is_the_loop_limit_surface() {
    let ifs = lattice_ifs(LatticeScheme::BoxSpline, &hexagon_parts(), &[(0, 0)]).unwrap();
    assert_eq!(ifs.control.len(), 19);
    for seed in [1, 2] {
        let (mesh, lattice) = lattice_mesh(7, seed);
        let points = attractor_points(&ifs, &control_of(&ifs, &lattice), 3, &[0, 1, 2, 3, 4, 5]);
        assert_eq!(points.len(), 6usize.pow(4));
        let worst = worst_distance(&points, &mesh, Scheme::Loop, 3);
        assert!(worst < 1e-12, "seed {seed}: {worst:e}");
    }
}

/// The four-map split (parallelogram, 14 control points) lies on the same
/// Loop surface: its corners' fixed points under words of length 3.
#[test]
fn box_spline_quad_attractor_is_the_loop_limit_surface() {
    let corners = [(0, 0), (1, 0), (0, 1), (1, 1)];
    let ifs = lattice_ifs(LatticeScheme::BoxSpline, &parallelogram_parts(), &corners).unwrap();
    assert_eq!(ifs.control.len(), 14);
    let (mesh, lattice) = lattice_mesh(7, 3);
    let points = attractor_points(&ifs, &control_of(&ifs, &lattice), 3, &[0, 1, 2, 3]);
    let worst = worst_distance(&points, &mesh, Scheme::Loop, 3);
    assert!(worst < 1e-12, "{worst:e}");
}

/// Fig. 8: the nine maps of √3's ternary split of a triangle (27 control
/// points). The fixed points of the three corner maps under all words of
/// length 2 are √3 limit points after 4 mesh steps (2 ternary rounds), to
/// 1e-12; the mesh's radius keeps its border rule away from the triangle.
#[test]
fn sqrt3_attractor_is_the_sqrt3_limit_surface() {
    let ifs = lattice_ifs(LatticeScheme::Sqrt3, &ternary_triangle_parts(), &[(0, 0), (1, 0), (0, 1)]).unwrap();
    assert_eq!(ifs.control.len(), 27);
    let (mesh, lattice) = lattice_mesh(8, 4);
    // Maps 0, 2 and 5 are the corner triangles: their fixed points are the corners.
    let points = attractor_points(&ifs, &control_of(&ifs, &lattice), 2, &[0, 2, 5]);
    let worst = worst_distance(&points, &mesh, Scheme::Sqrt3, 4);
    assert!(worst < 1e-12, "{worst:e}");
}

/// Fig. 9: leaving two maps out (G ⊂ F ⇒ G∞ ⊆ F∞) keeps the surface and
/// misses parts of it: the gasket's depth-5 mesh is made of triangles of
/// the box-spline's (every vertex one of its vertices, to rounding), and
/// under half of them.
#[test]
fn box_spline_gasket_is_a_subset_that_misses_parts() {
    let full = ifs_preset("box-spline", None, None).unwrap();
    let gasket = ifs_preset("box-spline-gasket", None, None).unwrap();
    let (f, g) = (super::evaluate(&full, 5), super::evaluate(&gasket, 5));
    assert_eq!(f.triangles.len(), 6 * 4usize.pow(5));
    let off = crate::hausdorff::directed_hausdorff(&g.points(), &f.points());
    assert!(off < 1e-12, "every gasket vertex is a vertex of the patch: {off:e}");
    let ratio = g.triangles.len() as f64 / f.triangles.len() as f64;
    assert!(ratio < 0.5 && ratio > 0.0, "the gasket keeps {ratio} of the patch's triangles");
}

/// The triangle patches render as surfaces (issue 25): at depth `k` the
/// cell's lattice triangles, mapped by every word of length `k` and
/// welded, make the fine lattice's triangles over the cell once each (the
/// hexagon's overlapping sub-hexagons give some twice: kept once): a disk
/// (V − E + F = 1, every edge in one or two triangles, oriented alike) of
/// `3R(R + 1) + 1` vertices and `6R²` triangles for the hexagon of radius
/// `R = 2^k`, `(R + 1)²` and `2R²` for the parallelogram, `(R + 1)(R + 2)/2`
/// and `R²` for √3's triangle (`R = 3^k`). Every vertex is a limit point of
/// Loop's or √3's subdivision of the same control points (on a wider lifted
/// lattice, so that border rules stay away), to 1e-12.
#[test]
fn triangle_patches_are_welded_meshes_of_the_limit_surface() {
    type Counts = fn(usize) -> (usize, usize);
    let cases: [(&str, Scheme, usize, Counts); 3] = [
        ("box-spline", Scheme::Loop, 3, |r| (3 * r * (r + 1) + 1, 6 * r * r)),
        ("box-spline-quad", Scheme::Loop, 3, |r| ((r + 1) * (r + 1), 2 * r * r)),
        ("sqrt3-patch", Scheme::Sqrt3, 2, |r| ((r + 1) * (r + 2) / 2, r * r)),
    ];
    for (name, scheme, k, counts) in cases {
        let plain = ifs_preset(name, None, None).unwrap();
        let order: Vec<Axial> = plain
            .model()
            .unwrap()
            .points
            .iter()
            .map(|p| {
                let j = (p[1] / (3f64.sqrt() / 2.0)).round();
                ((p[0] - 0.5 * j).round() as i64, j as i64)
            })
            .collect();
        let (mesh, lattice) = lattice_mesh(8, 5);
        let points = order.iter().map(|a| lattice[a].to_vec()).collect();
        let design = ifs_preset(name, Some(points), None).unwrap();
        let shape = super::evaluate(&design, k);
        let r = if scheme == Scheme::Sqrt3 { 3usize.pow(k as u32) } else { 1 << k };
        assert_eq!((shape.vertex_count(), shape.triangles.len()), counts(r), "{name}");
        let mut edges = std::collections::HashMap::new();
        for t in &shape.triangles {
            for i in 0..3 {
                *edges.entry((t[i], t[(i + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 1), "{name}: each directed edge once (oriented alike)");
        let undirected: std::collections::HashSet<_> = edges.keys().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        let euler = shape.vertex_count() as i64 - undirected.len() as i64 + shape.triangles.len() as i64;
        assert_eq!(euler, 1, "{name}: a disk");
        let steps = if scheme == Scheme::Sqrt3 { 2 * k } else { k };
        let worst = worst_distance(&shape.points(), &mesh, scheme, steps);
        assert!(worst < 1e-12, "{name}: {worst:e}");
    }
}

/// `render NAME --control` draws the lattice's triangles between the
/// control points: 24 for the hexagon of two rings, every control point used.
#[test]
fn triangle_presets_have_a_triangle_control_net() {
    for (name, points) in [("box-spline", 19), ("box-spline-quad", 14), ("sqrt3-patch", 27)] {
        let design = ifs_preset(name, None, None).unwrap();
        let model = design.model().unwrap();
        assert_eq!(model.points.len(), points, "{name}");
        let used: std::collections::HashSet<usize> = model.net.iter().flatten().copied().collect();
        assert_eq!(used.len(), points, "{name}");
        assert!(model.net.iter().all(|f| f.len() == 3));
    }
    assert_eq!(ifs_preset("box-spline", None, None).unwrap().model().unwrap().net.len(), 24);
}

/// The chaos game's default probabilities: the sub-patches of a lattice
/// cell are congruent, so each gets the same weight (the product of the
/// four largest eigenvalue moduli in R³: 1 · 1/2 · 1/2 · 1/4 for Loop,
/// 1 · 1/3 · 1/3 · 1/9 for √3), while an affine map on d + 1 points keeps
/// its `|det|`.
#[test]
fn congruent_sub_patches_are_drawn_equally_often() {
    for (scheme, parts, corners, ratio) in [
        (LatticeScheme::BoxSpline, hexagon_parts(), vec![(0, 0)], 1.0 / 16.0),
        (LatticeScheme::BoxSpline, parallelogram_parts(), vec![(0, 0), (1, 0), (0, 1), (1, 1)], 1.0 / 16.0),
        (LatticeScheme::Sqrt3, ternary_triangle_parts(), vec![(0, 0), (1, 0), (0, 1)], 1.0 / 81.0),
    ] {
        let ifs = lattice_ifs(scheme, &parts, &corners).unwrap();
        let blocks: Vec<DMatrix<f64>> = ifs.blocks.iter().map(|b| to_f64(b).transpose()).collect();
        let w = bcifs::eval::det_weights(&blocks.iter().collect::<Vec<_>>(), 3);
        assert!(w.iter().all(|x| (x - ratio).abs() < 1e-9 * ratio), "{scheme:?}: {w:?}");
    }
    let half = DMatrix::from_row_slice(3, 3, &[0.5, 0.0, 0.0, 0.0, 0.5, 0.0, 0.5, 0.5, 1.0]);
    assert!((bcifs::eval::det_weights(&[&half], 2)[0] - 0.25).abs() < 1e-15);
}
