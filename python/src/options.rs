//! Python keywords as the library's option keys: each keyword that names a
//! key of [`bcifs::render::KEYS`] is converted by the key's kind and checked
//! by [`Options::set`] (errors name the keyword, `depth=`); the others are
//! the design's parameters.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use bcifs::render::{KEYS, Key, Kind, OptionError, Options, Value};

use crate::err;

/// A library refusal with its key spelled as a Python keyword (`max_output_gib=`).
pub(crate) fn option_error(e: &OptionError) -> PyErr {
    err(e.spelled(|k| format!("{}=", k.name)))
}

/// A Python value as the value of `key`.
fn value(key: &Key, v: &Bound<'_, PyAny>) -> PyResult<Value> {
    let wrong = |what: &str| err(format!("{}=: expected {what}, not {}", key.name, type_name(v)));
    Ok(match key.kind {
        Kind::Switch => Value::Switch(v.extract().map_err(|_| wrong("True or False"))?),
        Kind::Count if v.is_instance_of::<pyo3::types::PyBool>() => return Err(wrong("a whole number")),
        Kind::Count => Value::Int(v.extract::<i128>().map_err(|_| wrong("a whole number"))?),
        Kind::Number => Value::Number(v.extract().map_err(|_| wrong("a number"))?),
        Kind::Text | Kind::Choice(_) => Value::Text(v.extract().map_err(|_| wrong("a string"))?),
        Kind::Names => match v.extract::<String>() {
            Ok(one) => Value::Texts(vec![one]),
            Err(_) => Value::Texts(v.extract().map_err(|_| wrong("a list of names"))?),
        },
        Kind::Values => {
            let dict = v.cast::<PyDict>().map_err(|_| wrong("a dict {name: value}"))?;
            Value::Texts(
                dict.iter()
                    .map(|(k, x)| Ok(format!("{}={}", k.extract::<String>()?, number_text(&x)?)))
                    .collect::<PyResult<_>>()?,
            )
        }
        Kind::Size | Kind::Angles => {
            let pair = v.cast::<PyTuple>().ok().filter(|t| t.len() == 2).ok_or_else(|| wrong("a pair (a, b)"))?;
            if key.kind == Kind::Size {
                let side =
                    |i: usize| pair.get_item(i)?.extract::<i64>().map_err(|_| wrong("two whole numbers of pixels"));
                Value::Pair(side(0)? as f64, side(1)? as f64)
            } else {
                Value::Pair(
                    pair.get_item(0)?.extract().map_err(|_| wrong("two numbers"))?,
                    pair.get_item(1)?.extract().map_err(|_| wrong("two numbers"))?,
                )
            }
        }
    })
}

/// A number, or an exact value's text (`"1/4"`), as the text `NAME=VALUE` takes.
fn number_text(x: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(text) = x.extract::<String>() {
        return Ok(text);
    }
    let x: f64 =
        x.extract().map_err(|_| err(format!("expected a number or an exact value's text, not {}", type_name(x))))?;
    // Rust writes the shortest decimal that reads back to the same f64, without an exponent.
    Ok(format!("{x}"))
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

/// The options of `keywords` (the keys among them; `tone` {brightness, …}
/// expands into its keys) over `options`; the other keywords are returned,
/// the design's parameter values.
pub(crate) fn apply(options: &mut Options, keywords: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut given: Vec<(&str, Value)> = Vec::new();
    let mut params = Vec::new();
    for (k, v) in keywords.into_iter().flat_map(|d| d.iter()) {
        let name: String = k.extract()?;
        if v.is_none() {
            continue;
        }
        if name == "tone" {
            let tone = v.cast::<PyDict>().map_err(|_| err("tone=: expected a dict {brightness: …}"))?;
            for (t, x) in tone.iter() {
                let t: String = t.extract()?;
                let key = KEYS
                    .iter()
                    .find(|k| k.name == t && TONE.contains(&k.name))
                    .ok_or_else(|| err(format!("tone has no setting `{t}`: {}", TONE.join(", "))))?;
                given.push((key.name, value(key, &x)?));
            }
            continue;
        }
        match KEYS.iter().find(|k| k.name == name) {
            Some(key) => given.push((key.name, value(key, &v)?)),
            None => params.push((name.clone(), crate::param_value(&name, &v)?)),
        }
    }
    options.set_values(given).map_err(|e| option_error(&e))?;
    if !params.is_empty() && !options.params.is_empty() {
        return Err(err("give the parameters as keywords or as params={…}, not both"));
    }
    Ok(params)
}

/// The keys `tone` {…} takes.
const TONE: [&str; 7] = ["brightness", "gamma", "vibrancy", "supersample", "blur", "blur_curve", "background"];

/// Options over the defaults from `keywords`, the design's parameters among them.
pub(crate) fn options(keywords: Option<&Bound<'_, PyDict>>) -> PyResult<Options> {
    let mut options = Options::default();
    let params = apply(&mut options, keywords)?;
    if !params.is_empty() {
        options.params = params;
    }
    Ok(options)
}

/// The keys, for Python: `[{name, flag, group, kind, choices, default, help}]`.
#[pyfunction]
pub(crate) fn option_keys<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
    crate::json_object(py, &KEYS)
}

/// A front end's budget by name (`cli`, `explorer`, `gallery`, `blender`…):
/// `{memory_mib, max_output_gib, threads, time, max_depth, max_side, size}`.
#[pyfunction]
pub(crate) fn profile<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    let profile = bcifs::render::Profile::named(name).ok_or_else(|| {
        let names: Vec<&str> = bcifs::render::Profile::ALL.iter().map(|p| p.name()).collect();
        err(format!("no profile `{name}`: {}", names.join(", ")))
    })?;
    let budget = profile.budget();
    let d = PyDict::new(py);
    d.set_item("memory_mib", budget.memory >> 20)?;
    d.set_item("max_output_gib", budget.output as f64 / f64::from(1u32 << 30))?;
    d.set_item("threads", budget.threads)?;
    d.set_item("time", budget.time.map(|t| t.as_secs_f64()))?;
    d.set_item("max_depth", budget.max_depth)?;
    d.set_item("max_side", budget.max_side)?;
    d.set_item("size", profile.size())?;
    Ok(d)
}
