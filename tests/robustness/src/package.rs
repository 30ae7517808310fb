//! The packaged FMUs as shipped (`target/fmu/*.fmu`, written by `cargo xtask fmus`):
//! unpacked into a temporary folder, with their model description and shared library.
use model_description::{Causality, ModelDescription, VariableKind};
use std::path::{Path, PathBuf};

/// The FMUs under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Lander {
    Gnc,
    Plant,
    /// The navigation-error unit between the plant and the GNC.
    Nav,
    /// IMU, laser altimeter and Doppler velocimeter measuring the plant's true state.
    Sensors,
    /// The error-state Kalman filter fusing the sensors' measurements.
    Filter,
}

impl Lander {
    pub const ALL: [Lander; 5] = [
        Lander::Gnc,
        Lander::Plant,
        Lander::Nav,
        Lander::Sensors,
        Lander::Filter,
    ];

    pub fn model_identifier(self) -> &'static str {
        match self {
            Lander::Gnc => "LanderGnc",
            Lander::Plant => "LanderPlant",
            Lander::Nav => "LanderNav",
            Lander::Sensors => "LanderSensors",
            Lander::Filter => "LanderFilter",
        }
    }

    pub fn parse(name: &str) -> Option<Lander> {
        Lander::ALL
            .into_iter()
            .find(|l| l.model_identifier().eq_ignore_ascii_case(name))
    }
}

#[derive(Debug, thiserror::Error)]
pub enum PackageError {
    #[error("{path} is missing: run `cargo xtask fmus` first")]
    Missing { path: PathBuf },
    #[error("cannot unpack {path}: {reason}")]
    Unpack { path: PathBuf, reason: String },
    #[error("modelDescription.xml of {path}: {reason}")]
    Description { path: PathBuf, reason: String },
}

/// One declared variable, as the fuzzer and the tests need it.
#[derive(Debug, Clone)]
pub struct VariableInfo {
    pub name: String,
    pub value_reference: u32,
    /// The kind whose get/set functions access it (enumerations are Integers).
    pub kind: VariableKind,
    pub causality: Causality,
}

/// An FMU unzipped into a temporary folder (removed on drop).
#[derive(Debug)]
pub struct Unpacked {
    _files: fmi_testkit::unpack::Unpacked,
    pub lander: Lander,
    pub library: PathBuf,
    pub guid: String,
    pub description: ModelDescription,
    pub variables: Vec<VariableInfo>,
}

impl Unpacked {
    pub fn open(lander: Lander) -> Result<Unpacked, PackageError> {
        let path = fmu_dir().join(format!("{}.fmu", lander.model_identifier()));
        if !path.is_file() {
            return Err(PackageError::Missing { path });
        }
        let files =
            fmi_testkit::unpack::Unpacked::open(&path).map_err(|e| PackageError::Unpack {
                path: path.clone(),
                reason: e.to_string(),
            })?;
        let description =
            ModelDescription::from_file(files.model_description_path()).map_err(|e| {
                PackageError::Description {
                    path: path.clone(),
                    reason: e.to_string(),
                }
            })?;
        let variables = description
            .variables()
            .filter_map(|v| {
                Some(VariableInfo {
                    name: v.name.clone(),
                    value_reference: v.value_reference,
                    kind: v.kind()?.accessed_as(),
                    causality: v.causality_or_default(),
                })
            })
            .collect();
        let library = files.binary_path(lander.model_identifier());
        Ok(Unpacked {
            guid: description.guid.clone(),
            _files: files,
            lander,
            library,
            description,
            variables,
        })
    }

    /// The value reference of the variable `name`; panics if the FMU does not declare it
    /// (the names are the public contract, so a missing one is a test failure).
    pub fn vr(&self, name: &str) -> u32 {
        self.variables
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("{} declares no {name}", self.lander.model_identifier()))
            .value_reference
    }

    pub fn of_kind(&self, kind: VariableKind) -> impl Iterator<Item = &VariableInfo> {
        self.variables.iter().filter(move |v| v.kind == kind)
    }
}

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("tests/robustness lives two levels below the workspace root")
        .to_path_buf()
}

/// `target/fmu`, resolved as xtask resolves it (CARGO_TARGET_DIR or `target`).
pub fn fmu_dir() -> PathBuf {
    let target = match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if Path::new(&dir).is_absolute() => PathBuf::from(dir),
        Some(dir) => workspace_root().join(dir),
        None => workspace_root().join("target"),
    };
    target.join("fmu")
}
