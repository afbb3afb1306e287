//! The scalar of automaton files and of the solver: an exact [`Surd`]
//! whenever it can be, with an explicit floating-point escape hatch.

use std::fmt;

use num_bigint::BigInt;
use num_rational::BigRational;

use super::surd::Surd;

/// Largest power of ten a decimal literal may carry: far beyond any float
/// (`1e308`), small enough to stay exact in microseconds.
pub const MAX_EXPONENT: u32 = 4000;

/// A number of an automaton file: exact (a rational, or a sum of rational
/// multiples of square roots such as `1/2 - sqrt(3)/6`) whenever it can be;
/// a float only for values outside that field (`sqrt(1 + sqrt(2))`,
/// a division by a sum of roots).
///
/// Arithmetic between two exact numbers stays exact when the result is a
/// surd; any operation that involves an approximate number gives an
/// approximate number.
#[derive(Clone, Debug)]
pub enum Num {
    /// An exact value.
    Exact(Surd),
    /// A floating-point approximation of a value that is not a surd.
    Approx(f64),
}

impl Num {
    /// The exact integer `n`.
    pub fn int(n: i64) -> Num {
        Num::Exact(Surd::int(n))
    }

    /// The exact fraction `p / q`. `q` must not be zero.
    pub fn frac(p: i64, q: i64) -> Num {
        Num::Exact(Surd::frac(p, q))
    }

    /// The exact rational `q`.
    pub fn rational(q: BigRational) -> Num {
        Num::Exact(Surd::rational(q))
    }

    /// Zero.
    pub fn zero() -> Num {
        Num::Exact(Surd::zero())
    }

    /// One.
    pub fn one() -> Num {
        Num::Exact(Surd::one())
    }

    /// Parses a decimal literal (`3`, `0.5625`, `1e-3`, `2.5E+2`) exactly;
    /// `None` when it is not one, or when its power of ten is beyond
    /// ±`MAX_EXPONENT` (an exact `10^900000000` would take gigabytes).
    pub fn parse_decimal(text: &str) -> Option<Num> {
        let (mantissa, exponent) = match text.find(['e', 'E']) {
            Some(i) => (&text[..i], text[i + 1..].parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (int_part, frac_part) = match mantissa.find('.') {
            Some(i) => (&mantissa[..i], &mantissa[i + 1..]),
            None => (mantissa, ""),
        };
        if int_part.is_empty() && frac_part.is_empty() {
            return None;
        }
        if !int_part.chars().chain(frac_part.chars()).all(|c| c.is_ascii_digit()) {
            return None;
        }
        let scale = exponent.checked_sub(i32::try_from(frac_part.len()).ok()?)?;
        // Up to 18 digits and a power of ten up to 10^18: machine integers, no text built.
        if int_part.len() + frac_part.len() <= 18 && scale.unsigned_abs() <= 18 {
            let digits = int_part.bytes().chain(frac_part.bytes()).fold(0i64, |acc, b| acc * 10 + i64::from(b - b'0'));
            let power = 10i64.pow(scale.unsigned_abs());
            return Some(if scale >= 0 {
                match digits.checked_mul(power) {
                    Some(n) => Num::frac(n, 1),
                    None => Num::rational(BigRational::from_integer(BigInt::from(digits) * BigInt::from(power))),
                }
            } else {
                Num::frac(digits, power)
            });
        }
        let digits: BigInt = format!("{int_part}{frac_part}0").parse().ok()?;
        let digits = digits / BigInt::from(10);
        if scale.unsigned_abs() > MAX_EXPONENT {
            return None;
        }
        let ten = BigInt::from(10);
        let value = if scale >= 0 {
            BigRational::from_integer(digits * num_traits::pow(ten, scale as usize))
        } else {
            BigRational::new(digits, num_traits::pow(ten, (-scale) as usize))
        };
        Some(Num::rational(value))
    }

    /// The number a person means by the float `x`: its shortest decimal
    /// form, read exactly (`0.1` is `1/10`, not the dyadic nearest to it).
    /// Non-finite values stay approximate.
    pub fn from_f64(x: f64) -> Num {
        if !x.is_finite() {
            return Num::Approx(x);
        }
        let text = format!("{:e}", x.abs());
        match Num::parse_decimal(&text) {
            Some(n) if x < 0.0 => n.neg(),
            Some(n) => n,
            None => Num::Approx(x),
        }
    }

    /// Whether the number is exactly (or, if approximate, numerically) zero.
    pub fn is_zero(&self) -> bool {
        match self {
            Num::Exact(s) => s.is_zero(),
            Num::Approx(x) => *x == 0.0,
        }
    }

    /// Whether the number is exactly one.
    pub fn is_one(&self) -> bool {
        matches!(self, Num::Exact(s) if s.is_one())
    }

    /// Whether the number is exact.
    pub fn is_exact(&self) -> bool {
        matches!(self, Num::Exact(_))
    }

    /// The rational value, if the number is an exact rational.
    pub fn as_rational(&self) -> Option<BigRational> {
        match self {
            Num::Exact(s) => s.as_rational(),
            Num::Approx(_) => None,
        }
    }

    /// The rational value as `(numerator, denominator)` machine integers
    /// (denominator positive, reduced), if the number is an exact rational that fits.
    pub fn as_small_rational(&self) -> Option<(i64, i64)> {
        match self {
            Num::Exact(s) => s.as_small_rational(),
            Num::Approx(_) => None,
        }
    }

    /// Whether the number is negative.
    pub fn is_negative(&self) -> bool {
        match self {
            Num::Exact(s) => s.is_negative(),
            Num::Approx(x) => *x < 0.0,
        }
    }

    /// The nearest `f64`.
    pub fn to_f64(&self) -> f64 {
        match self {
            Num::Exact(s) => s.to_f64(),
            Num::Approx(x) => *x,
        }
    }

    /// The absolute value.
    pub fn abs(&self) -> Num {
        if self.is_negative() { self.neg() } else { self.clone() }
    }

    /// `self + other`.
    pub fn add(&self, other: &Num) -> Num {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a.add(b)),
            _ => Num::Approx(self.to_f64() + other.to_f64()),
        }
    }

    /// `self - other`.
    pub fn sub(&self, other: &Num) -> Num {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a.sub(b)),
            _ => Num::Approx(self.to_f64() - other.to_f64()),
        }
    }

    /// `-self`.
    pub fn neg(&self) -> Num {
        match self {
            Num::Exact(a) => Num::Exact(a.neg()),
            Num::Approx(x) => Num::Approx(-x),
        }
    }

    /// `self * other`.
    pub fn mul(&self, other: &Num) -> Num {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a.mul(b)),
            _ => Num::Approx(self.to_f64() * other.to_f64()),
        }
    }

    /// `self / other`, or `None` when `other` is zero. Exact when `other`
    /// is a single term `q√r`.
    pub fn div(&self, other: &Num) -> Option<Num> {
        if other.is_zero() {
            return None;
        }
        Some(match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => match a.div(b) {
                Some(q) => Num::Exact(q),
                None => Num::Approx(self.to_f64() / other.to_f64()),
            },
            _ => Num::Approx(self.to_f64() / other.to_f64()),
        })
    }

    /// The square root: exact for a non-negative rational (`sqrt(12)` is
    /// `2*sqrt(3)`), approximate otherwise; `None` for a negative number.
    pub fn sqrt(&self) -> Option<Num> {
        if self.is_negative() {
            return None;
        }
        if let Some(q) = self.as_rational()
            && let Some(s) = Surd::sqrt_of(&q)
        {
            return Some(Num::Exact(s));
        }
        Some(Num::Approx(self.to_f64().sqrt()))
    }
}

impl From<Surd> for Num {
    fn from(s: Surd) -> Num {
        Num::Exact(s)
    }
}

impl From<i64> for Num {
    fn from(n: i64) -> Num {
        Num::int(n)
    }
}

impl PartialEq for Num {
    fn eq(&self, other: &Num) -> bool {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => a == b,
            _ => self.to_f64() == other.to_f64(),
        }
    }
}

impl fmt::Display for Num {
    /// Re-parseable text: `2`, `-1/16`, `1/2 - sqrt(3)/6`, or a float.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Num::Exact(s) => write!(f, "{s}"),
            Num::Approx(x) => write!(f, "{x:?}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_are_exact() {
        assert_eq!(Num::parse_decimal("0.5625"), Some(Num::frac(9, 16)));
        assert_eq!(Num::parse_decimal("3"), Some(Num::int(3)));
        assert_eq!(Num::parse_decimal("1e-3"), Some(Num::frac(1, 1000)));
        assert_eq!(Num::parse_decimal("2.5E+2"), Some(Num::int(250)));
        assert_eq!(Num::parse_decimal(".25"), Some(Num::frac(1, 4)));
        assert_eq!(Num::parse_decimal("1.2.3"), None);
        assert_eq!(Num::parse_decimal("."), None);
    }

    #[test]
    fn floats_are_read_as_written() {
        assert_eq!(Num::from_f64(0.1), Num::frac(1, 10));
        assert_eq!(Num::from_f64(-0.5625), Num::frac(-9, 16));
        assert_eq!(Num::from_f64(3.0), Num::int(3));
        assert_eq!(Num::from_f64(1e-20), Num::Exact(Surd::parse("1/100000000000000000000").unwrap()));
        assert!(!Num::from_f64(f64::NAN).is_exact());
    }

    #[test]
    fn square_roots_stay_exact() {
        assert_eq!(Num::frac(9, 16).sqrt(), Some(Num::frac(3, 4)));
        let s3 = Num::int(3).sqrt().unwrap();
        assert!(s3.is_exact());
        assert_eq!(s3.mul(&s3), Num::int(3));
        assert_eq!(Num::int(-1).sqrt(), None);
        assert!(!Num::int(1).add(&Num::int(2).sqrt().unwrap()).sqrt().unwrap().is_exact());
    }

    #[test]
    fn display_is_plain_and_reparseable() {
        assert_eq!(Num::frac(-1, 16).to_string(), "-1/16");
        assert_eq!(Num::int(2).to_string(), "2");
        let x = Num::frac(1, 2).sub(&Num::int(3).sqrt().unwrap().div(&Num::int(6)).unwrap());
        assert_eq!(x.to_string(), "1/2 - sqrt(3)/6");
    }
}
