//! Closed surfaces turned outward: the orientation of a mesh bcifs writes
//! comes from its geometry (the sign of the volume each closed piece
//! encloses), never from the order in which a member's matrices happen to
//! list a cell's corners.

/// Per face, whether to turn it (reverse its corners) so that every closed,
/// consistently oriented piece of the mesh encloses a positive volume. A
/// piece is the faces joined through shared vertices; it is closed and
/// consistently oriented when each of its edges is run once each way. Open
/// pieces, pieces run inconsistently and flat ones (no volume to speak of)
/// are left as they are.
///
/// `faces(f)` gives face `f`'s corners (vertex numbers below `vertices`),
/// `point(v)` vertex `v`'s position.
///
/// ```
/// // A tetrahedron listed inward: every face is turned.
/// let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let faces: [[usize; 3]; 4] = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
/// let turn = bcifs::geometry::inward_faces(4, faces.len(), |f| &faces[f][..], |v| p[v]);
/// assert_eq!(turn, [true; 4]);
/// ```
pub fn inward_faces<'a>(
    vertices: usize,
    count: usize,
    faces: impl Fn(usize) -> &'a [usize],
    point: impl Fn(usize) -> [f64; 3],
) -> Vec<bool> {
    let mut parent: Vec<usize> = (0..vertices).collect();
    let root = |parent: &mut [usize], mut v: usize| {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    };
    for f in 0..count {
        let c = faces(f);
        for w in c.windows(2) {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[1]));
            parent[a] = b;
        }
    }
    let piece: Vec<usize> =
        (0..count).map(|f| faces(f).first().map_or(usize::MAX, |&v| root(&mut parent, v))).collect();
    // Directed edges: a piece is closed and consistent when each is run once and its reverse once.
    let mut runs: rustc_hash::FxHashMap<(usize, usize), u32> = rustc_hash::FxHashMap::default();
    for f in 0..count {
        let c = faces(f);
        for k in 0..c.len() {
            *runs.entry((c[k], c[(k + 1) % c.len()])).or_insert(0) += 1;
        }
    }
    let mut good: rustc_hash::FxHashMap<usize, bool> = rustc_hash::FxHashMap::default();
    for (&(a, b), &n) in &runs {
        let ok = n == 1 && runs.get(&(b, a)) == Some(&1);
        let r = root(&mut parent, a);
        *good.entry(r).or_insert(true) &= ok;
    }
    // Each piece's volume about its first vertex (numerically kinder than about the origin).
    let mut volume: rustc_hash::FxHashMap<usize, (f64, f64, [f64; 3])> = rustc_hash::FxHashMap::default();
    for (f, &at) in piece.iter().enumerate() {
        let c = faces(f);
        if c.len() < 3 || !good.get(&at).copied().unwrap_or(false) {
            continue;
        }
        let (v, size, o) = volume.entry(at).or_insert((0.0, 0.0, point(c[0])));
        let at = |i: usize| {
            let p = point(c[i]);
            [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
        };
        let p0 = at(0);
        for i in 1..c.len() - 1 {
            let (a, b) = (at(i), at(i + 1));
            let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
            let t = p0[0] * cross[0] + p0[1] * cross[1] + p0[2] * cross[2];
            *v += t;
            *size += t.abs();
        }
    }
    (0..count)
        .map(|f| volume.get(&piece[f]).is_some_and(|&(v, size, _)| v < -crate::algebra::tolerance::DEGENERATE * size))
        .collect()
}
