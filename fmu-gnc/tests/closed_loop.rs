//! Closed loop against a rigid body (no FMI): every law converges from a grid of initial
//! attitudes, with the state quaternion's sign flipped at every control step (no unwinding).
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::{paper_settings, RigidBody};
use fmu_gnc::attitude::phi_b::phi_b;
use fmu_gnc::attitude::reference::{q_guid, q_ref};
use fmu_gnc::attitude::{attitude_command, ControlLaw};
use fmu_gnc::conventions::wrap_angle;
use lander_math::frames::{Body, Nue};
use nalgebra::{Unit, UnitQuaternion, Vector3};

const DT_S: f64 = 0.01;
const DURATION_S: f64 = 30.0;

fn initial_attitudes() -> Vec<UnitQuaternion<f64>> {
    let axes = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        -Vector3::z(),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::new(-1.0, 0.5, 1.0),
        Vector3::new(0.3, -1.0, -0.7),
    ];
    let mut grid = vec![UnitQuaternion::identity()];
    for axis in axes {
        for angle_deg in [40.0_f64, 100.0, 170.0] {
            grid.push(UnitQuaternion::from_axis_angle(
                &Unit::new_normalize(axis),
                angle_deg.to_radians(),
            ));
        }
    }
    grid
}

/// Fly `law` from `q0` toward the reference of `a_thrust_nue`, `phi_cmd`; the controller
/// sees `-q` at every other step.
fn fly(
    law: ControlLaw,
    q0: UnitQuaternion<f64>,
    a_thrust_nue: &Vector3<f64>,
    phi_cmd: f64,
) -> RigidBody {
    let settings = paper_settings(law);
    let mut body = RigidBody {
        q_body_to_nue: q0,
        omega_body: Vector3::new(0.02, -0.03, 0.01),
    };
    for k in 0..(DURATION_S / DT_S) as usize {
        let q_seen = if k % 2 == 1 {
            UnitQuaternion::new_unchecked(-body.q_body_to_nue.into_inner())
        } else {
            body.q_body_to_nue
        };
        let cmd = attitude_command(
            &settings,
            &q_seen,
            &Body(body.omega_body),
            &Nue(*a_thrust_nue),
            phi_cmd,
        );
        body.step(&cmd.torque_body_nm.0, DT_S);
    }
    body
}

fn cases() -> [(Vector3<f64>, f64); 3] {
    [
        (Vector3::new(0.0, 1.62, 0.0), 0.0),
        (Vector3::new(0.3, 1.62, -0.2), 150f64.to_radians()),
        (Vector3::new(-0.5, 1.5, 0.4), -2.0),
    ]
}

#[test]
fn coupled_law_converges_to_the_full_reference() {
    for (a, phi_cmd) in cases() {
        let target = q_ref(&q_guid(&Nue(a)), phi_cmd);
        for q0 in initial_attitudes() {
            let end = fly(ControlLaw::Coupled, q0, &a, phi_cmd);
            let err = end.q_body_to_nue.angle_to(&target);
            assert!(err < 1e-3, "from {q0:?} to a {a} phi {phi_cmd}: {err} rad");
            assert!(end.omega_body.norm() < 1e-3);
        }
    }
}

#[test]
fn decoupled_law_aligns_the_thrust_axis_and_phi_b_converges_to_phi_cmd() {
    for (a, phi_cmd) in cases() {
        for q0 in initial_attitudes() {
            let end = fly(ControlLaw::Decoupled, q0, &a, phi_cmd);
            let tilt = end.thrust_axis_nue().angle(&a);
            // ERRATA 7: phi_b (not the swing-twist angle) converges to phi_cmd
            let roll_err = wrap_angle(phi_b(&end.q_body_to_nue) - phi_cmd);
            assert!(tilt < 1e-3, "from {q0:?} to a {a}: tilt {tilt}");
            assert!(
                roll_err.abs() < 1e-3,
                "from {q0:?} phi {phi_cmd}: {roll_err}"
            );
            assert!(end.omega_body.norm() < 1e-3);
        }
    }
}

#[test]
fn reduced_law_converges_with_and_without_thrust_axis_rotation() {
    for (a, phi_cmd) in cases() {
        let target = q_ref(&q_guid(&Nue(a)), phi_cmd);
        for q0 in initial_attitudes() {
            let end = fly(ControlLaw::Reduced, q0, &a, phi_cmd);
            let err = end.q_body_to_nue.angle_to(&target);
            assert!(err < 1e-2, "from {q0:?} to a {a} phi {phi_cmd}: {err} rad");
            assert!(end.thrust_axis_nue().angle(&a) < 1e-3);
        }
    }
}
