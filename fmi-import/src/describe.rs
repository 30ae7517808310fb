//! An FMU's model description, read and checked the one way both a load and a plan use: what
//! a master needs to plan a run it will make in another process (names, units, start
//! values) while no FMU code runs in its own.
use super::archive::Unpacked;
use super::error::LoadError;
use super::fmi3::{self, View};
use super::version::FmiVersion;
use model_description::fmi3::Fmi3ModelDescription;
use model_description::ModelDescription;
use std::path::{Path, PathBuf};

/// A model description as read, by FMI version.
// One per load, moved once: its size costs nothing worth a box.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Described {
    Fmi2(ModelDescription),
    /// The file as read, and its scalar view (`r_nue` as `r_nue[1..3]`).
    Fmi3(Box<Fmi3ModelDescription>, View),
}

/// Where a description's errors say it is: inside its archive, not in a temporary directory
/// that is gone by the time the user reads the message.
pub(crate) fn described_path(unpacked: &Unpacked) -> PathBuf {
    match unpacked.archive() {
        Some(archive) => archive.join("modelDescription.xml"),
        None => unpacked.model_description_path(),
    }
}

/// Reads the unpacked FMU's description (FMI 2.0 or 3.0, by its `fmiVersion`).
pub(crate) fn parse(unpacked: &Unpacked) -> Result<Described, LoadError> {
    let description_path = unpacked.model_description_path();
    let bytes = std::fs::read(&description_path).map_err(|source| LoadError::Io {
        path: description_path.clone(),
        source,
    })?;
    let version = model_description::fmi3::fmi_version_of(&bytes);
    if version
        .as_deref()
        .is_some_and(|v| v.trim().starts_with("3."))
    {
        let description3 = Fmi3ModelDescription::from_bytes(&bytes).map_err(|source| {
            LoadError::ModelDescription {
                path: described_path(unpacked),
                source,
            }
        })?;
        let view = fmi3::scalar_view(&description3, &[])?;
        return Ok(Described::Fmi3(Box::new(description3), view));
    }
    let description = ModelDescription::from_file(&description_path).map_err(|source| {
        LoadError::ModelDescription {
            path: described_path(unpacked),
            source,
        }
    })?;
    if description.fmi_version.trim() != "2.0" {
        return Err(LoadError::UnsupportedFmiVersion {
            found: description.fmi_version.clone(),
        });
    }
    Ok(Described::Fmi2(description))
}

/// The model description of a `.fmu` archive or unpacked FMU directory, as [`crate::Fmu`]
/// sees it once loaded (for FMI 3.0 its scalar view), without loading its binary; the archive
/// is unpacked and checked whole, as a load checks it.
pub fn read_description(
    path: impl AsRef<Path>,
) -> Result<(FmiVersion, ModelDescription), LoadError> {
    described(Unpacked::open(path.as_ref())?)
}

/// A variable as its file declares it, beside the description's FMI 2.0-like view of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Declared {
    /// `UInt64`, `Binary` for FMI 3.0; `Real`, `Integer` for FMI 2.0.
    pub type_name: String,
    /// The start value as the file writes it (FMI 3.0; `None` for FMI 2.0, whose
    /// description holds it exactly).
    pub start: Option<String>,
}

/// [`read_description`] with each variable of the description as its file declares it, in
/// order.
pub fn read_description_typed(
    path: impl AsRef<Path>,
) -> Result<(FmiVersion, ModelDescription, Vec<Declared>), LoadError> {
    Ok(match parse(&Unpacked::open(path.as_ref())?)? {
        Described::Fmi2(description) => {
            let declared = description
                .model_variables
                .variables
                .iter()
                .map(|v| Declared {
                    type_name: v
                        .kind()
                        .map_or_else(|| "?".to_owned(), |k| format!("{k:?}")),
                    start: None,
                })
                .collect();
            (FmiVersion::Fmi2, description, declared)
        }
        Described::Fmi3(_, view) => {
            let declared = view
                .types
                .iter()
                .zip(view.start_texts)
                .map(|(kind, start)| Declared {
                    type_name: kind.name().to_owned(),
                    start,
                })
                .collect();
            (FmiVersion::Fmi3, view.description, declared)
        }
    })
}

/// [`read_description`] writing only the description: the archive's directory is checked
/// (names, links, duplicates, declared sizes) but no other entry is inflated. For a master
/// whose worker process loads (and checks whole) the same FMU.
pub fn peek_description(
    path: impl AsRef<Path>,
) -> Result<(FmiVersion, ModelDescription), LoadError> {
    described(Unpacked::open_description(path.as_ref())?)
}

fn described(unpacked: Unpacked) -> Result<(FmiVersion, ModelDescription), LoadError> {
    Ok(match parse(&unpacked)? {
        Described::Fmi2(description) => (FmiVersion::Fmi2, description),
        Described::Fmi3(_, view) => (FmiVersion::Fmi3, view.description),
    })
}
