//! The error parameters of each signal group, their defaults (every error off) and their
//! validation, naming the field of the offending value.
use serde::{Deserialize, Serialize};

/// Largest `max_latency_steps`: the history it sizes holds that many samples of the 14
/// navigation values (10 000 samples, about 1.1 MB), so no parameter can ask for gigabytes.
pub const LATENCY_CAP_STEPS: i32 = 10_000;

/// The errors of one signal group, each axis alike except the bias. All zero is no error.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupErrors {
    /// Standard deviation of the white noise, one independent sample per communication step
    /// (signal unit; for the attitude, rad about each body axis).
    pub noise_sigma: f64,
    /// Constant offset per axis (signal unit).
    pub bias: [f64; 3],
    /// Random walk: standard deviation of the walk after 1 s, growing as sqrt(t / 1 s);
    /// numerically the sigma per sqrt(s) (signal unit).
    pub random_walk: f64,
    /// Output resolution: the corrupted value is rounded to a multiple of it; 0 = none.
    pub quantum: f64,
    /// Whole communication steps the group's values are late.
    pub latency_steps: i32,
}

/// The signal groups, in the fixed order of the noise draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    Position = 0,
    Velocity = 1,
    Attitude = 2,
    Rate = 3,
    Mass = 4,
}

impl Group {
    pub const ALL: [Group; 5] = [
        Group::Position,
        Group::Velocity,
        Group::Attitude,
        Group::Rate,
        Group::Mass,
    ];

    /// The group's name, as its parameters are prefixed.
    pub const fn name(self) -> &'static str {
        match self {
            Group::Position => "r_nue",
            Group::Velocity => "v_nue",
            Group::Attitude => "attitude",
            Group::Rate => "omega_body",
            Group::Mass => "mass",
        }
    }

    /// Number of axes the group's errors act on.
    pub const fn axes(self) -> usize {
        match self {
            Group::Mass => 1,
            _ => 3,
        }
    }
}

/// Every parameter of the navigation errors.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct NavParameters {
    /// Seed of the noise draws (non-negative).
    pub seed: i32,
    /// Bound of every group's latency; sizes the history of past inputs.
    pub max_latency_steps: i32,
    pub r_nue: GroupErrors,
    pub v_nue: GroupErrors,
    /// Small rotation in body axes (rad); `quantum` is not used (a quantised quaternion
    /// is not a rotation).
    pub attitude: GroupErrors,
    pub omega_body: GroupErrors,
    /// Only the first element of `bias` is used.
    pub mass: GroupErrors,
}

pub use fmi_model::parameter::ParameterError;

impl NavParameters {
    pub fn group(&self, group: Group) -> &GroupErrors {
        match group {
            Group::Position => &self.r_nue,
            Group::Velocity => &self.v_nue,
            Group::Attitude => &self.attitude,
            Group::Rate => &self.omega_body,
            Group::Mass => &self.mass,
        }
    }

    /// The seed as the draws use it (a negative one is refused by validation).
    pub fn seed(&self) -> u64 {
        u64::try_from(self.seed).unwrap_or(0)
    }

    /// Longest latency of any group: the history kept.
    pub fn longest_latency(&self) -> usize {
        Group::ALL
            .iter()
            .map(|&g| steps(self.group(g).latency_steps))
            .max()
            .unwrap_or(0)
    }

    /// What the declarations cannot say (each value on its own is checked against its
    /// declaration, `fmi_model::parameter::check_declared`): no group is later than
    /// `max_latency_steps`, which sizes the history.
    pub fn validate(&self) -> Result<(), ParameterError> {
        let groups = [
            (&self.r_nue, "r_nue.latency_steps"),
            (&self.v_nue, "v_nue.latency_steps"),
            (&self.attitude, "attitude.latency_steps"),
            (&self.omega_body, "omega_body.latency_steps"),
            (&self.mass, "mass.latency_steps"),
        ];
        for (errors, field) in groups {
            if errors.latency_steps > self.max_latency_steps {
                return Err(refuse(
                    field,
                    None,
                    errors.latency_steps,
                    &format!(
                        "must be in [0, max_latency_steps = {}]",
                        self.max_latency_steps
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A latency as a count of steps; a negative one (refused by validation) counts as none.
pub fn steps(latency_steps: i32) -> usize {
    usize::try_from(latency_steps).unwrap_or(0)
}

fn refuse(
    field: &'static str,
    index: Option<usize>,
    value: impl ToString,
    reason: &str,
) -> ParameterError {
    ParameterError::new(field, index, value, reason)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid_and_switch_every_error_off() {
        let p = NavParameters::default();
        assert_eq!(p.check(), Ok(()));
        for g in Group::ALL {
            assert_eq!(*p.group(g), GroupErrors::default());
        }
        assert_eq!(p.longest_latency(), 0);
    }

    /// Spoils one value, and names the field (and element) that must be refused.
    type Case = (fn(&mut NavParameters), &'static str, Option<usize>);

    #[test]
    fn each_bad_value_is_refused_naming_its_field() {
        let cases: [Case; 8] = [
            (|p| p.seed = -1, "seed", None),
            (
                |p| p.max_latency_steps = LATENCY_CAP_STEPS + 1,
                "max_latency_steps",
                None,
            ),
            (|p| p.r_nue.noise_sigma = -1e-9, "r_nue.noise_sigma", None),
            (
                |p| p.v_nue.random_walk = f64::NAN,
                "v_nue.random_walk",
                None,
            ),
            (|p| p.omega_body.quantum = -0.5, "omega_body.quantum", None),
            (
                |p| p.attitude.bias[2] = f64::INFINITY,
                "attitude.bias",
                Some(2),
            ),
            (|p| p.mass.latency_steps = -1, "mass.latency_steps", None),
            // A latency beyond the bound the history is sized for.
            (|p| p.r_nue.latency_steps = 1, "r_nue.latency_steps", None),
        ];
        for (spoil, field, index) in cases {
            let mut p = NavParameters::default();
            spoil(&mut p);
            let e = p.check().expect_err(field);
            assert_eq!((e.field, e.index), (field, index), "{e:?}");
        }
    }

    #[test]
    fn a_latency_up_to_the_bound_is_accepted() {
        let mut p = NavParameters {
            max_latency_steps: 3,
            ..NavParameters::default()
        };
        p.v_nue.latency_steps = 3;
        p.mass.latency_steps = 1;
        assert_eq!(p.check(), Ok(()));
        assert_eq!(p.longest_latency(), 3);
    }
}
