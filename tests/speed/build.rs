//! The benchmark links LanderGnc's and LanderPlant's models together (the plain-Rust loop of
//! the same math). Each FMU crate defines the FMI C functions (`fmi2GetReal`, ...) in its
//! library, and whether the linker pulls both definitions depends on how the compiler split
//! the crates into object files (it does without incremental compilation and in release
//! builds). The benchmark calls the FMUs' C functions only through the packaged binaries it
//! loads, never these, so its programs keep the first definition.
fn main() {
    let target_os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if matches!(
        target_os.as_str(),
        "linux" | "android" | "freebsd" | "netbsd" | "openbsd"
    ) {
        println!("cargo:rustc-link-arg=-Wl,--allow-multiple-definition");
    }
}
