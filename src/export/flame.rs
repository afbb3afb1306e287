//! flam3's `.flame` XML (what flam3-render, Apophysis and Chaotica read):
//! the one place flame records are formatted.

use std::fmt::Write as _;
use std::path::Path;

use super::atomic::write_atomic;
use super::density::{Palette, Tone};
use super::png::INK;
use super::view::RasterSettings;
use crate::geometry::PlainIfs;

/// Why a `.flame` file was not written.
#[derive(Debug, thiserror::Error)]
pub enum FlameError {
    /// The chaos game is not a plain IFS of the plane (the reason).
    #[error("{0}")]
    NotPlain(String),
    /// Writing.
    #[error("cannot write {0}: {1}")]
    Io(std::path::PathBuf, std::io::Error),
}

/// The `.flame` text of a plain IFS: one `<flame>` whose `<xform>`s are
/// its maps (`linear` variations, so each is the affine map itself) with
/// their probabilities as weights and their colour coordinates (each after
/// a comment naming its arrow: flam3 takes an xform's `name` for a
/// variation), seen from
/// `centre` at `scale` pixels per unit, the picture's size, tone and
/// palette (256 colours; one ink over white paper without a palette), and
/// `samples` points in all (flam3's quality is samples per pixel).
///
/// flam3 applies `coefs="a b c d e f"` as `(x, y) ↦ (a x + c y + e, b x +
/// d y + f)` and puts `y` down the picture: each map is written flipped
/// (`y ↦ −y` before and after), and so is the centre, so that the picture
/// stands as bcifs draws it.
///
/// ```
/// use bcifs::geometry::PlainIfs;
/// let half = |e: f64, f: f64| [0.5, 0.0, e, 0.0, 0.5, f];
/// let ifs = PlainIfs {
///     names: vec!["a".into(), "b".into(), "c".into()],
///     maps: vec![half(0.0, 0.0), half(0.5, 0.0), half(0.0, 0.5)],
///     probabilities: vec![1.0 / 3.0; 3],
///     colours: vec![0.0, 0.5, 1.0],
///     colour_speed: 0.5,
/// };
/// let raster = bcifs::export::RasterSettings::default().with_size(64, 64);
/// let text = bcifs::export::flame_text("gasket", &ifs, ([0.5, 0.5], 60.0), &raster, &Default::default(), None, 100_000);
/// assert!(text.contains(r#"<!-- b -->
///    <xform weight="0.3333333333333333" color="0.5" color_speed="0.5" linear="1" coefs="0.5 0 0 0.5 0.5 0"/>"#));
/// assert!(text.contains(r#"center="0.5 -0.5""#));
/// ```
pub fn flame_text(
    name: &str,
    ifs: &PlainIfs,
    (centre, scale): ([f64; 2], f64),
    raster: &RasterSettings,
    tone: &Tone,
    palette: Option<&Palette>,
    samples: usize,
) -> String {
    let (w, h) = (raster.width.max(1), raster.height.max(1));
    let quality = (samples as f64 / (f64::from(w) * f64::from(h))).max(1e-6);
    let paper = tone.paper(palette.is_some()).map(|c| f64::from(c) / 255.0);
    let escape = |s: &str| s.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;").replace('>', "&gt;");
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<!-- written by bcifs {} -->", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(
        out,
        "<flame name=\"{}\" version=\"bcifs {}\" size=\"{w} {h}\" center=\"{} {}\" scale=\"{scale}\" rotate=\"0\" \
         oversample=\"{}\" filter=\"0.2\" quality=\"{quality}\" background=\"{} {} {}\" brightness=\"{}\" \
         gamma=\"{}\" vibrancy=\"{}\" estimator_radius=\"{}\" estimator_minimum=\"0\" estimator_curve=\"{}\" \
         palette_mode=\"linear\" interpolation_type=\"linear\">",
        escape(name),
        env!("CARGO_PKG_VERSION"),
        centre[0],
        0.0 - centre[1],
        tone.supersample.clamp(1, 8),
        paper[0],
        paper[1],
        paper[2],
        4.0 * tone.brightness,
        tone.gamma,
        tone.vibrancy,
        tone.blur,
        tone.blur_curve,
    );
    for (k, m) in ifs.maps.iter().enumerate() {
        // y flipped on both sides: (a, b, e, c, d, f) ↦ (a, −b, e, −c, d, −f).
        let [a, b, e, c, d, f] = *m;
        let _ = writeln!(
            out,
            "   <!-- {} -->\n   <xform weight=\"{}\" color=\"{}\" color_speed=\"{}\" linear=\"1\" coefs=\"{a} {} {} {d} {e} {}\"/>",
            escape(&ifs.names[k]),
            ifs.probabilities[k],
            ifs.colours[k],
            ifs.colour_speed,
            0.0 - c,
            0.0 - b,
            0.0 - f
        );
    }
    for i in 0..256 {
        let rgb = match palette {
            Some(p) => p.colour(i as f32 / 255.0),
            None => INK.map(|c| c as u8),
        };
        let _ = writeln!(out, "   <color index=\"{i}\" rgb=\"{} {} {}\"/>", rgb[0], rgb[1], rgb[2]);
    }
    out.push_str("</flame>\n");
    out
}

/// Writes the plain IFS `ifs` as a `.flame` file for `samples` points,
/// framed at `frame` (centre and pixels per unit: bcifs's density picture's
/// frame, [`super::picture_frame`]), atomically.
///
/// # Errors
/// An I/O error.
pub fn write_flame(
    path: &Path,
    name: &str,
    ifs: &PlainIfs,
    frame: ([f64; 2], f64),
    look: (&RasterSettings, &Tone, Option<&Palette>),
    samples: usize,
) -> Result<(), FlameError> {
    let (raster, tone, palette) = look;
    let text = flame_text(name, ifs, frame, raster, tone, palette, samples);
    write_atomic(path, text.as_bytes()).map_err(|e| FlameError::Io(path.to_path_buf(), e))
}
