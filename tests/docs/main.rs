//! The documentation is tested: every `bcifs` command of the README's and
//! the guide's shell blocks runs in a scratch directory (inputs shipped —
//! `automata/`, `tests/data/` and `docs/silhouette.png` are linked in — or made by an earlier
//! command of the same page) and succeeds; in `console` blocks the output
//! shown is the output (durations aside); every relative link and image
//! path exists; every picture of the guide (`images/NAME.png`) is the
//! picture a command of the guide writes to `NAME.png`, pixel for pixel;
//! the command-line reference is `bcifs reference`'s output; the README
//! stays under 200 lines.
//!
//! `BCIFS_BLESS_DOCS=1 cargo test --test docs` rewrites the shown outputs
//! and the pictures from the commands (then review the diff).

use std::io::{BufRead as _, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const BIN: &str = env!("CARGO_BIN_EXE_bcifs");
/// The longest a documented command may take (a page should show quick ones).
const COMMAND_TIME: Duration = Duration::from_secs(300);

/// The README and every page of the guide.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![Path::new(ROOT).join("README.md")];
    let mut stack = vec![Path::new(ROOT).join("docs/guide/src")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    pages.sort();
    pages
}

/// A fenced block: its language, its first line's number, its lines.
struct Block {
    lang: String,
    line: usize,
    lines: Vec<String>,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        if let Some(rest) = trimmed.strip_prefix("```") {
            match open.take() {
                Some(b) => out.push(b),
                None => {
                    let lang = rest.split([',', ' ']).next().unwrap_or("").to_string();
                    open = Some(Block { lang, line: i + 2, lines: Vec::new() });
                }
            }
        } else if let Some(b) = &mut open {
            b.lines.push(line.to_string());
        }
    }
    out
}

/// A command to run and, in `console` blocks, the output shown after it.
struct Step {
    command: String,
    shown: Option<Vec<String>>,
    line: usize,
}

fn steps(block: &Block) -> Vec<Step> {
    let mut out: Vec<Step> = Vec::new();
    match block.lang.as_str() {
        "sh" | "bash" | "shell" => {
            let mut pending = String::new();
            for (k, line) in block.lines.iter().enumerate() {
                let line = line.trim_end();
                if let Some(head) = line.strip_suffix('\\') {
                    pending.push_str(head);
                    continue;
                }
                pending.push_str(line);
                let command = std::mem::take(&mut pending);
                if command.trim_start().starts_with("bcifs ") {
                    out.push(Step { command: command.trim().to_string(), shown: None, line: block.line + k });
                }
            }
        }
        "console" => {
            for (k, line) in block.lines.iter().enumerate() {
                if let Some(command) = line.strip_prefix("$ ") {
                    out.push(Step { command: command.to_string(), shown: Some(Vec::new()), line: block.line + k });
                } else if let Some(Step { shown: Some(shown), .. }) = out.last_mut() {
                    shown.push(line.clone());
                }
            }
            out.retain(|s| s.command.starts_with("bcifs "));
        }
        _ => {}
    }
    out
}

/// Durations (`0.05 s`, `(1.2 s)`) and the machine's own numbers vary from run to run.
fn normalised(text: &str) -> String {
    let mut out = String::new();
    for line in text.trim_end().lines() {
        let words: Vec<String> = line
            .split(' ')
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| {
                let bare = w[0].trim_start_matches('(');
                let next = w[1].trim_end_matches([')', ',', ';', '.']);
                if (next == "s" || next == "ms") && bare.parse::<f64>().is_ok() {
                    w[0].replace(bare, "T")
                } else {
                    w[0].to_string()
                }
            })
            .chain(line.split(' ').next_back().map(str::to_string))
            .collect();
        out.push_str(words.join(" ").trim_end());
        out.push('\n');
    }
    out
}

/// `sh -c command` started in `dir` with `PATH`, its output piped.
fn shell(command: &str, dir: &Path, path: &str) -> Result<std::process::Child, String> {
    Command::new("sh")
        .arg("-c")
        .arg(command)
        .current_dir(dir)
        .env("PATH", path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())
}

/// Runs `command` in `dir` through `sh`, `bcifs` being this build; its stdout.
fn run(command: &str, dir: &Path) -> Result<String, String> {
    let path = format!("{}:{}", Path::new(BIN).parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    if command.contains("bcifs explore ") {
        // A server: it starts, prints its URL, and is stopped.
        let mut child = shell(&format!("exec {command} --no-open --port 0"), dir, &path)?;
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap()).read_line(&mut line).map_err(|e| e.to_string())?;
        let _ = child.kill();
        let _ = child.wait();
        return if line.starts_with("http://127.0.0.1:") {
            Ok(String::new())
        } else {
            Err(format!("no URL: {line:?}"))
        };
    }
    let mut child = shell(command, dir, &path)?;
    let started = Instant::now();
    let (mut stdout, mut stderr) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stdout, &mut s);
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut s);
        s
    });
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let (out, err) = (out.join().unwrap(), err.join().unwrap());
            return if status.success() { Ok(out) } else { Err(format!("{status}: {err}")) };
        }
        if started.elapsed() > COMMAND_TIME {
            let _ = child.kill();
            return Err(format!("took over {} s", COMMAND_TIME.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The images a page shows: `](images/x.png)` and `src="images/x.png"`.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        let end = rest.find([')', ' ']).unwrap_or(rest.len());
        out.push(rest[..end].to_string());
    }
    let mut rest = text;
    while let Some(at) = rest.find("src=\"") {
        rest = &rest[at + 5..];
        let end = rest.find('"').unwrap_or(rest.len());
        out.push(rest[..end].to_string());
    }
    out.retain(|l| !l.starts_with("http") && !l.starts_with('#') && !l.starts_with("mailto:") && !l.is_empty());
    out
}

/// A scratch directory with the shipped inputs linked in.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bcifs-docs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("tests")).unwrap();
    std::os::unix::fs::symlink(Path::new(ROOT).join("automata"), dir.join("automata")).unwrap();
    std::os::unix::fs::symlink(Path::new(ROOT).join("tests/data"), dir.join("tests/data")).unwrap();
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    std::os::unix::fs::symlink(Path::new(ROOT).join("docs/silhouette.png"), dir.join("docs/silhouette.png")).unwrap();
    dir
}

/// Every command of `page`, its shown outputs and its pictures: the failures.
fn check_page(page: &Path, bless: bool) -> Vec<String> {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page.strip_prefix(ROOT).unwrap().display().to_string();
    let dir = scratch(&name.replace('/', "_"));
    let mut failures = Vec::new();
    let mut blessed = text.clone();
    for block in blocks(&text) {
        for step in steps(&block) {
            match run(&step.command, &dir) {
                Err(e) => failures.push(format!("{name}:{}: `{}` failed: {e}", step.line, step.command)),
                Ok(out) => {
                    if let Some(shown) = &step.shown {
                        let shown = shown.join("\n");
                        if normalised(&shown) != normalised(&out) {
                            if bless {
                                let lines = |t: &str| if t.is_empty() { String::new() } else { format!("{t}\n") };
                                let old = format!("$ {}\n{}", step.command, lines(&shown));
                                let new = format!("$ {}\n{}", step.command, lines(out.trim_end()));
                                blessed = blessed.replacen(&old, &new, 1);
                            } else {
                                failures.push(format!(
                                    "{name}:{}: `{}` prints\n{out}\nnot what the page shows:\n{shown}",
                                    step.line, step.command
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    if bless && blessed != text {
        std::fs::write(page, &blessed).unwrap();
    }
    // Links and pictures.
    for link in links(&text) {
        let target = link.split('#').next().unwrap();
        let path = page.parent().unwrap().join(target);
        if let Some(picture) = target.strip_prefix("images/") {
            let made = dir.join(picture);
            if !made.exists() {
                failures.push(format!("{name}: {target} is not written by a command of the page"));
                continue;
            }
            if bless {
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::copy(&made, &path).unwrap();
            }
            if !path.exists() {
                failures.push(format!("{name}: {target} does not exist"));
            } else if made.extension().is_some_and(|e| e == "png") {
                let (a, b) = (image::open(&made).unwrap().to_rgba8(), image::open(&path).unwrap().to_rgba8());
                if a != b {
                    failures.push(format!("{name}: {target} is not the picture its command draws"));
                }
            }
        } else if !path.exists() {
            failures.push(format!("{name}: the link {link} leads nowhere"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    failures
}

#[test]
fn every_documented_command_runs_and_every_link_leads_somewhere() {
    let bless = std::env::var_os("BCIFS_BLESS_DOCS").is_some();
    let pages = pages();
    assert!(pages.len() > 10, "the guide's pages: {pages:?}");
    let queue = std::sync::Mutex::new(pages);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                while let Some(page) = queue.lock().unwrap().pop() {
                    let found = check_page(&page, bless);
                    failures.lock().unwrap().extend(found);
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n\n"));
}

#[test]
fn the_readme_is_short_and_the_cli_reference_is_the_programs() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).unwrap();
    assert!(readme.lines().count() <= 200, "the README has {} lines", readme.lines().count());
    assert!(!readme.contains("seed 00"), "the papers are cited by authors and year");
    let out = Command::new(BIN).arg("reference").output().unwrap();
    assert!(out.status.success());
    let page = Path::new(ROOT).join("docs/guide/src/reference/cli.md");
    if std::env::var_os("BCIFS_BLESS_DOCS").is_some() {
        std::fs::write(&page, &out.stdout).unwrap();
    }
    assert_eq!(
        std::fs::read_to_string(&page).unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        "docs/guide/src/reference/cli.md is `bcifs reference`'s output (BCIFS_BLESS_DOCS=1 rewrites it)"
    );
}
