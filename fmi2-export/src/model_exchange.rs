//! The 10 Model Exchange functions of FMI 2.0 (§3.2), for a model that implements
//! [`ContinuousModel`]: argument unpacking around the core's accessors
//! ([`fmi_export::model_exchange`]), through the same [`call`] as everything else.
//!
//! # Safety
//! As for [`crate::abi`]: the master passes pointers valid as the standard requires.
#![allow(unsafe_code)]

use crate::abi::{call, out};
use crate::ffi::*;
use crate::state::Function;
use crate::Fmi2;
use fmi_export::model_exchange as me;
use fmi_export::{Category, Status, Success};
use fmi_model::ContinuousModel;

fn flag(b: bool) -> fmi2Boolean {
    if b {
        fmi2True
    } else {
        fmi2False
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: ContinuousModel>(c: fmi2Component) -> fmi2Status {
    let f = Function::EnterEventMode;
    unsafe { call::<M, Fmi2>(c, f, || format!("{}()", f.name()), me::enter_event_mode) }
}

/// The model's event update; `terminateSimulation` when it asks to end (touchdown).
///
/// # Safety
/// See the module documentation.
pub unsafe fn new_discrete_states<M: ContinuousModel>(
    c: fmi2Component,
    event_info: *mut fmi2EventInfo,
) -> fmi2Status {
    let f = Function::NewDiscreteStates;
    unsafe {
        call::<M, Fmi2>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                let info = out(event_info, "fmi2EventInfo")?;
                let (success, update) = me::update_discrete_states(inst, f)?;
                if update.terminate && inst.logger.is_on(Category::StatusOk) {
                    inst.logger.log(
                        Status::Ok,
                        Category::StatusOk,
                        &format!("{}: the model ends the simulation", f.name()),
                    );
                }
                *info = fmi2EventInfo {
                    newDiscreteStatesNeeded: fmi2False,
                    terminateSimulation: flag(update.terminate),
                    nominalsOfContinuousStatesChanged: flag(update.nominals_changed),
                    valuesOfContinuousStatesChanged: flag(update.states_changed),
                    nextEventTimeDefined: fmi2False,
                    nextEventTime: 0.0,
                };
                Ok(success)
            },
        )
    }
}

/// No step event and no end: the models need no action after an accepted solver step
/// (the description says `completedIntegratorStepNotNeeded`).
///
/// # Safety
/// See the module documentation.
pub unsafe fn completed_integrator_step<M: ContinuousModel>(
    c: fmi2Component,
    no_set_fmu_state_prior_to_current_point: fmi2Boolean,
    enter_event_mode: *mut fmi2Boolean,
    terminate_simulation: *mut fmi2Boolean,
) -> fmi2Status {
    let f = Function::CompletedIntegratorStep;
    let trace = || {
        format!(
            "{}(noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})",
            f.name()
        )
    };
    unsafe {
        call::<M, Fmi2>(c, f, trace, |inst| {
            *out(enter_event_mode, "enterEventMode")? = fmi2False;
            *out(terminate_simulation, "terminateSimulation")? = flag(inst.core.terminated);
            Ok(Success::Ok)
        })
    }
}
