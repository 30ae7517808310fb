//! `Panicky`, a test-only FMI 2.0 Co-Simulation model whose `do_step` panics once the time
//! reaches its parameter `panic_at`: the only way to make a panic cross an FMU's call on
//! purpose, since the shipped FMUs must not offer one. The system tests load its
//! cross-built library under Wine to check that the export core's panic guard still catches
//! the unwind at the C boundary there (SEH unwinding on Windows, DWARF on Linux).
#![deny(unsafe_code)]

use fmi2_export::{decl, Declaration, Experiment, Log, Model, ModelError, StepEnd};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Panicky {
    panic_at_s: f64,
    time_s: f64,
}

impl Default for Panicky {
    fn default() -> Self {
        // Never, unless the master asks for it.
        Self {
            panic_at_s: f64::MAX,
            time_s: 0.0,
        }
    }
}

/// The message of the panic, which the master must find in its log.
pub const PANIC_MESSAGE: &str = "Panicky: panic requested by the parameter panic_at";

#[rustfmt::skip]
static DECLARATIONS: [Declaration<Panicky>; 2] = [
    decl!(0, parameter panic_at: panic_at_s, "s", "Time from which fmi2DoStep panics"),
    decl!(1, output time: time_s, "s", "Time at the end of the last step"),
];

impl Model for Panicky {
    const MODEL_IDENTIFIER: &'static str = "Panicky";
    const MODEL_NAME: &'static str = "Panicky";
    const VERSION: &'static str = "0.0.0";
    const DESCRIPTION: &'static str = "A test model that panics in fmi2DoStep on request";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
        tolerance: None,
    };
    fn declarations() -> &'static [Declaration<Self>] {
        &DECLARATIONS
    }
    fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
        Ok(())
    }
    fn do_step(&mut self, t: f64, h: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
        if t >= self.panic_at_s {
            panic!("{PANIC_MESSAGE}");
        }
        self.time_s = t + h;
        Ok(StepEnd::Complete)
    }
}

fmi2_export::export_fmi2!(crate::Panicky);

/// The `fmuGUID` a master passes to `fmi2Instantiate`; this FMU has no model description to
/// read it from.
pub fn guid() -> String {
    fmi2_export::guid::<Panicky>()
}
