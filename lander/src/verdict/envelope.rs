//! What a scenario expects of its run: how it should end and, when it lands, the touchdown
//! envelope. Written in the scenario TOML as an optional `[verdict]` table; every key has a
//! default, so the paper's scenarios carry none.
//!
//! Default limits and why (all at the instant the plant reports touchdown):
//! - vertical speed <= 2 m/s: the project's landing requirement. Leg strokes of small lunar
//!   landers are sized for a few m/s; 2 m/s keeps a margin of 2x over the 1 m/s the terminal
//!   descent commands.
//! - horizontal speed <= 0.5 m/s: the project's requirement. Sliding feet on regolith trip
//!   the lander over its downhill legs; a quarter of the vertical limit keeps the tip-over
//!   moment small.
//! - tilt <= 12 deg: the project's requirement: thrust axis from the local vertical, the
//!   angle a four-legged lander can touch down at on a level site and still settle on all legs.
//! - body rate <= 5 deg/s: our choice. At touchdown the attitude loop holds the lander still;
//!   5 deg/s over a 2 m foot radius moves a foot at 0.17 m/s, a third of the horizontal
//!   limit, so rate adds little to the foot speed the horizontal limit bounds.
use serde::Deserialize;

/// How a run is expected to end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Expect {
    /// Reaches the stop time without touching the ground (the paper's descent to a hover).
    #[default]
    Completed,
    /// Touches down inside the envelope.
    Landed,
    /// An FMU ends the run itself before the stop time (`fmi2Terminated` /
    /// `terminateSimulation`), not a touchdown: for models that are not landers.
    Stopped,
}

impl Expect {
    pub fn name(self) -> &'static str {
        match self {
            Expect::Completed => "completed",
            Expect::Landed => "landed",
            Expect::Stopped => "stopped",
        }
    }
}

/// Touchdown limits (SI and degrees as named).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Envelope {
    pub max_vertical_speed_mps: f64,
    pub max_horizontal_speed_mps: f64,
    pub max_tilt_deg: f64,
    pub max_body_rate_degps: f64,
}

impl Default for Envelope {
    fn default() -> Self {
        Self {
            max_vertical_speed_mps: 2.0,
            max_horizontal_speed_mps: 0.5,
            max_tilt_deg: 12.0,
            max_body_rate_degps: 5.0,
        }
    }
}

/// The `[verdict]` table of a scenario.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    #[serde(default)]
    pub expect: Expect,
    #[serde(default)]
    pub envelope: Envelope,
}

impl Spec {
    /// Every limit must be a positive finite number.
    pub fn validate(&self) -> Result<(), String> {
        let e = &self.envelope;
        let bad: Vec<String> = [
            ("max_vertical_speed_mps", e.max_vertical_speed_mps),
            ("max_horizontal_speed_mps", e.max_horizontal_speed_mps),
            ("max_tilt_deg", e.max_tilt_deg),
            ("max_body_rate_degps", e.max_body_rate_degps),
        ]
        .iter()
        .filter(|(_, v)| !(v.is_finite() && *v > 0.0))
        .map(|(n, v)| format!("verdict.envelope.{n} = {v} must be a positive number"))
        .collect();
        if bad.is_empty() {
            Ok(())
        } else {
            Err(bad.join("; "))
        }
    }
}

/// Splits a scenario TOML into the text the system parser reads (the `[verdict]` tables
/// blanked out line for line, so its error positions stay right) and the verdict spec.
pub fn split_scenario(text: &str) -> Result<(String, Spec), String> {
    #[derive(Deserialize)]
    struct Outer {
        #[serde(default)]
        verdict: Spec,
    }
    let outer: Outer = toml::from_str::<toml::Table>(text)
        .map_err(|e| e.to_string())
        .and_then(|mut table| {
            let verdict = table.remove("verdict");
            // Requirements are read by `cosim::requirements::from_toml`.
            table.remove("requirement");
            let mut only = toml::Table::new();
            if let Some(v) = verdict {
                only.insert("verdict".into(), v);
            }
            Outer::deserialize(toml::Value::Table(only)).map_err(|e| e.to_string())
        })?;
    outer.verdict.validate()?;
    let mut inside = false;
    let stripped: Vec<&str> = text
        .lines()
        .map(|line| {
            let head = line.trim_start();
            if head.starts_with('[') {
                let name = head.trim_start_matches('[').trim_start();
                inside = name.starts_with("verdict]")
                    || name.starts_with("verdict.")
                    || name.starts_with("verdict ")
                    || name.starts_with("requirement]");
            }
            if inside {
                ""
            } else {
                line
            }
        })
        .collect();
    Ok((stripped.join("\n"), outer.verdict))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scenario_without_a_verdict_table_expects_completion_with_the_default_envelope() {
        let (text, spec) = split_scenario("name = \"x\"\n[[instance]]\nname = \"a\"\n").unwrap();
        assert_eq!(spec, Spec::default());
        assert_eq!(spec.envelope.max_vertical_speed_mps, 2.0);
        assert!(text.contains("[[instance]]"));
    }

    #[test]
    fn the_verdict_table_is_read_and_blanked_keeping_line_numbers() {
        let text = "name = \"x\"\n[verdict]\nexpect = \"landed\"\n[verdict.envelope]\n\
                    max_tilt_deg = 8.0\n[[instance]]\nname = \"a\"\n";
        let (stripped, spec) = split_scenario(text).unwrap();
        assert_eq!(spec.expect, Expect::Landed);
        assert_eq!(spec.envelope.max_tilt_deg, 8.0);
        assert_eq!(spec.envelope.max_horizontal_speed_mps, 0.5);
        assert_eq!(stripped.lines().count(), text.lines().count());
        assert!(!stripped.contains("verdict") && !stripped.contains("max_tilt"));
        assert_eq!(stripped.lines().nth(5), Some("[[instance]]"));
    }

    #[test]
    fn unknown_keys_and_bad_limits_are_refused_by_name() {
        let e = split_scenario("[verdict]\nexpect = \"crashed\"\n").unwrap_err();
        assert!(e.contains("crashed"), "{e}");
        let e = split_scenario("[verdict.envelope]\nmax_tilt = 3.0\n").unwrap_err();
        assert!(e.contains("max_tilt"), "{e}");
        let e =
            split_scenario("[verdict.envelope]\nmax_tilt_deg = -1.0\nmax_body_rate_degps = nan\n")
                .unwrap_err();
        assert!(
            e.contains("max_tilt_deg = -1") && e.contains("max_body_rate_degps = NaN"),
            "{e}"
        );
    }
}
