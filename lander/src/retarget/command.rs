//! The retarget a scenario commands (LanderGnc's `retarget_time`, `retarget_site_nue`) and
//! the divert's figures of merit: overshoot past the new site, final error, peak tilt,
//! settling time (docs/retarget.md). Read by the scenarios (where a flight should end) and
//! the metrics, below the flights that compare the laws on it.
use cosim::master::Trajectory;
use cosim::system::{ParamValue, SystemDescription};

/// Distance from the site within which the divert counts as settled (m).
pub const SETTLE_RADIUS_M: f64 = 1.0;

/// What the scenario commands: when (s after the start) and where to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RetargetCommand {
    pub time_s: f64,
    pub site_nue: [f64; 3],
}

/// A real (or integer) parameter the scenario sets on its `gnc` instance.
pub(crate) fn real(system: &SystemDescription, name: &str) -> Option<f64> {
    let gnc = system.instance("gnc")?;
    gnc.parameters.iter().find_map(|(n, v)| match v {
        ParamValue::Real(x) if n == name => Some(*x),
        ParamValue::Integer(x) if n == name => Some(*x as f64),
        _ => None,
    })
}

impl RetargetCommand {
    /// The retarget a scenario sets on its `gnc` instance (the site's elements default to
    /// LanderGnc's start values, 0, 150, 0 m); an error when it sets none.
    pub fn of(system: &SystemDescription) -> anyhow::Result<Self> {
        let time_s = real(system, "retarget_time")
            .filter(|t| *t >= 0.0)
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "scenario '{}' commands no retarget: set gnc.retarget_time (>= 0 s) and \
                 gnc.retarget_site_nue[1..3]",
                    system.name
                )
            })?;
        let default = [0.0, 150.0, 0.0];
        let mut site_nue = default;
        for (k, x) in site_nue.iter_mut().enumerate() {
            if let Some(value) = real(system, &format!("retarget_site_nue[{}]", k + 1)) {
                *x = value;
            }
        }
        Ok(Self { time_s, site_nue })
    }
}

/// The divert's figures of merit, from the command on.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DivertMetrics {
    /// Largest horizontal distance past the site along the divert (from the position at the
    /// command toward the site); 0 when the lander never passes it (m).
    pub overshoot_m: f64,
    /// Largest horizontal distance off the line from the position at the command to the site (m).
    pub cross_track_m: f64,
    /// |r - site| at the end of the run (m), and its horizontal part.
    pub final_error_m: f64,
    pub final_horizontal_error_m: f64,
    /// Largest tilt of the body thrust axis from vertical (deg).
    pub peak_tilt_deg: f64,
    /// Largest angle between the thrust axis and the commanded thrust direction (deg).
    pub peak_tilt_error_deg: f64,
    /// From the command to the last time the lander was farther than [`SETTLE_RADIUS_M`] from
    /// the site (s); NaN when it is not within it at the end of the run.
    pub settle_time_s: f64,
    pub min_altitude_m: f64,
    pub max_altitude_m: f64,
}

fn columns(trajectory: &Trajectory, names: &[&str]) -> anyhow::Result<Vec<Vec<f64>>> {
    names
        .iter()
        .map(|n| {
            trajectory
                .column(n)
                .ok_or_else(|| anyhow::anyhow!("the trajectory has no column {n}"))
        })
        .collect()
}

/// The divert's metrics of one flight.
pub fn divert_metrics(
    trajectory: &Trajectory,
    command: &RetargetCommand,
) -> anyhow::Result<DivertMetrics> {
    let c = columns(
        trajectory,
        &[
            "plant.r_nue[1]",
            "plant.r_nue[2]",
            "plant.r_nue[3]",
            "plant.q_body_to_nue[1]",
            "plant.q_body_to_nue[2]",
            "plant.q_body_to_nue[3]",
            "plant.q_body_to_nue[4]",
            "gnc.tilt_error",
        ],
    )?;
    let [sn, su, se] = command.site_nue;
    let after: Vec<usize> = (0..trajectory.len())
        .filter(|&k| trajectory.times[k] >= command.time_s - 1e-9)
        .collect();
    let first = *after.first().ok_or_else(|| {
        anyhow::anyhow!("the run ends before the retarget at {} s", command.time_s)
    })?;
    // The divert's direction, horizontal, from the position at the command.
    let (dn, de) = (sn - c[0][first], se - c[2][first]);
    let length = dn.hypot(de);
    let (un, ue) = if length > 0.0 {
        (dn / length, de / length)
    } else {
        (0.0, 0.0)
    };
    let mut m = DivertMetrics {
        overshoot_m: 0.0,
        cross_track_m: 0.0,
        final_error_m: f64::NAN,
        final_horizontal_error_m: f64::NAN,
        peak_tilt_deg: 0.0,
        peak_tilt_error_deg: 0.0,
        settle_time_s: f64::NAN,
        min_altitude_m: f64::INFINITY,
        max_altitude_m: f64::NEG_INFINITY,
    };
    let mut last_outside = None;
    for &k in &after {
        let (en, eu, ee) = (c[0][k] - sn, c[1][k] - su, c[2][k] - se);
        let along = en * un + ee * ue;
        m.overshoot_m = m
            .overshoot_m
            .max(if length > 0.0 { along } else { en.hypot(ee) });
        m.cross_track_m = m.cross_track_m.max((en * ue - ee * un).abs());
        // Body +y in NUE: its Up component is 1 - 2 (x^2 + z^2), scalar first.
        let (x, z) = (c[4][k], c[6][k]);
        let up = 1.0 - 2.0 * (x * x + z * z);
        m.peak_tilt_deg = m.peak_tilt_deg.max(up.clamp(-1.0, 1.0).acos().to_degrees());
        m.peak_tilt_error_deg = m.peak_tilt_error_deg.max(c[7][k].to_degrees());
        m.min_altitude_m = m.min_altitude_m.min(c[1][k]);
        m.max_altitude_m = m.max_altitude_m.max(c[1][k]);
        let error = (en * en + eu * eu + ee * ee).sqrt();
        if error > SETTLE_RADIUS_M {
            last_outside = Some(k);
        }
        m.final_error_m = error;
        m.final_horizontal_error_m = en.hypot(ee);
    }
    m.settle_time_s = match last_outside {
        None => 0.0,
        Some(k) if k == *after.last().unwrap() => f64::NAN,
        Some(k) => trajectory.times[k + 1] - command.time_s,
    };
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A trajectory of the columns `divert_metrics` reads, upright, along `north(t)`.
    fn straight(north: impl Fn(f64) -> f64, end_s: f64) -> Trajectory {
        let names = [
            "plant.r_nue[1]",
            "plant.r_nue[2]",
            "plant.r_nue[3]",
            "plant.q_body_to_nue[1]",
            "plant.q_body_to_nue[2]",
            "plant.q_body_to_nue[3]",
            "plant.q_body_to_nue[4]",
            "gnc.tilt_error",
        ];
        let mut t = Trajectory {
            names: names.iter().map(|s| s.to_string()).collect(),
            ..Default::default()
        };
        let steps = (end_s * 10.0) as usize;
        for k in 0..=steps {
            let time = k as f64 * 0.1;
            t.times.push(time);
            t.values
                .extend([north(time), 150.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
        }
        t
    }

    const COMMAND: RetargetCommand = RetargetCommand {
        time_s: 10.0,
        site_nue: [30.0, 150.0, 0.0],
    };

    #[test]
    fn a_flight_that_passes_the_site_and_comes_back_shows_its_overshoot_and_settling() {
        // GIVEN a lander at the origin until 10 s, then 30 m North with a 5 m overshoot at
        // 20 s, back on the site from 30 s
        let north = |t: f64| {
            if t < 10.0 {
                0.0
            } else if t < 20.0 {
                3.5 * (t - 10.0)
            } else if t < 30.0 {
                35.0 - 0.5 * (t - 20.0)
            } else {
                30.0
            }
        };
        let m = divert_metrics(&straight(north, 60.0), &COMMAND).unwrap();
        // THEN the overshoot is 5 m, and it settles within 1 m of the site at 28 s (back at
        // 31 m North at 0.5 m/s), 18 s after the command
        assert!((m.overshoot_m - 5.0).abs() < 1e-9, "{m:?}");
        assert!((m.settle_time_s - 18.0).abs() < 1e-9, "{m:?}");
        assert_eq!(m.final_error_m, 0.0);
        assert_eq!(m.cross_track_m, 0.0);
        assert_eq!(m.peak_tilt_deg, 0.0);
    }

    #[test]
    fn a_flight_that_never_arrives_never_settles() {
        let m = divert_metrics(&straight(|t| (t - 10.0).max(0.0), 25.0), &COMMAND).unwrap();
        assert!(m.settle_time_s.is_nan());
        assert_eq!(m.overshoot_m, 0.0, "it never passes the site");
        assert!((m.final_error_m - 15.0).abs() < 1e-9);
    }
}
