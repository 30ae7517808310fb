//! The FMI 2.0 Co-Simulation functions of one shared library, resolved by name with
//! `libloading` into the test kit's table of raw C function pointers.
#![allow(unsafe_code)]

use fmi_testkit::Fmi2Functions;
use std::ops::Deref;
use std::path::Path;

/// Raw function pointers of one FMU library; the library stays loaded while this lives.
pub struct Api {
    functions: Fmi2Functions,
    _library: libloading::Library,
}

/// The exported symbol names, in the order of the standard's function list.
pub const SYMBOLS: &[&str] = &fmi_testkit::fmi2::FUNCTION_NAMES;

impl Api {
    /// Loads `path` and resolves all 34 functions.
    pub fn load(path: &Path) -> Result<Api, libloading::Error> {
        // SAFETY: loading runs the library's initialisers; an FMU library has none beyond
        // what the Rust runtime sets up.
        let library = unsafe { libloading::Library::new(path) }?;
        // SAFETY: an FMU's fmi2* symbols have the standard's signatures; the pointers are
        // used only while `library` is held (it lives in the same struct).
        let functions = unsafe { Fmi2Functions::load(&library) }?;
        Ok(Api {
            functions,
            _library: library,
        })
    }
}

impl Deref for Api {
    type Target = Fmi2Functions;
    fn deref(&self) -> &Fmi2Functions {
        &self.functions
    }
}
