//! FMI 2.0 as the export core sees it: its statuses, its logger call, its variable view.
#![allow(unsafe_code)]

use crate::ffi::*;
use crate::index::VariableIndex;
use crate::state::Function;
use crate::variable::Variable;
use fmi_export::{Abi, Category, Logger, State, StateMask, Status};
use fmi_model::registry::Registry;
use fmi_model::Model;
use std::ffi::{CStr, CString};

/// The FMI 2.0 version of the export core.
#[derive(Debug)]
pub struct Fmi2;

/// The copied `fmi2CallbackFunctions.logger`, its environment and the instance name (FMI
/// 2.0's logger takes the name with every message).
#[derive(Debug, Clone)]
pub struct Sink {
    pub callback: fmi2CallbackLogger,
    pub environment: fmi2ComponentEnvironment,
    pub instance_name: CString,
}

// SAFETY: the environment pointer is only handed back to the master's logger, never
// dereferenced by us; FMI 2.0 lets the master drive an instance from any thread (one
// thread at a time), so the master must accept its logger being called from that thread.
unsafe impl Send for Sink {}

/// The FMI 2.0 scalars of a model and their lookup.
pub struct View<M: 'static> {
    pub table: Box<[Variable<M>]>,
    pub index: VariableIndex<M>,
}

/// Every live FMI 2.0 instance of this FMU.
static LIVE: Registry<Logger<Fmi2>> = Registry::new();

/// The categories of an FMI 2.0 model description (events are Model Exchange events of the
/// FMI 3.0 layer and are logged as status messages here).
pub(crate) const CATEGORIES: &[Category] = &[
    Category::StatusOk,
    Category::StatusWarning,
    Category::StatusDiscard,
    Category::StatusError,
    Category::StatusFatal,
    Category::Calls,
];

impl Abi for Fmi2 {
    const SNAPSHOT_MAGIC: [u8; 8] = crate::SNAPSHOT_MAGIC;
    const TOKEN_ARGUMENT: &'static str = "fmuGUID";
    const EXPERIMENT: &'static str = "fmi2SetupExperiment";
    const CATEGORIES: &'static [Category] = CATEGORIES;
    // StepCanceled is never entered (steps are synchronous); Fatal is never restored.
    const STATES: StateMask = StateMask::of(&[
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::Terminated,
        State::Error,
        State::EventMode,
        State::ContinuousTimeMode,
    ]);
    type CStatus = fmi2Status;
    type CByte = fmi2Byte;
    type Function = Function;
    type Sink = Sink;
    type View<M: Model> = View<M>;

    #[inline(always)]
    fn status(status: Status) -> fmi2Status {
        fmi2Status(status.code())
    }

    fn emit(sink: &Sink, status: Status, category: Category, message: &CStr) {
        let Some(callback) = sink.callback else {
            return;
        };
        // SAFETY: the callback was non-null at instantiation and the master promises it
        // stays callable for the instance's lifetime; all strings are NUL-terminated and
        // outlive the call. The fixed "%s" format means no master ever interprets our text.
        unsafe {
            callback(
                sink.environment,
                sink.instance_name.as_ptr(),
                Self::status(status),
                category.name().as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }

    fn view<M: Model>() -> View<M> {
        let table = crate::variables::<M>().into_boxed_slice();
        View {
            index: VariableIndex::new(&table),
            table,
        }
    }

    #[inline(always)]
    fn registry() -> &'static Registry<Logger<Fmi2>> {
        &LIVE
    }

    fn interface_uuid<M: Model>() -> uuid::Uuid {
        crate::interface_uuid::<M>()
    }
}
