//! Smoothness and fractal analysis of uniform stationary subdivision schemes
//! through their masks (Laurent polynomials), after Dyn and Levin's
//! difference-scheme theory.
//!
//! A `p`-ary scheme with mask `a(z) = Σ a_m z^m` maps `p^k` to `p^{k+1}` by
//! `p^{k+1}_f = Σ_j a_{f - pj} p^k_j`. When it reproduces constants,
//! `σ(z) = 1 + z + … + z^{p-1}` divides `a(z)` and the differences
//! `d_j = p_j - p_{j-1}` obey the scheme of mask `b(z) = a(z)/σ(z)`:
//!
//! - **C0**: the scheme converges uniformly iff the difference scheme is
//!   contractive, i.e. `‖S_b^L‖∞ < 1` for some `L` (`‖S_c^L‖∞` is the largest
//!   sum of `|coefficients|` over the `p^L` residue classes of the `L`-step
//!   mask `c(z) c(z^p) … c(z^{p^{L-1}})`). [`contraction`] returns
//!   `min_L ‖S_b^L‖∞^{1/L}`, an upper bound of the joint spectral radius;
//!   [`spectral_lower_bound`] a lower bound from the spectral radii of
//!   products of the difference scheme's square blocks.
//! - **C^m**: the scheme is `C^m` if the scheme of mask `p^m a(z)/σ(z)^m`
//!   converges, i.e. if the mask `p^m a(z)/σ(z)^{m+1}` is contractive.
//! - **Length**: the polygon between two fixed points after `k` steps has
//!   length `Σ |d_f^k|` over `p^k` differences; its growth rate is measured
//!   on a polygon ([`length_growth`]) and bounded by `‖b_k‖_1^{1/k}` where
//!   `b_k` is the `k`-step difference mask ([`l1_growth`]). A convergent scheme
//!   whose polygon length grows geometrically (rate > 1) has a continuous,
//!   non-rectifiable limit: a fractal curve.

use crate::schemes::Rules;

/// A Laurent polynomial `Σ c_i z^{start + i}` with `f64` coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Mask {
    /// Exponent of the first coefficient.
    pub start: i64,
    /// Coefficients.
    pub coeffs: Vec<f64>,
}

impl Mask {
    /// The mask of a scheme: rule `r` with `(offset o, weight w)` puts `w` at `z^{r - p·o}`.
    pub fn from_rules(rules: &Rules) -> Mask {
        let p = rules.arity as i64;
        let terms: Vec<(i64, f64)> = rules
            .rules
            .iter()
            .enumerate()
            .flat_map(|(r, rule)| rule.iter().map(move |(o, w)| (r as i64 - p * o, w.to_f64())))
            .collect();
        let start = terms.iter().map(|t| t.0).min().unwrap_or(0);
        let end = terms.iter().map(|t| t.0).max().unwrap_or(0);
        let mut coeffs = vec![0.0; (end - start + 1) as usize];
        for (m, w) in terms {
            coeffs[(m - start) as usize] += w;
        }
        Mask { start, coeffs }
    }

    /// `self · s`.
    pub fn scale(&self, s: f64) -> Mask {
        Mask { start: self.start, coeffs: self.coeffs.iter().map(|c| c * s).collect() }
    }

    /// `self / σ(z)` with `σ = 1 + z + … + z^{p-1}`, or `None` when the
    /// remainder is not zero (the scheme does not reproduce constants).
    pub fn divide_by_sigma(&self, p: usize) -> Option<Mask> {
        let n = self.coeffs.len();
        if n < p {
            return None;
        }
        // Synthetic division from the highest power: q has n - p + 1 coefficients.
        let mut rem = self.coeffs.clone();
        let mut q = vec![0.0; n - p + 1];
        for i in (0..q.len()).rev() {
            let c = rem[i + p - 1];
            q[i] = c;
            for j in 0..p {
                rem[i + j] -= c;
            }
        }
        let scale = self.coeffs.iter().map(|c| c.abs()).fold(1.0, f64::max);
        rem.iter()
            .all(|r| r.abs() <= crate::algebra::tolerance::ROUNDING * scale)
            .then_some(Mask { start: self.start, coeffs: q })
    }

    /// The `L`-step mask `c(z) c(z^p) … c(z^{p^{L-1}})`.
    pub fn steps(&self, p: usize, l: usize) -> Mask {
        let mut out = Mask { start: 0, coeffs: vec![1.0] };
        let mut stride = 1usize;
        for _ in 0..l {
            out = out.times_scaled(self, stride);
            stride *= p;
        }
        out
    }

    /// `self(z) · c(z^stride)`.
    fn times_scaled(&self, c: &Mask, stride: usize) -> Mask {
        let len = self.coeffs.len() + (c.coeffs.len() - 1) * stride;
        let mut next = vec![0.0; len];
        for (j, b) in c.coeffs.iter().enumerate() {
            if *b == 0.0 {
                continue;
            }
            for (x, a) in next[j * stride..].iter_mut().zip(&self.coeffs) {
                *x += a * b;
            }
        }
        Mask { start: self.start + c.start * stride as i64, coeffs: next }
    }

    /// `‖S^L‖∞`: the largest sum of `|c|` over a residue class mod `p^L` of the `L`-step mask.
    pub fn norm_inf(&self, p: usize, l: usize) -> f64 {
        let m = self.steps(p, l);
        let q = p.pow(l as u32);
        let mut sums = vec![0.0; q];
        for (i, c) in m.coeffs.iter().enumerate() {
            sums[(m.start + i as i64).rem_euclid(q as i64) as usize] += c.abs();
        }
        sums.into_iter().fold(0.0, f64::max)
    }

    /// `‖c_L‖_1`: the sum of `|c|` over the `L`-step mask.
    pub fn norm_1(&self, p: usize, l: usize) -> f64 {
        self.steps(p, l).coeffs.iter().map(|c| c.abs()).sum()
    }

    /// The rules of the scheme with this mask (rule `r` gets `c_{r - p o}` at offset `o`).
    pub fn rules(&self, p: usize) -> Rules {
        let pi = p as i64;
        let mut rules = vec![Vec::new(); p];
        for (i, c) in self.coeffs.iter().enumerate() {
            if *c == 0.0 {
                continue;
            }
            let m = self.start + i as i64;
            let r = m.rem_euclid(pi);
            let o = (r - m) / pi;
            rules[r as usize].push((
                o,
                crate::algebra::Surd::rational(num_rational::BigRational::from_float(*c).unwrap_or_default()),
            ));
        }
        Rules { arity: p, rules }
    }
}

/// `min_{1 ≤ L ≤ max_steps} ‖S_c^L‖∞^{1/L}`: below 1, the scheme of mask `c` is contractive.
pub fn contraction(mask: &Mask, p: usize, max_steps: usize) -> f64 {
    let mut best = f64::INFINITY;
    let mut m = Mask { start: 0, coeffs: vec![1.0] };
    let mut stride = 1usize;
    for l in 1..=max_steps.max(1) {
        m = m.times_scaled(mask, stride);
        stride *= p;
        let mut sums = vec![0.0; stride];
        for (i, c) in m.coeffs.iter().enumerate() {
            sums[(m.start + i as i64).rem_euclid(stride as i64) as usize] += c.abs();
        }
        best = best.min(sums.into_iter().fold(0.0, f64::max).powf(1.0 / l as f64));
    }
    best
}

/// `‖c_L‖_1^{1/L}` for `L = steps`: the growth rate of `Σ |d|` per step that
/// the difference mask `c` allows.
pub fn l1_growth(mask: &Mask, p: usize, steps: usize) -> f64 {
    mask.norm_1(p, steps).powf(1.0 / steps as f64)
}

/// A lower bound of the joint spectral radius of the scheme of mask `c`:
/// `max ρ(B_w)^{1/|w|}` over products of its square blocks of length ≤ 4
/// (blocks on the smallest window that gives them, up to 40 points).
pub fn spectral_lower_bound(mask: &Mask, p: usize) -> Option<f64> {
    let rules = mask.rules(p);
    let blocks = (2..=40).find_map(|n| rules.blocks(n).ok())?;
    let mats: Vec<nalgebra::DMatrix<f64>> = blocks.iter().map(crate::schemes::to_f64).collect();
    let rho = |m: &nalgebra::DMatrix<f64>| {
        crate::algebra::eigenvalues(m).unwrap_or_default().iter().map(|l| l.norm()).fold(0.0, f64::max)
    };
    let mut best: f64 = 0.0;
    let mut words: Vec<nalgebra::DMatrix<f64>> = mats.clone();
    for len in 1..=4 {
        for w in &words {
            best = best.max(rho(w).powf(1.0 / len as f64));
        }
        if len < 4 {
            words = words.iter().flat_map(|w| mats.iter().map(move |m| w * m)).collect();
        }
    }
    Some(best)
}

/// A lower bound of the growth rate of the polygon length of the scheme
/// whose difference mask is `c`: `max ρ(Σ_i s_i B_i)` over the sign
/// vectors `s` (`s_0 = +1`) and the square blocks `B_i` of `c`.
///
/// After `K` steps the edges between two control points are `r B_P w` over
/// the `p^K` block products `P` (`w` the initial differences around them),
/// so by the triangle inequality `L_K ≥ |r (Σ_i s_i B_i)^K w|` for any signs:
/// when the bound exceeds 1 the length diverges at that rate for every
/// control polygon whose differences have a component along the dominant
/// eigenvector (all but a closed set of measure zero: the generic case).
pub fn length_lower_bound(mask: &Mask, p: usize) -> Option<f64> {
    let rules = mask.rules(p);
    let blocks = (2..=40).find_map(|n| rules.blocks(n).ok())?;
    let mats: Vec<nalgebra::DMatrix<f64>> = blocks.iter().map(crate::schemes::to_f64).collect();
    let mut best: f64 = 0.0;
    for signs in 0..1usize << (mats.len() - 1) {
        let mut sum = mats[0].clone();
        for (i, m) in mats.iter().enumerate().skip(1) {
            if signs >> (i - 1) & 1 == 1 {
                sum -= m;
            } else {
                sum += m;
            }
        }
        let rho = crate::algebra::eigenvalues(&sum).unwrap_or_default().iter().map(|l| l.norm()).fold(0.0, f64::max);
        best = best.max(rho);
    }
    Some(best)
}

/// The growth rate of the polygon length between two fixed control points:
/// the scheme refines a closed test polygon (`n` points on a wavy closed
/// curve, in general position) `steps` times and the rate is
/// `(L_steps / L_{steps - 2})^{1/2}`.
pub fn length_growth(rules: &Rules, steps: usize) -> f64 {
    let n = 9;
    let mut pts: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let r = 1.0 + 0.3 * (3.0 * t).sin() + 0.1 * (i as f64 * 1.7).cos();
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    let len = |p: &[f64]| -> f64 {
        let m = p.len() / 2;
        (0..m)
            .map(|i| {
                let j = (i + 1) % m;
                ((p[2 * i] - p[2 * j]).powi(2) + (p[2 * i + 1] - p[2 * j + 1]).powi(2)).sqrt()
            })
            .sum()
    };
    let mut lengths = vec![len(&pts)];
    for _ in 0..steps.max(2) {
        pts = rules.refine_closed_flat(&pts, 2);
        lengths.push(len(&pts));
    }
    let k = lengths.len() - 1;
    (lengths[k] / lengths[k - 2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_bspline_differences_and_smoothness() {
        let a = Mask::from_rules(&Rules::cubic_bspline());
        // a(z) = (1 + z)^4 / (8 z^2): coefficients 1/8, 1/2, 3/4, 1/2, 1/8 from z^-2.
        assert_eq!(a.start, -2);
        assert_eq!(a.coeffs, vec![0.125, 0.5, 0.75, 0.5, 0.125]);
        let b = a.divide_by_sigma(2).unwrap();
        assert_eq!(b.coeffs, vec![0.125, 0.375, 0.375, 0.125]);
        // C0, C1, C2 (the cubic B-spline is C2): contraction factors 1/2 each.
        for m in 0..3 {
            let mut c = a.scale(2f64.powi(m));
            for _ in 0..=m {
                c = c.divide_by_sigma(2).unwrap();
            }
            assert!(contraction(&c, 2, 4) < 1.0, "C{m}");
        }
        // Non-negative difference mask: the length stays bounded (growth 1).
        assert!((l1_growth(&b, 2, 6) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn four_point_is_c1_not_c2() {
        let a = Mask::from_rules(&Rules::four_point());
        let c = |m: i32| {
            let mut c = a.scale(2f64.powi(m));
            for _ in 0..=m {
                c = c.divide_by_sigma(2).unwrap();
            }
            c
        };
        assert!(contraction(&c(0), 2, 6) < 1.0);
        assert!(contraction(&c(1), 2, 8) < 1.0);
        assert!(spectral_lower_bound(&c(2), 2).unwrap() >= 1.0 - 1e-9);
    }
}
