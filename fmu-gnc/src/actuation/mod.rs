//! Thruster mode of the RCS: a commanded torque becomes eight duty cycles.
//!
//! * [`allocation`]: torque -> non-negative thrust of each thruster, on the thruster geometry.
//! * [`pwpf`]: thrust fraction -> on-time of each thruster over the coming period
//!   (pulse-width pulse-frequency modulation).
pub mod allocation;
pub mod pwpf;

pub use allocation::THRUSTER_COUNT;

use allocation::Allocator;
use nalgebra::Vector3;
use pwpf::{Pwpf, PwpfSettings};
use serde::{Deserialize, Serialize};

/// How the RCS is commanded; exchanged as the Enumeration parameter `rcs_model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RcsModel {
    /// A torque per axis (`torque_cmd_body`), the paper's model.
    Torque = 1,
    /// Eight thrusters: allocation and PWPF give `rcs_duty`.
    Thrusters = 2,
}

impl RcsModel {
    pub fn from_index(value: i32) -> Option<Self> {
        match value {
            1 => Some(Self::Torque),
            2 => Some(Self::Thrusters),
            _ => None,
        }
    }
}

/// The eight modulators: the memory of the thruster chain.
pub type PwpfBank = [Pwpf; THRUSTER_COUNT];

/// The duty of each thruster over the coming period of `period_s` for a commanded torque,
/// and the modulators' state after that period.
pub fn duties(
    allocator: &Allocator,
    settings: &PwpfSettings,
    bank: &PwpfBank,
    torque_cmd_body_nm: &Vector3<f64>,
    tilt_first: bool,
    period_s: f64,
) -> ([f64; THRUSTER_COUNT], PwpfBank) {
    let demand = if tilt_first {
        allocator.allocate_tilt_first(torque_cmd_body_nm)
    } else {
        allocator.allocate(torque_cmd_body_nm)
    };
    let mut next = *bank;
    let duty = std::array::from_fn(|k| next[k].step(settings, demand[k], period_s) / period_s);
    (duty, next)
}
