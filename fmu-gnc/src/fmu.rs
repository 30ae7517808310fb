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
use fmi_model::{decl, Declaration, Experiment, Log, Model, ModelError, StepEnd};
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

    fn declarations() -> &'static [Declaration<Self>] {
        DECLARATIONS
    }

    fn calculate_values(&mut self, log: &mut Log) {
        self.preview(log);
    }

    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        self.params
            .validate()
            .map_err(|e| ModelError::InvalidParameter {
                field: e.field,
                index: e.index,
                value: e.value,
                reason: e.reason.to_string(),
            })?;
        self.start_time_s = start_time;
        self.time_s = start_time;
        self.guidance = GuidanceState::initial(self.params.gravity_mps2);
        self.preview(log);
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        if !initialized {
            // Parameters are checked at exit_initialization; the memory is the initial one.
            return Ok(());
        }
        self.params
            .validate()
            .map_err(|e| ModelError::InvalidParameter {
                field: e.field,
                index: e.index,
                value: e.value,
                reason: e.reason.to_string(),
            })?;
        restored_guidance_inconsistency(
            &self.params,
            &self.guidance,
            self.start_time_s,
            self.time_s,
        )
        .map_or(Ok(()), |why| {
            Err(ModelError::Other(format!("restored state: {why}")))
        })
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

/// Why a guidance memory cannot be one the sequencer reached by `time_s` (a restored FMU
/// state), if it cannot: times not finite or out of order, a command or solve not finite, a
/// cycle solved in the future, a time-to-go beyond the descent's, a phase ahead of the
/// schedule or one the parameters never enter.
fn restored_guidance_inconsistency(
    params: &GncParameters,
    g: &GuidanceState,
    start_time_s: f64,
    time_s: f64,
) -> Option<String> {
    use crate::guidance::sequencer::Phase;
    let tolerance = |t: f64| 1e-9 * t.abs().max(1.0);
    if !(start_time_s.is_finite() && time_s.is_finite())
        || time_s < start_time_s - tolerance(start_time_s)
    {
        return Some(format!(
            "time {time_s} s before the start time {start_time_s} s"
        ));
    }
    let elapsed_s = time_s - start_time_s;
    let (cycle_now, _) = guidance_cycle_index(elapsed_s, params.guidance_cycle_s);
    if g.last_cycle.is_some_and(|k| k < 0 || k > cycle_now) {
        return Some(format!(
            "guidance cycle {:?} was never reached by t = {time_s} s",
            g.last_cycle
        ));
    }
    if !g.a_thrust_cmd_nue.iter().all(|a| a.is_finite()) {
        return Some("the held thrust command is not finite".into());
    }
    let scenario = params.scenario();
    let tgo_max = scenario.descent_time_to_go_s + tolerance(scenario.descent_time_to_go_s);
    if !(0.0..=tgo_max).contains(&g.time_to_go_s) {
        return Some(format!(
            "time to go {} s outside [0, {tgo_max}] s",
            g.time_to_go_s
        ));
    }
    if let Some(d) = &g.descent {
        let finite = d
            .cubic
            .coeffs
            .iter()
            .all(|c| c.iter().all(|v| v.is_finite()));
        if !finite
            || !(0.0..=elapsed_s + tolerance(elapsed_s)).contains(&d.solved_at_s)
            || !(0.0..=tgo_max).contains(&d.time_to_go_at_solve_s)
        {
            return Some("the descent solve is not finite or not from this run".into());
        }
    }
    let rank = |p: Phase| match p {
        Phase::InitialHover => 1,
        Phase::Descent => 2,
        Phase::TargetHover => 3,
        Phase::Hold | Phase::TerminalDescent => 4,
    };
    let scheduled = scenario.phase_at(elapsed_s + tolerance(elapsed_s));
    let never = match g.phase {
        Phase::Hold => scenario.terminal_descent_speed_mps > 0.0,
        Phase::TerminalDescent => scenario.terminal_descent_speed_mps <= 0.0,
        _ => false,
    };
    if never || rank(g.phase) > rank(scheduled) {
        return Some(format!(
            "guidance phase {:?} at t = {time_s} s, scheduled {scheduled:?}",
            g.phase
        ));
    }
    None
}

// ---- the declarations ------------------------------------------------------------------

fmi_model::enumeration! {
    ControlLaw = "ControlLaw", "Attitude control law" {
        Coupled: "coupled", "classical quaternion PD on q_ref";
        Decoupled: "decoupled", "decoupled thrust-axis control (the paper)";
        Reduced: "reduced", "PX4-style reduced attitude (Brescianini et al. 2013)";
    }
}

const NUE: &[&str] = &["North", "Up", "East"];
const BODY: &[&str] = &[
    "about body x (yaw)",
    "about body y (roll, thrust axis)",
    "about body z (pitch)",
];
const QUATERNION: &[&str] = &[
    "scalar part",
    "vector part x",
    "vector part y",
    "vector part z",
];

// Start values are those of `LanderGnc::default()`; bounds are those `GncParameters::validate`
// enforces on a single value (relations between parameters are checked there only).
#[rustfmt::skip]
static DECLARATIONS: &[Declaration<LanderGnc>] = &[
    // inputs: the plant's navigation state
    decl!(1, input r_nue[3]: inputs.r_nue_m, "m", "position", components = NUE),
    decl!(4, input v_nue[3]: inputs.v_nue_mps, "m/s", "velocity", components = NUE),
    decl!(7, input q_body_to_nue[4]: inputs.q_body_to_nue, "1", "attitude quaternion (Hamilton, body to NUE)", components = QUATERNION),
    decl!(11, input omega_body[3]: inputs.omega_body_radps, "rad/s", "body rate", components = BODY),
    decl!(14, input mass: inputs.mass_kg, "kg", "current mass"),
    // outputs: the commands
    decl!(100, output thrust_cmd: outputs.thrust_cmd_n, "N", "commanded total engine thrust along body +y"),
    decl!(101, output torque_cmd_body[3]: outputs.torque_cmd_body_nm, "N.m", "commanded control torque", components = BODY),
    // diagnostic outputs
    decl!(110, output a_cmd_nue[3]: outputs.a_cmd_nue_mps2, "m/s2", "commanded thrust acceleration (guidance net acceleration minus gravity)", components = NUE),
    decl!(113, output q_ref[4]: outputs.q_ref, "1", "reference attitude q_guid * q_phicmd", components = QUATERNION),
    decl!(117, output phi_b: outputs.phi_b_rad, "rad", "achieved rotation about the thrust axis (third 1-3-2 Euler angle)"),
    decl!(118, output err_roll: outputs.err_roll_rad, "rad", "thrust-axis (roll, body y) error the active law acts on"),
    decl!(119, output err_yaw: outputs.err_yaw_rad, "rad", "yaw (body x) error the active law acts on"),
    decl!(120, output err_pitch: outputs.err_pitch_rad, "rad", "pitch (body z) error the active law acts on"),
    decl!(121, output tilt_error: outputs.tilt_error_rad, "rad", "angle between the body thrust axis and the commanded thrust direction"),
    decl!(122, discrete_output guidance_phase: outputs.guidance_phase as i32, "guidance phase: 1 hover, 2 polynomial descent, 3 hover at the descent target, 4 hold, 5 terminal descent", int_min = 1, int_max = 5),
    decl!(123, output time_to_go: outputs.time_to_go_s, "s", "descent time-to-go at the last guidance sample (0 outside the descent)"),
    // parameters
    // An Integer in the model description, so that every master can select the law (libcosim
    // and Ecos ignore FMI 2.0 Enumerations); the values are listed from ControlLaw.
    decl!(200, parameter control_law: params.control_law as enum ControlLaw, "attitude control law", as_integer = true),
    decl!(201, parameter phi_cmd: params.phi_cmd_rad, "rad", "commanded rotation about the thrust axis (mission constraint)"),
    decl!(202, parameter phi_cmd_time: params.phi_cmd_time_s, "s", "time at which phi_cmd is applied (before it: 0)"),
    decl!(203, parameter control_bandwidth: params.control_bandwidth_hz, "Hz", "attitude control bandwidth f_c (omega_c = 2 pi f_c), > 0", above = 0.0),
    decl!(204, parameter control_damping: params.control_damping, "1", "attitude control damping ratio, > 0", above = 0.0),
    decl!(205, parameter guidance_bandwidth: params.guidance_bandwidth_hz, "Hz", "hover (PV) guidance bandwidth f_g (omega_g = 2 pi f_g), > 0 and <= 0.5 / guidance_cycle", above = 0.0),
    decl!(206, parameter guidance_damping: params.guidance_damping, "1", "hover (PV) guidance damping ratio, > 0", above = 0.0),
    decl!(207, parameter guidance_cycle: params.guidance_cycle_s, "s", "guidance cycle time (zero-order hold between solves), > 0", above = 0.0),
    decl!(208, parameter inertia_body[3]: params.inertia_body_kgm2, "kg.m2", "moment of inertia used for the gains, > 0", above = 0.0, components = BODY),
    decl!(211, parameter thrust_min: params.thrust_min_n, "N", "lowest commanded thrust (two engines at minimum throttle)", min = 0.0),
    decl!(212, parameter thrust_max: params.thrust_max_n, "N", "highest commanded thrust (two engines at full throttle), >= thrust_min", min = 0.0),
    decl!(213, parameter torque_limit_body[3]: params.torque_limit_body_nm, "N.m", "RCS torque limit", min = 0.0, components = BODY),
    decl!(216, parameter gravity: params.gravity_mps2, "m/s2", "lunar gravity magnitude g (gravity vector [0, -g, 0] NUE), > 0", above = 0.0),
    decl!(217, parameter hover_target_nue[3]: params.hover_target_nue_m, "m", "phase 1 hover target", components = NUE),
    decl!(220, parameter hover_duration: params.hover_duration_s, "s", "phase 1 (PV hover) duration from the start time", min = 0.0),
    decl!(221, parameter descent_target_nue[3]: params.descent_target_nue_m, "m", "phase 2 descent target and phase 3-4 hover point", components = NUE),
    decl!(224, parameter descent_time_to_go: params.descent_time_to_go_s, "s", "phase 2 (polynomial descent) time-to-go at its start, > 0", above = 0.0),
    decl!(225, parameter descent_freeze_time_to_go: params.descent_freeze_time_to_go_s, "s", "below this time-to-go the polynomial is no longer re-solved; >= guidance_cycle", above = 0.0),
    decl!(226, parameter target_hover_duration: params.target_hover_duration_s, "s", "phase 3 (PV hover at the descent target) duration; phase 4 holds there after it", min = 0.0),
    decl!(227, parameter reduced_yaw_weight: params.reduced_yaw_weight, "1", "reduced law: weight of the rotation about the thrust axis, in [0, 1]", min = 0.0, max = 1.0),
    decl!(228, parameter rate_shaping_margin: params.rate_shaping_margin, "1", "share of the torque limit the attitude laws count on to brake a rotation; large angle errors are shaped so the rate demand can be stopped in time (beyond the paper, ArduPilot-style square-root controller); 0.5 is a good choice; 0 = the paper's pure PD (default), in [0, 1]", min = 0.0, max = 1.0),
    decl!(229, parameter terminal_descent_speed: params.terminal_descent_speed_mps, "m/s", "phase 5 (beyond the paper): after the target hover, descend vertically over the descent target at this speed until touchdown; 0 = no terminal descent, hold the hover (default)", min = 0.0),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The declared bounds are the ones validation enforces: a value just past a declared
    /// bound is refused by the model's own validation, naming the declared field.
    #[test]
    fn declared_bounds_agree_with_the_validation() {
        let probed = fmi_testkit::assert_declared_bounds_are_validated::<LanderGnc>(|m| {
            m.params.validate().err().map(|e| e.field)
        });
        assert!(probed >= 20, "{probed}");
    }

    #[test]
    fn the_export_layer_accepts_the_declarations() {
        assert_eq!(fmi2_export::check_table::<LanderGnc>(), Ok(()));
    }

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

    #[test]
    fn a_reached_guidance_memory_is_accepted_and_a_doctored_one_refused() {
        use crate::guidance::sequencer::Phase;
        // GIVEN a run 20 s in, in the descent (after the 12 s hover)
        let mut gnc = LanderGnc::default();
        let mut log = Log::default();
        gnc.exit_initialization(0.0, &mut log).unwrap();
        for k in 0..200 {
            gnc.do_step(f64::from(k) * 0.1, 0.1, &mut log).unwrap();
        }
        assert_eq!(gnc.guidance.phase, Phase::Descent);
        assert_eq!(gnc.validate_restored(true), Ok(()));
        // WHEN its memory is doctored THEN each is refused, naming what is wrong
        type Doctor = fn(&mut LanderGnc);
        let doctored: [(&str, Doctor); 5] = [
            ("phase", |g| g.guidance.phase = Phase::TargetHover),
            ("phase", |g| g.guidance.phase = Phase::TerminalDescent),
            ("time to go", |g| g.guidance.time_to_go_s = 1e6),
            ("cycle", |g| g.guidance.last_cycle = Some(1_000_000)),
            ("time", |g| g.time_s = f64::NAN),
        ];
        for (what, doctor) in doctored {
            let mut restored = gnc.clone();
            doctor(&mut restored);
            let err = restored.validate_restored(true).unwrap_err().to_string();
            assert!(err.contains(what), "{what}: {err}");
        }
        // AND a parameter that exit_initialization would refuse is refused by name
        let mut restored = gnc.clone();
        restored.params.guidance_cycle_s = -1.0;
        assert!(matches!(
            restored.validate_restored(true),
            Err(ModelError::InvalidParameter {
                field: "guidance_cycle_s",
                ..
            })
        ));
    }
}
