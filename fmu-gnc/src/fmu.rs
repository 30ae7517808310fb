//! `LanderGnc` as an FMI 2.0 co-simulation model: the variable table (names per docs/interface.md)
//! and the sampled-data timing. All GNC math lives in the pure modules.
//!
//! Timing: a sampled-data controller with direct feedthrough. The outputs at communication
//! point `t` are a function of the inputs at `t` and the internal state: `calculate_values`
//! evaluates the sample at `t` without committing it; `do_step(t, h)` commits the sample taken
//! at `t` (guidance re-solve on a new guidance cycle, phase change) and advances to `t + h`.
//!
//! One evaluation of the attitude law per step, whatever the master's call order: a master
//! that reads the outputs and then steps at the same point has the evaluated sample's memory
//! committed as it is (when its inputs are bit-identical and its time is the same sample time,
//! see [`Evaluated`], [`SampleTime`]); a master that steps before reading has only the
//! sample's memory computed ([`gnc_advance`]: guidance and profile, no attitude law), since
//! nobody can read the outputs at `t` any more. Only the thruster model evaluates the law at
//! such a step, because its modulators integrate the commanded torque. Either way the
//! committed memory is bit-identical to `gnc_sample`'s at the master's `t`: gets never change
//! a trajectory.
use crate::actuation::{PwpfBank, RcsModel};
use crate::attitude::profile::PhiProfile;
use crate::attitude::{ControlLaw, GuidanceReference};
use crate::controller::{
    actuate, gnc_advance, gnc_advance_into, gnc_outputs_keeping_reference_in_place, gnc_sample,
    Advance, GncOutputs, NavigationInputs, Sample, QUATERNION_NORM_TOLERANCE,
};
use crate::guidance::retarget::MAX_DIVERT_TIME_S;
use crate::guidance::sequencer::{guidance_cycle_index, has_reached, GuidanceState};
use crate::params::{self, GncDesign, GncParameters};
use crate::supervision::consistency::Observation;
use crate::supervision::{feasibility, Supervisor};
use fmi_model::parameter::{check_declared, ParameterError};
use fmi_model::{
    decl, same_names, Declaration, Experiment, Log, MatchingRule, Model, ModelError, StepEnd,
    Terminal,
};
use lander_math::signal_groups as groups;
use nalgebra::Quaternion;
use serde::{Deserialize, Serialize};

/// The GNC FMU instance: parameters, latest inputs and outputs, guidance memory, time.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LanderGnc {
    params: GncParameters,
    inputs: NavigationInputs,
    outputs: GncOutputs,
    guidance: GuidanceState,
    profile: PhiProfile,
    /// The thruster modulators (thruster model).
    pwpf: PwpfBank,
    /// Whether a step of another length than rcs_duty_period has been reported.
    period_mismatch_reported: bool,
    start_time_s: f64,
    time_s: f64,
    /// Set by `exit_initialization`: the parameters are fixed from then on.
    initialized: bool,
    /// Feasibility and input consistency findings (observes only).
    supervisor: Supervisor,
    /// The supervision's outputs as the last get showed them.
    supervision_outputs: SupervisionOutputs,
    /// Derived from the parameters once they are fixed; a restored or deserialized instance
    /// derives it again at its first evaluation.
    #[serde(skip)]
    design: Option<GncDesign>,
    /// A cache, not state: a restored or deserialized instance evaluates afresh.
    #[serde(skip)]
    evaluated: Evaluated,
    /// The reference attitude of the last guidance command shown, kept for the samples that
    /// hold it (a cache keyed by the bits it was computed from, not state).
    #[serde(skip)]
    reference: Option<GuidanceReference>,
}

/// The supervision's outputs: its findings so far and the residuals of the last window.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
struct SupervisionOutputs {
    status: i32,
    attitude_residual_rad: f64,
    position_residual_m: f64,
    acceleration_residual_mps2: f64,
    angular_response: f64,
}

/// The latest sample evaluated without being committed, with the time and inputs it was
/// evaluated at. It is only valid while the parameters, the start time and the guidance
/// state are those it was evaluated with: these change only in `exit_initialization`
/// (which evaluates and stores afresh) and in `do_step` (which consumes it); a parameter
/// set in initialization mode is followed by `exit_initialization`; a reset and
/// restoring an FMU state replace the whole instance, this cache included. Kept in place
/// with a validity mark rather than as an `Option`: a read writes the memory where it
/// stays, not into a value moved there.
#[derive(Debug, Clone, Default)]
struct Evaluated {
    /// Whether the rest holds a sample not yet consumed.
    valid: bool,
    /// The time it was evaluated at, exactly: a step from that very time needs no
    /// [`SampleTime`] comparison.
    t_bits: u64,
    /// The guidance cycle of that time; with it the [`SampleTime`] of the sample is worked
    /// out only for a step from another time (the state it depends on is that of the
    /// evaluation while the sample is valid).
    cycle: (i64, bool),
    input_bits: [u64; 14],
    /// The memory the sample leaves (its outputs are in `LanderGnc::outputs`); its guidance
    /// state only if `solves` (else the guidance memory stays as it is).
    advance: Advance,
    /// The sample solved a guidance cycle: `advance.guidance` holds the new memory.
    solves: bool,
    /// The thrust-axis profile is shaped: `advance.profile` holds its new memory (without
    /// shaping it stays as it is).
    profile_moves: bool,
    /// The modulators after the coming period, for this sample's duties (thruster model:
    /// `pwpf_moves`; without thrusters they stay as they are and this is not written).
    pwpf: PwpfBank,
    pwpf_moves: bool,
}

impl Evaluated {
    /// The [`SampleTime`] of the kept sample, for `gnc` as it was evaluated in (the kept
    /// sample is valid).
    fn time(&self, gnc: &LanderGnc) -> SampleTime {
        gnc.sample_time_in(f64::from_bits(self.t_bits), self.cycle)
    }

    /// Whether the kept sample opens its guidance cycle (`SampleTime::opens_cycle`).
    fn opens_cycle(&self, gnc: &LanderGnc) -> bool {
        gnc.guidance.last_cycle != Some(self.cycle.0)
    }
}

/// All that `gnc_sample` reads of its time `t` (for given parameters, start time and
/// guidance state): whether phi_cmd applies and the guidance cycle `t` falls in; `t` itself
/// only when it opens that cycle off its nominal start (a late sample, after degenerate
/// inputs), the one case in which the sequencer solves at the sample's own time. Equal keys give bit-identical samples, so a master's `t` a few
/// ulps off ours (`k h` against our `(k - 1) h + h`, a third of the steps of a 0.01 s grid)
/// still commits the kept sample; tests below check the equivalence against `gnc_sample`.
/// A shaped thrust-axis profile is a function of `t` itself: with it on, the key holds `t`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct SampleTime {
    phi_cmd_applies: bool,
    cycle: i64,
    /// The sample solves the guidance cycle (the guidance state has not yet): only then do
    /// the navigation inputs reach the guidance memory.
    opens_cycle: bool,
    off_nominal_bits: Option<u64>,
    /// A shaped thrust-axis profile moves with `t` itself.
    profile_bits: Option<u64>,
}

impl Default for LanderGnc {
    fn default() -> Self {
        let params = GncParameters::default();
        Self {
            params,
            inputs: NavigationInputs::default(),
            outputs: GncOutputs::default(),
            guidance: GuidanceState::initial(params.gravity_mps2),
            profile: PhiProfile::default(),
            pwpf: PwpfBank::default(),
            period_mismatch_reported: false,
            start_time_s: 0.0,
            time_s: 0.0,
            initialized: false,
            supervisor: Supervisor::default(),
            supervision_outputs: SupervisionOutputs {
                angular_response: 1.0,
                ..SupervisionOutputs::default()
            },
            design: None,
            evaluated: Evaluated::default(),
            reference: None,
        }
    }
}

impl GncParameters {
    /// Every check of the parameters (what [`GncParameters::design`] runs): each value
    /// against its declaration, as the FMI layer checks it on every set, then
    /// [`GncParameters::validate`].
    pub fn check(&self) -> Result<(), ParameterError> {
        check_declared(&LanderGnc {
            params: *self,
            ..LanderGnc::default()
        })?;
        self.validate()
    }
}

impl LanderGnc {
    /// Whether the kept sample's time is the same sample time as the current one (out of
    /// line: a master whose time is ours to the bit needs no key).
    #[inline(never)]
    fn same_sample_time(&self, e: &Evaluated) -> bool {
        e.time(self) == self.sample_time(self.time_s)
    }

    /// The [`SampleTime`] of the sample at `t_s`, mirroring how `gnc_sample` and the guidance
    /// sequencer use the time.
    fn sample_time(&self, t_s: f64) -> SampleTime {
        self.sample_time_in(t_s, self.cycle_at(t_s))
    }

    /// The guidance cycle the sample at `t_s` falls in, as `gnc_advance` finds it.
    fn cycle_at(&self, t_s: f64) -> (i64, bool) {
        guidance_cycle_index(t_s - self.start_time_s, self.params.guidance_cycle_s)
    }

    /// [`Self::sample_time`] with [`Self::cycle_at`] of `t_s` given.
    fn sample_time_in(&self, t_s: f64, (cycle, on_boundary): (i64, bool)) -> SampleTime {
        let elapsed_s = t_s - self.start_time_s;
        let opens_cycle = self.guidance.last_cycle != Some(cycle);
        SampleTime {
            phi_cmd_applies: has_reached(t_s, self.params.phi_cmd_time_s),
            cycle,
            opens_cycle,
            off_nominal_bits: (opens_cycle && !on_boundary).then_some(elapsed_s.to_bits()),
            profile_bits: (self.params.phi_rate_limit_radps > 0.0
                || self.params.phi_accel_limit_radps2 > 0.0)
                .then_some(t_s.to_bits()),
        }
    }

    /// Keeps the design once the parameters are fixed (after initialization, or in a restored
    /// instance, which was initialized); in initialization mode it is derived per evaluation,
    /// as a parameter may still change.
    fn keep_design(&mut self) {
        if self.initialized && self.design.is_none() {
            self.design = Some(self.params.design_unchecked());
        }
    }

    /// The sample at the current time, its duties included, and the modulators after it.
    #[inline(always)]
    fn evaluate(&self) -> (Sample, PwpfBank) {
        #[cfg(test)]
        tests::EVALUATIONS.with(|n| n.set(n.get() + 1));
        let unchecked;
        let design = match &self.design {
            Some(design) => design,
            None => {
                unchecked = self.params.design_unchecked();
                &unchecked
            }
        };
        let mut sample = gnc_sample(
            design,
            self.start_time_s,
            &self.guidance,
            &self.profile,
            &self.inputs,
            self.time_s,
        );
        let pwpf = actuate(design, &mut sample.outputs, &self.pwpf);
        (sample, pwpf)
    }

    /// Evaluate the sample at the current time without committing it, show its outputs and
    /// keep its memory for the `do_step` that usually follows.
    fn preview(&mut self, log: &mut Log) {
        self.keep_design();
        if !self.initialized {
            if let Err(e) = self.params.check() {
                log.warning(format!(
                    "{e}: the end of initialization will refuse it; the outputs shown until \
                     then are provisional"
                ));
            }
        }
        #[cfg(test)]
        tests::EVALUATIONS.with(|n| n.set(n.get() + 1));
        // As `evaluate`, with the outputs computed where the getters read them.
        let unchecked;
        let design = match &self.design {
            Some(design) => design,
            None => {
                unchecked = self.params.design_unchecked();
                &unchecked
            }
        };
        let cycle = self.cycle_at(self.time_s);
        let kept = &mut self.evaluated;
        // Written in place, the guidance memory only when the sample solves a cycle (one
        // sample in ten at 100 Hz): the others hold it as it is.
        kept.solves = gnc_advance_into(
            design,
            self.start_time_s,
            &self.guidance,
            &self.profile,
            &self.inputs,
            self.time_s,
            cycle,
            &mut kept.advance,
        );
        kept.profile_moves = design.roll_profile.is_some();
        let next = if kept.solves {
            &kept.advance.guidance
        } else {
            &self.guidance
        };
        gnc_outputs_keeping_reference_in_place(
            design,
            &kept.advance,
            next,
            &self.guidance,
            &self.inputs,
            &mut self.outputs,
            &mut self.reference,
        );
        kept.pwpf_moves = design.thrusters.is_some();
        if kept.pwpf_moves {
            kept.pwpf = actuate(design, &mut self.outputs, &self.pwpf);
        }
        kept.t_bits = self.time_s.to_bits();
        kept.cycle = cycle;
        kept.input_bits = self.inputs.to_bits();
        kept.valid = true;
        report(&kept.advance, self.time_s, log);
        let residuals = self.supervisor.residuals();
        self.supervision_outputs = SupervisionOutputs {
            status: self.supervisor.status(),
            attitude_residual_rad: residuals.attitude_rad,
            position_residual_m: residuals.position_m,
            acceleration_residual_mps2: residuals.acceleration_mps2,
            angular_response: residuals.angular_response,
        };
        // Validated parameters give finite outputs for the finite inputs the layer admits;
        // before the end of initialization has validated them, the outputs shown are
        // provisional and may not be.
        if !self.initialized && self.outputs.zero_non_finite() {
            log.warning(format!(
                "t = {} s: the parameters give non-finite outputs (shown as 0); \
                 the end of initialization will name the parameter",
                self.time_s
            ));
        }
    }

    /// Commit the sample at the current time: the memory of the evaluated one if it was
    /// evaluated at the same sample time with these very inputs, or with other inputs when
    /// these cannot reach the memory (see [`Self::inputs_reach_memory`]); otherwise computed
    /// afresh, without the attitude law unless the thruster modulators need its torque. The
    /// outputs are left as the last get showed them: the layer evaluates at `t + h` for the
    /// next get.
    fn commit(&mut self, log: &mut Log) {
        self.keep_design();
        // Read in place: the kept memory is a few hundred bytes, worth not moving twice.
        let same_time =
            |e: &Evaluated| e.t_bits == self.time_s.to_bits() || self.same_sample_time(e);
        // The attitude the sample normalised from these very inputs, when it used them as
        // they came: the input monitor's reading of them as given, bit for bit.
        let attitude = match &self.evaluated {
            // A sample that solves no guidance cycle leaves the guidance memory as it is,
            // and one without thrusters the modulators: nothing to copy back then.
            e if e.valid && self.inputs.has_bits(&e.input_bits) && same_time(e) => {
                report(&e.advance, self.time_s, log);
                if e.solves {
                    self.guidance = e.advance.guidance;
                }
                if e.profile_moves {
                    self.profile = e.advance.profile;
                }
                if e.pwpf_moves {
                    self.pwpf = e.pwpf;
                }
                as_given(&e.advance)
            }
            // A master that steps before it reads (fmpy's loop, Jacobi) evaluated the
            // previous inputs at this time.
            e if e.valid && !self.inputs_reach_memory(e) && same_time(e) => {
                if e.solves {
                    self.guidance = e.advance.guidance;
                }
                if e.profile_moves {
                    self.profile = e.advance.profile;
                }
                None
            }
            _ => {
                let (advance, pwpf) = self.advance_without_outputs();
                report(&advance, self.time_s, log);
                self.guidance = advance.guidance;
                self.profile = advance.profile;
                self.pwpf = pwpf;
                as_given(&advance)
            }
        };
        self.evaluated.valid = false;
        self.supervise(attitude, log);
    }

    /// The supervision of the committed sample: the inputs at the current time with the
    /// command last shown, which is the one acting from now on whatever the master's order
    /// (read before the step, or after the previous one).
    /// `attitude` is the inputs' quaternion normalised as they came, if the caller has it.
    fn supervise(&mut self, attitude: Option<Quaternion<f64>>, log: &mut Log) {
        let p = &self.params;
        let derived;
        let settings = match &self.design {
            Some(design) => &design.supervision,
            None => {
                derived = p.supervision_settings();
                &derived
            }
        };
        let nav = &self.inputs;
        // Forces other than thrust and gravity: the gear on the ground, after the engine cut.
        let height_m = nav.r_nue_m[1] - p.terminal_ground_height_m;
        let ground_contact_possible = self.guidance.engine_cut
            || (self.guidance.phase == crate::guidance::sequencer::Phase::TerminalDescent
                && height_m < GROUND_CONTACT_HEIGHT_M);
        *self.supervisor.incoming() = Observation {
            t_s: self.time_s,
            r_nue_m: nav.r_nue_m,
            v_nue_mps: nav.v_nue_mps,
            q_body_to_nue: nav.q_body_to_nue,
            omega_body_radps: nav.omega_body_radps,
            mass_kg: nav.mass_kg,
            thrust_cmd_n: self.outputs.thrust_cmd_n,
            torque_cmd_body_nm: self.outputs.torque_cmd_body_nm,
            ground_contact_possible,
        };
        let (tilt_error_rad, time_s) = (self.outputs.tilt_error_rad, self.time_s);
        self.supervisor
            .observe(settings, attitude, tilt_error_rad, &mut |message| {
                log.warning(format!("t = {time_s} s: {message}"));
            });
    }

    /// Whether the memory a sample at the time of `e` commits may differ from `e`'s for the
    /// current inputs, or they are to be reported. They reach the guidance memory only
    /// when the sample opens a guidance cycle, the modulators only in the thruster model
    /// (the profile is a function of time alone); inputs with a quaternion of norm near 1
    /// and a positive mass are used as they are, with nothing to report (conservatively
    /// what `gnc_advance` accepts without a warning).
    fn inputs_reach_memory(&self, e: &Evaluated) -> bool {
        let torque_model = self.design.as_ref().is_some_and(|d| d.thrusters.is_none());
        let q = self.inputs.q_body_to_nue;
        let norm_squared: f64 = q.iter().map(|c| c * c).sum();
        let plain =
            (norm_squared - 1.0).abs() <= QUATERNION_NORM_TOLERANCE && self.inputs.mass_kg > 0.0;
        e.opens_cycle(self) || !torque_model || !plain
    }

    /// The memory of the sample at the current time, with the modulators after it.
    fn advance_without_outputs(&self) -> (Advance, PwpfBank) {
        if let Some(design) = self.design.as_ref().filter(|d| d.thrusters.is_none()) {
            let advance = gnc_advance(
                design,
                self.start_time_s,
                &self.guidance,
                &self.profile,
                &self.inputs,
                self.time_s,
            );
            (advance, self.pwpf)
        } else {
            let (sample, pwpf) = self.evaluate();
            (sample.advance, pwpf)
        }
    }
}

/// Height above `terminal_ground_height` below which, in the terminal descent, the gear may
/// touch: the legs and a margin for the terrain.
const GROUND_CONTACT_HEIGHT_M: f64 = 5.0;

/// The sample's attitude when it is its quaternion input normalised as it came (a norm
/// near 1: not rescaled before normalising).
#[inline(always)]
fn as_given(advance: &Advance) -> Option<Quaternion<f64>> {
    match advance.non_unit_quaternion_norm {
        None => advance.attitude.map(|q| q.into_inner()),
        Some(_) => None,
    }
}

/// Log what the sample found wrong with its inputs, if anything.
#[inline(always)]
fn report(advance: &Advance, time_s: f64, log: &mut Log) {
    if advance.non_unit_quaternion_norm.is_some() || advance.degenerate.is_some() {
        report_inputs(advance, time_s, log);
    }
}

#[cold]
#[inline(never)]
fn report_inputs(advance: &Advance, time_s: f64, log: &mut Log) {
    if let Some(norm) = advance.non_unit_quaternion_norm {
        log.warning(format!(
            "t = {time_s} s: q_body_to_nue has norm {norm:e}, not 1; used normalised"
        ));
    }
    if let Some(why) = advance.degenerate {
        log.warning(format!("t = {time_s} s: {why}"));
    }
}

const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "navigation",
        matching_rule: MatchingRule::Plug,
        kind: groups::NAVIGATION_KIND,
        description: "The vehicle state guidance and control act on (from the plant, \
                      LanderNav or a filter)",
        members: &same_names(groups::NAVIGATION),
    },
    Terminal {
        name: "commands",
        matching_rule: MatchingRule::Plug,
        kind: groups::COMMANDS_KIND,
        description: "Thrust, torque and RCS duty commands, for the plant",
        members: &same_names(groups::COMMANDS),
    },
];

impl Model for LanderGnc {
    const MODEL_IDENTIFIER: &'static str = "LanderGnc";
    const MODEL_NAME: &'static str = "LanderGnc";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str =
        "Lunar lander guidance (PV hover, cubic-polynomial descent) and \
        attitude control (the laws of the ControlLaw type) after Rallapalli et al., \
        'Decoupled Thrust-Axis Attitude Control Using Quaternions for Chandrayaan-3'";
    /// 2: the thrust-axis profile and the initialization flag; 3: and the RCS thruster
    /// model's modulators.
    /// 5: and the supervision; 6: its input monitor's window keeps the thrust axis and
    /// which mistakes it integrates; 7: and its last two observations in turn, in place of
    /// the newest alone.
    const STATE_VERSION: u32 = 7;
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn declarations() -> &'static [Declaration<Self>] {
        DECLARATIONS
    }

    fn terminals() -> &'static [Terminal] {
        TERMINALS
    }

    fn calculate_values(&mut self, log: &mut Log) {
        self.preview(log);
    }

    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        let design = self.params.design().map_err(ModelError::from)?;
        self.design = Some(design);
        self.initialized = true;
        self.start_time_s = start_time;
        self.time_s = start_time;
        self.guidance = GuidanceState::initial(self.params.gravity_mps2);
        self.profile = PhiProfile::default();
        self.pwpf = PwpfBank::default();
        self.supervisor = Supervisor::default();
        let p = &self.params;
        for message in self
            .supervisor
            .parameters(feasibility::bandwidth_out_of_reach(
                p.control_bandwidth_hz,
                p.inertia_body_kgm2,
                p.torque_limit_body_nm,
            ))
        {
            log.warning(message);
        }
        self.preview(log);
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        if !initialized {
            // Parameters are checked at exit_initialization; the memory is the initial one.
            return Ok(());
        }
        self.params.check()?;
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

    const PROVIDES_DIRECTIONAL_DERIVATIVES: bool = true;

    /// The partials of the sample at the current time (`derivatives.rs`: which, and why).
    fn directional_derivative(
        &mut self,
        unknowns: &[fmi_model::ScalarRef],
        knowns: &[fmi_model::ScalarRef],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<(), ModelError> {
        self.keep_design();
        let unchecked;
        let design = match &self.design {
            Some(design) => design,
            None => {
                unchecked = self.params.design_unchecked();
                &unchecked
            }
        };
        let at = crate::derivatives::At {
            design,
            start_time_s: self.start_time_s,
            guidance: &self.guidance,
            profile: &self.profile,
            inputs: &self.inputs,
            time_s: self.time_s,
        };
        let name = |r: &fmi_model::ScalarRef| (DECLARATIONS[r.declaration].name, r.element);
        crate::derivatives::by_name(
            &at,
            unknowns.iter().map(name),
            knowns.iter().map(name),
            seed,
            sensitivity,
        )
        .map_err(ModelError::Refused)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError> {
        // The master's t is authoritative: it may differ from ours by rounding (and then the
        // sample kept from the get is not used).
        self.time_s = t;
        let period = self.params.rcs_duty_period_s;
        let thrusters = self.params.rcs() == RcsModel::Thrusters;
        if thrusters && (h - period).abs() > 1e-9 * period && !self.period_mismatch_reported {
            self.period_mismatch_reported = true;
            log.warning(format!(
                "t = {t} s: communication step {h} s differs from rcs_duty_period = {period} s: \
                 the duties are fractions of rcs_duty_period, the plant applies them to its step"
            ));
        }
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
    if !g.a_thrust_cmd_nue.0.iter().all(|a| a.is_finite()) {
        return Some("the held thrust command is not finite".into());
    }
    let scenario = params.scenario();
    let plan = g.retarget.as_ref();
    if let Some(p) = plan {
        let commanded = scenario
            .retarget
            .is_some_and(|r| elapsed_s + tolerance(elapsed_s) >= r.time_s);
        let finite = p.site_nue.0.iter().all(|x| x.is_finite())
            && p.lateral_authority_mps2.is_finite()
            && p.descent_start_s.is_finite()
            && p.descent_end_s.is_finite();
        if !commanded
            || !finite
            || p.descent_start_s < 0.0
            || p.descent_end_s < p.descent_start_s
            || p.descent_end_s - p.descent_start_s
                > MAX_DIVERT_TIME_S.max(scenario.descent_time_to_go_s)
                    + tolerance(MAX_DIVERT_TIME_S)
        {
            return Some("the retarget plan is not finite or not from this run".into());
        }
    }
    let descent_length_s = plan.map_or(scenario.descent_time_to_go_s, |p| {
        p.descent_end_s - p.descent_start_s
    });
    let tgo_max = descent_length_s + tolerance(descent_length_s);
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
            .all(|c| c.0.iter().all(|v| v.is_finite()));
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
    let scheduled = scenario.phase_with(plan, elapsed_s + tolerance(elapsed_s));
    let never = match g.phase {
        Phase::Hold => scenario.terminal.enabled(),
        Phase::TerminalDescent => !scenario.terminal.enabled(),
        _ => g.engine_cut,
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
    RcsModel = "RcsModel", "How the RCS is commanded" {
        Torque: "torque", "a torque per axis, torque_cmd_body (the paper)";
        Thrusters: "thrusters", "eight thrusters: allocation of torque_cmd_body, PWPF modulation, rcs_duty";
    }
}

const THRUSTERS: &[&str] = &[
    "thruster 1",
    "thruster 2",
    "thruster 3",
    "thruster 4",
    "thruster 5",
    "thruster 6",
    "thruster 7",
    "thruster 8",
];
const THRUSTER_XYZ: &[&str] = &[
    "thruster 1, body x",
    "thruster 1, body y",
    "thruster 1, body z",
    "thruster 2, body x",
    "thruster 2, body y",
    "thruster 2, body z",
    "thruster 3, body x",
    "thruster 3, body y",
    "thruster 3, body z",
    "thruster 4, body x",
    "thruster 4, body y",
    "thruster 4, body z",
    "thruster 5, body x",
    "thruster 5, body y",
    "thruster 5, body z",
    "thruster 6, body x",
    "thruster 6, body y",
    "thruster 6, body z",
    "thruster 7, body x",
    "thruster 7, body y",
    "thruster 7, body z",
    "thruster 8, body x",
    "thruster 8, body y",
    "thruster 8, body z",
];
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
    decl!(130, output rcs_duty[8]: outputs.rcs_duty, "1", "thruster model: fraction of the coming rcs_duty_period each RCS thruster fires, from its start (PWPF of the allocated torque); 0 in the torque model", components = THRUSTERS),
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
    // supervision (observes only; docs/interface.md, bringing your own vehicle)
    decl!(124, discrete_output monitor_status: supervision_outputs.status as i32, "supervision findings so far, a sum of bits: 1 attitude vs body rates, 2 position vs velocity, 4 velocity change vs thrust and gravity, 8 angular response vs torque and inertia, 16 weight above thrust_max, 32 control_bandwidth beyond the torque limit, 64 thrust pinned at a limit, 128 torque pinned at a limit, 256 tilt error beyond 90 deg; 0 = none", int_min = 0, int_max = 511),
    decl!(125, output monitor_attitude_residual: supervision_outputs.attitude_residual_rad, "rad", "input monitor: angle between the attitude's change and the integrated omega_body over the last window"),
    decl!(126, output monitor_position_residual: supervision_outputs.position_residual_m, "m", "input monitor: distance between the position's change and the integrated v_nue over the last window"),
    decl!(127, output monitor_acceleration_residual: supervision_outputs.acceleration_residual_mps2, "m/s2", "input monitor: difference between the velocity's change and gravity plus thrust_cmd / mass along body +y over the last window"),
    decl!(128, output monitor_angular_response: supervision_outputs.angular_response, "1", "input monitor: the body rates' change over what torque_cmd_body predicts for inertia_body in the last window judged (1 = as predicted)"),
    // parameters
    // An Integer in the model description, so that every master can select the law (libcosim
    // and Ecos ignore FMI 2.0 Enumerations); the values are listed from ControlLaw's table (attitude/mod.rs).
    decl!(200, parameter control_law: params.control_law as enum ControlLaw, "attitude control law", as_integer = true),
    decl!(201, parameter phi_cmd: params.phi_cmd_rad, "rad", "commanded rotation about the thrust axis (mission constraint), within +-4 pi", min = -params::MAX_PHI_CMD_RAD, max = params::MAX_PHI_CMD_RAD),
    decl!(202, parameter phi_cmd_time: params.phi_cmd_time_s, "s", "time at which phi_cmd is applied (before it: 0)"),
    decl!(203, parameter control_bandwidth: params.control_bandwidth_hz, "Hz", "attitude control bandwidth f_c (omega_c = 2 pi f_c), > 0", above = 0.0),
    decl!(204, parameter control_damping: params.control_damping, "1", "attitude control damping ratio, in (0, 100]", above = 0.0, max = params::MAX_DAMPING),
    decl!(205, parameter guidance_bandwidth: params.guidance_bandwidth_hz, "Hz", "hover (PV) guidance bandwidth f_g (omega_g = 2 pi f_g), > 0 and <= 0.5 / guidance_cycle", above = 0.0),
    decl!(206, parameter guidance_damping: params.guidance_damping, "1", "hover (PV) guidance damping ratio, in (0, 100]", above = 0.0, max = params::MAX_DAMPING),
    decl!(207, parameter guidance_cycle: params.guidance_cycle_s, "s", "guidance cycle time (zero-order hold between solves), >= 1 ms", min = params::MIN_GUIDANCE_CYCLE_S),
    decl!(208, parameter inertia_body[3]: params.inertia_body_kgm2, "kg.m2", "moment of inertia used for the gains, in (0, 1e9]", above = 0.0, max = params::MAX_INERTIA_KGM2, components = BODY),
    decl!(211, parameter thrust_min: params.thrust_min_n, "N", "lowest commanded thrust (two engines at minimum throttle), <= thrust_max", min = 0.0),
    decl!(212, parameter thrust_max: params.thrust_max_n, "N", "highest commanded thrust (two engines at full throttle), >= thrust_min, <= 1e9", min = 0.0, max = params::MAX_THRUST_N),
    decl!(213, parameter torque_limit_body[3]: params.torque_limit_body_nm, "N.m", "RCS torque limit, in [0, 1e9]", min = 0.0, max = params::MAX_TORQUE_NM, components = BODY),
    decl!(216, parameter gravity: params.gravity_mps2, "m/s2", "lunar gravity magnitude g (gravity vector [0, -g, 0] NUE), in (0, 100]", above = 0.0, max = params::MAX_GRAVITY_MPS2),
    decl!(217, parameter hover_target_nue[3]: params.hover_target_nue_m, "m", "phase 1 hover target, each within +-1e7 m", min = -params::MAX_TARGET_M, max = params::MAX_TARGET_M, components = NUE),
    decl!(220, parameter hover_duration: params.hover_duration_s, "s", "phase 1 (PV hover) duration from the start time, <= 1e6 s", min = 0.0, max = params::MAX_DURATION_S),
    decl!(221, parameter descent_target_nue[3]: params.descent_target_nue_m, "m", "phase 2 descent target and phase 3-4 hover point, each within +-1e7 m", min = -params::MAX_TARGET_M, max = params::MAX_TARGET_M, components = NUE),
    decl!(224, parameter descent_time_to_go: params.descent_time_to_go_s, "s", "phase 2 (polynomial descent) time-to-go at its start, in (0, 1e6]", above = 0.0, max = params::MAX_DURATION_S),
    decl!(225, parameter descent_freeze_time_to_go: params.descent_freeze_time_to_go_s, "s", "below this time-to-go the polynomial is no longer re-solved; >= guidance_cycle, <= 1e6 s", above = 0.0, max = params::MAX_DURATION_S),
    decl!(226, parameter target_hover_duration: params.target_hover_duration_s, "s", "phase 3 (PV hover at the descent target) duration; phase 4 holds there after it; <= 1e6 s", min = 0.0, max = params::MAX_DURATION_S),
    decl!(227, parameter reduced_yaw_weight: params.reduced_yaw_weight, "1", "reduced law: weight of the rotation about the thrust axis, in [0, 1]", min = 0.0, max = 1.0),
    decl!(228, parameter rate_shaping_margin: params.rate_shaping_margin, "1", "share of the torque limit the attitude laws count on to brake a rotation; large angle errors are shaped so the rate demand can be stopped in time (beyond the paper, ArduPilot-style square-root controller); 0.5 is a good choice; 0 = the paper's pure PD (default), in [0, 1]", min = 0.0, max = 1.0),
    decl!(300, parameter rcs_model: params.rcs_model as enum RcsModel, "RCS model: 1 torque per axis (default, the paper), 2 eight thrusters driven by rcs_duty", as_integer = true),
    decl!(301, parameter rcs_thruster_force: params.rcs_thruster_force_n, "N", "thruster model: force of one RCS thruster, as the plant's", above = 0.0),
    decl!(302, parameter rcs_position_body[24]: params.rcs_position_body_m, "m", "thruster model: nozzle position of thruster k (elements 3k+1..3k+3) relative to the centre of mass, as the plant's", components = THRUSTER_XYZ),
    decl!(326, parameter rcs_direction_body[24]: params.rcs_direction_body, "1", "thruster model: unit direction of the force of thruster k (elements 3k+1..3k+3), as the plant's", components = THRUSTER_XYZ),
    decl!(355, parameter rcs_tilt_first: params.rcs_tilt_first as bool, "thruster model: a torque beyond the thrusters' reach keeps its tilt part (body x, z) and gives the roll (body y) what is left (true, default), or keeps its direction (false)"),
    decl!(350, parameter pwpf_gain: params.pwpf_gain, "1", "thruster model: PWPF filter gain Km (filter Tm x' = Km (u - y) - x on the thrust fraction u and thruster output y)", above = 0.0),
    decl!(351, parameter pwpf_time_constant: params.pwpf_time_constant_s, "s", "thruster model: PWPF filter time constant Tm", above = 0.0),
    decl!(352, parameter pwpf_on_threshold: params.pwpf_on_threshold, "1", "thruster model: PWPF trigger on threshold Uon, > pwpf_off_threshold"),
    decl!(353, parameter pwpf_off_threshold: params.pwpf_off_threshold, "1", "thruster model: PWPF trigger off threshold Uoff, > 0", above = 0.0),
    decl!(354, parameter rcs_duty_period: params.rcs_duty_period_s, "s", "thruster model: the period a duty is a fraction of; set it to the communication step", above = 0.0),
    decl!(229, parameter terminal_descent_speed: params.terminal_descent_speed_mps, "m/s", "phase 5 (beyond the paper): after the target hover, descend vertically over the descent target at this speed until touchdown; 0 = no terminal descent, hold the hover (default)", min = 0.0),
    decl!(238, parameter terminal_final_speed: params.terminal_final_speed_mps, "m/s", "terminal descent: the sink rate near the ground the profile slows to (with terminal_flare_time > 0), in [0, terminal_descent_speed]", min = 0.0),
    decl!(239, parameter terminal_flare_time: params.terminal_flare_time_s, "s", "terminal descent: time constant of the slowing sink, sink = clamp(height / terminal_flare_time, terminal_final_speed, terminal_descent_speed), height above terminal_ground_height; 0 = a constant terminal_descent_speed (default), <= 1e6 s", min = 0.0, max = params::MAX_DURATION_S),
    decl!(240, parameter terminal_ground_height: params.terminal_ground_height_m, "m", "terminal descent: Up coordinate of the ground under the site the profile's heights count from, within +-1e7 m", min = -params::MAX_TARGET_M, max = params::MAX_TARGET_M),
    decl!(241, parameter engine_cutoff_height: params.engine_cutoff_height_m, "m", "terminal descent: at a guidance cycle at or below this height above terminal_ground_height, thrust_cmd becomes 0 for the rest of the flight (the attitude held upright); negative = never (default), <= 1e4 m", max = 1e4),
    decl!(230, parameter phi_rate_limit: params.phi_rate_limit_radps, "rad/s", "shaped thrust-axis manoeuvre (beyond the paper): the reference follows phi_cmd at most this fast, the rate fed forward; 0 = unlimited; with phi_accel_limit also 0, the paper's step (default); <= 100", min = 0.0, max = params::MAX_PHI_RATE_RADPS),
    decl!(231, parameter phi_accel_limit: params.phi_accel_limit_radps2, "rad/s2", "shaped thrust-axis manoeuvre: the reference's angular acceleration limit (bang-coast-bang profile), fed forward as torque; 0 = unlimited; <= 1e4", min = 0.0, max = params::MAX_PHI_ACCEL_RADPS2),
    decl!(232, parameter retarget_time: params.retarget_time_s, "s", "retarget (beyond the paper): time after the start time (the phase schedule's clock) at which the site becomes retarget_site_nue; from the guidance cycle at or after it the guidance re-plans to the new site (docs/retarget.md); negative = never (default); <= 1e6 s", max = params::MAX_DURATION_S),
    decl!(233, parameter retarget_site_nue[3]: params.retarget_site_nue_m, "m", "retarget: the new site, the hover point replacing descent_target_nue from retarget_time on (the terminal descent descends over it), each within +-1e7 m", min = -params::MAX_TARGET_M, max = params::MAX_TARGET_M, components = NUE),
    decl!(236, parameter retarget_max_tilt: params.retarget_max_tilt_rad, "rad", "retarget: tilt of the thrust axis from vertical the divert may count on; the lateral authority is min(g tan(retarget_max_tilt), sqrt((thrust_max / mass)^2 - g^2)) at the retarget, in (0, 80 deg]; default 15 deg", above = 0.0, max = crate::guidance::retarget::MAX_RETARGET_TILT_RAD),
    decl!(242, parameter input_monitor: params.input_monitor as bool, "supervision: compare the inputs' changes with the body rates, the velocity, the commands, gravity and inertia, and log once the likely cause of a mismatch (true, default); observes only"),
    decl!(243, parameter saturation_time: params.saturation_time_s, "s", "supervision: a thrust or torque command at a limit of its range for longer than this is logged once, <= 1e6 s", min = 0.0, max = params::MAX_DURATION_S),
    decl!(244, parameter descent_from_hover_command: params.descent_from_hover_command as bool, "descent handover: true (default, the paper) the descent's cubic starts from the hover's last acceleration command; false from zero net acceleration (thrust balancing gravity), so a hover still correcting an error does not hand its command to the cubic, which would carry it open loop (docs/results.md, the handover); the later solves start from the held command either way"),
    decl!(237, parameter retarget_replan: params.retarget_replan as bool, "retarget: true (default) re-plans a cubic divert from the current state whose duration keeps its peak lateral acceleration within the authority, then hovers at the site; false only moves the target, the phase schedule unchanged (the baseline)"),
];

#[cfg(test)]
mod tests {
    use super::*;

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
        let half = 0.05 * libm::sin(0.7 * s);
        let mut nav = NavigationInputs {
            r_nue_m: [0.3, 800.0 - 2.0 * s, -0.2],
            v_nue_mps: [0.01, -2.0, 0.02],
            q_body_to_nue: [
                libm::cos(half),
                0.2 * libm::sin(half),
                0.5 * libm::sin(half),
                0.84 * libm::sin(half),
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

    /// Supervision off: `navigation` is no flight (its attitude does not follow its rates),
    /// and the supervision judges the command a get showed, which these tests vary on
    /// purpose between instances that must commit the same memory.
    fn paper_params() -> GncParameters {
        GncParameters {
            phi_cmd_rad: 150f64.to_radians(),
            input_monitor: false,
            saturation_time_s: 1e6,
            ..GncParameters::default()
        }
    }

    /// The paper case with a shaped thrust-axis manoeuvre, whose profile moves with `t`.
    fn shaped_params() -> GncParameters {
        GncParameters {
            phi_rate_limit_radps: 0.3,
            phi_accel_limit_radps2: 0.1,
            ..paper_params()
        }
    }

    /// The paper case retargeted 30 m North during the descent (at 15.05 s, off the guidance
    /// grid), so that the runs below re-plan a divert.
    fn retargeted_params() -> GncParameters {
        GncParameters {
            retarget_time_s: 15.05,
            retarget_site_nue_m: [30.0, 150.0, 0.0],
            ..paper_params()
        }
    }

    /// `{:?}` of f64 is exact (shortest round trip) and tells -0.0 from 0.0.
    fn exact<T: std::fmt::Debug>(value: &T) -> String {
        format!("{value:?}")
    }

    thread_local! {
        /// Attitude-law evaluations on this test's thread.
        pub(super) static EVALUATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    fn evaluations() -> usize {
        EVALUATIONS.with(|n| n.get())
    }

    /// The memory a step commits: guidance, thrust-axis profile, modulators.
    fn memory(gnc: &LanderGnc) -> String {
        exact(&(gnc.guidance, gnc.profile, gnc.pwpf))
    }

    /// What the next get shows (the layer calls `calculate_values` before it).
    fn next_get(gnc: &LanderGnc) -> GncOutputs {
        let mut copy = gnc.clone();
        copy.calculate_values(&mut Log::default());
        copy.outputs
    }

    fn messages(log: &Log) -> Vec<String> {
        log.entries
            .iter()
            .map(|(l, m)| format!("{l:?}: {m}"))
            .collect()
    }

    #[test]
    fn the_thruster_modulators_are_part_of_the_serialized_state() {
        // GIVEN the thruster model, stepped into the 150 deg roll (thrusters pulsing)
        let mut gnc = initialized(GncParameters {
            rcs_model: crate::actuation::RcsModel::Thrusters as i32,
            ..paper_params()
        });
        for k in 0..150 {
            gnc.inputs = navigation(k);
            gnc.do_step(k as f64 * H, H, &mut Log::default()).unwrap();
        }
        assert!(gnc.pwpf.iter().any(|m| m.filter != 0.0), "{:?}", gnc.pwpf);
        // WHEN its state is serialized and restored into a fresh instance
        let header = fmi_export::snapshot::Header {
            magic: *b"testtest",
            state_version: 2,
            guid: Default::default(),
            interface: fmi_model::Interface::CoSimulation,
        };
        let bytes = fmi_export::snapshot::encode(&gnc, header).unwrap();
        let mut restored: LanderGnc = fmi_export::snapshot::decode(&bytes, header).unwrap();
        // THEN both command the same duties from there on
        for k in 150..400 {
            for m in [&mut gnc, &mut restored] {
                m.inputs = navigation(k);
                m.do_step(k as f64 * H, H, &mut Log::default()).unwrap();
            }
            assert_eq!(memory(&restored), memory(&gnc), "step {k}");
            assert_eq!(
                exact(&next_get(&restored)),
                exact(&next_get(&gnc)),
                "step {k}"
            );
        }
        assert!(next_get(&gnc).rcs_duty.iter().any(|&d| d > 0.0));
    }

    #[test]
    fn gets_between_steps_do_not_change_the_trajectory() {
        gets_between_steps_do_not_change_the_trajectory_with(paper_params());
        gets_between_steps_do_not_change_the_trajectory_with(shaped_params());
        gets_between_steps_do_not_change_the_trajectory_with(retargeted_params());
    }

    fn gets_between_steps_do_not_change_the_trajectory_with(params: GncParameters) {
        // GIVEN two instances, one stepped bare, one read before (almost) every step
        let mut bare = initialized(params);
        let mut read = initialized(params);
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
            // THEN both commit bit-identical memories, report the same warnings and show
            // the same outputs next
            assert_eq!(memory(&read), memory(&bare), "step {k}");
            assert_eq!(messages(&read_log), messages(&bare_log), "step {k}");
            if k % 10 == 0 {
                assert_eq!(exact(&next_get(&read)), exact(&next_get(&bare)), "step {k}");
            }
        }
        assert!(
            kept_time > 200 && other_time > 200,
            "{kept_time} {other_time}"
        );
        assert_eq!(
            next_get(&bare).guidance_phase,
            2,
            "the run reaches the descent"
        );
        assert_eq!(
            bare.guidance.retarget.is_some(),
            params.retarget_time_s >= 0.0,
            "a retarget is planned in the run that commands one"
        );
    }

    /// The claim of `SampleTime`: equal keys, bit-identical samples. Probed along a run
    /// with guidance states that have and have not solved the cycle, and late ones, at the
    /// master's time, our accumulated time, times a few ulps and a few tolerances away, and
    /// on both sides of phi_cmd_time (off the guidance cycle grid).
    #[test]
    fn equal_sample_times_give_bit_identical_samples() {
        equal_sample_times_give_bit_identical_samples_with(paper_params());
        equal_sample_times_give_bit_identical_samples_with(shaped_params());
        equal_sample_times_give_bit_identical_samples_with(retargeted_params());
    }

    fn equal_sample_times_give_bit_identical_samples_with(params: GncParameters) {
        let phi_cmd_time_s = 12.345;
        let mut gnc = initialized(GncParameters {
            phi_cmd_time_s,
            ..params
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
                let (sample, _) = LanderGnc {
                    time_s,
                    ..gnc.clone()
                }
                .evaluate();
                (
                    exact(&sample.outputs),
                    exact(&sample.advance.guidance),
                    exact(&sample.advance.profile),
                )
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
        // A shaped profile moves with t itself: only bit-equal times share a key.
        assert_eq!(
            gnc.guidance.retarget.is_some(),
            params.retarget_time_s >= 0.0
        );
        let shaped = params.phi_rate_limit_radps > 0.0 || params.phi_accel_limit_radps2 > 0.0;
        assert!(shaped || pairs > 10_000, "{pairs}");
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
            let (previewed, _) = gnc.evaluate();
            let mut step_log = Log::default();
            let before = evaluations();
            gnc.do_step(t, H, &mut step_log).unwrap();
            assert_eq!(
                evaluations(),
                before,
                "the step reuses the get's sample, step {k}"
            );
            let advance = &previewed.advance;
            assert_eq!(
                exact(&(gnc.guidance, gnc.profile)),
                exact(&(advance.guidance, advance.profile)),
                "step {k}"
            );
            assert_eq!(messages(&step_log), messages(&get_log), "step {k}");
        }
    }

    /// Counts attitude-law evaluations in three call orders of a master over `steps` steps
    /// (after initialization): read then step, step then read, and steps nobody reads.
    fn evaluations_per_order(params: GncParameters, steps: usize) -> [usize; 3] {
        let mut counts = [0; 3];
        for (order, count) in counts.iter_mut().enumerate() {
            let mut gnc = initialized(params);
            let before = evaluations();
            for k in 0..steps {
                let t = k as f64 * H;
                gnc.inputs = navigation(k);
                if order == 0 {
                    gnc.calculate_values(&mut Log::default());
                }
                gnc.do_step(t, H, &mut Log::default()).unwrap();
                if order == 1 {
                    gnc.calculate_values(&mut Log::default());
                }
            }
            *count = evaluations() - before;
        }
        counts
    }

    #[test]
    fn the_attitude_law_is_evaluated_once_per_read_step_in_any_call_order() {
        // Torque model: a step evaluates the law only if nobody did for its inputs; a step
        // after a get of other inputs computes the guidance memory alone.
        assert_eq!(evaluations_per_order(paper_params(), 500), [500, 500, 0]);
        assert_eq!(evaluations_per_order(shaped_params(), 500), [500, 500, 0]);
        // Thruster model: the modulators integrate the law's torque, so a step evaluates it
        // unless the get just did.
        let thrusters = GncParameters {
            rcs_model: crate::actuation::RcsModel::Thrusters as i32,
            ..paper_params()
        };
        assert_eq!(evaluations_per_order(thrusters, 500), [500, 1000, 500]);
    }

    /// A step without a get commits the memory of the full sample, in the torque model
    /// (where it skips the attitude law), with the profile stepped and shaped.
    #[test]
    fn a_step_without_a_get_commits_the_memory_of_the_full_sample() {
        for params in [paper_params(), shaped_params()] {
            let mut gnc = initialized(params);
            for k in 0..1500 {
                let t = k as f64 * H;
                gnc.inputs = navigation(k);
                // The sample at the master's t, which do_step takes as authoritative.
                gnc.time_s = t;
                let (full, _) = gnc.evaluate();
                gnc.do_step(t, H, &mut Log::default()).unwrap();
                let advance = &full.advance;
                assert_eq!(
                    exact(&(gnc.guidance, gnc.profile)),
                    exact(&(advance.guidance, advance.profile)),
                    "step {k}"
                );
            }
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
        assert_eq!(memory(&gnc), memory(&bare));
        assert_eq!(exact(&next_get(&gnc)), exact(&next_get(&bare)));
        assert_ne!(exact(&next_get(&gnc)), previewed);
    }

    #[test]
    fn a_get_in_initialization_mode_with_a_refused_parameter_warns_naming_it() {
        // GIVEN an unknown control law, set in initialization mode
        let mut gnc = LanderGnc {
            inputs: navigation(0),
            ..LanderGnc::default()
        };
        gnc.params.control_law = 7;
        // WHEN the outputs are read before initialization ends
        let mut log = Log::default();
        gnc.calculate_values(&mut log);
        // THEN the get warns, naming the parameter (no silent fallback)
        assert!(log.has_warning());
        assert!(messages(&log)[0].contains("control_law = 7"), "{log:?}");
        // AND initialization refuses it
        let refused = gnc.exit_initialization(0.0, &mut Log::default());
        assert!(matches!(
            refused,
            Err(ModelError::InvalidParameter {
                field: "control_law",
                ..
            })
        ));
        // AND valid parameters read silently
        let mut log = Log::default();
        LanderGnc::default().calculate_values(&mut log);
        assert!(!log.has_warning(), "{log:?}");
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
        assert_eq!(memory(&gnc), memory(&fresh));
        assert_eq!(exact(&next_get(&gnc)), exact(&next_get(&fresh)));
        assert_ne!(exact(&next_get(&gnc)), before);
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

    #[test]
    fn a_restored_retarget_plan_is_accepted_and_a_doctored_one_refused() {
        // GIVEN a run 20 s in, retargeted at 15.05 s (a divert under way)
        let mut gnc = LanderGnc {
            params: retargeted_params(),
            ..LanderGnc::default()
        };
        let mut log = Log::default();
        gnc.exit_initialization(0.0, &mut log).unwrap();
        for k in 0..200 {
            gnc.do_step(f64::from(k) * 0.1, 0.1, &mut log).unwrap();
        }
        let plan = gnc.guidance.retarget.expect("planned at 15.1 s");
        assert!((plan.descent_start_s - 15.1).abs() < 1e-9, "{plan:?}");
        assert_eq!(gnc.validate_restored(true), Ok(()));
        // WHEN the plan is doctored, or kept by parameters that command no retarget
        type Doctor = fn(&mut LanderGnc);
        let doctored: [Doctor; 4] = [
            |g| g.guidance.retarget.as_mut().unwrap().descent_end_s = f64::NAN,
            |g| g.guidance.retarget.as_mut().unwrap().site_nue.0.x = f64::INFINITY,
            |g| g.guidance.retarget.as_mut().unwrap().descent_end_s = 1e7,
            |g| g.params.retarget_time_s = -1.0,
        ];
        // THEN each is refused
        for doctor in doctored {
            let mut restored = gnc.clone();
            doctor(&mut restored);
            let err = restored.validate_restored(true).unwrap_err().to_string();
            assert!(err.contains("retarget plan"), "{err}");
        }
    }
}
