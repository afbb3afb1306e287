//! What the commands share: their arguments' parsing (keywords,
//! parameters), the output checks, loading a design, the
//! run's command line, its interrupt flag and its progress bar.

use anyhow::{Context, Result, bail};

use bcifs::render::{Design, Progress};

pub(super) fn keyword<T: Copy>(what: &str, value: &str, options: &[(&str, T)]) -> Result<T> {
    options.iter().find(|(k, _)| *k == value).map(|(_, v)| *v).with_context(|| {
        let names: Vec<&str> = options.iter().map(|(k, _)| *k).collect();
        match bcifs::render::suggest(value, names.iter().copied()) {
            Some(s) => format!("unknown {what} `{value}` (did you mean `{s}`?); expected {}", names.join(", ")),
            None => format!("unknown {what} `{value}`; expected {}", names.join(", ")),
        }
    })
}

/// The extensions of every format a render writes.
pub(super) fn render_formats() -> Vec<&'static str> {
    bcifs::render::Format::ALL.iter().map(|f| f.extension()).collect()
}

/// Checks, before any work, that an output path can be written (not a
/// directory, in a directory that exists) and has one of the `extensions`.
pub(super) fn check_output(path: &std::path::Path, extensions: &[&str], inputs: &[&std::path::Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|input| bcifs::render::same_file(path, input)) {
        bail!(
            "-o {} is the input {}: writing it would lose the input; give another output file",
            path.display(),
            input.display()
        );
    }
    bcifs::render::check_target(path).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if !extensions.is_empty() && !extensions.contains(&ext.as_str()) {
        let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        bail!("{}: unknown output format `{ext}`: expected {}", path.display(), list.join(", "));
    }
    Ok(())
}

/// Reads a file, or a shipped automaton or scheme preset by name when no
/// such file exists; a name that is neither says which one is closest.
pub(super) fn load(file: &str) -> Result<Design> {
    Ok(bcifs::render::load(file)?)
}

pub(super) fn parse_params(params: &[String]) -> Result<Vec<(String, f64)>> {
    Ok(parse_exact_params(params)?.into_iter().map(|(n, v)| (n, v.to_f64())).collect())
}

/// `NAME=VALUE` pairs, the values exact (`1/20`, `0.05`, `sqrt(2)/4`).
pub(super) fn parse_exact_params(params: &[String]) -> Result<Vec<(String, bcifs::render::Num)>> {
    let mut out: Vec<(String, bcifs::render::Num)> = Vec::with_capacity(params.len());
    for p in params {
        let (name, value) = p.split_once('=').with_context(|| format!("`{p}`: expected NAME=VALUE"))?;
        let value = value.trim().parse::<bcifs::render::Num>().map_err(|e| anyhow::anyhow!("`{p}`: {e}"))?;
        let name = name.trim().to_string();
        if out.iter().any(|(n, _)| *n == name) {
            bail!("`{name}` is given twice: one value per name");
        }
        out.push((name, value));
    }
    Ok(out)
}

/// This run's command line, as a picture records it (`bcifs render …`).
pub(super) fn command_line() -> String {
    // The thread count changes no byte of the output: it is left out, so that pictures made with
    // any `--threads` are the same file.
    let mut args = Vec::new();
    let mut given = std::env::args().skip(1);
    while let Some(a) = given.next() {
        match a.as_str() {
            "--threads" => {
                given.next();
            }
            _ if a.starts_with("--threads=") => {}
            _ => args.push(a),
        }
    }
    format!("bcifs {}", args.join(" "))
}

/// The `tEXt` chunks of a picture a command writes (as `render`'s): `Software`,
/// `Title`, `Comment` (its settings) and `Description` (the command line).
pub(super) fn png_text(title: &str, comment: &str) -> Vec<(String, String)> {
    vec![
        ("Software".to_string(), format!("bcifs {}", env!("CARGO_PKG_VERSION"))),
        ("Title".to_string(), title.to_string()),
        ("Comment".to_string(), comment.to_string()),
        ("Description".to_string(), command_line()),
    ]
}

/// The flag every render of this run is cancelled by: Ctrl-C sets it.
pub(super) fn interrupt() -> &'static bcifs::render::Cancel {
    static FLAG: std::sync::OnceLock<bcifs::render::Cancel> = std::sync::OnceLock::new();
    FLAG.get_or_init(bcifs::render::Cancel::new)
}

/// A progress bar on stderr when it is a terminal, fed by the library's callback.
pub(super) fn progress_bar() -> Option<Progress> {
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        return None;
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(Progress::new(move |done, total| {
        if done >= total {
            bar.finish_and_clear();
        } else {
            bar.set_length(total);
            bar.set_position(done);
        }
    }))
}

/// The command line's words for what the library says neutrally: the flag
/// that does what a refusal suggests (`render anyway by forcing it`: `--force`).
pub(super) fn hint(e: &anyhow::Error) -> Option<String> {
    use bcifs::render::EvalError;
    use bcifs::render::{LoadError, RenderError};
    let eval = |e: &EvalError| match e {
        EvalError::Diverges { .. } => Some("--force evaluates it anyway".to_string()),
        EvalError::TooLarge { .. } => Some("--memory-mib raises the in-memory limit".into()),
        _ => None,
    };
    if let Some(e) = e.downcast_ref::<RenderError>() {
        return match e {
            RenderError::Inconsistent { .. } => Some("--force renders it anyway".into()),
            RenderError::TooBig(why) if why.contains("output limit") => {
                Some("--max-output-gib raises the output limit".into())
            }
            RenderError::Raster(_) => Some("--memory-mib raises the in-memory limit".into()),
            RenderError::Mesh(bcifs::render::SubdivideError::NotTriangles { .. }) => {
                Some("--triangulate splits the faces into triangles first".into())
            }
            RenderError::Mesh(bcifs::render::SubdivideError::TooLarge { .. }) => {
                Some("--memory-mib raises the in-memory limit".into())
            }
            RenderError::Eval(e) => eval(e),
            RenderError::Instantiate(bcifs::render::DesignInstantiateError::Values(
                bcifs::render::InstantiateError::Missing { .. },
            )) => Some("--param NAME=VALUE gives a parameter its value".into()),
            _ => None,
        };
    }
    if let Some(e) = e.downcast_ref::<EvalError>() {
        return eval(e);
    }
    if let Some(LoadError::MeshWithoutScheme(file)) = e.downcast_ref::<LoadError>() {
        return Some(format!(
            "`bcifs explore {file} --scheme catmull-clark`, or write its automaton with `bcifs surface {file} --scheme catmull-clark --print -o automaton.toml`"
        ));
    }
    None
}
