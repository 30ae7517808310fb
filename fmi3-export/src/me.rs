//! The Model Exchange functions of FMI 3.0 (§3), for a model that implements
//! [`ContinuousModel`]; [`no_me`] has the same functions for a Co-Simulation-only model,
//! each refusing with a log line. They go through the same [`call`] as everything else.
//!
//! # Safety
//! As for [`crate::abi`]: the master passes pointers valid as the standard requires.
#![allow(unsafe_code)]

use crate::abi::{call, instantiate, out, show, slice, slice_mut};
use crate::error::{CallError, Success};
use crate::ffi::*;
use crate::instance::Instance;
use crate::state::{Function, Interface, State};
use fmi_model::continuous::{check_length, check_states};
use fmi_model::{ContinuousModel, Log};

/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_model_exchange<M: ContinuousModel>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    _visible: fmi3Boolean,
    logging_on: fmi3Boolean,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    unsafe {
        instantiate::<M>(
            Interface::ModelExchange,
            Ok(()),
            instance_name,
            instantiation_token,
            resource_path,
            logging_on,
            environment,
            log_message,
            String::new(),
        )
    }
}

unsafe fn simple<M: ContinuousModel>(
    c: fmi3Instance,
    f: Function,
    body: impl FnOnce(&mut Instance<M>) -> Result<Success, CallError>,
) -> fmi3Status {
    unsafe { call::<M>(c, f, || format!("{}()", f.name()), body) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: ContinuousModel>(c: fmi3Instance) -> fmi3Status {
    unsafe {
        simple::<M>(c, Function::EnterEventMode, |inst| {
            inst.core.state = State::EventMode;
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_continuous_time_mode<M: ContinuousModel>(c: fmi3Instance) -> fmi3Status {
    unsafe {
        simple::<M>(c, Function::EnterContinuousTimeMode, |inst| {
            inst.core.state = State::ContinuousTimeMode;
            Ok(Success::Ok)
        })
    }
}

/// The model's event update; `terminateSimulation` when it asks to end (touchdown).
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn update_discrete_states<M: ContinuousModel>(
    c: fmi3Instance,
    discrete_states_need_update: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    nominals_changed: *mut fmi3Boolean,
    values_changed: *mut fmi3Boolean,
    next_event_time_defined: *mut fmi3Boolean,
    next_event_time: *mut fmi3Float64,
) -> fmi3Status {
    let f = Function::UpdateDiscreteStates;
    unsafe {
        simple::<M>(c, f, |inst| {
            let need = out(discrete_states_need_update, "discreteStatesNeedUpdate")?;
            let terminate = out(terminate_simulation, "terminateSimulation")?;
            let nominals = out(nominals_changed, "nominalsOfContinuousStatesChanged")?;
            let values = out(values_changed, "valuesOfContinuousStatesChanged")?;
            let time_defined = out(next_event_time_defined, "nextEventTimeDefined")?;
            let time = out(next_event_time, "nextEventTime")?;
            let mut log = Log::default();
            let result = inst.core.model.update_discrete_states(&mut log);
            inst.dirty = true;
            let success = inst.forward(f, &log);
            let update = result.map_err(|e| inst.model_failure(e))?;
            inst.core.terminated |= update.terminate;
            *need = false;
            *terminate = update.terminate;
            *nominals = update.nominals_changed;
            *values = update.states_changed;
            *time_defined = false;
            *time = 0.0;
            Ok(success)
        })
    }
}

/// No step event: the models need no action after an accepted solver step.
///
/// # Safety
/// See the module documentation.
pub unsafe fn completed_integrator_step<M: ContinuousModel>(
    c: fmi3Instance,
    _no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    enter_event_mode: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
) -> fmi3Status {
    unsafe {
        simple::<M>(c, Function::CompletedIntegratorStep, |inst| {
            *out(enter_event_mode, "enterEventMode")? = false;
            *out(terminate_simulation, "terminateSimulation")? = inst.core.terminated;
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_time<M: ContinuousModel>(c: fmi3Instance, time: fmi3Float64) -> fmi3Status {
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
                // Against the start time, which a restored state guarantees finite: the
                // instance's own time may be what is corrupt.
                let start = inst.core.start_time;
                if time < start - crate::abi::TIME_TOLERANCE * start.abs().max(1.0) {
                    return Err(CallError::InvalidArgument(format!(
                        "time {time} is before the start time {start}"
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
    c: fmi3Instance,
    x: *const fmi3Float64,
    nx: usize,
) -> fmi3Status {
    let f = Function::SetContinuousStates;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(nx={nx}, x={})", f.name(), show(x, nx)),
            |inst| {
                let x = slice(x, nx, "continuousStates")?;
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

unsafe fn read_vector<M: ContinuousModel>(
    c: fmi3Instance,
    f: Function,
    ptr: *mut fmi3Float64,
    n: usize,
    count: fn(&M) -> usize,
    read: fn(&mut Instance<M>, &mut [f64]) -> Result<(), CallError>,
) -> fmi3Status {
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(n={n})", f.name()),
            |inst| {
                let values = slice_mut(ptr, n, "values")?;
                check_length::<M>("values", n, count(&inst.core.model))
                    .map_err(CallError::InvalidArgument)?;
                let success = inst.refresh(f);
                read(inst, values)?;
                Ok(success)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_continuous_state_derivatives<M: ContinuousModel>(
    c: fmi3Instance,
    derivatives: *mut fmi3Float64,
    nx: usize,
) -> fmi3Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetContinuousStateDerivatives,
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
    c: fmi3Instance,
    z: *mut fmi3Float64,
    nz: usize,
) -> fmi3Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetEventIndicators,
            z,
            nz,
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
    c: fmi3Instance,
    x: *mut fmi3Float64,
    nx: usize,
) -> fmi3Status {
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
    c: fmi3Instance,
    nominals: *mut fmi3Float64,
    nx: usize,
) -> fmi3Status {
    unsafe {
        read_vector::<M>(
            c,
            Function::GetNominalsOfContinuousStates,
            nominals,
            nx,
            M::state_count,
            |inst, n| {
                inst.core.model.nominals(n);
                Ok(())
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_number_of_event_indicators<M: ContinuousModel>(
    c: fmi3Instance,
    n: *mut usize,
) -> fmi3Status {
    unsafe {
        simple::<M>(c, Function::GetNumberOfEventIndicators, |inst| {
            *out(n, "nEventIndicators")? = inst.core.model.event_indicator_count();
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_number_of_continuous_states<M: ContinuousModel>(
    c: fmi3Instance,
    n: *mut usize,
) -> fmi3Status {
    unsafe {
        simple::<M>(c, Function::GetNumberOfContinuousStates, |inst| {
            *out(n, "nContinuousStates")? = inst.core.model.state_count();
            Ok(Success::Ok)
        })
    }
}

/// The same functions for a model without Model Exchange: instantiation is refused (NULL,
/// logged), the rest refused by the state table of a Co-Simulation instance, and the
/// counts are 0.
pub mod no_me {
    #![allow(clippy::too_many_arguments, clippy::missing_safety_doc)]
    use crate::abi::{call, instantiate, out};
    use crate::error::{CallError, Success};
    use crate::ffi::*;
    use crate::state::{Function, Interface, Refusal};
    use fmi_model::Model;

    fn refuse<M: Model>(c: fmi3Instance, f: Function) -> fmi3Status {
        // A Co-Simulation instance: the table answers for the interface.
        unsafe {
            call::<M>(
                c,
                f,
                || format!("{}(...)", f.name()),
                |inst| {
                    Err(CallError::Refused(
                        f.admit(inst.interface, inst.core.state)
                            .err()
                            .unwrap_or(Refusal::WrongInterface(Interface::CoSimulation)),
                    ))
                },
            )
        }
    }

    pub unsafe fn instantiate_model_exchange<M: Model>(
        instance_name: fmi3String,
        instantiation_token: fmi3String,
        resource_path: fmi3String,
        _visible: fmi3Boolean,
        logging_on: fmi3Boolean,
        environment: fmi3InstanceEnvironment,
        log_message: fmi3LogMessageCallback,
    ) -> fmi3Instance {
        unsafe {
            instantiate::<M>(
                Interface::ModelExchange,
                Err(format!(
                    "{} offers Co-Simulation only, not Model Exchange",
                    M::MODEL_IDENTIFIER
                )),
                instance_name,
                instantiation_token,
                resource_path,
                logging_on,
                environment,
                log_message,
                String::new(),
            )
        }
    }
    pub unsafe fn enter_event_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
        refuse::<M>(c, Function::EnterEventMode)
    }
    pub unsafe fn enter_continuous_time_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
        refuse::<M>(c, Function::EnterContinuousTimeMode)
    }
    pub unsafe fn update_discrete_states<M: Model>(
        c: fmi3Instance,
        _need_update: *mut fmi3Boolean,
        _terminate: *mut fmi3Boolean,
        _nominals_changed: *mut fmi3Boolean,
        _values_changed: *mut fmi3Boolean,
        _time_defined: *mut fmi3Boolean,
        _next_time: *mut fmi3Float64,
    ) -> fmi3Status {
        refuse::<M>(c, Function::UpdateDiscreteStates)
    }
    pub unsafe fn completed_integrator_step<M: Model>(
        c: fmi3Instance,
        _no_set_prior: fmi3Boolean,
        _enter_event_mode: *mut fmi3Boolean,
        _terminate: *mut fmi3Boolean,
    ) -> fmi3Status {
        refuse::<M>(c, Function::CompletedIntegratorStep)
    }
    pub unsafe fn set_time<M: Model>(c: fmi3Instance, _time: fmi3Float64) -> fmi3Status {
        refuse::<M>(c, Function::SetTime)
    }
    pub unsafe fn set_continuous_states<M: Model>(
        c: fmi3Instance,
        _x: *const fmi3Float64,
        _n: usize,
    ) -> fmi3Status {
        refuse::<M>(c, Function::SetContinuousStates)
    }
    pub unsafe fn get_continuous_state_derivatives<M: Model>(
        c: fmi3Instance,
        _x: *mut fmi3Float64,
        _n: usize,
    ) -> fmi3Status {
        refuse::<M>(c, Function::GetContinuousStateDerivatives)
    }
    pub unsafe fn get_event_indicators<M: Model>(
        c: fmi3Instance,
        _x: *mut fmi3Float64,
        _n: usize,
    ) -> fmi3Status {
        refuse::<M>(c, Function::GetEventIndicators)
    }
    pub unsafe fn get_continuous_states<M: Model>(
        c: fmi3Instance,
        _x: *mut fmi3Float64,
        _n: usize,
    ) -> fmi3Status {
        refuse::<M>(c, Function::GetContinuousStates)
    }
    pub unsafe fn get_nominals_of_continuous_states<M: Model>(
        c: fmi3Instance,
        _x: *mut fmi3Float64,
        _n: usize,
    ) -> fmi3Status {
        refuse::<M>(c, Function::GetNominalsOfContinuousStates)
    }
    pub unsafe fn get_number_of_event_indicators<M: Model>(
        c: fmi3Instance,
        n: *mut usize,
    ) -> fmi3Status {
        let f = Function::GetNumberOfEventIndicators;
        unsafe {
            call::<M>(
                c,
                f,
                || format!("{}()", f.name()),
                |_| {
                    *out(n, "nEventIndicators")? = 0;
                    Ok(Success::Ok)
                },
            )
        }
    }
    pub unsafe fn get_number_of_continuous_states<M: Model>(
        c: fmi3Instance,
        n: *mut usize,
    ) -> fmi3Status {
        let f = Function::GetNumberOfContinuousStates;
        unsafe {
            call::<M>(
                c,
                f,
                || format!("{}()", f.name()),
                |_| {
                    *out(n, "nContinuousStates")? = 0;
                    Ok(Success::Ok)
                },
            )
        }
    }
}
