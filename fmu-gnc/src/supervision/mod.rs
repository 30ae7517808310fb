//! Supervision of a flight (beyond the paper): whether the vehicle the parameters describe
//! can fly the mission ([`feasibility`]) and whether the inputs move the way the GNC's own
//! conventions say they should ([`consistency`]). It observes only: the commands are the
//! controller's, bit for bit, with or without it. Each finding is reported once a run, with
//! its numbers.
pub mod consistency;
pub mod feasibility;

use consistency::{ConsistencyMonitor, MonitorSettings, Observation, Residuals};
use feasibility::{Limits, Pinned, SaturationClock};
use nalgebra::Quaternion;
use serde::{Deserialize, Serialize};

/// Bits of the status output beyond the consistency checks' ([`consistency::ATTITUDE_BIT`]
/// and the next three).
pub const CANNOT_HOVER_BIT: i32 = 16;
pub const BANDWIDTH_BIT: i32 = 32;
pub const THRUST_PINNED_BIT: i32 = 64;
pub const TORQUE_PINNED_BIT: i32 = 128;
pub const TILT_BIT: i32 = 256;

/// What the supervision reads of the parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisionSettings {
    pub monitor: MonitorSettings,
    /// The input consistency monitor is on.
    pub monitor_enabled: bool,
    /// The commands' ranges and how long one may sit at a limit.
    pub limits: Limits,
}

/// The supervision's memory over a run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Supervisor {
    consistency: ConsistencyMonitor,
    saturation: SaturationClock,
    /// Bits of the feasibility findings reported in this run.
    reported: i32,
    /// Whether the weight has been compared with thrust_max (at the first usable sample).
    weight_checked: bool,
}

impl Supervisor {
    /// Every finding raised in this run: the consistency checks' bits and the feasibility
    /// bits above.
    pub fn status(&self) -> i32 {
        self.consistency.raised | self.reported
    }

    pub fn residuals(&self) -> Residuals {
        self.consistency.residuals
    }

    /// A finding of the parameters alone, reported once (at the end of initialization).
    pub fn parameters(&mut self, bandwidth_finding: Option<String>) -> Vec<String> {
        match bandwidth_finding {
            Some(message) if first(&mut self.reported, BANDWIDTH_BIT) => vec![message],
            _ => Vec::new(),
        }
    }

    /// Where the caller writes the observation of the next committed sample (the inputs
    /// with the command shown for them) before [`Self::observe`] takes it.
    pub fn incoming(&mut self) -> &mut Observation {
        self.consistency.incoming()
    }

    /// One committed sample, written to [`Self::incoming`]: `attitude` its quaternion
    /// normalised as given if the caller has it, `tilt_error_rad` the tilt error shown;
    /// `report` is given the message of each finding it raised.
    pub fn observe(
        &mut self,
        settings: &SupervisionSettings,
        attitude: Option<Quaternion<f64>>,
        tilt_error_rad: f64,
        report: &mut impl FnMut(String),
    ) {
        let o = self.consistency.next_observation();
        if !self.weight_checked && o.mass_kg > 0.0 && o.mass_kg.is_finite() {
            self.weight_checked = true;
            let finding = feasibility::cannot_hover(
                o.mass_kg,
                settings.monitor.gravity_mps2,
                settings.limits.thrust_range_n.1,
            );
            if let Some(message) = finding {
                if first(&mut self.reported, CANNOT_HOVER_BIT) {
                    report(message);
                }
            }
        }
        let reported = &mut self.reported;
        self.saturation.observe(
            o.t_s,
            o.thrust_cmd_n,
            o.torque_cmd_body_nm,
            &settings.limits,
            o.ground_contact_possible,
            &mut |pinned| {
                let (bit, message) = match pinned {
                    Pinned::Thrust(m) => (THRUST_PINNED_BIT, m),
                    Pinned::Torque(m) => (TORQUE_PINNED_BIT, m),
                };
                if first(reported, bit) {
                    report(message);
                }
            },
        );
        if tilt_error_rad > feasibility::MAX_TILT_ERROR_RAD && first(&mut self.reported, TILT_BIT) {
            report(format!(
                "the tilt error is {:.1} deg, beyond 90 deg: the thrust pushes away from where \
                 guidance wants it; if the vehicle is upright, check the quaternion convention \
                 (scalar first, body to NUE) and the thrust axis (body +y)",
                tilt_error_rad.to_degrees()
            ));
        }
        if settings.monitor_enabled {
            self.consistency
                .observe(&settings.monitor, attitude, report);
        }
    }
}

/// Marks the finding of `bit` reported; whether it is its first time (each finding is
/// reported once a run).
fn first(reported: &mut i32, bit: i32) -> bool {
    let first = *reported & bit == 0;
    *reported |= bit;
    first
}
