//! Property tests: no NaN for finite input, invariants of the thrust-axis split, sign
//! invariance of the laws (no unwinding).
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmu_gnc::attitude::errors::thrust_axis_errors;
use fmu_gnc::attitude::phi_b::phi_b;
use fmu_gnc::attitude::profile::PhiProfile;
use fmu_gnc::attitude::reduced::reduced_reference;
use fmu_gnc::attitude::reference::{q_guid, q_phi, q_ref};
use fmu_gnc::attitude::{attitude_command, ControlLaw};
use fmu_gnc::controller::{gnc_sample, NavigationInputs};
use fmu_gnc::guidance::sequencer::GuidanceState;
use fmu_gnc::params::GncParameters;
use lander_math::frames::{Body, Nue};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use proptest::prelude::*;

/// Any finite f64, including zero, subnormals and the extremes.
fn any_finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

fn any_vector() -> impl Strategy<Value = Vector3<f64>> {
    (any_finite(), any_finite(), any_finite()).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

fn bounded_vector(limit: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-limit..limit, -limit..limit, -limit..limit).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

fn any_attitude() -> impl Strategy<Value = UnitQuaternion<f64>> {
    (-1.0..1.0, -1.0..1.0, -1.0..1.0, -1.0..1.0)
        .prop_filter("non-zero", |(w, x, y, z): &(f64, f64, f64, f64)| {
            w * w + x * x + y * y + z * z > 1e-6
        })
        .prop_map(|(w, x, y, z)| UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)))
}

fn law() -> impl Strategy<Value = ControlLaw> {
    prop_oneof![
        Just(ControlLaw::Coupled),
        Just(ControlLaw::Decoupled),
        Just(ControlLaw::Reduced)
    ]
}

fn settings(law: ControlLaw, weight: f64) -> fmu_gnc::attitude::AttitudeSettings {
    GncParameters {
        control_law: law as i32,
        reduced_yaw_weight: weight,
        ..Default::default()
    }
    .attitude_settings()
    .unwrap()
}

fn finite_quaternion(q: &UnitQuaternion<f64>) -> bool {
    q.coords.iter().all(|c| c.is_finite()) && (q.into_inner().norm() - 1.0).abs() < 1e-12
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn no_nan_from_the_attitude_functions(
        a in any_vector(), q in any_attitude(), phi in any_finite(), w in any_vector(),
        law in law(), weight in 0.0..=1.0,
    ) {
        let guid = q_guid(&Nue(a));
        prop_assert!(finite_quaternion(&guid));
        prop_assert!(finite_quaternion(&q_phi(phi)));
        prop_assert!(finite_quaternion(&q_ref(&guid, phi)));
        prop_assert!(phi_b(&q).is_finite());
        let e = thrust_axis_errors(&q, &guid, phi);
        prop_assert!([e.roll_rad, e.yaw_rad, e.pitch_rad, e.tilt_rad, e.phi_b_rad].iter().all(|x| x.is_finite()));
        prop_assert!(finite_quaternion(&reduced_reference(&q, &q_ref(&guid, phi), weight)));
        let cmd = attitude_command(&settings(law, weight), &q, &Body(w), &Nue(a), phi);
        prop_assert!(cmd.torque_body_nm.0.iter().all(|x| x.is_finite()));
        prop_assert!(cmd.torque_body_nm.0.iter().all(|x| x.abs() <= 116.0));
        prop_assert!(cmd.angle_error_body.0.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn no_nan_from_a_gnc_sample(
        r in bounded_vector(1e6), v in bounded_vector(1e4), q in any_attitude(),
        w in bounded_vector(1e3), mass in prop_oneof![Just(0.0), -10.0..1e5],
        t in 0.0..400.0, law in 1..=3, phi in -10.0..10.0,
    ) {
        let params = GncParameters { control_law: law, phi_cmd_rad: phi, ..Default::default() };
        let nav = NavigationInputs {
            r_nue_m: r.into(), v_nue_mps: v.into(),
            q_body_to_nue: [q.w, q.i, q.j, q.k], omega_body_radps: w.into(), mass_kg: mass,
        };
        let s = gnc_sample(&params.design().unwrap(), 0.0, &GuidanceState::initial(1.62), &PhiProfile::default(), &nav, t);
        let o = s.outputs;
        let reals = [o.thrust_cmd_n, o.phi_b_rad, o.err_roll_rad, o.err_yaw_rad, o.err_pitch_rad, o.tilt_error_rad, o.time_to_go_s];
        prop_assert!(reals.iter().chain(&o.torque_cmd_body_nm).chain(&o.a_cmd_nue_mps2).chain(&o.q_ref).all(|x| x.is_finite()));
        prop_assert!((720.0..=1600.0).contains(&o.thrust_cmd_n));
    }

    #[test]
    fn tilt_error_is_unchanged_by_rotation_about_the_thrust_axis(
        q in any_attitude(), a in bounded_vector(10.0), phi in -4.0..4.0, spin in -7.0..7.0,
    ) {
        let guid = q_guid(&Nue(a));
        let before = thrust_axis_errors(&q, &guid, phi);
        let after = thrust_axis_errors(&(q * q_phi(spin)), &guid, phi);
        prop_assert!((before.tilt_rad - after.tilt_rad).abs() < 1e-9);
        // the lateral error only turns within the body x-z plane: its size is unchanged
        let lateral = |e: &fmu_gnc::attitude::errors::ThrustAxisErrors| e.yaw_rad.hypot(e.pitch_rad);
        prop_assert!((lateral(&before) - lateral(&after)).abs() < 1e-9);
    }

    #[test]
    fn thrust_axis_error_is_zero_for_a_pure_tilt(
        a1 in -3.1..3.1, a3 in -1.5..1.5, target in bounded_vector(10.0),
    ) {
        // A pure tilt in the paper's 1-3-2 sense: rotations about x and then z, none about y.
        let q = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), a1)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a3);
        let e = thrust_axis_errors(&q, &q_guid(&Nue(target)), 0.0);
        prop_assert!(e.roll_rad.abs() < 1e-9, "roll error {}", e.roll_rad);
    }

    #[test]
    fn errata_7_lateral_error_is_zero_with_the_thrust_axis_on_target(
        a in bounded_vector(10.0), twist in -7.0..7.0, phi in -4.0..4.0,
    ) {
        prop_assume!(a.norm() > 1e-3);
        let guid = q_guid(&Nue(a));
        let e = thrust_axis_errors(&(guid * q_phi(twist)), &guid, phi);
        prop_assert!(e.yaw_rad.abs() < 1e-9 && e.pitch_rad.abs() < 1e-9, "{e:?}");
        prop_assert!(e.tilt_rad < 1e-7);
    }

    #[test]
    fn every_law_gives_the_same_torque_for_q_and_minus_q(
        q in any_attitude(), a in bounded_vector(10.0), phi in -4.0..4.0,
        w in bounded_vector(1.0), law in law(), weight in 0.0..=1.0,
    ) {
        let s = settings(law, weight);
        let minus_q = UnitQuaternion::new_unchecked(-q.into_inner());
        let t1 = attitude_command(&s, &q, &Body(w), &Nue(a), phi).torque_body_nm.0;
        let t2 = attitude_command(&s, &minus_q, &Body(w), &Nue(a), phi).torque_body_nm.0;
        prop_assert!((t1 - t2).norm() < 1e-9, "{t1} vs {t2}");
    }
}
