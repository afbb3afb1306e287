//! Colours of a deterministic evaluation (`--colour state|level|map`): a
//! colour coordinate in `[0, 1]` per vertex, which a palette turns into a
//! colour.
//!
//! - **map**: as the chaos game colours its points: each map of the path
//!   from the root to the cell moves the coordinate towards the map's
//!   colour ([`RandomSettings::colours`], else spread over the arrows) by the
//!   colour speed `s`, the map nearest the root last — the path `e₁ … e_k`
//!   gives `Σ s (1 − s)^{j−1} c(e_j) + (1 − s)^k / 2`.
//! - **state**: the state of the cell that makes the vertex, by its index
//!   among the states.
//! - **level**: the coarsest depth at which the vertex is already there
//!   (a corner of a cell `j` subdivisions down), over the depth: the
//!   subdivision's hierarchy made visible.

use std::collections::HashMap;

use petgraph::graph::EdgeIndex;

use super::prepared::Evaluator;
use super::sampling::{RandomSettings, arrow_colour};
use super::settings::{Depth, EvalError};
use crate::automaton::{ArrowKind, Automaton};
use crate::geometry::Shape;

/// What colours the vertices of a deterministic evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Colouring {
    /// The state of the cell that makes the vertex.
    State,
    /// The coarsest subdivision level at which the vertex is there.
    Level,
    /// The maps from the root to the cell, as the chaos game colours.
    Map,
}

/// The colour of cells as the recursion goes down: per arrow its colour
/// coordinate, the speed, the states' count; the vertices' colours so far.
pub(super) struct CellColours<'a> {
    mode: Colouring,
    arrows: &'a HashMap<EdgeIndex, f64>,
    speed: f64,
    states: usize,
    /// Per vertex, its coordinate.
    pub(super) out: Vec<f32>,
}

impl CellColours<'_> {
    /// One map down: `colour` is `(sum so far, weight of the next map)`.
    pub(super) fn step(&self, arrow: EdgeIndex, [sum, weight]: [f64; 2]) -> [f64; 2] {
        let c = self.arrows.get(&arrow).copied().unwrap_or(0.5);
        [sum + weight * self.speed * c, weight * (1.0 - self.speed)]
    }

    /// The colour of a leaf cell of `state` reached with `colour`.
    pub(super) fn leaf(&self, state: usize, [sum, weight]: [f64; 2]) -> f32 {
        match self.mode {
            Colouring::State => (state as f64 / (self.states.max(2) - 1) as f64) as f32,
            Colouring::Map | Colouring::Level => (sum + weight * 0.5) as f32,
        }
    }
}

impl Evaluator {
    /// Evaluates at the fixed depth and colours every vertex by `mode`
    /// (see the module's documentation): the shape and one coordinate in
    /// `[0, 1]` per vertex. Faces are meshed as welded cell polygons (the
    /// cells' colours need the cells); arrow colours and the colour speed
    /// come from `random` (the chaos game's settings).
    ///
    /// # Errors
    /// A depth given by a tolerance (colours need a fixed depth), or the evaluation's errors.
    pub fn evaluate_coloured(
        &mut self,
        automaton: &Automaton<f64>,
        mode: Colouring,
        random: &RandomSettings,
    ) -> Result<(Shape, Vec<f32>), EvalError> {
        let Depth::Fixed(k) = self.settings.depth else {
            return Err(EvalError::Unsupported("colours by state, level or map need a fixed depth".into()));
        };
        let subdivision: Vec<_> = automaton.arrows().filter(|(_, a)| a.kind == ArrowKind::Subdivision).collect();
        let arrows: HashMap<EdgeIndex, f64> = subdivision
            .iter()
            .enumerate()
            .map(|(i, (e, a))| (*e, arrow_colour(random, i, subdivision.len(), &a.name)))
            .collect();
        let mut cells = CellColours {
            mode,
            arrows: &arrows,
            speed: random.colour_speed,
            states: self.plan.states.iter().flatten().count(),
            out: Vec::new(),
        };
        let (shape, mut colours) = if self.meshes() || self.polygon_faces() {
            let mut shape = Shape::default();
            self.polygons_coloured(k, &mut shape, Some(&mut cells), None)?;
            let n = shape.vertex_count();
            cells.out.resize(n, 0.5);
            (shape, cells.out)
        } else {
            let shape = self.evaluate()?;
            let colours = self.sample_colours(&shape, k, &mut cells);
            (shape, colours)
        };
        if mode == Colouring::Level {
            colours = self.levels(&shape, k)?;
        }
        Ok((shape, colours))
    }

    /// Curves and points: the colour of each sample, in the order the
    /// pieces' samples are made (a depth-first walk), matched to the
    /// shape's vertices; a vertex no sample made (a curve's end point) takes
    /// the colour of the one before.
    fn sample_colours(&self, shape: &Shape, k: usize, cells: &mut CellColours<'_>) -> Vec<f32> {
        let d = self.pieces.dim;
        let mut samples = Vec::new();
        let mut points = Vec::new();
        for (pi, piece) in self.pieces.pieces.iter().enumerate() {
            self.walk(piece.state, k, [0.0, 1.0], cells, &mut samples);
            let mut out = Vec::new();
            self.fill_piece(pi, k, &mut out);
            points.extend(out);
        }
        let mut colours = Vec::with_capacity(shape.vertex_count());
        let mut at = 0;
        for v in shape.positions.chunks_exact(shape.dim.max(1)) {
            let same = points
                .get(at * d..(at + 1) * d)
                .is_some_and(|p| p.iter().zip(v).all(|(a, b)| a.to_bits() == b.to_bits()));
            let c = if same {
                at += 1;
                samples[at - 1]
            } else {
                colours.last().copied().unwrap_or(0.5)
            };
            colours.push(c);
        }
        colours
    }

    /// The colours of the samples of a depth-`r` subtree of `state`, depth first.
    fn walk(&self, state: usize, r: usize, colour: [f64; 2], cells: &CellColours<'_>, out: &mut Vec<f32>) {
        let sp = self.plan.state(state);
        if r == 0 {
            let c = cells.leaf(state, colour);
            out.extend(std::iter::repeat_n(c, sp.samples.len()));
            return;
        }
        for (e, t, _) in &sp.children {
            self.walk(*t, r - 1, cells.step(*e, colour), cells, out);
        }
    }

    /// Level colours: each vertex's coarsest depth `j ≤ k` whose evaluation
    /// has a vertex at the same place (to [`crate::algebra::tolerance::SAME_POINT`] of the
    /// shape's size), over `k`.
    fn levels(&mut self, shape: &Shape, k: usize) -> Result<Vec<f32>, EvalError> {
        let scale = shape.positions.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let q = crate::algebra::tolerance::SAME_POINT * scale;
        let key = |p: &[f64]| -> Vec<i64> { p.iter().map(|x| (x / q).round() as i64).collect() };
        let mut level: HashMap<Vec<i64>, usize> = HashMap::new();
        for j in (0..k).rev() {
            self.set_depth(Depth::Fixed(j))?;
            let coarse = self.evaluate()?;
            for p in coarse.positions.chunks_exact(coarse.dim.max(1)) {
                level.insert(key(p), j);
            }
        }
        self.set_depth(Depth::Fixed(k))?;
        let d = shape.dim.max(1);
        let found = |p: &[f64]| -> usize {
            let base = key(p);
            let mut best = k;
            for n in 0..3usize.pow(d as u32) {
                let mut cell = base.clone();
                let mut m = n;
                for x in &mut cell {
                    *x += (m % 3) as i64 - 1;
                    m /= 3;
                }
                if let Some(&j) = level.get(&cell) {
                    best = best.min(j);
                }
            }
            best
        };
        Ok(shape.positions.chunks_exact(d).map(|p| found(p) as f32 / k.max(1) as f32).collect())
    }
}
