//! Supervision of a flight (beyond the paper): whether the vehicle the parameters describe
//! can fly the mission ([`feasibility`]) and whether the inputs move the way the GNC's own
//! conventions say they should ([`consistency`]). It observes only: the commands are the
//! controller's, bit for bit, with or without it. Each finding is reported once a run, with
//! its numbers.
pub mod consistency;
pub mod feasibility;

use consistency::{ConsistencyMonitor, MonitorSettings, Observation, Residuals};
use feasibility::{Pinned, SaturationClock};
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
    pub thrust_range_n: (f64, f64),
    pub torque_limit_body_nm: [f64; 3],
    pub saturation_time_s: f64,
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
        self.report(BANDWIDTH_BIT, bandwidth_finding)
    }

    fn report(&mut self, bit: i32, finding: Option<String>) -> Vec<String> {
        match finding {
            Some(message) if self.reported & bit == 0 => {
                self.reported |= bit;
                vec![message]
            }
            _ => Vec::new(),
        }
    }

    /// One committed sample: `o` the inputs with the command shown for them, `tilt_error_rad`
    /// the tilt error shown; the messages of the findings it raised.
    pub fn observe(
        &mut self,
        settings: &SupervisionSettings,
        o: Observation,
        tilt_error_rad: f64,
    ) -> Vec<String> {
        let mut messages = Vec::new();
        if !self.weight_checked && o.mass_kg > 0.0 && o.mass_kg.is_finite() {
            self.weight_checked = true;
            let finding = feasibility::cannot_hover(
                o.mass_kg,
                settings.monitor.gravity_mps2,
                settings.thrust_range_n.1,
            );
            messages.extend(self.report(CANNOT_HOVER_BIT, finding));
        }
        let limits = feasibility::Limits {
            thrust_range_n: settings.thrust_range_n,
            torque_limit_body_nm: settings.torque_limit_body_nm,
            time_s: settings.saturation_time_s,
        };
        for pinned in self.saturation.observe(
            o.t_s,
            o.thrust_cmd_n,
            o.torque_cmd_body_nm,
            &limits,
            o.ground_contact_possible,
        ) {
            let (bit, message) = match pinned {
                Pinned::Thrust(m) => (THRUST_PINNED_BIT, m),
                Pinned::Torque(m) => (TORQUE_PINNED_BIT, m),
            };
            messages.extend(self.report(bit, Some(message)));
        }
        let tilt = (tilt_error_rad > feasibility::MAX_TILT_ERROR_RAD).then(|| {
            format!(
                "the tilt error is {:.1} deg, beyond 90 deg: the thrust pushes away from where \
                 guidance wants it; if the vehicle is upright, check the quaternion convention \
                 (scalar first, body to NUE) and the thrust axis (body +y)",
                tilt_error_rad.to_degrees()
            )
        });
        messages.extend(self.report(TILT_BIT, tilt));
        if settings.monitor_enabled {
            messages.extend(self.consistency.observe(&settings.monitor, o));
        }
        messages
    }
}
