//! Retargeting (docs/retarget.md) in a closed loop without FMI: the GNC samples against a
//! rigid body that also translates under its thrust (thrust along body +y, gravity, mass
//! flow at Isp 300 s), the paper's start (15 deg tilt toward North, phi_cmd = 150 deg at 0 s).
// std's functions measure the flight here (tilt, horizontal norms), a reference independent of
// the libm the model uses; the hashed values are the model's outputs alone.
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::RigidBody;
use fmu_gnc::attitude::profile::PhiProfile;
use fmu_gnc::controller::{gnc_sample, NavigationInputs};
use fmu_gnc::guidance::sequencer::GuidanceState;
use fmu_gnc::params::GncParameters;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

const H_S: f64 = 0.01;
const G0_MPS2: f64 = 9.81;
const ISP_S: f64 = 300.0;

/// One communication point of the flight: time, position, tilt of the thrust axis, the
/// commanded thrust acceleration, the guidance phase.
#[derive(Debug, Clone, Copy)]
struct Point {
    t_s: f64,
    r_nue: Vector3<f64>,
    tilt_rad: f64,
    a_cmd_nue: Vector3<f64>,
    phase: i32,
}

/// Flies `params` for `duration_s`; returns the points and a hash of every output's bits.
fn fly(params: &GncParameters, duration_s: f64) -> (Vec<Point>, u64) {
    let design = params.design().unwrap();
    let mut body = RigidBody {
        q_body_to_nue: UnitQuaternion::from_quaternion(Quaternion::new(
            0.9914448613738104,
            0.0,
            0.0,
            -0.13052619222005157,
        )),
        omega_body: Vector3::zeros(),
    };
    let mut r = Vector3::new(0.0, 800.0, 0.0);
    let mut v = Vector3::zeros();
    let mut mass_kg = 900.0;
    let mut guidance = GuidanceState::initial(params.gravity_mps2);
    let mut profile = PhiProfile::default();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |x: f64| {
        for byte in x.to_bits().to_le_bytes() {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    let mut points = Vec::new();
    let steps = (duration_s / H_S).round() as usize;
    for k in 0..=steps {
        let t_s = k as f64 * H_S;
        let q = body.q_body_to_nue.into_inner();
        let nav = NavigationInputs {
            r_nue_m: r.into(),
            v_nue_mps: v.into(),
            q_body_to_nue: [q.w, q.i, q.j, q.k],
            omega_body_radps: body.omega_body.into(),
            mass_kg,
        };
        let sample = gnc_sample(&design, 0.0, &guidance, &profile, &nav, t_s);
        guidance = sample.advance.guidance;
        profile = sample.advance.profile;
        let out = &sample.outputs;
        for x in [out.thrust_cmd_n, out.phi_b_rad, out.tilt_error_rad]
            .iter()
            .chain(&out.torque_cmd_body_nm)
            .chain(&out.a_cmd_nue_mps2)
            .chain(&out.q_ref)
        {
            mix(*x);
        }
        mix(f64::from(out.guidance_phase));
        mix(out.time_to_go_s);
        let axis = body.thrust_axis_nue();
        points.push(Point {
            t_s,
            r_nue: r,
            tilt_rad: axis.y.clamp(-1.0, 1.0).acos(),
            a_cmd_nue: Vector3::from(out.a_cmd_nue_mps2),
            phase: out.guidance_phase,
        });
        // The plant over the step: thrust along the thrust axis held, gravity, mass flow.
        let a = axis * (out.thrust_cmd_n / mass_kg) - Vector3::new(0.0, params.gravity_mps2, 0.0);
        r += v * H_S + a * (0.5 * H_S * H_S);
        v += a * H_S;
        mass_kg -= out.thrust_cmd_n / (ISP_S * G0_MPS2) * H_S;
        body.step(&Vector3::from(out.torque_cmd_body_nm), H_S);
    }
    (points, hash)
}

/// The paper's flight passes 150 m at 140.74 s in this loop; the divert is commanded at the
/// guidance cycle after it, with the camera pointing (phi_cmd) commanded at the same time.
const RETARGET_S: f64 = 140.8;
const SITE_NUE: [f64; 3] = [30.0, 150.0, 0.0];

fn retarget(law: i32, replan: bool) -> GncParameters {
    GncParameters {
        control_law: law,
        phi_cmd_time_s: RETARGET_S,
        retarget_time_s: RETARGET_S,
        retarget_site_nue_m: SITE_NUE,
        retarget_replan: replan,
        ..paper()
    }
}

/// After the retarget: the largest distance North past the site, the largest horizontal
/// command, the largest tilt, the last time farther than 1 m from the site, the end point.
struct Divert {
    overshoot_m: f64,
    peak_lateral_cmd_mps2: f64,
    peak_tilt_rad: f64,
    settled_at_s: f64,
    end_nue: Vector3<f64>,
}

fn divert(points: &[Point]) -> Divert {
    let site = Vector3::from(SITE_NUE);
    let after: Vec<&Point> = points.iter().filter(|p| p.t_s >= RETARGET_S).collect();
    Divert {
        overshoot_m: after
            .iter()
            .map(|p| p.r_nue.x - site.x)
            .fold(f64::NEG_INFINITY, f64::max),
        peak_lateral_cmd_mps2: after
            .iter()
            .map(|p| p.a_cmd_nue.x.hypot(p.a_cmd_nue.z))
            .fold(0.0, f64::max),
        peak_tilt_rad: after.iter().map(|p| p.tilt_rad).fold(0.0, f64::max),
        settled_at_s: after
            .iter()
            .rev()
            .find(|p| (p.r_nue - site).norm() > 1.0)
            .map_or(RETARGET_S, |p| p.t_s),
        end_nue: after.last().unwrap().r_nue,
    }
}

fn paper() -> GncParameters {
    GncParameters {
        phi_cmd_rad: 150f64.to_radians(),
        phi_cmd_time_s: 0.0,
        ..GncParameters::default()
    }
}

/// The hash of the paper flight's outputs (172 s) before retargeting existed, with the
/// same closed loop: computed from the code of the commit before the retarget parameters.
const PAPER_FLIGHT_HASH: u64 = 0xcc26_3295_64d1_c5a2;

#[test]
fn without_a_retarget_the_flight_is_bit_identical_to_before() {
    // GIVEN the paper flight with the default (never) retarget
    let (_, hash) = fly(&paper(), 172.0);
    // THEN every output is bit-identical to the flight before retargeting existed
    assert_eq!(hash, PAPER_FLIGHT_HASH, "{hash:#x}");
    // AND so it is with a retarget scheduled after the end of the flight
    let later = GncParameters {
        retarget_time_s: 500.0,
        retarget_site_nue_m: SITE_NUE,
        ..paper()
    };
    assert_eq!(fly(&later, 172.0).1, PAPER_FLIGHT_HASH);
    // AND a retarget inside the flight does change it (the hash sees the feature)
    let inside = GncParameters {
        retarget_time_s: 150.0,
        retarget_site_nue_m: SITE_NUE,
        ..paper()
    };
    assert_ne!(fly(&inside, 172.0).1, PAPER_FLIGHT_HASH);
}

#[test]
fn the_paper_flight_passes_150_m_just_before_the_retarget() {
    let (points, _) = fly(&paper(), 172.0);
    let crossing = points.iter().find(|p| p.r_nue.y <= 150.0).unwrap().t_s;
    assert!(
        crossing <= RETARGET_S && crossing > RETARGET_S - 0.1,
        "{crossing}"
    );
}

#[test]
fn a_replanned_30_m_divert_at_150_m_arrives_without_overshoot_within_the_tilt_limit() {
    let authority = 1.62 * libm::tan(15f64.to_radians());
    for law in [1, 2] {
        // GIVEN the paper flight retargeted 30 m North at 150 m, camera pointed at the same time
        let (points, _) = fly(&retarget(law, true), 230.0);
        let d = divert(&points);
        // THEN the horizontal command stays within the 15 deg authority, the tilt near it
        assert!(d.peak_lateral_cmd_mps2 <= authority + 1e-12, "law {law}");
        assert!(
            d.peak_tilt_rad < 16f64.to_radians(),
            "law {law}: {}",
            d.peak_tilt_rad
        );
        // AND the lander does not pass the site by more than 0.1 m and ends on it
        assert!(d.overshoot_m < 0.1, "law {law}: {} m", d.overshoot_m);
        assert!(
            (d.end_nue - Vector3::from(SITE_NUE)).norm() < 0.01,
            "{}",
            d.end_nue
        );
        // AND it flies the divert (phase 2) from the command, then hovers there and holds
        let phase_at = |t: f64| points.iter().find(|p| p.t_s >= t).unwrap().phase;
        assert_eq!(phase_at(RETARGET_S - 0.5), 2, "the nominal descent");
        assert_eq!(
            phase_at(RETARGET_S + 15.0),
            2,
            "the divert, past the nominal 142 s"
        );
        assert_eq!(phase_at(RETARGET_S + 30.0), 3);
        assert_eq!(points.last().unwrap().phase, 4);
        // AND it is within 1 m of it some 20 s after the command (the divert lasts ~22 s)
        let settle = d.settled_at_s - RETARGET_S;
        assert!(settle > 10.0 && settle < 25.0, "law {law}: {settle} s");
    }
}

#[test]
fn only_moving_the_target_overshoots_the_site_by_far_more() {
    for law in [1, 2] {
        // GIVEN the same retarget with the re-plan switched off (the target only moves)
        let (points, _) = fly(&retarget(law, false), 230.0);
        let baseline = divert(&points);
        let (points, _) = fly(&retarget(law, true), 230.0);
        let replanned = divert(&points);
        // THEN the short-tgo cubic and the saturated hover pass the site by more than 10 m
        assert!(
            baseline.overshoot_m > 10.0,
            "law {law}: {}",
            baseline.overshoot_m
        );
        assert!(baseline.peak_tilt_rad > 60f64.to_radians());
        assert!(baseline.overshoot_m > 100.0 * replanned.overshoot_m.max(0.01));
    }
}
