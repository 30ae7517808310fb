//! The rules of a Co-Simulation step, once for both versions: the arguments checked, the
//! model advanced, the time kept. The outcome is version-neutral; each layer reports it as
//! its standard says (FMI 2.0: a step that ended early is `fmi2Discard` with
//! `fmi2LastSuccessfulTime`; FMI 3.0: `fmi3OK` with `earlyReturn`, `terminateSimulation` and
//! `lastSuccessfulTime`).
use crate::instance::Instance;
use crate::status::{CallError, Success};
use crate::version::Abi;
use crate::{time_tolerance, TIME_TOLERANCE};
use fmi_model::{readable, Log, Model, StepEnd};

/// How a step that was carried out ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Advance {
    /// At `t + h`.
    Complete,
    /// Early, at the model's event.
    Stopped {
        at: f64,
        terminated: bool,
        reason: String,
    },
}

/// Checks a step from `t` of `h` and returns its end `t + h`; refuses (and changes nothing)
/// a step that is not a finite advance from the instance's time or passes the stop time.
pub fn check<M: Model, A: Abi>(inst: &Instance<M, A>, t: f64, h: f64) -> Result<f64, CallError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(CallError::InvalidArgument(format!(
            "communicationStepSize {} is not a finite positive number",
            readable(h)
        )));
    }
    let time = inst.core.time;
    // Written so that a NaN anywhere (the master's t, or a corrupt time of ours) refuses.
    if !(t.is_finite() && time.is_finite() && (t - time).abs() <= time_tolerance(time)) {
        return Err(CallError::InvalidArgument(format!(
            "currentCommunicationPoint {} does not match the FMU's time {} \
             (relative tolerance {TIME_TOLERANCE:e})",
            readable(t),
            readable(time)
        )));
    }
    // The master's own t + h: the next call's t must match it, so no rounding of ours.
    let end = t + h;
    if !(end.is_finite() && end > t) {
        return Err(CallError::InvalidArgument(format!(
            "currentCommunicationPoint {} + communicationStepSize {} = {}: the step does not \
             advance a finite time",
            readable(t),
            readable(h),
            readable(end)
        )));
    }
    if let Some(stop) = inst.core.stop_time {
        if end > stop + time_tolerance(stop) {
            return Err(CallError::InvalidArgument(format!(
                "step to {} (currentCommunicationPoint {} + communicationStepSize {}) passes \
                 the stop time {} given to {}",
                readable(end),
                readable(t),
                readable(h),
                readable(stop),
                A::EXPERIMENT
            )));
        }
    }
    Ok(end)
}

/// [`check`] for a call's fast path: the step's end when `check` accepts the step, else
/// `None` (for `check` to say why). The same tests in fewer instructions: `x - x` is 0
/// exactly when `x` is finite (NaN otherwise), so one sum tells whether `h`, `t`, the
/// instance's time and `t + h` all are; the comparisons then need no finite operands.
#[inline(always)]
pub fn accepted<M: Model, A: Abi>(inst: &Instance<M, A>, t: f64, h: f64) -> Option<f64> {
    let time = inst.core.time;
    let end = t + h;
    #[allow(clippy::eq_op)]
    let nan_unless_finite = (h - h) + (t - t) + (time - time) + (end - end);
    let accepted = nan_unless_finite == 0.0
        && h > 0.0
        && end > t
        && (t - time).abs() <= time_tolerance(time)
        && match inst.core.stop_time {
            // (A NaN stop time, which `check` lets pass, is left to it.)
            Some(stop) => end <= stop + time_tolerance(stop),
            None => true,
        };
    accepted.then_some(end)
}

/// One step of the model from `t` to `t + h` (checked by [`check`]); the instance's time
/// is then the step's end or where the model stopped. A model that stops outside the step
/// is a failure of the model (state Error) in both versions.
pub fn advance<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
    t: f64,
    h: f64,
) -> Result<(Success, Advance), CallError> {
    let end = check(inst, t, h)?;
    advance_checked(inst, f, t, h, end)
}

#[inline(always)]
/// [`advance`] of a step [`check`] has accepted, ending at `end` (= `t + h` as the master
/// computed it); also the rest of a step after an event inside it.
pub fn advance_checked<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
    t: f64,
    h: f64,
    end: f64,
) -> Result<(Success, Advance), CallError> {
    let mut log = Log::default();
    let result = inst.core.model.do_step(t, h, &mut log);
    inst.dirty = true;
    let success = inst.forward(f, &log);
    match result.map_err(|e| inst.model_failure(e))? {
        StepEnd::Complete => {
            inst.core.time = end;
            inst.core.last_successful_time = end;
            Ok((success, Advance::Complete))
        }
        StepEnd::Stopped {
            time: at,
            terminated,
            reason,
        } => {
            if !(t..=end).contains(&at) {
                return Err(inst.fail(CallError::Model(format!(
                    "model error: stopped at {}, outside the step [{}, {}]",
                    readable(at),
                    readable(t),
                    readable(end)
                ))));
            }
            inst.core.time = at;
            inst.core.last_successful_time = at;
            inst.core.terminated |= terminated;
            Ok((
                success,
                Advance::Stopped {
                    at,
                    terminated,
                    reason,
                },
            ))
        }
    }
}

/// The call trace of a step, in the words of both standards' argument names.
pub fn trace(function: &str, t: f64, h: f64, no_set_prior: impl std::fmt::Display) -> String {
    format!(
        "{function}(currentCommunicationPoint={t}, communicationStepSize={h}, \
         noSetFMUStatePriorToCurrentPoint={no_set_prior})"
    )
}
