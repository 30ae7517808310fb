//! Loading a scenario together with what its run is expected to do: the `[verdict]` table
//! and the `[[requirement]]`s of a TOML scenario (built-in or file); an SSP `.ssd` has none
//! and gets the defaults.
use crate::scenarios::{self, BUILT_IN};
use crate::verdict::envelope::{split_scenario, Spec};
use cosim::system::{toml_format, SystemDescription, SystemError};
use std::path::Path;

/// The TOML text of a built-in scenario or a `.toml` file; `None` for anything else.
fn toml_text(name_or_path: &str) -> Result<Option<(String, String)>, SystemError> {
    if let Some((name, text)) = BUILT_IN.iter().find(|(name, _)| *name == name_or_path) {
        return Ok(Some((
            format!("<built-in scenario {name}>"),
            (*text).to_owned(),
        )));
    }
    let path = Path::new(name_or_path);
    if matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("ssd" | "ssp" | "fmu")
    ) {
        return Ok(None);
    }
    let text = std::fs::read_to_string(path).map_err(|e| scenarios::not_found(name_or_path, e))?;
    Ok(Some((name_or_path.to_owned(), text)))
}

/// The system parser's view of a scenario's TOML: without its `[verdict]` table.
pub fn parse_toml(text: &str, origin: &Path) -> Result<SystemDescription, SystemError> {
    let (stripped, _) = split_scenario(text).map_err(|message| SystemError::Syntax {
        path: origin.to_owned(),
        message,
    })?;
    toml_format::parse(&stripped, origin)
}

/// A scenario (built-in name, `.toml`, `.ssd`, `.ssp`, or one `.fmu` alone) and what its run
/// is expected to do.
pub fn load(name_or_path: &str) -> Result<(SystemDescription, Spec), SystemError> {
    match toml_text(name_or_path)? {
        None => Ok((scenarios::load(name_or_path)?, Spec::default())),
        Some((origin, text)) => {
            let origin = Path::new(&origin);
            let (stripped, spec) =
                split_scenario(&text).map_err(|message| SystemError::Syntax {
                    path: origin.to_owned(),
                    message,
                })?;
            Ok((toml_format::parse(&stripped, origin)?, spec))
        }
    }
}

/// Reads a TOML scenario file, its `[verdict]` table set aside.
pub fn read_toml(path: &Path) -> Result<SystemDescription, SystemError> {
    let text = std::fs::read_to_string(path).map_err(|source| SystemError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse_toml(&text, path)
}

/// The `[[requirement]]` entries of a scenario (none for an SSP file or an FMU).
pub fn requirements(
    name_or_path: &str,
) -> Result<Vec<cosim::requirements::Requirement>, SystemError> {
    match toml_text(name_or_path)? {
        None => Ok(Vec::new()),
        Some((origin, text)) => {
            cosim::requirements::from_toml(&text).map_err(|message| SystemError::Syntax {
                path: origin.into(),
                message,
            })
        }
    }
}
