//! FMI 3.0 as the export core sees it: its statuses, its logger call, its variable view.
#![allow(unsafe_code)]

use crate::ffi::*;
use crate::state::Function;
use crate::variables::{Float64Slot, Index};
use fmi_export::registry::Registry;
use fmi_export::{Abi, Category, Logger, Sink, State, StateMask, Status};
use fmi_model::Model;
use std::ffi::CStr;

/// The FMI 3.0 version of the export core.
#[derive(Debug)]
pub struct Fmi3;

/// The FMI 3.0 variables of a model (one per declaration) and their lookup.
pub struct View<M: 'static> {
    pub index: Index,
    /// The Float64 declarations by row, ready for the exchange.
    pub float64: Box<[Option<Float64Slot<M>>]>,
}

/// Every live FMI 3.0 instance of this FMU.
static LIVE: Registry<Logger<Fmi3>> = Registry::new();

pub(crate) const CATEGORIES: &[Category] = &Category::ALL;

impl Abi for Fmi3 {
    const SNAPSHOT_MAGIC: [u8; 8] = crate::SNAPSHOT_MAGIC;
    const TOKEN_ARGUMENT: &'static str = "instantiationToken";
    const EXPERIMENT: &'static str = "fmi3EnterInitializationMode";
    const CATEGORIES: &'static [Category] = CATEGORIES;
    const REGISTRY: &'static Registry<Logger<Self>> = &LIVE;
    // FMI 3.0 has no StepFailed or StepCanceled (a step either succeeds or changes nothing);
    // Fatal is never restored.
    const STATES: StateMask =
        StateMask::all_but(&[State::StepFailed, State::StepCanceled, State::Fatal]);
    type CStatus = fmi3Status;
    type Callback = fmi3LogMessageCallback;
    type Function = Function;
    type View<M: Model> = View<M>;

    fn emit(
        sink: &Sink<fmi3LogMessageCallback>,
        status: Status,
        category: Category,
        message: &CStr,
    ) {
        let Some(callback) = sink.callback else {
            return;
        };
        // SAFETY: the callback was non-null at instantiation and stays callable for the
        // instance's lifetime; both strings are NUL-terminated and outlive the call.
        unsafe {
            callback(
                sink.environment,
                Self::status(status),
                category.name().as_ptr(),
                message.as_ptr(),
            );
        }
    }

    fn view<M: Model>() -> View<M> {
        View {
            index: Index::new::<M>(),
            float64: Float64Slot::table(),
        }
    }

    fn interface_uuid<M: Model>() -> uuid::Uuid {
        crate::description::interface_uuid::<M>()
    }
}
