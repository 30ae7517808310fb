//! `LanderGnc` as an FMI 2.0 co-simulation model: the variable table (names per INTERFACE.md)
//! and the sampled-data timing. All GNC math lives in the pure modules.
//!
//! Timing: a sampled-data controller with direct feedthrough. The outputs at communication
//! point `t` are a function of the inputs at `t` and the internal state: `calculate_values`
//! evaluates the sample at `t` without committing it; `do_step(t, h)` commits the sample taken
//! at `t` (guidance re-solve on a new guidance cycle, phase change) and advances to `t + h`.
//!
//! A master reads the outputs and then steps at the same point, so the sample evaluated for
//! the get is kept and committed by `do_step` when its inputs are bit-identical and its time
//! is the same sample time (see [`Evaluated`], [`SampleTime`]); otherwise `do_step` evaluates
//! again. Either way the committed sample is bit-identical to `gnc_sample` at the master's
//! `t`: gets never change a trajectory.
use crate::attitude::ControlLaw;
use crate::controller::{gnc_sample, GncOutputs, NavigationInputs, Sample};
use crate::guidance::sequencer::{guidance_cycle_index, has_reached, GuidanceState};
use crate::params::GncParameters;
use fmi2_export::{
    Access, Causality, EnumerationDecl, Experiment, Initial, Log, Model, ModelError, StepEnd,
    Variability, Variable,
};
use serde::{Deserialize, Serialize};

/// The GNC FMU instance: parameters, latest inputs and outputs, guidance memory, time.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LanderGnc {
    params: GncParameters,
    inputs: NavigationInputs,
    outputs: GncOutputs,
    guidance: GuidanceState,
    start_time_s: f64,
    time_s: f64,
    /// A cache, not state: a restored or deserialized instance evaluates afresh.
    #[serde(skip)]
    evaluated: Option<Evaluated>,
}

/// The latest sample evaluated without being committed, with the time and inputs it was
/// evaluated at. It is only valid while the parameters, the start time and the guidance
/// state are those it was evaluated with: these change only in `exit_initialization`
/// (which evaluates and stores afresh) and in `do_step` (which consumes it); a parameter
/// set in initialization mode is followed by `exit_initialization`; `fmi2Reset` and
/// `fmi2SetFMUstate` replace the whole instance, this cache included.
#[derive(Debug, Clone)]
struct Evaluated {
    time: SampleTime,
    input_bits: [u64; 14],
    sample: Sample,
}

/// All that `gnc_sample` reads of its time `t` (for given parameters, start time and
/// guidance state): whether phi_cmd applies and the guidance cycle `t` falls in; `t` itself
/// only when it opens that cycle off its nominal start (a late sample, after degenerate
/// inputs), the one case in which the sequencer solves at the sample's own time. Equal keys give bit-identical samples, so a master's `t` a few
/// ulps off ours (`k h` against our `(k - 1) h + h`, a third of the steps of a 0.01 s grid)
/// still commits the kept sample; tests below check the equivalence against `gnc_sample`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct SampleTime {
    phi_cmd_applies: bool,
    cycle: i64,
    off_nominal_bits: Option<u64>,
}

impl Default for LanderGnc {
    fn default() -> Self {
        let params = GncParameters::default();
        Self {
            params,
            inputs: NavigationInputs::default(),
            outputs: GncOutputs::default(),
            guidance: GuidanceState::initial(params.gravity_mps2),
            start_time_s: 0.0,
            time_s: 0.0,
            evaluated: None,
        }
    }
}

impl LanderGnc {
    /// The [`SampleTime`] of the sample at `t_s`, mirroring how `gnc_sample` and the guidance
    /// sequencer use the time.
    fn sample_time(&self, t_s: f64) -> SampleTime {
        let elapsed_s = t_s - self.start_time_s;
        let (cycle, on_boundary) = guidance_cycle_index(elapsed_s, self.params.guidance_cycle_s);
        let opens_cycle = self.guidance.last_cycle != Some(cycle);
        SampleTime {
            phi_cmd_applies: has_reached(t_s, self.params.phi_cmd_time_s),
            cycle,
            off_nominal_bits: (opens_cycle && !on_boundary).then_some(elapsed_s.to_bits()),
        }
    }

    fn evaluate(&self) -> Sample {
        gnc_sample(
            &self.params,
            self.start_time_s,
            &self.guidance,
            &self.inputs,
            self.time_s,
        )
    }

    /// Evaluate the sample at the current time without committing it, show its outputs and
    /// keep it for the `do_step` that usually follows.
    fn preview(&mut self, log: &mut Log) {
        let evaluated = self.evaluated.insert(Evaluated {
            time: self.sample_time(self.time_s),
            input_bits: self.inputs.to_bits(),
            sample: self.evaluate(),
        });
        publish(&evaluated.sample, self.time_s, &mut self.outputs, log);
    }

    /// Commit the sample at the current time: the kept one if it was evaluated at the same
    /// sample time with these very inputs, otherwise a fresh one.
    fn commit(&mut self, log: &mut Log) {
        let (time, input_bits) = (self.sample_time(self.time_s), self.inputs.to_bits());
        let fresh;
        // Read in place: a sample is a few hundred bytes, worth not moving twice per step.
        let sample = match &self.evaluated {
            Some(e) if e.time == time && e.input_bits == input_bits => &e.sample,
            _ => {
                fresh = self.evaluate();
                &fresh
            }
        };
        publish(sample, self.time_s, &mut self.outputs, log);
        self.guidance = sample.guidance;
        self.evaluated = None;
    }
}

/// Show `sample` as the outputs; its warning, if any, goes to this call's log.
fn publish(sample: &Sample, time_s: f64, outputs: &mut GncOutputs, log: &mut Log) {
    if let Some(why) = sample.degenerate {
        log.warning(format!("t = {time_s} s: {why}"));
    }
    *outputs = sample.outputs;
    if outputs.zero_non_finite() {
        log.warning(format!(
            "t = {time_s} s: the parameters give non-finite outputs (shown as 0); \
             fmi2ExitInitializationMode will name the parameter"
        ));
    }
}

impl Model for LanderGnc {
    const MODEL_IDENTIFIER: &'static str = "LanderGnc";
    const MODEL_NAME: &'static str = "LanderGnc";
    const DESCRIPTION: &'static str =
        "Lunar lander guidance (PV hover, cubic-polynomial descent) and \
        attitude control (coupled, decoupled thrust-axis, reduced) after Rallapalli et al., \
        'Decoupled Thrust-Axis Attitude Control Using Quaternions for Chandrayaan-3'";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn variables() -> &'static [Variable<Self>] {
        VARIABLES
    }

    fn enumeration_types() -> &'static [EnumerationDecl] {
        &[EnumerationDecl {
            name: "ControlLaw",
            description: "Attitude control law",
            items: &[
                (
                    "coupled",
                    ControlLaw::Coupled as i32,
                    "classical quaternion PD on q_ref",
                ),
                (
                    "decoupled",
                    ControlLaw::Decoupled as i32,
                    "decoupled thrust-axis control (the paper)",
                ),
                (
                    "reduced",
                    ControlLaw::Reduced as i32,
                    "PX4-style reduced attitude (Brescianini et al. 2013)",
                ),
            ],
        }]
    }

    fn calculate_values(&mut self, log: &mut Log) {
        self.preview(log);
    }

    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        self.params
            .validate()
            .map_err(|e| ModelError::InvalidParameter {
                name: e.name,
                value: e.value,
                reason: e.reason.to_string(),
            })?;
        self.start_time_s = start_time;
        self.time_s = start_time;
        self.guidance = GuidanceState::initial(self.params.gravity_mps2);
        self.preview(log);
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError> {
        // The master's t is authoritative: it may differ from ours by rounding (and then the
        // sample kept from the get is not used).
        self.time_s = t;
        self.commit(log);
        self.time_s = t + h;
        Ok(StepEnd::Complete)
    }
}

// ---- the variable table ----------------------------------------------------------------

const fn input(
    name: &'static str,
    value_reference: u32,
    unit: Option<&'static str>,
    description: &'static str,
    start: f64,
    get: fn(&LanderGnc) -> f64,
    set: fn(&mut LanderGnc, f64),
) -> Variable<LanderGnc> {
    Variable {
        name,
        value_reference,
        causality: Causality::Input,
        variability: Variability::Continuous,
        initial: None,
        unit,
        description,
        access: Access::Real {
            start: Some(start),
            min: None,
            max: None,
            get,
            set: Some(set),
        },
    }
}

const fn output(
    name: &'static str,
    value_reference: u32,
    unit: Option<&'static str>,
    description: &'static str,
    get: fn(&LanderGnc) -> f64,
) -> Variable<LanderGnc> {
    Variable {
        name,
        value_reference,
        causality: Causality::Output,
        variability: Variability::Continuous,
        initial: Some(Initial::Calculated),
        unit,
        description,
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get,
            set: None,
        },
    }
}

#[allow(clippy::too_many_arguments)]
const fn parameter(
    name: &'static str,
    value_reference: u32,
    unit: Option<&'static str>,
    description: &'static str,
    start: f64,
    min: Option<f64>,
    get: fn(&LanderGnc) -> f64,
    set: fn(&mut LanderGnc, f64),
) -> Variable<LanderGnc> {
    Variable {
        name,
        value_reference,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit,
        description,
        access: Access::Real {
            start: Some(start),
            min,
            max: None,
            get,
            set: Some(set),
        },
    }
}

const M: Option<&str> = Some("m");
const MPS: Option<&str> = Some("m/s");
const MPS2: Option<&str> = Some("m/s2");
const RAD: Option<&str> = Some("rad");
const RADPS: Option<&str> = Some("rad/s");
const KG: Option<&str> = Some("kg");
const N: Option<&str> = Some("N");
const NM: Option<&str> = Some("N.m");
const S: Option<&str> = Some("s");
const HZ: Option<&str> = Some("Hz");
const KGM2: Option<&str> = Some("kg.m2");
const ONE: Option<&str> = None;

// Defaults repeated as literals here are checked against `GncParameters::default()` and
// `NavigationInputs::default()` by a test.
#[rustfmt::skip]
static VARIABLES: &[Variable<LanderGnc>] = &[
    // inputs: the plant's navigation state (INTERFACE.md)
    input("r_nue[1]", 1, M, "position North", 0.0, |m| m.inputs.r_nue_m[0], |m, v| m.inputs.r_nue_m[0] = v),
    input("r_nue[2]", 2, M, "position Up (altitude)", 800.0, |m| m.inputs.r_nue_m[1], |m, v| m.inputs.r_nue_m[1] = v),
    input("r_nue[3]", 3, M, "position East", 0.0, |m| m.inputs.r_nue_m[2], |m, v| m.inputs.r_nue_m[2] = v),
    input("v_nue[1]", 4, MPS, "velocity North", 0.0, |m| m.inputs.v_nue_mps[0], |m, v| m.inputs.v_nue_mps[0] = v),
    input("v_nue[2]", 5, MPS, "velocity Up", 0.0, |m| m.inputs.v_nue_mps[1], |m, v| m.inputs.v_nue_mps[1] = v),
    input("v_nue[3]", 6, MPS, "velocity East", 0.0, |m| m.inputs.v_nue_mps[2], |m, v| m.inputs.v_nue_mps[2] = v),
    input("q_body_to_nue[1]", 7, ONE, "attitude quaternion, scalar part (Hamilton, body to NUE)", 1.0, |m| m.inputs.q_body_to_nue[0], |m, v| m.inputs.q_body_to_nue[0] = v),
    input("q_body_to_nue[2]", 8, ONE, "attitude quaternion, vector part x", 0.0, |m| m.inputs.q_body_to_nue[1], |m, v| m.inputs.q_body_to_nue[1] = v),
    input("q_body_to_nue[3]", 9, ONE, "attitude quaternion, vector part y", 0.0, |m| m.inputs.q_body_to_nue[2], |m, v| m.inputs.q_body_to_nue[2] = v),
    input("q_body_to_nue[4]", 10, ONE, "attitude quaternion, vector part z", 0.0, |m| m.inputs.q_body_to_nue[3], |m, v| m.inputs.q_body_to_nue[3] = v),
    input("omega_body[1]", 11, RADPS, "body rate about x (yaw)", 0.0, |m| m.inputs.omega_body_radps[0], |m, v| m.inputs.omega_body_radps[0] = v),
    input("omega_body[2]", 12, RADPS, "body rate about y (roll, thrust axis)", 0.0, |m| m.inputs.omega_body_radps[1], |m, v| m.inputs.omega_body_radps[1] = v),
    input("omega_body[3]", 13, RADPS, "body rate about z (pitch)", 0.0, |m| m.inputs.omega_body_radps[2], |m, v| m.inputs.omega_body_radps[2] = v),
    input("mass", 14, KG, "current mass", 900.0, |m| m.inputs.mass_kg, |m, v| m.inputs.mass_kg = v),
    // outputs: the commands (INTERFACE.md)
    output("thrust_cmd", 100, N, "commanded total engine thrust along body +y", |m| m.outputs.thrust_cmd_n),
    output("torque_cmd_body[1]", 101, NM, "commanded control torque about body x (yaw)", |m| m.outputs.torque_cmd_body_nm[0]),
    output("torque_cmd_body[2]", 102, NM, "commanded control torque about body y (roll)", |m| m.outputs.torque_cmd_body_nm[1]),
    output("torque_cmd_body[3]", 103, NM, "commanded control torque about body z (pitch)", |m| m.outputs.torque_cmd_body_nm[2]),
    // diagnostic outputs
    output("a_cmd_nue[1]", 110, MPS2, "commanded thrust acceleration (guidance net acceleration minus gravity), North", |m| m.outputs.a_cmd_nue_mps2[0]),
    output("a_cmd_nue[2]", 111, MPS2, "commanded thrust acceleration, Up", |m| m.outputs.a_cmd_nue_mps2[1]),
    output("a_cmd_nue[3]", 112, MPS2, "commanded thrust acceleration, East", |m| m.outputs.a_cmd_nue_mps2[2]),
    output("q_ref[1]", 113, ONE, "reference attitude q_guid * q_phicmd, scalar part", |m| m.outputs.q_ref[0]),
    output("q_ref[2]", 114, ONE, "reference attitude, vector part x", |m| m.outputs.q_ref[1]),
    output("q_ref[3]", 115, ONE, "reference attitude, vector part y", |m| m.outputs.q_ref[2]),
    output("q_ref[4]", 116, ONE, "reference attitude, vector part z", |m| m.outputs.q_ref[3]),
    output("phi_b", 117, RAD, "achieved rotation about the thrust axis (third 1-3-2 Euler angle)", |m| m.outputs.phi_b_rad),
    output("err_roll", 118, RAD, "thrust-axis (roll, body y) error the active law acts on", |m| m.outputs.err_roll_rad),
    output("err_yaw", 119, RAD, "yaw (body x) error the active law acts on", |m| m.outputs.err_yaw_rad),
    output("err_pitch", 120, RAD, "pitch (body z) error the active law acts on", |m| m.outputs.err_pitch_rad),
    output("tilt_error", 121, RAD, "angle between the body thrust axis and the commanded thrust direction", |m| m.outputs.tilt_error_rad),
    Variable {
        name: "guidance_phase",
        value_reference: 122,
        causality: Causality::Output,
        variability: Variability::Discrete,
        initial: Some(Initial::Calculated),
        unit: None,
        description: "guidance phase: 1 hover, 2 polynomial descent, 3 hover at the descent target, 4 hold, 5 terminal descent",
        access: Access::Integer { start: None, min: Some(1), max: Some(5), get: |m| m.outputs.guidance_phase, set: None },
    },
    output("time_to_go", 123, S, "descent time-to-go at the last guidance sample (0 outside the descent)", |m| m.outputs.time_to_go_s),
    // parameters
    Variable {
        name: "control_law",
        value_reference: 200,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: None,
        description: "attitude control law: 1 coupled, 2 decoupled (the paper), 3 reduced (PX4-style)",
        access: Access::Enumeration { type_name: "ControlLaw", start: Some(2), get: |m| m.params.control_law, set: Some(|m, v| m.params.control_law = v) },
    },
    parameter("phi_cmd", 201, RAD, "commanded rotation about the thrust axis (mission constraint)", 0.0, None, |m| m.params.phi_cmd_rad, |m, v| m.params.phi_cmd_rad = v),
    parameter("phi_cmd_time", 202, S, "time at which phi_cmd is applied (before it: 0)", 12.0, None, |m| m.params.phi_cmd_time_s, |m, v| m.params.phi_cmd_time_s = v),
    parameter("control_bandwidth", 203, HZ, "attitude control bandwidth f_c (omega_c = 2 pi f_c)", 0.5, Some(0.0), |m| m.params.control_bandwidth_hz, |m, v| m.params.control_bandwidth_hz = v),
    parameter("control_damping", 204, ONE, "attitude control damping ratio", 0.8, Some(0.0), |m| m.params.control_damping, |m, v| m.params.control_damping = v),
    parameter("guidance_bandwidth", 205, HZ, "hover (PV) guidance bandwidth f_g (omega_g = 2 pi f_g)", 0.06, Some(0.0), |m| m.params.guidance_bandwidth_hz, |m, v| m.params.guidance_bandwidth_hz = v),
    parameter("guidance_damping", 206, ONE, "hover (PV) guidance damping ratio", 0.8, Some(0.0), |m| m.params.guidance_damping, |m, v| m.params.guidance_damping = v),
    parameter("guidance_cycle", 207, S, "guidance cycle time (zero-order hold between solves)", 0.1, Some(0.0), |m| m.params.guidance_cycle_s, |m, v| m.params.guidance_cycle_s = v),
    parameter("inertia_body[1]", 208, KGM2, "moment of inertia about body x used for the gains", 400.0, Some(0.0), |m| m.params.inertia_body_kgm2[0], |m, v| m.params.inertia_body_kgm2[0] = v),
    parameter("inertia_body[2]", 209, KGM2, "moment of inertia about body y used for the gains", 300.0, Some(0.0), |m| m.params.inertia_body_kgm2[1], |m, v| m.params.inertia_body_kgm2[1] = v),
    parameter("inertia_body[3]", 210, KGM2, "moment of inertia about body z used for the gains", 450.0, Some(0.0), |m| m.params.inertia_body_kgm2[2], |m, v| m.params.inertia_body_kgm2[2] = v),
    parameter("thrust_min", 211, N, "lowest commanded thrust (two engines at minimum throttle)", 720.0, Some(0.0), |m| m.params.thrust_min_n, |m, v| m.params.thrust_min_n = v),
    parameter("thrust_max", 212, N, "highest commanded thrust (two engines at full throttle)", 1600.0, Some(0.0), |m| m.params.thrust_max_n, |m, v| m.params.thrust_max_n = v),
    parameter("torque_limit_body[1]", 213, NM, "RCS torque limit about body x", 116.0, Some(0.0), |m| m.params.torque_limit_body_nm[0], |m, v| m.params.torque_limit_body_nm[0] = v),
    parameter("torque_limit_body[2]", 214, NM, "RCS torque limit about body y", 116.0, Some(0.0), |m| m.params.torque_limit_body_nm[1], |m, v| m.params.torque_limit_body_nm[1] = v),
    parameter("torque_limit_body[3]", 215, NM, "RCS torque limit about body z", 116.0, Some(0.0), |m| m.params.torque_limit_body_nm[2], |m, v| m.params.torque_limit_body_nm[2] = v),
    parameter("gravity", 216, MPS2, "lunar gravity magnitude g (gravity vector [0, -g, 0] NUE)", 1.62, Some(0.0), |m| m.params.gravity_mps2, |m, v| m.params.gravity_mps2 = v),
    parameter("hover_target_nue[1]", 217, M, "phase 1 hover target, North", 0.0, None, |m| m.params.hover_target_nue_m[0], |m, v| m.params.hover_target_nue_m[0] = v),
    parameter("hover_target_nue[2]", 218, M, "phase 1 hover target, Up", 800.0, None, |m| m.params.hover_target_nue_m[1], |m, v| m.params.hover_target_nue_m[1] = v),
    parameter("hover_target_nue[3]", 219, M, "phase 1 hover target, East", 0.0, None, |m| m.params.hover_target_nue_m[2], |m, v| m.params.hover_target_nue_m[2] = v),
    parameter("hover_duration", 220, S, "phase 1 (PV hover) duration from the start time", 12.0, Some(0.0), |m| m.params.hover_duration_s, |m, v| m.params.hover_duration_s = v),
    parameter("descent_target_nue[1]", 221, M, "phase 2 descent target and phase 3-4 hover point, North", 0.0, None, |m| m.params.descent_target_nue_m[0], |m, v| m.params.descent_target_nue_m[0] = v),
    parameter("descent_target_nue[2]", 222, M, "descent target, Up", 150.0, None, |m| m.params.descent_target_nue_m[1], |m, v| m.params.descent_target_nue_m[1] = v),
    parameter("descent_target_nue[3]", 223, M, "descent target, East", 0.0, None, |m| m.params.descent_target_nue_m[2], |m, v| m.params.descent_target_nue_m[2] = v),
    parameter("descent_time_to_go", 224, S, "phase 2 (polynomial descent) time-to-go at its start", 130.0, Some(0.0), |m| m.params.descent_time_to_go_s, |m, v| m.params.descent_time_to_go_s = v),
    parameter("descent_freeze_time_to_go", 225, S, "below this time-to-go the polynomial is no longer re-solved", 5.0, Some(0.0), |m| m.params.descent_freeze_time_to_go_s, |m, v| m.params.descent_freeze_time_to_go_s = v),
    parameter("target_hover_duration", 226, S, "phase 3 (PV hover at the descent target) duration; phase 4 holds there after it", 30.0, Some(0.0), |m| m.params.target_hover_duration_s, |m, v| m.params.target_hover_duration_s = v),
    parameter("reduced_yaw_weight", 227, ONE, "reduced law: weight of the rotation about the thrust axis, in [0, 1]", 0.4, Some(0.0), |m| m.params.reduced_yaw_weight, |m, v| m.params.reduced_yaw_weight = v),
    parameter("rate_shaping_margin", 228, ONE, "share of the torque limit the attitude laws count on to brake a rotation; large angle errors are shaped so the rate demand can be stopped in time (beyond the paper, ArduPilot-style square-root controller); 0.5 is a good choice; 0 = the paper's pure PD (default), in [0, 1]", 0.0, Some(0.0), |m| m.params.rate_shaping_margin, |m, v| m.params.rate_shaping_margin = v),
    parameter("terminal_descent_speed", 229, MPS, "phase 5 (beyond the paper): after the target hover, descend vertically over the descent target at this speed until touchdown; 0 = no terminal descent, hold the hover (default)", 0.0, Some(0.0), |m| m.params.terminal_descent_speed_mps, |m, v| m.params.terminal_descent_speed_mps = v),
];

#[cfg(test)]
mod tests {
    use super::*;

    const H: f64 = 0.01;

    /// A lander descending 2 m/s and rocking slowly (an open-loop input sequence, enough
    /// to pass the phase change, the phi_cmd switch and the 10 Hz re-solves), with one
    /// degenerate sample whose warning must appear in both runs.
    fn navigation(k: usize) -> NavigationInputs {
        let s = k as f64 * H;
        let half = 0.05 * (0.7 * s).sin();
        let mut nav = NavigationInputs {
            r_nue_m: [0.3, 800.0 - 2.0 * s, -0.2],
            v_nue_mps: [0.01, -2.0, 0.02],
            q_body_to_nue: [
                half.cos(),
                0.2 * half.sin(),
                0.5 * half.sin(),
                0.84 * half.sin(),
            ],
            omega_body_radps: [0.01, -0.02, 0.005],
            mass_kg: 880.0,
        };
        // On guidance cycle boundaries (7.8 s in the hover, 15 s in the descent), so that the
        // next sample opens the cycle late.
        if k == 780 || k == 1500 {
            nav.q_body_to_nue = [0.0; 4];
        }
        nav
    }

    fn initialized(params: GncParameters) -> LanderGnc {
        let mut gnc = LanderGnc {
            params,
            ..LanderGnc::default()
        };
        gnc.exit_initialization(0.0, &mut Log::default()).unwrap();
        gnc
    }

    fn paper_params() -> GncParameters {
        GncParameters {
            phi_cmd_rad: 150f64.to_radians(),
            ..GncParameters::default()
        }
    }

    /// `{:?}` of f64 is exact (shortest round trip) and tells -0.0 from 0.0.
    fn exact<T: std::fmt::Debug>(value: &T) -> String {
        format!("{value:?}")
    }

    fn messages(log: &Log) -> Vec<String> {
        log.entries
            .iter()
            .map(|(l, m)| format!("{l:?}: {m}"))
            .collect()
    }

    #[test]
    fn gets_between_steps_do_not_change_the_trajectory() {
        // GIVEN two instances, one stepped bare, one read before (almost) every step
        let mut bare = initialized(paper_params());
        let mut read = initialized(paper_params());
        let (mut kept_time, mut other_time) = (0, 0);
        for k in 0..2000 {
            // The master's time from an integer step counter: about a quarter of these
            // differ in the last bits from our t + h (the same sample time all the same).
            let t = k as f64 * H;
            if read.time_s.to_bits() == t.to_bits() {
                kept_time += 1;
            } else {
                other_time += 1;
            }
            // WHEN the reading instance sees, by turns: a get of the step's inputs; a get
            // of other inputs then the step's inputs without a get; no get at all
            match k % 3 {
                0 => {
                    read.inputs = navigation(k);
                    read.calculate_values(&mut Log::default());
                }
                1 => {
                    read.inputs = navigation(k + 50);
                    read.calculate_values(&mut Log::default());
                    read.inputs = navigation(k);
                }
                _ => read.inputs = navigation(k),
            }
            bare.inputs = navigation(k);
            let (mut bare_log, mut read_log) = (Log::default(), Log::default());
            bare.do_step(t, H, &mut bare_log).unwrap();
            read.do_step(t, H, &mut read_log).unwrap();
            // THEN both commit bit-identical samples and report the same warnings
            assert_eq!(exact(&read.outputs), exact(&bare.outputs), "step {k}");
            assert_eq!(exact(&read.guidance), exact(&bare.guidance), "step {k}");
            assert_eq!(messages(&read_log), messages(&bare_log), "step {k}");
        }
        assert!(
            kept_time > 200 && other_time > 200,
            "{kept_time} {other_time}"
        );
        assert_eq!(
            bare.outputs.guidance_phase, 2,
            "the run reaches the descent"
        );
    }

    /// The claim of `SampleTime`: equal keys, bit-identical samples. Probed along a run
    /// with guidance states that have and have not solved the cycle, and late ones, at the
    /// master's time, our accumulated time, times a few ulps and a few tolerances away, and
    /// on both sides of phi_cmd_time (off the guidance cycle grid).
    #[test]
    fn equal_sample_times_give_bit_identical_samples() {
        let phi_cmd_time_s = 12.345;
        let mut gnc = initialized(GncParameters {
            phi_cmd_time_s,
            ..paper_params()
        });
        let (mut pairs, mut late) = (0, 0);
        for k in 0..2000 {
            let t = k as f64 * H;
            gnc.inputs = navigation(k);
            let mut times = vec![
                t,
                gnc.time_s,
                t + 2e-9,
                t - 2e-9,
                f64::from_bits(t.to_bits() + 3),
                f64::from_bits(t.to_bits().saturating_sub(3)),
            ];
            if (t - phi_cmd_time_s).abs() < H {
                times.extend([phi_cmd_time_s - 2e-8, phi_cmd_time_s + 2e-8]);
            }
            late += usize::from(gnc.sample_time(t).off_nominal_bits.is_some());
            let at = |time_s| {
                let sample = LanderGnc {
                    time_s,
                    ..gnc.clone()
                }
                .evaluate();
                (exact(&sample.outputs), exact(&sample.guidance))
            };
            for (i, &a) in times.iter().enumerate() {
                for &b in &times[i + 1..] {
                    if a.to_bits() != b.to_bits() && gnc.sample_time(a) == gnc.sample_time(b) {
                        pairs += 1;
                        assert_eq!(at(a), at(b), "{a} and {b}");
                    }
                }
            }
            gnc.do_step(t, H, &mut Log::default()).unwrap();
        }
        assert!(pairs > 10_000, "{pairs}");
        assert!(late >= 2, "{late} late samples probed");
    }

    #[test]
    fn a_get_previews_exactly_the_sample_the_step_commits() {
        let mut gnc = initialized(paper_params());
        for k in 0..300 {
            let t = k as f64 * H;
            gnc.time_s = t;
            gnc.inputs = navigation(k);
            let mut get_log = Log::default();
            gnc.calculate_values(&mut get_log);
            let previewed = exact(&gnc.outputs);
            let mut step_log = Log::default();
            gnc.do_step(t, H, &mut step_log).unwrap();
            assert_eq!(exact(&gnc.outputs), previewed, "step {k}");
            assert_eq!(messages(&step_log), messages(&get_log), "step {k}");
        }
    }

    #[test]
    fn a_step_at_another_time_than_the_get_evaluates_afresh() {
        // GIVEN a get just before phi_cmd_time (12 s), where q_ref has no rotation yet
        let mut gnc = initialized(paper_params());
        gnc.time_s = 11.99;
        gnc.inputs = navigation(0);
        gnc.calculate_values(&mut Log::default());
        let previewed = exact(&gnc.outputs);
        // WHEN the step is taken at 12 s with the same inputs
        gnc.do_step(12.0, H, &mut Log::default()).unwrap();
        // THEN it commits the sample at 12 s, as an instance that had no get does
        let mut bare = initialized(paper_params());
        bare.inputs = navigation(0);
        bare.do_step(12.0, H, &mut Log::default()).unwrap();
        assert_eq!(exact(&gnc.outputs), exact(&bare.outputs));
        assert_ne!(exact(&gnc.outputs), previewed);
    }

    #[test]
    fn a_parameter_set_after_a_get_in_initialization_mode_is_used() {
        // GIVEN a get in initialization mode, then a new hover target
        let mut gnc = LanderGnc {
            inputs: navigation(0),
            ..LanderGnc::default()
        };
        gnc.calculate_values(&mut Log::default());
        let before = exact(&gnc.outputs);
        gnc.params.hover_target_nue_m = [40.0, 700.0, -30.0];
        // WHEN initialization ends and the first step is taken with the same inputs
        gnc.exit_initialization(0.0, &mut Log::default()).unwrap();
        gnc.do_step(0.0, H, &mut Log::default()).unwrap();
        // THEN the step commands towards the new target, as an instance that never saw the
        // old one does
        let mut fresh = initialized(GncParameters {
            hover_target_nue_m: [40.0, 700.0, -30.0],
            ..GncParameters::default()
        });
        fresh.inputs = navigation(0);
        fresh.do_step(0.0, H, &mut Log::default()).unwrap();
        assert_eq!(exact(&gnc.outputs), exact(&fresh.outputs));
        assert_ne!(exact(&gnc.outputs), before);
    }
}
