//! The lander mission over the co-simulation master (`cosim`) and the importer
//! (`fmi-import`): the shipped scenarios, verdicts, flight metrics, the paper's law
//! comparison and the divert, Monte Carlo campaigns, figures and reports, and the `harness`
//! command line.
#![forbid(unsafe_code)]

pub mod metrics;
pub mod montecarlo;
pub mod overrides;
pub mod paper;
pub mod plots;
pub mod report;
pub mod retarget;
pub mod scenarios;
pub mod vars;
pub mod verdict;
