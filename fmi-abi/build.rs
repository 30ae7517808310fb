//! Compiles the C side of the master's callbacks (see `csrc/callbacks.c` for why it is C),
//! only with the `callbacks` feature: an FMU, which never calls its own logger, gets none
//! of it.
fn main() {
    #[cfg(feature = "callbacks")]
    if std::env::var_os("CARGO_FEATURE_CALLBACKS").is_some() {
        println!("cargo:rerun-if-changed=csrc/callbacks.c");
        cc::Build::new()
            .file("csrc/callbacks.c")
            .std("c99")
            .warnings(true)
            .extra_warnings(true)
            .warnings_into_errors(true)
            .compile("fmi_abi_callbacks");
    }
}
