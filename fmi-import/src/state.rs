//! A saved FMU state: a token for a slot of the instance that made it.

use crate::logger::LogEnv;
use std::sync::Weak;

/// A saved FMU state, usable only with the instance that made it. Free it with
/// [`crate::Instance::free_fmu_state`]; states still held when the instance drops are freed then.
#[derive(Debug)]
pub struct FmuState {
    pub(crate) slot: usize,
    pub(crate) owner: Weak<LogEnv>,
}
