//! `bcifs contour`: contours as Bézier fractals (seed 002).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Subcommand;

/// What to do with a contour.
#[derive(Subcommand)]
pub enum ContourCommand {
    /// Print the maps of every segment in the paper's convention (homogeneous row
    /// vectors, [x' y' 1] = [x y 1] F): L, M for arcs (eq. 10), F1, F2 for line segments (eqs. 12–14).
    Ifs {
        /// The segments file (TOML: [[segment]] points = [[x, y], ...], 2 or 3 points each).
        segments: PathBuf,
        /// Print JSON: {"maps": [{"segment", "name", "matrix"}, ...]}.
        #[arg(long)]
        json: bool,
    },
    /// Print the automaton (with its model) of the whole contour: arcs and line segments chained
    /// into one curve; `bcifs render`, `check` and `--random` work on it.
    Automaton {
        /// The segments file.
        segments: PathBuf,
    },
}

/// Runs a contour command.
pub fn run(out: &mut String, command: ContourCommand) -> Result<u8> {
    match command {
        ContourCommand::Ifs { segments, json } => {
            let pieces = bcifs::contour::read_segments(&segments)?;
            let mut maps = Vec::new();
            for (k, s) in pieces.iter().enumerate() {
                let pair = s.maps().map_err(|e| anyhow::anyhow!("{}: segment {k}: {e}", segments.display()))?;
                for (name, m) in pair {
                    maps.push((k, name, m));
                }
            }
            if json {
                let list: Vec<serde_json::Value> = maps
                    .iter()
                    .map(|(k, name, m)| serde_json::json!({"segment": k, "name": name, "matrix": m}))
                    .collect();
                writeln!(out, "{}", serde_json::to_string_pretty(&serde_json::json!({ "maps": list }))?)?;
            } else {
                for (k, name, m) in &maps {
                    writeln!(out, "segment {k} {name}:")?;
                    for row in m {
                        writeln!(out, "  [{:>10.6} {:>10.6} {:>10.6}]", row[0], row[1], row[2])?;
                    }
                }
            }
            Ok(0)
        }
        ContourCommand::Automaton { segments } => {
            let pieces = bcifs::contour::read_segments(&segments)?;
            let name = segments.file_stem().map_or("contour".into(), |s| s.to_string_lossy().to_string());
            let design = bcifs::contour::contour_design(&name, &pieces)?;
            out.push_str(&bcifs::write_design(&design));
            Ok(0)
        }
    }
}
