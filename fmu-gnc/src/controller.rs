//! One GNC sample: guidance (held at its own rate), thrust magnitude, reference attitude and
//! attitude law, from the navigation inputs at time `t`. Pure: the caller decides whether to
//! commit the returned guidance state (do_step) or only read the outputs (calculate_values).
use crate::actuation::{duties, PwpfBank, THRUSTER_COUNT};
use crate::attitude::profile::{PhiProfile, RollReference};
use crate::attitude::{command_toward, reference, GuidanceReference};
use crate::conventions::{
    attitude_from_scalar_first, attitude_to_scalar_first, Attitude, MIN_QUATERNION_NORM,
};
use crate::guidance::sequencer::{
    guidance_cycle_index, guidance_sample_in_cycle, has_reached, GuidanceInputs, GuidanceState,
};
use crate::guidance::thrust::thrust_magnitude_n;
use crate::params::{GncDesign, GncParameters};
use lander_math::frames::{Body, Nue};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The navigation state (LanderPlant outputs), as exchanged: scalar-first quaternion.
/// `repr(C)`: the 14 values lie in the order a master exchanges them (the plant's outputs),
/// so a set of all of them is one block copy.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[repr(C)]
pub struct NavigationInputs {
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    pub q_body_to_nue: [f64; 4],
    pub omega_body_radps: [f64; 3],
    pub mass_kg: f64,
}

impl Default for NavigationInputs {
    /// The paper's initial condition: upright, at rest, 800 m up, 900 kg.
    fn default() -> Self {
        Self {
            r_nue_m: [0.0, 800.0, 0.0],
            v_nue_mps: [0.0; 3],
            q_body_to_nue: [1.0, 0.0, 0.0, 0.0],
            omega_body_radps: [0.0; 3],
            mass_kg: 900.0,
        }
    }
}

impl NavigationInputs {
    /// Every component as its bit pattern: two inputs with equal bits give bit-identical
    /// samples (unlike `==`, which equates 0.0 with -0.0, and the sign of a zero can reach
    /// an `atan2`).
    pub fn to_bits(&self) -> [u64; 14] {
        let [r0, r1, r2] = self.r_nue_m.map(f64::to_bits);
        let [v0, v1, v2] = self.v_nue_mps.map(f64::to_bits);
        let [q0, q1, q2, q3] = self.q_body_to_nue.map(f64::to_bits);
        let [w0, w1, w2] = self.omega_body_radps.map(f64::to_bits);
        [
            r0,
            r1,
            r2,
            v0,
            v1,
            v2,
            q0,
            q1,
            q2,
            q3,
            w0,
            w1,
            w2,
            self.mass_kg.to_bits(),
        ]
    }

    /// Whether `bits` are [`Self::to_bits`] of these inputs: the pairs' differences or-ed
    /// together, in vector lanes and without a call to `memcmp`.
    #[inline(always)]
    pub fn has_bits(&self, bits: &[u64; 14]) -> bool {
        let differing = self
            .to_bits()
            .iter()
            .zip(bits)
            .fold(0, |all, (a, b)| all | (a ^ b));
        differing == 0
    }
}

/// Commands and diagnostics of one sample, as exchanged.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct GncOutputs {
    pub thrust_cmd_n: f64,
    pub torque_cmd_body_nm: [f64; 3],
    /// Thruster model: fraction of the coming period each thruster fires, from its start.
    pub rcs_duty: [f64; THRUSTER_COUNT],
    /// Commanded thrust acceleration (guidance net acceleration minus gravity), NUE.
    pub a_cmd_nue_mps2: [f64; 3],
    pub q_ref: [f64; 4],
    pub phi_b_rad: f64,
    pub err_roll_rad: f64,
    pub err_yaw_rad: f64,
    pub err_pitch_rad: f64,
    pub tilt_error_rad: f64,
    pub guidance_phase: i32,
    pub time_to_go_s: f64,
}

impl GncOutputs {
    /// Replaces every non-finite value by 0 and says whether there was one. Validated
    /// parameters never produce one; this is for outputs read in initialization mode, before
    /// the end of initialization has checked the parameters (a master may set an absurd
    /// bandwidth and read the outputs first): never NaN out of the FMU.
    pub fn zero_non_finite(&mut self) -> bool {
        if self.all_finite() {
            return false;
        }
        let mut found = false;
        let mut fix = |x: &mut f64| {
            if !x.is_finite() {
                *x = 0.0;
                found = true;
            }
        };
        fix(&mut self.thrust_cmd_n);
        self.rcs_duty.iter_mut().for_each(&mut fix);
        self.torque_cmd_body_nm.iter_mut().for_each(&mut fix);
        self.a_cmd_nue_mps2.iter_mut().for_each(&mut fix);
        self.q_ref.iter_mut().for_each(&mut fix);
        for x in [
            &mut self.phi_b_rad,
            &mut self.err_roll_rad,
            &mut self.err_yaw_rad,
            &mut self.err_pitch_rad,
            &mut self.tilt_error_rad,
            &mut self.time_to_go_s,
        ] {
            fix(x);
        }
        found
    }

    /// Whether every value is finite: `x * 0` is 0 for finite `x` and NaN otherwise, so one
    /// sum tells (the common case, checked at every published sample).
    fn all_finite(&self) -> bool {
        let scalars = [
            self.thrust_cmd_n,
            self.phi_b_rad,
            self.err_roll_rad,
            self.err_yaw_rad,
            self.err_pitch_rad,
            self.tilt_error_rad,
            self.time_to_go_s,
        ];
        let probe: f64 = scalars
            .iter()
            .chain(&self.torque_cmd_body_nm)
            .chain(&self.rcs_duty)
            .chain(&self.a_cmd_nue_mps2)
            .chain(&self.q_ref)
            .map(|x| x * 0.0)
            .sum();
        probe == 0.0
    }
}

/// Why a sample's navigation inputs cannot be used (docs/interface.md, degenerate first inputs).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum DegenerateInput {
    #[error("q_body_to_nue has (near) zero norm: no attitude; commanding minimum thrust and zero torque")]
    ZeroNormQuaternion,
    #[error("mass = {0} kg is not positive; commanding minimum thrust and zero torque")]
    NonPositiveMass(f64),
}

/// A quaternion input whose norm is off 1 by more than this (relative) is used normalised,
/// with a warning: a navigation source that drifts that far is worth a look, while the
/// rounding of a propagated quaternion (1e-15) or a master's linear interpolation between
/// close samples (1e-5) is not.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

/// Distance of a sum of squares from 1 inside which the norm is surely within
/// [`QUATERNION_NORM_TOLERANCE`] of 1 (its square's band is 2e-3 wide on either side).
const UNIT_SQUARES_MARGIN: f64 = 1.9 * QUATERNION_NORM_TOLERANCE;

/// The norm of `q`, computed without overflow or underflow (components scaled by the largest
/// before squaring), and `q` scaled by that largest component.
pub fn quaternion_norm(q: [f64; 4]) -> (f64, [f64; 4]) {
    let scale = q.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return (scale, q);
    }
    let scaled = q.map(|c| c / scale);
    let sum: f64 = scaled.iter().map(|c| c * c).sum();
    (scale * sum.sqrt(), scaled)
}

/// The attitude of a quaternion input and, when its norm is far from 1, that norm.
/// Inlined: the common case is a few instructions; the others are out of line.
#[inline(always)]
fn input_attitude(q: [f64; 4]) -> (Option<Attitude>, Option<f64>) {
    // The common case without the scaling: a sum of squares this close to 1 has a norm
    // within the tolerance whatever the rounding ((1 -+ 1e-3)^2 = 1 -+ 2e-3 + 1e-6), so the
    // exact test below would take the first branch too.
    let squares = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (squares - 1.0).abs() <= UNIT_SQUARES_MARGIN {
        return (attitude_from_scalar_first(q), None);
    }
    input_attitude_scaled(q)
}

/// [`input_attitude`] of a quaternion whose sum of squares is not close to 1.
#[cold]
#[inline(never)]
fn input_attitude_scaled(q: [f64; 4]) -> (Option<Attitude>, Option<f64>) {
    let (norm, scaled) = quaternion_norm(q);
    if (norm - 1.0).abs() <= QUATERNION_NORM_TOLERANCE || norm < MIN_QUATERNION_NORM {
        // Unit-norm inputs exactly as they come (trajectories bit for bit); (near) zero ones
        // are degenerate.
        (attitude_from_scalar_first(q), None)
    } else {
        (attitude_from_scalar_first(scaled), Some(norm))
    }
}

/// What a sample commits, computed without the attitude law: the guidance and profile
/// memory after it, and what it found wrong with its inputs. A step whose outputs nobody
/// read needs no more than this (torque model), so stepping costs no attitude law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Advance {
    /// Guidance state to commit if this sample is taken (unchanged on degenerate input).
    pub guidance: GuidanceState,
    /// Thrust-axis profile state to commit (a function of time alone).
    pub profile: PhiProfile,
    pub degenerate: Option<DegenerateInput>,
    /// The norm of a quaternion input used normalised because it was far from 1.
    pub non_unit_quaternion_norm: Option<f64>,
    /// The reference rotation about the thrust axis at this sample.
    pub(crate) roll: RollReference,
    /// The input attitude, when the inputs are usable.
    pub(crate) attitude: Option<Attitude>,
}

impl Default for Advance {
    /// A placeholder for storage marked as holding no sample; never read as a sample's
    /// memory (its gravity is 0).
    fn default() -> Self {
        Self {
            guidance: GuidanceState::initial(0.0),
            profile: PhiProfile::default(),
            degenerate: None,
            non_unit_quaternion_norm: None,
            roll: RollReference::default(),
            attitude: None,
        }
    }
}

/// Result of one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// What the sample commits.
    pub advance: Advance,
    pub outputs: GncOutputs,
}

/// The memory a sample at absolute time `t_s` leaves behind (see [`Advance`]); the part of
/// [`gnc_sample`] before the attitude law, so the two cannot disagree. Inlined: each caller
/// gets the memory built where it keeps it.
#[inline(always)]
pub fn gnc_advance(
    design: &GncDesign,
    start_time_s: f64,
    guidance: &GuidanceState,
    profile: &PhiProfile,
    nav: &NavigationInputs,
    t_s: f64,
) -> Advance {
    let cycle = guidance_cycle_index(t_s - start_time_s, design.scenario.guidance_cycle_s);
    let mut advance = Advance {
        guidance: *guidance,
        profile: *profile,
        ..Advance::default()
    };
    gnc_advance_into(
        design,
        start_time_s,
        guidance,
        profile,
        nav,
        t_s,
        cycle,
        &mut advance,
    );
    advance
}

/// [`gnc_advance`] for a caller that has the guidance cycle of `t_s` ([`guidance_cycle_index`]
/// of the time elapsed since `start_time_s`) and keeps the memory in place, written into
/// `out`: `out.guidance` is written only when the sample solves a guidance cycle, and whether it
/// did is returned; otherwise the guidance memory is `guidance` as it is (the zero-order
/// hold), and `out.guidance` is left as it was. Likewise `out.profile` is written only with
/// a shaped thrust-axis profile (`design.roll_profile`); without one it stays `profile`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn gnc_advance_into(
    design: &GncDesign,
    start_time_s: f64,
    guidance: &GuidanceState,
    profile: &PhiProfile,
    nav: &NavigationInputs,
    t_s: f64,
    cycle: (i64, bool),
    out: &mut Advance,
) -> bool {
    let params = &design.params;
    let phi_cmd_rad = if has_reached(t_s, params.phi_cmd_time_s) {
        params.phi_cmd_rad
    } else {
        0.0
    };
    out.roll = match &design.roll_profile {
        Some(limits) => {
            let (profile, roll) = profile.advance(limits, t_s, phi_cmd_rad);
            out.profile = profile;
            roll
        }
        None => RollReference::step(phi_cmd_rad),
    };
    let (q, non_unit_quaternion_norm) = input_attitude(nav.q_body_to_nue);
    let degenerate = match q {
        None => Some(DegenerateInput::ZeroNormQuaternion),
        Some(_) if nav.mass_kg <= 0.0 => Some(DegenerateInput::NonPositiveMass(nav.mass_kg)),
        Some(_) => None,
    };
    let attitude = q.filter(|_| degenerate.is_none());
    // No guidance solve from unusable inputs; within a solved cycle `guidance_sample_in_cycle`
    // holds the memory as it is.
    let solves = attitude.is_some() && guidance.last_cycle != Some(cycle.0);
    if solves {
        out.guidance = guidance_sample_in_cycle(
            &design.scenario,
            guidance,
            t_s - start_time_s,
            cycle,
            &GuidanceInputs {
                r_nue: Nue::from(nav.r_nue_m),
                v_nue: Nue::from(nav.v_nue_mps),
                mass_kg: nav.mass_kg,
            },
        );
    }
    out.degenerate = degenerate;
    out.non_unit_quaternion_norm = non_unit_quaternion_norm;
    out.attitude = attitude;
    solves
}

/// Evaluate the GNC at absolute time `t_s`; `start_time_s` anchors the phase schedule.
/// `design` comes from validated parameters ([`GncParameters::design`]). Never returns NaN for
/// finite input.
pub fn gnc_sample(
    design: &GncDesign,
    start_time_s: f64,
    guidance: &GuidanceState,
    profile: &PhiProfile,
    nav: &NavigationInputs,
    t_s: f64,
) -> Sample {
    let mut sample = Sample {
        advance: gnc_advance(design, start_time_s, guidance, profile, nav, t_s),
        outputs: GncOutputs::default(),
    };
    gnc_outputs(design, &sample.advance, guidance, nav, &mut sample.outputs);
    sample
}

/// The outputs of the sample whose memory is `advance` ([`gnc_advance`] from the guidance
/// state `guidance` and `nav`), written to `out`: [`gnc_sample`] after its first part, for
/// a caller that keeps the two apart (the FMU writes each where it keeps it). Never inlined:
/// one call is one evaluation of the attitude law, which is what a profile counts
/// (tests/speed).
#[inline(never)]
pub fn gnc_outputs(
    design: &GncDesign,
    advance: &Advance,
    guidance: &GuidanceState,
    nav: &NavigationInputs,
    out: &mut GncOutputs,
) {
    outputs(
        design,
        advance,
        &advance.guidance,
        guidance,
        nav,
        out,
        &mut None,
    );
}

/// [`gnc_outputs`] for a caller that keeps the reference attitude of the guidance command
/// in `reference` from one sample to the next (computed afresh when the command or the
/// angle about the thrust axis changed): the same outputs, bit for bit. Never inlined, and
/// named so, for the same count.
#[inline(never)]
pub fn gnc_outputs_keeping_reference(
    design: &GncDesign,
    advance: &Advance,
    guidance: &GuidanceState,
    nav: &NavigationInputs,
    out: &mut GncOutputs,
    reference: &mut Option<GuidanceReference>,
) {
    outputs(
        design,
        advance,
        &advance.guidance,
        guidance,
        nav,
        out,
        reference,
    );
}

/// [`gnc_outputs_keeping_reference`] of a memory kept by [`gnc_advance_into`]: `next` is the
/// guidance memory after the sample (`advance.guidance` if the sample solved a cycle, else
/// `guidance`). Never inlined, and named so, for the same count.
#[inline(never)]
pub fn gnc_outputs_keeping_reference_in_place(
    design: &GncDesign,
    advance: &Advance,
    next: &GuidanceState,
    guidance: &GuidanceState,
    nav: &NavigationInputs,
    out: &mut GncOutputs,
    reference: &mut Option<GuidanceReference>,
) {
    outputs(design, advance, next, guidance, nav, out, reference);
}

#[inline(always)]
fn outputs(
    design: &GncDesign,
    advance: &Advance,
    next: &GuidanceState,
    guidance: &GuidanceState,
    nav: &NavigationInputs,
    out: &mut GncOutputs,
    reference: &mut Option<GuidanceReference>,
) {
    let params = &design.params;
    let Some(q) = advance.attitude else {
        *out = safe_outputs(params, guidance, advance.roll.phi_rad);
        return;
    };
    let reference = GuidanceReference::keep(
        reference,
        &design.attitude,
        &next.a_thrust_cmd_nue,
        advance.roll.phi_rad,
    );
    let attitude = command_toward(
        &design.attitude,
        reference,
        &q,
        &Body::from(nav.omega_body_radps),
        &advance.roll,
    );
    *out = GncOutputs {
        thrust_cmd_n: if next.engine_cut {
            0.0
        } else {
            thrust_magnitude_n(
                nav.mass_kg,
                &next.a_thrust_cmd_nue,
                params.thrust_min_n,
                params.thrust_max_n,
            )
        },
        torque_cmd_body_nm: attitude.torque_body_nm.to_array(),
        rcs_duty: [0.0; THRUSTER_COUNT],
        a_cmd_nue_mps2: next.a_thrust_cmd_nue.to_array(),
        q_ref: attitude_to_scalar_first(&attitude.q_ref),
        phi_b_rad: attitude.phi_b_rad,
        err_yaw_rad: attitude.angle_error_body.0.x,
        err_roll_rad: attitude.angle_error_body.0.y,
        err_pitch_rad: attitude.angle_error_body.0.z,
        tilt_error_rad: attitude.tilt_rad,
        guidance_phase: next.phase as i32,
        time_to_go_s: next.time_to_go_s,
    };
}

/// In the thruster model, turns the sample's torque command into the duties of the coming
/// period (`outputs.rcs_duty`) and returns the modulators' state after it; in the torque
/// model the duties stay 0 and the modulators as they are.
pub fn actuate(design: &GncDesign, outputs: &mut GncOutputs, bank: &PwpfBank) -> PwpfBank {
    let Some(thrusters) = &design.thrusters else {
        return *bank;
    };
    let (duty, next) = duties(
        &thrusters.allocator,
        &thrusters.pwpf,
        bank,
        &Vector3::from(outputs.torque_cmd_body_nm),
        design.params.rcs_tilt_first,
        design.params.rcs_duty_period_s,
    );
    outputs.rcs_duty = duty;
    next
}

/// Minimum thrust (none once the engine is cut), zero torque; guidance diagnostics held;
/// attitude diagnostics zero.
fn safe_outputs(params: &GncParameters, guidance: &GuidanceState, phi_cmd_rad: f64) -> GncOutputs {
    let q_ref = reference::q_ref(&reference::q_guid(&guidance.a_thrust_cmd_nue), phi_cmd_rad);
    GncOutputs {
        thrust_cmd_n: if guidance.engine_cut {
            0.0
        } else {
            params.thrust_min_n
        },
        torque_cmd_body_nm: [0.0; 3],
        a_cmd_nue_mps2: guidance.a_thrust_cmd_nue.to_array(),
        q_ref: attitude_to_scalar_first(&q_ref),
        guidance_phase: guidance.phase as i32,
        time_to_go_s: guidance.time_to_go_s,
        ..GncOutputs::default()
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    fn initial() -> GuidanceState {
        GuidanceState::initial(GncParameters::default().gravity_mps2)
    }

    fn sample(params: &GncParameters, nav: &NavigationInputs, t_s: f64) -> Sample {
        let design = params.design().unwrap();
        gnc_sample(&design, 0.0, &initial(), &PhiProfile::default(), nav, t_s)
    }

    #[test]
    fn the_unit_shortcut_decides_as_the_scaled_norm_does() {
        // Norms swept across both edges of the tolerance band, in four directions.
        for k in 0..=4000 {
            let norm = 1.0 - 2e-3 + 1e-6 * f64::from(k);
            for dir in [
                [1.0, 0.0, 0.0, 0.0],
                [0.5, -0.5, 0.5, 0.5],
                [0.1, 0.7, -0.7, 0.1],
            ] {
                let unit = quaternion_norm(dir).0;
                let q = dir.map(|c| c / unit * norm);
                let (exact, _) = quaternion_norm(q);
                let expected_warning =
                    ((exact - 1.0).abs() > QUATERNION_NORM_TOLERANCE).then_some(exact);
                let (attitude, warning) = input_attitude(q);
                assert_eq!(warning, expected_warning, "norm {norm}");
                assert!(attitude.is_some());
            }
        }
    }

    #[test]
    fn upright_hover_on_target_commands_weight_and_no_torque() {
        let params = GncParameters::default();
        let s = sample(&params, &NavigationInputs::default(), 0.0);
        assert_eq!(s.advance.degenerate, None);
        assert!((s.outputs.thrust_cmd_n - 900.0 * 1.62).abs() < 1e-9);
        assert_eq!(s.outputs.torque_cmd_body_nm, [0.0; 3]);
        assert_eq!(s.outputs.guidance_phase, 1);
        assert_eq!(s.outputs.q_ref, [1.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn degenerate_inputs_give_safe_outputs_and_keep_guidance() {
        let params = GncParameters::default();
        let zeros = NavigationInputs {
            r_nue_m: [0.0; 3],
            v_nue_mps: [0.0; 3],
            q_body_to_nue: [0.0; 4],
            omega_body_radps: [0.0; 3],
            mass_kg: 0.0,
        };
        let s = sample(&params, &zeros, 0.0);
        assert_eq!(
            s.advance.degenerate,
            Some(DegenerateInput::ZeroNormQuaternion)
        );
        assert_eq!(s.outputs.thrust_cmd_n, params.thrust_min_n);
        assert_eq!(s.outputs.torque_cmd_body_nm, [0.0; 3]);
        assert_eq!(
            s.advance.guidance,
            initial(),
            "no guidance solve from garbage"
        );
        let massless = NavigationInputs {
            mass_kg: -1.0,
            ..NavigationInputs::default()
        };
        let s = sample(&params, &massless, 0.0);
        assert_eq!(
            s.advance.degenerate,
            Some(DegenerateInput::NonPositiveMass(-1.0))
        );
        assert_eq!(s.outputs.torque_cmd_body_nm, [0.0; 3]);
    }

    #[test]
    fn input_bits_tell_every_component_and_the_sign_of_zero_apart() {
        let base = NavigationInputs::default();
        let bits = base.to_bits();
        assert_eq!(bits[1], 800.0f64.to_bits());
        assert_eq!(bits[6], 1.0f64.to_bits());
        assert_eq!(bits[13], 900.0f64.to_bits());
        for k in 0..14 {
            let mut nav = base;
            let mut fields = [0.0; 14];
            for (f, b) in fields.iter_mut().zip(bits) {
                *f = f64::from_bits(b);
            }
            // -0.0 == 0.0 but must count as a different input.
            fields[k] = if fields[k] == 0.0 { -0.0 } else { -fields[k] };
            nav.r_nue_m.copy_from_slice(&fields[0..3]);
            nav.v_nue_mps.copy_from_slice(&fields[3..6]);
            nav.q_body_to_nue.copy_from_slice(&fields[6..10]);
            nav.omega_body_radps.copy_from_slice(&fields[10..13]);
            nav.mass_kg = fields[13];
            let new_bits = nav.to_bits();
            let differing: Vec<usize> = (0..14).filter(|&i| new_bits[i] != bits[i]).collect();
            assert_eq!(differing, [k]);
        }
    }

    #[test]
    fn a_kept_reference_gives_the_fresh_outputs_bit_for_bit() {
        // GIVEN samples whose command, angle about the thrust axis or design change, and
        // repeat, in turn
        let params = GncParameters {
            phi_cmd_rad: 1.0,
            ..GncParameters::default()
        };
        let designs = [
            params.design().unwrap(),
            GncParameters {
                phi_cmd_rad: -2.0,
                ..params
            }
            .design()
            .unwrap(),
        ];
        let nav = NavigationInputs {
            q_body_to_nue: [0.9, 0.1, -0.3, 0.2],
            omega_body_radps: [0.01, -0.02, 0.03],
            ..NavigationInputs::default()
        };
        let base = gnc_advance(
            &designs[0],
            0.0,
            &initial(),
            &PhiProfile::default(),
            &nav,
            0.0,
        );
        let commands = [Nue::new(0.2, 1.5, -0.1), Nue::new(-0.3, 1.6, 0.0)];
        let angles = [1.0, 0.4, -0.0, 0.0];
        let mut kept = None;
        let mut compared = 0;
        for design in &designs {
            for a in commands {
                for phi_rad in angles {
                    for _repeat in 0..2 {
                        let mut advance = base;
                        advance.guidance.a_thrust_cmd_nue = a;
                        advance.roll = RollReference::step(phi_rad);
                        let (mut fresh, mut from_kept) = Default::default();
                        gnc_outputs(design, &advance, &initial(), &nav, &mut fresh);
                        gnc_outputs_keeping_reference(
                            design,
                            &advance,
                            &initial(),
                            &nav,
                            &mut from_kept,
                            &mut kept,
                        );
                        // THEN each output has the fresh one's bits (Debug prints an f64
                        // exactly, the sign of a zero included)
                        assert_eq!(format!("{fresh:?}"), format!("{from_kept:?}"));
                        compared += 1;
                    }
                }
            }
        }
        assert_eq!(compared, 32);
    }

    #[test]
    fn phi_cmd_applies_from_its_time_with_tolerance() {
        let params = GncParameters {
            phi_cmd_rad: 1.0,
            ..GncParameters::default()
        };
        let nav = NavigationInputs::default();
        let before = sample(&params, &nav, 11.99);
        assert_eq!(before.outputs.q_ref, [1.0, 0.0, 0.0, 0.0]);
        let at = sample(&params, &nav, 11.999999999999789);
        assert!((at.outputs.q_ref[2] - 0.5_f64.sin()).abs() < 1e-15);
        assert!((at.outputs.err_roll_rad + 1.0).abs() < 1e-15);
    }
}

#[cfg(test)]
mod non_finite_tests {
    use super::GncOutputs;

    #[test]
    fn non_finite_outputs_are_zeroed_and_reported() {
        let mut outputs = GncOutputs {
            thrust_cmd_n: 1000.0,
            torque_cmd_body_nm: [1.0, f64::NAN, 2.0],
            rcs_duty: [0.0; 8],
            a_cmd_nue_mps2: [0.0, f64::INFINITY, 0.0],
            q_ref: [1.0, 0.0, 0.0, 0.0],
            phi_b_rad: 0.1,
            err_roll_rad: 0.0,
            err_yaw_rad: 0.0,
            err_pitch_rad: 0.0,
            tilt_error_rad: f64::NEG_INFINITY,
            guidance_phase: 1,
            time_to_go_s: 0.0,
        };
        assert!(outputs.zero_non_finite());
        assert_eq!(outputs.torque_cmd_body_nm, [1.0, 0.0, 2.0]);
        assert_eq!(outputs.a_cmd_nue_mps2, [0.0, 0.0, 0.0]);
        assert_eq!(outputs.tilt_error_rad, 0.0);
        assert_eq!(outputs.thrust_cmd_n, 1000.0);
        assert!(!outputs.zero_non_finite(), "a finite set is left alone");
    }

    #[test]
    fn a_non_finite_value_in_any_field_is_found() {
        let fields: [fn(&mut GncOutputs) -> &mut f64; 12] = [
            |o| &mut o.thrust_cmd_n,
            |o| &mut o.torque_cmd_body_nm[2],
            |o| &mut o.rcs_duty[0],
            |o| &mut o.rcs_duty[7],
            |o| &mut o.a_cmd_nue_mps2[1],
            |o| &mut o.q_ref[3],
            |o| &mut o.phi_b_rad,
            |o| &mut o.err_roll_rad,
            |o| &mut o.err_yaw_rad,
            |o| &mut o.err_pitch_rad,
            |o| &mut o.tilt_error_rad,
            |o| &mut o.time_to_go_s,
        ];
        for (k, field) in fields.iter().enumerate() {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut outputs = GncOutputs {
                    thrust_cmd_n: 1e300,
                    ..GncOutputs::default()
                };
                *field(&mut outputs) = bad;
                assert!(outputs.zero_non_finite(), "field {k}, {bad}");
                assert_eq!(*field(&mut outputs), 0.0, "field {k}");
            }
        }
    }
}
