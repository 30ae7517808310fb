//! Parameters are validated as far as the outputs: any parameter set that passes validation
//! yields finite derived quantities and, for every admissible input, finite outputs.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmu_gnc::actuation::PwpfBank;
use fmu_gnc::attitude::profile::PhiProfile;
use fmu_gnc::controller::{actuate, gnc_sample, NavigationInputs};
use fmu_gnc::guidance::sequencer::GuidanceState;
use fmu_gnc::params::GncParameters;
use nalgebra::{Quaternion, UnitQuaternion};
use proptest::prelude::*;

/// A value of any magnitude and sign, often an extreme one.
fn any_magnitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-300.0..300.0f64, any::<bool>()).prop_map(|(e, neg)| {
            let x = 10f64.powf(e);
            if neg {
                -x
            } else {
                x
            }
        }),
        Just(0.0),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
    ]
}

/// Either the default or any magnitude (so that sets mixing sane and extreme values are common).
fn or_default(default: f64) -> impl Strategy<Value = f64> {
    prop_oneof![8 => Just(default), 1 => any_magnitude()]
}

/// At an admissible extreme, or the default.
fn at_bounds(default: f64, low: f64, high: f64) -> impl Strategy<Value = f64> {
    prop_oneof![Just(default), Just(low), Just(high)]
}

/// Every bounded parameter at its default or at either end of its admissible range (the
/// relations between them still checked by validation).
fn extreme_parameters() -> impl Strategy<Value = GncParameters> {
    use fmu_gnc::params::*;
    let d = GncParameters::default();
    let duration = |x| at_bounds(x, 0.0, MAX_DURATION_S);
    let target = |x| at_bounds(x, -MAX_TARGET_M, MAX_TARGET_M);
    let inertia = |x| at_bounds(x, 1e-300, MAX_INERTIA_KGM2);
    let torque = || at_bounds(116.0, 0.0, MAX_TORQUE_NM);
    let a = (
        1..=3i32,
        at_bounds(2.6, -MAX_PHI_CMD_RAD, MAX_PHI_CMD_RAD),
        at_bounds(0.0, -1e300, 1e300),
        at_bounds(0.5, 1e-300, 1e140),
        at_bounds(0.8, 1e-300, MAX_DAMPING),
        at_bounds(0.06, 1e-300, 0.5 / MIN_GUIDANCE_CYCLE_S),
        at_bounds(0.8, 1e-300, MAX_DAMPING),
        at_bounds(0.1, MIN_GUIDANCE_CYCLE_S, 1.0),
        [inertia(400.0), inertia(300.0), inertia(450.0)],
        at_bounds(720.0, 0.0, MAX_THRUST_N),
        at_bounds(1600.0, 0.0, MAX_THRUST_N),
        [torque(), torque(), torque()],
    );
    let b = (
        at_bounds(1.62, 1e-300, MAX_GRAVITY_MPS2),
        [target(0.0), target(800.0), target(0.0)],
        duration(d.hover_duration_s),
        [target(0.0), target(150.0), target(0.0)],
        duration(d.descent_time_to_go_s),
        at_bounds(5.0, MIN_GUIDANCE_CYCLE_S, MAX_DURATION_S),
        duration(d.target_hover_duration_s),
        at_bounds(0.4, 0.0, 1.0),
        at_bounds(0.0, 1e-300, 1.0),
        at_bounds(0.0, 1e-300, f64::MAX),
        at_bounds(0.0, 1e-300, MAX_PHI_RATE_RADPS),
        at_bounds(0.0, 1e-300, MAX_PHI_ACCEL_RADPS2),
    );
    (a, b).prop_map(assemble)
}

fn parameters() -> impl Strategy<Value = GncParameters> {
    let d = GncParameters::default();
    let a = (
        1..=3i32,
        or_default(2.6),
        or_default(d.phi_cmd_time_s),
        or_default(d.control_bandwidth_hz),
        or_default(d.control_damping),
        or_default(d.guidance_bandwidth_hz),
        or_default(d.guidance_damping),
        or_default(d.guidance_cycle_s),
        [or_default(400.0), or_default(300.0), or_default(450.0)],
        or_default(d.thrust_min_n),
        or_default(d.thrust_max_n),
        [or_default(116.0), or_default(116.0), or_default(116.0)],
    );
    let b = (
        or_default(d.gravity_mps2),
        [or_default(0.0), or_default(800.0), or_default(0.0)],
        or_default(d.hover_duration_s),
        [or_default(0.0), or_default(150.0), or_default(0.0)],
        or_default(d.descent_time_to_go_s),
        or_default(d.descent_freeze_time_to_go_s),
        or_default(d.target_hover_duration_s),
        prop_oneof![Just(0.4), 0.0..=1.0],
        prop_oneof![Just(0.0), Just(0.5), 0.0..=1.0],
        or_default(0.0),
        or_default(0.0),
        or_default(0.0),
    );
    (a, b).prop_map(assemble)
}

/// A retarget drawn on top of the other parameters: at any time of the schedule (or beyond),
/// to any admissible site, with any admissible tilt limit, re-planned or not.
fn retarget_parameters() -> impl Strategy<Value = GncParameters> {
    use fmu_gnc::guidance::retarget::MAX_RETARGET_TILT_RAD;
    use fmu_gnc::params::MAX_TARGET_M;
    let target = || prop_oneof![Just(-MAX_TARGET_M), Just(MAX_TARGET_M), -1e3..1e3f64];
    (
        prop_oneof![1 => extreme_parameters(), 3 => parameters()],
        prop_oneof![Just(0.0), Just(1e6), 0.0..1.0f64],
        [target(), target(), target()],
        prop_oneof![Just(1e-300), Just(MAX_RETARGET_TILT_RAD), 0.0..1.0f64],
        any::<bool>(),
    )
        .prop_map(|(base, fraction, site, tilt, replan)| {
            let end_s =
                base.hover_duration_s + base.descent_time_to_go_s + base.target_hover_duration_s;
            GncParameters {
                retarget_time_s: if fraction > 1.0 {
                    fraction
                } else {
                    (fraction * end_s).min(1e6)
                },
                retarget_site_nue_m: site,
                retarget_max_tilt_rad: tilt,
                retarget_replan: replan,
                ..base
            }
        })
}

/// The thruster model with its chain drawn too: the default layout with each thruster's
/// position scaled by any magnitude, force, modulator settings and duty period of any
/// magnitude (sane or extreme). Directions stay unit vectors (validation requires them).
fn thruster_parameters() -> impl Strategy<Value = GncParameters> {
    let d = GncParameters::default();
    (
        // Mostly the default rest, so that the chain's own extremes are what validation sees.
        prop_oneof![3 => Just(d), 1 => parameters()],
        prop::array::uniform8(or_default(1.0)),
        (
            or_default(d.rcs_thruster_force_n),
            any::<bool>(),
            or_default(d.pwpf_gain),
            or_default(d.pwpf_time_constant_s),
        ),
        (
            or_default(d.pwpf_on_threshold),
            or_default(d.pwpf_off_threshold),
            or_default(d.rcs_duty_period_s),
        ),
    )
        .prop_map(move |(base, scale, a, b)| {
            let mut position = d.rcs_position_body_m;
            for (k, p) in position.iter_mut().enumerate() {
                *p *= scale[k / 3];
            }
            GncParameters {
                rcs_model: fmu_gnc::actuation::RcsModel::Thrusters as i32,
                rcs_position_body_m: position,
                rcs_thruster_force_n: a.0,
                rcs_tilt_first: a.1,
                pwpf_gain: a.2,
                pwpf_time_constant_s: a.3,
                pwpf_on_threshold: b.0,
                pwpf_off_threshold: b.1,
                rcs_duty_period_s: b.2,
                ..base
            }
        })
}

type Head = (
    i32,
    f64,
    f64,
    f64,
    f64,
    f64,
    f64,
    f64,
    [f64; 3],
    f64,
    f64,
    [f64; 3],
);
type Tail = (
    f64,
    [f64; 3],
    f64,
    [f64; 3],
    f64,
    f64,
    f64,
    f64,
    f64,
    f64,
    f64,
    f64,
);

fn assemble((a, b): (Head, Tail)) -> GncParameters {
    GncParameters {
        control_law: a.0,
        phi_cmd_rad: a.1,
        phi_cmd_time_s: a.2,
        control_bandwidth_hz: a.3,
        control_damping: a.4,
        guidance_bandwidth_hz: a.5,
        guidance_damping: a.6,
        guidance_cycle_s: a.7,
        inertia_body_kgm2: a.8,
        thrust_min_n: a.9,
        thrust_max_n: a.10,
        torque_limit_body_nm: a.11,
        gravity_mps2: b.0,
        hover_target_nue_m: b.1,
        hover_duration_s: b.2,
        descent_target_nue_m: b.3,
        descent_time_to_go_s: b.4,
        descent_freeze_time_to_go_s: b.5,
        target_hover_duration_s: b.6,
        reduced_yaw_weight: b.7,
        rate_shaping_margin: b.8,
        terminal_descent_speed_mps: b.9,
        phi_rate_limit_radps: b.10,
        phi_accel_limit_radps2: b.11,
        // The thruster chain keeps its defaults here (torque model).
        ..GncParameters::default()
    }
}

fn all_finite(values: &[f64]) -> bool {
    values.iter().all(|x| x.is_finite())
}

/// The property for one parameter set and one input: nothing to check if validation refuses.
#[allow(clippy::too_many_arguments)]
fn check_finite(
    params: GncParameters,
    r: [f64; 3],
    v: [f64; 3],
    q: [f64; 4],
    w: [f64; 3],
    mass: f64,
    t_fraction: f64,
) -> Result<(), TestCaseError> {
    let Ok(design) = params.design() else {
        return Ok(());
    };
    let gains = design.attitude.gains;
    prop_assert!(
        all_finite(gains.kp_nm_per_rad.as_slice()) && all_finite(gains.kd_nms_per_rad.as_slice())
    );
    prop_assert!(all_finite(&[
        design.scenario.pv_gains.kr,
        design.scenario.pv_gains.kv
    ]));
    let q = UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
    let nav = NavigationInputs {
        r_nue_m: r,
        v_nue_mps: v,
        q_body_to_nue: [q.w, q.i, q.j, q.k],
        omega_body_radps: w,
        mass_kg: mass,
    };
    // Any time of the flight, its schedule as the parameters set it.
    let end_s =
        params.hover_duration_s + params.descent_time_to_go_s + params.target_hover_duration_s;
    let t = t_fraction * end_s.min(1e9);
    let mut guidance = GuidanceState::initial(params.gravity_mps2);
    let mut profile = PhiProfile::default();
    let mut bank = PwpfBank::default();
    for t in [0.0, t, t + 0.01, t + params.guidance_cycle_s] {
        let mut s = gnc_sample(&design, 0.0, &guidance, &profile, &nav, t);
        (guidance, profile) = (s.advance.guidance, s.advance.profile);
        // The thruster chain (a no-op in the torque model): duties within [0, 1].
        bank = actuate(&design, &mut s.outputs, &bank);
        prop_assert!(
            s.outputs.rcs_duty.iter().all(|d| (0.0..=1.0).contains(d)),
            "{params:?} {nav:?} t {t}: duties {:?}",
            s.outputs.rcs_duty
        );
        prop_assert!(
            !s.outputs.zero_non_finite(),
            "{params:?} {nav:?} t {t}: {:?}",
            s.outputs
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8000))]

    #[test]
    fn valid_parameters_give_finite_derived_quantities_and_outputs(
        params in parameters(),
        r in prop::array::uniform3(-1e6..1e6f64),
        v in prop::array::uniform3(-1e4..1e4f64),
        q in prop::array::uniform4(-1.0..1.0f64),
        w in prop::array::uniform3(-1e3..1e3f64),
        mass in 1.0..1e5f64,
        t_fraction in 0.0..1.0f64,
    ) {
        prop_assume!(q.iter().map(|c| c * c).sum::<f64>() > 1e-6);
        check_finite(params, r, v, q, w, mass, t_fraction)?;
    }

    #[test]
    fn parameters_at_their_admissible_extremes_give_finite_outputs(
        params in extreme_parameters(),
        r in prop::array::uniform3(prop_oneof![Just(-1e6), Just(0.0), Just(1e6), -1e6..1e6f64]),
        v in prop::array::uniform3(prop_oneof![Just(-1e4), Just(1e4), -1e4..1e4f64]),
        q in prop::array::uniform4(-1.0..1.0f64),
        w in prop::array::uniform3(prop_oneof![Just(-1e3), Just(1e3), -1e3..1e3f64]),
        mass in prop_oneof![Just(1.0), Just(1e5), 1.0..1e5f64],
        t_fraction in prop_oneof![Just(0.0), Just(1.0), 0.0..1.0f64],
    ) {
        prop_assume!(q.iter().map(|c| c * c).sum::<f64>() > 1e-6);
        check_finite(params, r, v, q, w, mass, t_fraction)?;
    }
}

/// The thruster model, its chain drawn too. Run on a thread with a large stack: the value
/// tree of a parameter set this large overflows a test thread's default stack in debug builds.
#[test]
fn valid_thruster_chains_give_finite_duties_and_outputs() {
    use proptest::test_runner::{Config, TestRunner};
    let run = || {
        let mut runner = TestRunner::new(Config::with_cases(3000));
        let inputs = (
            thruster_parameters(),
            prop::array::uniform3(-1e6..1e6f64),
            prop::array::uniform3(-1e4..1e4f64),
            prop::array::uniform4(-1.0..1.0f64),
            prop::array::uniform3(-1e3..1e3f64),
            1.0..1e5f64,
            0.0..1.0f64,
        );
        runner
            .run(&inputs, |(params, r, v, q, w, mass, t_fraction)| {
                prop_assume!(q.iter().map(|c| c * c).sum::<f64>() > 1e-6);
                check_finite(params, r, v, q, w, mass, t_fraction)
            })
            .map_err(|e| e.to_string())
    };
    let outcome = std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(run)
        .unwrap()
        .join()
        .unwrap();
    if let Err(e) = outcome {
        panic!("{e}");
    }
}

/// A retarget at any time of the schedule, on top of any valid parameters. On a thread with a
/// large stack, as the thruster chain's (the value tree is as large).
#[test]
fn a_retarget_with_any_valid_parameters_gives_finite_outputs() {
    use proptest::test_runner::{Config, TestRunner};
    let run = || {
        let mut runner = TestRunner::new(Config::with_cases(3000));
        let inputs = (
            retarget_parameters(),
            prop::array::uniform3(-1e6..1e6f64),
            prop::array::uniform3(-1e4..1e4f64),
            prop::array::uniform4(-1.0..1.0f64),
            prop::array::uniform3(-1e3..1e3f64),
            prop_oneof![Just(1.0), Just(1e5), 1.0..1e5f64],
            0.0..1.0f64,
        );
        runner
            .run(&inputs, |(params, r, v, q, w, mass, t_fraction)| {
                prop_assume!(q.iter().map(|c| c * c).sum::<f64>() > 1e-6);
                check_finite(params, r, v, q, w, mass, t_fraction)
            })
            .map_err(|e| e.to_string())
    };
    let outcome = std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(run)
        .unwrap()
        .join()
        .unwrap();
    if let Err(e) = outcome {
        panic!("{e}");
    }
}
