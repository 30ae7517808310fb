//! A saved FMU state: a token for a slot of the instance that made it; and whether an FMU
//! declares that it can save its state at all.

use crate::logger::LogEnv;
use crate::model_exchange::Interface;
use crate::version::FmiVersion;
use model_description::ModelDescription;
use std::sync::Weak;

/// A saved FMU state, usable only with the instance that made it. Free it with
/// [`crate::Instance::free_fmu_state`]; states still held when the instance drops are freed then.
#[derive(Debug)]
pub struct FmuState {
    pub(crate) slot: usize,
    pub(crate) owner: Weak<LogEnv>,
}

/// Why FMU states of `description`'s `interface` cannot be got and set (with `serialize`,
/// also serialized), from its capability flags; `None` when they can. An FMU that does not
/// declare a flag cannot (both standards default it to false), and its functions for states
/// need not do anything: they are not called.
pub fn refusal(
    description: &ModelDescription,
    version: FmiVersion,
    interface: Interface,
    serialize: bool,
) -> Option<String> {
    let (get_set, serializes) = match interface {
        Interface::CoSimulation => description
            .co_simulation
            .as_ref()
            .map(|cs| (cs.can_get_and_set_fmu_state, cs.can_serialize_fmu_state)),
        // The FMI 3.0 view carries no flags of <ModelExchange>: read as undeclared.
        Interface::ModelExchange => description
            .model_exchange
            .as_ref()
            .map(|me| (me.can_get_and_set_fmu_state, me.can_serialize_fmu_state)),
    }
    .unwrap_or_default();
    let state = match version {
        FmiVersion::Fmi2 => "FMUstate",
        FmiVersion::Fmi3 => "FMUState",
    };
    let element = match interface {
        Interface::CoSimulation => "CoSimulation",
        Interface::ModelExchange => "ModelExchange",
    };
    if version == FmiVersion::Fmi3 && interface == Interface::ModelExchange {
        return Some(format!(
            "model '{}': FMU states of FMI 3.0 Model Exchange instances are not driven (the \
             importer does not read the flags of <ModelExchange>)",
            description.model_name
        ));
    }
    let missing = if get_set != Some(true) {
        format!("canGetAndSet{state}")
    } else if serialize && serializes != Some(true) {
        format!("canSerialize{state}")
    } else {
        return None;
    };
    Some(format!(
        "model '{}' does not declare {missing}=\"true\" in its <{element}> element, so its \
         state cannot be {}",
        description.model_name,
        if missing.starts_with("canSerialize") {
            "serialized"
        } else {
            "saved and restored"
        }
    ))
}
