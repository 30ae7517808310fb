//! One instance of a loaded FMU, FMI 2.0 or 3.0, driven through one safe API: the master,
//! the system and the results never ask which version they drive. Every FMI status comes back
//! as a `Result`, and a failure carries what the FMU logged during the failing call.
//!
//! Values travel by value reference; for FMI 3.0 that is the element reference of the scalar
//! view (an array element such as `r_nue[2]` has one, see `fmi3/view.rs`), so the same names
//! and the same calls serve both versions.
use super::error::{CallError, FmiError};
use super::fmi2::Fmi2Instance;
use super::fmi3::Fmi3Instance;
use super::loaded::{Api, FmuShared};
use super::logger::{LogEnv, LogMessage};
use super::state::FmuState;
use super::status::{StepStatus, Success};
use super::variables::VariableInfo;
use super::version::FmiVersion;
use crate::model_exchange::{EventUpdate, Interface, MeVector, StepEnd};
use model_description::VariableKind;
use std::sync::Arc;

/// How a master means to drive an instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct InstanceOptions {
    /// The FMU sends its debug messages (errors are logged either way).
    pub logging_on: bool,
    /// The master will get outputs after setting inputs at the same communication point and
    /// wants them computed from those inputs. FMI 2.0 allows that in any state. FMI 3.0 forbids
    /// it in Step Mode (4.2.1): with this set, and an FMU with `hasEventMode`, the instance
    /// is made with `eventModeUsed = true` and exchanges in Event Mode (see `fmi3/instance.rs`);
    /// without it, such a get is refused.
    pub same_instant_feedthrough: bool,
    /// Co-Simulation (the default) or Model Exchange, which FMI 2.0 FMUs offer here.
    pub interface: Interface,
}

/// A Co-Simulation instance; freed (`fmi2FreeInstance`, `fmi3FreeInstance`) on drop.
///
/// `Send`, so each thread of a Monte Carlo campaign can own its instances, but not `Sync`:
/// every call takes `&mut self`, so calls into one instance never overlap.
///
/// ```compile_fail
/// fn shared_between_threads<T: Sync>() {}
/// shared_between_threads::<harness::Instance>();
/// ```
pub struct Instance {
    fmu: Arc<FmuShared>,
    backend: Backend,
    interface: Interface,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("name", &self.name())
            .field("model_name", &self.fmu.description.model_name)
            .field("backend", &self.backend)
            .finish_non_exhaustive()
    }
}

// FMI 2.0 inline, as before there were two backends: no indirection on its hot path.
#[allow(clippy::large_enum_variant)]
#[derive(Debug)]
enum Backend {
    Fmi2(Fmi2Instance),
    Fmi3(Box<Fmi3Instance>),
}

// Monte Carlo workers own their instances and FMU handles; fail to compile if that breaks.
const _: () = {
    const fn assert_send<T: Send>() {}
    const fn assert_send_sync<T: Send + Sync>() {}
    assert_send::<Instance>();
    assert_send::<FmuState>();
    assert_send_sync::<super::Fmu>();
};

/// Calls the same method on whichever backend the instance has.
macro_rules! both {
    ($self:ident, $backend:ident => $call:expr) => {
        match &mut $self.backend {
            Backend::Fmi2($backend) => $call,
            Backend::Fmi3($backend) => $call,
        }
    };
}

/// [`both!`], the call noted first in the black box (see `blackbox.rs`) under the
/// function's name in the instance's FMI version.
macro_rules! noted {
    ($self:ident, $fmi2:literal, $fmi3:literal, $backend:ident => $call:expr) => {{
        let _call = match &$self.backend {
            Backend::Fmi2(i) => crate::blackbox::enter(
                i.black_box,
                const { crate::blackbox::function($fmi2) },
            ),
            Backend::Fmi3(i) => crate::blackbox::enter(
                i.black_box,
                const { crate::blackbox::function($fmi3) },
            ),
        };
        both!($self, $backend => $call)
    }};
}

impl Instance {
    pub(crate) fn new(
        fmu: Arc<FmuShared>,
        name: &str,
        options: InstanceOptions,
    ) -> Result<Self, CallError> {
        let backend = match &fmu.api {
            Api::Fmi2(functions) => {
                let available = match options.interface {
                    Interface::CoSimulation => functions.co_simulation.is_some(),
                    Interface::ModelExchange => functions.model_exchange.is_some(),
                };
                if !available {
                    return Err(CallError::InvalidArgument {
                        function: "fmi2Instantiate",
                        instance: name.to_owned(),
                        reason: format!(
                            "model '{}' does not declare {:?} (its model description has no <{}> \
                             element)",
                            fmu.description.model_name,
                            options.interface,
                            match options.interface {
                                Interface::CoSimulation => "CoSimulation",
                                Interface::ModelExchange => "ModelExchange",
                            }
                        ),
                    });
                }
                Backend::Fmi2(Fmi2Instance::new(
                    Arc::clone(&fmu),
                    *functions,
                    name,
                    options.logging_on,
                    options.interface,
                )?)
            }
            Api::Fmi3(api) => {
                let event_mode = options.same_instant_feedthrough
                    && api
                        .description
                        .co_simulation
                        .as_ref()
                        .is_some_and(|cs| cs.has_event_mode);
                Backend::Fmi3(Box::new(Fmi3Instance::new(
                    Arc::clone(&fmu),
                    Arc::clone(api),
                    name,
                    options.logging_on,
                    event_mode,
                    options.interface,
                )?))
            }
        };
        Ok(Self {
            fmu,
            backend,
            interface: options.interface,
        })
    }

    pub fn name(&self) -> &str {
        match &self.backend {
            Backend::Fmi2(i) => i.name(),
            Backend::Fmi3(i) => i.name(),
        }
    }

    pub fn fmi_version(&self) -> FmiVersion {
        match self.backend {
            Backend::Fmi2(_) => FmiVersion::Fmi2,
            Backend::Fmi3(_) => FmiVersion::Fmi3,
        }
    }

    /// Whether a get may follow a set at one communication point and see the inputs just
    /// set: always in FMI 2.0; in FMI 3.0 only in Event Mode, i.e. for an instance made with
    /// [`InstanceOptions::same_instant_feedthrough`] of an FMU with `hasEventMode`.
    pub fn can_get_after_set(&self) -> bool {
        match &self.backend {
            Backend::Fmi2(_) => true,
            Backend::Fmi3(i) => i.event_mode_used(),
        }
    }

    /// The step function's name, for messages: `fmi2DoStep` or `fmi3DoStep`.
    pub fn do_step_function(&self) -> &'static str {
        match self.backend {
            Backend::Fmi2(_) => "fmi2DoStep",
            Backend::Fmi3(_) => "fmi3DoStep",
        }
    }

    fn log(&self) -> &Arc<LogEnv> {
        match &self.backend {
            Backend::Fmi2(i) => i.log(),
            Backend::Fmi3(i) => i.log(),
        }
    }

    /// Everything the FMU logged for this instance (the newest [`LOG_CAPACITY`](super::LOG_CAPACITY) messages).
    pub fn log_messages(&self) -> Vec<LogMessage> {
        self.log().all()
    }

    pub fn clear_log(&self) {
        self.log().clear();
    }

    pub fn variable(&self, name: &str) -> Result<&VariableInfo, CallError> {
        Ok(self.fmu.variables.get(name)?)
    }

    /// `fmi2SetDebugLogging` / `fmi3SetDebugLogging`; an empty `categories` means all.
    pub fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[&str],
    ) -> Result<Success, CallError> {
        noted!(self, "fmi2SetDebugLogging", "fmi3SetDebugLogging", i => i.set_debug_logging(logging_on, categories))
    }

    /// `fmi2SetupExperiment`; FMI 3.0 passes the values to `fmi3EnterInitializationMode`.
    /// `None` leaves the tolerance or stop time undefined.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Success, FmiError> {
        crate::blackbox::set_time(start_time);
        noted!(self, "fmi2SetupExperiment", "fmi3EnterInitializationMode", i => i.setup_experiment(tolerance, start_time, stop_time))
    }

    pub fn enter_initialization_mode(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2EnterInitializationMode", "fmi3EnterInitializationMode", i => i.enter_initialization_mode())
    }

    pub fn exit_initialization_mode(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2ExitInitializationMode", "fmi3ExitInitializationMode", i => i.exit_initialization_mode())
    }

    pub fn terminate(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2Terminate", "fmi3Terminate", i => i.terminate())
    }

    /// Back to the freshly instantiated state. Saved FMU states stay valid.
    pub fn reset(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2Reset", "fmi3Reset", i => i.reset())
    }

    /// One communication step from `current_time` over `step_size`.
    ///
    /// FMI 2.0: `noSetFMUStatePriorToCurrentPoint` is false because this API lets the caller
    /// restore any saved state at any time; a discard is reported with
    /// `fmi2LastSuccessfulTime` and `fmi2Terminated`. FMI 3.0: Event Mode is left first if the
    /// instance is in it; `terminateSimulation` is [`StepStatus::Terminated`].
    pub fn do_step(&mut self, current_time: f64, step_size: f64) -> Result<StepStatus, FmiError> {
        crate::blackbox::set_time(current_time);
        let stepped =
            noted!(self, "fmi2DoStep", "fmi3DoStep", i => i.do_step(current_time, step_size));
        // The calls after a step belong to the communication point it reached.
        crate::blackbox::set_time(current_time + step_size);
        stepped
    }

    /// Where the last step stopped (FMI 2.0: `fmi2GetRealStatus(fmi2LastSuccessfulTime)`;
    /// FMI 3.0: `lastSuccessfulTime` of the last `fmi3DoStep`).
    pub fn last_successful_time(&mut self) -> Result<f64, FmiError> {
        match &mut self.backend {
            Backend::Fmi2(i) => i.last_successful_time(),
            Backend::Fmi3(i) => Ok(i.last_successful_time()),
        }
    }

    /// The FMU wants the simulation to end (FMI 2.0: `fmi2GetBooleanStatus(fmi2Terminated)`;
    /// FMI 3.0: `terminateSimulation` of the last step).
    pub fn terminated(&mut self) -> Result<bool, FmiError> {
        match &mut self.backend {
            Backend::Fmi2(i) => i.terminated(),
            Backend::Fmi3(i) => Ok(i.terminated()),
        }
    }

    // ---- Model Exchange ----

    /// The numbers of continuous states and event indicators (FMI 2.0: from the model
    /// description, `ModelStructure/Derivatives` and `numberOfEventIndicators`; FMI 3.0:
    /// `fmi3GetNumberOfContinuousStates`, `fmi3GetNumberOfEventIndicators`).
    pub fn model_exchange_sizes(&mut self) -> Result<(usize, usize), FmiError> {
        match &mut self.backend {
            Backend::Fmi2(_) => {
                let description = &self.fmu.description;
                let states = description
                    .model_structure
                    .derivatives
                    .as_ref()
                    .map_or(0, |list| list.unknowns.len());
                let indicators = description.number_of_event_indicators.unwrap_or(0) as usize;
                Ok((states, indicators))
            }
            Backend::Fmi3(i) => i.model_exchange_sizes(),
        }
    }

    pub fn set_time(&mut self, time: f64) -> Result<Success, FmiError> {
        crate::blackbox::set_time(time);
        noted!(self, "fmi2SetTime", "fmi3SetTime", i => i.set_time(time))
    }

    pub fn set_continuous_states(&mut self, x: &[f64]) -> Result<Success, FmiError> {
        noted!(self, "fmi2SetContinuousStates", "fmi3SetContinuousStates", i => i.set_continuous_states(x))
    }

    /// States, derivatives, event indicators or nominals of a Model Exchange instance.
    pub fn get_vector(&mut self, which: MeVector, values: &mut [f64]) -> Result<Success, FmiError> {
        noted!(self, "fmi2GetDerivatives", "fmi3GetContinuousStateDerivatives", i => i.get_vector(which, values))
    }

    /// Event Mode of a Model Exchange instance (`fmi2EnterEventMode`, `fmi3EnterEventMode`).
    pub fn enter_event_mode_me(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2EnterEventMode", "fmi3EnterEventMode", i => i.enter_event_mode_me())
    }

    pub fn enter_continuous_time_mode(&mut self) -> Result<Success, FmiError> {
        noted!(self, "fmi2EnterContinuousTimeMode", "fmi3EnterContinuousTimeMode", i => i.enter_continuous_time_mode())
    }

    /// One call of the event iteration (`fmi2NewDiscreteStates`, `fmi3UpdateDiscreteStates`).
    pub fn update_discrete_states(&mut self) -> Result<EventUpdate, FmiError> {
        noted!(self, "fmi2NewDiscreteStates", "fmi3UpdateDiscreteStates", i => i.update_discrete_states())
    }

    pub fn completed_integrator_step(&mut self) -> Result<StepEnd, FmiError> {
        noted!(self, "fmi2CompletedIntegratorStep", "fmi3CompletedIntegratorStep", i => i.completed_integrator_step())
    }

    // ---- values by value reference ----

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<Success, CallError> {
        noted!(self, "fmi2SetReal", "fmi3SetFloat64", i => i.set_real(vrs, values))
    }

    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<Success, CallError> {
        noted!(self, "fmi2GetReal", "fmi3GetFloat64", i => i.get_real(vrs, values))
    }

    /// Also sets Enumeration variables.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<Success, CallError> {
        noted!(self, "fmi2SetInteger", "fmi3SetInt32", i => i.set_integer(vrs, values))
    }

    /// Also gets Enumeration variables.
    pub fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<Success, CallError> {
        noted!(self, "fmi2GetInteger", "fmi3GetInt32", i => i.get_integer(vrs, values))
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<Success, CallError> {
        noted!(self, "fmi2SetBoolean", "fmi3SetBoolean", i => i.set_boolean(vrs, values))
    }

    pub fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<Success, CallError> {
        noted!(self, "fmi2GetBoolean", "fmi3GetBoolean", i => i.get_boolean(vrs, values))
    }

    /// Booleans as C `int` values (0 is false), as a master that keeps its exchange in the
    /// FMI 2.0 representation passes them.
    pub fn set_boolean_raw(&mut self, vrs: &[u32], values: &[i32]) -> Result<Success, CallError> {
        noted!(self, "fmi2SetBoolean", "fmi3SetBoolean", i => i.set_boolean_raw(vrs, values))
    }

    /// Booleans into C `int` values, each normalised to 0 or 1 (an FMU may return any
    /// non-zero value for true), so they pass on and record as [`Self::get_boolean`]'s.
    pub fn get_boolean_raw(
        &mut self,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<Success, CallError> {
        noted!(self, "fmi2GetBoolean", "fmi3GetBoolean", i => i.get_boolean_raw(vrs, values))
    }

    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<Success, CallError> {
        noted!(self, "fmi2SetString", "fmi3SetString", i => i.set_string(vrs, values))
    }

    /// The strings are copied at once: the FMU's pointers are valid only until its next call.
    pub fn get_string(&mut self, vrs: &[u32]) -> Result<(Vec<String>, Success), CallError> {
        let mut values = vec![String::new(); vrs.len()];
        let success = self.get_string_into(vrs, &mut values)?;
        Ok((values, success))
    }

    /// [`Instance::get_string`] into existing strings, which keep their capacity: a master
    /// that reads the same strings every step allocates only when one grows.
    pub fn get_string_into(
        &mut self,
        vrs: &[u32],
        values: &mut [String],
    ) -> Result<Success, CallError> {
        noted!(self, "fmi2GetString", "fmi3GetString", i => i.get_string_into(vrs, values))
    }

    /// FMI 3.0 only: a backend that is not is an error naming `function`, the FMU not called.
    fn fmi3_values(&mut self, function: &'static str) -> Result<&mut Fmi3Instance, CallError> {
        match &mut self.backend {
            Backend::Fmi3(i) => Ok(i),
            Backend::Fmi2(i) => Err(CallError::InvalidArgument {
                function,
                instance: i.name().to_owned(),
                reason: "an FMI 2.0 FMU has no Float32, 8-, 16- or 64-bit integer, UInt32 or \
                         Binary variables"
                    .to_owned(),
            }),
        }
    }

    // The FMI 3.0 backend notes each of these calls in the black box under the function of
    // the variable's type.

    /// Sets variables of the FMI 3.0 types that travel as words ([`crate::word`]: Float32,
    /// Int8, UInt8, Int16, UInt16, UInt32, Int64, UInt64), each through its own function; a
    /// word its variable's type cannot hold is refused before the FMU is called.
    pub fn set_words(&mut self, vrs: &[u32], words: &[u64]) -> Result<Success, CallError> {
        const F: &str = "fmi3Set{Float32,Int8,...,UInt64}";
        self.fmi3_values(F)?.set_words(vrs, words)
    }

    /// Gets variables of the word types ([`Instance::set_words`]).
    pub fn get_words(&mut self, vrs: &[u32], words: &mut [u64]) -> Result<Success, CallError> {
        const F: &str = "fmi3Get{Float32,Int8,...,UInt64}";
        self.fmi3_values(F)?.get_words(vrs, words)
    }

    pub fn set_binary(&mut self, vrs: &[u32], values: &[&[u8]]) -> Result<Success, CallError> {
        self.fmi3_values("fmi3SetBinary")?.set_binary(vrs, values)
    }

    /// Binary values into existing vectors (copied at once: the FMU's pointers are valid only
    /// until its next call).
    pub fn get_binary_into(
        &mut self,
        vrs: &[u32],
        values: &mut [Vec<u8>],
    ) -> Result<Success, CallError> {
        self.fmi3_values("fmi3GetBinary")?
            .get_binary_into(vrs, values)
    }

    // ---- values by name ----

    /// The element reference of `name` if it is of a word type.
    fn word_vr(&self, name: &str) -> Result<(u32, crate::Fmi3Type), CallError> {
        let info = self.fmu.variables.get(name)?;
        match info.fmi3_type {
            Some(kind) if crate::word::is_word(kind) => Ok((info.value_reference, kind)),
            _ => Err(CallError::InvalidArgument {
                function: "fmi3Set{Float32,Int8,...,UInt64}",
                instance: self.name().to_owned(),
                reason: format!(
                    "'{name}' is {}, not one of the FMI 3.0 types that travel as words",
                    info.type_name()
                ),
            }),
        }
    }

    /// Sets a variable of a word type from its word ([`crate::word`]).
    pub fn set_word_by_name(&mut self, name: &str, word: u64) -> Result<Success, CallError> {
        let (vr, _) = self.word_vr(name)?;
        self.set_words(&[vr], &[word])
    }

    pub fn get_word_by_name(&mut self, name: &str) -> Result<u64, CallError> {
        let (vr, _) = self.word_vr(name)?;
        let mut word = [0];
        self.get_words(&[vr], &mut word)?;
        Ok(word[0])
    }

    fn vr(&self, name: &str, kind: VariableKind) -> Result<u32, CallError> {
        Ok(self.fmu.variables.value_reference(name, kind)?)
    }

    pub fn set_real_by_name(&mut self, name: &str, value: f64) -> Result<Success, CallError> {
        let vr = self.vr(name, VariableKind::Real)?;
        self.set_real(&[vr], &[value])
    }

    pub fn get_real_by_name(&mut self, name: &str) -> Result<f64, CallError> {
        let vr = self.vr(name, VariableKind::Real)?;
        let mut value = [0.0];
        self.get_real(&[vr], &mut value)?;
        Ok(value[0])
    }

    /// Sets an Integer or Enumeration variable.
    pub fn set_integer_by_name(&mut self, name: &str, value: i32) -> Result<Success, CallError> {
        let vr = self.vr(name, VariableKind::Integer)?;
        self.set_integer(&[vr], &[value])
    }

    /// Gets an Integer or Enumeration variable.
    pub fn get_integer_by_name(&mut self, name: &str) -> Result<i32, CallError> {
        let vr = self.vr(name, VariableKind::Integer)?;
        let mut value = [0];
        self.get_integer(&[vr], &mut value)?;
        Ok(value[0])
    }

    pub fn set_boolean_by_name(&mut self, name: &str, value: bool) -> Result<Success, CallError> {
        let vr = self.vr(name, VariableKind::Boolean)?;
        self.set_boolean(&[vr], &[value])
    }

    pub fn get_boolean_by_name(&mut self, name: &str) -> Result<bool, CallError> {
        let vr = self.vr(name, VariableKind::Boolean)?;
        let mut value = [false];
        self.get_boolean(&[vr], &mut value)?;
        Ok(value[0])
    }

    pub fn set_string_by_name(&mut self, name: &str, value: &str) -> Result<Success, CallError> {
        let vr = self.vr(name, VariableKind::String)?;
        self.set_string(&[vr], &[value])
    }

    pub fn get_string_by_name(&mut self, name: &str) -> Result<String, CallError> {
        let vr = self.vr(name, VariableKind::String)?;
        let (mut values, _) = self.get_string(&[vr])?;
        Ok(values.remove(0))
    }

    // ---- partial derivatives ----

    /// The continuous states and the dependencies the model description declares (for
    /// sparsity); the error names the entry that does not resolve.
    pub fn derivative_structure(&self) -> Result<crate::derivatives::Structure, String> {
        crate::derivatives::structure(&self.fmu.description)
    }

    /// Why this instance's directional (with `adjoint`, adjoint) derivatives cannot be asked
    /// for, from its FMU's capability flags; `None` when they can.
    pub fn derivative_refusal(&self, adjoint: bool) -> Option<String> {
        let fmi3 = match &self.backend {
            Backend::Fmi2(_) => None,
            Backend::Fmi3(_) => match &self.fmu.api {
                crate::loaded::Api::Fmi3(api) => Some(&api.description),
                crate::loaded::Api::Fmi2(_) => None,
            },
        };
        crate::derivatives::refusal(&self.fmu.description, fmi3, self.interface, adjoint)
    }

    /// The names of `vrs` (Real variables; a number where none has it), for messages.
    fn real_names(&self, vrs: &[u32]) -> String {
        let names: Vec<String> = vrs
            .iter()
            .map(|&vr| {
                self.fmu
                    .description
                    .model_variables
                    .variables
                    .iter()
                    .find(|v| v.value_reference == vr && v.real.is_some())
                    .map_or_else(|| format!("#{vr}"), |v| v.name.clone())
            })
            .collect();
        names.join(", ")
    }

    /// `fmi2GetDirectionalDerivative` / `fmi3GetDirectionalDerivative`: `sensitivity = J
    /// seed`, `J` the partial derivatives of `unknowns` with respect to `knowns` (value
    /// references as for gets and sets; FMI 3.0 array elements may be asked for alone).
    /// Refused, the FMU not called, unless its description declares the capability; the
    /// error names the FMU, the instance and the variables.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Success, CallError> {
        let function = named_by_version(
            self.fmi_version(),
            "fmi2GetDirectionalDerivative",
            "fmi3GetDirectionalDerivative",
        );
        self.derivative_call(function, false, unknowns, knowns, seed, sensitivity)
    }

    /// `fmi3GetAdjointDerivative`: `sensitivity = seed^T J` (`seed` over `unknowns`,
    /// `sensitivity` over `knowns`). FMI 3.0 only; refused as
    /// [`Instance::get_directional_derivative`] is.
    pub fn get_adjoint_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Success, CallError> {
        self.derivative_call(
            "fmi3GetAdjointDerivative",
            true,
            unknowns,
            knowns,
            seed,
            sensitivity,
        )
    }

    fn derivative_call(
        &mut self,
        function: &'static str,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Success, CallError> {
        // Named only for a message: a Jacobian of many columns asks often.
        let what = |instance: &Self| {
            format!(
                "the partials of ({}) with respect to ({})",
                instance.real_names(unknowns),
                instance.real_names(knowns)
            )
        };
        if let Some(reason) = self.derivative_refusal(adjoint) {
            return Err(CallError::InvalidArgument {
                function,
                instance: self.name().to_owned(),
                reason: format!("not called for {}: {reason}", what(self)),
            });
        }
        let called = match &mut self.backend {
            Backend::Fmi2(i) => {
                let _call = crate::blackbox::enter(
                    i.black_box,
                    const { crate::blackbox::function("fmi2GetDirectionalDerivative") },
                );
                i.directional_derivative(unknowns, knowns, seed, sensitivity)
            }
            Backend::Fmi3(i) => i.derivative(adjoint, unknowns, knowns, seed, sensitivity),
        };
        called.map_err(|error| {
            let what = what(self);
            match error {
                CallError::Fmi(mut fmi) => {
                    fmi.log.0.push(crate::LogMessage {
                        instance_name: fmi.instance.clone(),
                        status: crate::Status::Error,
                        version: self.fmi_version(),
                        category: "importer".into(),
                        message: format!(
                            "model '{}' failed to give {what}",
                            self.fmu.description.model_name
                        ),
                    });
                    CallError::Fmi(fmi)
                }
                CallError::InvalidArgument {
                    function,
                    instance,
                    reason,
                } => CallError::InvalidArgument {
                    function,
                    instance,
                    reason: format!("{reason} (asked for {what})"),
                },
                other => other,
            }
        })
    }

    // ---- FMU state ----

    /// Why this instance's FMU states cannot be used (with `serialize`, also serialized),
    /// from its FMU's capability flags; `None` when they can.
    pub fn fmu_state_refusal(&self, serialize: bool) -> Option<String> {
        super::state::refusal(
            &self.fmu.description,
            self.fmi_version(),
            self.interface,
            serialize,
        )
    }

    /// The refusal of a state function the FMU does not declare, before calling it.
    fn declared(&self, function: &'static str, serialize: bool) -> Result<(), FmiError> {
        match self.fmu_state_refusal(serialize) {
            None => Ok(()),
            Some(reason) => Err(FmiError::from_importer(
                function,
                self.name(),
                self.fmi_version(),
                format!("not called: {reason}"),
            )),
        }
    }

    /// `fmi2GetFMUstate` / `fmi3GetFMUState` into a new state.
    pub fn get_fmu_state(&mut self) -> Result<FmuState, FmiError> {
        self.declared(
            named_by_version(self.fmi_version(), "fmi2GetFMUstate", "fmi3GetFMUState"),
            false,
        )?;
        both!(self, i => i.get_fmu_state())
    }

    /// `fmi2GetFMUstate` / `fmi3GetFMUState` overwriting an existing state, without a new
    /// allocation.
    pub fn update_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        both!(self, i => i.update_fmu_state(state))
    }

    /// `fmi2SetFMUstate` / `fmi3SetFMUState`: continue from a saved state. FMI 3.0: in the
    /// mode the state was saved in.
    pub fn set_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        noted!(self, "fmi2SetFMUstate", "fmi3SetFMUState", i => i.set_fmu_state(state))
    }

    /// `fmi2FreeFMUstate` / `fmi3FreeFMUState`.
    pub fn free_fmu_state(&mut self, state: FmuState) -> Result<Success, CallError> {
        both!(self, i => i.free_fmu_state(state))
    }

    /// `fmi2SerializedFMUstateSize` + `fmi2SerializeFMUstate` (the FMU's bytes); FMI 3.0:
    /// the importer's record of the instance's mode, then the FMU's bytes
    /// (`fmi3/instance/fmu_state.rs`), which only [`Instance::deserialize_fmu_state`] of an
    /// FMI 3.0 instance reads.
    pub fn serialize_fmu_state(&mut self, state: &FmuState) -> Result<Vec<u8>, CallError> {
        self.declared(
            named_by_version(
                self.fmi_version(),
                "fmi2SerializeFMUstate",
                "fmi3SerializeFMUState",
            ),
            true,
        )?;
        both!(self, i => i.serialize_fmu_state(state))
    }

    /// `fmi2DeSerializeFMUstate` / `fmi3DeserializeFMUState` into a new state.
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, FmiError> {
        self.declared(
            named_by_version(
                self.fmi_version(),
                "fmi2DeSerializeFMUstate",
                "fmi3DeserializeFMUState",
            ),
            true,
        )?;
        noted!(self, "fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState", i => i.deserialize_fmu_state(bytes))
    }
}

fn named_by_version(version: FmiVersion, fmi2: &'static str, fmi3: &'static str) -> &'static str {
    match version {
        FmiVersion::Fmi2 => fmi2,
        FmiVersion::Fmi3 => fmi3,
    }
}
