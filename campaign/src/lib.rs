//! Monte Carlo campaigns of the lander mission (`lander`): a scenario's descent flown over a
//! phi_cmd grid, for several control laws, from seeded dispersions of the initial state,
//! mass, inertia and thrust alignment; their manifests, statistics and summaries. No figures
//! and no printing: the `report` crate draws, the `harness` command line prints.
//!
//! - [`definition`]: the definition and the numbering of flights (run j x phi_cmd x law) and
//!   shards; [`seed`]: run seeds; [`dispersion`]: the draw of a run and how it is applied;
//!   [`estimator_start`]: a navigation filter's dispersed start.
//! - [`flight`]: one flight on a loaded simulation; [`runner`]: parallel execution, one FMU
//!   instance pair per worker, rows streamed to `manifest.csv` ([`manifest`]) with
//!   `campaign.toml` ([`config`]) beside it.
//! - [`merge`] joins shards; [`replay`] re-flies one flight bit-exactly; [`summary`] and
//!   [`summary_csv`] give the table and `summary.csv` ([`stats`]: the bounds); [`analysis`]
//!   what drives each metric and the paired law differences.
#![forbid(unsafe_code)]
// std's transcendental functions compute the dispersions, the attitude draws and the statistics
// here, outside any FMU (the workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]

pub mod analysis;
pub mod attitude;
pub mod config;
pub mod definition;
pub mod dispersion;
pub mod estimator_start;
pub mod flight;
pub mod generic;
pub mod manifest;
pub mod merge;
pub mod parallel;
pub mod replay;
pub mod runner;
pub mod seed;
pub mod stats;
pub mod summary;
pub mod summary_csv;

pub use definition::{CampaignSpec, Flight, Shard, DEFAULT_SCENARIO};
pub use dispersion::{Dispersion, DispersionRanges};
