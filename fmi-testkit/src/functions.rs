//! The FMI 2.0 Co-Simulation entry points of one FMU: the importer's common and
//! Co-Simulation tables (`fmi-import`, listed once there), the common ones reached directly.
use fmi_import::tables::fmi2::{Fmi2CoSimulation, Fmi2Common};

/// Every FMI 2.0 Co-Simulation function: `functions.get_real`, `functions.co_simulation.do_step`.
#[derive(Debug, Clone, Copy)]
pub struct Fmi2Functions {
    pub common: Fmi2Common,
    pub co_simulation: Fmi2CoSimulation,
}

impl std::ops::Deref for Fmi2Functions {
    type Target = Fmi2Common;
    fn deref(&self) -> &Fmi2Common {
        &self.common
    }
}

/// The [`Fmi2Functions`] of an FMU crate linked into the test (its `export_fmi2!` symbols),
/// e.g. `static FMU: Fmi2Functions = fmi2_functions!(fmu_gnc);`.
#[macro_export]
macro_rules! fmi2_functions {
    ($fmu:path) => {
        $crate::Fmi2Functions {
            common: $crate::fmi_import::fmi2_common!($fmu),
            co_simulation: $crate::fmi_import::fmi2_co_simulation!($fmu),
        }
    };
}

impl Fmi2Functions {
    /// The entry points of a loaded shared library (an FMU's binary). The library must stay
    /// loaded while the table is used.
    ///
    /// # Safety
    /// The library's `fmi2*` symbols must have the standard's signatures.
    pub unsafe fn load(library: &libloading::Library) -> Result<Fmi2Functions, libloading::Error> {
        // SAFETY: forwarded from the caller.
        unsafe {
            Ok(Fmi2Functions {
                common: Fmi2Common::load(library).map_err(|e| e.source)?,
                co_simulation: Fmi2CoSimulation::load(library).map_err(|e| e.source)?,
            })
        }
    }
}
