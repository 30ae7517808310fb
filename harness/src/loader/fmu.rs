//! A loaded FMU: its files, model description and resolved binary, shared by its instances.
#![allow(unsafe_code)]

use super::archive::{Unpacked, PLATFORM};
use super::error::{CallError, LoadError, VariableError};
use super::functions::Fmi2Functions;
use super::instance::Instance;
use super::variables::{VariableIndex, VariableInfo};
use libloading::Library;
use model_description::ModelDescription;
use model_description::VariableKind;
use std::ffi::{c_char, CStr};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// An FMI 2.0 Co-Simulation FMU, loaded and checked. Cheap to clone; every [`Instance`] keeps
/// the library loaded (and the unpacked files present) for as long as it lives.
#[derive(Clone)]
pub struct Fmu {
    shared: Arc<FmuShared>,
}

pub(crate) struct FmuShared {
    pub(crate) functions: Fmi2Functions,
    pub(crate) description: ModelDescription,
    pub(crate) variables: VariableIndex,
    pub(crate) resource_uri: String,
    binary_path: PathBuf,
    // Declared last and in this order: fields drop in declaration order, so the library is
    // unloaded before the temporary directory holding its file is deleted.
    _library: Library,
    unpacked: Unpacked,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu")
            .field("model_name", &self.shared.description.model_name)
            .field("binary", &self.shared.binary_path)
            .finish_non_exhaustive()
    }
}

impl Fmu {
    /// Loads a `.fmu` archive (unpacked into a temporary directory) or an unpacked FMU directory.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let unpacked = Unpacked::open(path)?;
        let description_path = unpacked.model_description_path();
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
        let model_identifier = description
            .co_simulation
            .as_ref()
            .map(|co_simulation| co_simulation.model_identifier.clone())
            .ok_or_else(|| LoadError::NotCoSimulation {
                model_name: description.model_name.clone(),
            })?;
        let variables = VariableIndex::new(&description)?;

        let binary_path = unpacked.binary_path(&model_identifier);
        if !binary_path.is_file() {
            let (platform, extension) = PLATFORM;
            return Err(LoadError::MissingBinary {
                path: binary_path,
                platform,
                extension,
            });
        }
        // SAFETY: loading runs the binary's initialisers; trusting the FMU's code is inherent
        // to co-simulation with it.
        let library =
            unsafe { Library::new(&binary_path) }.map_err(|source| LoadError::Library {
                path: binary_path.clone(),
                source,
            })?;
        let functions = Fmi2Functions::resolve(&library, &binary_path)?;
        check_binary(&functions, &binary_path)?;

        Ok(Self {
            shared: Arc::new(FmuShared {
                functions,
                description,
                variables,
                resource_uri: unpacked.resource_uri(),
                binary_path,
                _library: library,
                unpacked,
            }),
        })
    }

    pub fn model_description(&self) -> &ModelDescription {
        &self.shared.description
    }

    pub fn model_name(&self) -> &str {
        &self.shared.description.model_name
    }

    /// The directory holding the unpacked FMU (a temporary one for a `.fmu`).
    pub fn unpacked_dir(&self) -> &Path {
        self.shared.unpacked.root()
    }

    pub fn binary_path(&self) -> &Path {
        &self.shared.binary_path
    }

    pub fn variable(&self, name: &str) -> Result<&VariableInfo, VariableError> {
        self.shared.variables.get(name)
    }

    /// The value reference of `name`, checked to be exchanged through the `kind` functions
    /// (an Enumeration is exchanged as Integer).
    pub fn value_reference(&self, name: &str, kind: VariableKind) -> Result<u32, VariableError> {
        self.shared.variables.value_reference(name, kind)
    }

    /// Instantiates a Co-Simulation slave (not visible, no interactive tool) named `name`.
    /// With `logging_on` the FMU sends its debug messages; errors are logged either way.
    pub fn instantiate(&self, name: &str, logging_on: bool) -> Result<Instance, CallError> {
        Instance::new(Arc::clone(&self.shared), name, logging_on)
    }
}

/// A binary built for another FMI version or a non-default platform would misread our
/// arguments, so both are checked before any instance is made.
fn check_binary(functions: &Fmi2Functions, binary: &Path) -> Result<(), LoadError> {
    // SAFETY: both functions take no arguments and return a static C string (FMI 2.0 §2.1.4).
    let (version, platform) =
        unsafe { ((functions.get_version)(), (functions.get_types_platform)()) };
    for (function, found, expected) in [
        ("fmi2GetVersion", version, "2.0"),
        ("fmi2GetTypesPlatform", platform, "default"),
    ] {
        let found = static_text(found);
        if found != expected {
            return Err(LoadError::BinaryMismatch {
                binary: binary.to_path_buf(),
                function,
                found,
                expected,
            });
        }
    }
    Ok(())
}

fn static_text(pointer: *const c_char) -> String {
    if pointer.is_null() {
        return "(null)".to_owned();
    }
    // SAFETY: non-null, and the standard requires a NUL-terminated string.
    unsafe { CStr::from_ptr(pointer) }
        .to_string_lossy()
        .into_owned()
}
