//! Whether the vehicle the parameters describe can do what the GNC asks of it: checks of the
//! parameters against each other and against what the plant reports, each with the numbers a
//! user needs to fix it. Pure: the caller decides when to ask and reports each finding once.
use serde::{Deserialize, Serialize};

/// The attitude error at which a PD loop of bandwidth `omega_c` on inertia `I` asks for the
/// whole torque limit (`I omega_c^2 theta = tau_max`) must be at least this: below it the loop
/// is saturated at any error a navigation solution and a reference step produce, and it
/// flies bang-bang at the torque limit, not at its bandwidth. 0.5 deg: the paper's vehicle
/// keeps 1.7 deg, a 1,000 kg vehicle with 1,000 kg m2 and 200 N m keeps 1.2 deg.
pub const MIN_LINEAR_RANGE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The tilt error beyond which the thrust pushes away from where guidance wants it.
pub const MAX_TILT_ERROR_RAD: f64 = std::f64::consts::FRAC_PI_2;

/// Weight above the highest thrust: the vehicle cannot hover.
pub fn cannot_hover(mass_kg: f64, gravity_mps2: f64, thrust_max_n: f64) -> Option<String> {
    let weight_n = mass_kg * gravity_mps2;
    (weight_n > thrust_max_n).then(|| {
        format!(
            "weight {weight_n} N (mass {mass_kg} kg x gravity {gravity_mps2} m/s2) is above \
             thrust_max = {thrust_max_n} N: the vehicle cannot hover and will fall; set \
             thrust_max to the plant's full thrust (and gravity, mass to the plant's)"
        )
    })
}

/// An axis whose torque limit is reached at an attitude error below
/// [`MIN_LINEAR_RANGE_RAD`] for the commanded bandwidth and declared inertia.
pub fn bandwidth_out_of_reach(
    control_bandwidth_hz: f64,
    inertia_body_kgm2: [f64; 3],
    torque_limit_body_nm: [f64; 3],
) -> Option<String> {
    let omega_c = 2.0 * std::f64::consts::PI * control_bandwidth_hz;
    let axes = ["x", "y", "z"];
    for k in 0..3 {
        let stiffness = inertia_body_kgm2[k] * omega_c * omega_c;
        let linear_range_rad = torque_limit_body_nm[k] / stiffness;
        if linear_range_rad < MIN_LINEAR_RANGE_RAD {
            // The bandwidth at which this axis keeps the minimum linear range.
            let reachable_hz =
                (torque_limit_body_nm[k] / (inertia_body_kgm2[k] * MIN_LINEAR_RANGE_RAD)).sqrt()
                    / (2.0 * std::f64::consts::PI);
            return Some(format!(
                "control_bandwidth = {control_bandwidth_hz} Hz asks body {} for I omega_c^2 = \
                 {stiffness:.4e} N m/rad (inertia_body = {} kg m2): its torque limit {} N m is \
                 reached at {:.3} deg of error, so the loop flies at the torque limit, not at \
                 its bandwidth; at most {reachable_hz:.3} Hz keeps {:.1} deg; check inertia_body \
                 (kg m2) and torque_limit_body against the plant's",
                axes[k],
                inertia_body_kgm2[k],
                torque_limit_body_nm[k],
                linear_range_rad.to_degrees(),
                MIN_LINEAR_RANGE_RAD.to_degrees(),
            ));
        }
    }
    None
}

/// How long each command has sat at a limit of its range, without a break.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SaturationClock {
    /// Since when the thrust has been at `thrust_min` or `thrust_max` (`None`: it is not).
    thrust_since_s: Option<f64>,
    /// The same for any axis of the torque at its limit.
    torque_since_s: Option<f64>,
}

/// The ranges of the commands and how long one may sit at a limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    pub thrust_range_n: (f64, f64),
    pub torque_limit_body_nm: [f64; 3],
    pub time_s: f64,
    /// How close to each limit counts as at it ([`AT_LIMIT`] of the limit, at least of 1),
    /// derived once.
    thrust_closeness_n: (f64, f64),
    torque_closeness_body_nm: [f64; 3],
}

impl Limits {
    pub fn new(thrust_range_n: (f64, f64), torque_limit_body_nm: [f64; 3], time_s: f64) -> Self {
        let closeness = |limit: f64| AT_LIMIT * limit.abs().max(1.0);
        Limits {
            thrust_range_n,
            torque_limit_body_nm,
            time_s,
            thrust_closeness_n: (closeness(thrust_range_n.0), closeness(thrust_range_n.1)),
            torque_closeness_body_nm: torque_limit_body_nm.map(closeness),
        }
    }
}

/// A command pinned at a limit longer than allowed.
#[derive(Debug, Clone, PartialEq)]
pub enum Pinned {
    Thrust(String),
    Torque(String),
}

/// Relative closeness that counts as "at the limit": the GNC clamps to exactly the limit.
const AT_LIMIT: f64 = 1e-9;

impl SaturationClock {
    /// Counts the command `thrust_cmd_n`, `torque_cmd_body_nm` shown at `t_s`; `found` is
    /// given each command pinned for longer than `limits.time_s`.
    pub fn observe(
        &mut self,
        t_s: f64,
        thrust_cmd_n: f64,
        torque_cmd_body_nm: [f64; 3],
        limits: &Limits,
        ground_contact_possible: bool,
        found: &mut impl FnMut(Pinned),
    ) {
        // On the ground the gear holds the vehicle against its commands.
        if ground_contact_possible {
            *self = SaturationClock::default();
            return;
        }
        let (thrust_min_n, thrust_max_n) = limits.thrust_range_n;
        let (torque_limit_body_nm, limit_s) = (limits.torque_limit_body_nm, limits.time_s);
        let at = |value: f64, limit: f64, closeness: f64| (value - limit).abs() <= closeness;
        let at_max = |thrust_n| at(thrust_n, thrust_max_n, limits.thrust_closeness_n.1);
        // An engine switched off is a choice of guidance, not a saturation.
        let thrust_pinned = thrust_cmd_n > 1.0
            && (at_max(thrust_cmd_n)
                || at(thrust_cmd_n, thrust_min_n, limits.thrust_closeness_n.0));
        let torque_axis = (0..3).find(|&k| {
            torque_limit_body_nm[k] > 0.0
                && at(
                    torque_cmd_body_nm[k].abs(),
                    torque_limit_body_nm[k],
                    limits.torque_closeness_body_nm[k],
                )
        });
        self.thrust_since_s = if thrust_pinned {
            let since = self.thrust_since_s.unwrap_or(t_s);
            if t_s - since > limit_s {
                let which = if at_max(thrust_cmd_n) {
                    "thrust_max"
                } else {
                    "thrust_min"
                };
                found(thrust_pinned_finding(which, thrust_cmd_n, since, limit_s));
            }
            Some(since)
        } else {
            None
        };
        self.torque_since_s = match torque_axis {
            Some(k) => {
                let since = self.torque_since_s.unwrap_or(t_s);
                if t_s - since > limit_s {
                    found(torque_pinned_finding(
                        k,
                        torque_cmd_body_nm[k],
                        since,
                        limit_s,
                    ));
                }
                Some(since)
            }
            None => None,
        };
    }
}

// The findings' words, out of line: the count above runs at every sample.

#[cold]
#[inline(never)]
fn thrust_pinned_finding(which: &str, thrust_cmd_n: f64, since: f64, limit_s: f64) -> Pinned {
    Pinned::Thrust(format!(
        "thrust_cmd has been at {which} = {thrust_cmd_n} N since t = {since} s \
         (longer than saturation_time = {limit_s} s): guidance asks for more than \
         the throttle range gives; check thrust_min, thrust_max, gravity and the \
         mass against the plant's"
    ))
}

#[cold]
#[inline(never)]
fn torque_pinned_finding(axis: usize, torque_cmd_nm: f64, since: f64, limit_s: f64) -> Pinned {
    Pinned::Torque(format!(
        "torque_cmd_body has been at a torque limit (body {} at {} N m) since \
         t = {since} s (longer than saturation_time = {limit_s} s): the \
         attitude loop cannot reach its reference; check inertia_body, \
         torque_limit_body and control_bandwidth against the plant's, and the \
         attitude and rate conventions",
        ["x", "y", "z"][axis],
        torque_cmd_nm
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_above_thrust_max_is_found_with_its_numbers() {
        let found = cannot_hover(1000.0, 1.62, 1600.0).expect("1620 N > 1600 N");
        assert!(found.contains("weight 1620 N"), "{found}");
        assert!(found.contains("thrust_max = 1600 N"), "{found}");
        assert_eq!(cannot_hover(900.0, 1.62, 1600.0), None);
    }

    #[test]
    fn the_paper_vehicle_reaches_its_bandwidth_and_a_thousandfold_inertia_does_not() {
        assert_eq!(
            bandwidth_out_of_reach(0.5, [400.0, 300.0, 450.0], [116.0; 3]),
            None
        );
        assert_eq!(
            bandwidth_out_of_reach(0.5, [900.0, 700.0, 1000.0], [200.0; 3]),
            None
        );
        let found = bandwidth_out_of_reach(0.5, [400e3, 300.0, 450.0], [116.0; 3])
            .expect("a thousandfold inertia");
        assert!(found.contains("body x"), "{found}");
        assert!(found.contains("at most 0.0"), "{found}");
    }

    #[test]
    fn a_command_pinned_past_the_allowed_time_is_found_and_a_break_restarts_the_clock() {
        let mut clock = SaturationClock::default();
        let limits = Limits::new((720.0, 1600.0), [116.0; 3], 4.0);
        let mut found = Vec::new();
        for k in 0..700 {
            let t = f64::from(k) * 0.01;
            // a break at 2 s
            let thrust = if k == 200 { 1500.0 } else { 1600.0 };
            clock.observe(t, thrust, [0.0, -116.0, 0.0], &limits, false, &mut |p| {
                found.push(p)
            });
        }
        assert!(found
            .iter()
            .any(|p| matches!(p, Pinned::Torque(m) if m.contains("body y"))));
        assert!(found
            .iter()
            .any(|p| matches!(p, Pinned::Thrust(m) if m.contains("since t = 2.01"))));
        assert!(!found
            .iter()
            .any(|p| matches!(p, Pinned::Thrust(m) if m.contains("since t = 0 s"))));
        // on the ground the clocks rest
        let mut clock = SaturationClock::default();
        for k in 0..700 {
            let t = f64::from(k) * 0.01;
            clock.observe(t, 1600.0, [116.0; 3], &limits, true, &mut |p| {
                panic!("{p:?} on the ground")
            });
        }
        // an engine switched off is no saturation
        let mut clock = SaturationClock::default();
        for k in 0..700 {
            let t = f64::from(k) * 0.01;
            clock.observe(t, 0.0, [0.0; 3], &limits, false, &mut |p| {
                panic!("{p:?} with the engine off")
            });
        }
    }
}
