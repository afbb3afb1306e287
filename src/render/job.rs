//! One output of a design, built once: the options prepared for it, its
//! model and its instance. Every route starts from a [`Job`]; none makes
//! its own model or instance.

use super::options::Options;
use super::output::{Format, RenderError};
use crate::automaton::Automaton;
use crate::design::{Design, Model};
use crate::eval::{ChaosGame, Evaluator, RandomSettings};
use crate::geometry::Shape;

/// A design ready to be output: the options prepared ([`Job::new`]), the
/// model that projects it and its automaton at the options' parameters.
pub(super) struct Job<'a> {
    /// The design.
    pub design: &'a Design,
    /// The options, prepared for this design.
    pub options: Options,
    /// Its model.
    pub model: Model,
    /// Its automaton with numbers.
    pub automaton: Automaton<f64>,
}

impl<'a> Job<'a> {
    /// The job of `design` with `options`: not cancelled, a model in a mesh
    /// file's (Y-up) axes drawn standing and written without a turn, a
    /// family that solves (or forced), instantiated at the parameters.
    ///
    /// # Errors
    /// Cancelled, no model, constraints that fail, parameters.
    pub fn new(design: &'a Design, options: &Options) -> Result<Job<'a>, RenderError> {
        options.check_cancel()?;
        let y_up = design.model().is_some_and(|m| m.y_up);
        let mut options = options.clone();
        options.look.view.y_up = y_up;
        options.file.coordinates.y_up_input = y_up;
        if let Err(crate::family::SolveError::Inconsistent { conflicts }) = crate::family::solve(design)
            && !options.sampling.force
        {
            return Err(RenderError::Inconsistent { name: design.name().to_string(), conflicts });
        }
        let model = crate::report::model_of(design)?;
        let automaton = crate::family::instantiate(design, &options.params)?.automaton;
        Ok(Job { design, options, model, automaton })
    }

    /// The design's name.
    pub fn name(&self) -> &str {
        self.design.name()
    }

    /// The deterministic evaluator; its warnings (undecided convergence), named after the design, go to `warnings`.
    pub fn evaluator(&self, warnings: &mut Vec<String>) -> Result<Evaluator, RenderError> {
        let ev = Evaluator::new(&self.automaton, &self.model, self.options.eval_settings())?;
        warnings.extend(ev.warnings().iter().map(|w| format!("{}: {w}", self.name())));
        Ok(ev)
    }

    /// A chaos game whose points are streamed or counted, never held: its
    /// memory check is for one batch.
    pub fn game(&self, random: &RandomSettings) -> Result<ChaosGame, RenderError> {
        crate::eval::check_samples(random.points)?;
        let batch = random.clone().with_points(random.points.min(crate::geometry::BATCH));
        Ok(ChaosGame::new(&self.automaton, &self.model, &batch)?)
    }

    /// The output in memory: the chaos game's points, or the deterministic
    /// evaluation ([`RenderError::Cancelled`] when the options' flag stopped it).
    pub fn evaluate(&self, warnings: &mut Vec<String>) -> Result<Shape, RenderError> {
        let shape = match self.options.random_settings() {
            Some(r) => crate::eval::chaos_game(&self.automaton, &self.model, &r),
            None => self.evaluator(warnings)?.evaluate(),
        };
        let shape = shape?;
        self.options.check_cancel()?;
        Ok(shape)
    }
}

/// The ways an output is made: the one route table ([`route`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Route {
    /// A print file (STL, 3MF): in memory, checked, sized in millimetres
    /// ([`crate::report::printed`]); streamed as it is over the memory budget.
    Print,
    /// A surface thickened into a shell ([`crate::mesh::thicken`]): in memory.
    Shell,
    /// A deterministic evaluation coloured by state, level or map: in memory, with its colours.
    Coloured,
    /// flam3's XML of a plain IFS.
    Flame,
    /// Geometry files (OBJ, OFF, PLY, STL, glTF), streamed into a file or a buffer.
    Stream,
    /// A PNG picture: a chaos game's density, or a deterministic picture.
    Picture,
    /// Evaluated in memory and drawn (SVG; a deduplicated cloud's picture).
    Memory,
}

/// Which route an output in `format` with `options` takes.
pub(super) fn route(format: Format, options: &Options) -> Route {
    let chaos = options.sampling.samples.is_some();
    match format {
        f if f.is_print() && !chaos => Route::Print,
        _ if options.file.thickness.is_some() && !chaos => Route::Shell,
        _ if options.look.colour.is_some() && !chaos => Route::Coloured,
        Format::Flame => Route::Flame,
        f if f.is_geometry() => Route::Stream,
        Format::Png if !options.file.dedup => Route::Picture,
        _ => Route::Memory,
    }
}
