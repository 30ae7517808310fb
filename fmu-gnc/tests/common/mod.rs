//! A rigid body for closed-loop tests, independent of the code under test:
//! `I omega' = tau - omega x I omega`, `q' = ½ q ⊗ [0, omega]` (ERRATA 3), classical RK4 with
//! the torque held over the step, quaternion renormalised after each step.
#![allow(dead_code)]
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

pub const INERTIA_KGM2: [f64; 3] = [400.0, 300.0, 450.0];

#[derive(Debug, Clone, Copy)]
pub struct RigidBody {
    pub q_body_to_nue: UnitQuaternion<f64>,
    pub omega_body: Vector3<f64>,
}

fn derivative(
    q: &Quaternion<f64>,
    omega: &Vector3<f64>,
    torque: &Vector3<f64>,
) -> (Quaternion<f64>, Vector3<f64>) {
    let inertia = Vector3::from(INERTIA_KGM2);
    let q_dot = q * Quaternion::from_imag(*omega) * 0.5;
    let omega_dot = (torque - omega.cross(&inertia.component_mul(omega))).component_div(&inertia);
    (q_dot, omega_dot)
}

impl RigidBody {
    pub fn step(&mut self, torque_body: &Vector3<f64>, dt: f64) {
        let q0 = self.q_body_to_nue.into_inner();
        let w0 = self.omega_body;
        let (k1q, k1w) = derivative(&q0, &w0, torque_body);
        let (k2q, k2w) = derivative(
            &(q0 + k1q * (dt / 2.0)),
            &(w0 + k1w * (dt / 2.0)),
            torque_body,
        );
        let (k3q, k3w) = derivative(
            &(q0 + k2q * (dt / 2.0)),
            &(w0 + k2w * (dt / 2.0)),
            torque_body,
        );
        let (k4q, k4w) = derivative(&(q0 + k3q * dt), &(w0 + k3w * dt), torque_body);
        let q = q0 + (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (dt / 6.0);
        self.q_body_to_nue = UnitQuaternion::from_quaternion(q);
        self.omega_body = w0 + (k1w + k2w * 2.0 + k3w * 2.0 + k4w) * (dt / 6.0);
    }

    /// The body thrust axis (body +y) in NUE.
    pub fn thrust_axis_nue(&self) -> Vector3<f64> {
        self.q_body_to_nue * Vector3::y()
    }
}

/// The paper's attitude settings (Table II, ERRATA defaults) for `law`.
pub fn paper_settings(law: fmu_gnc::attitude::ControlLaw) -> fmu_gnc::attitude::AttitudeSettings {
    fmu_gnc::params::GncParameters {
        control_law: law as i32,
        ..Default::default()
    }
    .attitude_settings()
    .unwrap()
}
