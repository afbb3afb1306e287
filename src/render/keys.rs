//! The keys of [`Options`], described once: the command line's flags, the
//! Python module's keywords and the explorer's query parameters are made
//! from [`KEYS`], and every value is checked here, in [`Options::set`], so
//! no front end validates, converts or words an option itself.
//!
//! ```
//! use bcifs::render::{KEYS, Options, Value};
//! let depth = KEYS.iter().find(|k| k.name == "depth").unwrap();
//! assert_eq!(depth.flag, "depth");
//! let mut options = Options::default();
//! options.set("memory_mib", Value::from(512))?;
//! assert_eq!(options.budget.memory, 512 << 20);
//! let e = options.set("max_output_gib", Value::from(-1.0)).unwrap_err();
//! assert_eq!(e.key, "max_output_gib");
//! assert_eq!(e.spelled(|k| format!("--{}", k.flag)), "--max-output-gib -1: expected a positive number of GiB");
//! # Ok::<(), bcifs::render::OptionError>(())
//! ```

use std::time::Duration;

use super::options::{Budget, Options};
use crate::eval::{Colouring, Depth};
use crate::export::{Palette, Tone, Up};

/// What a key is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Group {
    /// The design's parameters.
    Design,
    /// What is sampled: depth, tolerance or chaos game.
    Sampling,
    /// What the work may take.
    Budget,
    /// How pictures look.
    Look,
    /// How files are written.
    File,
}

/// The kind of value a key takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "choices")]
pub enum Kind {
    /// On when given (a flag without value).
    Switch,
    /// A whole number, 0 or more.
    Count,
    /// A real number.
    Number,
    /// Text (a palette name, a colour).
    Text,
    /// One of these words.
    Choice(&'static [&'static str]),
    /// Names, repeatable (arrows).
    Names,
    /// `NAME=VALUE` pairs, repeatable; values exact or decimal (`1/4`, `0.25`, `sqrt(2)/4`).
    Values,
    /// `WIDTHxHEIGHT` in pixels.
    Size,
    /// `YAW,PITCH` in degrees.
    Angles,
}

/// One key of [`Options`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Key {
    /// The key's name: the Python keyword and the explorer's query parameter.
    pub name: &'static str,
    /// The command line's long flag (without `--`).
    pub flag: &'static str,
    /// What it is about.
    pub group: Group,
    /// The value it takes.
    #[serde(flatten)]
    pub kind: Kind,
    /// The default, as the command line would write it (`None`: unset).
    pub default: Option<&'static str>,
    /// The placeholder of its value in help texts.
    pub value_name: &'static str,
    /// What it does.
    pub help: &'static str,
}

const fn key(name: &'static str, flag: &'static str, group: Group, kind: Kind, help: &'static str) -> Key {
    Key { name, flag, group, kind, default: None, value_name: "", help }
}

impl Key {
    const fn or(mut self, default: &'static str) -> Key {
        self.default = Some(default);
        self
    }

    const fn shown(mut self, value_name: &'static str) -> Key {
        self.value_name = value_name;
        self
    }
}

use Group::{Budget as B, Design as D, File as F, Look as L, Sampling as S};

/// Every key of [`Options`], in the order help lists them.
pub const KEYS: &[Key] = &[
    key("params", "param", D, Kind::Values, "A parameter value, NAME=VALUE (repeatable).").shown("NAME=VALUE"),
    key("depth", "depth", S, Kind::Count, "Subdivision depth."),
    key("tolerance", "tolerance", S, Kind::Number, "Subdivide until every cell is smaller than this (modelling units): its part of the attractor for an IFS of affine contractions (a Hausdorff bound), its control polygon otherwise."),
    key("samples", "random", S, Kind::Count, "Chaos game with this many points instead of deterministic evaluation.").shown("N"),
    key("seed", "seed", S, Kind::Count, "Seed of the chaos game.").or("1"),
    key("probs", "prob", S, Kind::Values, "Probability of an arrow in the chaos game, ARROW=P (repeatable; default ∝ |det|).").shown("ARROW=P"),
    key("drop", "drop", S, Kind::Names, "Leave out a subdivision arrow (repeatable): a subset of the attractor.").shown("ARROW"),
    key("force", "force", S, Kind::Switch, "Evaluate even a system whose convergence bounds prove it diverges."),
    key("threads", "threads", B, Kind::Count, "Worker threads (default: all cores)."),
    key("memory_mib", "memory-mib", B, Kind::Count, "In-memory limit in MiB (pictures, evaluation, meshes).").or("4096"),
    key("max_output_gib", "max-output-gib", B, Kind::Number, "Largest file to write, in GiB (the estimate is checked before writing; raise it on purpose).").or("4"),
    key("size", "size", L, Kind::Size, "Picture size in pixels, WIDTHxHEIGHT.").or("800x800").shown("WIDTHxHEIGHT"),
    key("view", "view", L, Kind::Angles, "View of 3D shapes: YAW,PITCH in degrees.").or("30,35").shown("YAW,PITCH"),
    key("transparent", "transparent", L, Kind::Switch, "PNG with a transparent background (RGBA): the shape over nothing, for compositing."),
    key("palette", "palette", L, Kind::Text, "Chaos game to PNG: colour by the arrows applied, with this palette: fire, ocean, rainbow, viridis, sunset, or a picture file (its middle row, left to right)."),
    key("colour", "colour", L, Kind::Choice(&["state", "level", "map"]), "Colour the vertices of a deterministic evaluation (OBJ, PLY, glTF) with the palette (default rainbow): by the `state` of the cell that makes them, the `level` at which they appear, or the `map`s that lead to them (as the chaos game colours, with the arrows' colours and the colour speed)."),
    key("colours", "color", L, Kind::Values, "Chaos game with a palette: the colour coordinate of an arrow, ARROW=C with C in [0, 1] (repeatable; the others are spread evenly in arrow order).").shown("ARROW=C"),
    key("colour_speed", "color-speed", L, Kind::Number, "Chaos game with a palette: each step moves the colour coordinate this far towards the arrow's colour, c ← (1 − s) c + s c_arrow (flam3's colour speed).").or("0.5"),
    key("brightness", "brightness", L, Kind::Number, "Chaos game to PNG: log-density brightness b, v = (ln(1 + b·count) / ln(1 + b·max))^(1/gamma).").or("1"),
    key("gamma", "gamma", L, Kind::Number, "Chaos game to PNG: the gamma of the tone mapping.").or("2.2"),
    key("supersample", "supersample", L, Kind::Count, "Chaos game to PNG: cells per pixel side, averaged (1 to 8).").or("1"),
    key("vibrancy", "vibrancy", L, Kind::Number, "Chaos game with a palette: 1 keeps the hues as the density fades, 0 tone-maps each channel.").or("1"),
    key("blur", "blur", L, Kind::Number, "Chaos game to PNG: density-estimation blur, the largest radius in pixels (sparse cells spread over radius/count^curve, dense ones stay sharp; 0: off).").or("0"),
    key("blur_curve", "blur-curve", L, Kind::Number, "Chaos game to PNG: how fast the blur radius shrinks with the count.").or("0.4"),
    key("background", "background", L, Kind::Text, "Chaos game to PNG: the background, RRGGBB in hexadecimal, white or black (default: white, black with a palette)."),
    key("uv", "uv", F, Kind::Switch, "Texture coordinates on meshes: one (u, v) parameterization of the whole grid or torus."),
    key("up", "up", F, Kind::Choice(&["auto", "y", "z"]), "The file's up axis: auto (the format's convention: y in OBJ, OFF and PLY, model z becoming the file's y; z in STL and 3MF, the printers' and Blender's STL importer's), y or z (as is); glTF is y-up by definition.").or("auto"),
    key("ascii", "ascii", F, Kind::Switch, "PLY as text instead of binary little-endian."),
    key("precision", "precision", F, Kind::Count, "File coordinates with this many significant digits (1 to 15): smaller files, written faster (default: the shortest text that reads back to the same number, up to 17 digits)."),
    key("dedup", "dedup", F, Kind::Switch, "Drop exact duplicate points of a point cloud (evaluated in memory), reporting how many."),
    key("thickness", "thickness", F, Kind::Number, "Write a surface (a lace) as a closed shell of this thickness (modelling units), for printing: evaluated in memory, refused when thicker than its smallest cell or pinched."),
    key("print_size", "print-size", F, Kind::Number, "Print files (STL, 3MF): the longest side of the print in millimetres (the mesh scaled to it; default: a model unit is a millimetre).").shown("MM"),
    key("print_scale", "print-scale", F, Kind::Number, "Print files (STL, 3MF): millimetres per model unit (instead of the print size).").shown("MM"),
    key("nozzle", "nozzle", F, Kind::Number, "Print files: the nozzle's width in millimetres; thinner walls and narrower holes are warned of.").or("0.4").shown("MM"),
    key("allow_non_manifold", "allow-non-manifold", F, Kind::Switch, "Write a print file (STL, 3MF) even where the mesh is not a closed 2-manifold (refused otherwise; warned of)."),
];

/// The key named `name` (its [`Key::name`] or its [`Key::flag`]).
pub fn key_named(name: &str) -> Option<&'static Key> {
    KEYS.iter().find(|k| k.name == name || k.flag == name)
}

/// A value given to a key: typed, or text that the key's [`Kind`] parses
/// (what a command line or a query string gives).
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A switch.
    Switch(bool),
    /// A whole number.
    Int(i128),
    /// A real number.
    Number(f64),
    /// Text, parsed as the key's kind.
    Text(String),
    /// Several texts (a repeated flag), each parsed as the key's kind.
    Texts(Vec<String>),
    /// `NAME=VALUE` pairs, the values given.
    Values(Vec<(String, f64)>),
    /// Two numbers (a size, a view).
    Pair(f64, f64),
}

impl From<bool> for Value {
    fn from(b: bool) -> Value {
        Value::Switch(b)
    }
}
impl From<i64> for Value {
    fn from(n: i64) -> Value {
        Value::Int(n.into())
    }
}
impl From<i32> for Value {
    fn from(n: i32) -> Value {
        Value::Int(n.into())
    }
}
impl From<usize> for Value {
    fn from(n: usize) -> Value {
        Value::Int(n as i128)
    }
}
impl From<f64> for Value {
    fn from(x: f64) -> Value {
        Value::Number(x)
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Value {
        Value::Text(s.to_string())
    }
}
impl From<String> for Value {
    fn from(s: String) -> Value {
        Value::Text(s)
    }
}

/// An option refused, with the key it names (a front end spells the key
/// its own way: `--max-output-gib`, `max_output_gib=`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.spelled(|k| k.name.to_string()))]
pub struct OptionError {
    /// The key's name (empty for a key no option has).
    pub key: &'static str,
    /// The value given, as text.
    pub given: String,
    /// What was expected.
    pub why: String,
}

impl OptionError {
    fn new(key: &Key, given: impl std::fmt::Display, why: impl Into<String>) -> OptionError {
        OptionError { key: key.name, given: given.to_string(), why: why.into() }
    }

    /// The message, the key written by `spell` (`--depth 3`, or `depth=3`
    /// when the spelling ends with `=`).
    pub fn spelled(&self, spell: impl Fn(&Key) -> String) -> String {
        let Some(k) = key_named(self.key) else { return self.why.clone() };
        let key = spell(k);
        match (self.given.is_empty(), key.ends_with('=')) {
            (true, _) => format!("{}: {}", key.trim_end_matches('='), self.why),
            (false, true) => format!("{key}{}: {}", self.given, self.why),
            (false, false) => format!("{key} {}: {}", self.given, self.why),
        }
    }
}

/// The budgets of the front ends, named: what a render may take there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// The command line and the Python module: 4 GiB of memory, 4 GiB files, no time limit.
    Cli,
    /// The explorer's server: 768 MiB per render (exports are held in memory to be
    /// sent), 20 s, depth 16, pictures up to 2048 px.
    Explorer,
    /// The gallery's geometry files: 1 MiB each, depth 16.
    Gallery,
    /// The gallery's deep versions (`gallery --full`): 12 MiB each.
    GalleryFull,
    /// The gallery's pictures: their points up to 64 MiB.
    GalleryPicture,
    /// The Blender add-on: depth 14 for meshes, maps of 160 px (up to 1024).
    Blender,
}

impl Profile {
    /// Every profile.
    pub const ALL: [Profile; 6] = [
        Profile::Cli,
        Profile::Explorer,
        Profile::Gallery,
        Profile::GalleryFull,
        Profile::GalleryPicture,
        Profile::Blender,
    ];

    /// Its name (`cli`, `explorer`, `gallery`, `gallery_full`, `gallery_picture`, `blender`).
    pub fn name(self) -> &'static str {
        match self {
            Profile::Cli => "cli",
            Profile::Explorer => "explorer",
            Profile::Gallery => "gallery",
            Profile::GalleryFull => "gallery_full",
            Profile::GalleryPicture => "gallery_picture",
            Profile::Blender => "blender",
        }
    }

    /// The profile of this name.
    pub fn named(name: &str) -> Option<Profile> {
        Profile::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Its budget.
    pub fn budget(self) -> Budget {
        let cli = Budget::default();
        match self {
            Profile::Cli => cli,
            Profile::Explorer => Budget {
                memory: 768 << 20,
                output: 768 << 20,
                time: Some(Duration::from_secs(20)),
                max_depth: 16,
                max_side: 2048,
                ..cli
            },
            Profile::Gallery => Budget { output: 1 << 20, max_depth: 16, ..cli },
            Profile::GalleryFull => Budget { output: 12 << 20, max_depth: 16, ..cli },
            Profile::GalleryPicture => Budget { output: 64 << 20, max_depth: 16, ..cli },
            Profile::Blender => Budget { max_depth: 14, max_side: 1024, ..cli },
        }
    }

    /// The size of its pictures and maps when none is asked, in pixels.
    pub fn size(self) -> (u32, u32) {
        match self {
            Profile::Explorer => (640, 640),
            Profile::Blender => (160, 160),
            _ => (Options::default().look.width, Options::default().look.height),
        }
    }

    /// Default options within this profile's budget, at its picture size.
    pub fn options(self) -> Options {
        let (w, h) = self.size();
        Options::default().with_budget(self.budget()).with_size(w, h)
    }
}

impl Options {
    /// Options from keys and values, over the defaults: each value checked
    /// by [`Options::set`], then the keys together (the chaos game takes
    /// no depth or tolerance).
    ///
    /// # Errors
    /// The first value refused, or two keys that exclude each other.
    pub fn from_values<K: AsRef<str>>(values: impl IntoIterator<Item = (K, Value)>) -> Result<Options, OptionError> {
        let mut options = Options::default();
        options.set_values(values)?;
        Ok(options)
    }

    /// [`Options::from_values`] over these options (a profile's, say).
    ///
    /// # Errors
    /// As [`Options::from_values`].
    pub fn set_values<K: AsRef<str>>(
        &mut self,
        values: impl IntoIterator<Item = (K, Value)>,
    ) -> Result<(), OptionError> {
        let mut given = Vec::new();
        for (k, v) in values {
            given.push(self.set(k.as_ref(), v)?.name);
        }
        let has = |name: &str| given.contains(&name);
        let conflict = |a: &str, b: &str, why: &str| {
            let key = key_named(a).expect("a key");
            Err(OptionError::new(key, "", format!("{why}: {b}")))
        };
        if has("samples") && (has("depth") || has("tolerance")) {
            return conflict("samples", "a depth and a tolerance do not apply to it", "draws points by the chaos game");
        }
        if has("depth") && has("tolerance") {
            return conflict(
                "tolerance",
                "a fixed depth does not apply to it",
                "subdivides until every cell is small enough",
            );
        }
        Ok(())
    }

    /// Sets one key (by [`Key::name`] or [`Key::flag`]) to `value`, checked:
    /// the one place where options are validated and converted.
    ///
    /// # Errors
    /// A key no option has (with the closest name), or a value it does not take.
    pub fn set(&mut self, name: &str, value: Value) -> Result<&'static Key, OptionError> {
        let Some(key) = key_named(name) else {
            let closest = KEYS.iter().map(|k| (strsim::levenshtein(k.name, name), k.name)).min();
            let hint = closest.filter(|(d, _)| *d <= 3).map(|(_, n)| format!(": did you mean `{n}`?"));
            return Err(OptionError {
                key: "",
                given: String::new(),
                why: format!("no option `{name}`{}", hint.unwrap_or_default()),
            });
        };
        self.apply(key, value)?;
        Ok(key)
    }

    fn apply(&mut self, key: &'static Key, value: Value) -> Result<(), OptionError> {
        match key.group {
            Group::Design => {
                self.params = pairs(key, value)?;
                Ok(())
            }
            Group::Sampling => self.apply_sampling(key, value),
            Group::Budget => self.apply_budget(key, value),
            Group::Look => self.apply_look(key, value),
            Group::File => self.apply_file(key, value),
        }
    }

    /// A sampling key: depth, tolerance or the chaos game.
    fn apply_sampling(&mut self, key: &'static Key, value: Value) -> Result<(), OptionError> {
        let given = shown(&value);
        let refuse = |why: &str| OptionError::new(key, &given, why);
        match key.name {
            "depth" => {
                let k = count(key, value)?;
                let max = self.budget.max_depth as u128;
                if k > max {
                    return Err(refuse(&format!("at most {max}")));
                }
                self.sampling.depth = Depth::Fixed(k as usize);
            }
            "tolerance" => match number(key, value)? {
                eps if eps > 0.0 && eps.is_finite() => self.sampling.depth = Depth::Tolerance(eps),
                _ => return Err(refuse("expected a positive length")),
            },
            "samples" => {
                let n = count(key, value)?;
                let n = usize::try_from(n).map_err(|_| refuse("too many points"))?;
                self.sampling.samples = Some(n);
            }
            "seed" => {
                let seed = u64::try_from(count(key, value)?).map_err(|_| refuse("expected 0 to 2^64 − 1"))?;
                self.sampling.seed = seed;
            }
            "probs" => self.sampling.probabilities = pairs(key, value)?,
            "drop" => self.sampling.dropped = names(key, value)?,
            "force" => self.sampling.force = switch(key, value)?,
            other => unreachable!("the key `{other}` has no setter"),
        }
        Ok(())
    }

    /// A budget key: threads, memory, output.
    fn apply_budget(&mut self, key: &'static Key, value: Value) -> Result<(), OptionError> {
        let given = shown(&value);
        let refuse = |why: &str| OptionError::new(key, &given, why);
        match key.name {
            "threads" => {
                let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
                match count(key, value)? {
                    t if t == 0 || t > 64 * cores as u128 => {
                        return Err(refuse(&format!("expected 1 to {} on this machine", 64 * cores)));
                    }
                    t => self.budget.threads = Some(t as usize),
                }
            }
            "memory_mib" => match count(key, value)? {
                0 => return Err(refuse("expected at least 1 MiB")),
                mib => self.budget.memory = usize::try_from(mib << 20).unwrap_or(usize::MAX),
            },
            "max_output_gib" => match number(key, value)? {
                gib if gib > 0.0 && gib.is_finite() => self.budget.output = (gib * f64::from(1u32 << 30)) as u128,
                _ => return Err(refuse("expected a positive number of GiB")),
            },
            other => unreachable!("the key `{other}` has no setter"),
        }
        Ok(())
    }

    /// A look key: size, view, colours, tone.
    fn apply_look(&mut self, key: &'static Key, value: Value) -> Result<(), OptionError> {
        let given = shown(&value);
        let refuse = |why: &str| OptionError::new(key, &given, why);
        match key.name {
            "size" => {
                let (w, h) = pair(key, value, 'x')?;
                let max = self.budget.max_side;
                let side = |s: f64| (s.fract() == 0.0 && s >= 1.0 && s <= f64::from(max)).then_some(s as u32);
                let (Some(w), Some(h)) = (side(w), side(h)) else {
                    let range = if max == u32::MAX { "at least 1 pixel".into() } else { format!("1 to {max} pixels") };
                    return Err(refuse(&format!("each side is a whole number, {range}")));
                };
                (self.look.width, self.look.height) = (w, h);
            }
            "view" => {
                let (yaw, pitch) = pair(key, value, ',')?;
                if !(yaw.is_finite() && pitch.is_finite()) {
                    return Err(refuse("the angles must be finite numbers of degrees"));
                }
                (self.look.view.yaw, self.look.view.pitch) = (yaw, pitch);
            }
            "transparent" => self.look.transparent = switch(key, value)?,
            "palette" => self.look.palette = Some(Palette::parse(&text(key, value)?).map_err(|e| refuse(&e))?),
            "colour" => {
                self.look.colour = Some(match choice(key, value)? {
                    "state" => Colouring::State,
                    "level" => Colouring::Level,
                    _ => Colouring::Map,
                })
            }
            "colours" => {
                let colours = pairs(key, value)?;
                if let Some((name, c)) = colours.iter().find(|(_, c)| !(0.0..=1.0).contains(c)) {
                    return Err(refuse(&format!("{name}={c}: a colour coordinate is between 0 and 1")));
                }
                self.look.arrow_colours = colours;
            }
            "colour_speed" => match number(key, value)? {
                s if (0.0..=1.0).contains(&s) => self.look.colour_speed = s,
                _ => return Err(refuse("expected a number between 0 and 1")),
            },
            "brightness" | "gamma" | "supersample" | "vibrancy" | "blur" | "blur_curve" | "background" => {
                self.look.tone = tone(key, value, self.look.tone).map_err(|e| refuse(&e))?;
            }
            other => unreachable!("the key `{other}` has no setter"),
        }
        Ok(())
    }

    /// A file key: axes, digits, ASCII, dedup, texture.
    fn apply_file(&mut self, key: &'static Key, value: Value) -> Result<(), OptionError> {
        let given = shown(&value);
        let refuse = |why: &str| OptionError::new(key, &given, why);
        match key.name {
            "uv" => self.file.uv = switch(key, value)?,
            "up" => {
                self.file.coordinates.up = match choice(key, value)? {
                    "z" => Up::Z,
                    "y" => Up::Y,
                    _ => Up::Auto,
                }
            }
            "ascii" => self.file.ascii = switch(key, value)?,
            "precision" => match count(key, value)? {
                p @ 1..=15 => self.file.coordinates = self.file.coordinates.with_precision(Some(p as u32)),
                _ => return Err(refuse("a number of significant digits is 1 to 15")),
            },
            "dedup" => self.file.dedup = switch(key, value)?,
            "thickness" => match number(key, value)? {
                t if t.is_finite() && t > 0.0 => self.file.thickness = Some(t),
                _ => return Err(refuse("a thickness is a positive number (modelling units)")),
            },
            "print_size" | "print_scale" | "nozzle" => {
                let mm = match number(key, value)? {
                    mm if mm.is_finite() && mm > 0.0 && mm <= 1e6 => mm,
                    _ => return Err(refuse("a length in millimetres, positive and at most 10⁶ (a kilometre)")),
                };
                match key.name {
                    "print_size" => (self.file.print.size, self.file.print.scale) = (Some(mm), None),
                    "print_scale" => (self.file.print.scale, self.file.print.size) = (Some(mm), None),
                    _ => self.file.print.nozzle = mm,
                }
            }
            "allow_non_manifold" => self.file.print.allow_non_manifold = switch(key, value)?,
            other => unreachable!("the key `{other}` has no setter"),
        }
        Ok(())
    }
}

/// The tone with one of its settings changed, checked.
fn tone(key: &Key, value: Value, mut t: Tone) -> Result<Tone, String> {
    if key.name == "background" {
        t.background = Some(Tone::parse_colour(&text(key, value).map_err(|e| e.why)?)?);
        return Ok(t);
    }
    let x = number(key, value).map_err(|e| e.why)?;
    match key.name {
        "brightness" => t.brightness = x,
        "gamma" => t.gamma = x,
        "vibrancy" => t.vibrancy = x,
        "blur" => t.blur = x,
        "blur_curve" => t.blur_curve = x,
        _ if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) => t.supersample = x as u32,
        _ => return Err("expected a whole number".into()),
    }
    let checked = t.checked()?;
    Ok(checked)
}

/// A value as the message quotes it.
fn shown(value: &Value) -> String {
    match value {
        Value::Switch(b) => b.to_string(),
        Value::Int(n) => n.to_string(),
        Value::Number(x) => x.to_string(),
        Value::Text(t) => clip(t),
        Value::Texts(ts) => clip(&ts.join(" ")),
        Value::Values(vs) => vs.iter().map(|(n, v)| format!("{n}={v}")).collect::<Vec<_>>().join(" "),
        Value::Pair(a, b) => format!("{a},{b}"),
    }
}

/// At most 40 characters of a text given, so a message stays a line;
/// quoted when it is empty or has spaces.
fn clip(text: &str) -> String {
    let short = match text.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_string(),
    };
    if short.is_empty() || short.contains(char::is_whitespace) { format!("`{short}`") } else { short }
}

fn expected(key: &Key, value: &Value, what: &str) -> OptionError {
    OptionError::new(key, shown(value), format!("expected {what}"))
}

fn switch(key: &Key, value: Value) -> Result<bool, OptionError> {
    match value {
        Value::Switch(b) => Ok(b),
        Value::Text(t) if matches!(t.as_str(), "true" | "1" | "yes" | "on") => Ok(true),
        Value::Text(t) if matches!(t.as_str(), "false" | "0" | "no" | "off") => Ok(false),
        other => Err(expected(key, &other, "true or false")),
    }
}

fn count(key: &Key, value: Value) -> Result<u128, OptionError> {
    match value {
        Value::Int(n) if n >= 0 => Ok(n as u128),
        Value::Text(ref t) => t.trim().parse().map_err(|_| expected(key, &value, "a whole number, 0 or more")),
        other => Err(expected(key, &other, "a whole number, 0 or more")),
    }
}

fn number(key: &Key, value: Value) -> Result<f64, OptionError> {
    let x = match value {
        Value::Number(x) => x,
        Value::Int(n) => n as f64,
        Value::Text(ref t) => t.trim().parse().map_err(|_| expected(key, &value, "a number"))?,
        other => return Err(expected(key, &other, "a number")),
    };
    if x.is_nan() {
        return Err(expected(key, &Value::Number(x), "a number"));
    }
    Ok(x)
}

fn text(key: &Key, value: Value) -> Result<String, OptionError> {
    match value {
        Value::Text(t) => Ok(t),
        other => Err(expected(key, &other, "text")),
    }
}

fn choice(key: &'static Key, value: Value) -> Result<&'static str, OptionError> {
    let Kind::Choice(words) = key.kind else { unreachable!("{} is a choice", key.name) };
    let t = text(key, value)?;
    let quoted: Vec<String> = words.iter().map(|w| format!("`{w}`")).collect();
    words.iter().copied().find(|w| *w == t).ok_or_else(|| expected(key, &Value::Text(t), &quoted.join(", ")))
}

fn names(key: &Key, value: Value) -> Result<Vec<String>, OptionError> {
    match value {
        Value::Text(t) => Ok(vec![t]),
        Value::Texts(ts) => Ok(ts),
        other => Err(expected(key, &other, "names")),
    }
}

/// `NAME=VALUE` pairs: given, or parsed (exact values: `1/4`, `sqrt(2)/4`); a name given twice is refused.
fn pairs(key: &Key, value: Value) -> Result<Vec<(String, f64)>, OptionError> {
    let texts = match value {
        Value::Values(vs) => return distinct(key, vs),
        Value::Text(t) => vec![t],
        Value::Texts(ts) => ts,
        other => return Err(expected(key, &other, "NAME=VALUE pairs")),
    };
    let mut out = Vec::with_capacity(texts.len());
    for t in texts {
        let bad = |why: String| OptionError::new(key, clip(&t), why);
        let (name, v) = t.split_once('=').ok_or_else(|| bad("expected NAME=VALUE".into()))?;
        let v = v.trim().parse::<crate::algebra::Num>().map_err(|e| bad(e.to_string()))?;
        out.push((name.trim().to_string(), v.to_f64()));
    }
    distinct(key, out)
}

fn distinct(key: &Key, pairs: Vec<(String, f64)>) -> Result<Vec<(String, f64)>, OptionError> {
    for (i, (name, v)) in pairs.iter().enumerate() {
        if !v.is_finite() {
            return Err(OptionError::new(key, format!("{name}={v}"), "expected a finite number"));
        }
        if pairs[..i].iter().any(|(n, _)| n == name) {
            return Err(OptionError::new(key, "", format!("`{name}` is given twice: one value per name")));
        }
    }
    Ok(pairs)
}

/// Two numbers: given, or text `AsepB` (`800x600`, `30,35`).
fn pair(key: &Key, value: Value, sep: char) -> Result<(f64, f64), OptionError> {
    let what = if sep == 'x' { "WIDTHxHEIGHT" } else { "YAW,PITCH" };
    match value {
        Value::Pair(a, b) => Ok((a, b)),
        Value::Text(ref t) => {
            let parsed = t.split_once(sep).and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)));
            parsed.ok_or_else(|| expected(key, &value, what))
        }
        other => Err(expected(key, &other, what)),
    }
}
