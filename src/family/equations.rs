//! The scalar equations of a design: every entry of every constraint (a
//! path's product viewed through its trailing selections, not multiplied
//! out), then every column sum.

use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use nalgebra::DMatrix;
use petgraph::stable_graph::EdgeIndex;

use super::error::SolveError;
use crate::algebra::{Affine, Env, Expr, ExprError};
use crate::automaton::{Automaton, Relation};
use crate::design::Design;

/// One scalar equation `form = 0`, with the text that names it.
#[derive(Clone, Debug)]
pub struct Equation {
    /// `group: text (row i, column j)` or `column sums: T0 column j`.
    pub label: Label,
    /// The affine form that must vanish.
    pub form: Affine,
}

/// The name of an [`Equation`], printed only when it is needed (an error names
/// it): a generated automaton has hundreds of thousands of scalar equations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Label {
    /// A constraint's name (`group: text`) as written.
    Constraint(Arc<str>),
    /// The entry `(row, column)` of a path constraint.
    Entry {
        /// The constraint's name.
        constraint: Arc<str>,
        /// The row.
        row: usize,
        /// The column.
        column: usize,
    },
    /// The column sum of an arrow's matrix.
    ColumnSum {
        /// The arrow.
        arrow: Arc<str>,
        /// The column.
        column: usize,
    },
}

impl fmt::Display for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Label::Constraint(c) => f.write_str(c),
            Label::Entry { constraint, row, column } => write!(f, "{constraint} (row {row}, column {column})"),
            Label::ColumnSum { arrow, column } => write!(f, "column sums: {arrow} column {column} sums to 1"),
        }
    }
}

struct Symbols<'a> {
    design: &'a Design,
}

impl Env<Affine> for Symbols<'_> {
    fn param(&self, name: &str) -> Option<Affine> {
        self.design.variable(name).map(Affine::var)
    }
    fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<Affine> {
        let a = &self.design.automaton();
        let m = &a.arrow(a.arrow_id(arrow)?).matrix;
        (row < m.nrows() && col < m.ncols()).then(|| m[(row, col)].clone())
    }
}

/// The scalar equations of a design: every entry of every constraint, then
/// every column sum. A constraint stated again (the same equation, in any
/// group) is counted once: 20,000 copies of one made 120,000 equations.
///
/// # Errors
/// [`SolveError::Nonlinear`] or [`SolveError::Eval`] naming the constraint.
pub fn equations(design: &Design) -> Result<Vec<Equation>, SolveError> {
    system(design).map(|s| s.equations)
}

/// A design's scalar equations and how many held without solving.
pub(super) struct System {
    pub(super) equations: Vec<Equation>,
    /// Distinct constraints.
    pub(super) constraints: usize,
    /// Scalar equations that hold identically (dropped from `equations`).
    pub(super) identities: usize,
}

/// [`equations`], with the counts a report gives.
pub(super) fn system(design: &Design) -> Result<System, SolveError> {
    use rayon::prelude::*;
    let a = &design.automaton();
    let picks = selections(a);
    let mut seen = std::collections::HashSet::new();
    let unique: Vec<_> = a.constraints().iter().filter(|c| seen.insert(c.text.as_str())).collect();
    // Each constraint's equations on the pool's threads, gathered in the constraints' order (the
    // first error in that order is the one reported).
    let per_constraint: Vec<Result<(Vec<Equation>, usize), SolveError>> = unique
        .par_iter()
        .map(|c| {
            let mut out = Vec::new();
            let mut compared = 0;
            match &c.relation {
                Relation::Paths { lhs, rhs } => {
                    let side = |path: &[_], side| {
                        product_view(a, path, &picks)
                            .map_err(|_| SolveError::Nonlinear { constraint: c.to_string(), side })
                    };
                    let (l, r) = (side(lhs, "left")?, side(rhs, "right")?);
                    let name: Arc<str> = c.to_string().into();
                    compared += l.matrix.nrows() * l.ncols();
                    for row in 0..l.matrix.nrows() {
                        for column in 0..l.ncols() {
                            let (l, r) = (l.at(row, column), r.at(row, column));
                            // Most entries of a constraint that holds are equal forms: no difference made.
                            if l == r {
                                continue;
                            }
                            let form = l.sub(r);
                            if !form.is_zero() {
                                let label = Label::Entry { constraint: name.clone(), row, column };
                                out.push(Equation { label, form });
                            }
                        }
                    }
                }
                Relation::Entries { lhs, rhs } => {
                    let env = Symbols { design };
                    let eval =
                        |e: &Expr| e.eval(&env).map_err(|error| SolveError::Eval { constraint: c.to_string(), error });
                    let form = eval(lhs)?.sub(&eval(rhs)?);
                    compared += 1;
                    if !form.is_zero() {
                        out.push(Equation { label: Label::Constraint(c.to_string().into()), form });
                    }
                }
            }
            Ok((out, compared))
        })
        .collect();
    let mut out = Vec::new();
    let mut compared = 0;
    for equations in per_constraint {
        let (equations, count) = equations?;
        out.extend(equations);
        compared += count;
    }
    for (_, arrow) in a.arrows() {
        let name: Arc<str> = arrow.name.as_str().into();
        compared += arrow.matrix.ncols();
        for column in 0..arrow.matrix.ncols() {
            let sum = arrow.matrix.column(column).iter().fold(Affine::zero(), |acc, e| acc.add(e));
            let form = sum.sub(&Affine::one());
            if !form.is_zero() {
                out.push(Equation { label: Label::ColumnSum { arrow: name.clone(), column }, form });
            }
        }
    }
    Ok(System { identities: compared - out.len(), constraints: unique.len(), equations: out })
}

/// The arrows whose matrices select columns (one entry exactly one in each
/// column, the others exactly zero: the boundary and turning arrows of a
/// generated automaton): the row each column picks.
fn selections(a: &Automaton<Affine>) -> HashMap<EdgeIndex, Vec<usize>> {
    use rayon::prelude::*;
    let arrows: Vec<_> = a.arrows().collect();
    arrows
        .par_iter()
        .filter_map(|(id, arrow)| {
            let m = &arrow.matrix;
            let pick = (0..m.ncols()).map(|j| {
                let column = m.column(j);
                let one = column.iter().position(Affine::is_one)?;
                column.iter().enumerate().all(|(i, e)| i == one || e.is_zero()).then_some(one)
            });
            Some((*id, pick.collect::<Option<Vec<usize>>>()?))
        })
        .collect()
}

/// A path's product as a matrix and the columns of it that its trailing
/// selections keep (composed, not multiplied out): entry `(i, j)` of the
/// product is the matrix's `(i, pick[j])`. A constraint `T0 b1 = T1 b0`
/// compares entries of `T0` and `T1` in place.
struct PathView<'a> {
    matrix: Cow<'a, DMatrix<Affine>>,
    pick: Option<Vec<usize>>,
}

impl PathView<'_> {
    fn ncols(&self) -> usize {
        self.pick.as_ref().map_or(self.matrix.ncols(), Vec::len)
    }

    fn at(&self, row: usize, column: usize) -> &Affine {
        &self.matrix[(row, self.pick.as_ref().map_or(column, |p| p[column]))]
    }
}

/// The [`PathView`] of `path`.
///
/// # Errors
/// A product of two matrices with unknowns.
fn product_view<'a>(
    a: &'a Automaton<Affine>,
    path: &[EdgeIndex],
    picks: &HashMap<EdgeIndex, Vec<usize>>,
) -> Result<PathView<'a>, ExprError> {
    let tail = path.iter().rev().take_while(|id| picks.contains_key(id)).count();
    let head = &path[..path.len() - tail];
    if tail == 0 || head.is_empty() {
        return Ok(PathView { matrix: Cow::Owned(a.product(path)?), pick: None });
    }
    let matrix = match head {
        [one] => Cow::Borrowed(&a.arrow(*one).matrix),
        _ => Cow::Owned(a.product(head)?),
    };
    let mut pick = picks[&path[path.len() - 1]].clone();
    for id in path[head.len()..path.len() - 1].iter().rev() {
        pick = pick.iter().map(|&j| picks[id][j]).collect();
    }
    Ok(PathView { matrix, pick: Some(pick) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{PolyMesh, Scheme};

    /// A path's view (trailing selections and turns composed, not multiplied
    /// out) has the entries of its product, on shipped automata with
    /// selections and on generated ones whose paths end in a boundary and a turn.
    #[test]
    fn a_path_view_is_its_product() {
        let cube = PolyMesh::cube();
        let mut designs: Vec<Design> =
            ["corner_cutting", "doo_sabin_quad", "koch"].map(|n| crate::format::builtin_design(n).unwrap()).into();
        for scheme in [Scheme::CatmullClark, Scheme::DooSabin] {
            designs.push(crate::schemes::mesh_automaton(&cube, scheme, None).unwrap());
        }
        let mut composed = 0;
        for design in &designs {
            let a = design.automaton();
            let picks = selections(a);
            assert!(!picks.is_empty(), "{}", design.name());
            for c in a.constraints() {
                let Relation::Paths { lhs, rhs } = &c.relation else { continue };
                for path in [lhs, rhs] {
                    let (view, product) = (product_view(a, path, &picks).unwrap(), a.product(path).unwrap());
                    assert_eq!(view.ncols(), product.ncols());
                    for (i, j) in (0..product.nrows()).flat_map(|i| (0..product.ncols()).map(move |j| (i, j))) {
                        assert_eq!(view.at(i, j), &product[(i, j)], "{}: {c} at ({i}, {j})", design.name());
                    }
                    composed += usize::from(path.iter().rev().take_while(|id| picks.contains_key(*id)).count() > 1);
                }
            }
        }
        assert!(composed > 0, "no path ends in two selections");
    }
}
