//! Compiles the variadic logger shim (see `csrc/logger.c` for why it is C).
fn main() {
    println!("cargo:rerun-if-changed=csrc/logger.c");
    cc::Build::new()
        .file("csrc/logger.c")
        .std("c99")
        .warnings(true)
        .extra_warnings(true)
        .warnings_into_errors(true)
        .compile("robustness_fmi2_logger");
}
