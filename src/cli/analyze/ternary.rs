//! `bcifs analyze ternary5`: the ternary 5-point scheme's smoothness over ω (Siddiqi et al. 2014).

use std::fmt::Write as _;

use anyhow::{Context, Result, bail};
use bcifs::render::ternary::TernaryRow;

use crate::cli::plot::{Plot, Series};

pub fn run_ternary5(
    out: &mut String,
    (from, to): (f64, f64),
    steps: usize,
    output: &std::path::Path,
    as_json: bool,
) -> Result<u8> {
    use bcifs::render::ternary::{omegas, ternary5_rows};
    if from >= to || !from.is_finite() || !to.is_finite() {
        bail!("--omega-range A B needs finite A < B");
    }
    if steps == 0 || steps > 10_000 {
        bail!("--steps must be between 1 and 10000");
    }
    // In chunks, with a progress bar on a terminal.
    let all = omegas(from, to, steps);
    let bar = crate::cli::common::progress_bar();
    let mut rows = Vec::with_capacity(all.len());
    for chunk in all.chunks(32) {
        rows.extend(ternary5_rows(chunk));
        if let Some(b) = &bar {
            b.report(rows.len() as u64, all.len() as u64);
        }
    }
    let table = ternary5_table(&rows, (from, to))?;
    let ranges = ternary5_ranges(&rows, (from, to), steps);
    if as_json {
        ranges.json(out, &rows)?;
    } else {
        out.push_str(&table);
        ranges.text(out)?;
    }
    let img = ternary5_plot(&rows).render(900, 600)?;
    let text = crate::cli::common::png_text("ternary5", &format!("ω from {from} to {to}, {steps} steps"));
    bcifs::render::write_png_text(output, &img, &text).with_context(|| format!("cannot write {}", output.display()))?;
    if !as_json {
        writeln!(out, "plot → {}", output.display())?;
    }
    Ok(0)
}

/// The table of rows and its legend.
fn ternary5_table(rows: &[TernaryRow], (from, to): (f64, f64)) -> Result<String> {
    let mut table = String::new();
    writeln!(table, "ternary 5-point scheme (Siddiqi et al. 2014, eq. 1), ω from {from} to {to}")?;
    writeln!(
        table,
        "{:>10}  {:>8}  {:>8}  {:>8}  {:>8}  {:>8}  {:>8}  verdict",
        "omega", "C0 bound", "JSR low", "C1 bound", "C2 bound", "len low", "growth"
    )?;
    for r in rows {
        writeln!(
            table,
            "{:>10.5}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}  {}",
            r.omega,
            r.c0,
            r.c0_lower,
            r.c1,
            r.c2,
            r.length_lower,
            r.growth,
            r.verdict()
        )?;
    }
    writeln!(
        table,
        "
C0 bound: min over L ≤ 8 of ‖S_b^L‖∞^(1/L) for the difference scheme b = a/(1+z+z²) (< 1 proves C0);"
    )?;
    writeln!(table, "JSR low: max over block products of length ≤ 4 of ρ^(1/len) (≥ 1 proves divergence);")?;
    writeln!(table, "C1/C2 bounds: the same for 3a/σ² and 9a/σ³ (< 1 proves C1, C2);")?;
    writeln!(
        table,
        "len low: max over signs of ρ(Σ ±B_i) for the blocks of b (> 1 proves the length diverges);
growth: the measured polygon length ratio per step after 10 steps (shown, no verdict uses it).
"
    )?;
    Ok(table)
}

/// The ω ranges where each property is proven, their ends refined between grid points.
struct Ranges {
    c0: Vec<(f64, f64)>,
    fails: Vec<(f64, f64)>,
    c1: Vec<(f64, f64)>,
    c2: Vec<(f64, f64)>,
    fractal: Vec<(f64, f64)>,
}

fn ternary5_ranges(rows: &[TernaryRow], (from, to): (f64, f64), steps: usize) -> Ranges {
    use bcifs::render::ternary::{boundary, intervals};
    let step = (to - from) / steps as f64;
    let refine = |ranges: Vec<(f64, f64)>, pred: &dyn Fn(&bcifs::render::ternary::TernaryRow) -> bool| {
        ranges
            .into_iter()
            .map(|(a, b)| {
                let lo = if a > from { boundary(a - step, a, 1e-6, pred) } else { a };
                let hi = if b < to { boundary(b, b + step, 1e-6, pred) } else { b };
                (lo, hi)
            })
            .collect::<Vec<_>>()
    };
    Ranges {
        c0: refine(intervals(rows, |r| r.converges()), &|r| r.converges()),
        fails: refine(intervals(rows, |r| r.fails()), &|r| r.fails()),
        c1: refine(intervals(rows, |r| r.c1 < 1.0), &|r| r.c1 < 1.0),
        c2: refine(intervals(rows, |r| r.c2 < 1.0), &|r| r.c2 < 1.0),
        fractal: refine(intervals(rows, |r| r.fractal()), &|r| r.fractal()),
    }
}

impl Ranges {
    /// The ranges as text, beside the paper's.
    fn text(&self, out: &mut String) -> Result<()> {
        use bcifs::render::ternary::PAPER_RANGES;
        let show = |v: &[(f64, f64)]| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.iter().map(|(a, b)| format!("({a:.5}, {b:.5})")).collect::<Vec<_>>().join(" ∪ ")
            }
        };
        let paper = |i: usize| format!("paper: ({:.5}, {:.5})", PAPER_RANGES[i].1, PAPER_RANGES[i].2);
        writeln!(out, "C0 proven on       {}   [{}]", show(&self.c0), paper(0))?;
        writeln!(out, "not C0 (proven) on {}", show(&self.fails))?;
        writeln!(out, "C1 proven on       {}   [{}]", show(&self.c1), paper(1))?;
        writeln!(out, "C2 proven on       {}   [{}]", show(&self.c2), paper(2))?;
        writeln!(out, "fractal (C0 and length growth proven > 1) on {}", show(&self.fractal))?;
        Ok(())
    }

    /// The rows and ranges as JSON.
    fn json(&self, out: &mut String, rows: &[TernaryRow]) -> Result<()> {
        let ranges = |v: &[(f64, f64)]| serde_json::json!(v.iter().map(|(a, b)| [a, b]).collect::<Vec<_>>());
        let json_rows: Vec<_> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "omega": r.omega, "c0_upper": r.c0, "c0_lower": r.c0_lower, "c1_upper": r.c1,
                    "c2_upper": r.c2, "length_lower": r.length_lower, "growth_measured": r.growth,
                    "verdict": r.verdict(),
                })
            })
            .collect();
        let doc = serde_json::json!({
            "scheme": "ternary5", "rows": json_rows,
            "ranges": {"c0": ranges(&self.c0), "not_c0": ranges(&self.fails), "c1": ranges(&self.c1),
                       "c2": ranges(&self.c2), "fractal": ranges(&self.fractal)},
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&doc)?)?;
        Ok(())
    }
}

/// The plot of the ternary 5-point analysis: measured length growth per step
/// and the C0 contraction bound against ω, the line 1, the fractal intervals
/// shaded, and the paper's C0 bounds as vertical lines.
pub fn ternary5_plot(rows: &[bcifs::render::ternary::TernaryRow]) -> Plot {
    use bcifs::render::ternary::{PAPER_RANGES, intervals};
    let series = |label: &str, f: &dyn Fn(&bcifs::render::ternary::TernaryRow) -> f64, color| Series {
        label: label.into(),
        points: rows.iter().map(|r| (r.omega, f(r))).collect(),
        color,
    };
    let mut bands: Vec<(f64, f64, [u8; 3], String)> = intervals(rows, |r| r.fractal())
        .into_iter()
        .map(|(a, b)| (a, b, [255, 222, 222], "fractal".to_string()))
        .collect();
    bands
        .extend(intervals(rows, |r| r.fails()).into_iter().map(|(a, b)| (a, b, [225, 225, 225], "not C0".to_string())));
    // One legend entry per kind.
    let mut seen = std::collections::HashSet::new();
    for b in &mut bands {
        if !seen.insert(b.3.clone()) {
            b.3.clear();
        }
    }
    let top = rows.iter().map(|r| r.growth.max(r.c0)).fold(1.5f64, f64::max).min(4.0);
    Plot {
        title: "Ternary 5-point scheme (Siddiqi et al. 2014)".into(),
        x_label: "tension ω".into(),
        y_label: "rate per step".into(),
        series: vec![
            series("length growth", &|r| r.growth, [30, 70, 170]),
            series("C0 bound (< 1: C0)", &|r| r.c0, [230, 120, 20]),
            series("C1 bound", &|r| r.c1, [40, 150, 60]),
        ],
        bands,
        hlines: vec![(1.0, [200, 0, 0])],
        vlines: vec![(PAPER_RANGES[0].1, [150, 0, 150]), (PAPER_RANGES[0].2, [150, 0, 150])],
        y_range: Some((0.0, top)),
    }
}
