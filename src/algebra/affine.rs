//! Affine forms `c + Σ k_i x_i` over exact numbers.

use std::fmt;

use num_traits::One;

use super::expr::{ExprError, ExprValue};
use super::num::Num;

/// An affine expression `constant + Σ coeff · x_var` in numbered variables.
///
/// Terms are kept sorted by variable with non-zero coefficients, so equal
/// forms compare equal.
#[derive(Clone, Debug, PartialEq)]
pub struct Affine {
    constant: Num,
    terms: Vec<(usize, Num)>,
}

/// The sorted terms of `left + k · right`, without zero coefficients.
fn merge_scaled(left: &[(usize, Num)], right: &[(usize, Num)], k: &Num) -> Vec<(usize, Num)> {
    let mut terms = Vec::with_capacity(left.len() + right.len());
    let (mut i, mut j) = (0, 0);
    while i < left.len() || j < right.len() {
        let take_left = j >= right.len() || (i < left.len() && left[i].0 < right[j].0);
        let take_right = i >= left.len() || (j < right.len() && right[j].0 < left[i].0);
        if take_left {
            terms.push(left[i].clone());
            i += 1;
        } else if take_right {
            terms.push((right[j].0, right[j].1.mul(k)));
            j += 1;
        } else {
            terms.push((left[i].0, left[i].1.add(&right[j].1.mul(k))));
            i += 1;
            j += 1;
        }
    }
    terms.retain(|(_, c)| !c.is_zero());
    terms
}

/// A product of two non-constant affine forms: the system would not be linear.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("product of two expressions that both depend on unknowns is not linear")]
pub struct Nonlinear;

impl Affine {
    /// The constant form `c`.
    pub fn constant(c: Num) -> Affine {
        Affine { constant: c, terms: Vec::new() }
    }

    /// The constant zero.
    pub fn zero() -> Affine {
        Affine::constant(Num::zero())
    }

    /// The constant one.
    pub fn one() -> Affine {
        Affine::constant(Num::one())
    }

    /// The form `x_var`.
    pub fn var(var: usize) -> Affine {
        Affine { constant: Num::zero(), terms: vec![(var, Num::one())] }
    }

    /// The constant term.
    pub fn constant_term(&self) -> &Num {
        &self.constant
    }

    /// The terms `(variable, coefficient)`, sorted by variable, coefficients non-zero.
    pub fn terms(&self) -> &[(usize, Num)] {
        &self.terms
    }

    /// The constant value, if the form has no variable.
    pub fn as_constant(&self) -> Option<&Num> {
        self.terms.is_empty().then_some(&self.constant)
    }

    /// Whether the form is the constant zero.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty() && self.constant.is_zero()
    }

    /// Whether the form is the constant one.
    pub fn is_one(&self) -> bool {
        self.terms.is_empty() && self.constant.is_one()
    }

    /// `self + other`.
    pub fn add(&self, other: &Affine) -> Affine {
        self.add_scaled(other, &Num::one())
    }

    /// `self - other`.
    pub fn sub(&self, other: &Affine) -> Affine {
        self.add_scaled(other, &Num::int(-1))
    }

    /// `self + k · other`, merging the sorted term lists.
    pub fn add_scaled(&self, other: &Affine, k: &Num) -> Affine {
        if self.terms.is_empty() || other.terms.is_empty() {
            // The common cases of matrix products, adding to nothing or adding a constant: no merge.
            let mut out = self.clone();
            out.add_scaled_to(other, k);
            return out;
        }
        Affine {
            constant: self.constant.add(&other.constant.mul(k)),
            terms: merge_scaled(&self.terms, &other.terms, k),
        }
    }

    /// `self += k · other`: a matrix product's step, which allocates only
    /// when `other` has terms (none when it is a constant, as selection
    /// matrices' and most subdivision matrices' entries are).
    pub fn add_scaled_to(&mut self, other: &Affine, k: &Num) {
        // Adding an exact zero to an exact constant changes nothing (an approximate one would make it approximate).
        if !(other.constant.is_zero() && other.constant.is_exact() && self.constant.is_exact() && k.is_exact()) {
            self.constant =
                if k.is_one() { self.constant.add(&other.constant) } else { self.constant.add(&other.constant.mul(k)) };
        }
        if other.terms.is_empty() {
            return;
        }
        self.terms = if self.terms.is_empty() && k.is_one() {
            other.terms.clone()
        } else {
            merge_scaled(&self.terms, &other.terms, k)
        };
    }

    /// `k · self`.
    pub fn scale(&self, k: &Num) -> Affine {
        if k.is_zero() {
            return Affine::constant(Num::zero());
        }
        Affine { constant: self.constant.mul(k), terms: self.terms.iter().map(|(v, c)| (*v, c.mul(k))).collect() }
    }

    /// `self · other`; an error unless one of them is constant.
    pub fn mul(&self, other: &Affine) -> Result<Affine, Nonlinear> {
        match (self.as_constant(), other.as_constant()) {
            (Some(a), _) => Ok(other.scale(a)),
            (_, Some(b)) => Ok(self.scale(b)),
            _ => Err(Nonlinear),
        }
    }

    /// Replaces every variable `x_v` by `subst(v)`.
    pub fn substitute(&self, subst: &dyn Fn(usize) -> Affine) -> Affine {
        let mut out = Affine::constant(self.constant.clone());
        for (v, c) in &self.terms {
            out.add_scaled_to(&subst(*v), c);
        }
        out
    }

    /// The value for variable values `values[var]`.
    pub fn eval(&self, values: &[f64]) -> f64 {
        self.terms.iter().fold(self.constant.to_f64(), |acc, (v, c)| acc + c.to_f64() * values[*v])
    }

    /// The value at exact variable values `x` (approximate where a value or
    /// a coefficient is).
    pub fn eval_num(&self, x: &[Num]) -> Num {
        self.terms.iter().fold(self.constant.clone(), |acc, (v, c)| acc.add(&c.mul(&x[*v])))
    }

    /// The constant and the `(variable, coefficient)` terms in floating
    /// point, for evaluating the same form many times.
    pub fn to_f64_terms(&self) -> (f64, Vec<(usize, f64)>) {
        (self.constant.to_f64(), self.terms.iter().map(|(v, c)| (*v, c.to_f64())).collect())
    }

    /// A displayable view that prints variables with the given names.
    pub fn display<'a>(&'a self, names: &'a [String]) -> AffineDisplay<'a> {
        AffineDisplay { form: self, names }
    }
}

impl ExprValue for Affine {
    fn from_num(n: &Num) -> Affine {
        Affine::constant(n.clone())
    }
    fn plus(&self, other: &Affine) -> Affine {
        self.add(other)
    }
    fn minus(&self, other: &Affine) -> Affine {
        self.sub(other)
    }
    fn times(&self, other: &Affine) -> Result<Affine, ExprError> {
        self.mul(other).map_err(|_| ExprError::Nonlinear)
    }
    fn divide(&self, other: &Affine) -> Result<Affine, ExprError> {
        let d = other.as_constant().ok_or(ExprError::BadDivision)?;
        let inv = Num::one().div(d).ok_or(ExprError::BadDivision)?;
        Ok(self.scale(&inv))
    }
    fn root(&self) -> Result<Affine, ExprError> {
        let c = self.as_constant().ok_or(ExprError::BadSqrt)?;
        c.sqrt().map(Affine::constant).ok_or(ExprError::BadSqrt)
    }
}

/// Prints an [`Affine`] as `1 - a - b`, `3/16`, `a/2 + 2*b`.
pub struct AffineDisplay<'a> {
    form: &'a Affine,
    names: &'a [String],
}

impl fmt::Display for AffineDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        if !self.form.constant.is_zero() || self.form.terms.is_empty() {
            write!(f, "{}", self.form.constant)?;
            first = false;
        }
        for (v, c) in &self.form.terms {
            let name = self.names.get(*v).map_or("?", String::as_str);
            let negative = c.is_negative();
            match (first, negative) {
                (true, true) => write!(f, "-")?,
                (true, false) => {}
                (false, true) => write!(f, " - ")?,
                (false, false) => write!(f, " + ")?,
            }
            first = false;
            let magnitude = c.abs();
            let write_ratio =
                |f: &mut fmt::Formatter<'_>, n: &dyn fmt::Display, n_one: bool, d: &dyn fmt::Display, d_one: bool| {
                    match (n_one, d_one) {
                        (true, true) => write!(f, "{name}"),
                        (false, true) => write!(f, "{n}*{name}"),
                        (true, false) => write!(f, "{name}/{d}"),
                        (false, false) => write!(f, "{n}*{name}/{d}"),
                    }
                };
            if let Some((n, d)) = magnitude.as_small_rational() {
                write_ratio(f, &n, n == 1, &d, d == 1)?;
            } else if let Some(r) = magnitude.as_rational() {
                let (n, d) = (r.numer(), r.denom());
                write_ratio(f, n, n.is_one(), d, d.is_one())?;
            } else {
                write!(f, "({magnitude})*{name}")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        vec!["a".into(), "b".into()]
    }

    #[test]
    fn prints_like_the_paper() {
        let one = Affine::constant(Num::one());
        let e = one.sub(&Affine::var(0)).sub(&Affine::var(1));
        assert_eq!(e.display(&names()).to_string(), "1 - a - b");
        let half_a = Affine::var(0).scale(&Num::frac(1, 2));
        assert_eq!(half_a.display(&names()).to_string(), "a/2");
        let e = Affine::var(1).scale(&Num::frac(-3, 4));
        assert_eq!(e.display(&names()).to_string(), "-3*b/4");
        assert_eq!(Affine::constant(Num::zero()).display(&names()).to_string(), "0");
    }

    #[test]
    fn terms_cancel() {
        let e = Affine::var(0).add(&Affine::var(1)).sub(&Affine::var(0));
        assert_eq!(e, Affine::var(1));
        assert!(Affine::var(0).sub(&Affine::var(0)).is_zero());
    }

    /// The in-place step of a product is the form `add_scaled` makes, exact
    /// stays exact and an approximate constant makes the sum approximate.
    #[test]
    fn adding_in_place_is_adding() {
        let forms = [
            Affine::zero(),
            Affine::one(),
            Affine::var(1),
            Affine::var(0).scale(&Num::frac(1, 4)).add(&Affine::constant(Num::frac(1, 2))),
            Affine::var(0).add(&Affine::var(1)).scale(&Num::frac(-1, 8)),
            Affine::constant(Num::Approx(0.0)),
            Affine::constant(Num::Approx(0.25)).add(&Affine::var(1)),
        ];
        for a in &forms {
            for b in &forms {
                for k in [Num::one(), Num::zero(), Num::frac(-1, 3), Num::Approx(0.5)] {
                    let mut c = a.clone();
                    c.add_scaled_to(b, &k);
                    let d = a.add_scaled(b, &k);
                    assert_eq!(c, d, "{a:?} + {k:?} {b:?}");
                    assert_eq!(c.constant.is_exact(), d.constant.is_exact(), "{a:?} + {k:?} {b:?}");
                }
            }
        }
        let mut c = Affine::constant(Num::frac(1, 2));
        c.add_scaled_to(&Affine::constant(Num::Approx(0.0)), &Num::one());
        assert!(!c.constant.is_exact());
    }

    #[test]
    fn products_must_be_linear() {
        assert!(Affine::var(0).mul(&Affine::var(1)).is_err());
        let two = Affine::constant(Num::int(2));
        assert_eq!(two.mul(&Affine::var(0)).unwrap(), Affine::var(0).scale(&Num::int(2)));
    }
}
