//! Monte Carlo campaigns: the paper's descent flown over a phi_cmd grid, for several control
//! laws, from seeded dispersions of the initial state, mass, inertia and thrust alignment.
//!
//! - [`campaign`]: the definition and the numbering of flights (run j x phi_cmd x law) and
//!   shards; [`seed`]: run seeds; [`dispersion`]: the draw of a run and how it is applied.
//! - [`runner`]: parallel execution, one FMU instance pair per worker, rows streamed to
//!   `manifest.csv` ([`manifest`]) with `campaign.toml` ([`config`]) beside it.
//! - [`merge`] joins shards; [`replay`] re-flies one flight bit-exactly; [`summary`] and
//!   [`plots`] give the table and the paper's Monte Carlo figure; [`analysis`] what drives
//!   each metric and the paired law differences; [`cli`] the subcommands.
pub mod analysis;
pub mod attitude;
pub mod campaign;
pub mod cli;
pub mod config;
pub mod dispersion;
pub mod estimator_start;
pub mod flight;
pub mod manifest;
pub mod merge;
pub mod plots;
pub mod replay;
pub mod runner;
pub mod seed;
pub mod stats;
pub mod summary;
pub mod summary_csv;

pub use campaign::{CampaignSpec, Flight, Shard};
pub use dispersion::{Dispersion, DispersionRanges};
