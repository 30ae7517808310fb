//! The `harness` command line is the binary (`main.rs`); the mission, campaigns and reports
//! it drives are the `lander`, `campaign` and `report` crates. This library only passes on
//! the shipped scenarios under their old path, `harness::scenarios`, for the end-to-end
//! tests that still load them from here (`tests/import`, `tests/supervision.rs`).
#![forbid(unsafe_code)]

pub use lander::scenarios;
