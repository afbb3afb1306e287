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
    /// A normal-vector figure that could not be made.
    #[error(transparent)]
    Normal(#[from] crate::schemes::NormalSchemeError),
    /// A polygon mesh (OBJ, OFF) opened without a scheme.
    #[error(
        "{0} is a polygon mesh, not an automaton: give the subdivision scheme that makes its automaton (doo-sabin, catmull-clark, loop or sqrt3)"
    )]
    MeshWithoutScheme(String),
    /// A polygon mesh that could not be read.
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshReadError),
    /// A mesh whose automaton could not be generated.
    #[error(transparent)]
    Generate(#[from] crate::schemes::MeshAutomatonError),
}

/// Whether `path` names a polygon mesh file (by its extension: `.obj`, `.off`).
pub fn is_mesh_path(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj") || e.eq_ignore_ascii_case("off"))
}

/// [`load`], and a polygon mesh file (`.obj`, `.off`) as the automaton
/// `scheme` generates from it with the classic weights (what `bcifs
/// surface FILE --scheme S --print` writes).
///
/// # Errors
/// As [`load`]; a mesh without a scheme, unreadable, or whose automaton the
/// scheme cannot make.
pub fn load_with_scheme(name_or_path: &str, scheme: Option<crate::mesh::Scheme>) -> Result<Design, LoadError> {
    let path = Path::new(name_or_path);
    if !(path.is_file() && is_mesh_path(path)) {
        return load(name_or_path);
    }
    let Some(scheme) = scheme else { return Err(LoadError::MeshWithoutScheme(name_or_path.to_string())) };
    let mesh = crate::mesh::read_mesh(path)?;
    Ok(crate::schemes::mesh_automaton(&mesh, scheme, None)?)
}

/// The design in the file `name_or_path`, or, when no such file exists, the
/// shipped automaton, scheme preset or normal-vector figure of that name
/// (every name `bcifs list` shows; `.toml` and `_`/`-` spellings accepted).
///
/// ```
/// let fern = bcifs::render::load("fern")?;
/// assert_eq!(fern.name(), "fern");
/// assert!(bcifs::render::load("box_spline").is_ok());
/// assert_eq!(bcifs::render::load("koch_quad")?.name(), "koch-quad"); // a normal-vector figure
/// let e = bcifs::render::load("fren").unwrap_err();
/// assert!(e.to_string().contains("did you mean `fern`?"));
/// # Ok::<(), bcifs::render::LoadError>(())
/// ```
///
/// # Errors
/// [`LoadError`]: an unknown name (with the closest one), a malformed file.
pub fn load(name_or_path: &str) -> Result<Design, LoadError> {
    let path = Path::new(name_or_path);
    if path.is_file() && is_mesh_path(path) {
        return Err(LoadError::MeshWithoutScheme(name_or_path.to_string()));
    }
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
    if crate::schemes::PRESET_NAMES.contains(&preset.as_str()) {
        return Ok(crate::schemes::normal_preset(&preset)?.design()?);
    }
    let shipped: Vec<&str> = crate::format::BUILTIN_AUTOMATA
        .iter()
        .map(|(n, _)| *n)
        .chain(crate::schemes::IFS_NAMES)
        .chain(crate::schemes::PRESET_NAMES)
        .collect();
    Err(LoadError::Unknown {
        name: name_or_path.to_string(),
        suggestion: crate::names::suggest(name, shipped.iter().copied()),
    })
}
