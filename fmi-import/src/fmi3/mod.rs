//! FMI 3.0 Co-Simulation: the model description's scalar view, the entry points, and the
//! instance backend of [`super::Instance`].

mod instance;
mod view;

use crate::binary::Fmi3Functions;
pub(crate) use instance::Fmi3Instance;
pub(crate) use view::{scalar_view, Element, Starts, View};

/// What an FMI 3.0 FMU shares with its instances besides the library.
#[derive(Debug)]
pub(crate) struct Fmi3Api {
    pub(crate) functions: Fmi3Functions,
    /// Per element reference of the scalar view (the harness's value reference for it).
    pub(crate) elements: Vec<Element>,
    pub(crate) starts: Starts,
    pub(crate) description: model_description::fmi3::Fmi3ModelDescription,
}

/// The FMI 3.0 platform folder of this host (`binaries/<platform>/`) and the library suffix.
#[cfg(all(target_arch = "x86_64", target_os = "linux"))]
pub(crate) const PLATFORM: (&str, &str) = ("x86_64-linux", "so");
#[cfg(all(target_arch = "aarch64", target_os = "linux"))]
pub(crate) const PLATFORM: (&str, &str) = ("aarch64-linux", "so");
#[cfg(all(target_arch = "x86_64", target_os = "macos"))]
pub(crate) const PLATFORM: (&str, &str) = ("x86_64-darwin", "dylib");
#[cfg(all(target_arch = "aarch64", target_os = "macos"))]
pub(crate) const PLATFORM: (&str, &str) = ("aarch64-darwin", "dylib");
#[cfg(all(target_arch = "x86_64", target_os = "windows"))]
pub(crate) const PLATFORM: (&str, &str) = ("x86_64-windows", "dll");
