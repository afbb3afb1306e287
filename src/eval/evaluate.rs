//! Evaluating a prepared automaton: into memory (reusing a shape's
//! buffers) or streamed to a sink; meshes for face roots, curves and
//! points otherwise.

use super::prepared::Evaluator;
use super::settings::{Depth, EvalError};
use super::surface::{mesh_into, mesh_stream};
use crate::geometry::{Shape, Sink};

/// Where an evaluation writes: a shape in memory (whose buffers the mesher
/// reuses), or a streaming sink.
enum Output<'a> {
    /// In memory, overwriting this shape.
    Memory(&'a mut Shape),
    /// Streamed in bounded batches.
    Stream(&'a mut dyn Sink),
}

impl Evaluator {
    /// Evaluates into memory.
    ///
    /// # Errors
    /// An output over the memory limit (with the estimate), or an unsupported combination.
    pub fn evaluate(&self) -> Result<Shape, EvalError> {
        let mut shape = Shape::default();
        self.evaluate_into(&mut shape)?;
        Ok(shape)
    }

    /// Evaluates into `shape`, reusing its buffers: re-evaluating a mesh of
    /// the same size (a parameter changed) allocates nothing.
    ///
    /// # Errors
    /// As [`Evaluator::evaluate`].
    pub fn evaluate_into(&self, shape: &mut Shape) -> Result<(), EvalError> {
        // A mesh's tolerance is a uniform depth: its size is known before any work.
        let depth = match self.settings.depth {
            Depth::Fixed(k) => Some(k),
            Depth::Tolerance(eps) if self.polygon_faces() || self.meshes() => {
                Some(self.depth_for_tolerance_within(eps, self.settings.memory_limit)?)
            }
            Depth::Tolerance(_) => None,
        };
        if let Some(k) = depth {
            let estimate = self.estimate_bytes(k);
            if estimate > self.settings.memory_limit as u128 {
                return Err(EvalError::TooLarge { estimate, limit: self.settings.memory_limit });
            }
        }
        // The mesher overwrites the shape's buffers in place; the other outputs start afresh.
        if !self.meshes() {
            *shape = Shape::default();
        }
        self.run(Output::Memory(shape), depth)
    }

    /// Evaluates into any sink, streaming: memory stays bounded whatever
    /// the depth. The caller finishes the sink (an
    /// [`crate::export::ObjWriter`] by its consuming `finish`).
    ///
    /// # Errors
    /// A write error of the sink, or an unsupported combination.
    pub fn stream(&self, sink: &mut dyn Sink) -> Result<(), EvalError> {
        self.run(Output::Stream(sink), None)
    }

    /// The uniform depth of a mesh: `known` (found already), else the settings'.
    fn mesh_depth(&self, known: Option<usize>) -> Result<usize, EvalError> {
        match (known, self.settings.depth) {
            (Some(k), _) | (None, Depth::Fixed(k)) => Ok(k),
            (None, Depth::Tolerance(eps)) => self.depth_for_tolerance(eps),
        }
    }

    /// Evaluates into `out`; `known`: the depth a tolerance came to, when
    /// [`Evaluator::evaluate_into`] found it already (the walk is not done twice).
    fn run(&self, out: Output<'_>, known: Option<usize>) -> Result<(), EvalError> {
        if self.polygon_faces() {
            let depth = self.mesh_depth(known)?;
            let sink: &mut dyn Sink = match out {
                Output::Memory(shape) => shape,
                Output::Stream(sink) => sink,
            };
            return self.polygons(depth, sink);
        }
        if self.meshes() {
            let depth = self.mesh_depth(known)?;
            return match out {
                Output::Memory(shape) => mesh_into(self, depth, shape),
                Output::Stream(sink) => mesh_stream(self, depth, sink),
            };
        }
        let in_memory = matches!(out, Output::Memory(_));
        let sink: &mut dyn Sink = match out {
            Output::Memory(shape) => shape,
            Output::Stream(sink) => sink,
        };
        match self.settings.depth {
            Depth::Fixed(k) => self.curves_fixed(k, sink, in_memory),
            Depth::Tolerance(eps) => self.curves_adaptive(eps, sink),
        }
    }
}
