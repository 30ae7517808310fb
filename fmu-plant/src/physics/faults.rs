//! Faults a scenario can throw mid-flight, as tunable parameters: an RCS thruster whose valve
//! sticks closed or open, and a loss of main-engine thrust (`Engines::health`). They change
//! what the actuators deliver, never what the GNC commands or knows.
use super::thrusters::THRUSTER_COUNT;
use serde::{Deserialize, Serialize};

/// How a stuck thruster's valve failed (FMI Enumeration `RcsStuckMode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RcsStuckMode {
    /// Fails closed: no force, whatever the command.
    Off = 1,
    /// Fails open: full force over every step, commanded or not.
    On = 2,
}

/// One RCS thruster stuck off or on (thruster model).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RcsStuck {
    /// The thruster, 1..=8 as in docs/rcs-layout.md; 0: none.
    pub thruster: i32,
    /// An `RcsStuckMode` as its integer.
    pub mode: i32,
}

impl Default for RcsStuck {
    fn default() -> Self {
        Self {
            thruster: 0,
            mode: RcsStuckMode::Off as i32,
        }
    }
}

impl RcsStuck {
    /// The stuck thruster's index (0-based) and mode; `None` when no thruster is stuck.
    /// An index or mode outside its range counts as none (the setters refuse them; a
    /// restored FMU state is checked by [`RcsStuck::check`]).
    pub fn fault(&self) -> Option<(usize, RcsStuckMode)> {
        let k = usize::try_from(self.thruster).ok()?.checked_sub(1)?;
        let mode = match self.mode {
            1 => RcsStuckMode::Off,
            2 => RcsStuckMode::On,
            _ => return None,
        };
        (k < THRUSTER_COUNT).then_some((k, mode))
    }

    /// The duties the valves act on: the commanded ones, but 0 for a thruster stuck off and
    /// 1 (the whole step) for one stuck on.
    pub fn duty(&self, commanded: &[f64; THRUSTER_COUNT]) -> [f64; THRUSTER_COUNT] {
        let mut duty = *commanded;
        if let Some((k, mode)) = self.fault() {
            duty[k] = match mode {
                RcsStuckMode::Off => 0.0,
                RcsStuckMode::On => 1.0,
            };
        }
        duty
    }

    /// Why these values are not a fault the plant can apply, naming the field.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        if !(0..=THRUSTER_COUNT as i32).contains(&self.thruster) {
            return Err((
                "rcs_stuck.thruster",
                format!("{} must be 0 (none) or a thruster 1..8", self.thruster),
            ));
        }
        if !(1..=2).contains(&self.mode) {
            return Err((
                "rcs_stuck.mode",
                format!("{} must be 1 (off) or 2 (on)", self.mode),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stuck_off_thruster_never_fires_and_a_stuck_on_one_always_does() {
        let commanded = [0.3, 0.0, 1.0, 0.5, 0.0, 0.0, 0.2, 0.0];
        let off = RcsStuck {
            thruster: 3,
            mode: RcsStuckMode::Off as i32,
        };
        let on = RcsStuck {
            thruster: 2,
            mode: RcsStuckMode::On as i32,
        };
        let mut expected = commanded;
        expected[2] = 0.0;
        assert_eq!(off.duty(&commanded), expected);
        let mut expected = commanded;
        expected[1] = 1.0;
        assert_eq!(on.duty(&commanded), expected);
        assert_eq!(RcsStuck::default().duty(&commanded), commanded);
    }

    #[test]
    fn a_thruster_or_mode_out_of_range_is_named() {
        let bad = RcsStuck {
            thruster: 9,
            mode: 1,
        };
        assert_eq!(bad.fault(), None);
        assert_eq!(bad.check().unwrap_err().0, "rcs_stuck.thruster");
        let bad = RcsStuck {
            thruster: 1,
            mode: 3,
        };
        assert_eq!(bad.check().unwrap_err().0, "rcs_stuck.mode");
    }
}
