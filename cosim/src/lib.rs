//! A co-simulation master for FMUs loaded by `fmi-import`: systems described in TOML or in
//! an SSP package ([`system`]), the master that connects and steps them with a chosen ordering
//! and exchange convention ([`master`]), requirements written as temporal formulas over the
//! recorded signals ([`requirements`]), result files ([`results`]) and the reference results an
//! FMU carries (FMI-LS-REF, [`reference`]). Nothing here knows
//! what the FMUs model.
#![deny(unsafe_code)]

mod abnormal;
mod limits;
pub mod linear;
pub mod master;
pub mod memory;
pub mod reference;
pub mod requirements;
pub mod results;
pub mod suggest;
pub mod supervise;
pub mod system;
