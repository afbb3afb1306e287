//! Designs by name or path: what every front end (the command line, the
//! Python module) opens.

use std::path::Path;

use crate::design::Design;

/// Why a design could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// Neither a file nor a shipped automaton or preset.
    #[error("`{name}` is neither a file nor a shipped automaton{}; `bcifs list` shows the shipped ones", .suggestion.as_ref().map(|s| format!(" (did you mean `{s}`?)")).unwrap_or_default())]
    Unknown {
        /// What was asked.
        name: String,
        /// The closest shipped name.
        suggestion: Option<String>,
    },
    /// The file could not be read or is malformed (`file:line:column`).
    #[error(transparent)]
    Read(#[from] crate::format::ReadError),
    /// A preset that could not be made.
    #[error(transparent)]
    Preset(#[from] crate::schemes::CatalogError),
}

/// The design in the file `name_or_path`, or, when no such file exists, the
/// shipped automaton or scheme preset of that name (`.toml` and `_`/`-`
/// spellings accepted).
///
/// ```
/// let fern = bcifs::render::load("fern")?;
/// assert_eq!(fern.name(), "fern");
/// assert!(bcifs::render::load("box_spline").is_ok());
/// let e = bcifs::render::load("fren").unwrap_err();
/// assert!(e.to_string().contains("did you mean `fern`?"));
/// # Ok::<(), bcifs::render::LoadError>(())
/// ```
///
/// # Errors
/// [`LoadError`]: an unknown name (with the closest one), a malformed file.
pub fn load(name_or_path: &str) -> Result<Design, LoadError> {
    let path = Path::new(name_or_path);
    if path.exists() {
        return Ok(crate::format::read_design(path)?);
    }
    let name = name_or_path.trim_end_matches(".toml");
    if let Some(d) = crate::format::builtin_design(name) {
        return Ok(d);
    }
    let preset = name.replace('_', "-");
    if crate::schemes::IFS_NAMES.contains(&preset.as_str()) {
        return Ok(crate::schemes::ifs_preset(&preset, None, None)?);
    }
    let shipped: Vec<&str> =
        crate::format::BUILTIN_AUTOMATA.iter().map(|(n, _)| *n).chain(crate::schemes::IFS_NAMES).collect();
    Err(LoadError::Unknown {
        name: name_or_path.to_string(),
        suggestion: crate::names::suggest(name, shipped.iter().copied()),
    })
}
