//! The guidance phase sequencer (paper Sec. V scenario) and the 10 Hz zero-order hold.
//!
//! Phases by default: (1) PV hover at 800 m for 12 s, (2) polynomial descent to 150 m with
//! tgo = 130 s, (3) PV hover at 150 m for 30 s, (4) hold: PV hover at the descent target for
//! ever. Targets, durations and tgo are parameters. The schedule counts from the start time.
//! Optionally (beyond the paper, off by default) phase 4 is replaced by (5) a terminal descent:
//! straight down over the descent target at a commanded constant speed until touchdown.
//!
//! Optionally (beyond the paper, off by default) a retarget moves the site in flight
//! ([`Retarget`]): from the guidance cycle at its time, the phases after it are re-planned to
//! the new site: (2) a cubic divert from the current state, long enough for the lateral
//! authority ([`super::retarget`]), then (3) the hover at the new site for the target hover
//! duration, then (4) or (5) over it. The plan is kept in [`GuidanceState::retarget`].
//!
//! Guidance is sampled: a new command is computed once per guidance cycle, at the first sample
//! whose integer cycle index differs from the last one solved, and held in between. The index is
//! derived from the elapsed time with a tolerance, never accumulated, so masters that reach
//! `t = 11.999999999999789` instead of 12 see the same cycle and the same phase.
use super::polynomial::{solve_cubic, BoundaryConditions, CubicAcceleration};
use super::pv::{pv_thrust_acceleration_nue, PvGains};
use super::retarget::{
    divert_time_to_go_s, lateral_authority_mps2, limit_horizontal, DIVERT_AUTHORITY_SHARE,
};
use super::terminal::TerminalDescent;
use super::thrust::{
    achievable_thrust_acceleration_nue, net_acceleration_nue, thrust_acceleration_nue,
};
use lander_math::frames::Nue;
use serde::{Deserialize, Serialize};

/// Relative tolerance of time comparisons against schedule boundaries: a master's time carries
/// rounding (docs/interface.md, timing).
pub const TIME_TOLERANCE_REL: f64 = 1e-9;

fn time_tolerance(t: f64) -> f64 {
    TIME_TOLERANCE_REL * t.abs().max(1.0)
}

/// `t` has reached `boundary`, allowing for accumulated rounding in `t`.
pub fn has_reached(t: f64, boundary: f64) -> bool {
    t >= boundary - time_tolerance(boundary)
}

/// The guidance cycle that `elapsed_s` falls in, and whether `elapsed_s` is on its start
/// (within tolerance). `elapsed_s` below zero counts as cycle 0.
pub fn guidance_cycle_index(elapsed_s: f64, cycle_s: f64) -> (i64, bool) {
    let elapsed_s = elapsed_s.max(0.0);
    let index = floor((elapsed_s + time_tolerance(elapsed_s)) / cycle_s);
    let on_boundary = (elapsed_s - index * cycle_s).abs() <= time_tolerance(elapsed_s);
    // An f64 quotient of a finite time by a validated positive cycle fits an i64 for any
    // realistic run; `as` saturates rather than wraps beyond that.
    (index as i64, on_boundary)
}

/// `x.floor()` but for the sign of a zero, inline: below 2^52 in magnitude an f64 truncates
/// exactly through an i64 (one below the truncation for a negative fraction), and from
/// there on (infinities and NaN too) it is its own floor. Only the sign of a zero result
/// can differ (+0 for -0), which neither `as i64` nor `elapsed - index * cycle` sees.
#[inline(always)]
fn floor(x: f64) -> f64 {
    const INTEGRAL_FROM: f64 = 4_503_599_627_370_496.0;
    if x.abs() < INTEGRAL_FROM {
        let truncated = x as i64 as f64;
        if truncated > x {
            truncated - 1.0
        } else {
            truncated
        }
    } else {
        x
    }
}

/// The scenario: targets, durations and the guidance settings, all in SI and NUE.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenario {
    pub hover_target_nue: Nue,
    pub hover_duration_s: f64,
    pub descent_target_nue: Nue,
    pub descent_time_to_go_s: f64,
    /// ERRATA defaults: polynomial coefficients frozen once tgo drops below this.
    pub freeze_time_to_go_s: f64,
    pub target_hover_duration_s: f64,
    pub guidance_cycle_s: f64,
    pub gravity_mps2: f64,
    pub pv_gains: PvGains,
    /// Engine range, for the achievable command (see `achievable_thrust_acceleration_nue`).
    pub thrust_min_n: f64,
    pub thrust_max_n: f64,
    /// The terminal descent after the target hover and its engine cut-off;
    /// [`TerminalDescent::NONE`]: hold the hover (the paper).
    pub terminal: TerminalDescent,
    /// A new site commanded in flight; `None`: never (the paper).
    pub retarget: Option<Retarget>,
    /// What the descent's first solve, after a hover, starts from ([`Handover`]).
    pub handover: Handover,
}

/// The acceleration the descent's cubic starts from at its first solve after a hover; the
/// later solves always start from the held command (continuity within the descent).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Handover {
    /// The hover's last command (the paper). A hover still correcting an error hands the
    /// cubic its command, and the open-loop cubic from rest with start acceleration `a0`
    /// strays `a0 tgo^2 u^2 (1 - u)^3 / 2` (`u` the elapsed fraction), at most
    /// `0.01728 a0 tgo^2` at `u = 0.4`: 292 m per m/s^2 with the paper's 130 s.
    HoverCommand,
    /// Zero net acceleration (the thrust balancing gravity): the cubic answers the state
    /// only, not the hover's transient.
    ZeroNet,
}

/// A retarget command: at `time_s` the site becomes `site_nue`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Retarget {
    /// Elapsed time since the start (the phase schedule's clock), s.
    pub time_s: f64,
    /// The new hover point, replacing the descent target for the rest of the flight, NUE.
    pub site_nue: Nue,
    /// Tilt of the thrust axis from vertical the divert may count on, rad.
    pub max_tilt_rad: f64,
    /// `true`: re-plan the divert for the authority. `false`: only move the target, the
    /// schedule unchanged (the baseline the re-plan is compared with).
    pub replan: bool,
}

/// The schedule after a retarget, fixed at the guidance cycle it was commanded in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RetargetPlan {
    pub site_nue: Nue,
    /// Elapsed times of the (re-planned) descent's start and end; the hover at the site
    /// follows for the target hover duration.
    pub descent_start_s: f64,
    pub descent_end_s: f64,
    /// The lateral authority at the retarget, m/s^2.
    pub lateral_authority_mps2: f64,
    /// Whether the descent was re-planned for the authority (and its horizontal command is
    /// held within it), or the target only moved.
    pub replanned: bool,
}

/// Guidance phase, exchanged as the Integer output `guidance_phase`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    InitialHover = 1,
    Descent = 2,
    TargetHover = 3,
    Hold = 4,
    TerminalDescent = 5,
}

impl Scenario {
    /// The phase scheduled at `elapsed_s` after the start.
    pub fn phase_at(&self, elapsed_s: f64) -> Phase {
        self.phase_between(
            elapsed_s,
            self.hover_duration_s,
            self.hover_duration_s + self.descent_time_to_go_s,
        )
    }

    /// The phase at `elapsed_s` under a retarget plan (the schedule when there is none).
    pub fn phase_with(&self, plan: Option<&RetargetPlan>, elapsed_s: f64) -> Phase {
        match plan {
            None => self.phase_at(elapsed_s),
            Some(p) => self.phase_between(elapsed_s, p.descent_start_s, p.descent_end_s),
        }
    }

    /// The site the descent, the hover after it and the terminal descent fly to.
    pub fn site_with(&self, plan: Option<&RetargetPlan>) -> Nue {
        plan.map_or(self.descent_target_nue, |p| p.site_nue)
    }

    fn phase_between(&self, elapsed_s: f64, descent_start: f64, descent_end: f64) -> Phase {
        let target_hover_end = descent_end + self.target_hover_duration_s;
        if !has_reached(elapsed_s, descent_start) {
            Phase::InitialHover
        } else if !has_reached(elapsed_s, descent_end) {
            Phase::Descent
        } else if !has_reached(elapsed_s, target_hover_end) {
            Phase::TargetHover
        } else if self.terminal.enabled() {
            Phase::TerminalDescent
        } else {
            Phase::Hold
        }
    }
}

/// One polynomial solve, kept to evaluate it at later samples once frozen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DescentSolution {
    pub cubic: CubicAcceleration,
    /// Elapsed time of the sample it was solved at.
    pub solved_at_s: f64,
    pub time_to_go_at_solve_s: f64,
}

/// The guidance's memory between samples (part of the FMU state).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GuidanceState {
    /// Index of the guidance cycle last solved; `None` before the first solve.
    pub last_cycle: Option<i64>,
    pub phase: Phase,
    /// Held command: thrust acceleration in NUE (what the thrust axis is aligned with).
    pub a_thrust_cmd_nue: Nue,
    /// Held time-to-go of the descent (0 outside it).
    pub time_to_go_s: f64,
    /// The latest descent solve, while in the descent phase.
    pub descent: Option<DescentSolution>,
    /// The plan of a retarget once commanded; `None` before (and without) one.
    pub retarget: Option<RetargetPlan>,
    /// The terminal descent has cut the engine: thrust 0 from then on, the attitude held
    /// upright.
    pub engine_cut: bool,
}

impl GuidanceState {
    /// Before the first sample: hold gravity cancellation, i.e. hover.
    pub fn initial(gravity_mps2: f64) -> Self {
        Self {
            last_cycle: None,
            phase: Phase::InitialHover,
            a_thrust_cmd_nue: Nue::new(0.0, gravity_mps2, 0.0),
            time_to_go_s: 0.0,
            descent: None,
            retarget: None,
            engine_cut: false,
        }
    }
}

/// The navigation state guidance samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceInputs {
    pub r_nue: Nue,
    pub v_nue: Nue,
    pub mass_kg: f64,
}

/// One guidance sample at `elapsed_s`: the state to commit. Returns `state` unchanged unless
/// this sample opens a new guidance cycle (zero-order hold in between).
pub fn guidance_sample(
    scenario: &Scenario,
    state: &GuidanceState,
    elapsed_s: f64,
    nav: &GuidanceInputs,
) -> GuidanceState {
    let cycle = guidance_cycle_index(elapsed_s, scenario.guidance_cycle_s);
    guidance_sample_in_cycle(scenario, state, elapsed_s, cycle, nav)
}

/// [`guidance_sample`] for a caller that has the cycle `elapsed_s` falls in, as
/// [`guidance_cycle_index`] gives it.
#[inline(always)]
pub fn guidance_sample_in_cycle(
    scenario: &Scenario,
    state: &GuidanceState,
    elapsed_s: f64,
    (cycle, on_boundary): (i64, bool),
    nav: &GuidanceInputs,
) -> GuidanceState {
    if state.last_cycle == Some(cycle) {
        return *state;
    }
    // Late samples (after a degenerate step) use their own time; on-time ones the nominal cycle
    // time, so every master computes the same command whatever its rounding of `t`.
    let sample_s = if on_boundary {
        cycle as f64 * scenario.guidance_cycle_s
    } else {
        elapsed_s
    };
    // A retarget is planned once, at the first cycle at or after its time; a fresh plan is
    // never flown with a solve frozen for the old site.
    let (plan, fresh_plan) = match (&state.retarget, &scenario.retarget) {
        (Some(plan), _) => (Some(*plan), false),
        (None, Some(command)) if has_reached(sample_s, command.time_s) => (
            Some(plan_retarget(scenario, command, state, sample_s, nav)),
            true,
        ),
        _ => (None, false),
    };
    let phase = scenario.phase_with(plan.as_ref(), sample_s);
    let site_nue = scenario.site_with(plan.as_ref());
    let mut next = GuidanceState {
        last_cycle: Some(cycle),
        phase,
        time_to_go_s: 0.0,
        descent: None,
        retarget: plan,
        ..*state
    };
    match phase {
        Phase::InitialHover => {
            next.a_thrust_cmd_nue = hover(scenario, &scenario.hover_target_nue, nav);
        }
        Phase::TargetHover | Phase::Hold => {
            next.a_thrust_cmd_nue = hover(scenario, &site_nue, nav);
        }
        Phase::TerminalDescent => {
            next.engine_cut = state.engine_cut || scenario.terminal.cuts_off_at(nav.r_nue.0.y);
            next.a_thrust_cmd_nue = if next.engine_cut {
                Nue::new(0.0, scenario.gravity_mps2, 0.0)
            } else {
                terminal_descent(scenario, &site_nue, nav)
            };
        }
        Phase::Descent => {
            let descent_end_s = plan.map_or(
                scenario.hover_duration_s + scenario.descent_time_to_go_s,
                |p| p.descent_end_s,
            );
            let tgo_s = descent_end_s - sample_s;
            let previous = state
                .descent
                .filter(|_| state.phase == Phase::Descent && !fresh_plan);
            let solution = match previous {
                Some(frozen) if tgo_s < scenario.freeze_time_to_go_s => frozen,
                _ => {
                    let bc = descent_boundary_conditions(scenario, state, nav, &site_nue);
                    DescentSolution {
                        cubic: solve_cubic(&bc, tgo_s),
                        solved_at_s: sample_s,
                        time_to_go_at_solve_s: tgo_s,
                    }
                }
            };
            // Paper Sec. III: the command is the cubic one guidance step ahead of the solve;
            // once frozen the same cubic is read further along, never past its own tgo.
            let s = (sample_s - solution.solved_at_s + scenario.guidance_cycle_s)
                .min(solution.time_to_go_at_solve_s);
            let a_net_nue = solution.cubic.net_acceleration_nue(s);
            next.a_thrust_cmd_nue = thrust_acceleration_nue(&a_net_nue, scenario.gravity_mps2);
            // A re-planned divert never asks more of the tilt than the authority: the re-solves
            // that correct tracking errors are held to it, and restart from the held command.
            if let Some(p) = plan.filter(|p| p.replanned) {
                next.a_thrust_cmd_nue =
                    limit_horizontal(&next.a_thrust_cmd_nue, p.lateral_authority_mps2);
            }
            next.time_to_go_s = tgo_s;
            next.descent = Some(solution);
        }
    }
    next.a_thrust_cmd_nue = achievable_thrust_acceleration_nue(
        &next.a_thrust_cmd_nue,
        nav.mass_kg,
        scenario.thrust_min_n,
        scenario.thrust_max_n,
    );
    next
}

/// The descent's boundary conditions from the current state: start at the held command (net;
/// at the first solve after a hover, as [`Scenario::handover`] says), end at `site_nue` at
/// rest with zero acceleration.
fn descent_boundary_conditions(
    scenario: &Scenario,
    state: &GuidanceState,
    nav: &GuidanceInputs,
    site_nue: &Nue,
) -> BoundaryConditions {
    let after_hover = state.phase != Phase::Descent;
    let a0_net_nue = match scenario.handover {
        Handover::ZeroNet if after_hover => Nue::zeros(),
        _ => net_acceleration_nue(&state.a_thrust_cmd_nue, scenario.gravity_mps2),
    };
    BoundaryConditions {
        r0_nue: nav.r_nue,
        v0_nue: nav.v_nue,
        a0_net_nue,
        rf_nue: *site_nue,
        vf_nue: Nue::zeros(),
        af_net_nue: Nue::zeros(),
    }
}

/// The schedule after a retarget commanded at `sample_s`.
///
/// Before the nominal descent starts, the site moves and the schedule stays: the descent
/// will fly to the new site over its full time-to-go. Later (descent, hover, hold, terminal
/// descent), with `replan`, a divert starts now and lasts [`divert_time_to_go_s`] from the
/// current state to the new site, sized for [`DIVERT_AUTHORITY_SHARE`] of the lateral
/// authority, from a lower bound: the nominal descent's remaining
/// time-to-go, and the freeze time-to-go (at least one fresh solve). Without `replan` the
/// site moves and the schedule stays (the baseline).
pub fn plan_retarget(
    scenario: &Scenario,
    command: &Retarget,
    state: &GuidanceState,
    sample_s: f64,
    nav: &GuidanceInputs,
) -> RetargetPlan {
    let nominal_start_s = scenario.hover_duration_s;
    let nominal_end_s = nominal_start_s + scenario.descent_time_to_go_s;
    let lateral_authority_mps2 = lateral_authority_mps2(
        scenario.thrust_max_n,
        nav.mass_kg,
        scenario.gravity_mps2,
        command.max_tilt_rad,
    );
    let moved = RetargetPlan {
        site_nue: command.site_nue,
        descent_start_s: nominal_start_s,
        descent_end_s: nominal_end_s,
        lateral_authority_mps2,
        replanned: false,
    };
    if !command.replan || !has_reached(sample_s, nominal_start_s) {
        return moved;
    }
    let bc = descent_boundary_conditions(scenario, state, nav, &command.site_nue);
    let min_tgo_s = (nominal_end_s - sample_s).max(scenario.freeze_time_to_go_s);
    let tgo_s = divert_time_to_go_s(
        &bc,
        min_tgo_s,
        scenario.guidance_cycle_s,
        DIVERT_AUTHORITY_SHARE * lateral_authority_mps2,
    );
    RetargetPlan {
        descent_start_s: sample_s,
        descent_end_s: sample_s + tgo_s,
        replanned: true,
        ..moved
    }
}

fn hover(scenario: &Scenario, target_nue: &Nue, nav: &GuidanceInputs) -> Nue {
    pv_thrust_acceleration_nue(
        &scenario.pv_gains,
        scenario.gravity_mps2,
        target_nue,
        &Nue::zeros(),
        &nav.r_nue,
        &nav.v_nue,
    )
}

/// PV law holding the descent target's North/East while tracking the profile's sink rate
/// ([`TerminalDescent::sink_rate_mps`]): the reference altitude is the current one, so only
/// the velocity error drives the vertical axis and the lander keeps sinking whatever the
/// ground height; a slowing reference's acceleration is fed forward.
fn terminal_descent(scenario: &Scenario, target: &Nue, nav: &GuidanceInputs) -> Nue {
    let (sink_mps, slowing_mps2) = scenario.terminal.sink_rate_mps(nav.r_nue.0.y);
    let r_ref_nue = Nue::new(target.0.x, nav.r_nue.0.y, target.0.z);
    let v_ref_nue = Nue::new(0.0, -sink_mps, 0.0);
    let pv = pv_thrust_acceleration_nue(
        &scenario.pv_gains,
        scenario.gravity_mps2,
        &r_ref_nue,
        &v_ref_nue,
        &nav.r_nue,
        &nav.v_nue,
    );
    if slowing_mps2 == 0.0 {
        pv
    } else {
        pv + Nue::new(0.0, slowing_mps2, 0.0)
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn paper_scenario() -> Scenario {
        Scenario {
            hover_target_nue: Nue::new(0.0, 800.0, 0.0),
            hover_duration_s: 12.0,
            descent_target_nue: Nue::new(0.0, 150.0, 0.0),
            descent_time_to_go_s: 130.0,
            freeze_time_to_go_s: 5.0,
            target_hover_duration_s: 30.0,
            guidance_cycle_s: 0.1,
            gravity_mps2: 1.62,
            pv_gains: PvGains::from_bandwidth(0.06, 0.8),
            thrust_min_n: 720.0,
            thrust_max_n: 1600.0,
            terminal: TerminalDescent::NONE,
            retarget: None,
            handover: Handover::HoverCommand,
        }
    }

    #[test]
    fn the_inline_floor_is_std_floor_but_for_the_sign_of_zero() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::from_bits(1),
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.3e18,
            -9.3e18,
            1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            values.extend([x, x.fract(), x * 1e-300, (state >> 11) as f64 * 1e-12]);
        }
        for k in 0..=100_000 {
            values.extend([f64::from(k) * 0.01, f64::from(k) * 0.1 + 1e-9]);
        }
        for x in values {
            let (ours, std) = (floor(x), x.floor());
            if std.is_nan() {
                assert!(ours.is_nan(), "{x:e}");
            } else {
                assert_eq!(ours, std, "{x:e}");
                assert!(
                    ours != 0.0 || ours.to_bits() == std.to_bits() || x == 0.0,
                    "{x:e}"
                );
            }
        }
    }

    #[test]
    fn cycle_index_tolerates_accumulated_rounding() {
        // fmpy's SSP runner reaches step 1200 of 0.01 s here
        assert_eq!(guidance_cycle_index(11.999999999999789, 0.1), (120, true));
        assert_eq!(guidance_cycle_index(12.0, 0.1), (120, true));
        assert_eq!(guidance_cycle_index(12.05, 0.1), (120, false));
        assert_eq!(guidance_cycle_index(12.0999999, 0.1), (120, false));
        assert_eq!(
            guidance_cycle_index(12.099999999, 0.1),
            (121, true),
            "within 1e-9 relative"
        );
        // accumulating 0.01 a thousand times stays on the same cycles as exact multiples
        let mut t = 0.0;
        for step in 0..20_000_i64 {
            assert_eq!(guidance_cycle_index(t, 0.1).0, step / 10, "t = {t}");
            t += 0.01;
        }
    }

    #[test]
    fn phases_follow_the_schedule_with_tolerance() {
        let s = paper_scenario();
        assert_eq!(s.phase_at(0.0), Phase::InitialHover);
        assert_eq!(s.phase_at(11.9), Phase::InitialHover);
        assert_eq!(s.phase_at(11.999999999999789), Phase::Descent);
        assert_eq!(s.phase_at(141.99999999999), Phase::TargetHover);
        assert_eq!(s.phase_at(171.9), Phase::TargetHover);
        assert_eq!(s.phase_at(172.0), Phase::Hold);
    }

    #[test]
    fn command_is_held_within_a_cycle() {
        let s = paper_scenario();
        let nav = GuidanceInputs {
            r_nue: Nue::new(0.0, 790.0, 0.0),
            v_nue: Nue::zeros(),
            mass_kg: 900.0,
        };
        let first = guidance_sample(&s, &GuidanceState::initial(1.62), 0.0, &nav);
        let moved = GuidanceInputs {
            r_nue: Nue::new(5.0, 700.0, 0.0),
            ..nav
        };
        assert_eq!(guidance_sample(&s, &first, 0.05, &moved), first);
        assert_ne!(guidance_sample(&s, &first, 0.1, &moved), first);
    }

    #[test]
    fn open_loop_double_integrator_descends_to_the_target() {
        // GIVEN a point mass at rest at the hover target, integrated exactly between samples
        // (the command is constant over each 10 Hz cycle, so the integration is exact)
        let s = paper_scenario();
        // At 900 kg the braking at the end of the descent (net 0.23 m/s^2 up, thrust 1.85
        // m/s^2) would exceed 1600 N; in flight the mass is ~840 kg by then. A fixed 820 kg
        // keeps this test about the polynomial, not about saturation.
        let mass_kg = 820.0;
        let mut state = GuidanceState::initial(s.gravity_mps2);
        let mut r = s.hover_target_nue.0;
        let mut v = Vector3::zeros();
        let dt = s.guidance_cycle_s;
        let mut max_tgo_seen: f64 = 0.0;
        // WHEN guidance runs through hover and descent
        for k in 0..1420 {
            let elapsed = k as f64 * dt;
            state = guidance_sample(
                &s,
                &state,
                elapsed,
                &GuidanceInputs {
                    r_nue: Nue(r),
                    v_nue: Nue(v),
                    mass_kg,
                },
            );
            let a_net = net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2).0;
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
            if state.phase == Phase::Descent {
                max_tgo_seen = max_tgo_seen.max(state.time_to_go_s);
                assert!(state.time_to_go_s > 0.0);
            }
        }
        // THEN it arrives at 150 m at rest, within what the frozen last 5 s leave
        assert!((r - s.descent_target_nue.0).norm() < 0.5, "r = {r}");
        assert!(v.norm() < 0.05, "v = {v}");
        assert!((max_tgo_seen - 130.0).abs() < 1e-9);
        // AND the hover afterwards holds it there
        let held = guidance_sample(
            &s,
            &state,
            142.0,
            &GuidanceInputs {
                r_nue: Nue(r),
                v_nue: Nue(v),
                mass_kg,
            },
        );
        assert_eq!(held.phase, Phase::TargetHover);
        assert_eq!(held.time_to_go_s, 0.0);
    }

    #[test]
    fn coefficients_freeze_below_the_freeze_time_to_go() {
        let s = paper_scenario();
        let nav = GuidanceInputs {
            r_nue: Nue::new(0.0, 160.0, 0.0),
            v_nue: Nue::new(0.0, -2.0, 0.0),
            mass_kg: 900.0,
        };
        // tgo = 5.1 s: solved afresh
        let before = GuidanceState {
            phase: Phase::Descent,
            last_cycle: Some(1368),
            ..GuidanceState::initial(1.62)
        };
        let at_5_1 = guidance_sample(&s, &before, 136.9, &nav);
        let solved = at_5_1.descent.unwrap();
        assert!((solved.solved_at_s - 136.9).abs() < 1e-12);
        // tgo = 4.9 s with a very different state: still the old coefficients
        let far = GuidanceInputs {
            r_nue: Nue::new(50.0, 300.0, 0.0),
            ..nav
        };
        let at_4_9 = guidance_sample(
            &s,
            &GuidanceState {
                last_cycle: Some(1370),
                ..at_5_1
            },
            137.1,
            &far,
        );
        assert_eq!(at_4_9.descent.unwrap(), solved);
        assert!(at_4_9.a_thrust_cmd_nue.0.iter().all(|a| a.is_finite()));
    }

    /// The end of the initial hover (12 s) at rest on the vertical through the site, the
    /// hover's last command leaning `a0_north_mps2` North: what the descent's first solve sees.
    fn handing_over(a0_north_mps2: f64) -> GuidanceState {
        GuidanceState {
            phase: Phase::InitialHover,
            last_cycle: Some(119),
            a_thrust_cmd_nue: Nue::new(a0_north_mps2, 1.62, 0.0),
            ..GuidanceState::initial(1.62)
        }
    }

    /// Flies the descent open loop from [`handing_over`] (exact integration between samples,
    /// re-solved every cycle until the freeze); returns the largest distance North of the
    /// vertical and when it was reached.
    fn descent_excursion(s: &Scenario, a0_north_mps2: f64) -> (f64, f64) {
        // Light enough that the 0.3 m/s^2 lean and the braking stay inside the engine range.
        let mass_kg = 700.0;
        let mut state = handing_over(a0_north_mps2);
        let (mut r, mut v) = (s.hover_target_nue.0, Vector3::zeros());
        let dt = s.guidance_cycle_s;
        let mut peak = (0.0, 0.0);
        for k in 0..1300 {
            let elapsed = 12.0 + k as f64 * dt;
            let nav = GuidanceInputs {
                r_nue: Nue(r),
                v_nue: Nue(v),
                mass_kg,
            };
            state = guidance_sample(s, &state, elapsed, &nav);
            assert_eq!(state.phase, Phase::Descent);
            let a_net = net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2).0;
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
            if r.x.abs() > peak.0 {
                peak = (r.x.abs(), elapsed + dt);
            }
        }
        peak
    }

    #[test]
    fn the_papers_handover_carries_the_hover_command_through_the_descent() {
        // GIVEN the paper's handover and a hover that ends leaning 0.3 m/s^2 North, at rest on
        // the vertical
        let s = paper_scenario();
        let (a0, tgo) = (0.3, s.descent_time_to_go_s);
        // WHEN the descent flies it
        let (peak_m, at_s) = descent_excursion(&s, a0);
        // THEN it strays as the open-loop cubic from rest with a(0) = a0 and a, v, r back to 0
        // at tgo: a(u) = a0 (1 - 9u + 18u^2 - 10u^3), r(u) = a0 tgo^2 u^2 (1 - u)^3 / 2, at
        // most 0.01728 a0 tgo^2 at u = 0.4 (87.6 m here): re-solving every cycle from the held
        // command gives back the same cubic, so the closed loop cannot reject it. The sampled
        // command (the cubic one cycle ahead, held over the cycle) lowers the peak by 0.5 %.
        let expected_m = 0.01728 * a0 * tgo * tgo;
        assert!(
            (peak_m - expected_m).abs() < 1e-2 * expected_m,
            "{peak_m} m vs {expected_m} m"
        );
        assert!((at_s - (12.0 + 0.4 * tgo)).abs() < 0.5, "{at_s} s");
    }

    #[test]
    fn a_zero_net_handover_does_not_inherit_the_hover_command() {
        // GIVEN the same hover's end with the descent starting from zero net acceleration
        let s = Scenario {
            handover: Handover::ZeroNet,
            ..paper_scenario()
        };
        // WHEN the descent flies it
        let (peak_m, _) = descent_excursion(&s, 0.3);
        // THEN nothing moves it off the vertical: on target, at rest, no acceleration
        assert!(peak_m < 1e-12, "{peak_m} m");
        // AND only the first solve starts from zero: the next ones start from the held command
        let nav = GuidanceInputs {
            r_nue: Nue::new(3.0, 800.0, 0.0),
            v_nue: Nue::new(0.2, 0.0, 0.0),
            mass_kg: 700.0,
        };
        let first = guidance_sample(&s, &handing_over(0.3), 12.0, &nav);
        assert_eq!(first.descent.unwrap().cubic.coeffs[0], Nue::zeros());
        let second = guidance_sample(&s, &first, 12.1, &nav);
        let held_net = net_acceleration_nue(&first.a_thrust_cmd_nue, s.gravity_mps2);
        assert_eq!(second.descent.unwrap().cubic.coeffs[0], held_net);
        assert_ne!(held_net, Nue::zeros());
    }

    #[test]
    fn terminal_descent_replaces_the_hold_only_when_enabled() {
        let paper = paper_scenario();
        assert_eq!(paper.phase_at(500.0), Phase::Hold);
        let landing = Scenario {
            terminal: TerminalDescent {
                speed_mps: 1.0,
                ..TerminalDescent::NONE
            },
            ..paper
        };
        assert_eq!(landing.phase_at(171.9), Phase::TargetHover);
        assert_eq!(landing.phase_at(172.0), Phase::TerminalDescent);
    }

    #[test]
    fn terminal_descent_sinks_at_the_commanded_speed_and_holds_north_east() {
        // GIVEN a point mass hovering 3 m North of and 2 m East of the target, at 150 m
        let s = Scenario {
            terminal: TerminalDescent {
                speed_mps: 1.2,
                ..TerminalDescent::NONE
            },
            ..paper_scenario()
        };
        let mut state = GuidanceState::initial(s.gravity_mps2);
        let mut r = Vector3::new(3.0, 150.0, 2.0);
        let mut v = Vector3::zeros();
        let dt = s.guidance_cycle_s;
        // WHEN terminal descent guidance flies it for 100 s from 172 s (exact integration
        // between samples)
        for k in 0..1000 {
            let elapsed = 172.0 + k as f64 * dt;
            let nav = GuidanceInputs {
                r_nue: Nue(r),
                v_nue: Nue(v),
                mass_kg: 820.0,
            };
            state = guidance_sample(&s, &state, elapsed, &nav);
            assert_eq!(state.phase, Phase::TerminalDescent);
            let a_net = net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2).0;
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
        }
        // THEN it sinks at the commanded 1.2 m/s over the target's North/East
        assert!((v.y + 1.2).abs() < 1e-3, "v = {v}");
        assert!(
            r.x.hypot(r.z) < 0.05 && v.x.hypot(v.z) < 0.01,
            "r = {r}, v = {v}"
        );
        // the altitude lost is the speed times the time, less the speed-up transient
        let lost = 150.0 - r.y;
        assert!(lost > 100.0 && lost < 120.0, "lost {lost} m");
    }

    #[test]
    fn a_flaring_terminal_descent_slows_to_its_final_speed_and_cuts_the_engine() {
        // GIVEN a point mass at 150 m sinking under a profile from 2 m/s to 0.5 m/s with a
        // 10 s flare, the ground at 0 and the cut-off at 1.5 m
        let s = Scenario {
            terminal: TerminalDescent {
                speed_mps: 2.0,
                final_speed_mps: 0.5,
                flare_time_s: 10.0,
                ground_height_m: 0.0,
                cutoff_height_m: 1.5,
            },
            ..paper_scenario()
        };
        let mut state = GuidanceState::initial(s.gravity_mps2);
        let (mut r, mut v) = (Vector3::new(0.0, 150.0, 0.0), Vector3::zeros());
        let dt = s.guidance_cycle_s;
        let mut v_at_10_m = None;
        let mut cut_at = None;
        // WHEN terminal descent guidance flies it (exact integration between samples) until
        // it reaches the ground
        for k in 0..4000 {
            let nav = GuidanceInputs {
                r_nue: Nue(r),
                v_nue: Nue(v),
                mass_kg: 820.0,
            };
            state = guidance_sample(&s, &state, 172.0 + k as f64 * dt, &nav);
            if state.engine_cut && cut_at.is_none() {
                cut_at = Some((r.y, v.y));
            }
            if r.y < 10.0 && v_at_10_m.is_none() {
                v_at_10_m = Some(v.y);
            }
            let a_net = if state.engine_cut {
                Vector3::new(0.0, -s.gravity_mps2, 0.0)
            } else {
                net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2).0
            };
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
            if r.y <= 0.0 {
                break;
            }
        }
        // THEN at 10 m it sinks near h / tau = 1 m/s (the loop lags the reference a little),
        // the engine is cut within one guidance cycle of 1.5 m at about the final speed, and
        // the commanded thrust direction is upright from then on
        let v10 = v_at_10_m.unwrap();
        assert!((v10 + 1.0).abs() < 0.15, "{v10}");
        let (h_cut, v_cut) = cut_at.unwrap();
        assert!(h_cut <= 1.5 && h_cut > 1.5 - 0.1, "{h_cut}");
        assert!((v_cut + 0.5).abs() < 0.1, "{v_cut}");
        assert_eq!(state.a_thrust_cmd_nue, Nue::new(0.0, s.gravity_mps2, 0.0));
        // AND it falls freely from there: v^2 = v_cut^2 + 2 g (h_cut - h), which from the
        // cut-off height is the touchdown speed sqrt(v_cut^2 + 2 g h_cut)
        let expected = (v_cut * v_cut + 2.0 * s.gravity_mps2 * (h_cut - r.y)).sqrt();
        assert!(r.y <= 0.0);
        assert!((v.y.abs() - expected).abs() < 1e-9, "{} vs {expected}", v.y);
    }

    fn retargeted(time_s: f64, replan: bool) -> Scenario {
        Scenario {
            retarget: Some(Retarget {
                time_s,
                site_nue: Nue::new(30.0, 150.0, 0.0),
                max_tilt_rad: 15f64.to_radians(),
                replan,
            }),
            ..paper_scenario()
        }
    }

    /// Flies `s` open loop from `state` at `r`, `v` (at rest unless given) from `start_s`
    /// for `duration_s`, integrating the double integrator exactly between samples; returns
    /// the end state, position and the largest horizontal command seen.
    fn fly_open_loop(
        s: &Scenario,
        mut state: GuidanceState,
        mut r: Vector3<f64>,
        start_s: f64,
        duration_s: f64,
        mass_kg: f64,
    ) -> (GuidanceState, Vector3<f64>, Vector3<f64>, f64) {
        let mut v = Vector3::zeros();
        let dt = s.guidance_cycle_s;
        let mut peak_lateral: f64 = 0.0;
        for k in 0..(duration_s / dt).round() as i64 {
            let elapsed = start_s + k as f64 * dt;
            let nav = GuidanceInputs {
                r_nue: Nue(r),
                v_nue: Nue(v),
                mass_kg,
            };
            state = guidance_sample(s, &state, elapsed, &nav);
            let a = state.a_thrust_cmd_nue.0;
            peak_lateral = peak_lateral.max(a.x.hypot(a.z));
            let a_net = net_acceleration_nue(&Nue(a), s.gravity_mps2).0;
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
        }
        (state, r, v, peak_lateral)
    }

    fn hovering_at_150_m() -> GuidanceState {
        GuidanceState {
            phase: Phase::TargetHover,
            last_cycle: Some(1499),
            ..GuidanceState::initial(1.62)
        }
    }

    #[test]
    fn a_retarget_in_the_hover_replans_a_divert_sized_for_the_authority() {
        // GIVEN a lander at rest at 150 m in the target hover, retargeted 30 m North at 150 s
        let s = retargeted(150.0, true);
        let mass_kg = 840.0;
        let start = hovering_at_150_m();
        let nav = GuidanceInputs {
            r_nue: Nue::new(0.0, 150.0, 0.0),
            v_nue: Nue::zeros(),
            mass_kg,
        };
        // WHEN guidance samples the retarget's cycle
        let first = guidance_sample(&s, &start, 150.0, &nav);
        // THEN it plans a divert from now, as long as the closed form for 80 % of the
        // 15 deg authority (g tan 15 deg = 0.434 m/s^2) asks, rounded up to the 0.1 s grid
        let plan = first.retarget.unwrap();
        let authority = 1.62 * 15f64.to_radians().tan();
        assert!((plan.lateral_authority_mps2 - authority).abs() < 1e-12);
        let closed = super::super::retarget::rest_to_rest_divert_time_s(
            30.0,
            super::super::retarget::DIVERT_AUTHORITY_SHARE * authority,
        );
        let tgo = plan.descent_end_s - plan.descent_start_s;
        assert_eq!(plan.descent_start_s, 150.0);
        assert!(tgo >= closed - 1e-9 && tgo < closed + 0.1, "{tgo} {closed}");
        assert!(plan.replanned);
        assert_eq!(first.phase, Phase::Descent);
        assert!((first.time_to_go_s - tgo).abs() < 1e-12);
        // AND flown open loop it reaches the new site at rest, never commanding more lateral
        // acceleration than the authority; then it hovers there, then holds
        let (end, r, v, peak) = fly_open_loop(&s, first, nav.r_nue.0, 150.1, tgo + 40.0, mass_kg);
        assert!(
            (r - Vector3::new(30.0, 150.0, 0.0)).norm() < 0.05,
            "r = {r}"
        );
        assert!(v.norm() < 0.01, "v = {v}");
        assert!(peak <= 0.8 * authority + 1e-3, "{peak} > {authority}");
        assert_eq!(end.phase, Phase::Hold);
        assert_eq!(
            s.phase_with(Some(&plan), 150.0 + tgo + 1.0),
            Phase::TargetHover
        );
        assert_eq!(end.retarget, Some(plan), "planned once");
    }

    #[test]
    fn without_the_replan_the_target_only_moves() {
        // GIVEN the same retarget with the re-plan off
        let s = retargeted(150.0, false);
        let nav = GuidanceInputs {
            r_nue: Nue::new(0.0, 150.0, 0.0),
            v_nue: Nue::zeros(),
            mass_kg: 840.0,
        };
        let first = guidance_sample(&s, &hovering_at_150_m(), 150.0, &nav);
        // THEN the schedule is the nominal one and the hover pulls toward the new site
        let plan = first.retarget.unwrap();
        assert!(!plan.replanned);
        assert_eq!((plan.descent_start_s, plan.descent_end_s), (12.0, 142.0));
        assert_eq!(first.phase, Phase::TargetHover);
        let unretargeted = guidance_sample(&paper_scenario(), &hovering_at_150_m(), 150.0, &nav);
        assert!(
            first.a_thrust_cmd_nue.0.x > 0.5,
            "{}",
            first.a_thrust_cmd_nue.0
        );
        assert_eq!(unretargeted.a_thrust_cmd_nue.0.x, 0.0);
    }

    #[test]
    fn a_retarget_before_the_descent_moves_the_descent_target_on_schedule() {
        // GIVEN a retarget at 5 s, during the hover at 800 m
        let s = retargeted(5.0, true);
        let (state, r, _, _) = fly_open_loop(
            &s,
            GuidanceState::initial(1.62),
            s.hover_target_nue.0,
            0.0,
            142.0,
            820.0,
        );
        // THEN the schedule is the nominal one and the descent ends over the new site
        let plan = state.retarget.unwrap();
        assert_eq!((plan.descent_start_s, plan.descent_end_s), (12.0, 142.0));
        assert!((r - Vector3::new(30.0, 150.0, 0.0)).norm() < 0.5, "r = {r}");
    }

    #[test]
    fn a_retarget_not_yet_reached_changes_no_sample() {
        // GIVEN the paper's flight, and the same with a retarget at 1000 s
        let later = retargeted(1000.0, true);
        let (a, ra, va, _) = fly_open_loop(
            &paper_scenario(),
            GuidanceState::initial(1.62),
            paper_scenario().hover_target_nue.0,
            0.0,
            172.0,
            820.0,
        );
        let (b, rb, vb, _) = fly_open_loop(
            &later,
            GuidanceState::initial(1.62),
            later.hover_target_nue.0,
            0.0,
            172.0,
            820.0,
        );
        // THEN both end bit for bit in the same state
        assert_eq!((a, ra, va), (b, rb, vb));
        assert!(b.retarget.is_none());
    }
}
