//! Printing at a real size (issue 56 §6), checked by the programs that
//! print: every shipped solid and a lace's shell written at 40 mm is sliced
//! by Debian's PrusaSlicer (`--export-gcode`) and read by ADMesh. Where
//! bcifs warns of nothing, the slicer must slice without a warning and lay
//! down a first layer; each bcifs warning must be a real problem: pieces
//! floating above the bed leave the slicer empty layers, a first layer
//! without foothold is refused by the slicer or lays down a tenth of a
//! layer's filament at most, a wall or a hole thinner than the nozzle is as
//! thin as the geometry says. A client that is not installed is skipped
//! with a printed reason; `.ci/run` installs both.

use std::path::Path;
use std::process::Command;

/// Whether `program` runs (`--help` or `--version`); says so when it does not.
fn installed(program: &str) -> bool {
    let ok = Command::new(program).arg("--help").output().is_ok();
    if !ok {
        println!("skipped: {program} is not installed (apt-get install {program})");
    }
    ok
}

/// `bcifs render ... --json`: the report (with the print report's fields).
fn render(args: &[&str], out: &Path) -> serde_json::Value {
    let output = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .arg("render")
        .args(args)
        .arg("--json")
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    serde_json::from_slice(&output.stdout).unwrap()
}

/// What the slicer made of a print file: it succeeded, its warnings, and
/// the filament its first layer lays down against its median layer's
/// (skirt and brim left out).
struct Sliced {
    ok: bool,
    messages: String,
    first_layer_share: f64,
}

fn slice(file: &Path) -> Sliced {
    let gcode = file.with_extension("gcode");
    let out = Command::new("prusa-slicer").arg("--export-gcode").arg(file).arg("-o").arg(&gcode).output().unwrap();
    let messages = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let mut layers: Vec<f64> = Vec::new();
    let mut kind = String::new();
    for line in std::fs::read_to_string(&gcode).unwrap_or_default().lines() {
        if line.starts_with(";LAYER_CHANGE") {
            layers.push(0.0);
        } else if let Some(k) = line.strip_prefix(";TYPE:") {
            kind = k.to_string();
        } else if let (Some(code), Some(last)) = (line.split(';').next(), layers.last_mut())
            && code.starts_with("G1 ")
            && !kind.contains("Skirt")
            && !kind.contains("Brim")
            && let Some(e) =
                code.split_whitespace().find_map(|w| w.strip_prefix('E')).and_then(|e| e.parse::<f64>().ok())
            && e > 0.0
        {
            *last += e;
        }
    }
    std::fs::remove_file(&gcode).ok();
    let mut sorted = layers.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
    let first = layers.first().copied().unwrap_or(0.0);
    Sliced { ok: out.status.success(), messages, first_layer_share: if median > 0.0 { first / median } else { 0.0 } }
}

#[test]
fn shipped_solids_and_shells_slice_as_their_print_reports_say() {
    if !installed("prusa-slicer") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("bcifs-slice-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases: [(&str, &[&str]); 9] = [
        ("menger", &["menger", "--depth", "2", "--print-size", "40"]),
        ("jerusalem", &["jerusalem", "--depth", "2", "--print-size", "40"]),
        ("tricubic-sponge", &["tricubic-sponge", "--depth", "2", "--print-size", "40"]),
        ("cantor_dust", &["cantor_dust", "--depth", "2", "--print-size", "40"]),
        ("sierpinski_tetrahedron", &["sierpinski_tetrahedron", "--depth", "3", "--print-size", "40"]),
        ("tricubic", &["tricubic", "--depth", "2", "--print-size", "40"]),
        ("carpet_shell", &["carpet", "--depth", "3", "--thickness", "0.004", "--print-size", "40"]),
        // The sponge at 10 mm: its depth-3 tunnels are 10/27 mm wide, narrower than the nozzle.
        ("menger_small", &["menger", "--depth", "3", "--print-size", "10"]),
        // A model unit a millimetre: 1 mm across.
        ("menger_unit", &["menger", "--depth", "2"]),
    ];
    for (name, args) in cases {
        let file = dir.join(format!("{name}.3mf"));
        let report = render(args, &file);
        let warnings: Vec<String> =
            report["warnings"].as_array().unwrap().iter().map(|w| w.as_str().unwrap().to_string()).collect();
        let sliced = slice(&file);
        let slicer_warns = sliced.messages.contains("Empty layer") || sliced.messages.contains("no extrusions");
        if warnings.is_empty() {
            assert!(sliced.ok && !slicer_warns, "{name}: no bcifs warning, but the slicer: {}", sliced.messages);
            assert!(sliced.first_layer_share > 0.1, "{name}: a first layer of {:.3}", sliced.first_layer_share);
        }
        for w in &warnings {
            if w.contains("float above the bed") {
                assert!(sliced.messages.contains("Empty layer"), "{name}: {w}; the slicer: {}", sliced.messages);
            } else if w.contains("first layer") {
                assert!(
                    !sliced.ok || sliced.first_layer_share < 0.1,
                    "{name}: {w}; the slicer laid down {:.3} of a layer",
                    sliced.first_layer_share
                );
            } else if w.contains("too small to slice") {
                assert!(
                    !sliced.ok && sliced.messages.contains("empty"),
                    "{name}: {w}; the slicer: {}",
                    sliced.messages
                );
            } else if w.contains("thinner than the nozzle") || w.contains("narrower than the nozzle") {
                // Each is the geometry's: the shell's thickness, the sponge's tunnels at 10 mm.
                let measured = if w.contains("wall") { &report["smallest_wall"] } else { &report["smallest_hole"] };
                let expected = match name {
                    "carpet_shell" => 0.004 * 40.0,
                    "menger_small" => 10.0 / 27.0,
                    _ => 1.0 / 9.0,
                };
                let got = measured.as_f64().unwrap();
                assert!(
                    (got - expected).abs() < 0.02 * expected,
                    "{name}: {w}: measured {got}, the geometry's {expected}"
                );
            } else {
                panic!("{name}: a warning this test does not know how to check: {w}");
            }
        }
        assert!(report["scale"].as_f64().unwrap() > 0.0 && report["manifold"] == true, "{name}: {report}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// ADMesh, reading the STL files: one part per piece the print report
/// counts, the volume (to f32), no facet to fix, reverse or remove, and
/// the size asked for.
#[test]
fn admesh_reads_the_print_files_as_bcifs_reports_them() {
    if !installed("admesh") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("bcifs-admesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["menger", "jerusalem", "cantor_dust", "sierpinski_tetrahedron", "tricubic-sponge"] {
        let file = dir.join(format!("{name}.stl"));
        let report = render(&[name, "--depth", "2", "--print-size", "40"], &file);
        let out = Command::new("admesh").arg(&file).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        let field = |label: &str| -> f64 {
            let line = text.lines().find(|l| l.contains(label)).unwrap_or_else(|| panic!("{name}: no {label}: {text}"));
            let after = &line[line.find(label).unwrap() + label.len()..];
            after.trim_start_matches([' ', ':']).split_whitespace().next().unwrap().parse().unwrap()
        };
        assert_eq!(field("Number of parts") as u64, report["components"].as_u64().unwrap(), "{name}");
        let volume = report["volume"].as_f64().unwrap();
        assert!((field("Volume") - volume).abs() < 1e-4 * volume, "{name}: {} against {volume}", field("Volume"));
        for label in
            ["Edges fixed", "Facets removed", "Facets added", "Facets reversed", "Backwards edges", "Degenerate facets"]
        {
            assert_eq!(field(label), 0.0, "{name}: {label}");
        }
        let longest = (0..3)
            .map(|a| report["bbox"][1][a].as_f64().unwrap() - report["bbox"][0][a].as_f64().unwrap())
            .fold(0.0, f64::max);
        assert!((longest - 40.0).abs() < 1e-9, "{name}: {longest} mm");
    }
    std::fs::remove_dir_all(&dir).ok();
}
