//! A design: the automaton of a file or generator before solving, whose
//! entries are affine in the unknowns and parameters, plus its model.

use std::collections::HashMap;

use crate::algebra::Affine;
use crate::automaton::Automaton;

/// Where a variable of the constraint system comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Origin {
    /// A parameter that appears in known matrices or entry equations.
    Parameter,
    /// The entry `arrow[row][col]` of an unknown matrix.
    Entry {
        /// Arrow name.
        arrow: String,
        /// Row, from 0.
        row: usize,
        /// Column, from 0.
        col: usize,
    },
}

/// A variable of the constraint system.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    /// The name it prints with: the user's parameter name, or `T0_1_0` for
    /// the unnamed entry `T0[1][0]`.
    pub name: String,
    /// Whether the user named it (named variables are kept free if possible).
    pub named: bool,
    /// What it stands for.
    pub origin: Origin,
}

/// How the pieces of a model are cut from its control points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// One piece: the first `dim(root)` control points.
    Single,
    /// An open curve: windows of `dim(root)` consecutive points, sliding by `step`.
    Open,
    /// A closed curve: like `Open`, wrapping around.
    Closed,
    /// A sheet: `w × w` windows of a `rows × cols` grid (`dim(root) = w²`), sliding by `step`.
    Grid,
    /// A torus: like `Grid`, wrapping around in both directions.
    Torus,
    /// An open polyline of 2D points; piece `i` is `(P_i, P_{i+1}, Q_i)` with
    /// the rotated frame point `Q_i = P_i + R90(P_{i+1} - P_i)` (normal-vector schemes).
    Frames,
    /// Like `Frames`, closing the polygon.
    ClosedFrames,
    /// Separate pieces: piece `i` takes the next `dim(root_i)` control points
    /// (a union of attractors, seed 001 §2.2); nothing is shared or joined.
    Union,
}

impl Layout {
    /// All layouts.
    pub const ALL: [Layout; 8] = [
        Layout::Single,
        Layout::Open,
        Layout::Closed,
        Layout::Grid,
        Layout::Torus,
        Layout::Frames,
        Layout::ClosedFrames,
        Layout::Union,
    ];

    /// The keyword used in automaton files.
    pub fn keyword(self) -> &'static str {
        match self {
            Layout::Single => "single",
            Layout::Open => "open",
            Layout::Closed => "closed",
            Layout::Grid => "grid",
            Layout::Torus => "torus",
            Layout::Frames => "frames",
            Layout::ClosedFrames => "closed-frames",
            Layout::Union => "union",
        }
    }
}

/// A projection of the root attractor into modelling space.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// The states whose attractors are drawn: piece `i` is a cell of
    /// `roots[i % roots.len()]` (one root for most models; a cycle of roots
    /// for sign-alternating schemes and unions of different automata).
    pub roots: Vec<String>,
    /// Control points, all of the same dimension (2 or 3).
    pub points: Vec<Vec<f64>>,
    /// How pieces are cut from the points.
    pub layout: Layout,
    /// Window step for curve and grid layouts (`None`: derived from the boundary).
    pub step: Option<usize>,
    /// `(rows, cols)` of the control grid for grid layouts.
    pub grid: Option<(usize, usize)>,
    /// Start sets: barycentric points per state, emitted at leaves instead
    /// of the kind's default (any compact start set converges to the attractor).
    pub start: Vec<(String, Vec<Vec<f64>>)>,
}

impl Model {
    /// The root state of piece `i`.
    pub fn root(&self, i: usize) -> &str {
        &self.roots[i % self.roots.len().max(1)]
    }
}

/// An automaton whose entries are affine in the variables of its constraint
/// system, as read from a file or made by a generator.
#[derive(Clone, Debug)]
pub struct Design {
    /// The automaton; unknown entries are variables, known entries may use parameters.
    pub automaton: Automaton<Affine>,
    /// The variables, indexed as in the affine entries.
    pub variables: Vec<Variable>,
    /// Default values of parameters, by name.
    pub defaults: HashMap<String, f64>,
    /// The parameter names in the order the file declares them.
    pub declared: Vec<String>,
    /// The model, if the file has one.
    pub model: Option<Model>,
    /// Free text describing the design.
    pub description: String,
}

impl Design {
    /// The variable called `name`.
    pub fn variable(&self, name: &str) -> Option<usize> {
        self.variables.iter().position(|v| v.name == name)
    }

    /// The names of all variables, indexed like them.
    pub fn variable_names(&self) -> Vec<String> {
        self.variables.iter().map(|v| v.name.clone()).collect()
    }
}
