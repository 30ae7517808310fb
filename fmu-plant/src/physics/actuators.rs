//! Main engines and RCS: saturation, optional first-order lag, and the thrust line.
//!
//! Defaults (paper Table I, ERRATA "Modelling defaults"): two engines each throttleable from
//! 360 to 800 N, i.e. 720..1600 N along body +y, off at or below 1 N; RCS torque limited per
//! axis to 2 x 58 N x 1 m = 116 N m (one couple of two 58 N thrusters at a 1 m arm).
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The throttleable main engines, fired together.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Engines {
    pub count: u32,
    pub min_thrust_per_engine_n: f64,
    pub max_thrust_per_engine_n: f64,
    /// A command at or below this total thrust switches the engines off (thrust 0).
    pub off_threshold_n: f64,
    /// First-order lag of the delivered thrust, s; 0 = none.
    pub time_constant_s: f64,
    /// Delivered over commanded thrust once the throttle limits apply: a thrust-level error
    /// (engine performance, a miscalibrated throttle) the GNC does not know. 1 = nominal.
    pub thrust_scale: f64,
    /// The fraction of the thrust the engines still deliver, in [0, 1]: a fault thrown during
    /// the run (0.5: one of two engines lost, as SLIM's). 1 = healthy.
    pub health: f64,
}

impl Engines {
    /// Total thrust the engines deliver in steady state for a command, in N: the command
    /// within the throttle range, times the thrust level.
    #[inline]
    pub fn saturate(&self, thrust_cmd_n: f64) -> f64 {
        if thrust_cmd_n <= self.off_threshold_n {
            return 0.0;
        }
        let n = f64::from(self.count);
        // max/min rather than clamp: clamp panics on crossed bounds, and a restored FMU state
        // carries parameters that initialization never validated.
        thrust_cmd_n
            .max(n * self.min_thrust_per_engine_n)
            .min(n * self.max_thrust_per_engine_n)
            * self.thrust_scale
            * self.health
    }
}

/// The reaction control system, as a per-axis torque limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rcs {
    pub thruster_force_n: f64,
    pub moment_arm_m: f64,
    /// First-order lag of the delivered torque, s; 0 = none.
    pub time_constant_s: f64,
}

impl Rcs {
    /// Per-axis torque limit: one couple of two thrusters at the moment arm, in N m.
    #[inline]
    pub fn torque_limit_nm(&self) -> f64 {
        2.0 * self.thruster_force_n * self.moment_arm_m
    }

    /// Torque delivered in steady state for a command, each axis clamped independently.
    pub fn saturate(&self, torque_cmd_body_nm: &Vector3<f64>) -> Vector3<f64> {
        let limit = self.torque_limit_nm();
        // max/min rather than clamp: never panics on a negative limit from a restored state.
        torque_cmd_body_nm.map(|t| t.max(-limit).min(limit))
    }
}

/// Where and in which direction the engines push, for misalignment studies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThrustLine {
    /// Angle between the thrust direction and body +y, rad.
    pub misalignment_rad: f64,
    /// Direction of the tilt in the body x-z plane, measured from +x towards +z, rad.
    pub misalignment_azimuth_rad: f64,
    /// Point of application of the thrust relative to the centre of mass, body axes, m.
    pub point_body_m: Vector3<f64>,
}

impl ThrustLine {
    /// Unit thrust direction in body axes.
    pub fn direction_body(&self) -> Vector3<f64> {
        let (s, c) = libm::sincos(self.misalignment_rad);
        let (sa, ca) = libm::sincos(self.misalignment_azimuth_rad);
        Vector3::new(s * ca, c, s * sa)
    }

    /// Engine torque about the centre of mass for a thrust magnitude, body axes, N m.
    #[inline]
    pub fn torque_body_nm(&self, direction_body: &Vector3<f64>, thrust_n: f64) -> Vector3<f64> {
        self.point_body_m.cross(&(direction_body * thrust_n))
    }
}

/// Time derivative of a first-order lag `x' = (target - x) / tau`; 0 when there is no lag
/// (`tau == 0`: the output is then the target itself, see `lagged_or_direct`).
#[inline]
pub fn lag_rate(target: f64, current: f64, time_constant_s: f64) -> f64 {
    if time_constant_s > 0.0 {
        (target - current) / time_constant_s
    } else {
        0.0
    }
}

/// The delivered value: the lag state, or the target when the lag is disabled.
#[inline]
pub fn lagged_or_direct(target: f64, lag_state: f64, time_constant_s: f64) -> f64 {
    if time_constant_s > 0.0 {
        lag_state
    } else {
        target
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    fn engines() -> Engines {
        Engines {
            count: 2,
            min_thrust_per_engine_n: 360.0,
            max_thrust_per_engine_n: 800.0,
            thrust_scale: 1.0,
            health: 1.0,
            off_threshold_n: 1.0,
            time_constant_s: 0.0,
        }
    }

    #[test]
    fn the_thrust_level_scales_what_the_throttle_range_allows() {
        let nominal = engines();
        let high = Engines {
            thrust_scale: 1.05,
            health: 1.0,
            ..nominal
        };
        // Within the range, at the limits, and off.
        for (cmd, expected) in [
            (1000.0, 1050.0),
            (5000.0, 1680.0),
            (100.0, 756.0),
            (0.5, 0.0),
        ] {
            assert!(
                (high.saturate(cmd) - expected).abs() < 1e-9,
                "command {cmd}"
            );
        }
        // Nominal is the unscaled command to the bit.
        assert_eq!(nominal.saturate(1234.5678), 1234.5678);
    }

    #[test]
    fn engine_command_is_cut_below_the_threshold_and_clamped_to_the_throttle_range() {
        let e = engines();
        for (cmd, expected) in [
            (-50.0, 0.0),
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0 + 1e-9, 720.0),
            (500.0, 720.0),
            (1000.0, 1000.0),
            (1600.0, 1600.0),
            (5000.0, 1600.0),
        ] {
            assert_eq!(e.saturate(cmd), expected, "command {cmd}");
        }
    }

    #[test]
    fn rcs_saturates_each_axis_independently_at_116_nm() {
        let rcs = Rcs {
            thruster_force_n: 58.0,
            moment_arm_m: 1.0,
            time_constant_s: 0.0,
        };
        assert_eq!(rcs.torque_limit_nm(), 116.0);
        let sat = rcs.saturate(&Vector3::new(500.0, -20.0, -300.0));
        assert_eq!(sat, Vector3::new(116.0, -20.0, -116.0));
    }

    #[test]
    fn misaligned_thrust_through_an_offset_point_gives_the_lever_arm_torque() {
        // 1 deg tilt towards +x, nozzle 1.5 m below the centre of mass:
        // (0, -1.5, 0) x (F sin d, F cos d, 0) = (0, 0, 1.5 F sin d).
        let line = ThrustLine {
            misalignment_rad: 1f64.to_radians(),
            misalignment_azimuth_rad: 0.0,
            point_body_m: Vector3::new(0.0, -1.5, 0.0),
        };
        let d = line.direction_body();
        assert!((d.norm() - 1.0).abs() < 1e-15);
        let tau = line.torque_body_nm(&d, 1000.0);
        let expected_z = 1.5 * 1000.0 * 1f64.to_radians().sin();
        assert!(
            (tau - Vector3::new(0.0, 0.0, expected_z)).norm() < 1e-12,
            "{tau}"
        );
        // An aligned thrust through a point on the axis gives no torque.
        let aligned = ThrustLine {
            misalignment_rad: 0.0,
            ..line
        };
        assert_eq!(
            aligned.torque_body_nm(&aligned.direction_body(), 1000.0),
            Vector3::zeros()
        );
    }
}
