//! Nearest points: a k-d tree over a fixed set of points in space.

/// A k-d tree over points of space (coordinates `[x, y, z]`; a plane's
/// points have `z = 0`), answering which point is nearest to a query.
pub(crate) struct KdTree {
    points: Vec<[f64; 3]>,
    /// The points' indices, arranged so that each subrange's median splits it.
    order: Vec<u32>,
}

impl KdTree {
    pub(crate) fn new(points: Vec<[f64; 3]>) -> KdTree {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        build(&points, &mut order, 0);
        KdTree { points, order }
    }

    /// The points, as given.
    pub(crate) fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// The index of the point nearest to `q` and its squared distance
    /// (`None` for an empty tree).
    pub(crate) fn nearest(&self, q: [f64; 3]) -> Option<(usize, f64)> {
        let mut best = (usize::MAX, f64::INFINITY);
        self.search(&self.order, 0, q, &mut best);
        (best.0 != usize::MAX).then_some(best)
    }

    /// The indices of the `k` points nearest to `q`, nearest first.
    pub(crate) fn nearest_k(&self, q: [f64; 3], k: usize) -> Vec<usize> {
        let mut best: Vec<(f64, usize)> = Vec::with_capacity(k + 1);
        self.search_k(&self.order, 0, q, k, &mut best);
        best.into_iter().map(|(_, i)| i).collect()
    }

    fn search_k(&self, order: &[u32], axis: usize, q: [f64; 3], k: usize, best: &mut Vec<(f64, usize)>) {
        if order.is_empty() || k == 0 {
            return;
        }
        let mid = order.len() / 2;
        let i = order[mid] as usize;
        let p = self.points[i];
        let d2 = (0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>();
        if best.len() < k || d2 < best[best.len() - 1].0 {
            let at = best.partition_point(|b| b.0 <= d2);
            best.insert(at, (d2, i));
            best.truncate(k);
        }
        let delta = q[axis] - p[axis];
        let (near, far) =
            if delta < 0.0 { (&order[..mid], &order[mid + 1..]) } else { (&order[mid + 1..], &order[..mid]) };
        let next = (axis + 1) % 3;
        self.search_k(near, next, q, k, best);
        if best.len() < k || delta * delta < best[best.len() - 1].0 {
            self.search_k(far, next, q, k, best);
        }
    }

    fn search(&self, order: &[u32], axis: usize, q: [f64; 3], best: &mut (usize, f64)) {
        if order.is_empty() {
            return;
        }
        let mid = order.len() / 2;
        let i = order[mid] as usize;
        let p = self.points[i];
        let d2 = (0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>();
        if d2 < best.1 {
            *best = (i, d2);
        }
        let delta = q[axis] - p[axis];
        let (near, far) =
            if delta < 0.0 { (&order[..mid], &order[mid + 1..]) } else { (&order[mid + 1..], &order[..mid]) };
        let next = (axis + 1) % 3;
        self.search(near, next, q, best);
        if delta * delta < best.1 {
            self.search(far, next, q, best);
        }
    }
}

fn build(points: &[[f64; 3]], order: &mut [u32], axis: usize) {
    if order.len() <= 1 {
        return;
    }
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| points[a as usize][axis].total_cmp(&points[b as usize][axis]));
    let (left, right) = order.split_at_mut(mid);
    build(points, left, (axis + 1) % 3);
    build(points, &mut right[1..], (axis + 1) % 3);
}

#[cfg(test)]
mod tests {
    /// The tree's nearest point is the brute force's, on scattered points.
    #[test]
    fn nearest_is_the_brute_force_answer() {
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let points: Vec<[f64; 3]> = (0..500).map(|_| [next(), next(), next()]).collect();
        let tree = super::KdTree::new(points.clone());
        for _ in 0..200 {
            let q = [next() * 1.2 - 0.1, next(), next()];
            let brute =
                points.iter().map(|p| (0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>()).fold(f64::INFINITY, f64::min);
            assert_eq!(tree.nearest(q).unwrap().1, brute);
            let mut sorted: Vec<(f64, usize)> = points
                .iter()
                .enumerate()
                .map(|(i, p)| ((0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>(), i))
                .collect();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            let five: Vec<usize> = sorted[..5].iter().map(|s| s.1).collect();
            assert_eq!(tree.nearest_k(q, 5), five);
        }
    }
}
