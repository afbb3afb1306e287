//! The automaton: barycentric states, arrows carrying matrices, and the
//! path equalities (constraints) between them.

use std::collections::HashMap;
use std::fmt;

use nalgebra::DMatrix;
use petgraph::stable_graph::{EdgeIndex, NodeIndex, StableDiGraph};
use petgraph::visit::EdgeRef;

use crate::algebra::{Affine, Expr, ExprError, ExprValue, Num};
use crate::space::State;

/// What a matrix entry must support to be multiplied along paths.
///
/// Implemented by `f64` (instantiated automata) and by [`Affine`] (automata
/// whose entries depend on unknowns or parameters, for the solver).
pub trait Entry: nalgebra::Scalar + ExprValue {
    /// The additive identity.
    fn zero() -> Self;
    /// The multiplicative identity.
    fn one() -> Self;
    /// Whether this entry is (exactly) zero, to skip work in products.
    fn is_zero_entry(&self) -> bool;
    /// Whether this entry is (exactly) one: a product by it is a copy
    /// (selection matrices, the common factor of constraint paths).
    fn is_one_entry(&self) -> bool;
    /// `self + a · b`, the step of a matrix product.
    ///
    /// # Errors
    /// [`ExprError::Nonlinear`] when `a` and `b` both depend on unknowns.
    fn add_product(&self, a: &Self, b: &Self) -> Result<Self, ExprError> {
        let term = if b.is_one_entry() { a.clone() } else { a.times(b)? };
        Ok(if self.is_zero_entry() { term } else { self.plus(&term) })
    }
    /// `self += a · b`, in place where the type can.
    ///
    /// # Errors
    /// As [`Entry::add_product`].
    fn add_product_to(&mut self, a: &Self, b: &Self) -> Result<(), ExprError> {
        *self = self.add_product(a, b)?;
        Ok(())
    }
}

impl Entry for f64 {
    fn zero() -> f64 {
        0.0
    }
    fn one() -> f64 {
        1.0
    }
    fn is_zero_entry(&self) -> bool {
        *self == 0.0
    }
    fn is_one_entry(&self) -> bool {
        *self == 1.0
    }
}

impl Entry for Affine {
    fn zero() -> Affine {
        Affine::constant(Num::zero())
    }
    fn one() -> Affine {
        Affine::constant(Num::one())
    }
    fn is_zero_entry(&self) -> bool {
        self.is_zero()
    }
    fn is_one_entry(&self) -> bool {
        self.is_one()
    }
    fn add_product(&self, a: &Affine, b: &Affine) -> Result<Affine, ExprError> {
        let mut out = self.clone();
        out.add_product_to(a, b)?;
        Ok(out)
    }
    fn add_product_to(&mut self, a: &Affine, b: &Affine) -> Result<(), ExprError> {
        // One merge of sorted terms, no product formed apart (exact: the same form).
        match (a.as_constant(), b.as_constant()) {
            (_, Some(k)) => self.add_scaled_to(a, k),
            (Some(k), _) => self.add_scaled_to(b, k),
            _ => return Err(ExprError::Nonlinear),
        }
        Ok(())
    }
}

/// `a · b` for matrices of any [`Entry`] type.
///
/// # Errors
/// [`ExprError::Nonlinear`] when two entries that both depend on unknowns
/// would be multiplied.
pub fn mat_mul<E: Entry>(a: &DMatrix<E>, b: &DMatrix<E>) -> Result<DMatrix<E>, ExprError> {
    debug_assert_eq!(a.ncols(), b.nrows());
    let mut out = DMatrix::from_element(a.nrows(), b.ncols(), E::zero());
    for i in 0..a.nrows() {
        for k in 0..a.ncols() {
            let aik = &a[(i, k)];
            if aik.is_zero_entry() {
                continue;
            }
            for j in 0..b.ncols() {
                let bkj = &b[(k, j)];
                if bkj.is_zero_entry() {
                    continue;
                }
                out[(i, j)].add_product_to(aik, bkj)?;
            }
        }
    }
    Ok(out)
}

/// The two kinds of arrows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ArrowKind {
    /// A subdivision map `T_i`: part of the IFS, generates the attractor.
    Subdivision,
    /// An embedding `b_i` of a boundary cell into the cell it bounds.
    Boundary,
}

impl ArrowKind {
    /// The keyword used in automaton files.
    pub fn keyword(self) -> &'static str {
        match self {
            ArrowKind::Subdivision => "subdivision",
            ArrowKind::Boundary => "boundary",
        }
    }
}

/// An arrow from state `A` to state `B`: the matrix maps `B`-coordinates into
/// `A`-coordinates (`λ_A = M λ_B`), so it has shape `dim(A) × dim(B)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arrow<E: Entry> {
    /// Unique name within the automaton.
    pub name: String,
    /// Subdivision or boundary.
    pub kind: ArrowKind,
    /// The matrix, `dim(from) × dim(to)`, column-stochastic once solved.
    pub matrix: DMatrix<E>,
}

/// How the two sides of a constraint are compared.
#[derive(Clone, Debug, PartialEq)]
pub enum Relation {
    /// Two paths with the same start and end states have equal products.
    Paths {
        /// Left path, arrows in order.
        lhs: Vec<EdgeIndex>,
        /// Right path, arrows in order.
        rhs: Vec<EdgeIndex>,
    },
    /// Two expressions in matrix entries and parameters are equal
    /// (symmetries, pinned entries).
    Entries {
        /// Left side.
        lhs: Expr,
        /// Right side.
        rhs: Expr,
    },
}

/// A named equation of a constraint group.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// The group it belongs to (`adjacency`, `incidence`, `symmetry`, ...).
    pub group: String,
    /// The equation as the user wrote it.
    pub text: String,
    /// What it states.
    pub relation: Relation,
}

impl fmt::Display for Constraint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.group, self.text)
    }
}

/// Errors building an automaton.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AutomatonError {
    /// Two states or two arrows share a name.
    #[error("the name `{0}` is used twice")]
    DuplicateName(String),
    /// A matrix does not have the shape `dim(from) × dim(to)`.
    #[error(
        "arrow `{arrow}` goes from `{from}` (dim {rows}) to `{to}` (dim {cols}), so its matrix must be {rows}×{cols}, not {got_rows}×{got_cols}"
    )]
    Shape {
        /// Arrow name.
        arrow: String,
        /// Source state.
        from: String,
        /// Target state.
        to: String,
        /// Expected rows.
        rows: usize,
        /// Expected columns.
        cols: usize,
        /// Actual rows.
        got_rows: usize,
        /// Actual columns.
        got_cols: usize,
    },
    /// Consecutive arrows of a path do not chain.
    #[error("in `{path}`, `{first}` ends at `{end}` but `{second}` starts at `{start}`")]
    Broken {
        /// The path text.
        path: String,
        /// The first arrow.
        first: String,
        /// Where it ends.
        end: String,
        /// The next arrow.
        second: String,
        /// Where it starts.
        start: String,
    },
    /// The two sides of an equation start or end at different states.
    #[error(
        "the two sides go {lhs_from} → {lhs_to} and {rhs_from} → {rhs_to}; they must start and end at the same states"
    )]
    Ends {
        /// Left start.
        lhs_from: String,
        /// Left end.
        lhs_to: String,
        /// Right start.
        rhs_from: String,
        /// Right end.
        rhs_to: String,
    },
    /// A path with no arrow.
    #[error("a side of the equation has no arrow")]
    EmptyPath,
    /// A boundary arrow whose matrix is not an embedding.
    #[error("boundary arrow `{0}` is not an embedding (its constant matrix must have full column rank)")]
    NotEmbedding(String),
}

/// An automaton (graph-directed IFS with boundary arrows) whose matrices have
/// entries of type `E`.
///
/// The same structure holds affine expressions for the solver
/// (`Automaton<Affine>`) and numbers after instantiation (`Automaton<f64>`):
/// [`Automaton::map_matrices`] turns one into the other, keeping every index.
#[derive(Clone, Debug)]
pub struct Automaton<E: Entry> {
    /// Name (from the file or generator).
    pub name: String,
    graph: StableDiGraph<State, Arrow<E>>,
    states_by_name: HashMap<String, NodeIndex>,
    arrows_by_name: HashMap<String, EdgeIndex>,
    constraints: Vec<Constraint>,
}

impl<E: Entry> Automaton<E> {
    /// An empty automaton.
    pub fn new(name: impl Into<String>) -> Automaton<E> {
        Automaton {
            name: name.into(),
            graph: StableDiGraph::new(),
            states_by_name: HashMap::new(),
            arrows_by_name: HashMap::new(),
            constraints: Vec::new(),
        }
    }

    /// Adds a state.
    ///
    /// # Errors
    /// [`AutomatonError::DuplicateName`] if a state of that name exists.
    pub fn add_state(&mut self, state: State) -> Result<NodeIndex, AutomatonError> {
        if self.states_by_name.contains_key(&state.name) {
            return Err(AutomatonError::DuplicateName(state.name));
        }
        let name = state.name.clone();
        let id = self.graph.add_node(state);
        self.states_by_name.insert(name, id);
        Ok(id)
    }

    /// Adds an arrow `from → to`.
    ///
    /// # Errors
    /// A duplicate name, or a matrix that is not `dim(from) × dim(to)`.
    pub fn add_arrow(&mut self, from: NodeIndex, to: NodeIndex, arrow: Arrow<E>) -> Result<EdgeIndex, AutomatonError> {
        if self.arrows_by_name.contains_key(&arrow.name) {
            return Err(AutomatonError::DuplicateName(arrow.name));
        }
        let (a, b) = (&self.graph[from], &self.graph[to]);
        if arrow.matrix.shape() != (a.dim, b.dim) {
            return Err(AutomatonError::Shape {
                arrow: arrow.name.clone(),
                from: a.name.clone(),
                to: b.name.clone(),
                rows: a.dim,
                cols: b.dim,
                got_rows: arrow.matrix.nrows(),
                got_cols: arrow.matrix.ncols(),
            });
        }
        let name = arrow.name.clone();
        let id = self.graph.add_edge(from, to, arrow);
        self.arrows_by_name.insert(name, id);
        Ok(id)
    }

    /// Adds a constraint after checking that both sides are chained paths
    /// with the same ends (for path relations).
    ///
    /// # Errors
    /// A broken path, sides with different ends, or an empty side.
    pub fn add_constraint(&mut self, constraint: Constraint) -> Result<(), AutomatonError> {
        if let Relation::Paths { lhs, rhs } = &constraint.relation {
            let (a0, a1) = self.path_ends(lhs, &constraint.text)?;
            let (b0, b1) = self.path_ends(rhs, &constraint.text)?;
            if a0 != b0 || a1 != b1 {
                return Err(AutomatonError::Ends {
                    lhs_from: self.graph[a0].name.clone(),
                    lhs_to: self.graph[a1].name.clone(),
                    rhs_from: self.graph[b0].name.clone(),
                    rhs_to: self.graph[b1].name.clone(),
                });
            }
        }
        self.constraints.push(constraint);
        Ok(())
    }

    fn path_ends(&self, path: &[EdgeIndex], text: &str) -> Result<(NodeIndex, NodeIndex), AutomatonError> {
        let first = *path.first().ok_or(AutomatonError::EmptyPath)?;
        let (start, mut end) = self.arrow_ends(first);
        for pair in path.windows(2) {
            let (s, e) = self.arrow_ends(pair[1]);
            if s != end {
                return Err(AutomatonError::Broken {
                    path: text.to_string(),
                    first: self.graph[pair[0]].name.clone(),
                    end: self.graph[end].name.clone(),
                    second: self.graph[pair[1]].name.clone(),
                    start: self.graph[s].name.clone(),
                });
            }
            end = e;
        }
        Ok((start, end))
    }

    /// The state called `name`.
    pub fn state_id(&self, name: &str) -> Option<NodeIndex> {
        self.states_by_name.get(name).copied()
    }

    /// The arrow called `name`.
    pub fn arrow_id(&self, name: &str) -> Option<EdgeIndex> {
        self.arrows_by_name.get(name).copied()
    }

    /// The state at `id`.
    pub fn state(&self, id: NodeIndex) -> &State {
        &self.graph[id]
    }

    /// The arrow at `id`.
    pub fn arrow(&self, id: EdgeIndex) -> &Arrow<E> {
        &self.graph[id]
    }

    /// The arrow at `id`, mutably (its matrix shape must not change).
    pub fn arrow_mut(&mut self, id: EdgeIndex) -> &mut Arrow<E> {
        &mut self.graph[id]
    }

    /// `(from, to)` of arrow `id`.
    pub fn arrow_ends(&self, id: EdgeIndex) -> (NodeIndex, NodeIndex) {
        self.graph.edge_endpoints(id).expect("arrow index from this automaton")
    }

    /// All states, in insertion order.
    pub fn states(&self) -> impl Iterator<Item = (NodeIndex, &State)> + '_ {
        self.graph.node_indices().map(|i| (i, &self.graph[i]))
    }

    /// All arrows, in insertion order.
    pub fn arrows(&self) -> impl Iterator<Item = (EdgeIndex, &Arrow<E>)> + '_ {
        self.graph.edge_indices().map(|i| (i, &self.graph[i]))
    }

    /// Whether subdivision arrow `id` can occur more than once on a path: it
    /// lies on a cycle of subdivision arrows. Only those are iterated, so
    /// only their spectra matter for convergence (an arrow out of a root that
    /// nothing enters, like a mesh's patch selections, is applied once).
    pub fn on_cycle(&self, id: EdgeIndex) -> bool {
        let (from, to) = self.arrow_ends(id);
        let mut seen = vec![false; self.graph.node_count()];
        let mut stack = vec![to];
        while let Some(s) = stack.pop() {
            if s == from {
                return true;
            }
            if std::mem::replace(&mut seen[s.index()], true) {
                continue;
            }
            stack.extend(self.graph.edges(s).filter(|e| e.weight().kind == ArrowKind::Subdivision).map(|e| e.target()));
        }
        false
    }

    /// The arrows leaving `state` of the given kind, in insertion order.
    pub fn outgoing(&self, state: NodeIndex, kind: ArrowKind) -> Vec<EdgeIndex> {
        let mut out: Vec<EdgeIndex> =
            self.graph.edges(state).filter(|e| e.weight().kind == kind).map(|e| e.id()).collect();
        out.sort();
        out
    }

    /// The constraints, in file order.
    pub fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    /// The product of the matrices along `path`, in path order.
    ///
    /// # Errors
    /// [`ExprError::Nonlinear`] when two factors depend on unknowns.
    pub fn product(&self, path: &[EdgeIndex]) -> Result<DMatrix<E>, ExprError> {
        let mut iter = path.iter();
        let first = &self.graph[*iter.next().expect("paths are checked to be non-empty")].matrix;
        let Some(second) = iter.next() else { return Ok(first.clone()) };
        let mut acc = mat_mul(first, &self.graph[*second].matrix)?;
        for id in iter {
            acc = mat_mul(&acc, &self.graph[*id].matrix)?;
        }
        Ok(acc)
    }

    /// The same automaton with every matrix transformed by `f` (indices kept).
    ///
    /// # Errors
    /// The first error `f` returns.
    pub fn map_matrices<F: Entry, Err>(
        &self,
        mut f: impl FnMut(EdgeIndex, &Arrow<E>) -> Result<DMatrix<F>, Err>,
    ) -> Result<Automaton<F>, Err> {
        let mut first_error = None;
        let graph = self.graph.map(
            |_, s| s.clone(),
            |id, a| {
                let matrix = match f(id, a) {
                    Ok(m) => m,
                    Err(e) => {
                        first_error.get_or_insert(e);
                        DMatrix::from_element(0, 0, F::zero())
                    }
                };
                Arrow { name: a.name.clone(), kind: a.kind, matrix }
            },
        );
        if let Some(e) = first_error {
            return Err(e);
        }
        Ok(Automaton {
            name: self.name.clone(),
            graph,
            states_by_name: self.states_by_name.clone(),
            arrows_by_name: self.arrows_by_name.clone(),
            constraints: self.constraints.clone(),
        })
    }

    /// [`Automaton::map_matrices`] for a map that cannot fail, the matrices
    /// computed on the pool's threads.
    pub fn par_map_matrices<F: Entry + Send>(&self, f: impl Fn(&Arrow<E>) -> DMatrix<F> + Sync) -> Automaton<F>
    where
        E: Sync,
    {
        use rayon::prelude::*;
        let arrows: Vec<(EdgeIndex, &Arrow<E>)> = self.arrows().collect();
        let mut matrices: HashMap<EdgeIndex, DMatrix<F>> =
            arrows.par_iter().map(|(id, arrow)| (*id, f(arrow))).collect::<Vec<_>>().into_iter().collect();
        // Every arrow's matrix was made above (`f` again for one missing would give the same).
        let mapped = self.map_matrices(|id, arrow| {
            Ok::<_, std::convert::Infallible>(matrices.remove(&id).unwrap_or_else(|| f(arrow)))
        });
        match mapped {
            Ok(automaton) => automaton,
            Err(never) => match never {},
        }
    }

    /// The path as text, `T0·b1`.
    pub fn path_text(&self, path: &[EdgeIndex]) -> String {
        path.iter().map(|id| self.graph[*id].name.as_str()).collect::<Vec<_>>().join("·")
    }
}

impl Automaton<f64> {
    /// Whether every boundary arrow is an embedding (full column rank).
    ///
    /// # Errors
    /// [`AutomatonError::NotEmbedding`] naming the first arrow that is not.
    pub fn check_embeddings(&self) -> Result<(), AutomatonError> {
        for (_, arrow) in self.arrows() {
            if arrow.kind == ArrowKind::Boundary {
                let rank =
                    crate::algebra::svd(&arrow.matrix, false).map_or(0, |s| s.rank(crate::algebra::tolerance::RANK));
                if rank < arrow.matrix.ncols() {
                    return Err(AutomatonError::NotEmbedding(arrow.name.clone()));
                }
            }
        }
        Ok(())
    }
}

/// The `rows × cols` selection matrix whose column `j` is the unit vector
/// `e_{select[j]}`: the embedding of a boundary cell whose control points are
/// the points `select` of the bounded cell.
pub fn selection<E: Entry>(rows: usize, select: &[usize]) -> DMatrix<E> {
    DMatrix::from_fn(rows, select.len(), |i, j| if select[j] == i { E::one() } else { E::zero() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::CellKind;

    #[test]
    fn path_products_follow_arrow_order() {
        let mut a: Automaton<f64> = Automaton::new("t");
        let e = a.add_state(State::new("e", 3, CellKind::Edge)).unwrap();
        let v = a.add_state(State::new("v", 2, CellKind::Vertex)).unwrap();
        let t0 = DMatrix::from_row_slice(3, 3, &[0.75, 0.25, 0.0, 0.25, 0.75, 0.75, 0.0, 0.0, 0.25]);
        let t0 = a.add_arrow(e, e, Arrow { name: "T0".into(), kind: ArrowKind::Subdivision, matrix: t0 });
        let b1 = a
            .add_arrow(e, v, Arrow { name: "b1".into(), kind: ArrowKind::Boundary, matrix: selection(3, &[1, 2]) })
            .unwrap();
        let p = a.product(&[t0.unwrap(), b1]).unwrap();
        assert_eq!(p, DMatrix::from_row_slice(3, 2, &[0.25, 0.0, 0.75, 0.75, 0.0, 0.25]));
        assert!(a.check_embeddings().is_ok());
        let bad = a.add_arrow(v, e, Arrow { name: "x".into(), kind: ArrowKind::Boundary, matrix: selection(3, &[0]) });
        assert!(matches!(bad, Err(AutomatonError::Shape { .. })));
    }
}
