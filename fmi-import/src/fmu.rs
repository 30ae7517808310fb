//! A loaded FMU: its files, model description and resolved binary, shared by its instances.
#![allow(unsafe_code)]

use super::archive::{Unpacked, PLATFORM};
use super::describe::{parse, Described};
use super::error::{CallError, LoadError, VariableError};
use super::instance::{Instance, InstanceOptions};
use super::variables::{VariableIndex, VariableInfo};
use crate::binary::Fmi2Functions;
use crate::binary::Fmi3Functions;
use crate::fmi3;
use crate::loaded::{Api, Files, Fmi3Api, FmuShared};
use crate::version::FmiVersion;
use libloading::Library;
use model_description::ModelDescription;
use model_description::VariableKind;
use std::ffi::{c_char, CStr};
use std::path::Path;
use std::sync::Arc;

/// An FMI 2.0 or 3.0 Co-Simulation FMU, loaded and checked. Cheap to clone; every [`Instance`] keeps
/// the library loaded (and the unpacked files present) for as long as it lives.
#[derive(Clone)]
pub struct Fmu {
    shared: Arc<FmuShared>,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu")
            .field("model_name", &self.shared.description.model_name)
            .field("binary", &self.shared.files.binary_path)
            .finish_non_exhaustive()
    }
}

impl Fmu {
    /// Loads a `.fmu` archive (unpacked into a temporary directory) or an unpacked FMU directory.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let unpacked = Unpacked::open(path)?;
        let description = match parse(&unpacked)? {
            Described::Fmi2(description) => description,
            Described::Fmi3(description3, view) => {
                return Self::load_fmi3(unpacked, *description3, view)
            }
        };
        // One binary: Co-Simulation's, else Model Exchange's. Model Exchange is offered from
        // the same binary only (an FMU with two identifiers ships two libraries).
        let co_simulation = description
            .co_simulation
            .as_ref()
            .map(|cs| cs.model_identifier.clone());
        let model_exchange = description
            .model_exchange
            .as_ref()
            .map(|me| me.model_identifier.clone());
        let model_identifier = co_simulation
            .clone()
            .or_else(|| model_exchange.clone())
            .ok_or_else(|| LoadError::NotCoSimulation {
                model_name: description.model_name.clone(),
            })?;
        let variables = VariableIndex::new(&description, &[])?;

        let binary_path = unpacked.binary_path(&model_identifier);
        let library = open_library(&binary_path, PLATFORM)?;
        let functions = Fmi2Functions::resolve(
            &library,
            &binary_path,
            co_simulation.is_some(),
            model_exchange.as_deref() == Some(model_identifier.as_str()),
        )?;
        check_binary(&functions, &binary_path)?;

        Ok(Self {
            shared: Arc::new(FmuShared {
                api: Api::Fmi2(functions),
                description,
                variables,
                files: Arc::new(Files {
                    resource_uri: unpacked.resource_uri(),
                    binary_path,
                    _library: library,
                    unpacked,
                }),
            }),
        })
    }

    fn load_fmi3(
        unpacked: Unpacked,
        description3: model_description::fmi3::Fmi3ModelDescription,
        view: fmi3::View,
    ) -> Result<Self, LoadError> {
        // As for FMI 2.0: Co-Simulation's binary, else Model Exchange's, which is offered
        // from the same binary only.
        let co_simulation = description3
            .co_simulation
            .as_ref()
            .map(|co_simulation| co_simulation.model_identifier.clone());
        let model_exchange = description3.model_exchange.clone();
        let model_identifier = co_simulation
            .clone()
            .or_else(|| model_exchange.clone())
            .unwrap_or_default();
        let variables = VariableIndex::new(&view.description, &view.types)?;
        let (platform, extension) = fmi3::PLATFORM;
        let binary_path = unpacked
            .root()
            .join("binaries")
            .join(platform)
            .join(format!("{model_identifier}.{extension}"));
        let library = open_library(&binary_path, fmi3::PLATFORM)?;
        let functions = Fmi3Functions::resolve(
            &library,
            &binary_path,
            co_simulation.is_some(),
            model_exchange.as_deref() == Some(model_identifier.as_str()),
        )?;
        // SAFETY: no arguments, returns a static C string (FMI 3.0, fmi3GetVersion).
        let version = static_text(unsafe { (functions.get_version)() });
        if !version.starts_with("3.") {
            return Err(LoadError::BinaryMismatch {
                binary: binary_path,
                function: "fmi3GetVersion",
                found: version,
                expected: "3.0",
            });
        }
        Ok(Self {
            shared: Arc::new(FmuShared {
                api: Api::Fmi3(Arc::new(Fmi3Api {
                    functions,
                    elements: view.elements,
                    starts: view.starts,
                    configured: view.configured,
                    description: description3,
                })),
                description: view.description,
                variables,
                files: Arc::new(Files {
                    resource_uri: unpacked.resource_uri(),
                    binary_path,
                    _library: library,
                    unpacked,
                }),
            }),
        })
    }

    pub fn fmi_version(&self) -> FmiVersion {
        match self.shared.api {
            Api::Fmi2(_) => FmiVersion::Fmi2,
            Api::Fmi3(_) => FmiVersion::Fmi3,
        }
    }

    /// The FMI 3.0 model description as the file has it (arrays whole); `None` for FMI 2.0.
    pub fn fmi3_description(&self) -> Option<&model_description::fmi3::Fmi3ModelDescription> {
        match &self.shared.api {
            Api::Fmi3(api) => Some(&api.description),
            Api::Fmi2(_) => None,
        }
    }

    /// FMI 3.0 `hasEventMode`: whether an instance can give same-instant feedthrough
    /// ([`InstanceOptions::same_instant_feedthrough`]); always true for FMI 2.0, where a get
    /// may follow a set at any communication point.
    pub fn supports_same_instant_feedthrough(&self) -> bool {
        match &self.shared.api {
            Api::Fmi2(_) => true,
            Api::Fmi3(api) => api
                .description
                .co_simulation
                .as_ref()
                .is_some_and(|cs| cs.has_event_mode),
        }
    }

    pub fn model_description(&self) -> &ModelDescription {
        &self.shared.description
    }

    pub fn model_name(&self) -> &str {
        &self.shared.description.model_name
    }

    /// The directory holding the unpacked FMU (a temporary one for a `.fmu`).
    pub fn unpacked_dir(&self) -> &Path {
        self.shared.files.unpacked.root()
    }

    /// The FMU's terminals (`terminalsAndIcons/terminalsAndIcons.xml`, FMI 3.0 §2.4.9; an
    /// FMI 2.0 FMU may ship the file too), none when it has no such file. The error names
    /// the file and what is wrong in it.
    pub fn terminals(&self) -> Result<Vec<model_description::terminals::Terminal>, String> {
        let path = self
            .unpacked_dir()
            .join("terminalsAndIcons")
            .join("terminalsAndIcons.xml");
        match std::fs::read(&path) {
            Ok(bytes) => model_description::terminals::read_terminals(&bytes)
                .map_err(|e| format!("{} of model '{}': {e}", path.display(), self.model_name())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
            Err(e) => Err(format!("cannot read {}: {e}", path.display())),
        }
    }

    pub fn binary_path(&self) -> &Path {
        &self.shared.files.binary_path
    }

    /// The FMU for other values of its structural parameters (FMI 3.0), by name, as text
    /// (`"3"`): its scalar view built for them over the same binary, whose instances set them
    /// in Configuration Mode after instantiation, so that arrays sized by them have the
    /// extents set (see `fmi3/view.rs`). Refused for a name that is not a structural
    /// parameter, a value its type cannot hold, and an FMI 2.0 FMU.
    pub fn configured(&self, values: &[(String, String)]) -> Result<Fmu, LoadError> {
        let Api::Fmi3(api) = &self.shared.api else {
            return Err(LoadError::UnsupportedFmi3 {
                model_name: self.model_name().to_owned(),
                reason: "an FMI 2.0 FMU has no structural parameters".to_owned(),
            });
        };
        let view = fmi3::scalar_view(&api.description, values)?;
        let variables = VariableIndex::new(&view.description, &view.types)?;
        Ok(Self {
            shared: Arc::new(FmuShared {
                api: Api::Fmi3(Arc::new(Fmi3Api {
                    functions: api.functions,
                    elements: view.elements,
                    starts: view.starts,
                    configured: view.configured,
                    description: api.description.clone(),
                })),
                description: view.description,
                variables,
                files: Arc::clone(&self.shared.files),
            }),
        })
    }

    /// The names of the FMI 3.0 structural parameters (none for FMI 2.0).
    pub fn structural_parameters(&self) -> Vec<&str> {
        match &self.shared.api {
            Api::Fmi3(api) => api
                .description
                .variables
                .iter()
                .filter(|v| v.structural)
                .map(|v| v.name.as_str())
                .collect(),
            Api::Fmi2(_) => Vec::new(),
        }
    }

    pub fn variable(&self, name: &str) -> Result<&VariableInfo, VariableError> {
        self.shared.variables.get(name)
    }

    /// The value reference of `name` (for FMI 3.0 the element reference of the scalar view),
    /// checked to be exchanged through the `kind` functions
    /// (an Enumeration is exchanged as Integer).
    pub fn value_reference(&self, name: &str, kind: VariableKind) -> Result<u32, VariableError> {
        self.shared.variables.value_reference(name, kind)
    }

    /// Instantiates a Co-Simulation slave (not visible, no interactive tool) named `name`.
    /// With `logging_on` the FMU sends its debug messages; errors are logged either way.
    pub fn instantiate(&self, name: &str, logging_on: bool) -> Result<Instance, CallError> {
        self.instantiate_with(
            name,
            InstanceOptions {
                logging_on,
                ..Default::default()
            },
        )
    }

    /// [`Fmu::instantiate`] with the master's choices (see [`InstanceOptions`]).
    pub fn instantiate_with(
        &self,
        name: &str,
        options: InstanceOptions,
    ) -> Result<Instance, CallError> {
        Instance::new(Arc::clone(&self.shared), name, options)
    }
}

fn open_library(
    binary_path: &Path,
    platform: (&'static str, &'static str),
) -> Result<Library, LoadError> {
    if !binary_path.is_file() {
        let (platform, extension) = platform;
        return Err(LoadError::MissingBinary {
            path: binary_path.to_path_buf(),
            platform,
            extension,
        });
    }
    // SAFETY: loading runs the binary's initialisers; trusting the FMU's code is inherent
    // to co-simulation with it.
    unsafe { Library::new(binary_path) }.map_err(|source| LoadError::Library {
        path: binary_path.to_path_buf(),
        source,
    })
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
