//! Issue 23, item 17: every `bcifs` command of the README's shell blocks
//! runs as written, in a scratch directory where the shipped inputs
//! (`automata/`, `tests/data/`) are at hand and earlier commands make the
//! rest; no two commands write the same file; relative links point to files
//! that exist.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The README's shell blocks (```sh), in order.
fn shell_blocks(text: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        match (&mut current, line.trim_start()) {
            (None, l) if l.starts_with("```sh") || l.starts_with("```bash") => current = Some(String::new()),
            (Some(_), l) if l.starts_with("```") => blocks.push(current.take().unwrap_or_default()),
            (Some(block), _) => {
                block.push_str(line);
                block.push('\n');
            }
            (None, _) => {}
        }
    }
    blocks
}

/// A command line without its trailing comment (a `#` after a space, outside quotes).
fn without_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (None, '"' | '\'') => quote = Some(c),
            (None, '#') if previous.is_whitespace() => return line[..i].trim_end(),
            _ => {}
        }
        previous = c;
    }
    line.trim_end()
}

/// The files a command line writes: `-o FILE`, `--output FILE`, `> FILE`.
fn outputs(line: &str) -> Vec<String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    words
        .windows(2)
        .filter(|w| matches!(w[0], "-o" | "--output" | ">"))
        .map(|w| w[1].trim_matches('"').to_string())
        .collect()
}

/// The `bcifs` command lines of the README, in order.
fn readme_commands(root: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(root.join("README.md")).unwrap();
    shell_blocks(&text)
        .iter()
        .flat_map(|b| b.lines().map(without_comment).map(str::to_string).collect::<Vec<_>>())
        .filter(|l| l.starts_with("bcifs "))
        .collect()
}

#[test]
fn every_readme_command_runs_as_written() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let commands = readme_commands(&root);
    assert!(commands.len() >= 20, "the README shows the commands: {commands:?}");
    let mut written: Vec<(String, String)> = Vec::new();
    for line in &commands {
        for out in outputs(line) {
            if let Some((_, first)) = written.iter().find(|(o, _)| *o == out) {
                panic!("`{out}` is written by two commands of the README:\n  {first}\n  {line}");
            }
            written.push((out, line.clone()));
        }
    }
    let scratch = std::env::temp_dir().join(format!("bcifs-readme-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    for shipped in ["automata", "tests"] {
        std::os::unix::fs::symlink(root.join(shipped), scratch.join(shipped)).unwrap();
    }
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_bcifs"));
    let path = format!("{}:{}", bin.parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    for line in &commands {
        let started = std::time::Instant::now();
        let out = Command::new("sh").args(["-c", line]).current_dir(&scratch).env("PATH", &path).output().unwrap();
        assert!(
            out.status.success(),
            "README command failed ({}): {line}\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        println!("{:6.2} s  {line}", started.elapsed().as_secs_f64());
    }
    std::fs::remove_dir_all(&scratch).unwrap();
}

/// Every relative link and image of the README points to a file of the repository.
#[test]
fn readme_links_point_to_files() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("README.md")).unwrap();
    let mut missing = Vec::new();
    for (i, _) in text.match_indices("](") {
        let rest = &text[i + 2..];
        let Some(end) = rest.find(')') else { continue };
        let target = rest[..end].split('#').next().unwrap_or("");
        if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        if !root.join(target).exists() {
            missing.push(target.to_string());
        }
    }
    assert!(missing.is_empty(), "links to missing files: {missing:?}");
}
