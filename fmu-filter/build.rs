//! The filter's tests link LanderSensors' model beside its own (to draw measurements from the
//! sensor model, and to compare the shared parameters). Each FMU crate defines the FMI C
//! functions (`fmi2GetReal`, ...) in its library, and whether the linker pulls both
//! definitions depends on how the compiler split the crates into object files (it does
//! without incremental compilation, and always in a release test build). No test calls those
//! functions, so the test binaries keep the first definition.
fn main() {
    let target_os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if matches!(
        target_os.as_str(),
        "linux" | "android" | "freebsd" | "netbsd" | "openbsd"
    ) {
        println!("cargo:rustc-link-arg-tests=-Wl,--allow-multiple-definition");
    }
}
