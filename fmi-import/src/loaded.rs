//! What a loaded FMU shares with its instances: the resolved functions of its version, its
//! description and variables, the library and its unpacked files. Below both the FMU and
//! the instance backends, so that each reaches it without reaching the other.

use crate::archive::Unpacked;
use crate::binary::{Fmi2Functions, Fmi3Functions};
use crate::fmi3::view::{Element, Starts};
use crate::variables::VariableIndex;
use libloading::Library;
use model_description::ModelDescription;
use std::path::PathBuf;
use std::sync::Arc;

/// The functions of one version, resolved from the binary.
// One per loaded FMU, behind its `Arc`: the FMI 2.0 table inline costs nothing worth a box.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Api {
    Fmi2(Fmi2Functions),
    Fmi3(Arc<Fmi3Api>),
}

/// What an FMI 3.0 FMU shares with its instances besides the library.
#[derive(Debug)]
pub(crate) struct Fmi3Api {
    pub(crate) functions: Fmi3Functions,
    /// Per element reference of the scalar view (the harness's value reference for it).
    pub(crate) elements: Vec<Element>,
    pub(crate) starts: Starts,
    /// Element references of the structural parameters an instance sets in Configuration
    /// Mode (`fmi3/view.rs`); empty when the view is that of their start values.
    pub(crate) configured: Vec<u32>,
    pub(crate) description: model_description::fmi3::Fmi3ModelDescription,
}

pub(crate) struct FmuShared {
    pub(crate) api: Api,
    /// FMI 2.0: the file's description; FMI 3.0: its scalar view (`fmi3/view.rs`).
    pub(crate) description: ModelDescription,
    pub(crate) variables: VariableIndex,
    /// Shared by the views of one binary (`Fmu::configured`).
    pub(crate) files: Arc<Files>,
}

/// The binary and the unpacked files of a loaded FMU.
pub(crate) struct Files {
    pub(crate) resource_uri: String,
    pub(crate) binary_path: PathBuf,
    // Declared last and in this order: fields drop in declaration order, so the library is
    // unloaded before the temporary directory holding its file is deleted.
    pub(crate) _library: Library,
    pub(crate) unpacked: Unpacked,
}

impl Files {
    /// The unpacked `resources` folder, if the FMU has one.
    pub(crate) fn resources_dir(&self) -> Option<PathBuf> {
        Some(self.unpacked.root().join("resources")).filter(|dir| dir.is_dir())
    }
}
