//! Exact numbers of the form `q₀ + q₁·√r₁ + q₂·√r₂ + …` (rational `qᵢ`,
//! square-free integer `rᵢ`), so that scheme generators write automaton
//! files whose entries are exact (`1/2 - sqrt(3)/6`, not `0.2113248654…`)
//! and whose column sums are exactly 1.
//!
//! The papers' parameters are all of this kind: `√3/4` (Sierpinski, Li et al. 2013
//! eq. 3), `√3/6` (Koch, eq. 5), `-√3/18` (crown), rationals elsewhere.

use std::fmt;

use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::rat::Rat;

/// Largest radicand handled exactly (square-free factorisation by trial division).
const MAX_RADICAND: u64 = 1 << 40;

/// A sum of rational multiples of square roots of square-free integers: the
/// exact case of every number bcifs reads, writes and solves with.
///
/// ```
/// use bcifs::algebra::Surd;
/// let a = Surd::parse("1/2 - sqrt(3)/6").unwrap();
/// let b = Surd::parse("sqrt(12)/12").unwrap(); // = sqrt(3)/6
/// assert_eq!(a.add(&b), Surd::parse("1/2").unwrap());
/// assert_eq!(b.mul(&b), Surd::parse("1/12").unwrap());
/// assert_eq!(a.to_string(), "1/2 - sqrt(3)/6");
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct Surd {
    /// The rational part (machine integers while they fit: no allocation in the solver's
    /// common case).
    rational: Rat,
    /// `(radicand, coefficient)`: square-free radicands > 1, increasing, coefficients non-zero.
    /// Empty for a rational (no allocation).
    roots: Vec<(u64, Rat)>,
}

/// Why a text or expression is not an exact surd.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SurdError {
    /// The text is not an expression.
    #[error("`{text}` is not a number: {message}")]
    Syntax {
        /// The text.
        text: String,
        /// What the parser expected.
        message: String,
    },
    /// The expression uses a parameter or an entry.
    #[error("`{0}` must be a constant (numbers, + - * /, sqrt), not a parameter or matrix entry")]
    NotConstant(String),
    /// A square root of a negative number, of an irrational number, or a division by a sum of roots.
    #[error(
        "`{0}` is not exact: only square roots of non-negative rationals and divisions by a single term are kept exact"
    )]
    Inexact(String),
    /// Division by zero.
    #[error("`{0}` divides by zero")]
    DivisionByZero(String),
}

/// `(s, f)` with `n = s · f²` and `s` square-free.
fn square_free(mut n: u64) -> (u64, u64) {
    let (mut s, mut f) = (1u64, 1u64);
    let mut p = 2u64;
    while p * p <= n {
        while n.is_multiple_of(p * p) {
            n /= p * p;
            f *= p;
        }
        if n.is_multiple_of(p) {
            n /= p;
            s *= p;
        }
        p += 1;
    }
    (s * n, f)
}

impl Surd {
    /// Zero.
    pub fn zero() -> Surd {
        Surd::default()
    }

    /// One.
    pub fn one() -> Surd {
        Surd::int(1)
    }

    /// The rational `q`.
    pub fn rational(q: BigRational) -> Surd {
        Surd::of(Rat::from_big(q))
    }

    fn of(q: Rat) -> Surd {
        Surd { rational: q, roots: Vec::new() }
    }

    /// The integer `n`.
    pub fn int(n: i64) -> Surd {
        Surd::of(Rat::frac(n, 1))
    }

    /// The fraction `p / q` (`q ≠ 0`).
    pub fn frac(p: i64, q: i64) -> Surd {
        Surd::of(Rat::frac(p, q))
    }

    /// `q·√radicand` for a square-free `radicand`.
    fn term(radicand: u64, q: Rat) -> Surd {
        if radicand == 1 {
            Surd::of(q)
        } else if q.is_zero() || radicand == 0 {
            Surd::zero()
        } else {
            Surd { rational: Rat::ZERO, roots: vec![(radicand, q)] }
        }
    }

    /// `√q` for a non-negative rational `q`, or `None` if `q < 0` or too large.
    pub fn sqrt_of(q: &BigRational) -> Option<Surd> {
        if q.is_negative() {
            return None;
        }
        if q.is_zero() {
            return Some(Surd::zero());
        }
        // √(a/b) = √(a·b) / b.
        let (a, b) = (q.numer().to_u64()?, q.denom().to_u64()?);
        let ab = a.checked_mul(b).filter(|x| *x <= MAX_RADICAND)?;
        let (s, f) = square_free(ab);
        Some(Surd::term(s, Rat::from_u64(f).mul(&Rat::from_u64(b).recip()?)))
    }

    /// Whether it is zero.
    pub fn is_zero(&self) -> bool {
        self.rational.is_zero() && self.roots.is_empty()
    }

    /// Whether it is one.
    pub fn is_one(&self) -> bool {
        self.rational.is_one() && self.roots.is_empty()
    }

    /// Whether it is a rational (no square-root term).
    pub fn is_rational(&self) -> bool {
        self.roots.is_empty()
    }

    /// The rational value, if there is no square-root term.
    pub fn as_rational(&self) -> Option<BigRational> {
        self.roots.is_empty().then(|| self.rational.to_big())
    }

    /// The rational value as `(numerator, denominator)` machine integers
    /// (denominator positive, reduced), if it is a rational that fits.
    pub fn as_small_rational(&self) -> Option<(i64, i64)> {
        match (&self.rational, self.roots.is_empty()) {
            (Rat::Small(n, d), true) => Some((*n, *d)),
            _ => None,
        }
    }

    fn merge(&self, other: &Surd, k: &Rat) -> Vec<(u64, Rat)> {
        if other.roots.is_empty() {
            return self.roots.clone();
        }
        let mut out = Vec::with_capacity(self.roots.len() + other.roots.len());
        let (mut i, mut j) = (0, 0);
        while i < self.roots.len() || j < other.roots.len() {
            match (self.roots.get(i), other.roots.get(j)) {
                (Some(a), Some(b)) if a.0 == b.0 => {
                    let c = a.1.add(&k.mul(&b.1));
                    if !c.is_zero() {
                        out.push((a.0, c));
                    }
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a.0 < b.0 => {
                    out.push(a.clone());
                    i += 1;
                }
                (Some(a), None) => {
                    out.push(a.clone());
                    i += 1;
                }
                (_, Some(b)) => {
                    out.push((b.0, k.mul(&b.1)));
                    j += 1;
                }
                (None, None) => break,
            }
        }
        out
    }

    /// `self + k · other` for a rational `k`.
    pub fn add_scaled(&self, other: &Surd, k: &BigRational) -> Surd {
        self.add_scaled_rat(other, &Rat::from_big(k.clone()))
    }

    fn add_scaled_rat(&self, other: &Surd, k: &Rat) -> Surd {
        // Fast paths (the solver's common cases): nothing to add, nothing to add to, rationals.
        if k.is_zero() || other.is_zero() {
            return self.clone();
        }
        if self.is_zero() {
            return other.scale_rat(k);
        }
        let rational = self.rational.add(&k.mul(&other.rational));
        if self.roots.is_empty() && other.roots.is_empty() {
            return Surd::of(rational);
        }
        Surd { rational, roots: self.merge(other, k) }
    }

    /// `self + other`.
    pub fn add(&self, other: &Surd) -> Surd {
        self.add_scaled_rat(other, &Rat::ONE)
    }

    /// `-self`.
    pub fn neg(&self) -> Surd {
        Surd { rational: self.rational.neg(), roots: self.roots.iter().map(|(r, q)| (*r, q.neg())).collect() }
    }

    /// `self - other`.
    pub fn sub(&self, other: &Surd) -> Surd {
        self.add_scaled_rat(other, &Rat::frac(-1, 1))
    }

    /// `self · q` for a rational `q`.
    pub fn scale(&self, q: &BigRational) -> Surd {
        self.scale_rat(&Rat::from_big(q.clone()))
    }

    fn scale_rat(&self, q: &Rat) -> Surd {
        if q.is_zero() || self.is_zero() {
            return Surd::zero();
        }
        if q.is_one() {
            return self.clone();
        }
        if q.is_minus_one() {
            return self.neg();
        }
        Surd { rational: self.rational.mul(q), roots: self.roots.iter().map(|(r, c)| (*r, c.mul(q))).collect() }
    }

    fn terms(&self) -> impl Iterator<Item = (u64, &Rat)> {
        std::iter::once((1, &self.rational))
            .filter(|(_, q)| !q.is_zero())
            .chain(self.roots.iter().map(|(r, q)| (*r, q)))
    }

    /// `self · other`: `√a·√b = √(ab)`, reduced to square-free form.
    pub fn mul(&self, other: &Surd) -> Surd {
        if other.roots.is_empty() {
            return self.scale_rat(&other.rational);
        }
        if self.roots.is_empty() {
            return other.scale_rat(&self.rational);
        }
        let mut out = Surd::zero();
        for (ra, qa) in self.terms() {
            for (rb, qb) in other.terms() {
                let (s, f) = square_free(ra * rb);
                out = out.add(&Surd::term(s, qa.mul(qb).mul(&Rat::from_u64(f))));
            }
        }
        out
    }

    /// `self / other` when `other` is a single term `q√r` (`None` otherwise or for zero).
    pub fn div(&self, other: &Surd) -> Option<Surd> {
        let mut terms = other.terms();
        let (r, q) = terms.next()?;
        if terms.next().is_some() {
            return None;
        }
        // 1 / (q√r) = √r / (q r).
        let inv = Surd::term(r, q.mul(&Rat::from_u64(r)).recip()?);
        Some(self.mul(&inv))
    }

    /// The nearest `f64`.
    pub fn to_f64(&self) -> f64 {
        let rational = self.rational.to_f64();
        self.roots.iter().fold(rational, |acc, (r, q)| acc + q.to_f64() * (*r as f64).sqrt())
    }

    /// Whether it is negative (exact for rationals; by its `f64` value otherwise).
    pub fn is_negative(&self) -> bool {
        if self.roots.is_empty() { self.rational.is_negative() } else { self.to_f64() < 0.0 }
    }
}

impl From<i64> for Surd {
    fn from(n: i64) -> Surd {
        Surd::int(n)
    }
}

impl fmt::Display for Surd {
    /// Re-parseable text: `0`, `-1/16`, `1/2 - sqrt(3)/6`, `3*sqrt(3)/4`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_zero() {
            return f.write_str("0");
        }
        for (k, (r, q)) in self.terms().enumerate() {
            let negative = q.is_negative();
            match (k, negative) {
                (0, true) => f.write_str("-")?,
                (0, false) => {}
                (_, true) => f.write_str(" - ")?,
                (_, false) => f.write_str(" + ")?,
            }
            let (n, d) = q.abs_parts();
            if r == 1 {
                write!(f, "{n}")?;
            } else if n.is_one() {
                write!(f, "sqrt({r})")?;
            } else {
                write!(f, "{n}*sqrt({r})")?;
            }
            if !d.is_one() {
                write!(f, "/{d}")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_free_parts() {
        assert_eq!(square_free(12), (3, 2));
        assert_eq!(square_free(72), (2, 6));
        assert_eq!(square_free(1), (1, 1));
        assert_eq!(square_free(49), (1, 7));
    }

    #[test]
    fn arithmetic_is_exact_and_prints_back() {
        let s3 = Surd::parse("sqrt(3)").unwrap();
        assert_eq!(s3.mul(&s3), Surd::int(3));
        let x = Surd::parse("1/2 + sqrt(3)/4 - sqrt(27)/12").unwrap();
        assert_eq!(x, Surd::frac(1, 2));
        for text in ["0", "-1/16", "1/2 - sqrt(3)/6", "3*sqrt(3)/4", "-sqrt(3)/18 + sqrt(2)"] {
            let v = Surd::parse(text).unwrap();
            assert_eq!(Surd::parse(&v.to_string()).unwrap(), v, "{text}");
        }
        assert_eq!(Surd::parse("1/(2*sqrt(3))").unwrap(), Surd::parse("sqrt(3)/6").unwrap());
        assert!((Surd::parse("sqrt(3)/6").unwrap().to_f64() - 3f64.sqrt() / 6.0).abs() < 1e-16);
    }

    #[test]
    fn non_constants_and_inexact_values_are_refused() {
        assert!(matches!(Surd::parse("a + 1"), Err(SurdError::NotConstant(_))));
        assert!(matches!(Surd::parse("sqrt(-1)"), Err(SurdError::Inexact(_))));
        assert!(matches!(Surd::parse("sqrt(1 + sqrt(2))"), Err(SurdError::Inexact(_))));
        assert!(matches!(Surd::parse("1/(1 + sqrt(2))"), Err(SurdError::Inexact(_))));
        assert!(matches!(Surd::parse("1/0"), Err(SurdError::DivisionByZero(_))));
        assert!(matches!(Surd::parse("1 +"), Err(SurdError::Syntax { .. })));
    }
}
