//! The `bcifs` command line (cargo feature `cli`): parses arguments, calls
//! the library, prints. Application code only: rendering by file
//! extension, the gallery, progress bars.

mod analyze;
mod common;
mod contour;
mod core;
mod explore;
mod fit;
mod gallery;
mod keys;
mod plot;
mod render;
mod scheme;
mod surface;

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

use self::analyze::AnalyzeCommand;
use self::common::interrupt;
use self::core::Topology;
use self::render::RenderArgs;
use self::scheme::SchemeCommand;

#[derive(Parser)]
#[command(name = "bcifs", version, about = "Iterative geometric modelling with Boundary Controlled IFS")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve the constraints of an automaton file into its admissible family.
    Solve {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Instantiate an automaton and verify constraints, column sums and spectra.
    Check {
        /// The automaton file (TOML), or the name of a shipped automaton.
        file: String,
        /// A parameter value, NAME=VALUE (repeatable; defaults come from the file).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate an automaton with its model and write OBJ, OFF, PLY, STL, glTF, SVG or PNG.
    Render(RenderArgs),
    /// Subdivide a polygon mesh (OBJ or OFF) by Doo-Sabin, Catmull-Clark, Loop or √3: its limit surface or its net.
    Surface(surface::SurfaceArgs),
    /// Render every shipped automaton (PNG, OBJ) and an index.html into DIR.
    Gallery {
        /// Output directory.
        #[arg(default_value = "gallery")]
        dir: PathBuf,
        /// The geometry files of each entry, by extension: obj, ply or glb (repeatable; the formats
        /// that hold curves, surfaces and clouds alike).
        #[arg(long = "format", default_values_t = [String::from("obj")], value_parser = ["obj", "ply", "glb"])]
        formats: Vec<String>,
        /// The deep versions: every entry to the depth whose output takes 12 MiB in memory
        /// (about 330 MB on disk) instead of 1 MiB (about 70 MB).
        #[arg(long)]
        full: bool,
    },
    /// Generate the papers' subdivision schemes: render them or print their automaton.
    Scheme {
        #[command(subcommand)]
        scheme: SchemeCommand,
    },
    /// Fit a family's free parameters to a target: points or a mesh (OBJ, OFF, PLY), a picture's
    /// outline (PNG), a dimension, a junction angle, a porosity; the answer is proven to converge.
    Fit(fit::FitArgs),
    /// Analyse a design or a family: a curve's tangents (curve, blend), dimension, convergence maps (map, curve --map), the ternary 5-point scheme.
    Analyze {
        #[command(subcommand)]
        what: AnalyzeCommand,
    },
    /// Contours as Bézier fractals (the Bézier-fractal contours paper): the maps of a segments file, or its automaton.
    Contour {
        #[command(subcommand)]
        what: contour::ContourCommand,
    },
    /// Print a commented automaton file for a BC-IFS topology.
    New {
        #[command(subcommand)]
        topology: Topology,
    },
    /// List the shipped automata and the scheme presets, one line each.
    List,
    /// Print a shipped automaton (its TOML, with control points) or a scheme preset's automaton.
    Show {
        /// A shipped automaton, `scheme normal` preset or `scheme ifs` preset.
        name: String,
    },
    /// A local web page to explore a family: sliders for its parameters, its
    /// verdict and region maps, the attractor, checks and exports, live.
    Explore(explore::ExploreArgs),
    /// Print the command-line reference as Markdown (the guide's `reference/cli.md`).
    #[command(hide = true)]
    Reference,
}

/// The command-line reference, every command's long help, as Markdown: the
/// guide's page is this output (a test keeps them equal).
fn reference_markdown() -> String {
    use clap::CommandFactory as _;
    fn walk(cmd: &mut clap::Command, path: &str, out: &mut String) {
        let name = if path.is_empty() { cmd.get_name().to_string() } else { format!("{path} {}", cmd.get_name()) };
        if cmd.is_hide_set() || cmd.get_name() == "help" {
            return;
        }
        let level = "#".repeat((name.matches(' ').count() + 2).min(4));
        let help = cmd.render_long_help().to_string();
        let _ =
            std::fmt::Write::write_fmt(out, format_args!("{level} `{name}`\n\n```text\n{}\n```\n\n", help.trim_end()));
        let mut subs: Vec<clap::Command> = cmd.get_subcommands().cloned().collect();
        for sub in &mut subs {
            walk(sub, &name, out);
        }
    }
    let mut out = String::from(
        "# Command-line reference\n\nEvery command's `--help`, generated from the program itself (`bcifs reference`; \
         a test checks that this page is its output).\n\n",
    );
    let mut cmd = Cli::command();
    cmd.build();
    walk(&mut cmd, "", &mut out);
    out
}

/// The signal that interrupted the run (0: none).
static SIGNAL: std::sync::atomic::AtomicI32 = std::sync::atomic::AtomicI32::new(0);

fn run(out: &mut String, cli: Cli) -> Result<u8> {
    match cli.command {
        Command::Solve { file, json } => core::run_solve(out, &file, json),
        Command::Check { file, params, json } => core::run_check(out, &file, &params, json),
        Command::Render(args) => render::run(args),
        Command::Surface(args) => surface::run(out, args),
        Command::Gallery { dir, formats, full } => gallery::run(out, &dir, &formats, full),
        Command::Analyze { what } => analyze::run(out, what),
        Command::Fit(args) => fit::run(out, args),
        Command::Contour { what } => contour::run(out, what),
        Command::Scheme { scheme } => scheme::run(out, scheme),
        Command::New { topology } => core::run_new(out, topology),
        Command::List => core::run_list(out),
        Command::Show { name } => core::run_show(out, &name),
        Command::Explore(args) => explore::run(args),
        Command::Reference => {
            out.push_str(&reference_markdown());
            Ok(0)
        }
    }
}

/// Runs the command line and returns its exit code.
pub fn main() -> ExitCode {
    // Interrupted (SIGINT, SIGTERM, SIGHUP): the render in progress is cancelled through the
    // library's flag and stops at its next batch, removing its temporary files; whatever does not
    // stop within two seconds is ended here, its temporary files removed. Either way no
    // `.partial`/`.elements` file is left, and the exit code is 128 + the signal's number, as
    // shells do (130, 143, 129).
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                SIGNAL.store(signal, std::sync::atomic::Ordering::SeqCst);
                interrupt().cancel();
                std::thread::sleep(std::time::Duration::from_secs(2));
                bcifs::render::remove_temporary_files();
                gallery::remove_staging();
                eprintln!("\ninterrupted: the output files keep their old content");
                std::process::exit(128 + signal);
            }
        });
    }
    let cli = Cli::parse();
    let mut out = String::new();
    let code = match run(&mut out, cli) {
        Ok(code) => code,
        Err(_) if interrupt().is_cancelled() => {
            gallery::remove_staging();
            eprintln!("\ninterrupted: the output files keep their old content");
            (128 + SIGNAL.load(std::sync::atomic::Ordering::SeqCst)) as u8
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            if let Some(hint) = common::hint(&e) {
                eprintln!("hint: {hint}");
            }
            2
        }
    };
    // A closed pipe (`bcifs solve x | head`) is the reader's choice, not an error.
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(out.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: cannot write the output: {e}");
            ExitCode::from(2)
        }
        _ => ExitCode::from(code),
    }
}
