//! The inputs the fuzzer (`fuzz/`, `cargo +nightly fuzz run automaton`)
//! found crashing, hanging or blowing up memory, kept as regression tests
//! that run on stable: each goes through the fuzz target's pipeline and
//! must come back, with an error or a result, within a time limit.

use std::sync::mpsc;
use std::time::Duration;

#[path = "../common/pipeline.rs"]
mod pipeline;

#[test]
fn inputs_the_fuzzer_found_end_cleanly() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzzed");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/fuzzed exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fuzzed inputs in {}", dir.display());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || tx.send(pipeline::run(&text)));
        // Generous for a debug build on a loaded machine; the fuzzer's own limit was 10 s.
        match rx.recv_timeout(Duration::from_secs(60)) {
            Ok(stage) => println!("{}: ended at stage {stage}", file.display()),
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("{} hangs", file.display()),
            Err(mpsc::RecvTimeoutError::Disconnected) => panic!("{} panics", file.display()),
        }
    }
}
