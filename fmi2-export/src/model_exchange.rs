//! The 10 Model Exchange functions of FMI 2.0 (§3.2), for a model that implements
//! [`ContinuousModel`]. They go through the same [`call`] as the Co-Simulation functions:
//! state table, call trace, `catch_unwind`, every refusal logged. A vector of the wrong
//! length or a non-finite state is refused and changes nothing; a failure of the model
//! itself moves the instance to state Error.
//!
//! # Safety
//! As for [`crate::abi`]: the master passes pointers valid as the standard requires.
#![allow(unsafe_code)]

use crate::abi::{call, out, show, slice, slice_mut};
use crate::error::{CallError, Success};
use crate::ffi::*;
use crate::instance::Instance;
use crate::logging::Category;
use crate::model::Log;
use crate::state::{Function, State};
use fmi_model::continuous::{check_length, check_states};
use fmi_model::ContinuousModel;

/// # Safety
/// See the module documentation.
pub unsafe fn set_time<M: ContinuousModel>(c: fmi2Component, time: fmi2Real) -> fmi2Status {
    let f = Function::SetTime;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(time={time})", f.name()),
            |inst| {
                if !time.is_finite() {
                    return Err(CallError::InvalidArgument(format!(
                        "time {time} is not finite"
                    )));
                }
                inst.core.time = time;
                inst.core.model.set_time(time);
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_continuous_states<M: ContinuousModel>(
    c: fmi2Component,
    x: *const fmi2Real,
    nx: usize,
) -> fmi2Status {
    let f = Function::SetContinuousStates;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(nx={nx}, x={})", f.name(), show(x, nx)),
            |inst| {
                let x = slice(x, nx, "x")?;
                check_states(&inst.core.model, x).map_err(CallError::InvalidArgument)?;
                inst.core
                    .model
                    .set_states(x)
                    .map_err(|e| inst.model_failure(e))?;
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

/// The shared body of the four reads of a continuous vector.
unsafe fn read_vector<M: ContinuousModel>(
    c: fmi2Component,
    f: Function,
    out_ptr: *mut fmi2Real,
    n: usize,
    count: fn(&M) -> usize,
    read: fn(&mut Instance<M>, &mut [f64]) -> Result<(), CallError>,
) -> fmi2Status {
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(n={n})", f.name()),
            |inst| {
                let values = slice_mut(out_ptr, n, "values")?;
                check_length::<M>("values", n, count(&inst.core.model))
                    .map_err(CallError::InvalidArgument)?;
                // Outputs the derivatives depend on are the model's own: refresh first.
                let success = inst.refresh(f);
                read(inst, values)?;
                Ok(success)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_derivatives<M: ContinuousModel>(
    c: fmi2Component,
    derivatives: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetDerivatives,
            derivatives,
            nx,
            M::state_count,
            |inst, dx| {
                let result = inst.core.model.derivatives(dx);
                result.map_err(|e| inst.model_failure(e))
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_event_indicators<M: ContinuousModel>(
    c: fmi2Component,
    event_indicators: *mut fmi2Real,
    ni: usize,
) -> fmi2Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetEventIndicators,
            event_indicators,
            ni,
            M::event_indicator_count,
            |inst, z| {
                let result = inst.core.model.event_indicators(z);
                result.map_err(|e| inst.model_failure(e))
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_continuous_states<M: ContinuousModel>(
    c: fmi2Component,
    x: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetContinuousStates,
            x,
            nx,
            M::state_count,
            |inst, x| {
                inst.core.model.states(x);
                Ok(())
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_nominals_of_continuous_states<M: ContinuousModel>(
    c: fmi2Component,
    x_nominal: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetNominalsOfContinuousStates,
            x_nominal,
            nx,
            M::state_count,
            |inst, nominal| {
                inst.core.model.nominals(nominal);
                Ok(())
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: ContinuousModel>(c: fmi2Component) -> fmi2Status {
    let f = Function::EnterEventMode;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core.state = State::EventMode;
                Ok(Success::Ok)
            },
        )
    }
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
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                let info = out(event_info, "fmi2EventInfo")?;
                let mut log = Log::default();
                let result = inst.core.model.update_discrete_states(&mut log);
                inst.dirty = true;
                let success = inst.forward(f, &log);
                let update = result.map_err(|e| inst.model_failure(e))?;
                if update.terminate {
                    inst.core.terminated = true;
                    if inst.logger.is_on(Category::StatusOk) {
                        inst.logger.log(
                            fmi2OK,
                            Category::StatusOk,
                            &format!("{}: the model ends the simulation", f.name()),
                        );
                    }
                }
                let flag = |b: bool| if b { fmi2True } else { fmi2False };
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

/// # Safety
/// See the module documentation.
pub unsafe fn enter_continuous_time_mode<M: ContinuousModel>(c: fmi2Component) -> fmi2Status {
    let f = Function::EnterContinuousTimeMode;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core.state = State::ContinuousTimeMode;
                Ok(Success::Ok)
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
    unsafe {
        call::<M>(
            c,
            f,
            || {
                format!(
                    "{}(noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})",
                    f.name()
                )
            },
            |inst| {
                let enter = out(enter_event_mode, "enterEventMode")?;
                let terminate = out(terminate_simulation, "terminateSimulation")?;
                *enter = fmi2False;
                *terminate = if inst.core.terminated {
                    fmi2True
                } else {
                    fmi2False
                };
                Ok(Success::Ok)
            },
        )
    }
}
