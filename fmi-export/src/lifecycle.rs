//! The life of an instance between instantiation and free: logging flags, the experiment,
//! initialization, termination and reset.
use crate::instance::{Core, Instance};
use crate::logging::Category;
use crate::state::{Interface, State};
use crate::status::{CallError, Status, Success};
use crate::version::{Abi, Function};
use fmi_model::{Log, Model};

/// Switches the named categories (all of the version's when none is named) on or off.
/// Every name is checked before any flag changes.
pub fn set_debug_logging<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    on: bool,
    names: &[Option<&[u8]>],
) -> Result<Success, CallError> {
    let mut chosen = Vec::with_capacity(names.len());
    for name in names {
        let name = name.ok_or(CallError::NullArgument("categories[i]"))?;
        let category = Category::from_name(name, A::CATEGORIES).ok_or_else(|| {
            CallError::InvalidArgument(format!(
                "unknown log category {:?} (this FMU has {})",
                String::from_utf8_lossy(name),
                A::CATEGORIES
                    .iter()
                    .map(|c| c.name().to_string_lossy())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        chosen.push(category);
    }
    if chosen.is_empty() {
        inst.logger.set_all(on);
    } else {
        for category in chosen {
            inst.logger.set(category, on);
        }
    }
    Ok(Success::Ok)
}

/// The start and (optional) stop time of the run.
pub fn set_experiment<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    start_time: f64,
    stop_time: Option<f64>,
) -> Result<Success, CallError> {
    if !start_time.is_finite() {
        return Err(CallError::InvalidArgument(format!(
            "startTime {start_time} is not finite"
        )));
    }
    if let Some(stop) = stop_time {
        if !(stop.is_finite() && stop >= start_time) {
            return Err(CallError::InvalidArgument(format!(
                "stopTime {stop} is not a finite time at or after startTime {start_time}"
            )));
        }
    }
    let core = &mut inst.core;
    core.start_time = start_time;
    core.stop_time = stop_time;
    core.time = start_time;
    core.last_successful_time = start_time;
    Ok(Success::Ok)
}

pub fn enter_initialization<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
) -> Result<Success, CallError> {
    inst.core.state = State::InitializationMode;
    inst.dirty = true;
    Ok(Success::Ok)
}

/// The model's own initialization; then Event Mode (Model Exchange, or Co-Simulation with
/// Event Mode) or the first step.
pub fn exit_initialization<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
) -> Result<Success, CallError> {
    let mut log = Log::default();
    let start_time = inst.core.start_time;
    let result = inst.core.model.exit_initialization(start_time, &mut log);
    let success = inst.forward(f, &log);
    result.map_err(|e| inst.model_failure(e))?;
    inst.core.state = match inst.interface() {
        Interface::ModelExchange => State::EventMode,
        Interface::CoSimulation if inst.options.event_mode_used => State::EventMode,
        Interface::CoSimulation => State::StepComplete,
    };
    inst.core.time = start_time;
    inst.core.last_successful_time = start_time;
    inst.dirty = true;
    Ok(success)
}

/// The end of the run; each warning that came more than once is summarised in one line
/// with its count and the times of its first and last (and the call's status is Warning).
pub fn terminate<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
) -> Result<Success, CallError> {
    inst.core.state = State::Terminated;
    let mut success = Success::Ok;
    for kind in inst.warnings.repeated() {
        inst.logger.status(
            Status::Warning,
            &format!(
                "{}: this warning came {} times from t = {} s to t = {} s (logged once): {}",
                f.name(),
                kind.count,
                kind.first_time,
                kind.last_time,
                kind.first_message
            ),
        );
        success = Success::Warning;
    }
    inst.warnings.clear();
    Ok(success)
}

/// Back to the freshly instantiated state: start values reapplied, time and status reset,
/// the warnings' tally started afresh. Logging flags and FMU states stay: they belong to the master's session, not to the run.
pub fn reset<M: Model, A: Abi>(inst: &mut Instance<M, A>) -> Result<Success, CallError> {
    inst.core = Core::fresh(inst.interface());
    inst.warnings.clear();
    inst.dirty = true;
    Ok(Success::Ok)
}

/// The call trace of the function that declares the experiment, in the words of both
/// standards' argument names. The tolerance is shown but not used: the models step with a
/// fixed schedule of their own.
pub fn experiment_trace(
    function: &str,
    tolerance_defined: impl std::fmt::Display,
    tolerance: f64,
    start_time: f64,
    stop_time_defined: impl std::fmt::Display,
    stop_time: f64,
) -> String {
    format!(
        "{function}(toleranceDefined={tolerance_defined}, tolerance={tolerance:e} (not used: \
         fixed-step model), startTime={start_time}, stopTimeDefined={stop_time_defined}, \
         stopTime={stop_time})"
    )
}
