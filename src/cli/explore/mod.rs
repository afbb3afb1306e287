//! `bcifs explore NAME|FILE`: a local web page where a family's parameters,
//! its maps and the attractor sit side by side. The design is parsed,
//! solved and its parameter ranges found once; every request then renders
//! through the library's render API under a time and memory budget.
//!
//! The API (JSON errors `{"error": …}` with a 4xx status, never a panic):
//! `GET /api/design`, `/api/check?NAME=VALUE…`, `/api/dimension?…`,
//! `/api/picture.png?…&depth=&size=WxH&view=YAW,PITCH`,
//! `/api/map.png?x=&y=&kind=verdict|region|angle|smooth|dimension&size=&xr=&yr=&threshold=`
//! (without `y`: a strip over `x`, for one-parameter families),
//! `/api/scene.glb?…&depth=` (the GLB the export gives, for the page's 3D
//! view: cancelled by a newer one of its slot), `/api/export.{obj,ply,glb,png,toml}?…`,
//! `/api/bye?session=` (GET or the
//! page's beacon POST: its requests stop). A request that names a `slot`
//! (the page's picture, its map) cancels the older one of the same slot
//! (older: a smaller `seq`, the page's counter, else an earlier arrival).

use std::collections::HashMap;
use std::io::Read as _;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

mod fit;

use anyhow::{Context, Result, bail};
use serde_json::{Value, json};

use bcifs::render::{Cancel, Design};
use bcifs::render::{Options, Profile, SweepKind};

const PAGE: &str = include_str!("index.html");
const SCRIPT: &str = include_str!("explore.js");
/// The page's 3D view: a GLB reader and a WebGL orbit view, written here (nothing fetched at run time).
const VIEWER: &str = include_str!("view3d.js");
/// The tab's icon: the Sierpiński gasket at depth 2, three triangles of three.
const ICON: &str = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 8 7'><path fill='#2d3e50' \
d='M0 7h2l1-2zM2 7h2l-1-2zM1 5h2l-1-2zM4 7h2l1-2zM6 7h2l-1-2zM5 5h2l-1-2zM2 3h2l1-2zM4 3h2l-1-2zM3 1h2l-1-1z'/></svg>";

/// Every request's budget (time, memory, depth, picture side): the library's explorer profile.
const PROFILE: Profile = Profile::Explorer;
/// The render keys a query may give (the others are the design's parameters).
const QUERY_KEYS: [&str; 3] = ["depth", "size", "view"];

/// The time after which a request is cancelled.
fn time_budget() -> Duration {
    PROFILE.budget().time.unwrap_or(Duration::MAX)
}

/// Every request's memory for evaluation and pictures.
fn memory_budget() -> usize {
    PROFILE.budget().memory
}
/// Worker threads answering requests.
const WORKERS: usize = 8;
/// Requests that may hold [`memory_budget`] at once (pictures, maps,
/// dimensions, exports); the others wait their turn, within their time
/// budget: the server stays under this many budgets whatever the pages ask.
const HEAVY_AT_ONCE: usize = 2;

#[derive(clap::Args)]
pub struct ExploreArgs {
    /// The automaton file (TOML), or the name of a shipped automaton or preset.
    file: String,
    /// The port (0: a free one).
    #[arg(long, default_value_t = 8765)]
    port: u16,
    /// The address to listen on (127.0.0.1: this machine only).
    #[arg(long, default_value = "127.0.0.1")]
    bind: String,
    /// Do not open the browser.
    #[arg(long)]
    no_open: bool,
    /// For a polygon mesh (OBJ, OFF): the scheme whose generated automaton is
    /// explored (doo-sabin, catmull-clark, loop, sqrt3), its weights the parameters.
    #[arg(long, value_enum)]
    scheme: Option<bcifs::render::Scheme>,
}

/// A free parameter with its default and its convergence range.
type Parameter = bcifs::render::ParameterRange;

/// What every request shares: the design, prepared once.
struct Explorer {
    design: Design,
    parameters: Vec<Parameter>,
    slots: Mutex<HashMap<String, (u64, Cancel)>>,
    deadlines: Mutex<Vec<(Instant, Cancel)>>,
    sweeps: Mutex<HashMap<String, bcifs::render::SweepValues>>,
    /// Whether the maps of a curve family (regions, angles) can be drawn:
    /// offered by the page only then.
    curve_maps: bool,
    /// The output is a mesh (a surface or a solid).
    mesh: bool,
    /// Heavy requests running, and its signal when one ends.
    heavy: (Mutex<usize>, std::sync::Condvar),
}

/// A heavy request's turn ([`Explorer::admit`]), given back when dropped.
struct Turn<'a>(&'a Explorer);

impl Drop for Turn<'_> {
    fn drop(&mut self) {
        let (running, ended) = &self.0.heavy;
        if let Ok(mut running) = running.lock() {
            *running -= 1;
        }
        ended.notify_one();
    }
}

/// An answer: status, content type, body, and a file name for downloads.
struct Answer {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
    download: Option<String>,
}

impl Answer {
    fn json(value: &Value) -> Answer {
        Answer { status: 200, kind: "application/json", body: value.to_string().into_bytes(), download: None }
    }
    /// 409: superseded by a newer request of the same slot (over the time
    /// budget, [`Explorer::answer`] makes it a 422 that says so).
    fn cancelled() -> Answer {
        Answer::error(409, "cancelled: a newer request of the same slot")
    }
    /// A library refusal: 409 cancelled, 413 over the memory budget (with
    /// the estimate), 422 anything else the design or its parameters cause.
    fn refused(e: &bcifs::render::RenderError) -> Answer {
        use bcifs::render::RenderError as E;
        match e {
            E::Cancelled => Answer::cancelled(),
            E::Eval(bcifs::render::EvalError::TooLarge { .. }) | E::Raster(_) | E::TooBig(_) => {
                Answer::error(413, format!("over the memory budget of {} MiB: {e}", memory_budget() >> 20))
            }
            _ => Answer::error(422, e),
        }
    }
    fn error(status: u16, message: impl std::fmt::Display) -> Answer {
        let body = json!({ "error": message.to_string() }).to_string().into_bytes();
        Answer { status, kind: "application/json", body, download: None }
    }
}

impl Explorer {
    fn new(design: Design) -> Result<Explorer> {
        let many = bcifs::render::solve(&design).is_ok_and(|f| f.parameter_names().len() > 24);
        if design.automaton().states().count() > 64 || many {
            eprintln!(
                "explore: {}: finding each free parameter's convergence range (a minute on a large mesh or family)…",
                design.name()
            );
        }
        let parameters = bcifs::render::parameter_ranges(&design)?;
        // A curve map of one pixel at the defaults: made, or refused for what the design is.
        let curve_maps = parameters.first().is_some_and(|p| {
            let plane = bcifs::render::ParameterPlane::line(&p.name, p.default, p.default + 1e-9, 1);
            bcifs::render::sweep(&design, &plane, SweepKind::Angle, false, 0..1).is_ok()
        });
        // Whether the output is a mesh (a surface or a solid: the page offers its 3D view).
        let mesh = bcifs::render::evaluate_design(&design, &Options::default().with_depth(1), &mut Vec::new())
            .is_ok_and(|shape| !shape.quads.is_empty() || !shape.triangles.is_empty());
        Ok(Explorer {
            design,
            parameters,
            mesh,
            slots: Mutex::new(HashMap::new()),
            deadlines: Mutex::new(Vec::new()),
            sweeps: Mutex::new(HashMap::new()),
            curve_maps,
            heavy: (Mutex::new(0), std::sync::Condvar::new()),
        })
    }

    /// Waits for a heavy request's turn (at most [`HEAVY_AT_ONCE`] run at
    /// once); cancelled (superseded, over the time budget) while waiting: 409.
    fn admit(&self, cancel: &Cancel) -> std::result::Result<Turn<'_>, Answer> {
        let (running, ended) = &self.heavy;
        let mut running = running.lock().map_err(|_| Answer::error(500, "internal error"))?;
        while *running >= HEAVY_AT_ONCE {
            if cancel.is_cancelled() {
                return Err(Answer::cancelled());
            }
            running = ended
                .wait_timeout(running, Duration::from_millis(50))
                .map_err(|_| Answer::error(500, "internal error"))?
                .0;
        }
        *running += 1;
        Ok(Turn(self))
    }

    /// A cancel flag for a request: cancelled after the time budget, or
    /// when a newer request names the same `slot` (newer: a larger `seq`,
    /// the page's counter, else the later arrival). A request older than
    /// the slot's current one is cancelled at once.
    fn cancel_for(&self, slot: Option<&str>, seq: Option<u64>) -> Cancel {
        let cancel = Cancel::new();
        if let Some(slot) = slot
            && let Ok(mut slots) = self.slots.lock()
        {
            let seq = seq.unwrap_or_else(|| slots.get(slot).map_or(0, |(s, _)| s + 1));
            match slots.get(slot) {
                Some((current, _)) if *current > seq => cancel.cancel(),
                _ => {
                    if let Some((_, older)) = slots.insert(slot.to_string(), (seq, cancel.clone())) {
                        older.cancel();
                    }
                }
            }
        }
        if let Ok(mut d) = self.deadlines.lock() {
            d.push((Instant::now() + time_budget(), cancel.clone()));
        }
        cancel
    }

    /// Cancels every request of the page `session` (its slots end in
    /// `-SESSION`): the page is going away. How many were running.
    fn bye(&self, session: &str) -> usize {
        let suffix = format!("-{session}");
        let Ok(mut slots) = self.slots.lock() else { return 0 };
        let gone: Vec<String> = slots.keys().filter(|k| k.ends_with(&suffix)).cloned().collect();
        gone.iter()
            .filter_map(|k| slots.remove(k))
            .filter(|(_, cancel)| {
                let running = !cancel.is_cancelled();
                cancel.cancel();
                running
            })
            .count()
    }

    /// Cancels the requests past their budget (run every 100 ms).
    fn expire(&self) {
        if let Ok(mut d) = self.deadlines.lock() {
            let now = Instant::now();
            d.retain(|(at, cancel)| {
                if *at <= now {
                    cancel.cancel();
                }
                *at > now && !cancel.is_cancelled()
            });
        }
    }

    /// The parameter values of a query: every free parameter it names (others: defaults).
    fn values(&self, query: &Query) -> std::result::Result<Vec<(String, f64)>, Answer> {
        let reserved = ["slot", "seq", "x", "y", "kind", "xr", "yr", "threshold", "session"];
        let mut values: Vec<(String, f64)> = Vec::new();
        for (k, v) in &query.pairs {
            if reserved.contains(&k.as_str()) || QUERY_KEYS.contains(&k.as_str()) {
                continue;
            }
            if !self.parameters.iter().any(|p| &p.name == k) {
                let names: Vec<&str> = self.parameters.iter().map(|p| p.name.as_str()).collect();
                return Err(Answer::error(
                    400,
                    format!("`{}` is not a parameter of {}: {names:?}", clip(k), self.design.name()),
                ));
            }
            if values.iter().any(|(n, _)| n == k) {
                return Err(Answer::error(400, format!("parameter `{k}` is given twice: give it once")));
            }
            let x: f64 = v.parse().ok().filter(|x: &f64| x.is_finite()).ok_or_else(|| {
                Answer::error(400, format!("parameter `{k}` = `{}`: expected a finite number", clip(v)))
            })?;
            values.push((k.clone(), x));
        }
        Ok(values)
    }

    /// The render options of a query, checked: depth, size, view, under the budgets.
    fn options(&self, query: &Query, cancel: Cancel) -> std::result::Result<Options, Answer> {
        let mut options = PROFILE.options().with_cancel(cancel);
        options.params = self.values(query)?;
        let given = query.pairs.iter().filter(|(k, _)| QUERY_KEYS.contains(&k.as_str()));
        options
            .set_values(given.map(|(k, v)| (k, bcifs::render::Value::from(v.as_str()))))
            .map_err(|e| Answer::error(400, e))?;
        Ok(options)
    }

    /// The bytes `render` would write to a file of extension `ext`, made in memory.
    fn render_bytes(&self, options: &Options, ext: &str) -> std::result::Result<Vec<u8>, Answer> {
        let _turn = self.admit(&options.cancel)?;
        let format =
            bcifs::render::Format::of(std::path::Path::new(&format!("x.{ext}"))).map_err(|e| Answer::error(404, e))?;
        Ok(rendered(bcifs::render::render_bytes(&self.design, options, format), options)?.1)
    }

    /// The picture `render` would write, drawn in memory and encoded for the
    /// browser (fast compression: the page is on this machine).
    fn picture(&self, options: &Options) -> std::result::Result<Vec<u8>, Answer> {
        let _turn = self.admit(&options.cancel)?;
        let drawn = bcifs::render::picture_png(&self.design, options, bcifs::render::Compression::Fast);
        Ok(rendered(drawn, options)?.1)
    }

    fn design_json(&self) -> Value {
        let parameters: Vec<Value> = self
            .parameters
            .iter()
            .map(|p| json!({"name": p.name, "default": p.default, "range": [p.range.0, p.range.1]}))
            .collect();
        let curve = bcifs::render::instantiate(&self.design, &[])
            .ok()
            .is_some_and(|i| bcifs::render::curve_halves(&self.design, &i).is_ok());
        json!({
            "name": self.design.name(), "description": self.design.description(),
            "parameters": parameters, "curve": curve, "curve_maps": self.curve_maps, "mesh": self.mesh,
        })
    }

    /// `/api/map.png`: a map of two parameters (`x`, `y`), or a strip of one
    /// (`y` left out: a one-parameter family such as the ternary scheme's ω).
    fn map(&self, query: &Query, cancel: &Cancel) -> std::result::Result<Vec<u8>, Answer> {
        let asked = query.get("kind").unwrap_or("verdict");
        let (kind, smooth) = match asked {
            "smooth" => (SweepKind::Angle, true),
            other => (other.parse::<SweepKind>().map_err(|e| Answer::error(400, format!("{e} (or smooth)")))?, false),
        };
        let threshold: f64 =
            match query.get("threshold") {
                None => 5.0,
                Some(t) => t.parse().ok().filter(|t: &f64| t.is_finite() && *t > 0.0).ok_or_else(|| {
                    Answer::error(400, format!("threshold `{}`: a positive angle in degrees", clip(t)))
                })?,
            };
        let size: usize =
            query.get("size").unwrap_or("192").parse().map_err(|_| Answer::error(400, "size: a number of pixels"))?;
        if size == 0 || size > 512 {
            return Err(Answer::error(400, format!("map size {size}: 1 to 512 pixels")));
        }
        let axis = |key: &str, range_key: &str| -> std::result::Result<(String, f64, f64), Answer> {
            let name =
                query.get(key).ok_or_else(|| Answer::error(400, format!("`{key}`: the map's {key} parameter")))?;
            let p = self
                .parameters
                .iter()
                .find(|p| p.name == name)
                .ok_or_else(|| Answer::error(400, format!("`{}` is not a parameter", clip(name))))?;
            let (lo, hi) = match query.get(range_key) {
                Some(r) => parse_range(range_key, r)?,
                None => {
                    let w = p.range.1 - p.range.0;
                    (p.range.0 - w / 2.0, p.range.1 + w / 2.0)
                }
            };
            Ok((name.to_string(), lo, hi))
        };
        let x = axis("x", "xr")?;
        let plane = match query.get("y") {
            None => bcifs::render::ParameterPlane::line(&x.0, x.1, x.2, size),
            Some(y) if y == x.0 => return Err(Answer::error(400, "x and y must be two different parameters")),
            Some(_) => bcifs::render::ParameterPlane { x, y: axis("y", "yr")?, size: (size, size) },
        };
        let _turn = self.admit(cancel)?;
        let values = self.swept(&plane, kind, cancel)?.to_f64();
        // Angles are drawn where the bounds prove convergence; elsewhere the verdict's colour.
        let verdicts = match kind {
            SweepKind::Angle => Some(self.swept(&plane, SweepKind::Verdict, cancel)?.to_f64()),
            _ => None,
        };
        let colour = |i: usize| -> [u8; 3] {
            match &verdicts {
                Some(v) if v[i] != 1.0 => bcifs::render::verdict_colour(v[i] as i8),
                _ if smooth && values[i].is_nan() => [228, 228, 228],
                _ if smooth => {
                    if values[i] < threshold {
                        [20, 20, 20]
                    } else {
                        [255, 255, 255]
                    }
                }
                _ => bcifs::render::sweep_colour(kind, values[i]),
            }
        };
        let (w, h) = (size as u32, if plane.is_line() { (size as u32 / 6).max(8) } else { size as u32 });
        let img = image::RgbImage::from_fn(w, h, |i, j| {
            image::Rgb(colour(if plane.is_line() { i as usize } else { j as usize * size + i as usize }))
        });
        bcifs::render::png_bytes(&img, &[], None, bcifs::render::Compression::Fast).map_err(|e| Answer::error(500, e))
    }

    /// The sweep of `kind` over `plane`, computed band by band (a newer map
    /// or the budget stops it between bands) and kept for the next request.
    fn swept(
        &self,
        plane: &bcifs::render::ParameterPlane,
        kind: SweepKind,
        cancel: &Cancel,
    ) -> std::result::Result<bcifs::render::SweepValues, Answer> {
        let key = format!("{}|{plane:?}", kind.name());
        if let Some(values) = self.sweeps.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return Ok(values);
        }
        let rows = plane.size.1;
        // A dimension pixel evaluates an attractor: a row at a time.
        let band =
            if matches!(kind, SweepKind::Dimension | SweepKind::Porosity | SweepKind::Lacunarity) { 1 } else { 16 };
        let mut values: Option<bcifs::render::SweepValues> = None;
        for start in (0..rows).step_by(band) {
            if cancel.is_cancelled() {
                return Err(Answer::cancelled());
            }
            let rows = start..(start + band).min(rows);
            let band = bcifs::render::sweep_cancellable(&self.design, plane, kind, false, rows, cancel)
                .map_err(|e| Answer::refused(&e.into()))?;
            values = Some(match values {
                None => band,
                Some(v) => v.append(band),
            });
        }
        let values = values.ok_or_else(|| Answer::error(400, "an empty map"))?;
        if let Ok(mut m) = self.sweeps.lock() {
            m.insert(key, values.clone());
        }
        Ok(values)
    }

    /// The answer to `GET path?query`; a request cancelled after the time
    /// budget is a 422 that says so (the page shows it where the picture was).
    /// Not a 408: Chromium sends a request again when a reused connection
    /// answers 408, so a map over its budget was asked again for ever.
    fn answer(&self, path: &str, query: &Query) -> Answer {
        let started = Instant::now();
        let answer = self.answer_now(path, query);
        if answer.status == 409 && started.elapsed() >= time_budget() {
            let budget = time_budget().as_secs();
            return Answer::error(422, format!("over the time budget of {budget} s: lower the depth, size or range"));
        }
        answer
    }

    fn answer_now(&self, path: &str, query: &Query) -> Answer {
        if path.contains("..") || path.contains('\\') {
            return Answer::error(400, "`..` is not allowed in a path");
        }
        let slot = query.get("slot");
        let seq = query.get("seq").and_then(|s| s.parse().ok());
        match path {
            "/favicon.ico" | "/favicon.svg" => {
                Answer { status: 200, kind: "image/svg+xml", body: ICON.into(), download: None }
            }
            "/" | "/index.html" => {
                Answer { status: 200, kind: "text/html; charset=utf-8", body: PAGE.into(), download: None }
            }
            "/explore.js" => {
                Answer { status: 200, kind: "text/javascript; charset=utf-8", body: SCRIPT.into(), download: None }
            }
            "/view3d.js" => {
                Answer { status: 200, kind: "text/javascript; charset=utf-8", body: VIEWER.into(), download: None }
            }
            "/api/scene.glb" => {
                let cancel = self.cancel_for(slot, seq);
                match self.options(query, cancel).and_then(|options| self.render_bytes(&options, "glb")) {
                    Ok(body) => Answer { status: 200, kind: "model/gltf-binary", body, download: None },
                    Err(a) => a,
                }
            }
            "/api/design" => Answer::json(&self.design_json()),
            "/api/bye" => match query.get("session").filter(|s| !s.is_empty()) {
                Some(session) => Answer::json(&json!({ "cancelled": self.bye(session) })),
                None => Answer::error(400, "`session`: the page whose requests stop"),
            },
            "/api/check" => self.values(query).map_or_else(|a| a, |values| self.check(&values)),
            "/api/dimension" => match self.values(query) {
                Err(a) => a,
                Ok(values) => self.dimension(&values, &self.cancel_for(slot, seq)),
            },
            "/api/picture.png" => {
                let cancel = self.cancel_for(slot, seq);
                match self.options(query, cancel).and_then(|options| self.picture(&options)) {
                    Ok(body) => Answer { status: 200, kind: "image/png", body, download: None },
                    Err(a) => a,
                }
            }
            "/api/map.png" => {
                let cancel = self.cancel_for(slot, seq);
                match self.map(query, &cancel) {
                    Ok(body) => Answer { status: 200, kind: "image/png", body, download: None },
                    Err(a) => a,
                }
            }
            _ => match path.strip_prefix("/api/export.") {
                Some(ext) => self.export(ext, query),
                None => Answer::error(404, format!("`{}`: not found (the page is /, the API under /api/)", clip(path))),
            },
        }
    }

    /// `/api/check`: the check report at `values`, and the curve's analysis where it has one.
    fn check(&self, values: &[(String, f64)]) -> Answer {
        match bcifs::render::check_report(&self.design, values) {
            Err(e) => Answer::error(422, e),
            Ok(check) => {
                let exact: Vec<(String, bcifs::render::Num)> =
                    values.iter().map(|(n, v)| (n.clone(), bcifs::render::Num::from_f64(*v))).collect();
                let curve = bcifs::render::curve_analysis(&self.design, &exact).ok().map(|c| c.to_json());
                Answer::json(&json!({"check": check, "curve": curve}))
            }
        }
    }

    /// `/api/dimension`: the box-counting dimension at `values`, one at a time, cancellable.
    fn dimension(&self, values: &[(String, f64)], cancel: &bcifs::render::Cancel) -> Answer {
        let _turn = match self.admit(cancel) {
            Ok(turn) => turn,
            Err(a) => return a,
        };
        match bcifs::render::dimension_within(&self.design, values, memory_budget(), cancel) {
            Ok(_) if cancel.is_cancelled() => Answer::cancelled(),
            Ok(d) => Answer::json(&d.to_json()),
            Err(e) => Answer::refused(&e.into()),
        }
    }

    /// `/api/export.EXT`: the design with the page's values as defaults (`toml`), or a file of it.
    fn export(&self, ext: &str, query: &Query) -> Answer {
        match ext {
            "toml" => match self.values(query) {
                Err(a) => a,
                Ok(values) => {
                    let mut builder = self.design.to_builder();
                    for (n, v) in &values {
                        builder.default_value(n, *v);
                    }
                    match builder.build() {
                        Ok(d) => Answer {
                            status: 200,
                            kind: "application/toml",
                            body: bcifs::render::write_design(&d).into_bytes(),
                            download: Some(format!("{}.toml", d.name())),
                        },
                        Err(e) => Answer::error(422, e),
                    }
                }
            },
            "obj" | "ply" | "glb" | "png" => match self.options(query, self.cancel_for(None, None)) {
                Err(a) => a,
                Ok(options) => match self.render_bytes(&options, ext) {
                    Ok(body) => Answer {
                        status: 200,
                        kind: if ext == "png" { "image/png" } else { "application/octet-stream" },
                        body,
                        download: Some(format!("{}.{ext}", self.design.name())),
                    },
                    Err(a) => a,
                },
            },
            other => Answer::error(404, format!("no export to `.{}`: obj, ply, glb, png or toml", clip(other))),
        }
    }
}

/// A render's result as an answer: 409 when cancelled, or superseded while
/// it was evaluated (an in-memory evaluation looks at the flag between its
/// stages only: the page wants the newer one), 422 for the library's errors.
fn rendered<T>(
    result: std::result::Result<T, bcifs::render::RenderError>,
    options: &Options,
) -> std::result::Result<T, Answer> {
    match result {
        Ok(_) if options.cancel.is_cancelled() => Err(Answer::cancelled()),
        Ok(value) => Ok(value),
        Err(e) => Err(Answer::refused(&e)),
    }
}

/// `FROM:TO`, finite and increasing.
fn parse_range(key: &str, text: &str) -> std::result::Result<(f64, f64), Answer> {
    let bad = || Answer::error(400, format!("{key} `{}`: expected FROM:TO, finite, FROM < TO", clip(text)));
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let (a, b): (f64, f64) = (a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?);
    if !(a.is_finite() && b.is_finite() && a < b && (b - a).is_finite()) {
        return Err(bad());
    }
    Ok((a, b))
}

/// `text` as an error message quotes it: at most 40 characters, then how long it was.
fn clip(text: &str) -> String {
    match text.char_indices().nth(40) {
        None => text.to_string(),
        Some((at, _)) => format!("{}… ({} bytes)", &text[..at], text.len()),
    }
}

/// A URL's query, percent-decoded.
struct Query {
    pairs: Vec<(String, String)>,
}

impl Query {
    fn parse(text: &str) -> Query {
        let pairs = text
            .split('&')
            .filter(|p| !p.is_empty())
            .map(|p| {
                let (k, v) = p.split_once('=').unwrap_or((p, ""));
                (decode(k), decode(v))
            })
            .collect();
        Query { pairs }
    }

    fn get(&self, key: &str) -> Option<&str> {
        self.pairs.iter().rev().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

/// Percent-decoding (`+` is a space); invalid escapes are kept as they are.
fn decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < bytes.len() => {
                match u8::from_str_radix(std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("zz"), 16) {
                    Ok(b) => {
                        out.push(b);
                        i += 2;
                    }
                    Err(_) => out.push(b'%'),
                }
            }
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Whether a request's `Host` may be served: `localhost`, a loopback
/// address or the bound one, with any port; any address literal when bound
/// to all interfaces. Never another name: a page of another site whose
/// name was made to point here (DNS rebinding) would read the design and
/// start the costly endpoints. No `Host` (HTTP/1.0, no browser) is served.
fn host_allowed(host: Option<&str>, bound: std::net::IpAddr) -> bool {
    let Some(host) = host else { return true };
    let name = match host.strip_prefix('[') {
        Some(rest) => rest.split(']').next().unwrap_or(""),
        None => {
            host.rsplit_once(':').map_or(host, |(name, port)| if port.parse::<u16>().is_ok() { name } else { host })
        }
    };
    if name.eq_ignore_ascii_case("localhost") {
        return true;
    }
    match name.parse::<std::net::IpAddr>() {
        Ok(ip) => ip.is_loopback() || ip == bound || bound.is_unspecified(),
        Err(_) => false,
    }
}

/// Answers one request.
fn serve(explorer: &Explorer, mut request: tiny_http::Request, bound: std::net::IpAddr) {
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let path = decode(path);
    let method = request.method().clone();
    // The page's goodbye comes as a beacon (a POST); everything else only reads.
    let beacon = method == tiny_http::Method::Post && path == "/api/bye";
    // A fit's target comes as a POST's body (an upload), read up to its limit.
    let upload = method == tiny_http::Method::Post && path == "/api/fit";
    let reads = matches!(method, tiny_http::Method::Get | tiny_http::Method::Head);
    let mut body = Vec::new();
    if upload {
        let _ = request.as_reader().take(fit::UPLOAD_LIMIT).read_to_end(&mut body);
    } else if !reads {
        // Drain what was sent.
        let _ = std::io::copy(&mut request.as_reader().take(1 << 20), &mut std::io::sink());
    }
    let host = request.headers().iter().find(|h| h.field.equiv("Host")).map(|h| h.value.as_str().to_string());
    let answer = if !host_allowed(host.as_deref(), bound) {
        let shown = clip(host.as_deref().unwrap_or(""));
        Answer::error(403, format!("Host `{shown}` is not served: open the page at localhost or {bound}"))
    } else if upload {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| explorer.fit(&Query::parse(query), &body)))
            .unwrap_or_else(|_| Answer::error(500, "internal error"))
    } else if !reads && !beacon {
        Answer::error(405, "only GET and HEAD are served (and POST /api/bye, /api/fit)")
    } else {
        // A panic in a request is a 500, not a dead worker.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| explorer.answer(&path, &Query::parse(query))))
            .unwrap_or_else(|_| Answer::error(500, "internal error"))
    };
    let mut response = tiny_http::Response::from_data(answer.body).with_status_code(answer.status);
    let header = |k: &str, v: &str| tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes()).ok();
    for h in [
        header("Content-Type", answer.kind),
        header("Cache-Control", "no-store"),
        answer
            .download
            .as_deref()
            .and_then(|name| header("Content-Disposition", &format!("attachment; filename=\"{name}\""))),
    ]
    .into_iter()
    .flatten()
    {
        response.add_header(h);
    }
    let _ = request.respond(response);
}

/// `bcifs explore`.
pub fn run(args: ExploreArgs) -> Result<u8> {
    let design = bcifs::render::load_with_scheme(&args.file, args.scheme)?;
    let addr: std::net::IpAddr =
        args.bind.parse().with_context(|| format!("--bind `{}`: expected an IP address", args.bind))?;
    if !addr.is_loopback() {
        eprintln!(
            "warning: --bind {addr}: the explorer is reachable from other machines, and serves anyone who connects"
        );
    }
    let explorer = Arc::new(Explorer::new(design)?);
    let server = tiny_http::Server::http(SocketAddr::new(addr, args.port))
        .map_err(|e| anyhow::anyhow!("cannot listen on {addr}:{}: {e}", args.port))?;
    let port = server.server_addr().to_ip().map_or(args.port, |a| a.port());
    let host = if addr.is_unspecified() { "127.0.0.1".to_string() } else { addr.to_string() };
    let host = if host.contains(':') { format!("[{host}]") } else { host };
    let url = format!("http://{host}:{port}/");
    {
        use std::io::Write as _;
        let mut stdout = std::io::stdout().lock();
        writeln!(stdout, "{url}")?;
        writeln!(
            stdout,
            "{}: {} free parameter{}; Ctrl-C stops the server",
            explorer.design.name(),
            explorer.parameters.len(),
            if explorer.parameters.len() == 1 { "" } else { "s" }
        )?;
        stdout.flush()?;
    }
    if !args.no_open {
        open_browser(&url);
    }
    let server = Arc::new(server);
    let mut workers = Vec::new();
    for _ in 0..WORKERS {
        let (server, explorer) = (server.clone(), explorer.clone());
        workers.push(std::thread::spawn(move || {
            while !crate::cli::common::interrupt().is_cancelled() {
                match server.recv_timeout(Duration::from_millis(200)) {
                    // A panic while answering loses that answer, never the worker.
                    Ok(Some(request)) => {
                        if std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| serve(&explorer, request, addr)))
                            .is_err()
                        {
                            eprintln!("explore: a request failed (internal error)");
                        }
                    }
                    Ok(None) => {}
                    Err(_) => break,
                }
            }
        }));
    }
    while !crate::cli::common::interrupt().is_cancelled() {
        explorer.expire();
        std::thread::sleep(Duration::from_millis(100));
    }
    server.unblock();
    for w in workers {
        let _ = w.join();
    }
    bail!("stopped")
}

/// Opens `url` in the desktop's browser, quietly when there is none.
fn open_browser(url: &str) {
    for opener in ["xdg-open", "open"] {
        if std::process::Command::new(opener)
            .arg(url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .is_ok()
        {
            return;
        }
    }
}
