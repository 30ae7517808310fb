//! Shared support of the system tests (tests/tests/*.rs): where the packaged FMUs are, and
//! their unpacked contents. The tests exercise the FMUs exactly as shipped, so they read
//! `target/fmu/*.fmu` written by `cargo xtask fmus` and never build anything themselves.
//!
//! These helpers panic with a message saying what to run: they serve tests only.
#![deny(unsafe_code)]

use fmi_abi::unpack::Unpacked;
pub use fmu_metadata::{Fmi, FmuCrate};
use model_description::ModelDescription;
use std::path::{Path, PathBuf};

/// Every FMU crate of the workspace with what its `[package.metadata.fmu]` promises: the
/// list `cargo xtask fmus` packages from. The tests read the Cargo.toml files themselves
/// rather than a list xtask writes, so an FMU xtask failed to package fails the tests
/// instead of vanishing from them.
pub fn fmu_crates() -> Vec<FmuCrate> {
    fmu_metadata::workspace_fmus(&workspace_root()).unwrap_or_else(|e| panic!("{e}"))
}

/// The `modelIdentifier` of every FMU packaged in `version`, from the metadata. Every system
/// test checks all of them: one missing from `target/fmu` fails the tests instead of being
/// skipped.
pub fn shipped(version: Fmi) -> Vec<String> {
    fmu_crates()
        .into_iter()
        .filter(|f| f.ships(version))
        .map(|f| f.model_identifier)
        .collect()
}

/// The FMI 2.0 FMUs (`target/fmu/<id>.fmu`).
pub fn shipped_fmus() -> Vec<String> {
    shipped(Fmi::V2)
}

/// The FMI 3.0 FMUs (`target/fmu/fmi3/<id>.fmu`; 75 `fmi3*` functions in the library).
pub fn fmi3_fmus() -> Vec<String> {
    shipped(Fmi::V3)
}

/// The FMUs packaged in `version` that also declare Model Exchange.
pub fn model_exchange_fmus(version: Fmi) -> Vec<String> {
    fmu_crates()
        .into_iter()
        .filter(|f| f.ships_model_exchange(version))
        .map(|f| f.model_identifier)
        .collect()
}

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the system-tests crate lives one level below the workspace root")
        .to_path_buf()
}

/// The cargo target directory, resolved as xtask resolves it (CARGO_TARGET_DIR or `target`).
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if Path::new(&dir).is_absolute() => PathBuf::from(dir),
        Some(dir) => workspace_root().join(dir),
        None => workspace_root().join("target"),
    }
}

pub fn fmu_dir() -> PathBuf {
    target_dir().join("fmu")
}

/// Path of a packaged FMU; panics, naming the command that makes it, when it is missing.
/// `target/fmu/fmi3/<id>.fmu`, the FMI 3.0 FMU `cargo xtask fmus` packages.
pub fn fmi3_fmu_path(model_identifier: &str) -> PathBuf {
    let path = fmu_dir()
        .join("fmi3")
        .join(format!("{model_identifier}.fmu"));
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus` first (or `cargo xtask test`, which does)",
        path.display()
    );
    path
}

/// The host's library in an unpacked FMI 3.0 FMU: `binaries/<arch>-<system>/<id>.<ext>`.
pub fn fmi3_binary_path(root: &Path, model_identifier: &str) -> PathBuf {
    let (system, extension) = match std::env::consts::OS {
        "linux" => ("linux", "so"),
        "macos" => ("darwin", "dylib"),
        "windows" => ("windows", "dll"),
        other => panic!("no FMI 3.0 platform folder for {other}"),
    };
    root.join("binaries")
        .join(format!("{}-{system}", std::env::consts::ARCH))
        .join(format!("{model_identifier}.{extension}"))
}

pub fn fmu_path(model_identifier: &str) -> PathBuf {
    let path = fmu_dir().join(format!("{model_identifier}.fmu"));
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus` first (or `cargo xtask test`, which does)",
        path.display()
    );
    path
}

/// An FMU unzipped (by the workspace's one unpacker) into a temporary folder that is
/// removed on drop.
pub struct UnpackedFmu {
    unpacked: Unpacked,
    pub description: ModelDescription,
    pub model_identifier: String,
}

impl UnpackedFmu {
    pub fn open(model_identifier: &str) -> Self {
        let archive_path = fmu_path(model_identifier);
        let unpacked = Unpacked::open(&archive_path).unwrap_or_else(|e| panic!("{e}"));
        let description = ModelDescription::from_file(unpacked.model_description_path())
            .unwrap_or_else(|e| panic!("modelDescription.xml of {}: {e}", archive_path.display()));
        let identifier = description
            .co_simulation_identifier()
            .unwrap_or_else(|| panic!("{} has no <CoSimulation>", archive_path.display()))
            .to_owned();
        assert_eq!(
            identifier,
            model_identifier,
            "{} declares another modelIdentifier",
            archive_path.display()
        );
        Self {
            unpacked,
            description,
            model_identifier: identifier,
        }
    }

    pub fn root(&self) -> &Path {
        self.unpacked.root()
    }

    pub fn library(&self) -> PathBuf {
        self.unpacked.binary_path(&self.model_identifier)
    }

    /// `fmuResourceLocation` as a master passes it: a file URI of the `resources` folder.
    pub fn resource_uri(&self) -> String {
        self.unpacked.resource_uri()
    }
}

/// The 10 functions FMI 2.0 Model Exchange adds to the common ones.
pub const FMI2_ME_FUNCTIONS: [&str; 10] = [
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
];

/// The 34 functions of the FMI 2.0 Co-Simulation API (25 common + 9 co-simulation).
pub const FMI2_CS_FUNCTIONS: [&str; 34] = fmi_abi::fmi2::FUNCTION_NAMES;
