//! Quad patches: the biquadratic B-spline, welding, the torus.

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::geometry::Shape;

use super::{eval, load};

fn quad_bspline(t: f64) -> [f64; 3] {
    [(1.0 - t).powi(2) / 2.0, 0.5 + t - t * t, t * t / 2.0]
}

/// DESIGN §2: at (9/16, 3/16, 3/16) the patch is the biquadratic B-spline
/// surface. Each quad corner carries its natural parameters (u, v) as
/// texture coordinates; every quad lies on the tensor-product B-spline of
/// exactly one patch's 3×3 window at those parameters (within 1e-12), and
/// every patch has its 2^k × 2^k quads.
#[test]
fn classic_doo_sabin_is_the_biquadratic_bspline() {
    let (_, model, _) = load("doo_sabin_quad", &[]);
    let k = 5;
    let shape = eval(
        "doo_sabin_quad",
        &[("alpha", 0.5625), ("beta", 0.1875), ("gamma", 0.1875)],
        EvalSettings::default().with_depth(k).with_uv(),
    );
    let (rows, cols) = model.grid.unwrap();
    let (pr, pc) = (rows - 2, cols - 2);
    assert_eq!(shape.quads.len(), pr * pc * (1 << (2 * k)));
    let (nu, nv) = (pc << k, pr << k);
    assert_eq!(shape.uvs.len(), (nu + 1) * (nv + 1) * 2, "one parameterization of the whole sheet");
    // The patch of a quad: its texture quad gives (u, v) over the sheet; in patch
    // (i, j) that is (u·pc − j, v·pr − i), and exactly one patch's B-spline puts
    // those parameters at the quad's corners.
    let bspline = |i: usize, j: usize, u: f64, v: f64| -> [f64; 3] {
        let (wu, wv) = (quad_bspline(u), quad_bspline(v));
        std::array::from_fn(|a| {
            (0..3)
                .flat_map(|r| (0..3).map(move |s| (r, s)))
                .map(|(r, s)| wv[r] * wu[s] * model.points[(i + r) * cols + (j + s)][a])
                .sum()
        })
    };
    let mut per_patch = vec![0usize; pr * pc];
    for (q, t) in shape.quads.iter().zip(&shape.quad_uvs) {
        let (q, t) = (q.map(|x| x as usize), t.map(|x| x as usize));
        let matches: Vec<usize> = (0..pr * pc)
            .filter(|&patch| {
                (0..4).all(|c| {
                    let (i, j) = (patch / pc, patch % pc);
                    let (u, v) =
                        (shape.uvs[2 * t[c]] * pc as f64 - j as f64, shape.uvs[2 * t[c] + 1] * pr as f64 - i as f64);
                    let inside = (-1e-12..=1.0 + 1e-12).contains(&u) && (-1e-12..=1.0 + 1e-12).contains(&v);
                    let (p, e) = (shape.point(q[c]), bspline(i, j, u, v));
                    inside && (0..3).all(|a| (p[a] - e[a]).abs() < 1e-12)
                })
            })
            .collect();
        assert_eq!(matches.len(), 1, "quad {q:?}: on the B-spline of patches {matches:?}");
        per_patch[matches[0]] += 1;
    }
    assert!(per_patch.iter().all(|&n| n == 1 << (2 * k)), "{per_patch:?}");
}

fn check_manifold(shape: &Shape, boundary_edges: usize) {
    let edges = shape.edge_multiplicities();
    assert!(edges.values().all(|&m| m == 1 || m == 2), "an edge in more than two faces");
    assert_eq!(edges.values().filter(|&&m| m == 1).count(), boundary_edges);
    // Every quad has 4 distinct vertices.
    assert!(shape.quads.iter().all(|q| (0..4).all(|i| (i + 1..4).all(|j| q[i] != q[j]))));
}

/// The torus of doo_sabin_torus.toml is a closed 2-manifold: every edge in
/// exactly two faces, Euler characteristic 0, and no vertex unused.
#[test]
fn torus_is_a_closed_manifold() {
    for k in [1, 3, 6] {
        let shape = eval("doo_sabin_torus", &[], EvalSettings::default().with_depth(k));
        let quads = 64 << (2 * k);
        assert_eq!(shape.quads.len(), quads);
        assert_eq!(shape.vertex_count(), quads, "V = F on a torus of quads");
        check_manifold(&shape, 0);
        assert_eq!(shape.euler_characteristic(), 0);
        assert_eq!(shape.normals.len(), 3 * shape.vertex_count());
    }
}

/// The open sheet is a disc: one boundary loop, Euler characteristic 1, and
/// neighbouring patches share boundary vertices (welded by index).
#[test]
fn open_sheet_is_a_welded_disc() {
    let k = 4;
    let shape =
        eval("doo_sabin_quad", &[("alpha", 0.6), ("beta", 0.1), ("gamma", 0.2)], EvalSettings::default().with_depth(k));
    let side = 3 << k;
    check_manifold(&shape, 4 * side);
    assert_eq!(shape.euler_characteristic(), 1);
    assert_eq!(shape.vertex_count(), (side + 1) * (side + 1));
}

/// At any admissible parameters the two patches along a shared boundary
/// compute the same points (adjacency constraints): evaluating every patch
/// on its own gives boundary points that agree within 1e-12.
#[test]
fn neighbouring_patches_agree_on_their_boundary() {
    let (a, model, _) = load("doo_sabin_quad", &[("alpha", 0.7), ("beta", 0.05), ("gamma", 0.2)]);
    let cols = model.grid.unwrap().1;
    let k = 3;
    let patch = |i: usize, j: usize| {
        let mut m = model.clone();
        m.layout = bcifs::Layout::Single;
        m.grid = None;
        m.points = (0..9).map(|q| model.points[(i + q / 3) * cols + j + q % 3].clone()).collect();
        let s = Evaluator::new(&a, &m, EvalSettings::default().with_depth(k).with_uv()).unwrap().evaluate().unwrap();
        let n = 1 << k;
        // Corner positions by natural parameters.
        let mut grid = vec![[0.0; 3]; (n + 1) * (n + 1)];
        for (q, t) in s.quads.iter().zip(&s.quad_uvs) {
            for c in 0..4 {
                grid[t[c] as usize] = s.point(q[c] as usize);
            }
        }
        grid
    };
    let n = 1 << k;
    let (left, right) = (patch(0, 0), patch(0, 1));
    for v in 0..=n {
        let (p, q) = (left[v * (n + 1) + n], right[v * (n + 1)]);
        assert!((0..3).all(|a| (p[a] - q[a]).abs() < 1e-12), "v = {v}: {p:?} vs {q:?}");
    }
    let (below, above) = (patch(0, 0), patch(1, 0));
    for u in 0..=n {
        let (p, q) = (below[n * (n + 1) + u], above[u]);
        assert!((0..3).all(|a| (p[a] - q[a]).abs() < 1e-12), "u = {u}: {p:?} vs {q:?}");
    }
}

/// Re-evaluating into the same shape gives the same mesh (buffers reused).
#[test]
fn evaluate_into_reuses_and_matches() {
    let (a, model, _) = super::load("doo_sabin_torus", &[]);
    let ev = bcifs::eval::Evaluator::new(&a, &model, bcifs::eval::EvalSettings::default().with_depth(3)).unwrap();
    let fresh = ev.evaluate().unwrap();
    let mut shape = ev.evaluate().unwrap();
    let before = shape.positions.as_ptr();
    ev.evaluate_into(&mut shape).unwrap();
    assert_eq!(shape, fresh);
    assert_eq!(shape.positions.as_ptr(), before, "the position buffer is reused");
}

/// The fraction of quad corners whose vertex normal points against the
/// corner's own face normal (`(next − corner) × (previous − corner)`) or
/// against a triangle holding the corner in either split of the quad into
/// two triangles (as trimesh and renderers split it); degenerate triangles
/// (no area) are not counted.
fn flipped_corner_fraction(shape: &Shape) -> f64 {
    let v = |i: u32| nalgebra::Vector3::from(shape.point(i as usize));
    let n = |i: u32| nalgebra::Vector3::from_column_slice(&shape.normals[3 * i as usize..3 * i as usize + 3]);
    let (mut against, mut corners) = (0usize, 0usize);
    for q in &shape.quads {
        let face = (v(q[2]) - v(q[0])).cross(&(v(q[3]) - v(q[1])));
        for k in 0..4 {
            let at = |i: usize| v(q[(k + i) % 4]);
            let tri = |a: nalgebra::Vector3<f64>, b: nalgebra::Vector3<f64>, c: nalgebra::Vector3<f64>| {
                (b - a).cross(&(c - a))
            };
            let normals = [face, tri(at(3), at(0), at(1)), tri(at(0), at(1), at(2)), tri(at(0), at(2), at(3))];
            for f in normals.into_iter().filter(|f| f.norm() > 1e-14) {
                corners += 1;
                against += (f.dot(&n(q[k])) < 0.0) as usize;
            }
        }
    }
    against as f64 / corners as f64
}

/// Issue 15, item 5: vertex normals are the sums of the area vectors of the
/// quads around each vertex (across block, patch and torus seams), so no
/// corner of the shipped surfaces, nor of the rough ternary 5-point sheet at
/// ω = 3/50 (the default: a fractal sheet, where one-sided differences
/// flipped 9 % of them and the plain area-weighted sum still 4 %), nor at
/// ω = 1/50 (smooth) and 1/12 (rougher), has a normal pointing against its
/// face's area vector or a triangle of either split of it; and they are unit vectors.
#[test]
fn vertex_normals_agree_with_their_faces() {
    let mut shapes = vec![
        ("doo_sabin_quad".to_string(), eval("doo_sabin_quad", &[], EvalSettings::default().with_depth(6))),
        ("doo_sabin_torus".to_string(), eval("doo_sabin_torus", &[], EvalSettings::default().with_depth(6))),
    ];
    for name in ["ternary5-surface", "ternary5-torus"] {
        for omega in [None, Some(bcifs::algebra::Surd::frac(1, 50)), Some(bcifs::algebra::Surd::frac(1, 12))] {
            let design = bcifs::schemes::ifs_preset(name, None, omega.as_ref()).unwrap();
            let a = bcifs::instantiate(&design, &[]).unwrap().automaton;
            let settings = EvalSettings::default().with_depth(4).with_force();
            let ev = Evaluator::new(&a, design.model().unwrap(), settings).unwrap();
            shapes.push((format!("{name} ω={omega:?}"), ev.evaluate().unwrap()));
        }
    }
    // Issue 23, item 3: the default sheet (ω = 3/50) at depth 5, where 584 normals of 532,900
    // pointed against a triangle of their quads' splits.
    let design = bcifs::schemes::ifs_preset("ternary5-surface", None, None).unwrap();
    let a = bcifs::instantiate(&design, &[]).unwrap().automaton;
    let settings = EvalSettings::default().with_depth(5).with_force();
    let ev = Evaluator::new(&a, design.model().unwrap(), settings).unwrap();
    shapes.push(("ternary5-surface depth 5".to_string(), ev.evaluate().unwrap()));
    for (name, shape) in &shapes {
        assert_eq!(shape.normals.len(), shape.vertex_count() * 3, "{name}");
        for n in shape.normals.chunks(3) {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-12, "{name}: normal of length {len}");
        }
        let flipped = flipped_corner_fraction(shape);
        assert_eq!(flipped, 0.0, "{name}: {flipped} of the corners point against their face");
    }
}
