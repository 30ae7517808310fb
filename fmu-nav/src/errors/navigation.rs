//! The navigation errors of all groups together: which interval the run is in, the random
//! parts of each group's error during it, and the history for the latency.
//!
//! Timing, for communication points `t_0 < t_1 < ...`:
//! - the estimate at `t_k` is the truth at `t_k-n` (`n` the group's latency; the truth at
//!   `t_0` for `k < n`) with the error of interval `k`, then quantised;
//! - the error of interval 0 is fixed at the end of initialization; the step from `t_k`
//!   records the truth at `t_k` and draws the error of interval `k+1`. Reading the outputs
//!   draws nothing, so reads never change the sequence;
//! - with latency 0 an estimate depends on the truth of the same instant (direct
//!   feedthrough), so plant -> nav -> GNC adds no delay.
use super::attitude::rotate_body;
use super::draws::Draws;
use super::history::History;
use super::parameters::{steps, Group, NavParameters};
use super::signal::{corrupt, GroupError};
use serde::{Deserialize, Serialize};

/// The navigation signals, true (inputs) or estimated (outputs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Navigation {
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    /// Scalar first, Hamilton, body to NUE.
    pub q_body_to_nue: [f64; 4],
    pub omega_body_radps: [f64; 3],
    pub mass_kg: f64,
}

impl Default for Navigation {
    /// The paper's initial condition: upright, at rest, 800 m up, 900 kg.
    fn default() -> Self {
        Navigation {
            r_nue_m: [0.0, 800.0, 0.0],
            v_nue_mps: [0.0; 3],
            q_body_to_nue: [1.0, 0.0, 0.0, 0.0],
            omega_body_radps: [0.0; 3],
            mass_kg: 900.0,
        }
    }
}

/// The error state of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NavErrors {
    /// The interval the current errors belong to (0 from `t_0`).
    interval: u64,
    /// Per group, indexed by [`Group`].
    errors: [GroupError; 5],
    history: History<Navigation>,
}

impl NavErrors {
    /// The errors of the first interval.
    pub fn start(params: &NavParameters) -> NavErrors {
        let draws = Draws::of_interval(params.seed(), 0);
        NavErrors {
            interval: 0,
            errors: Group::ALL.map(|g| GroupError::first(params.group(g), g, &draws)),
            history: History::new(params.longest_latency()),
        }
    }

    pub fn interval(&self) -> u64 {
        self.interval
    }

    /// Why this cannot be a run of `params` (a restored FMU state), if it cannot: an error
    /// that is not finite, or a latency history of the wrong shape or with non-finite inputs.
    pub fn inconsistency(&self, params: &NavParameters) -> Option<String> {
        if let Some(group) = self.overflowing(params) {
            return Some(format!("the error of group {group:?} is not finite"));
        }
        if !self.history.holds(params.longest_latency()) {
            return Some("the latency history does not match the latency parameters".into());
        }
        let finite = |n: &Navigation| {
            n.r_nue_m
                .iter()
                .chain(&n.v_nue_mps)
                .chain(&n.q_body_to_nue)
                .chain(&n.omega_body_radps)
                .chain(std::iter::once(&n.mass_kg))
                .all(|v| v.is_finite())
        };
        if !self.history.samples().all(finite) {
            return Some("the latency history holds a non-finite input".into());
        }
        None
    }

    /// The first group whose current error is not finite (sigmas near the largest f64).
    pub fn overflowing(&self, params: &NavParameters) -> Option<Group> {
        overflowing(&self.errors, params)
    }

    /// The random parts of `group`'s error in the current interval.
    pub fn error(&self, group: Group) -> &GroupError {
        &self.errors[group as usize]
    }

    /// The step from the communication point where the truth is `truth`, `h_s` seconds long.
    /// Refused, with nothing changed, when it would make a group's error overflow (sigmas
    /// near the largest f64, or a walk over an enormous step): the group is returned.
    pub fn step(
        &mut self,
        params: &NavParameters,
        truth: &Navigation,
        h_s: f64,
    ) -> Result<(), Group> {
        let interval = self.interval + 1;
        let draws = Draws::of_interval(params.seed(), interval);
        let next =
            Group::ALL.map(|g| self.errors[g as usize].next(params.group(g), g, &draws, h_s));
        if let Some(g) = overflowing(&next, params) {
            return Err(g);
        }
        self.history.record(*truth);
        self.interval = interval;
        self.errors = next;
        Ok(())
    }

    /// The estimate at the current communication point, where the truth is `truth`.
    pub fn estimate(&self, params: &NavParameters, truth: &Navigation) -> Navigation {
        let late = |g: Group| {
            self.history
                .delayed(steps(params.group(g).latency_steps), *truth)
        };
        let total = |g: Group| self.errors[g as usize].total(params.group(g));
        let corrupt_all = |g: Group, values: [f64; 3]| {
            let (errors, quantum) = (total(g), params.group(g).quantum);
            std::array::from_fn(|i| corrupt(values[i], errors[i], quantum))
        };
        Navigation {
            r_nue_m: corrupt_all(Group::Position, late(Group::Position).r_nue_m),
            v_nue_mps: corrupt_all(Group::Velocity, late(Group::Velocity).v_nue_mps),
            q_body_to_nue: rotate_body(late(Group::Attitude).q_body_to_nue, total(Group::Attitude)),
            omega_body_radps: corrupt_all(Group::Rate, late(Group::Rate).omega_body_radps),
            mass_kg: corrupt(
                late(Group::Mass).mass_kg,
                total(Group::Mass)[0],
                params.mass.quantum,
            ),
        }
    }
}

fn overflowing(errors: &[GroupError; 5], params: &NavParameters) -> Option<Group> {
    Group::ALL.into_iter().find(|&g| {
        let total = errors[g as usize].total(params.group(g));
        // The attitude error becomes a rotation through its angle |theta|, whose square
        // overflows long before theta itself (|theta| > 1.3e154 rad).
        let squared = |t: &[f64; 3]| t.iter().map(|v| v * v).sum::<f64>();
        !total.iter().all(|v| v.is_finite())
            || (g == Group::Attitude && !squared(&total).is_finite())
    })
}
