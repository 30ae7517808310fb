//! Campaigns over any scenario (`harness campaign SCENARIO`): the scenario's `[campaign]`
//! table sweeps and disperses parameters of its FMUs, each run is judged by the scenario's
//! requirements, and the results are a manifest, a summary and sensitivities. Nothing here
//! names a lander variable.
//!
//! - `cosim::system::campaign_table`: the table as written; [`distribution`]: the distributions;
//!   [`sampling`]: random and Latin hypercube draws, correlations; [`target`]: what an input
//!   sets; [`plan`]: the checked campaign and its numbering.
//! - [`campaign`]: loading and checking against the FMUs, one run; [`runner`]: runs in
//!   parallel, shards, resume, replay; [`manifest`] and [`config`]: its files; [`merge`]:
//!   shards joined; [`summary`]: statistics and sensitivities.
pub mod campaign;
pub mod config;
pub mod distribution;
pub mod manifest;
pub mod merge;
pub mod plan;
pub mod runner;
pub mod sampling;
pub mod summary;
pub mod target;

#[cfg(test)]
mod tests;
