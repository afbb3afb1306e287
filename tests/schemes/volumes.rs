//! Trivariate B-spline volumes as IFS (issue 45): the tensor product of three
//! cubic curve IFS, with a Menger mask or every part kept, projected by a
//! 4×4×4 control lattice. Their meshes are checked against the B-spline map
//! written here from its basis functions (not the library's matrices), and a
//! lattice that turns a cell inside out is refused.

use bcifs::render::{Options, print_report};
use bcifs::schemes::{Basis, Pattern, PatternCell, PatternError, ifs_preset, pattern_design};

/// The Menger sponge's mask.
const MENGER: &str = "111101111101000101111101111";

/// The uniform cubic B-spline's four basis functions on one segment.
fn basis(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ]
}

/// The tricubic B-spline map of the lattice `points` (index 16·w + 4·v + u) at `(u, v, w)`.
fn tricubic(points: &[Vec<f64>], at: [f64; 3]) -> [f64; 3] {
    let [bu, bv, bw] = at.map(basis);
    let mut out = [0.0; 3];
    for (i, p) in points.iter().enumerate() {
        let weight = bu[i % 4] * bv[i / 4 % 4] * bw[i / 16];
        for a in 0..3 {
            out[a] += weight * p[a];
        }
    }
    out
}

fn points(shape: &bcifs::geometry::Shape) -> Vec<[f64; 3]> {
    (0..shape.positions.len() / 3).map(|v| shape.point(v)).collect()
}

/// Whether every point of `a` has a point of `b` within `tol`, and the other way round.
fn same_points(a: &[[f64; 3]], b: &[[f64; 3]], tol: f64) -> bool {
    let near = |p: &[f64; 3], set: &[[f64; 3]]| set.iter().any(|q| (0..3).all(|x| (p[x] - q[x]).abs() <= tol));
    a.len() == b.len() && a.iter().all(|p| near(p, b)) && b.iter().all(|p| near(p, a))
}

/// On its default lattice (the Greville points of the unit cube) the cubic
/// B-spline map is the identity (linear precision): the smooth sponge is the
/// affine one, vertex for vertex, with its print report.
#[test]
fn the_bspline_sponge_on_the_greville_lattice_is_the_affine_sponge() {
    let pattern = Pattern::parse_in(PatternCell::Hexahedron, "3x3x3", Some(MENGER), 4, Basis::BSpline).unwrap();
    let smooth = pattern_design(&pattern, "smooth").unwrap();
    assert!(bcifs::solve(&smooth).unwrap().parameter_names().is_empty(), "the matrices are fixed");
    let menger = bcifs::render::load("menger").unwrap();
    for k in 1..=2 {
        let (a, b) = (crate::evaluate(&smooth, k), crate::evaluate(&menger, k));
        assert!(same_points(&points(&a), &points(&b), 1e-12), "depth {k}");
        assert_eq!((a.quads.len(), a.triangles.len()), (b.quads.len(), b.triangles.len()));
    }
    let options = Options::default().with_depth(3);
    let (a, b) = (print_report(&smooth, &options).unwrap(), print_report(&menger, &options).unwrap());
    assert_eq!((a.genus, a.components, a.triangles, a.vertices), (b.genus, b.components, b.triangles, b.vertices));
    assert!((a.volume - (20.0f64 / 27.0).powi(3)).abs() < 1e-12 && (a.area - b.area).abs() < 1e-10);
}

/// The twisted sponge's every vertex is the tricubic B-spline map (its basis
/// functions, written above) of the affine sponge's vertex at the same lattice
/// place: the IFS of the tensor product is the B-spline volume.
#[test]
fn the_tricubic_sponge_is_the_bspline_map_of_the_menger_sponge() {
    let sponge = ifs_preset("tricubic-sponge", None, None).unwrap();
    let lattice = sponge.model().unwrap().points.clone();
    let menger = bcifs::render::load("menger").unwrap();
    for k in 1..=2 {
        let mapped: Vec<[f64; 3]> =
            points(&crate::evaluate(&menger, k)).into_iter().map(|p| tricubic(&lattice, p)).collect();
        let shape = crate::evaluate(&sponge, k);
        assert!(same_points(&points(&shape), &mapped, 1e-12), "depth {k}");
    }
    // A whole volume: the bent bar keeps its volume (the map shears along z: Jacobian 1).
    let bar = ifs_preset("tricubic", None, None).unwrap();
    let r = print_report(&bar, &Options::default().with_depth(3)).unwrap();
    assert_eq!((r.genus, r.components, r.closed), (Some(0), 1, true));
    assert!((r.volume - 3.0).abs() < 1e-12, "{}", r.volume);
}

/// A lattice whose middle layers cross turns cells inside out: refused, with
/// the place; the same lattice mirrored (every cell turned alike) is a solid.
#[test]
fn a_lattice_that_folds_the_volume_is_refused() {
    let greville = |i: usize| i as f64 - 1.0;
    let lattice = |fold: bool, mirror: bool| -> Vec<Vec<f64>> {
        (0..64)
            .map(|i| {
                let (u, v, w) = (i % 4, i / 4 % 4, i / 16);
                // Swap the two middle layers along w: the map turns back on itself there.
                let w = if fold { [0, 2, 1, 3][w] } else { w };
                let x = if mirror { -greville(u) } else { greville(u) };
                vec![x, greville(v), greville(w) * 1.5]
            })
            .collect()
    };
    let folded = ifs_preset("tricubic-sponge", Some(lattice(true, false)), None).unwrap();
    let e = print_report(&folded, &Options::default().with_depth(2)).unwrap_err().to_string();
    assert!(e.contains("fold the solid inside out near") && e.contains("depth-2 cell"), "{e}");
    let mirrored = ifs_preset("tricubic-sponge", Some(lattice(false, true)), None).unwrap();
    let r = print_report(&mirrored, &Options::default().with_depth(2)).unwrap();
    assert!(r.closed && r.oriented && (r.volume - 1.5 * (20.0f64 / 27.0).powi(2)).abs() < 1e-12, "{r:?}");
}

#[test]
fn a_bspline_basis_is_for_hexahedra_at_uniform_points() {
    let quad = Pattern::parse_in(PatternCell::Quad, "3x3", None, 4, Basis::BSpline);
    assert!(matches!(quad, Err(PatternError::Basis(ref e)) if e.contains("bicubic")), "{quad:?}");
    let at = Pattern::parse_in(PatternCell::Hexahedron, "3x3x3", None, 4, Basis::BSpline).unwrap().with_at("2/5,3/5");
    assert!(matches!(at, Err(PatternError::Basis(ref e)) if e.contains("uniform")), "{at:?}");
    let big = Pattern::parse_in(PatternCell::Hexahedron, "9x9x9", None, 4, Basis::BSpline);
    assert!(matches!(big, Err(PatternError::Basis(ref e)) if e.contains("entries")), "{big:?}");
    // The pattern file says its basis, and reads back the same.
    let p = Pattern::parse_in(PatternCell::Hexahedron, "3x3x3", Some(MENGER), 3, Basis::BSpline).unwrap();
    let (back, name) = Pattern::from_toml(&p.to_toml("q"), "q.toml").unwrap();
    assert_eq!((back, name.as_str()), (p, "q"));
    // A quadratic B-spline sponge: two layers across a side, the same topology as the affine one.
    let q = pattern_design(
        &Pattern::parse_in(PatternCell::Hexahedron, "3x3x3", Some(MENGER), 3, Basis::BSpline).unwrap(),
        "q",
    )
    .unwrap();
    let r = print_report(&q, &Options::default().with_depth(2)).unwrap();
    assert_eq!((r.genus, r.components), (Some(81), 1));
    assert!((r.volume - (20.0f64 / 27.0).powi(2)).abs() < 1e-12);
}

/// The print report's smallest wall and hole: the sponge's thinnest walls and
/// narrowest tunnels are one depth-k cell, 3^−k (its first tunnel is 1/3
/// wide, its outer shell a cell thick); the arch has no hole, and its walls,
/// a unit bar sheared along z, are thinner than 1 where it is steep; the
/// carpet's shell is as thick as asked, within the bend of its patch.
#[test]
fn the_print_report_measures_the_smallest_wall_and_hole() {
    let menger = bcifs::render::load("menger").unwrap();
    for k in 1..=3 {
        let r = print_report(&menger, &Options::default().with_depth(k)).unwrap();
        let cell = 3f64.powi(-(k as i32));
        assert!((r.smallest_wall.unwrap() - cell).abs() < 1e-12, "depth {k}: {:?}", r.smallest_wall);
        assert!((r.smallest_hole.unwrap() - cell).abs() < 1e-12, "depth {k}: {:?}", r.smallest_hole);
        let at = r.smallest_wall_at.unwrap();
        assert!(at.iter().all(|x| (-1e-12..=1.0 + 1e-12).contains(x)), "{at:?}");
    }
    let bar = ifs_preset("tricubic", None, None).unwrap();
    let r = print_report(&bar, &Options::default().with_depth(2)).unwrap();
    assert_eq!(r.smallest_hole, None);
    assert!(r.smallest_wall.unwrap() > 0.05 && r.smallest_wall.unwrap() < 1.0, "{:?}", r.smallest_wall);
    let carpet = bcifs::render::load("carpet").unwrap();
    let mut thick = Options::default().with_depth(2);
    thick.file.thickness = Some(0.01);
    let shell = print_report(&carpet, &thick).unwrap();
    let wall = shell.smallest_wall.unwrap();
    assert!((wall - 0.01).abs() < 1e-4, "{wall}");
    // An open sheet has no wall to measure.
    let sheet = print_report(&carpet, &Options::default().with_depth(2)).unwrap();
    assert_eq!((sheet.smallest_wall, sheet.smallest_hole), (None, None));
}

/// A lattice of n × n × n points makes (n − 3)³ cells welded where they
/// meet: on the 5 × 5 × 5 Greville lattice, eight sponges filling [0, 2]³,
/// one closed piece of eight sponges' volume, whose genus is the one counted
/// on their voxels (not by the library); a folding one and a lattice that is
/// no cube are refused.
#[test]
fn a_larger_lattice_welds_its_cells() {
    let greville = |n: usize| -> Vec<Vec<f64>> {
        (0..n * n * n).map(|i| vec![(i % n) as f64 - 1.0, (i / n % n) as f64 - 1.0, (i / n / n) as f64 - 1.0]).collect()
    };
    let sponges = ifs_preset("tricubic-sponge", Some(greville(5)), None).unwrap();
    let r = print_report(&sponges, &Options::default().with_depth(2)).unwrap();
    assert!(r.closed && r.oriented && r.components == 1, "{r:?}");
    assert!((r.volume - 8.0 * (20.0f64 / 27.0).powi(2)).abs() < 1e-10, "{}", r.volume);
    // The voxels of eight depth-2 sponges side by side.
    let (_, one) = crate::solids::voxels(MENGER, 2);
    let mut cubes = std::collections::HashSet::new();
    for [x, y, z] in one {
        for o in 0..8 {
            cubes.insert([x + 9 * (o & 1), y + 9 * (o >> 1 & 1), z + 9 * (o >> 2)]);
        }
    }
    let (_, betti) = crate::solids::cube_topology(18, &cubes);
    assert_eq!(r.genus, Some(betti[1]));
    // Two middle layers crossed: the cells there are turned over, refused as with one cell.
    let mut folded = greville(5);
    for p in folded.iter_mut() {
        p[2] = [0.0, 1.5, 0.5, 2.0, 3.0][(p[2] + 1.0) as usize] - 1.0;
    }
    let folded = ifs_preset("tricubic-sponge", Some(folded), None).unwrap();
    let e = print_report(&folded, &Options::default().with_depth(2)).unwrap_err().to_string();
    assert!(e.contains("fold the solid inside out"), "{e}");
    let e = ifs_preset("tricubic", Some(greville(5)[..100].to_vec()), None).unwrap_err().to_string();
    assert!(e.contains("n × n × n"), "{e}");
}
