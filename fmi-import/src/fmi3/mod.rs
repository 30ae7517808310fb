//! FMI 3.0 Co-Simulation: the model description's scalar view, the entry points, and the
//! instance backend of [`super::Instance`].

mod instance;
pub(crate) mod view;

pub(crate) use instance::Fmi3Instance;
pub use view::element_name;
pub(crate) use view::{scalar_view, View};

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
