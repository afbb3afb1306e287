//! The architecture, checked: the library's files import only from their own
//! layer or the layers below it, and no two files import each other, even
//! through others (the README's design notes list the layers).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's top-level modules, bottom first.
const LAYERS: [&[&str]; 16] = [
    &["algebra", "input", "names", "progress"],
    &["space"],
    &["automaton"],
    &["design"],
    &["geometry"],
    &["mesh"],
    &["family"],
    &["format"],
    &["schemes"],
    &["contour"],
    &["analysis"],
    &["eval"],
    &["export"],
    &["report"],
    &["fit"],
    &["render"],
];

fn rank(top: &str) -> usize {
    LAYERS.iter().position(|l| l.contains(&top)).unwrap_or_else(|| panic!("module `{top}` is in no layer"))
}

/// Every library source file (the `cli` application, `main.rs` and unit-test files, `tests.rs`, are
/// not the library).
fn library_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src is readable") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "cli") {
                library_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs")
            && path.file_name().is_some_and(|n| n != "main.rs" && n != "tests.rs")
        {
            out.push(path);
        }
    }
}

/// `src/eval/surface.rs` → `["eval", "surface"]`; `src/eval/mod.rs` → `["eval"]`; `src/lib.rs` → `[]`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).expect("under src").with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The module paths a file refers to (`crate::a::b`, `super::c`, `self::d`),
/// outside its unit tests.
fn references(text: &str, module: &[String], is_dir_module: bool) -> Vec<Vec<String>> {
    let code = text.split("#[cfg(test)]").next().unwrap_or_default();
    let code: String = code.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
    // `super` of `eval/surface.rs` is `eval`; of `eval/mod.rs` it is the crate.
    let parent: Vec<String> = if is_dir_module || module.is_empty() {
        module[..module.len().saturating_sub(1)].to_vec()
    } else {
        module[..module.len() - 1].to_vec()
    };
    let mut out = Vec::new();
    for (word, base) in [("crate::", Vec::new()), ("super::", parent), ("self::", module.to_vec())] {
        let mut rest = code.as_str();
        while let Some(at) = rest.find(word) {
            let before = rest[..at].chars().last();
            rest = &rest[at + word.len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            // `use crate::{a::X, b::Y}` names several paths.
            let heads: Vec<String> = if let Some(group) = rest.strip_prefix('{') {
                let end = group.find('}').unwrap_or(group.len());
                group[..end].split(',').map(|p| p.trim().to_string()).collect()
            } else {
                vec![rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect()]
            };
            for head in heads {
                let mut path = base.clone();
                path.extend(head.split("::").filter(|s| !s.is_empty()).map(str::to_string));
                out.push(path);
            }
        }
    }
    out
}

#[test]
fn no_file_imports_from_above_or_in_a_cycle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    library_files(&src, &mut files);
    let modules: BTreeMap<Vec<String>, PathBuf> = files.iter().map(|f| (module_of(&src, f), f.clone())).collect();
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    let mut above = Vec::new();
    for (module, file) in &modules {
        let text = std::fs::read_to_string(file).expect("readable");
        // A facade (`lib.rs`, `mod.rs`) depends on the children it declares.
        for line in text.lines().map(str::trim) {
            if let Some(child) = line.strip_prefix("mod ").or_else(|| line.strip_prefix("pub mod ")) {
                let mut path = module.clone();
                path.push(child.trim_end_matches(';').to_string());
                if modules.contains_key(&path) {
                    edges.entry(module.clone()).or_default().insert(path);
                }
            }
        }
        if module.is_empty() {
            continue;
        }
        let is_dir_module = file.file_name().is_some_and(|n| n == "mod.rs");
        for path in references(&text, module, is_dir_module) {
            // The deepest module file that the path goes through (the crate root at worst).
            let Some(target) = (0..=path.len()).rev().map(|k| path[..k].to_vec()).find(|p| modules.contains_key(p))
            else {
                continue;
            };
            if target == *module {
                continue;
            }
            match target.first() {
                None => above.push(format!("{} reaches into the crate root", module.join("::"))),
                Some(top) if rank(top) > rank(&module[0]) => {
                    above.push(format!("{} imports {}", module.join("::"), target.join("::")));
                }
                Some(_) => {}
            }
            edges.entry(module.clone()).or_default().insert(target);
        }
    }
    assert!(above.is_empty(), "imports from a layer above:\n  {}", above.join("\n  "));
    // A depth-first search finds any cycle.
    fn visit(
        m: &Vec<String>,
        edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        state: &mut BTreeMap<Vec<String>, u8>,
        stack: &mut Vec<Vec<String>>,
    ) -> Option<Vec<String>> {
        match state.get(m) {
            Some(2) => return None,
            Some(1) => {
                let from = stack.iter().position(|x| x == m).unwrap_or(0);
                return Some(stack[from..].iter().chain([m]).map(|p| p.join("::")).collect());
            }
            _ => {}
        }
        state.insert(m.clone(), 1);
        stack.push(m.clone());
        for next in edges.get(m).into_iter().flatten() {
            if let Some(cycle) = visit(next, edges, state, stack) {
                return Some(cycle);
            }
        }
        stack.pop();
        state.insert(m.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in modules.keys() {
        if let Some(cycle) = visit(m, &edges, &mut state, &mut Vec::new()) {
            panic!("import cycle: {}", cycle.join(" → "));
        }
    }
    assert!(edges.len() > 20, "the scan found the imports ({} files with imports)", edges.len());
}

/// Every source file of the library, the command line and the Python module.
fn all_sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            all_sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The sources of the library, the command line and the Python module.
fn library_and_module_sources() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    all_sources(&root.join("src"), &mut files);
    all_sources(&root.join("python/src"), &mut files);
    files
}

/// Issue 43: files stay readable: none over 800 lines (`family/solve.rs`
/// had 952: its equations, elimination and errors are files of their own;
/// the glTF writer's tests moved beside it).
#[test]
fn no_source_file_is_over_800_lines() {
    let files = library_and_module_sources();
    let long: Vec<String> = files
        .iter()
        .map(|f| (f, std::fs::read_to_string(f).expect("readable").lines().count()))
        .filter(|(_, n)| *n > 800)
        .map(|(f, n)| format!("{} ({n} lines)", f.display()))
        .collect();
    assert!(files.len() > 100, "{} files", files.len());
    assert!(long.is_empty(), "over 800 lines: {long:?}");
}

/// The functions of `text` longer than `most` lines, with their first
/// lines: a `fn` item (not a declaration ending in `;`) runs from its line
/// to the first line that closes it at its own indentation (rustfmt's layout).
fn long_functions(text: &str, most: usize) -> Vec<(usize, usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let code = line.trim_start();
        let indent = line.len() - code.len();
        let rest = ["pub ", "pub(crate) ", "pub(super) ", "const ", "async ", "unsafe "]
            .iter()
            .fold(code, |c, p| c.strip_prefix(p).unwrap_or(c));
        if !rest.starts_with("fn ") || line.trim_end().ends_with(';') {
            continue;
        }
        let close = format!("{}}}", " ".repeat(indent));
        if let Some(end) = lines[i..].iter().position(|l| l.trim_end() == close)
            && end + 1 > most
        {
            out.push((i + 1, end + 1, code.chars().take(60).collect()));
        }
    }
    out
}

/// Issue 43: functions stay readable: none over 80 lines (Francis's QR
/// step, the OBJ reader, the explorer's router, the options' setter and
/// four others were split into named steps).
#[test]
fn no_function_is_over_80_lines() {
    assert_eq!(long_functions("fn a() {\n    x;\n}\nfn b();\n", 2), [(1, 3, "fn a() {".to_string())]);
    let files = library_and_module_sources();
    let long: Vec<String> = files
        .iter()
        .flat_map(|f| {
            let text = std::fs::read_to_string(f).expect("readable");
            long_functions(&text, 80)
                .into_iter()
                .map(move |(at, n, head)| format!("{}:{at} {head} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "over 80 lines: {long:#?}");
}

/// The library paths a front-end source names (`bcifs::render::Options`,
/// `bcifs::mesh::Scheme`; a `use bcifs::{a, b::c}` group gives each).
fn library_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("bcifs::") {
        let before = rest[..at].chars().next_back();
        rest = &rest[at + "bcifs::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        group(rest, "", &mut out);
    }
    out
}

/// The paths of `text` (after `prefix::`): one path, or a `{…}` group of them.
fn group(text: &str, prefix: &str, out: &mut Vec<String>) {
    let path: String = text.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
    let path = path.trim_end_matches(':');
    let full = if prefix.is_empty() { path.to_string() } else { format!("{prefix}::{path}") };
    let after = text[path.len()..].trim_start_matches(':');
    if !after.starts_with('{') {
        if !full.is_empty() {
            out.push(full);
        }
        return;
    }
    let (mut depth, mut start) = (0, 1);
    for (i, c) in after.char_indices() {
        match c {
            '{' => depth += 1,
            '}' | ',' if depth == 1 => {
                let item = after[start..i].trim();
                let item = if item.contains('{') { item } else { item.split(" as ").next().unwrap_or(item).trim() };
                if !item.is_empty() && item != "self" {
                    group(item, &full, out);
                }
                start = i + 1;
                if c == '}' {
                    return;
                }
            }
            '}' => depth -= 1,
            _ => {}
        }
    }
}

/// Issue 43's measure: the front ends (the command line, the explorer, the
/// Python module) call the library through `bcifs::render` and what it
/// re-exports, nothing else: a new front-end feature goes through the
/// library's render API (or adds its names to that module's list), not around it.
#[test]
fn front_ends_reach_nothing_past_the_render_api() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    all_sources(&root.join("src/cli"), &mut files);
    all_sources(&root.join("python/src"), &mut files);
    let mut past = BTreeSet::new();
    let mut through = 0;
    for f in &files {
        for path in library_paths(&std::fs::read_to_string(f).expect("readable")) {
            if path.starts_with("render") {
                through += 1;
            } else {
                past.insert(path.split("::").take(2).collect::<Vec<_>>().join("::"));
            }
        }
    }
    assert_eq!(library_paths("use bcifs::{a, b::{c, d as e}, f::g};"), ["a", "b::c", "b::d", "f::g"]);
    assert!(through > 100, "the scan finds the render API's uses: {through}");
    assert!(past.is_empty(), "{} library paths past bcifs::render: {past:?}", past.len());
}
