//! Gauss-Jordan elimination over exact rationals on sparse rows, and the
//! smallest conflicting subset of an inconsistent system.

use std::collections::HashMap;

use num_rational::BigRational;
use num_traits::{One, Zero};

use super::equations::Equation;
use super::error::SolveError;
use crate::algebra::{Num, Surd};
use crate::design::Design;

/// A sparse row `Σ c_v x_v + constant = 0` with the set of input equations
/// it was combined from.
#[derive(Clone, Debug)]
pub(super) struct Row {
    /// `(variable, coefficient)`, by variable.
    pub(super) terms: Vec<(usize, BigRational)>,
    /// The constant term.
    pub(super) constant: Surd,
    origins: Vec<u64>,
}

impl Row {
    fn coeff(&self, var: usize) -> Option<&BigRational> {
        self.terms.binary_search_by_key(&var, |(v, _)| *v).ok().map(|i| &self.terms[i].1)
    }

    /// `self - k · other`.
    fn sub_scaled(&self, other: &Row, k: &BigRational) -> Row {
        let mut terms = Vec::with_capacity(self.terms.len() + other.terms.len());
        let (mut i, mut j) = (0, 0);
        while i < self.terms.len() || j < other.terms.len() {
            let left = self.terms.get(i).map(|t| t.0);
            let right = other.terms.get(j).map(|t| t.0);
            match (left, right) {
                (Some(a), Some(b)) if a == b => {
                    let c = &self.terms[i].1 - k * &other.terms[j].1;
                    if !c.is_zero() {
                        terms.push((a, c));
                    }
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a < b => {
                    terms.push(self.terms[i].clone());
                    i += 1;
                }
                (Some(a), None) => {
                    terms.push((a, self.terms[i].1.clone()));
                    i += 1;
                }
                (_, Some(b)) => {
                    terms.push((b, -(k * &other.terms[j].1)));
                    j += 1;
                }
                (None, None) => unreachable!(),
            }
        }
        let origins = self.origins.iter().zip(&other.origins).map(|(a, b)| a | b).collect();
        Row { terms, constant: self.constant.add_scaled(&other.constant, &-k), origins }
    }

    fn scale(&mut self, k: &BigRational) {
        for (_, c) in &mut self.terms {
            *c = &*c * k;
        }
        self.constant = self.constant.scale(k);
    }

    fn origin_list(&self) -> Vec<usize> {
        let mut out = Vec::new();
        for (w, bits) in self.origins.iter().enumerate() {
            for b in 0..64 {
                if bits >> b & 1 == 1 {
                    out.push(w * 64 + b);
                }
            }
        }
        out
    }
}

/// Incremental Gauss-Jordan elimination: rows stay fully reduced.
pub(super) struct Eliminator {
    /// The reduced rows.
    pub(super) rows: Vec<Row>,
    /// The row whose pivot each pivot variable is.
    pub(super) pivot_of: HashMap<usize, usize>,
    /// Pivot preference: lower keys become pivots first.
    key: Vec<(bool, usize)>,
}

impl Eliminator {
    fn new(key: Vec<(bool, usize)>) -> Eliminator {
        Eliminator { rows: Vec::new(), pivot_of: HashMap::new(), key }
    }

    /// Adds a row; returns the reduced row if it reads `0 = c ≠ 0`.
    fn insert(&mut self, mut row: Row) -> Result<(), Box<Row>> {
        let hits: Vec<(usize, BigRational)> =
            row.terms.iter().filter(|(v, _)| self.pivot_of.contains_key(v)).cloned().collect();
        for (v, c) in hits {
            row = row.sub_scaled(&self.rows[self.pivot_of[&v]], &c);
        }
        let Some(&(pivot, ref pc)) = row.terms.iter().min_by_key(|(v, _)| self.key[*v]) else {
            return if row.constant.is_zero() { Ok(()) } else { Err(Box::new(row)) };
        };
        let inv = BigRational::one() / pc;
        row.scale(&inv);
        for other in &mut self.rows {
            if let Some(c) = other.coeff(pivot).cloned() {
                *other = other.sub_scaled(&row, &c);
            }
        }
        self.pivot_of.insert(pivot, self.rows.len());
        self.rows.push(row);
        Ok(())
    }
}

fn to_row(eq: &Equation, index: usize, words: usize) -> Result<Row, SolveError> {
    let irrational = || SolveError::Irrational { equation: eq.label.to_string() };
    let terms = eq
        .form
        .terms()
        .iter()
        .map(|(v, c)| Ok((*v, c.as_rational().ok_or_else(irrational)?)))
        .collect::<Result<_, _>>()?;
    let constant = match eq.form.constant_term() {
        Num::Exact(s) => s.clone(),
        Num::Approx(_) => return Err(irrational()),
    };
    let mut origins = vec![0u64; words];
    origins[index / 64] |= 1 << (index % 64);
    Ok(Row { terms, constant, origins })
}

fn inconsistent(rows: &[&Row], key: &[(bool, usize)]) -> bool {
    let mut e = Eliminator::new(key.to_vec());
    rows.iter().any(|r| e.insert((*r).clone()).is_err())
}

/// The reduced system of `eqs`, or the smallest conflicting subset found.
pub(super) fn eliminate(design: &Design, eqs: &[Equation]) -> Result<Eliminator, SolveError> {
    let words = eqs.len().div_ceil(64).max(1);
    let key: Vec<(bool, usize)> = design.variables().iter().enumerate().map(|(i, v)| (v.named, i)).collect();
    let rows: Vec<Row> = eqs.iter().enumerate().map(|(i, e)| to_row(e, i, words)).collect::<Result<_, _>>()?;
    let mut elim = Eliminator::new(key.clone());
    for row in &rows {
        if let Err(bad) = elim.insert(row.clone()) {
            let mut subset: Vec<usize> = bad.origin_list();
            // Deletion filter: drop every equation whose removal keeps the conflict.
            let mut i = 0;
            while i < subset.len() {
                let trial: Vec<&Row> =
                    subset.iter().enumerate().filter(|(k, _)| *k != i).map(|(_, &e)| &rows[e]).collect();
                if inconsistent(&trial, &key) {
                    subset.remove(i);
                } else {
                    i += 1;
                }
            }
            return Err(SolveError::Inconsistent {
                conflicts: subset.iter().map(|&e| eqs[e].label.to_string()).collect(),
            });
        }
    }
    Ok(elim)
}
