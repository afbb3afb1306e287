//! Exact numbers with an explicit floating-point escape hatch.

use std::fmt;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// A number of an automaton file: an exact rational whenever it can be, a
/// float only when an irrational constant (such as `sqrt(3)`) made it one.
///
/// Arithmetic between two exact numbers stays exact; any operation that
/// involves an approximate number gives an approximate number.
#[derive(Clone, Debug)]
pub enum Num {
    /// An exact rational.
    Exact(BigRational),
    /// A floating-point approximation of an irrational value.
    Approx(f64),
}

impl Num {
    /// The exact integer `n`.
    pub fn int(n: i64) -> Num {
        Num::Exact(BigRational::from_integer(BigInt::from(n)))
    }

    /// The exact fraction `p / q`. `q` must not be zero.
    pub fn frac(p: i64, q: i64) -> Num {
        Num::Exact(BigRational::new(BigInt::from(p), BigInt::from(q)))
    }

    /// Zero.
    pub fn zero() -> Num {
        Num::Exact(BigRational::zero())
    }

    /// One.
    pub fn one() -> Num {
        Num::Exact(BigRational::one())
    }

    /// Parses a decimal literal (`3`, `0.5625`, `1e-3`, `2.5E+2`) exactly.
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
        let digits: BigInt = format!("{int_part}{frac_part}0").parse().ok()?;
        let digits = digits / BigInt::from(10);
        let scale = exponent - frac_part.len() as i32;
        let ten = BigInt::from(10);
        let value = if scale >= 0 {
            BigRational::from_integer(digits * num_traits::pow(ten, scale as usize))
        } else {
            BigRational::new(digits, num_traits::pow(ten, (-scale) as usize))
        };
        Some(Num::Exact(value))
    }

    /// Converts an `f64` exactly (every finite float is a dyadic rational).
    pub fn from_f64(x: f64) -> Num {
        BigRational::from_float(x).map_or(Num::Approx(x), Num::Exact)
    }

    /// Whether the number is exactly (or, if approximate, numerically) zero.
    pub fn is_zero(&self) -> bool {
        match self {
            Num::Exact(r) => r.is_zero(),
            Num::Approx(x) => *x == 0.0,
        }
    }

    /// Whether the number is exactly one.
    pub fn is_one(&self) -> bool {
        matches!(self, Num::Exact(r) if r.is_one())
    }

    /// Whether the number is exact.
    pub fn is_exact(&self) -> bool {
        matches!(self, Num::Exact(_))
    }

    /// Whether the number is negative.
    pub fn is_negative(&self) -> bool {
        match self {
            Num::Exact(r) => r.is_negative(),
            Num::Approx(x) => *x < 0.0,
        }
    }

    /// The nearest `f64`.
    pub fn to_f64(&self) -> f64 {
        match self {
            Num::Exact(r) => r.to_f64().unwrap_or(f64::NAN),
            Num::Approx(x) => *x,
        }
    }

    /// The absolute value.
    pub fn abs(&self) -> Num {
        match self {
            Num::Exact(r) => Num::Exact(r.abs()),
            Num::Approx(x) => Num::Approx(x.abs()),
        }
    }

    /// `self + other`.
    pub fn add(&self, other: &Num) -> Num {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a + b),
            _ => Num::Approx(self.to_f64() + other.to_f64()),
        }
    }

    /// `self - other`.
    pub fn sub(&self, other: &Num) -> Num {
        self.add(&other.neg())
    }

    /// `-self`.
    pub fn neg(&self) -> Num {
        match self {
            Num::Exact(a) => Num::Exact(-a),
            Num::Approx(x) => Num::Approx(-x),
        }
    }

    /// `self * other`.
    pub fn mul(&self, other: &Num) -> Num {
        match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a * b),
            _ => Num::Approx(self.to_f64() * other.to_f64()),
        }
    }

    /// `self / other`, or `None` when `other` is zero.
    pub fn div(&self, other: &Num) -> Option<Num> {
        if other.is_zero() {
            return None;
        }
        Some(match (self, other) {
            (Num::Exact(a), Num::Exact(b)) => Num::Exact(a / b),
            _ => Num::Approx(self.to_f64() / other.to_f64()),
        })
    }

    /// The square root: exact when both numerator and denominator are perfect
    /// squares, approximate otherwise; `None` for a negative number.
    pub fn sqrt(&self) -> Option<Num> {
        if self.is_negative() {
            return None;
        }
        if let Num::Exact(r) = self {
            let (n, d) = (r.numer().sqrt(), r.denom().sqrt());
            if &(&n * &n) == r.numer() && &(&d * &d) == r.denom() {
                return Some(Num::Exact(BigRational::new(n, d)));
            }
        }
        Some(Num::Approx(self.to_f64().sqrt()))
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
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Num::Exact(r) if r.is_integer() => write!(f, "{}", r.numer()),
            Num::Exact(r) => write!(f, "{}/{}", r.numer(), r.denom()),
            Num::Approx(x) => write!(f, "{x}"),
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
    fn sqrt_is_exact_for_squares() {
        assert_eq!(Num::frac(9, 16).sqrt(), Some(Num::frac(3, 4)));
        assert!(!Num::int(3).sqrt().is_some_and(|s| s.is_exact()));
        assert_eq!(Num::int(-1).sqrt(), None);
    }

    #[test]
    fn display_is_plain() {
        assert_eq!(Num::frac(-1, 16).to_string(), "-1/16");
        assert_eq!(Num::int(2).to_string(), "2");
    }
}
