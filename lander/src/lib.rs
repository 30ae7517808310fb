//! The lunar-lander mission flown over the co-simulation master (`cosim`): the shipped
//! scenarios and how a scenario argument is read, what a run is expected to do and its
//! verdict, the metrics of a flight, the laws compared on one scenario (`paper`) and on a
//! divert (`retarget`), and `--set` overrides. No figures, pages or command line: those are
//! the `report` and `harness` crates', above this one.
//!
//! Modules from the bottom up: `laws`, `verdict`, `retarget::command`, `scenarios`, `metrics`,
//! `provenance`, `overrides`; then `paper`, and `retarget`'s comparison on top of it;
//! `linearize` and `handover` (a recorded flight's hover-to-descent handover) beside them.
#![forbid(unsafe_code)]
// std's transcendental functions compute the flight metrics and the attitude geometry of a
// scenario here, outside any FMU (the workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]

pub mod handover;
pub mod laws;
pub mod linearize;
pub mod metrics;
pub mod overrides;
pub mod paper;
pub mod provenance;
pub mod retarget;
pub mod scenarios;
pub mod verdict;
