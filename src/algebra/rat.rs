//! Exact rationals that stay machine integers while they fit: the
//! coefficients of every [`Surd`](super::Surd). The weights of generated
//! automata (`3/8`, `-1/16`, `5/24`) and the products the solver forms from
//! them fit in 64 bits; a [`BigRational`] (two heap-allocated integers) is
//! made only when a numerator or a denominator does not.

use std::fmt;

use num_bigint::{BigInt, BigUint};
use num_rational::BigRational;
use num_traits::{One, PrimInt, Signed, ToPrimitive, Unsigned};

/// A rational number, canonical: `Small(n, d)` with `d > 0`, `gcd(n, d) = 1`
/// and `n ≠ i64::MIN` whenever the value has such a form, `Big` only when it
/// has none; so equal values are equal variants (derived `Eq` and `Hash` hold).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Rat {
    /// `n / d`.
    Small(i64, i64),
    /// A value whose reduced numerator or denominator does not fit.
    Big(Box<BigRational>),
}

impl Default for Rat {
    fn default() -> Rat {
        Rat::ZERO
    }
}

/// The greatest common divisor (binary: shifts and subtractions, no division), for
/// `u64` (the common case) and `u128` (the products of two `i64`).
fn gcd<T: PrimInt + Unsigned>(mut a: T, mut b: T) -> T {
    if a.is_zero() {
        return b;
    }
    if b.is_zero() {
        return a;
    }
    let shift = (a | b).trailing_zeros() as usize;
    a = a >> a.trailing_zeros() as usize;
    loop {
        b = b >> b.trailing_zeros() as usize;
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        b = b - a;
        if b.is_zero() {
            return a << shift;
        }
    }
}

impl Rat {
    /// Zero.
    pub(crate) const ZERO: Rat = Rat::Small(0, 1);
    /// One.
    pub(crate) const ONE: Rat = Rat::Small(1, 1);

    /// `n / d` (`d ≠ 0`) from 128-bit parts, reduced.
    fn from_i128(n: i128, d: i128) -> Rat {
        debug_assert!(d != 0);
        if let (Ok(n), Ok(d)) = (i64::try_from(n), i64::try_from(d))
            && n != i64::MIN
            && d > 0
        {
            // The common case, in 64-bit arithmetic (a 128-bit division is several times slower).
            let g = gcd(n.unsigned_abs(), d as u64) as i64;
            return Rat::Small(n / g, d / g);
        }
        let g = gcd(n.unsigned_abs(), d.unsigned_abs()) as i128;
        let (mut n, mut d) = (n / g, d / g);
        if d < 0 {
            // |n|, |d| ≤ 2^127 - 1 after a gcd ≥ 1 unless one is i128::MIN, which products of
            // two i64 never reach.
            n = -n;
            d = -d;
        }
        match (i64::try_from(n), i64::try_from(d)) {
            (Ok(n), Ok(d)) if n != i64::MIN => Rat::Small(n, d),
            _ => Rat::Big(Box::new(BigRational::new_raw(BigInt::from(n), BigInt::from(d)))),
        }
    }

    /// The canonical form of `q`.
    pub(crate) fn from_big(q: BigRational) -> Rat {
        match (q.numer().to_i64(), q.denom().to_i64()) {
            (Some(n), Some(d)) if n != i64::MIN => Rat::Small(n, d),
            _ => Rat::Big(Box::new(q)),
        }
    }

    /// `p / q` (`q ≠ 0`).
    pub(crate) fn frac(p: i64, q: i64) -> Rat {
        Rat::from_i128(p.into(), q.into())
    }

    /// The integer `u`.
    pub(crate) fn from_u64(u: u64) -> Rat {
        Rat::from_i128(u.into(), 1)
    }

    /// The value as a [`BigRational`].
    pub(crate) fn to_big(&self) -> BigRational {
        match self {
            Rat::Small(n, d) => BigRational::new_raw(BigInt::from(*n), BigInt::from(*d)),
            Rat::Big(q) => (**q).clone(),
        }
    }

    /// Whether it is zero.
    pub(crate) fn is_zero(&self) -> bool {
        matches!(self, Rat::Small(0, _))
    }

    /// Whether it is one.
    pub(crate) fn is_one(&self) -> bool {
        matches!(self, Rat::Small(1, 1))
    }

    /// Whether it is minus one.
    pub(crate) fn is_minus_one(&self) -> bool {
        matches!(self, Rat::Small(-1, 1))
    }

    /// Whether it is negative.
    pub(crate) fn is_negative(&self) -> bool {
        match self {
            Rat::Small(n, _) => *n < 0,
            Rat::Big(q) => q.is_negative(),
        }
    }

    /// `self + other`.
    pub(crate) fn add(&self, other: &Rat) -> Rat {
        match (self, other) {
            (Rat::Small(0, _), _) => other.clone(),
            (_, Rat::Small(0, _)) => self.clone(),
            (Rat::Small(a, b), Rat::Small(c, d)) if b == d => {
                Rat::from_i128(i128::from(*a) + i128::from(*c), (*b).into())
            }
            (Rat::Small(a, b), Rat::Small(c, d)) => {
                let (a, b, c, d) = (i128::from(*a), i128::from(*b), i128::from(*c), i128::from(*d));
                // |a d| + |c b| < 2^127: no overflow.
                Rat::from_i128(a * d + c * b, b * d)
            }
            _ => Rat::from_big(self.to_big() + other.to_big()),
        }
    }

    /// `-self`.
    pub(crate) fn neg(&self) -> Rat {
        match self {
            Rat::Small(n, d) => Rat::Small(-n, *d),
            Rat::Big(q) => Rat::from_big(-&**q),
        }
    }

    /// `self · other`.
    pub(crate) fn mul(&self, other: &Rat) -> Rat {
        match (self, other) {
            (Rat::Small(0, _), _) | (_, Rat::Small(0, _)) => Rat::ZERO,
            (Rat::Small(1, 1), _) => other.clone(),
            (_, Rat::Small(1, 1)) => self.clone(),
            (Rat::Small(a, b), Rat::Small(c, d)) => {
                Rat::from_i128(i128::from(*a) * i128::from(*c), i128::from(*b) * i128::from(*d))
            }
            _ => Rat::from_big(self.to_big() * other.to_big()),
        }
    }

    /// `1 / self`, or `None` for zero.
    pub(crate) fn recip(&self) -> Option<Rat> {
        match self {
            Rat::Small(0, _) => None,
            Rat::Small(n, d) => Some(Rat::from_i128((*d).into(), (*n).into())),
            Rat::Big(q) => Some(Rat::from_big(q.recip())),
        }
    }

    /// The nearest `f64` (correctly rounded, as [`BigRational`]'s conversion).
    pub(crate) fn to_f64(&self) -> f64 {
        const EXACT: i64 = 1 << f64::MANTISSA_DIGITS;
        match self {
            // Both exact in an f64: one correctly rounded division (the same fast track as
            // `num_rational`'s).
            Rat::Small(n, d) if n.abs() <= EXACT && *d <= EXACT => *n as f64 / *d as f64,
            _ => self.to_big().to_f64().unwrap_or(f64::NAN),
        }
    }

    /// The absolute value's numerator and the denominator, for printing.
    pub(crate) fn abs_parts(&self) -> (IntText<'_>, IntText<'_>) {
        match self {
            Rat::Small(n, d) => (IntText::Small(n.unsigned_abs()), IntText::Small(d.unsigned_abs())),
            Rat::Big(q) => (IntText::Big(q.numer().magnitude()), IntText::Big(q.denom().magnitude())),
        }
    }
}

/// A non-negative integer of a [`Rat`], printed in decimal.
pub(crate) enum IntText<'a> {
    /// A machine integer.
    Small(u64),
    /// A big one.
    Big(&'a BigUint),
}

impl IntText<'_> {
    /// Whether it is one.
    pub(crate) fn is_one(&self) -> bool {
        match self {
            IntText::Small(n) => *n == 1,
            IntText::Big(n) => n.is_one(),
        }
    }
}

impl fmt::Display for IntText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IntText::Small(n) => write!(f, "{n}"),
            IntText::Big(n) => write!(f, "{n}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn big(n: i128, d: i128) -> BigRational {
        BigRational::new(BigInt::from(n), BigInt::from(d))
    }

    /// Every operation agrees with `BigRational` at the edges of the 64-bit range, and the
    /// result is canonical (a `Small` whenever the value fits).
    #[test]
    fn agrees_with_big_rationals_and_stays_canonical() {
        let values: Vec<(i128, i128)> = vec![
            (0, 1),
            (1, 1),
            (-1, 1),
            (3, 8),
            (-5, 24),
            (i64::MAX as i128, 1),
            (-(i64::MAX as i128), 1),
            (1, i64::MAX as i128),
            (i64::MAX as i128, i64::MAX as i128 - 1),
            (-(i64::MAX as i128) + 2, 3),
            (1 << 40, 3),
            (7, 1 << 62),
            (i64::MIN as i128, 1),
            ((i64::MAX as i128) * 5, 3),
        ];
        let canonical = |r: &Rat, q: &BigRational| {
            let fits = q.numer().to_i64().is_some_and(|n| n != i64::MIN) && q.denom().to_i64().is_some();
            assert_eq!(matches!(r, Rat::Small(..)), fits, "{r:?} for {q}");
            assert_eq!(&r.to_big(), q);
        };
        for &(a, b) in &values {
            let qa = big(a, b);
            let ra = Rat::from_big(qa.clone());
            canonical(&ra, &qa);
            canonical(&ra.neg(), &-&qa);
            assert_eq!(ra.to_f64(), qa.to_f64().unwrap(), "{qa}");
            if let Some(r) = ra.recip() {
                canonical(&r, &qa.recip());
            }
            for &(c, d) in &values {
                let qc = big(c, d);
                let rc = Rat::from_big(qc.clone());
                canonical(&ra.add(&rc), &(&qa + &qc));
                canonical(&ra.add(&rc.neg()), &(&qa - &qc));
                canonical(&ra.mul(&rc), &(&qa * &qc));
            }
        }
        // Pseudo-random values of every magnitude, chained so that results feed later operations
        // (sums and products that overflow 64 bits and come back).
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |bits: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let v = (seed >> (64 - bits)) as i64;
            if seed & 1 == 0 { v } else { -v }
        };
        let (mut r, mut q) = (Rat::ONE, BigRational::one());
        for step in 0..20_000u32 {
            let bits = 1 + step % 63;
            let (n, d) = (next(bits), next(bits).unsigned_abs().max(1) as i64);
            let (rb, qb) = (Rat::frac(n, d), big(n.into(), d.into()));
            canonical(&rb, &qb);
            let (r2, q2) = match step % 3 {
                0 => (r.add(&rb), &q + &qb),
                1 => (r.mul(&rb), &q * &qb),
                _ => (r.add(&rb.neg()), &q - &qb),
            };
            canonical(&r2, &q2);
            assert_eq!(r2.to_f64(), q2.to_f64().unwrap());
            // Keep the chain's values from growing without bound.
            (r, q) = if q2.numer().bits() > 300 || q2.denom().bits() > 300 { (rb, qb) } else { (r2, q2) };
        }
        assert_eq!(Rat::frac(6, -4), Rat::Small(-3, 2));
        let q = Rat::frac(-7, 2);
        let (n, d) = q.abs_parts();
        assert_eq!((n.to_string(), d.to_string()), ("7".into(), "2".into()));
    }
}
