//! FMI 2.0 as the export core sees it: its statuses, its logger call, its variable view.
#![allow(unsafe_code)]

use crate::ffi::*;
use crate::index::VariableIndex;
use crate::state::Function;
use crate::variable::Variable;
use fmi_export::registry::Registry;
use fmi_export::{Abi, Category, Logger, Sink, State, StateMask, Status};
use fmi_model::Model;
use std::ffi::CStr;

/// The FMI 2.0 version of the export core.
#[derive(Debug)]
pub struct Fmi2;

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
    const REGISTRY: &'static Registry<Logger<Self>> = &LIVE;
    // StepCanceled is never entered (steps are synchronous); Fatal is never restored.
    const STATES: StateMask = StateMask::all_but(&[State::StepCanceled, State::Fatal]);
    type CStatus = fmi2Status;
    type Callback = fmi2CallbackLogger;
    type Function = Function;
    type View<M: Model> = View<M>;

    fn emit(sink: &Sink<fmi2CallbackLogger>, status: Status, category: Category, message: &CStr) {
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

    fn interface_uuid<M: Model>() -> uuid::Uuid {
        crate::interface_uuid::<M>()
    }
}
