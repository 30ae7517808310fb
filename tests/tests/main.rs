//! The system tests, one binary (each test binary is linked on its own): the C ABI against the
//! official headers, the `fmi` crate's importers, fmpy, the packaged FMUs' exports and metadata,
//! the platforms' binaries (ignored by default: `cargo xtask test` runs them in its platforms
//! stage), and what the documents and the workspace's layout promise.
mod abi_conformance;
mod all_platforms;
mod clippy_config;
mod cross;
mod doc_references;
#[allow(dead_code)] // each test module uses its own part
mod exports;
mod fmi3_importer;
mod fmi_crate_importer;
mod fmpy;
mod fmu_metadata;
mod module_layers;
mod readme_fmus;
mod release_directory;
mod same_bits;
mod windows_users;
