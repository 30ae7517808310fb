//! The verdict on a run: completed, landed inside the touchdown envelope, hard landing (each
//! broken limit and by how much), stopped for another reason, or error; and the process exit
//! code that carries it.
//!
//! Exit codes of `harness run`, `harness paper` and `harness monte-carlo`:
//! - [`EXIT_OK`] (0): every run ended as its scenario expects;
//! - [`EXIT_ERROR`] (1): the harness could not run (bad input, an FMU error); clap's usage
//!   errors keep their own code 2;
//! - [`EXIT_FAILED_VERDICT`] (3): the runs were flown, and at least one did not end as its
//!   scenario expects (hard landing, touchdown in a scenario that expects a hover, ...).
pub mod envelope;

pub use envelope::{Envelope, Expect, Spec};

use cosim::master::{RunEnd, Trajectory};
use std::fmt;

pub const EXIT_OK: i32 = 0;
pub const EXIT_ERROR: i32 = 1;
pub const EXIT_FAILED_VERDICT: i32 = 3;

/// The plant's state at touchdown, as the plant reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touchdown {
    pub time_s: f64,
    /// Downward speed (m/s), positive when descending.
    pub vertical_speed_mps: f64,
    pub horizontal_speed_mps: f64,
    /// Thrust axis from the local vertical (deg).
    pub tilt_deg: f64,
    /// |omega_body| (deg/s).
    pub body_rate_degps: f64,
    /// Horizontal distance from the landing site (m).
    pub horizontal_position_m: f64,
}

/// One limit of the envelope that the touchdown broke.
#[derive(Debug, Clone, PartialEq)]
pub struct Exceedance {
    pub quantity: &'static str,
    pub unit: &'static str,
    pub value: f64,
    pub limit: f64,
}

impl fmt::Display for Exceedance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let u = self.unit;
        // A fact with no scale (tipped over) is stated, not compared.
        if u.is_empty() {
            return write!(f, "{}", self.quantity);
        }
        write!(
            f,
            "{} {:.2} {u} > {:.2} {u} (by {:.2} {u})",
            self.quantity,
            self.value,
            self.limit,
            self.value - self.limit
        )
    }
}

/// How a run ended, judged.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    Completed {
        end_time_s: f64,
        /// Whether the plant's touchdown flag was recorded (a lander run), so that "without
        /// touching the ground" is a fact, not a guess about an FMU that is not a lander.
        touchdown_recorded: bool,
    },
    Landed(Touchdown),
    HardLanding {
        touchdown: Touchdown,
        broken: Vec<Exceedance>,
    },
    /// An instance stopped the run without a touchdown (or the propellant ran out).
    Stopped {
        instance: String,
        time_s: f64,
        reason: String,
    },
    Error(String),
}

impl Verdict {
    /// The short word the tables print (at most 12 characters).
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Completed { .. } => "completed",
            Verdict::Landed(_) => "landed",
            Verdict::HardLanding { .. } => "hard landing",
            Verdict::Stopped { .. } => "stopped",
            Verdict::Error(_) => "error",
        }
    }

    pub fn touchdown(&self) -> Option<&Touchdown> {
        match self {
            Verdict::Landed(t) | Verdict::HardLanding { touchdown: t, .. } => Some(t),
            _ => None,
        }
    }

    /// Whether the run ended as `expect` says.
    pub fn meets(&self, expect: Expect) -> bool {
        matches!(
            (self, expect),
            (Verdict::Completed { .. }, Expect::Completed)
                | (Verdict::Landed(_), Expect::Landed)
                | (Verdict::Stopped { .. }, Expect::Stopped)
        )
    }

    /// The exit code of a single run expected to end as `expect`.
    pub fn exit_code(&self, expect: Expect) -> i32 {
        match self {
            Verdict::Error(_) => EXIT_ERROR,
            v if v.meets(expect) => EXIT_OK,
            _ => EXIT_FAILED_VERDICT,
        }
    }

    /// One line for a person: the verdict, its numbers, and whether it is what was expected.
    pub fn describe(&self, expect: Expect) -> String {
        let body = match self {
            Verdict::Completed {
                end_time_s,
                touchdown_recorded: true,
            } => format!("completed at t = {end_time_s:.2} s without touching the ground"),
            Verdict::Completed { end_time_s, .. } => {
                format!("completed at t = {end_time_s:.2} s")
            }
            Verdict::Landed(t) => format!("landed inside the envelope, {}", touchdown_text(t)),
            Verdict::HardLanding { touchdown, broken } => format!(
                "HARD LANDING, {}; broken: {}",
                touchdown_text(touchdown),
                broken
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
            Verdict::Stopped {
                instance,
                time_s,
                reason,
            } => format!("stopped by '{instance}' at t = {time_s:.2} s: {reason}"),
            Verdict::Error(message) => format!("ERROR: {message}"),
        };
        let tail = match self {
            Verdict::Error(_) => String::new(),
            v if v.meets(expect) => " (as the scenario expects)".to_owned(),
            _ => format!(" (the scenario expects: {})", expect.name()),
        };
        format!("{body}{tail}")
    }
}

fn touchdown_text(t: &Touchdown) -> String {
    format!(
        "touchdown at t = {:.2} s: vertical {:.2} m/s, horizontal {:.2} m/s, tilt {:.1} deg, \
         body rate {:.2} deg/s, {:.2} m from the site",
        t.time_s,
        t.vertical_speed_mps,
        t.horizontal_speed_mps,
        t.tilt_deg,
        t.body_rate_degps,
        t.horizontal_position_m
    )
}

/// The plant columns a verdict reads (record them in campaigns).
pub const VERDICT_COLUMNS: [&str; 7] = [
    "plant.touchdown",
    "plant.touchdown_time",
    "plant.touchdown_v_nue",
    "plant.touchdown_omega_body",
    "plant.touchdown_tilt",
    "plant.propellant_exhausted",
    "plant.r_nue",
];

/// Judges a finished run against `envelope`, from its last recorded row. A run whose
/// trajectory lacks the touchdown columns can only be judged when it completed.
pub fn judge(trajectory: &Trajectory, end: &RunEnd, envelope: &Envelope) -> Verdict {
    let last = |name: &str| {
        trajectory
            .column_index(name)
            .filter(|_| !trajectory.is_empty())
            .map(|j| trajectory.row(trajectory.len() - 1)[j])
    };
    let touched = last("plant.touchdown").map(|x| x != 0.0);
    // A system with a `plant` instance is judged as a lander; any other only by how it ended.
    let lander = trajectory.names.iter().any(|n| n.starts_with("plant."));
    let exhausted = last("plant.propellant_exhausted").is_some_and(|x| x != 0.0);
    match (end, touched) {
        (_, Some(true)) => {
            let get = |n: &str| last(n).unwrap_or(f64::NAN);
            let v = |i: usize| get(&format!("plant.touchdown_v_nue[{i}]"));
            let w = |i: usize| get(&format!("plant.touchdown_omega_body[{i}]"));
            let touchdown = Touchdown {
                time_s: get("plant.touchdown_time"),
                vertical_speed_mps: -v(2),
                horizontal_speed_mps: v(1).hypot(v(3)),
                tilt_deg: get("plant.touchdown_tilt").to_degrees(),
                body_rate_degps: (w(1).powi(2) + w(2).powi(2) + w(3).powi(2))
                    .sqrt()
                    .to_degrees(),
                horizontal_position_m: get("plant.r_nue[1]").hypot(get("plant.r_nue[3]")),
            };
            let mut broken = exceedances(&touchdown, envelope);
            // Judged where recorded (a plant with landing gear declares it).
            if last("plant.tipped_over").is_some_and(|x| x != 0.0) {
                broken.push(Exceedance {
                    quantity: "tipped over after touchdown",
                    unit: "",
                    value: 1.0,
                    limit: 0.0,
                });
            }
            if broken.is_empty() {
                Verdict::Landed(touchdown)
            } else {
                Verdict::HardLanding { touchdown, broken }
            }
        }
        (RunEnd::Completed, _) if exhausted => Verdict::Stopped {
            instance: "plant".into(),
            time_s: trajectory.times.last().copied().unwrap_or(f64::NAN),
            reason: "propellant exhausted before the end of the run".into(),
        },
        (RunEnd::Completed, touched) => Verdict::Completed {
            end_time_s: trajectory.times.last().copied().unwrap_or(f64::NAN),
            touchdown_recorded: touched.is_some(),
        },
        (RunEnd::Terminated { instance, time }, touched) => Verdict::Stopped {
            instance: instance.clone(),
            time_s: *time,
            reason: match touched {
                None if lander => {
                    "no touchdown columns recorded to judge it (record plant.touchdown*)".into()
                }
                None => "the FMU ended the run".into(),
                Some(_) if exhausted => "propellant exhausted".into(),
                Some(_) => "terminated without a touchdown".into(),
            },
        },
    }
}

/// Every limit `touchdown` breaks (NaN values break their limit: nothing unknown passes).
pub fn exceedances(t: &Touchdown, e: &Envelope) -> Vec<Exceedance> {
    [
        (
            "vertical speed",
            "m/s",
            t.vertical_speed_mps,
            e.max_vertical_speed_mps,
        ),
        (
            "horizontal speed",
            "m/s",
            t.horizontal_speed_mps,
            e.max_horizontal_speed_mps,
        ),
        ("tilt", "deg", t.tilt_deg, e.max_tilt_deg),
        (
            "body rate",
            "deg/s",
            t.body_rate_degps,
            e.max_body_rate_degps,
        ),
    ]
    .into_iter()
    .filter(|(_, _, value, limit)| value.partial_cmp(limit).is_none_or(|o| o.is_gt()))
    .map(|(quantity, unit, value, limit)| Exceedance {
        quantity,
        unit,
        value,
        limit,
    })
    .collect()
}

#[cfg(test)]
mod tests;
