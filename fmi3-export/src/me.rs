//! The Model Exchange functions of FMI 3.0 (§3), for a model that implements
//! [`ContinuousModel`]: argument unpacking around the core's accessors
//! ([`fmi_export::model_exchange`]). [`no_me`] has the same functions for a
//! Co-Simulation-only model, refusing what is Model Exchange's. `fmi3EnterEventMode` and
//! `fmi3UpdateDiscreteStates` serve Co-Simulation's Event Mode too ([`crate::abi`]).
//!
//! # Safety
//! As for [`crate::abi`]: the master passes pointers valid as the standard requires.
#![allow(unsafe_code)]

use crate::abi::{self, call, instantiate, out, Instance};
use crate::ffi::*;
use crate::state::{Function, Interface};
use crate::Fmi3;
use fmi_export::model_exchange as me;
use fmi_export::{CallError, Options, Success};
use fmi_model::ContinuousModel;

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
            Options::default(),
            None,
            instance_name,
            instantiation_token,
            resource_path,
            logging_on,
            environment,
            log_message,
            String::new(),
            true,
        )
    }
}

unsafe fn simple<M: ContinuousModel>(
    c: fmi3Instance,
    f: Function,
    body: impl FnOnce(&mut Instance<M>) -> Result<Success, CallError>,
) -> fmi3Status {
    unsafe { call::<M, Fmi3>(c, f, || format!("{}()", f.name()), body) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: ContinuousModel>(c: fmi3Instance) -> fmi3Status {
    unsafe { abi::enter_event_mode::<M>(c) }
}

/// The model's event update (Model Exchange) or the Co-Simulation event's (nothing to
/// update); `terminateSimulation` when the model asks to end (touchdown).
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
            let (success, update) = match inst.interface() {
                Interface::ModelExchange => me::update_discrete_states(inst, f)?,
                Interface::CoSimulation => abi::co_simulation_event_update(inst),
            };
            *need = false;
            *terminate = inst.core.terminated;
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

/// `fmi3GetDirectionalDerivative` / `fmi3GetAdjointDerivative` (`f`) of a model with Model
/// Exchange: its states may be knowns and its state derivatives unknowns.
///
/// # Safety
/// See [`crate::abi`].
#[allow(clippy::too_many_arguments)]
pub unsafe fn derivative<M: ContinuousModel>(
    c: fmi3Instance,
    f: Function,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status {
    unsafe {
        abi::derivative::<M>(
            c,
            f,
            M::STATE_DERIVATIVES,
            unknowns,
            n_unknowns,
            knowns,
            n_knowns,
            seed,
            n_seed,
            sensitivity,
            n_sensitivity,
        )
    }
}

/// The same functions for a model without Model Exchange: instantiation is refused (NULL,
/// logged), the rest refused by the state table of a Co-Simulation instance, and the
/// counts are 0. Event Mode of Co-Simulation is served as for any model.
pub mod no_me {
    #![allow(clippy::too_many_arguments, clippy::missing_safety_doc)]
    use crate::abi::{self, call, instantiate, out};
    use crate::ffi::*;
    use crate::state::{Function, Interface, Refusal};
    use crate::Fmi3;
    use fmi_export::{CallError, Options, Success};
    use fmi_model::Model;

    fn refuse<M: Model>(c: fmi3Instance, f: Function) -> fmi3Status {
        // A Co-Simulation instance: the table answers for the interface.
        unsafe {
            call::<M, Fmi3>(
                c,
                f,
                || format!("{}(...)", f.name()),
                |inst| {
                    Err(CallError::Refused(
                        f.admit(inst.interface(), inst.core.state)
                            .err()
                            .unwrap_or(Refusal::WrongInterface(Interface::CoSimulation)),
                    ))
                },
            )
        }
    }

    /// The derivative functions of a model without Model Exchange: inputs and outputs only.
    pub unsafe fn derivative<M: Model>(
        c: fmi3Instance,
        f: Function,
        unknowns: *const fmi3ValueReference,
        n_unknowns: usize,
        knowns: *const fmi3ValueReference,
        n_knowns: usize,
        seed: *const fmi3Float64,
        n_seed: usize,
        sensitivity: *mut fmi3Float64,
        n_sensitivity: usize,
    ) -> fmi3Status {
        unsafe {
            abi::derivative::<M>(
                c,
                f,
                &[],
                unknowns,
                n_unknowns,
                knowns,
                n_knowns,
                seed,
                n_seed,
                sensitivity,
                n_sensitivity,
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
                Options::default(),
                None,
                instance_name,
                instantiation_token,
                resource_path,
                logging_on,
                environment,
                log_message,
                String::new(),
                false,
            )
        }
    }
    pub unsafe fn enter_event_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
        unsafe { abi::enter_event_mode::<M>(c) }
    }
    pub unsafe fn enter_continuous_time_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
        refuse::<M>(c, Function::EnterContinuousTimeMode)
    }
    pub unsafe fn update_discrete_states<M: Model>(
        c: fmi3Instance,
        need_update: *mut fmi3Boolean,
        terminate: *mut fmi3Boolean,
        nominals_changed: *mut fmi3Boolean,
        values_changed: *mut fmi3Boolean,
        time_defined: *mut fmi3Boolean,
        next_time: *mut fmi3Float64,
    ) -> fmi3Status {
        let f = Function::UpdateDiscreteStates;
        unsafe {
            call::<M, Fmi3>(
                c,
                f,
                || format!("{}()", f.name()),
                |inst| {
                    let outs = (
                        out(need_update, "discreteStatesNeedUpdate")?,
                        out(terminate, "terminateSimulation")?,
                        out(nominals_changed, "nominalsOfContinuousStatesChanged")?,
                        out(values_changed, "valuesOfContinuousStatesChanged")?,
                        out(time_defined, "nextEventTimeDefined")?,
                        out(next_time, "nextEventTime")?,
                    );
                    let (success, _) = abi::co_simulation_event_update(inst);
                    *outs.0 = false;
                    *outs.1 = inst.core.terminated;
                    *outs.2 = false;
                    *outs.3 = false;
                    *outs.4 = false;
                    *outs.5 = 0.0;
                    Ok(success)
                },
            )
        }
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
            call::<M, Fmi3>(
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
            call::<M, Fmi3>(
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
