//! The harness's end-to-end tests, one binary (each test binary is linked on its own): the
//! command line's runs, verdicts, campaigns, figures and reports over the packaged FMUs, and
//! what the documents say it does. The allocation count per step is a binary of its own
//! (no_allocation_per_step.rs): it installs a counting global allocator.
// std's transcendental functions here compute references and metrics independent of the
// libm the models use.
#![allow(clippy::disallowed_methods)]

mod common;

// The importer's and the master's fixtures, included rather than copied.
#[path = "../../fmi-import/tests/archives.rs"]
mod archives;
#[path = "../../cosim/tests/non_finite_fmu.rs"]
mod non_finite_fmu;
#[path = "../../fmi-import/tests/fixtures/stub_fmu3.rs"]
mod stub_fmu3;

mod arrow_python;
mod bounded_memory;
mod campaign_analysis;
mod campaign_dask;
mod campaign_divert;
mod campaign_filter_start;
mod campaign_lean;
mod campaign_requirements;
mod doc_commands;
mod figures;
mod flight_configuration;
mod full_fidelity;
mod full_fidelity_flight;
mod gnc_supervision;
mod golden_trajectory;
mod import;
mod linearize;
mod montecarlo;
mod montecarlo_cli;
mod montecarlo_resume;
mod nav_scenario;
mod paper_acceptance;
mod paper_requirements;
mod readme_examples;
mod reference_check;
mod report_browser;
mod requirements;
mod results_numbers;
mod retarget_scenario;
mod run_options;
mod saved_state;
mod scenario_campaign;
mod single_fmu;
mod ssp2_package;
mod ssp_scenario;
mod supervision;
mod thrusters_scenario;
mod vars_cli;
mod verdicts;
