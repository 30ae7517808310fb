//! The resolved entry points of one FMU binary: the common table of its version and the
//! table of the interface the importer drives, each from the one listing in `tables`.
#![allow(unsafe_code)]

use crate::error::LoadError;
use crate::tables::{fmi2, fmi3, MissingSymbol};
use libloading::Library;
use std::path::Path;

/// FMI 2.0: the common functions, reached directly, and those of each interface the model
/// description declares (an FMU need not export the functions of an interface it lacks).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fmi2Functions {
    pub(crate) common: fmi2::Fmi2Common,
    pub(crate) co_simulation: Option<fmi2::Fmi2CoSimulation>,
    pub(crate) model_exchange: Option<fmi2::Fmi2ModelExchange>,
}

impl std::ops::Deref for Fmi2Functions {
    type Target = fmi2::Fmi2Common;
    fn deref(&self) -> &fmi2::Fmi2Common {
        &self.common
    }
}

impl Fmi2Functions {
    pub(crate) fn resolve(
        library: &Library,
        path: &Path,
        co_simulation: bool,
        model_exchange: bool,
    ) -> Result<Self, LoadError> {
        // SAFETY: the tables are typed after the standard's headers; a binary exporting these
        // names with other signatures violates the standard and cannot be detected. The
        // tables live beside the library in the shared `Fmu` state, which outlives them.
        unsafe {
            Ok(Self {
                common: fmi2::Fmi2Common::load(library).map_err(|e| missing(e, path))?,
                co_simulation: declared(
                    co_simulation,
                    || fmi2::Fmi2CoSimulation::load(library),
                    path,
                )?,
                model_exchange: declared(
                    model_exchange,
                    || fmi2::Fmi2ModelExchange::load(library),
                    path,
                )?,
            })
        }
    }
}

/// FMI 3.0: the common functions, reached directly, and those of each interface the model
/// description declares.
#[derive(Clone, Copy)]
pub(crate) struct Fmi3Functions {
    pub(crate) common: fmi3::Fmi3Common,
    pub(crate) co_simulation: Option<fmi3::Fmi3CoSimulation>,
    pub(crate) model_exchange: Option<fmi3::Fmi3ModelExchange>,
}

impl std::fmt::Debug for Fmi3Functions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Fmi3Functions")
    }
}

impl std::ops::Deref for Fmi3Functions {
    type Target = fmi3::Fmi3Common;
    fn deref(&self) -> &fmi3::Fmi3Common {
        &self.common
    }
}

impl Fmi3Functions {
    pub(crate) fn resolve(
        library: &Library,
        path: &Path,
        co_simulation: bool,
        model_exchange: bool,
    ) -> Result<Self, LoadError> {
        // SAFETY: as for FMI 2.0 above.
        unsafe {
            Ok(Self {
                common: fmi3::Fmi3Common::load(library).map_err(|e| missing(e, path))?,
                co_simulation: declared(
                    co_simulation,
                    || fmi3::Fmi3CoSimulation::load(library),
                    path,
                )?,
                model_exchange: declared(
                    model_exchange,
                    || fmi3::Fmi3ModelExchange::load(library),
                    path,
                )?,
            })
        }
    }
}

/// The table of an interface, resolved only when the description declares the interface.
fn declared<T>(
    wanted: bool,
    load: impl FnOnce() -> Result<T, MissingSymbol>,
    path: &Path,
) -> Result<Option<T>, LoadError> {
    wanted.then(load).transpose().map_err(|e| missing(e, path))
}

fn missing(e: MissingSymbol, path: &Path) -> LoadError {
    LoadError::MissingSymbol {
        symbol: e.symbol,
        binary: path.to_path_buf(),
        source: e.source,
    }
}
