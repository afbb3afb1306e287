//! The data of a design: where its variables come from, and the model that
//! projects it into modelling space.

use std::collections::HashMap;

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
    /// (a union of attractors, Schaefer et al. 2005 §2.2); nothing is shared or joined.
    Union,
    /// Pieces cut by explicit lists of control points (`Model::patches`):
    /// piece `i` is a cell of `roots[i % roots.len()]` on the points
    /// `patches[i]`; pieces share the points they both list and are welded
    /// (a mesh's patches over its vertices).
    Patches,
}

impl Layout {
    /// All layouts.
    pub const ALL: [Layout; 9] = [
        Layout::Single,
        Layout::Open,
        Layout::Closed,
        Layout::Grid,
        Layout::Torus,
        Layout::Frames,
        Layout::ClosedFrames,
        Layout::Union,
        Layout::Patches,
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
            Layout::Patches => "patches",
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
    /// Faces over a state's start set (indices into its points, at least 3
    /// each): every cell of the state at the leaves is meshed by these faces
    /// of its start points, and the images are welded; faces that two cells
    /// both make are kept once. A patch triangulated by its maps (Schaefer et al. 2005
    /// §3.2): with the limit points of the cell's vertices as start set, the
    /// mesh's vertices lie on the limit surface.
    pub start_faces: Vec<(String, Vec<Vec<usize>>)>,
    /// Faces of the control net, as indices into `points` (at least 3 each),
    /// for drawing it (`bcifs render --control`); empty: the net follows
    /// from the layout (a polygon, or the grid's quads).
    pub net: Vec<Vec<usize>>,
    /// Layout `patches`: the control points of each piece, as indices into `points`.
    pub patches: Vec<Vec<usize>>,
    /// The points are Y-up (a mesh read from an OBJ or OFF file, whose
    /// generated automaton keeps the file's axes: `up = "y"` in the file);
    /// otherwise Z-up, modelling space's convention (the default).
    pub y_up: bool,
}

impl Model {
    /// A model of one piece (layout `single`) on the root state `root`.
    ///
    /// ```
    /// use bcifs::{Layout, Model};
    /// let m = Model::new("e", vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![2.0, 0.0]]).with_layout(Layout::Open);
    /// assert_eq!(m.roots, ["e"]);
    /// ```
    pub fn new(root: impl Into<String>, points: Vec<Vec<f64>>) -> Model {
        Model {
            roots: vec![root.into()],
            points,
            layout: Layout::Single,
            step: None,
            grid: None,
            start: Vec::new(),
            start_faces: Vec::new(),
            net: Vec::new(),
            patches: Vec::new(),
            y_up: false,
        }
    }

    /// The same model, its points Y-up (`true`) or Z-up (`false`).
    pub fn with_y_up(mut self, y_up: bool) -> Model {
        self.y_up = y_up;
        self
    }

    /// The same model with several roots, taken in turn by the pieces.
    pub fn with_roots(mut self, roots: Vec<String>) -> Model {
        self.roots = roots;
        self
    }

    /// The same model with another layout.
    pub fn with_layout(mut self, layout: Layout) -> Model {
        self.layout = layout;
        self
    }

    /// The same model with a window step.
    pub fn with_step(mut self, step: usize) -> Model {
        self.step = Some(step);
        self
    }

    /// The same model with the faces of its control net.
    pub fn with_net(mut self, net: Vec<Vec<usize>>) -> Model {
        self.net = net;
        self
    }

    /// The same model with a `rows × cols` control grid (grid layouts).
    pub fn with_grid(mut self, rows: usize, cols: usize) -> Model {
        self.grid = Some((rows, cols));
        self
    }

    /// The same model cut into explicit pieces (layout `patches`): piece `i`
    /// is a cell of `roots[i]` on the control points `patches[i]`.
    pub fn with_patches(mut self, roots: Vec<String>, patches: Vec<Vec<usize>>) -> Model {
        self.layout = Layout::Patches;
        self.roots = roots;
        self.patches = patches;
        self
    }

    /// The same model with a start set for `state` (barycentric points).
    pub fn with_start(mut self, state: impl Into<String>, points: Vec<Vec<f64>>) -> Model {
        self.start.push((state.into(), points));
        self
    }

    /// The same model with faces over the start set of `state` (see [`Model::start_faces`]).
    pub fn with_start_faces(mut self, state: impl Into<String>, faces: Vec<Vec<usize>>) -> Model {
        self.start_faces.push((state.into(), faces));
        self
    }

    /// The root state of piece `i`.
    pub fn root(&self, i: usize) -> &str {
        &self.roots[i % self.roots.len().max(1)]
    }
}

/// Free text attached to the parts of a design: written as comments when
/// the design is printed as an automaton file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Docs {
    /// Above the whole file.
    pub header: String,
    /// Per state, by name.
    pub states: HashMap<String, String>,
    /// Per arrow, by name.
    pub arrows: HashMap<String, String>,
    /// Per constraint group, by name.
    pub groups: HashMap<String, String>,
    /// Per equation, by its text: a line above it in its group.
    pub equations: HashMap<String, String>,
    /// Above the parameters.
    pub parameters: String,
    /// Above the model.
    pub model: String,
}
