//! The master's tests, one binary (each test binary is linked on its own): systems refused
//! before the run with every problem named, algebraic loops, Model Exchange instances on the
//! solver, outputs that stop being numbers, and runs saved and continued.
mod common;
mod events;
mod fmi3_types;
mod general_master;
mod master_errors;
mod model_exchange_import;
mod non_finite;
mod non_finite_fmu;
mod saved_runs;
mod stiff_jacobian;
