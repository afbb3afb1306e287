//! Contours as Bézier fractals (seed 002): the heart's printed matrices,
//! segments files and their errors, the automaton of a contour.

use bcifs::contour::{Segment, arc_ifs, chain, contour_design, parse_segments, write_segments};
use bcifs::schemes::RowMap;

/// Seed 002 §5: the eight printed matrices of the heart.
fn printed_heart() -> [(RowMap, RowMap); 4] {
    [
        (
            [[0.25, 0.5, 0.0], [0.0, 0.5, 0.0], [-0.75, 0.5, 1.0]],
            [[0.75, -0.5, 0.0], [0.25, 0.0, 0.0], [0.0, 0.0, 1.0]],
        ),
        (
            [[0.75, 0.5, 0.0], [-0.25, 0.0, 0.0], [0.0, 0.0, 1.0]],
            [[0.25, -0.5, 0.0], [0.0, 0.5, 0.0], [0.75, 0.5, 1.0]],
        ),
        (
            [[0.25, 0.0, 0.0], [0.0, 0.5, 0.0], [-0.75, 0.0, 1.0]],
            [[0.25, 0.0, 0.0], [-0.25, 0.5, 0.0], [-0.5, -1.0, 1.0]],
        ),
        ([[0.25, 0.0, 0.0], [0.25, 0.5, 0.0], [0.5, -1.0, 1.0]], [[0.25, 0.0, 0.0], [0.0, 0.5, 0.0], [0.75, 0.0, 1.0]]),
    ]
}

/// `[x y 1] F`.
fn apply(p: [f64; 2], f: &RowMap) -> [f64; 2] {
    [0, 1].map(|j| p[0] * f[0][j] + p[1] * f[1][j] + f[2][j])
}

/// The fixed point of an affine map of the plane: solves `x (I − A) = t`.
fn fixed(f: &RowMap) -> [f64; 2] {
    let (a, b, c, d) = (1.0 - f[0][0], -f[0][1], -f[1][0], 1.0 - f[1][1]);
    let det = a * d - b * c;
    [(f[2][0] * d - f[2][1] * c) / det, (a * f[2][1] - b * f[2][0]) / det]
}

/// The heart's arcs derived from the printed maps (P0 the fixed point of L,
/// P2 that of M, and P1 from `P2 L = (P0 + 2 P1 + P2)/4`), then the maps of
/// eq. 10 computed from those arcs: exactly the eight printed matrices.
#[test]
fn the_heart_gives_the_eight_printed_matrices() {
    for (k, (l, m)) in printed_heart().iter().enumerate() {
        let (p0, p2) = (fixed(l), fixed(m));
        let q = apply(p2, l);
        let p1 = [0, 1].map(|a| (4.0 * q[a] - p0[a] - p2[a]) / 2.0);
        let [lp, mp] = arc_ifs(p0, p1, p2).unwrap();
        for (ours, theirs) in [(lp, l), (mp, m)] {
            for i in 0..3 {
                for j in 0..3 {
                    assert!((ours[i][j] - theirs[i][j]).abs() < 1e-12, "arc {k}: {ours:?} vs {theirs:?}");
                }
            }
        }
    }
}

/// Each arc's two maps send the arc onto its halves: `L` maps `B(u)` to
/// `B(u/2)`, `M` to `B((1 + u)/2)` (de Casteljau), for arcs in every
/// quadrant; a line segment's maps halve it the same way.
#[test]
fn maps_send_pieces_onto_their_halves() {
    for p in [
        vec![[0.0, 0.0], [1.0, 2.0], [3.0, -1.0]],
        vec![[-2.0, 5.0], [-7.0, -3.0], [4.0, 4.0]],
        vec![[1.0, -1.0], [-3.0, -4.0]],
        vec![[0.0, 0.0], [-3.0, 4.0]],
    ] {
        let s = Segment { points: p };
        let [(_, f1), (_, f2)] = s.maps().unwrap();
        for u in [0.0, 0.3, 0.5, 0.9, 1.0] {
            let (a, b) = (apply(s.at(u), &f1), apply(s.at(u), &f2));
            let (ea, eb) = (s.at(u / 2.0), s.at((1.0 + u) / 2.0));
            assert!((a[0] - ea[0]).hypot(a[1] - ea[1]) < 1e-12 && (b[0] - eb[0]).hypot(b[1] - eb[1]) < 1e-12);
        }
    }
}

/// Segments files: read and written back; bad ones get `file:line:column`.
#[test]
fn segments_files_and_their_errors() {
    let text = "[[segment]]\npoints = [[-1, 0], [-1, 1], [0, 0]]\n[[segment]]\npoints = [[0, 0], [1.5, 0]]\n";
    let s = parse_segments(text, "s.toml").unwrap();
    assert_eq!(s.len(), 2);
    assert_eq!(parse_segments(&write_segments(&s), "again.toml").unwrap(), s);
    for (bad, at, what) in [
        ("[[segment]]\npoints = [[0, 0]]\n", "s.toml:2:10", "expected 2 points"),
        ("[[segment]]\npoints = [[0, 0], [1, 0], [2, 0], [3, 0]]\n", "s.toml:2:10", "not 4"),
        ("[[segment]]\npoints = [[0, 0], [1]]\n", "s.toml:2:19", "two finite numbers"),
        ("[[segment]]\npoints = [[0, 0], [0, 0]]\n", "s.toml:2:10", "two different points"),
        ("[[segment]]\npoint = [[0, 0], [1, 0]]\n", "s.toml:2:1", "unknown field"),
        ("", "s.toml:1:1", "at least one [[segment]]"),
    ] {
        let e = parse_segments(bad, "s.toml").unwrap_err().to_string();
        assert!(e.starts_with(at) && e.contains(what), "{bad:?}: {e}");
    }
}

/// The automaton of a contour: pieces chained in any order and direction
/// into one closed curve, `check` passes, and every vertex it draws at
/// depth 5 is a point of its piece at a dyadic parameter (to 1e-12);
/// collinear arc control points are drawn by the barycentric form though
/// eq. 10's maps do not exist; disjoint pieces are refused naming one.
#[test]
fn contour_automata_draw_their_pieces() {
    let heart = parse_segments(
        "[[segment]]\npoints = [[-1, 0], [-1, 1], [0, 0]]\n[[segment]]\npoints = [[0, 0], [1, 1], [1, 0]]\n\
         [[segment]]\npoints = [[-1, 0], [-1, -1], [0, -2]]\n[[segment]]\npoints = [[0, -2], [1, -1], [1, 0]]\n\
         [[segment]]\npoints = [[2, 5], [2, 6], [2, 8]]\n",
        "h.toml",
    )
    .unwrap();
    let e = contour_design("h", &heart).unwrap_err().to_string();
    assert!(e.contains("segment 4"), "{e}");
    let (pieces, closed) = chain(&heart[..4]).unwrap();
    assert!(closed && pieces.len() == 4);
    for w in pieces.windows(2) {
        assert_eq!(w[0].end(), w[1].start());
    }
    let collinear = Segment { points: vec![[1.0, 0.0], [1.0, -1.0], [1.0, -2.0]] };
    assert!(collinear.maps().unwrap_err().contains("collinear"));
    let mut with_line = heart[..4].to_vec();
    with_line[3] = Segment { points: vec![[0.0, -2.0], [1.0, 0.0]] };
    for set in [heart[..4].to_vec(), with_line] {
        let design = contour_design("c", &set).unwrap();
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let report = bcifs::analysis::check(&inst.automaton, &inst.values, 1e-12).unwrap();
        assert!(report.ok, "{report:?}");
        let shape = super::evaluate(&design, 5);
        let (pieces, _) = chain(&set).unwrap();
        for p in shape.points() {
            let on = pieces.iter().any(|s| {
                (0..=32).any(|j| {
                    let q = s.at(j as f64 / 32.0);
                    (q[0] - p[0]).hypot(q[1] - p[1]) < 1e-12
                })
            });
            assert!(on, "{p:?} is no dyadic point of a piece");
        }
    }
}
