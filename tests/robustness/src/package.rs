//! The packaged FMUs as shipped (`target/fmu/*.fmu`, written by `cargo xtask fmus`):
//! unpacked into a temporary folder, with their model description and shared library.
use model_description::{Causality, ModelDescription, VariableKind};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// An FMU under test, by model identifier. The FMUs under test are every FMU crate of the
/// workspace that ships FMI 2.0 ([`Lander::all`], read from each crate's
/// `[package.metadata.fmu]`), so a new FMU crate is fuzzed, cycled and checked for leaks
/// without an edit here. The five lander FMUs are named below because parts of the suite
/// know more about them (their inputs in flight, their invariants); an FMU they do not
/// name runs on its start values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Lander(&'static str);

// Named like the variants they replace, so that a `match` on a known FMU reads as before.
#[allow(non_upper_case_globals)]
impl Lander {
    pub const Gnc: Lander = Lander("LanderGnc");
    pub const Plant: Lander = Lander("LanderPlant");
    /// The navigation-error unit between the plant and the GNC.
    pub const Nav: Lander = Lander("LanderNav");
    /// IMU, laser altimeter and Doppler velocimeter measuring the plant's true state.
    pub const Sensors: Lander = Lander("LanderSensors");
    /// The error-state Kalman filter fusing the sensors' measurements.
    pub const Filter: Lander = Lander("LanderFilter");

    /// Every FMU of the workspace packaged as FMI 2.0, in the order of the workspace
    /// members; panics when the metadata cannot be read (a test failure, not a skip).
    pub fn all() -> Vec<Lander> {
        // Read once: the names of FMUs not named here live as long as the process, and
        // stay reachable from this static (valgrind's leak check runs on these binaries).
        static ALL: OnceLock<Vec<Lander>> = OnceLock::new();
        ALL.get_or_init(|| {
            let fmus = fmu_metadata::fmus_around(env!("CARGO_MANIFEST_DIR"))
                .unwrap_or_else(|e| panic!("[package.metadata.fmu]: {e}"));
            let all: Vec<Lander> = fmus
                .into_iter()
                .filter(|f| f.ships(fmu_metadata::Fmi::V2))
                .map(|f| Lander::named(&f.model_identifier))
                .collect();
            assert!(!all.is_empty(), "no FMU crate ships FMI 2.0");
            all
        })
        .clone()
    }

    /// The FMU of this model identifier.
    fn named(model_identifier: &str) -> Lander {
        let known = [
            Lander::Gnc,
            Lander::Plant,
            Lander::Nav,
            Lander::Sensors,
            Lander::Filter,
        ];
        known
            .into_iter()
            .find(|l| l.0 == model_identifier)
            .unwrap_or_else(|| Lander(Box::leak(model_identifier.to_string().into_boxed_str())))
    }

    pub fn model_identifier(self) -> &'static str {
        self.0
    }

    pub fn parse(name: &str) -> Option<Lander> {
        Lander::all()
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
