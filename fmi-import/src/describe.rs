//! An FMU's model description without its binary: what a master needs to plan a run it will
//! make in another process (names, units, start values) while no FMU code runs in its own.
use super::archive::Unpacked;
use super::error::LoadError;
use super::fmi3;
use super::fmu::FmiVersion;
use model_description::ModelDescription;
use std::path::Path;

/// The model description of a `.fmu` archive or unpacked FMU directory, as [`crate::Fmu`]
/// sees it once loaded (for FMI 3.0 its scalar view), read without loading the binary.
pub fn read_description(
    path: impl AsRef<Path>,
) -> Result<(FmiVersion, ModelDescription), LoadError> {
    let unpacked = Unpacked::open(path.as_ref())?;
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
        let description3 = model_description::fmi3::Fmi3ModelDescription::from_bytes(&bytes)
            .map_err(|source| LoadError::ModelDescription {
                path: description_path.clone(),
                source,
            })?;
        return Ok((
            FmiVersion::Fmi3,
            fmi3::scalar_view(&description3)?.description,
        ));
    }
    let description = ModelDescription::from_file(&description_path).map_err(|source| {
        LoadError::ModelDescription {
            path: description_path.clone(),
            source,
        }
    })?;
    if description.fmi_version.trim() != "2.0" {
        return Err(LoadError::UnsupportedFmiVersion {
            found: description.fmi_version.clone(),
        });
    }
    Ok((FmiVersion::Fmi2, description))
}
