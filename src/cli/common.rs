//! What the commands share: their arguments' parsing (keywords, sizes,
//! views, parameters, threads), the output checks, loading a design, the
//! run's command line, its interrupt flag and its progress bar.

use anyhow::{Context, Result, bail};

use bcifs::{Design, Progress};

pub(super) fn keyword<T: Copy>(what: &str, value: &str, options: &[(&str, T)]) -> Result<T> {
    options.iter().find(|(k, _)| *k == value).map(|(_, v)| *v).with_context(|| {
        let names: Vec<&str> = options.iter().map(|(k, _)| *k).collect();
        match bcifs::suggest(value, names.iter().copied()) {
            Some(s) => format!("unknown {what} `{value}` (did you mean `{s}`?); expected {}", names.join(", ")),
            None => format!("unknown {what} `{value}`; expected {}", names.join(", ")),
        }
    })
}

/// The picture flags `render`, `surface` and `scheme` share: size, view, memory.
#[derive(clap::Args, Clone, Debug)]
pub struct PictureArgs {
    /// Picture size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800", value_parser = parse_size, value_name = "WIDTHxHEIGHT")]
    pub size: (u32, u32),
    /// View of 3D shapes: YAW,PITCH in degrees.
    #[arg(long, default_value = "30,35", allow_hyphen_values = true, value_parser = parse_view, value_name = "YAW,PITCH")]
    pub view: (f64, f64),
    /// In-memory limit in MiB (pictures, evaluation, meshes).
    #[arg(long, default_value_t = 4096)]
    pub memory_mib: usize,
    /// PNG with a transparent background (RGBA): the shape over nothing, for compositing.
    #[arg(long)]
    pub transparent: bool,
}

impl PictureArgs {
    /// The in-memory limit in bytes.
    pub fn memory(&self) -> usize {
        self.memory_mib.saturating_mul(1 << 20)
    }

    /// The picture settings these flags ask for.
    pub fn raster(&self) -> bcifs::export::RasterSettings {
        let ((w, h), (yaw, pitch)) = (self.size, self.view);
        bcifs::export::RasterSettings::default()
            .with_size(w, h)
            .with_view(yaw, pitch)
            .with_memory_limit(self.memory())
            .with_transparent(self.transparent)
    }
}

/// `--size WIDTHxHEIGHT`: two positive numbers of pixels.
pub(super) fn parse_size(size: &str) -> Result<(u32, u32)> {
    let (w, h) = size.split_once('x').with_context(|| format!("--size `{size}`: expected WIDTHxHEIGHT"))?;
    let (w, h): (u32, u32) = (w.trim().parse().context("--size width")?, h.trim().parse().context("--size height")?);
    if w == 0 || h == 0 {
        bail!("--size {w}x{h}: each side must be at least 1 pixel");
    }
    Ok((w, h))
}

/// `--view YAW,PITCH`: two finite angles in degrees.
pub(super) fn parse_view(view: &str) -> Result<(f64, f64)> {
    let (yaw, pitch) = view.split_once(',').with_context(|| format!("--view `{view}`: expected YAW,PITCH"))?;
    let (yaw, pitch): (f64, f64) =
        (yaw.trim().parse().context("--view yaw")?, pitch.trim().parse().context("--view pitch")?);
    if !yaw.is_finite() || !pitch.is_finite() {
        bail!("--view {yaw},{pitch}: the angles must be finite numbers of degrees");
    }
    Ok((yaw, pitch))
}

/// The extensions of every format a render writes.
pub(super) fn render_formats() -> Vec<&'static str> {
    bcifs::render::Format::ALL.iter().map(|f| f.extension()).collect()
}

/// Checks, before any work, that an output path can be written (not a
/// directory, in a directory that exists) and has one of the `extensions`.
pub(super) fn check_output(path: &std::path::Path, extensions: &[&str], inputs: &[&std::path::Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|input| bcifs::export::same_file(path, input)) {
        bail!(
            "-o {} is the input {}: writing it would lose the input; give another output file",
            path.display(),
            input.display()
        );
    }
    bcifs::export::check_target(path).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if !extensions.is_empty() && !extensions.contains(&ext.as_str()) {
        let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        bail!("{}: unknown output format `{ext}`: expected {}", path.display(), list.join(", "));
    }
    Ok(())
}

/// Worker threads: at least 1, at most 64 times the cores (more only waits).
pub(super) fn check_threads(threads: Option<usize>) -> Result<Option<usize>> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match threads {
        Some(t) if t == 0 || t > 64 * cores => bail!("--threads {t}: expected 1 to {} on this machine", 64 * cores),
        other => Ok(other),
    }
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
pub(super) fn parse_exact_params(params: &[String]) -> Result<Vec<(String, bcifs::Num)>> {
    let mut out: Vec<(String, bcifs::Num)> = Vec::with_capacity(params.len());
    for p in params {
        let (name, value) = p.split_once('=').with_context(|| format!("`{p}`: expected NAME=VALUE"))?;
        let value = value.trim().parse::<bcifs::Num>().map_err(|e| anyhow::anyhow!("`{p}`: {e}"))?;
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
    let args: Vec<String> = std::env::args().skip(1).collect();
    format!("bcifs {}", args.join(" "))
}

/// The flag every render of this run is cancelled by: Ctrl-C sets it.
pub(super) fn interrupt() -> &'static bcifs::Cancel {
    static FLAG: std::sync::OnceLock<bcifs::Cancel> = std::sync::OnceLock::new();
    FLAG.get_or_init(bcifs::Cancel::new)
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
