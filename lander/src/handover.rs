//! The hover-to-descent handover of one recorded flight (`harness replay --handover`): what
//! the hover hands the descent's cubic and how far the cubic carries it.
//!
//! From rest on the vertical with start acceleration `a0` and end acceleration, velocity and
//! position zero at `tgo = T`, the cubic of the paper's eq. (3) strays
//! `a0 T^2 u^2 (1 - u)^3 / 2` (`u = s / T`), largest at `u = 2/5`: [`PEAK_FACTOR`] `a0 T^2`.
//! The flight's own start is not at rest, so beside that rule this also flies the cubic
//! open loop from the recorded state at the handover (position, velocity and the hover's
//! last command), and from the same state with `a0 = 0` (what is left without the command).
use cosim::master::Trajectory;

/// The largest of `u^2 (1 - u)^3 / 2` over [0, 1], at `u = 2/5`: `(4/25)(27/125)/2`.
pub const PEAK_FACTOR: f64 = 0.01728;

/// What the handover of a flight is made of; lengths in m, times in s, angles in deg.
#[derive(Debug, Clone, PartialEq)]
pub struct Handover {
    /// The first sample of the descent (guidance phase 2).
    pub time_s: f64,
    pub time_to_go_s: f64,
    pub hover_tilt_error_max_deg: f64,
    pub hover_tilt_error_max_at_s: f64,
    /// After this sample the hover's tilt error stays below 2 deg (to the handover).
    pub hover_tilt_error_below_2deg_from_s: f64,
    /// Horizontal position (North, East) and speed at the handover.
    pub offset_north_m: f64,
    pub offset_east_m: f64,
    pub speed_mps: f64,
    /// The hover's last horizontal command (North, East), m/s^2.
    pub a0_north_mps2: f64,
    pub a0_east_mps2: f64,
    /// The angle of the hover's last thrust command from the vertical, deg: the step of the
    /// thrust-axis reference a zero-net handover makes.
    pub a0_lean_deg: f64,
    /// The open-loop cubic from the handover state: its largest horizontal distance and where.
    pub cubic_peak_m: f64,
    pub cubic_peak_u: f64,
    /// The same with `a0 = 0`.
    pub cubic_without_a0_peak_m: f64,
    /// The largest tilt error in the descent and when (the attitude loop answering a step of
    /// the thrust-axis reference at the handover).
    pub descent_tilt_error_max_deg: f64,
    pub descent_tilt_error_max_at_s: f64,
    /// The flight's largest horizontal distance in the descent and when.
    pub observed_peak_m: f64,
    pub observed_peak_at_s: f64,
}

impl Handover {
    pub fn a0_mps2(&self) -> f64 {
        self.a0_north_mps2.hypot(self.a0_east_mps2)
    }

    /// The rule from rest: [`PEAK_FACTOR`] `|a0| T^2`.
    pub fn rule_peak_m(&self) -> f64 {
        PEAK_FACTOR * self.a0_mps2() * self.time_to_go_s * self.time_to_go_s
    }

    /// The printed rows: a label, then the value.
    pub fn rows(&self) -> Vec<(&'static str, String)> {
        let u = |t: f64| (t - self.time_s) / self.time_to_go_s;
        vec![
            ("handover (s)", format!("{:.2}", self.time_s)),
            (
                "descent time-to-go T (s)",
                format!("{:.1}", self.time_to_go_s),
            ),
            (
                "largest tilt error in the hover (deg)",
                format!("{:.1}", self.hover_tilt_error_max_deg),
            ),
            (
                "largest tilt error in the hover, at (s)",
                format!("{:.2}", self.hover_tilt_error_max_at_s),
            ),
            (
                "tilt error below 2 deg from (s)",
                format!("{:.2}", self.hover_tilt_error_below_2deg_from_s),
            ),
            (
                "North offset at the handover (m)",
                format!("{:.2}", self.offset_north_m),
            ),
            (
                "horizontal offset at the handover (m)",
                format!("{:.2}", self.offset_north_m.hypot(self.offset_east_m)),
            ),
            (
                "horizontal speed at the handover (m/s)",
                format!("{:.2}", self.speed_mps),
            ),
            (
                "hover's last command a0, North (m/s^2)",
                format!("{:.3}", self.a0_north_mps2),
            ),
            (
                "hover's last command a0, horizontal (m/s^2)",
                format!("{:.3}", self.a0_mps2()),
            ),
            (
                "lean of the hover's last command (deg)",
                format!("{:.1}", self.a0_lean_deg),
            ),
            (
                "rule 0.01728 a0 T^2 (m)",
                format!("{:.1}", self.rule_peak_m()),
            ),
            (
                "cubic from the handover state, peak (m)",
                format!("{:.1}", self.cubic_peak_m),
            ),
            (
                "cubic from the handover state, peak at u",
                format!("{:.3}", self.cubic_peak_u),
            ),
            (
                "cubic with a0 = 0, peak (m)",
                format!("{:.1}", self.cubic_without_a0_peak_m),
            ),
            (
                "largest tilt error in the descent (deg)",
                format!("{:.1}", self.descent_tilt_error_max_deg),
            ),
            (
                "largest tilt error in the descent, at (s)",
                format!("{:.2}", self.descent_tilt_error_max_at_s),
            ),
            (
                "observed descent peak (m)",
                format!("{:.1}", self.observed_peak_m),
            ),
            (
                "observed descent peak, at (s)",
                format!("{:.2}", self.observed_peak_at_s),
            ),
            (
                "observed descent peak, at u",
                format!("{:.3}", u(self.observed_peak_at_s)),
            ),
        ]
    }
}

fn column(trajectory: &Trajectory, name: &str) -> Result<Vec<f64>, String> {
    trajectory
        .column(name)
        .ok_or_else(|| format!("the flight recorded no `{name}`"))
}

/// The handover of a flight that recorded LanderGnc's `guidance_phase`, `time_to_go`,
/// `a_cmd_nue` and `tilt_error` (instance `gnc`) and the plant's `r_nue`, `v_nue` (instance
/// `plant`): the descent's first sample, its time-to-go there the cubic's `T`.
pub fn analyse(trajectory: &Trajectory) -> Result<Handover, String> {
    let times = &trajectory.times;
    let phase = column(trajectory, "gnc.guidance_phase")?;
    let at = phase
        .iter()
        .position(|&p| p == 2.0)
        .filter(|&k| k > 0)
        .ok_or("the flight has no descent after a hover (guidance_phase 2)")?;
    let time_to_go_s = column(trajectory, "gnc.time_to_go")?[at];
    let tilt = column(trajectory, "gnc.tilt_error")?;
    let (mut max_k, mut below_from) = (0, times[0]);
    for k in 0..at {
        if tilt[k] > tilt[max_k] {
            max_k = k;
        }
        if tilt[k] >= 2f64.to_radians() {
            below_from = times[(k + 1).min(at)];
        }
    }
    let [rn, re, vn, ve, an, au, ae] = [
        "plant.r_nue[1]",
        "plant.r_nue[3]",
        "plant.v_nue[1]",
        "plant.v_nue[3]",
        "gnc.a_cmd_nue[1]",
        "gnc.a_cmd_nue[2]",
        "gnc.a_cmd_nue[3]",
    ]
    .map(|name| column(trajectory, name));
    let (rn, re, vn, ve, an, au, ae) = (rn?, re?, vn?, ve?, an?, au?, ae?);
    let r0 = [rn[at], re[at]];
    let v0 = [vn[at], ve[at]];
    // The hover's last command: the sample before the descent's first.
    let a0 = [an[at - 1], ae[at - 1]];
    let (cubic_peak_m, cubic_peak_s) = cubic_peak(r0, v0, a0, time_to_go_s);
    let (cubic_without_a0_peak_m, _) = cubic_peak(r0, v0, [0.0; 2], time_to_go_s);
    let end = times.partition_point(|&t| t <= times[at] + time_to_go_s);
    let descent_tilt_k = (at..end).fold(at, |best, k| if tilt[k] > tilt[best] { k } else { best });
    let (observed_k, observed_peak_m) = (at..end)
        .map(|k| (k, rn[k].hypot(re[k])))
        .fold((at, 0.0), |best, x| if x.1 > best.1 { x } else { best });
    Ok(Handover {
        time_s: times[at],
        time_to_go_s,
        hover_tilt_error_max_deg: tilt[max_k].to_degrees(),
        hover_tilt_error_max_at_s: times[max_k],
        hover_tilt_error_below_2deg_from_s: below_from,
        offset_north_m: r0[0],
        offset_east_m: r0[1],
        speed_mps: v0[0].hypot(v0[1]),
        a0_north_mps2: a0[0],
        a0_east_mps2: a0[1],
        a0_lean_deg: a0[0].hypot(a0[1]).atan2(au[at - 1]).to_degrees(),
        cubic_peak_m,
        cubic_peak_u: cubic_peak_s / time_to_go_s,
        cubic_without_a0_peak_m,
        descent_tilt_error_max_deg: tilt[descent_tilt_k].to_degrees(),
        descent_tilt_error_max_at_s: times[descent_tilt_k],
        observed_peak_m,
        observed_peak_at_s: times[observed_k],
    })
}

/// The largest horizontal distance of the cubic from `r0`, `v0`, `a0` to rest at the origin
/// with zero acceleration after `t` (the coefficients of the paper's eq. (3) for those
/// boundary conditions, integrated term by term), and the time since its start it is reached.
pub fn cubic_peak(r0: [f64; 2], v0: [f64; 2], a0: [f64; 2], t: f64) -> (f64, f64) {
    let position = |axis: usize, s: f64| {
        let (r0, v0, a0) = (r0[axis], v0[axis], a0[axis]);
        let big_a = -a0;
        let big_b = (-v0 - a0 * t) / t;
        let big_d = (-r0 - v0 * t - a0 * 0.5 * t * t) / (t * t);
        let c = [
            a0,
            (3.0 * big_a - 24.0 * big_b + 60.0 * big_d) / t,
            (-12.0 * big_a + 84.0 * big_b - 180.0 * big_d) / (t * t),
            (10.0 * big_a - 60.0 * big_b + 120.0 * big_d) / (t * t * t),
        ];
        let mut r = r0 + v0 * s;
        for (k, c) in c.iter().enumerate() {
            let k = k as i32;
            r += c * s.powi(k + 2) / f64::from((k + 1) * (k + 2));
        }
        r
    };
    const SAMPLES: usize = 100_000;
    (0..=SAMPLES)
        .map(|i| {
            let s = t * i as f64 / SAMPLES as f64;
            (position(0, s).hypot(position(1, s)), s)
        })
        .fold((0.0, 0.0), |best, x| if x.0 > best.0 { x } else { best })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_rest_the_cubic_peaks_at_the_rule() {
        // From rest on the vertical the cubic is a0 T^2 u^2 (1 - u)^3 / 2, largest at u = 2/5
        let (peak, at) = cubic_peak([0.0; 2], [0.0; 2], [-0.8, 0.6], 130.0);
        assert!(
            (peak - PEAK_FACTOR * 1.0 * 130.0 * 130.0).abs() < 1e-6,
            "{peak}"
        );
        assert!((at / 130.0 - 0.4).abs() < 1e-4, "{at}");
        let u: f64 = 0.4;
        assert_eq!(
            PEAK_FACTOR,
            (u * u * (1.0 - u).powi(3) / 2.0 * 1e5).round() / 1e5
        );
    }

    #[test]
    fn the_cubic_ends_at_rest_on_the_vertical() {
        // A start with offset, velocity and acceleration: the peak is the start's offset or
        // more, and at the end the position is back at the origin (the peak at s = T is 0
        // only if nothing before it is larger: checked by flying r0 alone to its peak at 0)
        let (peak, at) = cubic_peak([5.0, 0.0], [0.0; 2], [0.0; 2], 130.0);
        assert_eq!((peak, at), (5.0, 0.0));
        // An initial velocity v0 alone carries v0 T u (1 - u)^3 (1 + 3u), at most (16/81) v0 T
        // at u = 1/3
        let (peak, at) = cubic_peak([0.0; 2], [0.0, 1.0], [0.0; 2], 130.0);
        assert!((peak - 16.0 / 81.0 * 130.0).abs() < 1e-6, "{peak}");
        assert!((at / 130.0 - 1.0 / 3.0).abs() < 1e-4, "{at}");
    }
}
