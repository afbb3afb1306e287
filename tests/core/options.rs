//! One options model (issue 43 §1): the keys are described once, checked
//! once, and the command line's flags are made from that description.

use std::process::Command;

use bcifs::render::{KEYS, Kind, Options, Profile, Value};

/// A value every key takes (valid for it).
fn valid(key: &bcifs::render::Key) -> Value {
    match (key.name, key.kind) {
        (_, Kind::Switch) => Value::Switch(true),
        ("palette", _) => "fire".into(),
        ("background", _) => "black".into(),
        (_, Kind::Count) => "2".into(),
        (_, Kind::Number) => "0.75".into(),
        (_, Kind::Choice(words)) => words[words.len() - 1].into(),
        (_, Kind::Names) => Value::Texts(vec!["T0".into(), "T1".into()]),
        (_, Kind::Values) => Value::Texts(vec!["a=1/2".into(), "b=0.25".into()]),
        (_, Kind::Size) => "10x20".into(),
        (_, Kind::Angles) => "-10,20".into(),
        (_, Kind::Text) => "x".into(),
    }
}

/// The options as a comparable text (the progress and cancel flags left out: no key sets them).
fn state(o: &Options) -> String {
    format!("{:?} {:?} {:?} {:?} {:?}", o.params, o.sampling, o.budget, o.look, o.file)
}

#[test]
fn every_key_is_set_by_its_description_and_its_default_is_the_default() {
    let names: Vec<&str> = KEYS.iter().map(|k| k.name).collect();
    for (i, name) in names.iter().enumerate() {
        assert!(!names[..i].contains(name), "`{name}` is described twice");
    }
    for key in KEYS {
        // Its default, given, changes nothing: the description and `Options::default` agree.
        if let Some(default) = key.default {
            let mut o = Options::default();
            o.set(key.name, default.into()).unwrap_or_else(|e| panic!("{}: {e}", key.name));
            assert_eq!(state(&o), state(&Options::default()), "the default of `{}`", key.name);
        }
        // A valid value changes the options; the flag's spelling names the same key.
        let mut by_name = Options::default();
        by_name.set(key.name, valid(key)).unwrap_or_else(|e| panic!("{}: {e}", key.name));
        assert_ne!(state(&by_name), state(&Options::default()), "`{}` changed nothing", key.name);
        let mut by_flag = Options::default();
        by_flag.set(key.flag, valid(key)).unwrap();
        assert_eq!(state(&by_flag), state(&by_name), "{}", key.flag);
    }
}

#[test]
fn values_are_checked_once_and_the_refusal_names_the_key() {
    let refused = [
        ("precision", Value::from(16)),
        ("precision", Value::from(0)),
        ("max_output_gib", Value::from(0.0)),
        ("max_output_gib", Value::from(f64::INFINITY)),
        ("colour_speed", Value::from(1.5)),
        ("tolerance", Value::from(0.0)),
        ("tolerance", Value::from(f64::NAN)),
        ("depth", Value::from(-1)),
        ("depth", Value::from("three")),
        ("depth", Value::from(1001)),
        ("threads", Value::from(0)),
        ("memory_mib", Value::from(0)),
        ("size", Value::from("0x10")),
        ("size", Value::from("10")),
        ("view", Value::from("nan,1")),
        ("up", Value::from("x")),
        ("colour", Value::from("height")),
        ("colours", Value::from("T0=2")),
        ("params", Value::Texts(vec!["a=1".into(), "a=2".into()])),
        ("params", Value::from("a")),
        ("gamma", Value::from(-1.0)),
        ("supersample", Value::from(0)),
        ("background", Value::from("purple")),
        ("palette", Value::from("no-such-palette")),
        ("force", Value::from("perhaps")),
    ];
    for (name, value) in refused {
        let e = Options::default().set(name, value.clone()).expect_err(&format!("{name} {value:?}"));
        assert_eq!(e.key, name, "{e}");
        let flag = KEYS.iter().find(|k| k.name == name).unwrap().flag;
        let cli = e.spelled(|k| format!("--{}", k.flag));
        assert!(cli.starts_with(&format!("--{flag}")), "{cli}");
        assert!(!e.to_string().contains("--"), "a neutral message names no flag: {e}");
    }
    let e = Options::default().set("depht", Value::from(3)).unwrap_err();
    assert!(e.to_string().contains("did you mean `depth`"), "{e}");
    // Keys that exclude each other.
    for pair in [["samples", "depth"], ["samples", "tolerance"], ["depth", "tolerance"]] {
        let e = Options::from_values(pair.map(|k| (k, Value::from("1")))).unwrap_err();
        assert!(e.to_string().contains("not apply"), "{e}");
    }
}

#[test]
fn profiles_hold_the_front_ends_budgets() {
    let explorer = Profile::Explorer.options();
    assert_eq!((explorer.budget.memory, explorer.budget.max_depth), (768 << 20, 16));
    assert_eq!(explorer.budget.time, Some(std::time::Duration::from_secs(20)));
    let mut o = explorer.clone();
    assert_eq!(o.set("depth", 17.into()).unwrap_err().to_string(), "depth 17: at most 16");
    assert!(o.set("size", "4096x10".into()).unwrap_err().to_string().contains("1 to 2048"));
    o.set("size", "2048x10".into()).unwrap();
    assert_eq!(Profile::Gallery.budget().output, 1 << 20);
    assert_eq!(Profile::Blender.budget().max_depth, 14);
    for p in Profile::ALL {
        assert_eq!(Profile::named(p.name()), Some(p));
    }
}

#[test]
fn the_command_line_s_flags_are_the_description_s() {
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).to_string(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (_, help, _) = run(&["render", "--help"]);
    for key in KEYS {
        assert!(
            help.contains(&format!("--{} ", key.flag)) || help.contains(&format!("--{}\n", key.flag)),
            "--{}",
            key.flag
        );
    }
    // The library's refusal, spelled with the flag.
    let out = std::env::temp_dir().join(format!("bcifs-options-{}.png", std::process::id()));
    let (code, _, err) = run(&["render", "koch", "--precision", "40", "-o", out.to_str().unwrap()]);
    assert_ne!(code, Some(0), "{err}");
    assert!(err.contains("--precision 40: a number of significant digits is 1 to 15"), "{err}");
    let (_, _, err) = run(&["render", "fern", "--random", "10", "--depth", "3", "-o", out.to_str().unwrap()]);
    assert!(err.contains("--random: draws points by the chaos game: a depth and a tolerance do not apply"), "{err}");
    assert!(!out.exists());
}

/// Library messages name options in words, not as one front end's flags
/// (issue 43 §1: 19 messages in 8 library files named CLI flags).
#[test]
fn library_messages_name_no_command_line_flag() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                if path != root.join("cli") {
                    stack.push(path);
                }
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") || path.file_name().is_some_and(|n| n == "tests.rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.trim_start();
                // Comments, and whole command lines quoted for the user (`bcifs new pattern --cell …`).
                if code.starts_with("//") || code.contains("`bcifs ") {
                    continue;
                }
                // A string literal holding ` --word`, `(--word` or `"--word`.
                let flag = |sep: &str| code.split(sep).skip(1).any(|t| t.starts_with(|c: char| c.is_ascii_lowercase()));
                if code.contains('"') && (flag(" --") || flag("(--") || flag("\"--")) {
                    found.push(format!("{}:{}: {code}", path.display(), n + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}
