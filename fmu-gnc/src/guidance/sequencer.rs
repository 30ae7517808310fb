//! The guidance phase sequencer (paper Sec. V scenario) and the 10 Hz zero-order hold.
//!
//! Phases by default: (1) PV hover at 800 m for 12 s, (2) polynomial descent to 150 m with
//! tgo = 130 s, (3) PV hover at 150 m for 30 s, (4) hold: PV hover at the descent target for
//! ever. Targets, durations and tgo are parameters. The schedule counts from the start time.
//! Optionally (beyond the paper, off by default) phase 4 is replaced by (5) a terminal descent:
//! straight down over the descent target at a commanded constant speed until touchdown.
//!
//! Guidance is sampled: a new command is computed once per guidance cycle, at the first sample
//! whose integer cycle index differs from the last one solved, and held in between. The index is
//! derived from the elapsed time with a tolerance, never accumulated, so masters that reach
//! `t = 11.999999999999789` instead of 12 see the same cycle and the same phase.
use super::polynomial::{solve_cubic, BoundaryConditions, CubicAcceleration};
use super::pv::{pv_thrust_acceleration_nue, PvGains};
use super::thrust::{
    achievable_thrust_acceleration_nue, net_acceleration_nue, thrust_acceleration_nue,
};
use nalgebra::Vector3;
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
    let index = ((elapsed_s + time_tolerance(elapsed_s)) / cycle_s).floor();
    let on_boundary = (elapsed_s - index * cycle_s).abs() <= time_tolerance(elapsed_s);
    // An f64 quotient of a finite time by a validated positive cycle fits an i64 for any
    // realistic run; `as` saturates rather than wraps beyond that.
    (index as i64, on_boundary)
}

/// The scenario: targets, durations and the guidance settings, all in SI and NUE.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenario {
    pub hover_target_nue: Vector3<f64>,
    pub hover_duration_s: f64,
    pub descent_target_nue: Vector3<f64>,
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
    /// Sink rate of the terminal descent after the target hover (m/s, > 0); 0 = no terminal
    /// descent, hold the hover (the paper).
    pub terminal_descent_speed_mps: f64,
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
        let descent_start = self.hover_duration_s;
        let descent_end = descent_start + self.descent_time_to_go_s;
        let target_hover_end = descent_end + self.target_hover_duration_s;
        if !has_reached(elapsed_s, descent_start) {
            Phase::InitialHover
        } else if !has_reached(elapsed_s, descent_end) {
            Phase::Descent
        } else if !has_reached(elapsed_s, target_hover_end) {
            Phase::TargetHover
        } else if self.terminal_descent_speed_mps > 0.0 {
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
    pub a_thrust_cmd_nue: Vector3<f64>,
    /// Held time-to-go of the descent (0 outside it).
    pub time_to_go_s: f64,
    /// The latest descent solve, while in the descent phase.
    pub descent: Option<DescentSolution>,
}

impl GuidanceState {
    /// Before the first sample: hold gravity cancellation, i.e. hover.
    pub fn initial(gravity_mps2: f64) -> Self {
        Self {
            last_cycle: None,
            phase: Phase::InitialHover,
            a_thrust_cmd_nue: Vector3::new(0.0, gravity_mps2, 0.0),
            time_to_go_s: 0.0,
            descent: None,
        }
    }
}

/// The navigation state guidance samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceInputs {
    pub r_nue: Vector3<f64>,
    pub v_nue: Vector3<f64>,
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
    let (cycle, on_boundary) = guidance_cycle_index(elapsed_s, scenario.guidance_cycle_s);
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
    let phase = scenario.phase_at(sample_s);
    let mut next = GuidanceState {
        last_cycle: Some(cycle),
        phase,
        time_to_go_s: 0.0,
        descent: None,
        ..*state
    };
    match phase {
        Phase::InitialHover => {
            next.a_thrust_cmd_nue = hover(scenario, &scenario.hover_target_nue, nav);
        }
        Phase::TargetHover | Phase::Hold => {
            next.a_thrust_cmd_nue = hover(scenario, &scenario.descent_target_nue, nav);
        }
        Phase::TerminalDescent => {
            next.a_thrust_cmd_nue = terminal_descent(scenario, nav);
        }
        Phase::Descent => {
            let descent_end_s = scenario.hover_duration_s + scenario.descent_time_to_go_s;
            let tgo_s = descent_end_s - sample_s;
            let previous = state.descent.filter(|_| state.phase == Phase::Descent);
            let solution = match previous {
                Some(frozen) if tgo_s < scenario.freeze_time_to_go_s => frozen,
                _ => {
                    let bc = BoundaryConditions {
                        r0_nue: nav.r_nue,
                        v0_nue: nav.v_nue,
                        a0_net_nue: net_acceleration_nue(
                            &state.a_thrust_cmd_nue,
                            scenario.gravity_mps2,
                        ),
                        rf_nue: scenario.descent_target_nue,
                        vf_nue: Vector3::zeros(),
                        af_net_nue: Vector3::zeros(),
                    };
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

fn hover(scenario: &Scenario, target_nue: &Vector3<f64>, nav: &GuidanceInputs) -> Vector3<f64> {
    pv_thrust_acceleration_nue(
        &scenario.pv_gains,
        scenario.gravity_mps2,
        target_nue,
        &Vector3::zeros(),
        &nav.r_nue,
        &nav.v_nue,
    )
}

/// PV law holding the descent target's North/East while tracking a constant sink rate: the
/// reference altitude is the current one, so only the velocity error drives the vertical axis
/// and the lander keeps sinking whatever the ground height.
fn terminal_descent(scenario: &Scenario, nav: &GuidanceInputs) -> Vector3<f64> {
    let target = scenario.descent_target_nue;
    let r_ref_nue = Vector3::new(target.x, nav.r_nue.y, target.z);
    let v_ref_nue = Vector3::new(0.0, -scenario.terminal_descent_speed_mps, 0.0);
    pv_thrust_acceleration_nue(
        &scenario.pv_gains,
        scenario.gravity_mps2,
        &r_ref_nue,
        &v_ref_nue,
        &nav.r_nue,
        &nav.v_nue,
    )
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    fn paper_scenario() -> Scenario {
        Scenario {
            hover_target_nue: Vector3::new(0.0, 800.0, 0.0),
            hover_duration_s: 12.0,
            descent_target_nue: Vector3::new(0.0, 150.0, 0.0),
            descent_time_to_go_s: 130.0,
            freeze_time_to_go_s: 5.0,
            target_hover_duration_s: 30.0,
            guidance_cycle_s: 0.1,
            gravity_mps2: 1.62,
            pv_gains: PvGains::from_bandwidth(0.06, 0.8),
            thrust_min_n: 720.0,
            thrust_max_n: 1600.0,
            terminal_descent_speed_mps: 0.0,
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
            r_nue: Vector3::new(0.0, 790.0, 0.0),
            v_nue: Vector3::zeros(),
            mass_kg: 900.0,
        };
        let first = guidance_sample(&s, &GuidanceState::initial(1.62), 0.0, &nav);
        let moved = GuidanceInputs {
            r_nue: Vector3::new(5.0, 700.0, 0.0),
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
        let mut r = s.hover_target_nue;
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
                    r_nue: r,
                    v_nue: v,
                    mass_kg,
                },
            );
            let a_net = net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2);
            r += v * dt + a_net * (0.5 * dt * dt);
            v += a_net * dt;
            if state.phase == Phase::Descent {
                max_tgo_seen = max_tgo_seen.max(state.time_to_go_s);
                assert!(state.time_to_go_s > 0.0);
            }
        }
        // THEN it arrives at 150 m at rest, within what the frozen last 5 s leave
        assert!((r - s.descent_target_nue).norm() < 0.5, "r = {r}");
        assert!(v.norm() < 0.05, "v = {v}");
        assert!((max_tgo_seen - 130.0).abs() < 1e-9);
        // AND the hover afterwards holds it there
        let held = guidance_sample(
            &s,
            &state,
            142.0,
            &GuidanceInputs {
                r_nue: r,
                v_nue: v,
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
            r_nue: Vector3::new(0.0, 160.0, 0.0),
            v_nue: Vector3::new(0.0, -2.0, 0.0),
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
            r_nue: Vector3::new(50.0, 300.0, 0.0),
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
        assert!(at_4_9.a_thrust_cmd_nue.iter().all(|a| a.is_finite()));
    }

    #[test]
    fn terminal_descent_replaces_the_hold_only_when_enabled() {
        let paper = paper_scenario();
        assert_eq!(paper.phase_at(500.0), Phase::Hold);
        let landing = Scenario {
            terminal_descent_speed_mps: 1.0,
            ..paper
        };
        assert_eq!(landing.phase_at(171.9), Phase::TargetHover);
        assert_eq!(landing.phase_at(172.0), Phase::TerminalDescent);
    }

    #[test]
    fn terminal_descent_sinks_at_the_commanded_speed_and_holds_north_east() {
        // GIVEN a point mass hovering 3 m North of and 2 m East of the target, at 150 m
        let s = Scenario {
            terminal_descent_speed_mps: 1.2,
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
                r_nue: r,
                v_nue: v,
                mass_kg: 820.0,
            };
            state = guidance_sample(&s, &state, elapsed, &nav);
            assert_eq!(state.phase, Phase::TerminalDescent);
            let a_net = net_acceleration_nue(&state.a_thrust_cmd_nue, s.gravity_mps2);
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
}
