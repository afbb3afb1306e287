//! Fuzzes the whole path of an automaton file: parse, solve, instantiate,
//! check (with the joint spectral radius bounds) and a shallow evaluation.
//! Any panic, abort, hang or memory blow-up is a bug; inputs that found one
//! are kept in `tests/fuzzed/` and run by `cargo test` on stable.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../tests/common/pipeline.rs"]
mod pipeline;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        pipeline::run(text);
    }
});
