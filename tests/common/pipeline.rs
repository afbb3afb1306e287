//! What a user's automaton file goes through, from text to points: shared
//! by the fuzz target (`fuzz/`) and the regression tests of the inputs it
//! found (`tests/fuzzed/`). Errors are fine; a panic, an abort or a hang is
//! not.

use bcifs::eval::{EvalSettings, Evaluator};

/// Parses `text` as an automaton file and, as far as it goes without an
/// error, solves, instantiates with its defaults, checks, and evaluates its
/// model at depth 3 within 16 MiB. Returns how far it got (0–5).
pub fn run(text: &str) -> u32 {
    let Ok(design) = bcifs::parse_design(text, "fuzzed.toml", "fuzzed") else { return 0 };
    let _ = bcifs::solve(&design);
    let Ok(instance) = bcifs::instantiate(&design, &[]) else { return 1 };
    if bcifs::analysis::check(&instance.automaton, &instance.values, 1e-9).is_err() {
        return 2;
    }
    let Some(model) = design.model() else { return 3 };
    let settings = EvalSettings::default().with_depth(3).with_memory_limit(16 << 20).with_threads(1);
    match Evaluator::new(&instance.automaton, model, settings) {
        Ok(ev) => 4 + u32::from(ev.evaluate().is_ok()),
        Err(_) => 4,
    }
}
